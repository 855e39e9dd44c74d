"""How a batch is run — backend, threads, chunk size, progress — as one frozen object.

An `Execution` is made once, at the public API (from its ``execution=`` argument or from the
``backend=``, ``workers=``, ``chunk=`` and ``progress=`` keywords), and handed down whole to
the kinematics, the tangents and the forces; none of them takes these settings one by one.

>>> from excavkin.execution import Execution
>>> Execution(backend="numpy", workers=1)
Execution(backend='numpy', workers=1, chunk=None, progress=None)
"""

from __future__ import annotations

import dataclasses
import numbers
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from typing import Any

from excavkin.backends import BACKENDS, require
from excavkin.errors import InputError

__all__ = ["Execution", "current", "settings", "use"]


@dataclass(frozen=True, slots=True)
class Execution:
    """Settings of a batch solve that change how it runs, never what it computes.

    Attributes
    ----------
    backend : {"auto", "numpy", "numba", "cuda"}
        Where the closed-form kinematics, their tangents and the forces run
        (`excavkin.backends`): ``"auto"`` (default) takes a compiled kernel when one is
        ready — compiled before and cached on disk — at any sample count, and NumPy otherwise.
    workers : int, optional
        Threads solving chunks side by side (default: one per core; 1: this thread only).
    chunk : int, optional
        Samples per pass (default: each workload's own, sized for the cache).
    progress : callable, optional
        ``progress(done, total)`` after each solved chunk of the kinematics (the calls are
        serialised, ``done`` increasing).
    """

    backend: str = "auto"
    workers: int | None = None
    chunk: int | None = None
    progress: Callable[[int, int], None] | None = None

    def __post_init__(self) -> None:
        if self.backend not in BACKENDS:
            raise InputError(f"backend must be one of {', '.join(BACKENDS)}; got {self.backend!r}")
        for name in ("workers", "chunk"):
            value = getattr(self, name)
            whole = isinstance(value, numbers.Integral) or (
                isinstance(value, float) and value.is_integer()
            )
            if value is not None and (isinstance(value, bool) or not whole or value < 1):
                raise InputError(f"{name} must be a whole number of at least 1, got {value!r}")

    def chunk_or(self, default: int) -> int:
        """Samples per pass: the chunk set, or ``default``.

        Parameters
        ----------
        default : int
            The workload's own chunk size.

        Returns
        -------
        int
        """
        return default if self.chunk is None else int(self.chunk)


#: the default settings
DEFAULT = Execution()
_current: ContextVar[Execution] = ContextVar("excavkin_execution", default=DEFAULT)


def current() -> Execution:
    """The settings a call without its own takes: `DEFAULT`, or those of the innermost
    `use` around it (in this thread).

    Returns
    -------
    Execution
    """
    return _current.get()


@contextmanager
def use(execution: Execution) -> Iterator[Execution]:
    """Run the block with ``execution`` as the settings of every call that gives none (a
    study's solves, made deep inside its metrics).

    Parameters
    ----------
    execution : Execution

    Yields
    ------
    Execution
        ``execution``.
    """
    token = _current.set(execution)
    try:
        yield execution
    finally:
        _current.reset(token)


def settings(
    execution: Execution | None = None,
    *,
    backend: str | None = None,
    compiled: bool | None = None,
    workers: int | None = None,
    chunk: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Execution:
    """The `Execution` of a public call: ``execution`` as given (default: `current`), with
    each keyword given replacing its field. A backend named that cannot run here is refused
    at once (`excavkin.backends.require`).

    Parameters
    ----------
    execution : Execution, optional
    backend : {"auto", "numpy", "numba", "cuda"}, optional
    compiled : bool, optional
        Deprecated (a `DeprecationWarning`): True is ``backend="numba"``, False
        ``backend="numpy"``.
    workers, chunk, progress : optional
        As for `Execution`.

    Returns
    -------
    Execution

    Raises
    ------
    InputError
        ``compiled`` and ``backend`` both given, a bad value, or a backend that cannot run.
    """
    if compiled is not None:
        replacement = "numba" if compiled else "numpy"
        warnings.warn(
            f"compiled= is deprecated and will be removed: use backend={replacement!r}",
            DeprecationWarning,
            stacklevel=3,
        )
        if backend is not None:
            raise InputError("give backend= or the deprecated compiled=, not both")
        backend = replacement
    given: dict[str, Any] = {
        k: v
        for k, v in (("backend", backend), ("workers", workers), ("chunk", chunk),
                     ("progress", progress))
        if v is not None
    }  # fmt: skip
    base = execution if execution is not None else current()
    if not isinstance(base, Execution):
        raise InputError(f"execution must be an Execution, got {type(base).__name__}")
    out = dataclasses.replace(base, **given) if given else base
    require(out.backend)
    return out
