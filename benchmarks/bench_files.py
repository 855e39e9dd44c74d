"""Tables and large sweeps, as ratios measured in one run.

Run: ``python benchmarks/bench_files.py [--large]``. On ``examples/fourbar.toml``:

* **CSV** and **Parquet** writing (``excavkin.outputs.tables.write_table``) of the four-bar's
  table of 2·10⁵ samples, in rows/s, against pandas' own ``to_csv`` and ``to_parquet`` of the
  same frame. Target for CSV: ≥ 10× pandas.
* **to_frame** of 10⁶ samples against their solve. Target: ≤ 1× (no copies).
* **columns=**: writing 10⁶ samples' whole table against 3 columns of it (``columns=``), CSV
  and Parquet, as the ratio of their times; and solving them: ``solve_stream`` of 10⁶
  four-bar and excavator samples (10⁷ with ``--large``), every part's table made, 3 columns
  against every column (the compiled kernel writes out only the rows asked).
* **parts**: 2·10⁶ rows of the whole table, in parts of 262 144, written as one Parquet file
  (one encoding thread) and as a folder of parts (``write_parts``, a thread a core).
* **excavkin solve** of 10⁶ samples to CSV and to Parquet, end to end (a process each).
* with ``--large`` (about 4 GB of memory and 20 GB of disk for a while): the in-memory solve's
  time per sample at 10⁷ against 10⁶ (target ≤ 1.3×; beside it, for reference, the same with
  NumPy's huge-page advice on the result's arrays), and ``excavkin solve`` streaming 10⁸
  samples to Parquet: time, file size and peak memory (``/usr/bin/time -v``); then the same
  with three columns (``--columns B.x,B.y,rocker.angle``) against the solve of those 10⁸
  samples streamed in parts and not written, plus the disk's time to write the file's bytes
  (the same number of bytes written by plain ``write`` calls of 64 MiB). Target ≤ 2×. Every
  file is removed afterwards.

Best of several repeats in the same process. Not a test: machines differ; the ratios are what
is tracked.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from timing import best_of

import excavkin
from excavkin.outputs.tables import write_table


def writing(n: int, folder: Path) -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    frame = mech.solve({"crank": np.linspace(0.0, 6.0 * np.pi, n)}, {"crank": 31.416}).to_frame()

    def ours(suffix: str) -> float:
        target = folder / f"ours{suffix}"
        return best_of(lambda: write_table(frame, target, force=True), repeat=3)

    plain = frame.assign(status=frame["status"].astype(str))
    t_csv = ours(".csv")
    t_pandas_csv = best_of(lambda: plain.to_csv(folder / "pandas.csv", index=False), repeat=1)
    t_parquet = ours(".parquet")
    t_pandas_parquet = best_of(lambda: plain.to_parquet(folder / "pandas.parquet"), repeat=3)
    print(f"writing the four-bar's table, {n:,} rows × {frame.shape[1]} columns")
    print(f"  CSV     excavkin {n / t_csv:12,.0f} rows/s   pandas {n / t_pandas_csv:10,.0f}"
          f" rows/s   ratio {t_pandas_csv / t_csv:5.1f}  (target ≥ 10)")  # fmt: skip
    ratio = t_pandas_parquet / t_parquet
    print(f"  Parquet excavkin {n / t_parquet:12,.0f} rows/s   pandas "
          f"{n / t_pandas_parquet:10,.0f} rows/s   ratio {ratio:5.1f}")  # fmt: skip


def frames(n: int) -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    q = np.linspace(0.0, 2.0 * np.pi, n)
    t_solve = best_of(lambda: mech.solve({"crank": q}))
    res = mech.solve({"crank": q})
    t_frame = best_of(res.to_frame)
    forces = mech.solve({"crank": q}, loads="model")
    t_forces = best_of(forces.to_frame)
    print(f"to_frame, {n:,} samples")
    print(f"  kinematics {t_frame * 1e3:7.1f} ms = {t_frame / t_solve:5.3f} × the solve "
          f"({t_solve * 1e3:.0f} ms; target ≤ 1)")  # fmt: skip
    print(
        f"  forces     {t_forces * 1e3:7.1f} ms = {t_forces / t_solve:5.3f} × the kinematic solve"
    )


def selected(n: int, folder: Path) -> None:
    """Writing the whole table against three of its columns (and status)."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    frame = mech.solve({"crank": np.linspace(0.0, 6.0 * np.pi, n)}, {"crank": 31.416}).to_frame()
    asked = ["B.x", "B.y", "rocker.angle"]
    print(f"writing {n:,} samples: all {frame.shape[1]} columns against {len(asked)} (columns=)")
    for suffix in (".csv", ".parquet"):
        target = folder / f"cols{suffix}"
        t_all = best_of(lambda t=target: write_table(frame, t, force=True), repeat=2)
        t_some = best_of(
            lambda t=target: write_table(frame, t, force=True, columns=asked), repeat=3
        )
        print(f"  {suffix[1:]:8} all {t_all * 1e3:8.0f} ms   3 columns {t_some * 1e3:7.0f} ms"
              f"   ratio {t_all / t_some:5.1f}")  # fmt: skip


