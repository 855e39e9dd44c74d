"""The timing helpers of the benchmarks: the best of several runs in the same process, and the
times of several programs run in turn."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence


def best_of(fn: Callable[[], object], repeat: int = 5) -> float:
    """The shortest of ``repeat`` wall-clock times of ``fn()``, seconds."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def times_in_turn(fns: Sequence[Callable[[], object]], repeat: int = 10) -> list[list[float]]:
    """``repeat`` wall-clock times of each of ``fns``, seconds, run in turn so that a change in
    the machine's load falls on all alike: for programs started anew each time."""
    times: list[list[float]] = [[] for _ in fns]
    for _ in range(repeat):
        for fn, own in zip(fns, times, strict=True):
            t0 = time.perf_counter()
            fn()
            own.append(time.perf_counter() - t0)
    return times
