"""Progress on long runs: a rich bar on stderr, silent when not a terminal or with ``--quiet``.

Use it in any subcommand::

    from excavkin.cli.progress import progress, solve_with_progress

    result = solve_with_progress(mech, values, rates, accels, quiet=quiet)

    with progress("writing report", quiet=quiet) as step:   # a spinner, no total
        ...
"""

from __future__ import annotations

import dataclasses
import sys
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from typing import Any, TextIO

import numpy as np
from numpy.typing import ArrayLike

#: a sweep with fewer samples than this is solved in one call, without a bar
MIN_SAMPLES_FOR_BAR = 200_000


def enabled(quiet: bool = False, stream: TextIO | None = None) -> bool:
    """Whether to show progress: not ``quiet`` and ``stream`` (stderr) is a terminal."""
    s = sys.stderr if stream is None else stream
    return not quiet and bool(getattr(s, "isatty", lambda: False)())


@contextmanager
def progress(
    description: str,
    total: float | None = None,
    *,
    quiet: bool = False,
    stream: TextIO | None = None,
) -> Iterator[Callable[[float], None]]:
    """A progress bar (or a spinner without ``total``) on stderr, removed when done.

    Parameters
    ----------
    description : str
    total : float, optional
        Units of work; without it a spinner shows that work goes on.
    quiet : bool
        Show nothing.
    stream : file, optional
        Default ``sys.stderr``; nothing is shown unless it is a terminal.

    Yields
    ------
    callable
        ``advance(amount)``; a no-op when silent.
    """
    if not enabled(quiet, stream):
        yield lambda amount: None
        return
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        SpinnerColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    console = Console(file=stream or sys.stderr)
    columns: list[Any] = [SpinnerColumn(), TextColumn("[progress.description]{task.description}")]
    if total is not None:
        columns += [BarColumn(), MofNCompleteColumn(), TimeRemainingColumn()]
    else:
        columns.append(TimeElapsedColumn())
    with Progress(*columns, console=console, transient=True) as bar:
        task = bar.add_task(description, total=total)
        yield lambda amount: bar.advance(task, amount)


def concat_results(results: list[Any]) -> Any:
    """Join kinematic results of one plan along the sample axis.

    Every array attribute whose first axis is the samples is concatenated, and so is the status.
    """
    if len(results) == 1:
        return results[0]
    first = results[0]
    changes: dict[str, Any] = {}
    for f in dataclasses.fields(first):
        value = getattr(first, f.name)
        if f.name == "status":
            changes["status"] = dataclasses.replace(
                value,
                code=np.concatenate([r.status.code for r in results]),
                step=np.concatenate([r.status.step for r in results]),
            )
        elif isinstance(value, np.ndarray):
            changes[f.name] = np.concatenate([getattr(r, f.name) for r in results], axis=0)
    return dataclasses.replace(first, **changes)


def solve_with_progress(
    mech: Any,
    values: Mapping[str, ArrayLike] | None = None,
    rates: Mapping[str, ArrayLike] | None = None,
    accels: Mapping[str, ArrayLike] | None = None,
    *,
    time: ArrayLike | None = None,
    quiet: bool = False,
    chunk: int | None = None,
    description: str = "solving",
    stream: TextIO | None = None,
) -> Any:
    """``mech.solve(values, rates, accels, time=time)`` with a progress bar on long sweeps.

    A sweep of at least :data:`MIN_SAMPLES_FOR_BAR` samples (or any with ``chunk`` given) is
    solved in chunks, each advancing the bar; the samples are independent, so the result is the
    same as one call's.

    Parameters
    ----------
    mech : Mechanism
    values, rates, accels : mapping of str to array_like, optional
        As for :meth:`Mechanism.solve`.
    time : array_like, optional
    quiet : bool
    chunk : int, optional
        Samples per chunk; default about 1 % of the sweep.
    description : str
    stream : file, optional

    Returns
    -------
    KinematicResult
    """
    arrays = [np.asarray(v) for src in (values, rates, accels) for v in (src or {}).values()]
    if time is not None:
        arrays.append(np.asarray(time))
    n = max((a.size for a in arrays if a.ndim == 1), default=1)
    if (chunk is None and n < MIN_SAMPLES_FOR_BAR) or n <= 1:
        return mech.solve(values, rates, accels, time=time)
    size = int(chunk or max(n // 100, 10_000))

    def part(src: Mapping[str, ArrayLike] | None, s: slice) -> dict[str, Any] | None:
        if src is None:
            return None
        out = {}
        for k, v in src.items():
            a = np.asarray(v)
            out[k] = a[s] if a.ndim == 1 and a.size == n else a
        return out

    results = []
    with progress(description, n, quiet=quiet, stream=stream) as advance:
        for start in range(0, n, size):
            s = slice(start, min(start + size, n))
            t = None if time is None else np.asarray(time)[s]
            results.append(mech.solve(part(values, s), part(rates, s), part(accels, s), time=t))
            advance(s.stop - s.start)
    return concat_results(results)
