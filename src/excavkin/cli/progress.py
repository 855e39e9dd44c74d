"""Progress on long runs: a rich bar on stderr, silent when not a terminal or with ``--quiet``.

Use it in any subcommand::

    from excavkin.cli.progress import progress, solve_with_progress

    result = solve_with_progress(mech, values, rates, accels, quiet=quiet)

    with progress("writing report", quiet=quiet) as step:   # a spinner, no total
        ...
"""

from __future__ import annotations

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
    count: str | None = None,
    percent: bool = False,
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
    count : str, optional
        Without ``total``: show the work done so far, so named (``"12 iterations"``).
    percent : bool
        With ``total``: show the share done (``"37%"``) rather than ``done/total``.

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
        TaskProgressColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    console = Console(file=stream or sys.stderr)
    columns: list[Any] = [SpinnerColumn(), TextColumn("[progress.description]{task.description}")]
    if total is not None:
        done = TaskProgressColumn() if percent else MofNCompleteColumn()
        columns += [BarColumn(), done, TimeRemainingColumn()]
    else:
        if count is not None:
            columns.append(TextColumn(f"{{task.completed:.0f}} {count}"))
        columns.append(TimeElapsedColumn())
    with Progress(*columns, console=console, transient=True) as bar:
        task = bar.add_task(description, total=total)
        yield lambda amount: bar.advance(task, amount)


@contextmanager
def staged(
    description: str,
    stages: int,
    *,
    quiet: bool = False,
    stream: TextIO | None = None,
) -> Iterator[Callable[[], Callable[[int, int], None]]]:
    """A bar over ``stages`` analyses run one after another, each moving it by its own
    ``progress(done, total)`` callback.

    Yields
    ------
    callable
        ``next_stage()`` → the next analysis's ``progress`` callback.

    Examples
    --------
    ::

        with staged("rated forces", 4, quiet=quiet) as next_stage:
            for working in ("arm", "bucket"):
                base_rated_force(machine, working, progress=next_stage())
    """
    with progress(description, float(stages), quiet=quiet, stream=stream, percent=True) as advance:
        state = {"at": 0.0, "stage": -1}

        def next_stage() -> Callable[[int, int], None]:
            state["stage"] += 1
            base = state["stage"]

            def report(done: int, total: int) -> None:
                at = base + (min(done / total, 1.0) if total > 0 else 1.0)
                advance(at - state["at"])
                state["at"] = at

            return report

        yield next_stage


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
    continuation: str = "side",
    **more: Any,
) -> Any:
    """``mech.solve(values, rates, accels, time=time)`` with a progress bar on long sweeps.

    The engine reports each chunk it finishes
    ([`Mechanism.solve`][excavkin.mechanism.Mechanism.solve]'s ``progress``); a
    sweep of at least `MIN_SAMPLES_FOR_BAR` samples (or any with ``chunk`` given) shows
    them as a bar. The result is the engine's own, whatever is shown.

    Parameters
    ----------
    mech : Mechanism
    values, rates, accels : mapping of str to array_like, optional
        As for [`Mechanism.solve`][excavkin.mechanism.Mechanism.solve].
    time : array_like, optional
    quiet : bool
    chunk : int, optional
        Samples per chunk of the engine.
    description : str
    stream : file, optional
    **more
        Passed on to [`Mechanism.solve`][excavkin.mechanism.Mechanism.solve] (``params``,
        ``sensitivities``).

    Returns
    -------
    KinematicResult
    """
    given = (values, rates, accels, more.get("params"))
    arrays = [np.asarray(v) for src in given for v in (src or {}).values()]
    if time is not None:
        arrays.append(np.asarray(time))
    n = max((a.size for a in arrays if a.ndim == 1), default=1)
    if chunk is None and n < MIN_SAMPLES_FOR_BAR:
        return mech.solve(values, rates, accels, time=time, continuation=continuation, **more)
    with progress(description, n, quiet=quiet, stream=stream) as advance:
        seen = [0]

        def report(done: int, total: int) -> None:
            advance(done - seen[0])
            seen[0] = done

        return mech.solve(
            values,
            rates,
            accels,
            time=time,
            progress=report,
            chunk=chunk,
            continuation=continuation,
            **more,
        )


@contextmanager
def compile_notes(quiet: bool = False, stream: TextIO | None = None) -> Iterator[None]:
    """Within the block, a kernel compiled for the first time (`excavkin.backends`: seconds,
    once per model structure) is announced on stderr before and after, so that the wait is
    not taken for a hang; ``quiet``: nothing is shown."""
    import logging

    if quiet:
        yield
        return
    log = logging.getLogger("excavkin.backends")

    class Note(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            print(f"excavkin: note: {record.getMessage()}", file=stream or sys.stderr)

    handler, level = Note(logging.INFO), log.level
    log.addHandler(handler)
    log.setLevel(logging.INFO)
    try:
        yield
    finally:
        log.removeHandler(handler)
        log.setLevel(level)
