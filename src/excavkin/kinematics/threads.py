"""Chunks of a batch on a thread per core: NumPy and the compiled loops release the GIL, and
chunks write disjoint slices of their outputs."""

from __future__ import annotations

import os
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor


def over_chunks(n: int, chunk: int, workers: int | None, one: Callable[[int], None]) -> None:
    """``one(start)`` for every chunk of ``chunk`` samples of ``n``, on ``workers`` threads
    (default: one per core; one chunk or one worker: in this thread)."""
    starts = range(0, n, chunk)
    threads = min(workers or os.cpu_count() or 1, len(starts))
    if threads > 1:
        with ThreadPoolExecutor(threads) as pool:
            list(pool.map(one, starts))
    else:
        for s in starts:
            one(s)