def parted(n: int, size: int, folder: Path) -> None:
    """The same frames written as one Parquet file and as a folder of parts on threads."""
    import shutil

    from excavkin.outputs.table_parts import part_threads, write_parts
    from excavkin.outputs.tables import write_tables

    mech = excavkin.load(excavkin.example_path("fourbar"))
    frame = mech.solve({"crank": np.linspace(0.0, 6.0 * np.pi, n)}, {"crank": 31.416}).to_frame()
    pieces = [frame.iloc[at : at + size] for at in range(0, n, size)]
    for piece in pieces:
        piece.attrs = frame.attrs
    one = folder / "one.parquet"
    t_one = best_of(lambda: write_tables(pieces, one, force=True), repeat=2)
    t_parts = best_of(lambda: write_parts(pieces, folder / "parts", force=True), repeat=2)
    shutil.rmtree(folder / "parts")
    one.unlink()
    print(f"{n:,} rows × {frame.shape[1]} columns in {len(pieces)} parts to Parquet: one file "
          f"{t_one:5.2f} s, a folder of parts on {part_threads()} threads {t_parts:5.2f} s; "
          f"ratio {t_one / t_parts:4.2f}")  # fmt: skip


#: the three columns a streamed solve asks of each model (`streamed`)
ASKED = {"fourbar": ["B.x", "B.y", "rocker.angle"], "excavator": ["W.x", "W.y", "bucket.angle"]}


def streamed(n: int, repeat: int = 3) -> None:
    """``solve_stream`` of ``n`` samples (rates given), every part's table made, asking three
    columns against every column: the compiled kernel writes out only the rows asked (and
    those the checks read), every status as the full solve's. Runs taken in turn; the
    processor time of every thread (steadier than the wall's on a busy machine) and the wall
    time, each the least of the runs, and the kernel's rows written out a sample."""
    from excavkin.kinematics import compiled
    from excavkin.kinematics.selection import asked_names, kept_rows
    from excavkin.kinematics.vectorise import written_rows
    from excavkin.sweeps import Linspace

    print(f"solve_stream of {n:,} samples, every part's to_frame(): all columns against 3")
    for name, asked in ASKED.items():
        mech = excavkin.load(excavkin.example_path(name))
        values: dict[str, object] = {}
        for k, v in mech.sketch_values().items():  # every driver about its sketch value
            if mech.input_kind(k) == "angle":
                values[k] = Linspace(v - 0.3, v + 0.3, n)
            else:
                values[k] = Linspace(0.97 * v, 1.03 * v, n)
        rates = {k: 0.5 for k in values}

        def run(
            columns: list[str] | None,
            mech: excavkin.Mechanism = mech,
            values: dict[str, object] = values,
            rates: dict[str, float] = rates,
        ) -> tuple[float, float]:
            cpu, wall = time.process_time(), time.perf_counter()
            for part in mech.solve_stream(values, rates, columns=columns, backend="numba"):
                part.to_frame()
            return time.process_time() - cpu, time.perf_counter() - wall

        run(asked)  # the kernels compiled (or loaded) before
        runs: dict[bool, list[tuple[float, float]]] = {False: [], True: []}
        for _ in range(repeat):
            for some in (False, True):
                runs[some].append(run(asked if some else None))
        every, some = ([min(r[k] for r in runs[s]) for k in range(2)] for s in (False, True))
        rows, n_rows = written_rows(compiled.kernel_source(mech.plan, keep=True))
        kept = int(kept_rows(mech.plan, rows, n_rows, asked_names(mech.plan, asked)).sum())
        print(f"  {name:10s} every column ({len(rows)} rows written): {every[0] / n * 1e9:4.0f} "
              f"ns/sample processor, {every[1] / n * 1e9:4.0f} wall")  # fmt: skip
        print(f"  {'':10s} 3 columns ({kept} rows written):     {some[0] / n * 1e9:4.0f} "
              f"ns/sample processor, {some[1] / n * 1e9:4.0f} wall; 3 columns / every: "
              f"processor {some[0] / every[0]:.2f}, wall {some[1] / every[1]:.2f}")  # fmt: skip


def command(args: list[str], suffix: str, folder: Path) -> tuple[float, int, int]:
    """Seconds, peak resident memory (bytes) and the file's size of an ``excavkin`` run
    writing a table of that suffix."""
    out = folder / f"out{suffix}"
    argv = [sys.executable, "-m", "excavkin", *args, "-o", str(out), "-q", "--force"]
    timed = Path("/usr/bin/time").exists()
    t0 = time.perf_counter()
    run = subprocess.run(
        ["/usr/bin/time", "-v", *argv] if timed else argv, capture_output=True, text=True
    )
    seconds = time.perf_counter() - t0
    if run.returncode:
        raise SystemExit(run.stderr)
    peak = re.search(r"Maximum resident set size \(kbytes\): (\d+)", run.stderr)
    size = out.stat().st_size
    out.unlink()
    return seconds, int(peak.group(1)) * 1024 if peak else -1, size


