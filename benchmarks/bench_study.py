"""A design study at scale: designs × poses of the four-bar, full kinematic state and metrics,
locally and on a local Dask cluster.

Run: ``python benchmarks/bench_study.py [DESIGNS] [--dask]`` (default 100 000 designs × 100
poses; the issue's target is 10⁶ designs × 100 poses in ≤ 30 min on this machine). Prints
designs/s and samples/s, the projected time of 10⁶ designs, and with ``--dask`` the Dask run's
time and its efficiency (local time / Dask time on the same cores).
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import excavkin
from excavkin.studies.metrics import Metric, Poses
from excavkin.studies.study import Study, run_study


def study(designs: int) -> Study:
    return Study(
        model=Path(excavkin.example_path("fourbar")),
        bounds={"A-B": (0.10, 0.14), "O4-B": (0.07, 0.11), "O4.x": (0.09, 0.115)},
        poses=Poses({"crank": np.linspace(0.0, 2 * np.pi, 100)}, {"crank": 31.4}, {}),
        metrics=(
            Metric("gamma_min", "B.transmission", "min"),
            Metric("omega_peak", "rocker.omega", "absmax"),
            Metric("swing_top", "rocker.angle", "max"),
        ),
        samples=designs,
    )


def main(designs: int = 100_000, dask: bool = False) -> None:
    s = study(designs)
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        run_study(s, Path(tmp) / "local.parquet")
        local = time.perf_counter() - t
        print(f"study: {designs:,} designs × 100 poses of the four-bar, 3 metrics")
        print(f"  local       : {local:7.1f} s  {designs / local:10,.0f} designs/s  "
              f"{designs * 100 / local / 1e6:5.2f} M samples/s")  # fmt: skip
        print(f"  10⁶ designs : {local * 1e6 / designs / 60:7.1f} min projected (target ≤ 30)")
        if dask:
            t = time.perf_counter()
            run_study(s, Path(tmp) / "dask.parquet", scheduler="dask")
            remote = time.perf_counter() - t
            print(f"  Dask, local cluster: {remote:7.1f} s, efficiency {local / remote:.2f} "
                  "(local time / Dask time, same cores)")  # fmt: skip


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    main(int(args[0]) if args else 100_000, "--dask" in sys.argv)
