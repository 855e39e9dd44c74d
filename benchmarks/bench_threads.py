"""Threads on fresh result memory: the compiled four-bar and excavator solves on 1 and N
threads (default: one per core), each solve writing a new result, as ``mech.solve`` does.

Run: ``python benchmarks/bench_threads.py [n] [threads]``.
Prints, for each mechanism, samples per second on 1 and N threads, the 1 → N scaling, and per
solve the minor page faults and the system (kernel) time, which is where faulting the result's
pages in goes, read from ``getrusage``. Two schedules, in turn in the same run:

- ``runs``: as shipped (`excavkin.kinematics.threads.over_chunks`), each thread a run of
  consecutive chunks, so each page of the result is faulted in by the one thread that writes it;
- ``dealt``: the chunks dealt to the threads in turn (how it was before), every thread
  writing into the same pages at once.

Then the four-bar's sweep of n samples streamed to Parquet (``solve_stream`` into
``write_tables``, as ``excavkin solve`` does), in turn: as shipped, each frame made Arrow arrays
as it is made and encoded on the writer thread while the next part is solved, against the
writer thread doing both (how it was before).

Not a test: machines differ (page faults most of all: a machine whose memory is nearly all in
use reclaims it as they come); the ratios are what is tracked.
"""

from __future__ import annotations

import os
import resource
import sys
import tempfile
import time
from collections.abc import Callable, Iterable
from concurrent.futures import Future, ThreadPoolExecutor
from functools import partial
from pathlib import Path

import numpy as np

import excavkin
from excavkin.io.files import check_target, write_atomic
from excavkin.kinematics import solve as solve_module
from excavkin.kinematics import threads as threads_module
from excavkin.outputs.tables import TableWriter, write_tables


def dealt(n: int, chunk: int, workers: int | None, one: Callable[[int], None]) -> None:
    """The chunks dealt to the threads in turn (the schedule before runs)."""
    starts = range(0, n, chunk)
    threads = min(workers or os.cpu_count() or 1, len(starts))
    if threads > 1:
        with ThreadPoolExecutor(threads) as pool:
            list(pool.map(one, starts))
    else:
        for s in starts:
            one(s)


def before(frames: Iterable[object], path: Path) -> None:
    """The frames written as before: made Arrow arrays and encoded on the writer thread."""

    def write(tmp: Path) -> None:
        with TableWriter(tmp, parquet=True) as out, ThreadPoolExecutor(1) as writer:
            pending: Future[None] | None = None
            for frame in frames:
                if pending is not None:
                    pending.result()
                pending = writer.submit(out.write, frame)  # type: ignore[arg-type]
            if pending is not None:
                pending.result()

    write_atomic(check_target(path, force=True, suffixes=(".parquet",)), write)