def end_to_end(n: int, folder: Path) -> None:
    print(f"excavkin solve fourbar --sweep crank=0deg:360deg:{n:,}, streamed, end to end")
    for suffix in (".csv", ".parquet"):
        seconds, peak, size = command(
            ["solve", "fourbar", "--sweep", f"crank=0deg:360deg:{n}"], suffix, folder
        )
        print(f"  {suffix[1:]:8} {seconds:6.1f} s  {n / seconds:12,.0f} samples/s  "
              f"file {size / 2**20:8,.0f} MiB  peak memory {peak / 2**20:6,.0f} MiB")  # fmt: skip


def per_sample(mech: excavkin.Mechanism) -> dict[int, float]:
    """Seconds per sample of the in-memory solve at 10⁶ and 10⁷ samples."""
    per = {}
    for n in (10**6, 10**7):
        q = np.linspace(0.0, 2.0 * np.pi, n)
        per[n] = best_of(lambda q=q: mech.solve({"crank": q}), repeat=3) / n
    return per


def large(folder: Path) -> None:
    import contextlib

    from excavkin.kinematics import solve

    mech = excavkin.load(excavkin.example_path("fourbar"))
    print("in-memory solve, time per sample")

    def huge(nbytes: int) -> contextlib.AbstractContextManager[None]:
        return contextlib.nullcontext()

    for label, pages in (("as shipped", None), ("huge pages", huge)):
        kept = solve._small_pages
        if pages is not None:  # the reference: NumPy's huge-page advice left on
            solve._small_pages = pages  # type: ignore[assignment]
        try:
            per = per_sample(mech)
        finally:
            solve._small_pages = kept
        print(f"  {label:15} 10⁶ {per[10**6] * 1e9:6.1f} ns   10⁷ {per[10**7] * 1e9:6.1f} ns"
              f"   ratio {per[10**7] / per[10**6]:4.2f}"
              + ("  (target ≤ 1.3)" if pages is None else ""))  # fmt: skip
    n = 10**8
    seconds, peak, size = command(
        ["solve", "fourbar", "--sweep", f"crank=0deg:3600deg:{n}"], ".parquet", folder
    )
    print(f"excavkin solve, {n:,} samples streamed to Parquet")
    print(f"  {seconds:6.1f} s  {n / seconds:12,.0f} samples/s  file {size / 2**30:6.2f} GiB  "
          f"peak memory {peak / 2**20:6,.0f} MiB")  # fmt: skip
    selected_large(mech, n, folder)


def disk_write(nbytes: int, folder: Path) -> float:
    """Seconds to write ``nbytes`` to a new file of ``folder`` by plain 64 MiB writes."""
    block = np.random.default_rng(0).bytes(64 * 2**20)
    target = folder / "disk.bin"
    t0 = time.perf_counter()
    with target.open("wb") as out:
        for at in range(0, nbytes, len(block)):
            out.write(block[: min(len(block), nbytes - at)])
    seconds = time.perf_counter() - t0
    target.unlink()
    return seconds


def selected_large(mech: excavkin.Mechanism, n: int, folder: Path) -> None:
    """Three columns of ``n`` samples to Parquet, end to end, against the solve of the same
    samples (streamed, nothing written) plus the disk's time to write the file's bytes."""
    from excavkin.sweeps import Linspace

    columns = "B.x,B.y,rocker.angle"
    seconds, peak, size = command(
        ["solve", "fourbar", "--sweep", f"crank=0deg:3600deg:{n}", "--columns", columns],
        ".parquet",
        folder,
    )
    sweep = {"crank": Linspace(0.0, 20.0 * np.pi, n)}
    t0 = time.perf_counter()
    for _ in mech.solve_stream(sweep):
        pass
    solving = time.perf_counter() - t0
    disk = disk_write(size, folder)
    print(f"excavkin solve, {n:,} samples, --columns {columns}, to Parquet")
    print(f"  {seconds:6.1f} s end to end (file {size / 2**30:5.2f} GiB, peak memory "
          f"{peak / 2**20:5,.0f} MiB); the solve alone {solving:5.1f} s, the disk's write "
          f"{disk:4.1f} s; ratio {seconds / (solving + disk):4.2f}  (target ≤ 2)")  # fmt: skip


def main() -> None:
    big = "--large" in sys.argv[1:] or os.environ.get("EXCAVKIN_BENCH_LARGE") == "1"
    with tempfile.TemporaryDirectory(prefix="excavkin-bench-") as tmp:
        folder = Path(tmp)
        writing(200_000, folder)
        frames(1_000_000)
        selected(1_000_000, folder)
        parted(2_000_000, 262_144, folder)
        streamed(1_000_000)
        end_to_end(1_000_000, folder)
        if big:
            streamed(10_000_000, repeat=2)
            large(folder)


if __name__ == "__main__":
    main()
