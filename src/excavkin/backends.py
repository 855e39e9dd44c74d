"""Where a batch runs: the backend registry, the one rule that picks a backend, and the one
kernel cache.

Three workloads can run either as NumPy array operations over chunks of samples or as one
generated kernel compiled to a machine-code loop over samples: the kinematics of a closed-form
plan (`excavkin.kinematics.compiled`), its design tangents
(`excavkin.kinematics.compiled_tangents`) and the kinetostatic elimination
(`excavkin.kinetostatics.compiled`). Each hands the registry a `Job`: what it is, how to make
its generated source, and how to run it either way. A `Backend` says whether it can run the
job and runs it:

- ``"numpy"``: the reference, always there, and the fallback whenever no other can run;
- ``"numba"``: the generated source compiled by numba for the CPU, kept on disk
  (`cache_dir`) so that a model's kernel is compiled once, ever;
- ``"cuda"``: named so that asking for it is one clear error; ``"auto"`` never picks it.

The choice (`choose`) is written once, here. ``"auto"`` takes the compiled kernel whenever it
is ready (compiled in this process or cached on disk by an earlier one), at any sample count;
a kernel not yet compiled is compiled unasked only for a batch of `COMPILE_AT` samples or
more, where compiling pays for itself, and never for a plan too large to compile quickly.
``EXCAVKIN_COMPILED=0`` keeps ``"auto"`` on NumPy.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import logging
import os
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

from excavkin.errors import InputError

__all__ = [
    "BACKENDS",
    "COMPILE_AT",
    "Backend",
    "Job",
    "available",
    "cache_dir",
    "choose",
    "is_cached",
    "kernel_of",
    "require",
]

#: the names ``backend=`` takes
BACKENDS = ("auto", "numpy", "numba", "cuda")
#: a kernel not yet compiled costs 5–20 s to compile (the four-bar's, the excavator's); it is
#: compiled unasked only for a batch this large, where it saves about as much (0.05–0.15 µs a
#: sample), and it is kept on disk for every later solve
COMPILE_AT = 20_000_000

#: a compiled kernel: the generated source's ``kernel`` function
Kernel = Callable[..., None]

log = logging.getLogger("excavkin.backends")


@dataclass(frozen=True, slots=True)
class Job:
    """One workload, as a backend sees it.

    Attributes
    ----------
    what : str
        What it computes (``"kinematics"``, ``"tangents"``, ``"forces"``), for messages.
    source : callable
        ``source()``: the generated source of its kernel (made only when a compiling
        backend asks).
    numpy : callable
        ``numpy()``: run it in NumPy.
    compiled : callable
        ``compiled(kernel)``: run it with its compiled kernel.
    unsupported : str, optional
        Why no compiling backend can run it (a plan with a Newton group); None: one can.
    unasked : bool
        Whether ``"auto"`` may compile its kernel unasked for a large batch (False: a plan too
        large to compile quickly; a kernel compiled before is still used).
    scalar : callable, optional
        ``scalar()``: the source as one plain loop over samples, for a device that runs a
        thread a sample (`excavkin.gpu`); None: the job has no device kernel.
    device : callable, optional
        ``device(kernel)``: run it with a kernel of ``scalar``'s calling convention; None:
        ``compiled`` does (the two conventions are the same).
    slower : callable, optional
        ``slower()``: whether its compiled kernel is known to run slower than NumPy (a large
        plan's kernel split into functions), so that ``"auto"`` keeps NumPy, cached kernel
        or not; a backend named still runs it. None: never.
    """

    what: str
    source: Callable[[], str]
    numpy: Callable[[], None]
    compiled: Callable[[Kernel], None]
    unsupported: str | None = None
    unasked: bool = True
    scalar: Callable[[], str] | None = None
    device: Callable[[Kernel], None] | None = None
    slower: Callable[[], bool] | None = None


class Backend(Protocol):
    """What a backend does with a `Job`."""

    name: str

    def unavailable(self) -> str | None:
        """Why this backend cannot run here (None: it can)."""
        ...

    def supports(self, job: Job) -> bool:
        """Whether it can run ``job``."""
        ...

    def ready(self, job: Job) -> bool:
        """Whether ``job`` runs without compiling first."""
        ...

    def run(self, job: Job) -> None:
        """Run ``job``."""
        ...


class NumpyBackend:
    """Array operations over chunks of samples: the reference, and the fallback."""

    name = "numpy"

    def unavailable(self) -> str | None:
        """Never: NumPy is always there.

        Returns
        -------
        None
        """
        return None

    def supports(self, job: Job) -> bool:
        """Every job.

        Parameters
        ----------
        job : Job

        Returns
        -------
        bool
            True.
        """
        return True

    def ready(self, job: Job) -> bool:
        """Always: nothing is compiled.

        Parameters
        ----------
        job : Job

        Returns
        -------
        bool
            True.
        """
        return True

    def run(self, job: Job) -> None:
        """Run the job's NumPy path.

        Parameters
        ----------
        job : Job
        """
        job.numpy()


class NumbaBackend:
    """The generated source compiled by numba to one loop over samples on the CPU."""

    name = "numba"

    def unavailable(self) -> str | None:
        """Why numba cannot be used (None: it can).

        Returns
        -------
        str or None
        """
        if importlib.util.find_spec("numba") is None:
            return "numba cannot be imported (pip install numba)"
        return None

    def supports(self, job: Job) -> bool:
        """Whether the job has a generated source.

        Parameters
        ----------
        job : Job

        Returns
        -------
        bool
        """
        return job.unsupported is None

    def ready(self, job: Job) -> bool:
        """Whether the job's kernel is compiled, in this process or cached by an earlier one.

        Parameters
        ----------
        job : Job

        Returns
        -------
        bool
        """
        return is_cached(job.source())

    def run(self, job: Job) -> None:
        """Run the job with its kernel (compiled first if it is not cached).

        Parameters
        ----------
        job : Job
        """
        job.compiled(kernel_of(job.source(), job.what))


class CudaBackend:
    """The generated source on an NVIDIA GPU, one thread a sample (`excavkin.gpu`): asked
    for by name only; ``"auto"`` does not pick it."""

    name = "cuda"

    def unavailable(self) -> str | None:
        """Why it cannot run here (None: it can): numba or its CUDA target missing, or no
        GPU (``NUMBA_ENABLE_CUDASIM=1``: numba's simulator stands in for one).

        Returns
        -------
        str or None
        """
        if importlib.util.find_spec("numba") is None:
            return "numba cannot be imported (pip install numba)"
        from excavkin.gpu import why_not

        return why_not()

    def supports(self, job: Job) -> bool:
        """Whether the job has a per-sample loop for the device.

        Parameters
        ----------
        job : Job

        Returns
        -------
        bool
        """
        return job.unsupported is None and job.scalar is not None

    def ready(self, job: Job) -> bool:
        """Whether the job's device kernel is loaded in this process.

        Parameters
        ----------
        job : Job

        Returns
        -------
        bool
        """
        from excavkin.gpu import device_source

        return job.scalar is not None and _key(device_source(job.scalar())) in _kernels

    def run(self, job: Job) -> None:
        """Run the job with its device kernel (made first if it is not loaded).

        Parameters
        ----------
        job : Job
        """
        from excavkin.gpu import DeviceKernel, device_source

        assert job.scalar is not None
        text = device_source(job.scalar())
        kernel = DeviceKernel(kernel_of(text, f"{job.what} (CUDA)"), text)
        (job.device or job.compiled)(kernel)


NUMPY = NumpyBackend()
#: every backend by name; ``"auto"`` tries `AUTO` in order and falls back to NumPy
REGISTRY: dict[str, Backend] = {"numpy": NUMPY, "numba": NumbaBackend(), "cuda": CudaBackend()}
AUTO: tuple[str, ...] = ("numba",)


def available() -> dict[str, str | None]:
    """Each backend, and why it cannot run here (None: it can).

    Returns
    -------
    dict of str to (str or None)
    """
    return {name: b.unavailable() for name, b in REGISTRY.items()}


def require(name: str, option: str | None = None) -> None:
    """Refuse a backend name that is unknown, or names a backend that cannot run here.

    Parameters
    ----------
    name : str
        ``"auto"`` or a backend's name.
    option : str, optional
        How the caller spells the choice, for the message (default ``backend='name'``;
        the CLI's ``--backend name``).

    Raises
    ------
    InputError
        Naming the backend and why.
    """
    if name == "auto":
        return
    b = REGISTRY.get(name)
    if b is None:
        raise InputError(f"backend must be one of {', '.join(BACKENDS)}; got {name!r}")
    why = b.unavailable()
    if why is not None:
        said, auto = (f"backend={name!r}", "backend='auto'") if option is None else (option, "auto")
        raise InputError(f"{said}: {why}; {auto} chooses what can run")


def choose(name: str, job: Job, n: int) -> Backend:
    """The backend that runs ``job`` over ``n`` samples, ``backend=name`` asked for.

    Parameters
    ----------
    name : {"auto", "numpy", "numba", "cuda"}
        ``"auto"``: a compiling backend whose kernel is ready (at any ``n``), or one that
        compiles it when ``n`` is at least `COMPILE_AT` and the job allows it, else NumPy
        (NumPy too for a job whose compiled kernel runs slower, `Job` ``slower``).
        A backend named is used, or it is an error saying why it cannot be.
    job : Job
    n : int
        Samples in the batch.

    Returns
    -------
    Backend

    Raises
    ------
    InputError
        An unknown name, or a backend named that cannot run the job here.
    """
    if name == "auto":
        if os.environ.get("EXCAVKIN_COMPILED", "") == "0":
            return NUMPY
        for candidate in AUTO:
            b = REGISTRY[candidate]
            if not b.supports(job) or b.unavailable() is not None:
                continue
            if job.slower is not None and job.slower():
                continue
            if b.ready(job) or (job.unasked and n >= COMPILE_AT):
                return b
        return NUMPY
    require(name)
    b = REGISTRY[name]
    if not b.supports(job):
        if job.unsupported is None and job.scalar is None:  # compiled for the CPU only
            why = f"the {job.what} of this plan have no device kernel"
        else:
            why = f"the {job.what} {job.unsupported or 'cannot be compiled'}"
        raise InputError(f"backend={name!r}: {why}; backend='auto' chooses what can run")
    return b


# ---------------------------------------------------------------------------------------------
# the kernel cache: one for every generated source


_lock = threading.Lock()
_kernels: dict[str, Kernel] = {}


def cache_dir() -> Path:
    """Where generated kernels and numba's machine code are kept between runs.

    Returns
    -------
    Path
        ``$EXCAVKIN_CACHE_DIR``, else ``$XDG_CACHE_HOME/excavkin/kernels``, else
        ``~/.cache/excavkin/kernels``.
    """
    base = os.environ.get("EXCAVKIN_CACHE_DIR") or os.environ.get("XDG_CACHE_HOME")
    root = Path(base) if base else Path.home() / ".cache"
    return (root if os.environ.get("EXCAVKIN_CACHE_DIR") else root / "excavkin") / "kernels"


def _key(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def is_cached(text: str) -> bool:
    """Whether a generated source's kernel has been compiled, here or in an earlier process.

    Parameters
    ----------
    text : str
        The generated source.

    Returns
    -------
    bool
    """
    key = _key(text)
    return key in _kernels or (cache_dir() / f"excavkin_kernel_{key}.compiled").exists()


def kernel_of(text: str, what: str = "kernel") -> Kernel:
    """The ``kernel`` function of a generated source: imported once, kept in memory and on
    disk. A kernel compiled for the first time is logged (``excavkin.backends``, INFO) before
    and after, with the seconds it took.

    Parameters
    ----------
    text : str
        The generated source.
    what : str
        What it computes, for the log.

    Returns
    -------
    callable
    """
    key = _key(text)
    with _lock:
        kernel = _kernels.get(key)
        if kernel is None:
            marker = cache_dir() / f"excavkin_kernel_{key}.compiled"
            first = not marker.exists()
            if first:
                log.info("compiling the %s kernel %s (once; kept in %s)", what, key, cache_dir())
            start = time.perf_counter()
            kernel = _compile(text, key, what)
            _kernels[key] = kernel
            if first:
                log.info(
                    "compiled the %s kernel %s in %.1f s", what, key, time.perf_counter() - start
                )
            with contextlib.suppress(OSError):  # what a later process's is_cached reads
                marker.touch()
    return kernel


#: Python's recursion limit while numba compiles a kernel: its SSA pass recurses once per
#: block between a name's uses and its assignments, and a scalar loop's branches (the
#: tangents' and forces' kernels) of a plan of 30-odd points pass the default 1,000
COMPILE_RECURSION = 20_000


def _compile(text: str, key: str, what: str) -> Kernel:
    """`_load` with room for numba's recursion; where even that is not enough, one message."""
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, COMPILE_RECURSION))
    try:
        return _load(text, key)
    except RecursionError:
        raise InputError(
            f"numba cannot compile the {what} kernel of this plan (its compiler passed "
            f"Python's recursion limit of {COMPILE_RECURSION}: the plan is too large for one "
            "kernel); backend='numpy' solves it"
        ) from None
    finally:
        sys.setrecursionlimit(limit)


def _load(text: str, key: str) -> Kernel:
    """Import the source from the cache folder (numba caches the machine code beside it); if
    the folder cannot be written, compile in memory for this process only."""
    name = f"excavkin_kernel_{key}"
    try:
        folder = cache_dir()
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / f"{name}.py"
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            tmp = folder / f".{name}.{os.getpid()}.tmp"
            tmp.write_text(text, encoding="utf-8")
            os.replace(tmp, path)
        spec = importlib.util.spec_from_file_location(name, path)
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
        return module.kernel  # type: ignore[no-any-return]
    except OSError:
        scope: dict[str, Any] = {}
        exec(compile(text.replace("cache=True", "cache=False"), name, "exec"), scope)
        return scope["kernel"]  # type: ignore[no-any-return]
