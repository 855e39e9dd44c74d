"""The chunks' schedule over threads (`excavkin.kinematics.threads`): every chunk once, each
thread a run of consecutive chunks, a slow thread's chunks taken by the others."""

from __future__ import annotations

import os
import threading
import time

import pytest

from excavkin.kinematics.threads import even, over_chunks, runs


@pytest.mark.parametrize(("chunks", "threads"), [(1, 1), (7, 2), (8, 2), (30, 16), (3, 5)])
def test_runs_are_consecutive_and_cover_every_chunk_once(chunks: int, threads: int) -> None:
    got = runs(chunks, threads)
    assert len(got) == threads
    assert [i for run in got for i in run] == list(range(chunks))
    sizes = [len(run) for run in got]
    assert max(sizes) - min(sizes) <= 1


@pytest.mark.parametrize(
    ("n", "chunk", "workers"), [(10, 3, 2), (100, 7, 3), (5, 10, 4), (9, 1, 1)]
)
def test_every_start_once(n: int, chunk: int, workers: int) -> None:
    seen: list[int] = []
    lock = threading.Lock()

    def one(s: int) -> None:
        with lock:
            seen.append(s)

    over_chunks(n, chunk, workers, one)
    assert sorted(seen) == list(range(0, n, chunk))


def test_each_thread_starts_on_its_own_run_and_a_slow_one_is_helped() -> None:
    by_thread: dict[int, list[int]] = {}
    lock = threading.Lock()
    others_done = threading.Event()
    waited: list[bool] = []

    def one(s: int) -> None:
        with lock:
            by_thread.setdefault(threading.get_ident(), []).append(s)
            if sum(len(v) for v in by_thread.values()) == 8:
                others_done.set()
        if s == 0:  # the first run's thread is held up until every other chunk is done:
            waited.append(others_done.wait(timeout=30))  # its run's rest taken by the other

    over_chunks(8, 1, 2, one)
    assert waited == [True]
    firsts = sorted(starts[0] for starts in by_thread.values())
    assert firsts == [0, 4]  # each thread began at its run's first chunk
    slow = next(starts for starts in by_thread.values() if starts[0] == 0)
    assert slow == [0]
    assert sorted(s for starts in by_thread.values() for s in starts) == list(range(8))


@pytest.mark.parametrize(
    ("n", "chunk"), [(65536, 7281), (1_000_000, 7281), (5, 10), (1, 7281), (100, 7), (9, 1)]
)
def test_even_chunks_are_as_few_as_the_chunk_allows_and_of_one_size(n: int, chunk: int) -> None:
    size = even(n, chunk)
    assert 1 <= size <= chunk
    count = -(-n // size)
    assert count == -(-n // chunk)  # as few chunks as before
    last = n - (count - 1) * size
    assert last > 0 and size - last < count  # the last short by less than their number


def test_a_block_is_dealt_to_two_threads_equally() -> None:
    """65 536 samples in chunks of at most 7 281: nine of 6 554 and one of 6 550, five for
    each thread, not nine whole chunks and a remnant of 7."""
    size = even(65536, 7281)
    assert size == 6554
    shares = [sum(min(size, 65536 - i * size) for i in run) for run in runs(10, 2)]
    assert shares == [32770, 32766]


def test_the_helper_threads_are_started_once_and_shared() -> None:
    """A second call reuses the helpers of the first (no pool started and joined per call)."""
    idents: list[set[int]] = []
    for _ in range(2):
        seen: set[int] = set()
        lock = threading.Lock()
        gate = threading.Barrier(2, timeout=30)

        def one(
            s: int,
            seen: set[int] = seen,
            lock: threading.Lock = lock,
            gate: threading.Barrier = gate,
        ) -> None:
            gate.wait()  # (both threads run a chunk at once: two threads, surely)
            with lock:
                seen.add(threading.get_ident())

        over_chunks(2, 1, 2, one)
        idents.append(seen)
    assert threading.get_ident() in idents[0]  # the caller takes a run itself
    assert idents[0] == idents[1] and len(idents[0]) == 2


def test_a_chunk_that_splits_again_runs_its_own_chunks_in_its_thread() -> None:
    """`over_chunks` called from within a chunk does not wait on the pool (whose threads
    may all be busy with the outer chunks): its chunks run in that chunk's thread."""
    inner: dict[int, set[int]] = {}
    lock = threading.Lock()

    def outer(s: int) -> None:
        mine: set[int] = set()

        def one(_: int) -> None:
            with lock:
                mine.add(threading.get_ident())
            time.sleep(0.002)  # (long enough for an idle helper to take a chunk, if it may)

        over_chunks(8, 1, 4, one)
        with lock:
            inner[s] = mine

    over_chunks(4, 1, 4, outer)
    assert sorted(inner) == [0, 1, 2, 3]
    assert all(len(ids) == 1 for ids in inner.values())  # the caller's chunks' too


def test_an_error_in_a_chunk_is_raised_once_every_chunk_has_stopped() -> None:
    done: list[int] = []
    lock = threading.Lock()

    def one(s: int) -> None:
        if s == 5:
            raise ValueError("chunk 5")
        with lock:
            done.append(s)

    with pytest.raises(ValueError, match="chunk 5"):
        over_chunks(8, 1, 2, one)
    settled = list(done)
    assert len(settled) >= 4  # the other thread's run finished; nothing runs after the raise
    threading.Event().wait(0.05)
    assert done == settled


@pytest.mark.skipif(not hasattr(os, "fork"), reason="os.fork is POSIX's")
def test_a_forked_child_starts_its_own_helpers() -> None:
    """A child forked after the helpers started has none of its parent's threads: its chunks
    still run (the pool it inherited would wait forever)."""
    over_chunks(4, 1, 2, lambda s: None)  # (the parent's helpers started)
    pid = os.fork()
    if pid == 0:  # the child: its chunks, on two threads, then out
        seen: list[int] = []
        over_chunks(4, 1, 2, seen.append)
        os._exit(0 if sorted(seen) == [0, 1, 2, 3] else 1)
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            assert os.waitstatus_to_exitcode(status) == 0
            return
        time.sleep(0.01)
    os.kill(pid, 9)
    os.waitpid(pid, 0)
    pytest.fail("the forked child's chunks did not finish in 30 s")