def streamed(n: int, repeat: int) -> None:
    """The four-bar's sweep streamed to Parquet: as shipped against as before."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    q = np.linspace(0.0, 20.0 * np.pi, n)
    mech.solve({"crank": q[:1000]}, {"crank": 31.416}, backend="numba")

    def frames() -> Iterable[object]:
        for part in mech.solve_stream({"crank": q}, {"crank": 31.416}):
            yield part.result.to_frame()

    with tempfile.TemporaryDirectory(prefix="excavkin-bench-") as tmp:
        target = Path(tmp) / "out.parquet"
        ways = {
            "as shipped": lambda: write_tables(frames(), target, force=True),  # type: ignore[arg-type]
            "before": lambda: before(frames(), target),
        }
        got: dict[str, list[float]] = {k: [] for k in ways}
        for _ in range(repeat):
            for label, fn in ways.items():
                got[label].append(measured(fn)[0])
        size = target.stat().st_size
    print(f"four-bar, {n:,} samples streamed to Parquet ({size / 2**20:,.0f} MiB), "
          f"{repeat} rounds (best; median)")  # fmt: skip
    for label, times in got.items():
        print(f"  {label:10s}: {n / min(times) / 1e6:6.2f}; "
              f"{n / float(np.median(times)) / 1e6:6.2f} M samples/s")  # fmt: skip
    ratio = min(got["before"]) / min(got["as shipped"])
    times_shipped, times_before = got.values()
    per_round = float(np.median([b / a for a, b in zip(times_shipped, times_before, strict=True)]))
    print(f"  before / as shipped: {ratio:.2f}×; {per_round:.2f}× (median)")


def inputs(name: str, n: int) -> tuple[excavkin.Mechanism, dict[str, np.ndarray], dict[str, float]]:
    mech = excavkin.load(excavkin.example_path(name))
    if name == "fourbar":
        return mech, {"crank": np.linspace(0.0, 2 * np.pi, n)}, {"crank": 31.416}
    values = {}
    for k, v in mech.sketch_values().items():
        span = 0.3 if mech.input_kind(k) == "angle" else 0.03 * v
        values[k] = v + span * np.sin(np.linspace(0.0, 7.0, n) + len(k))
    return mech, values, {k: 0.5 for k in values}


def measured(fn: Callable[[], object]) -> tuple[float, int, float, int]:
    """Wall time, minor faults, system time and the solving threads' voluntary context
    switches (a thread waiting: on another's fault of the same page, among others; the
    calling thread's own, waiting for the others, left out) of ``fn()`` (its result dropped
    at once)."""
    before = resource.getrusage(resource.RUSAGE_SELF)
    here = resource.getrusage(resource.RUSAGE_THREAD).ru_nvcsw
    t0 = time.perf_counter()
    fn()
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_SELF)
    here = resource.getrusage(resource.RUSAGE_THREAD).ru_nvcsw - here
    return (
        wall,
        after.ru_minflt - before.ru_minflt,
        after.ru_stime - before.ru_stime,
        after.ru_nvcsw - before.ru_nvcsw - here,
    )


def main(n: int = 2_000_000, threads: int | None = None, repeat: int = 5) -> None:
    streamed(n, repeat)
    scaling(n, threads or os.cpu_count() or 1, repeat)


def scaling(n: int, threads: int, repeat: int) -> None:
    """Samples per second of the compiled solves on 1 and ``threads`` threads, both
    schedules in turn."""
    schedules = {"runs": threads_module.over_chunks, "dealt": dealt}
    for name in ("fourbar", "excavator"):
        mech, values, rates = inputs(name, n)
        mech.solve({k: v[:1000] for k, v in values.items()}, rates=rates, backend="numba")
        got: dict[tuple[str, int], list[tuple[float, int, float, int]]] = {}
        for _ in range(repeat):  # in turn, so that the machine's load falls on all alike
            for label, schedule in schedules.items():
                solve_module.over_chunks = schedule  # type: ignore[attr-defined]
                for w in (1, threads):
                    solve = partial(mech.solve, values, rates=rates, backend="numba", workers=w)
                    got.setdefault((label, w), []).append(measured(solve))
        solve_module.over_chunks = threads_module.over_chunks  # type: ignore[attr-defined]
        print(f"{name}, compiled, fresh result each solve, N = {n:,}, {repeat} rounds "
              "(best; median)")  # fmt: skip
        for label in schedules:
            best = {w: min(got[(label, w)]) for w in (1, threads)}
            median = {w: float(np.median([t[0] for t in got[(label, w)]])) for w in (1, threads)}
            for w in (1, threads):
                wall, faults, system, waits = best[w]
                print(f"  {label:5s} {w:2d} threads: {n / wall / 1e6:6.2f}; "
                      f"{n / median[w] / 1e6:6.2f} M samples/s, {faults:8,d} faults, "
                      f"{system:5.2f} s system of {wall:5.2f} s, {waits:6,d} waits")  # fmt: skip
            print(f"  {label:5s} 1 → {threads} threads: {best[1][0] / best[threads][0]:.2f}×; "
                  f"{median[1] / median[threads]:.2f}×")  # fmt: skip


if __name__ == "__main__":
    args = [int(a) for a in sys.argv[1:]]
    main(*args)
