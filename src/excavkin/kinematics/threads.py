"""Chunks of a batch on a thread per core: NumPy and the compiled loops release the GIL, and
chunks write disjoint slices of their outputs.

Each thread takes its own run of consecutive chunks, in order, and only when its run is done
takes chunks from the end of the longest run left (so a thread slowed by the machine's load
holds no one up). A fresh output's pages are mapped as they are first written: with the chunks
dealt out in turn, every thread wrote into the same pages at once (a huge page is 2 MiB, 8
chunks of a row), and the threads queued on each page's fault; with a run each, a page is
first touched, and faulted in, by the one thread that writes it, and the threads fault their
pages side by side.

The caller solves the first run itself; the others' runs go to helper threads of one pool,
started once for the process (and anew in a forked child), not for every call.
"""

from __future__ import annotations

import os
import threading
from collections import deque
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor, wait


def over_chunks(n: int, chunk: int, workers: int | None, one: Callable[[int], None]) -> None:
    """``one(start)`` for every chunk of ``chunk`` samples of ``n``, on ``workers`` threads
    (default: one per core; one chunk or one worker: in this thread, in order): this thread
    and helpers from a pool started once (`_shared`). Each thread solves a run of
    consecutive chunks, then helps the others with theirs (`runs`). Called from within a
    chunk, it runs in that chunk's thread alone (the pool's threads may all be busy with
    the outer chunks: waiting on them would idle this one)."""
    starts = range(0, n, chunk)
    threads = min(workers or os.cpu_count() or 1, len(starts))
    if threads <= 1 or getattr(_inside, "here", False):
        for s in starts:
            one(s)
        return
    queues = runs(len(starts), threads)
    lock = threading.Lock()

    def next_start(t: int) -> int | None:
        with lock:
            if queues[t]:
                return starts[queues[t].popleft()]
            longest = max(queues, key=len)
            return starts[longest.pop()] if longest else None

    def work(t: int) -> None:
        while (s := next_start(t)) is not None:
            one(s)

    def inside(t: int) -> None:  # a chunk's own `over_chunks` runs in its thread
        outer = getattr(_inside, "here", False)
        _inside.here = True
        try:
            work(t)
        finally:
            _inside.here = outer

    pool = _shared(threads)
    helpers = [pool.submit(inside, t) for t in range(1, threads)]
    try:
        inside(0)  # (this thread takes the first run: it would wait idle otherwise)
    finally:
        wait(helpers)  # (no chunk left running when this returns, or raises)
    for h in helpers:
        h.result()


def _shared(threads: int) -> ThreadPoolExecutor:
    """The pool of helper threads every `over_chunks` shares, at least ``threads - 1`` of
    them: started once (a pool started and joined for each call cost ≈ 160 µs, a tenth of
    a 10⁴-sample solve, and a continuation calls it dozens of times)."""
    global _pool, _pool_size
    with _pool_lock:
        if _pool is None or _pool_size < threads - 1:
            _pool_size = max(threads - 1, (os.cpu_count() or 1) - 1, 1)
            _pool = ThreadPoolExecutor(_pool_size, thread_name_prefix="excavkin-chunks")
        return _pool


def _forget_pool() -> None:
    """A forked child has none of its parent's threads: its pool starts anew."""
    global _pool, _pool_lock
    _pool, _pool_lock = None, threading.Lock()


_pool: ThreadPoolExecutor | None = None
_pool_size = 0
_pool_lock = threading.Lock()
#: whether this thread is running a chunk (a chunk's own `over_chunks` then runs in it
#: alone: waiting on the pool from inside a chunk could wait on the outer chunks, or itself)
_inside = threading.local()
os.register_at_fork(after_in_child=_forget_pool)


def even(n: int, chunk: int) -> int:
    """Samples per chunk that cut ``n`` samples into as few chunks as ``chunk`` allows, all
    of about one size: a remnant of a few samples would leave the thread given it idle while
    another solves a whole chunk more. It depends on ``n`` and ``chunk`` alone, not on the
    threads (a NumPy Newton pass takes its chord steps a chunk at a time: the result stays the
    same on any number of threads).

    Parameters
    ----------
    n : int
        Samples.
    chunk : int
        Samples per chunk at most.

    Returns
    -------
    int
    """
    chunks = max(-(-n // chunk), 1)
    return max(1, -(-n // chunks))


def runs(chunks: int, threads: int) -> list[deque[int]]:
    """The chunks' indices dealt into ``threads`` runs of consecutive chunks, their lengths
    differing by one at most.

    Parameters
    ----------
    chunks : int
    threads : int

    Returns
    -------
    list of deque of int
        One run per thread, in order: together every index once.
    """
    return [
        deque(range(chunks * t // threads, chunks * (t + 1) // threads)) for t in range(threads)
    ]
