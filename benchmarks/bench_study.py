"""A design study at scale: designs × poses of the four-bar, three kinematic metrics, against
the engine solving the same number of samples of one design, in one run.

Run: ``python benchmarks/bench_study.py [DESIGNS] [--dask] [--repeat N]`` (default 20 000
designs × 100 poses = 2·10⁶ samples). Prints, best of N runs each (default 3), interleaved:

- the engine: one design's full kinematic state over the same 2·10⁶ samples (its compiled
  kernel, every core);
- the study: `run_study` of the designs, every core, its table written;
- their ratio (engine time / study time: 1.0 is the study at engine speed), and the ratio
  of their CPU time (every thread's), which other work on a shared machine disturbs less;
- the share of the study's wall time during which a thread held the GIL, sampled: a probe
  thread wakes about every millisecond and asks for the GIL; a wake-up that waits more than
  `LATE` seconds beyond its sleep found the GIL held (the share of such wake-ups estimates
  the share of the time it is held; the probe's own idle overshoot is measured first and
  taken off). Sampled over N runs of the study (each after its own idle measurement): their
  median and range, as other work on a shared machine makes the probe late too (it counts
  as held: the estimate errs high). The same probe over the engine's solve is printed
  beside it as a control: a compiled solve on every core that holds the GIL little, its
  share is mostly the probe's lateness for want of a core;
- with ``--dask``, a local Dask cluster's time on the same cores.

``python benchmarks/bench_study.py --device [DESIGNS] [--poses=P] [--call=K] [--repeat=N]``
(default 10⁹ designs × 100 poses, K = 10⁶ designs a call, N = 1; a run of fewer designs,
such as 10⁷, projects the time of 10⁹ from its own): the study on an NVIDIA GPU
(``backend="cuda"``, `excavkin.studies.device`: solved and reduced on the device, only the
metrics brought back), DESIGNS designs in calls of K (one set of K designs, drawn once,
evaluated again each call, so that the time is the study's and not the drawing's), against
the CPU engine (one design's full state, compiled, every core) on min(DESIGNS · P, 2·10⁶)
samples: each one's samples/s and their ratio, and the first call's table against the
CPU's study of the same designs (the largest difference of a metric, relative to its
column's largest magnitude: a GPU's fused multiply-adds and its own sine and cosine differ
from the CPU's in the last bits). ``NUMBA_ENABLE_CUDASIM=1`` runs it in numba's CUDA
simulator, one thread at a time in Python: a smoke test with a tiny DESIGNS and P, its
figures meaningless.
"""

from __future__ import annotations

import random
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

import excavkin
from excavkin.studies.metrics import Metric, Poses
from excavkin.studies.study import Study, run_study

#: a probe's wake-up later than this beyond its sleep found the GIL held
LATE = 2e-4
POSES = 100


def study(designs: int) -> Study:
    return Study(
        model=Path(excavkin.example_path("fourbar")),
        bounds={"A-B": (0.10, 0.14), "O4-B": (0.07, 0.11), "O4.x": (0.09, 0.115)},
        poses=Poses({"crank": np.linspace(0.0, 2 * np.pi, POSES)}, {"crank": 31.4}, {}),
        metrics=(
            Metric("gamma_min", "B.transmission", "min"),
            Metric("omega_peak", "rocker.omega", "absmax"),
            Metric("swing_top", "rocker.angle", "max"),
        ),
        samples=designs,
    )


class Probe:
    """Samples whether the GIL is held: a thread that sleeps a random 0.5–1.5 ms and counts
    the wake-ups that come late (`LATE`)."""

    def __init__(self) -> None:
        self.stop = threading.Event()
        self.wakes = 0
        self.late = 0
        self.thread = threading.Thread(target=self._run, daemon=True)

    def _run(self) -> None:
        rng = random.Random(0)
        while not self.stop.is_set():
            want = rng.uniform(5e-4, 1.5e-3)
            t0 = time.perf_counter()
            time.sleep(want)
            self.wakes += 1
            self.late += time.perf_counter() - t0 - want > LATE

    def __enter__(self) -> Probe:
        self.thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop.set()
        self.thread.join()

    @property
    def share(self) -> float:
        return self.late / max(self.wakes, 1)


def held_share(run: Callable[[], object]) -> tuple[float, float]:
    """The share of ``run``'s wall time during which the GIL is held (sampled, the probe's
    idle lateness taken off), and the wall time with the probe running."""
    with Probe() as idle:
        time.sleep(0.5)
    with Probe() as probe:
        t = time.perf_counter()
        run()
        wall = time.perf_counter() - t
    return max(0.0, probe.share - idle.share), wall


def main(designs: int = 20_000, dask: bool = False, repeat: int = 3) -> None:
    s = study(designs)
    mech = excavkin.load(s.model)
    crank = np.tile(np.linspace(0.0, 2 * np.pi, POSES), designs)
    n = designs * POSES
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)

        def engine() -> None:
            mech.solve({"crank": crank}, {"crank": 31.4}, backend="numba")

        def local() -> None:
            run_study(s, out / "local.parquet", force=True)

        engine()
        local()  # (the kernels compiled or loaded, the pages of the process touched)
        times: dict[str, list[float]] = {"engine": [], "study": []}
        cpu: dict[str, list[float]] = {"engine": [], "study": []}
        for _ in range(repeat):
            for name, run in (("engine", engine), ("study", local)):
                t, c = time.perf_counter(), time.process_time()
                run()
                times[name].append(time.perf_counter() - t)
                cpu[name].append(time.process_time() - c)
        e, st = min(times["engine"]), min(times["study"])
        ec, sc = min(cpu["engine"]), min(cpu["study"])
        probes = sorted(held_share(local) for _ in range(repeat))
        share, probed = probes[len(probes) // 2]
        low, high = probes[0][0], probes[-1][0]
        control = sorted(held_share(engine)[0] for _ in range(repeat))
        print(f"study: {designs:,} designs × {POSES} poses of the four-bar, 3 metrics, "
              f"best of {repeat}")  # fmt: skip
        print(f"  engine, one design : {e:7.3f} s  {n / e / 1e6:6.2f} M samples/s")
        print(f"  study              : {st:7.3f} s  {n / st / 1e6:6.2f} M samples/s  "
              f"{designs / st:10,.0f} designs/s")  # fmt: skip
        print(f"  ratio              : {e / st:7.2f}  (engine time / study time; target ≥ 0.5)")
        print(f"  CPU time           : engine {ec:.3f} s, study {sc:.3f} s, ratio {ec / sc:.2f} "
              "(every thread's; other load on the cores weighs on it less)")  # fmt: skip
        print(f"  GIL held           : {share:7.1%}  of the study's wall time (sampled, median "
              f"of {repeat}: {low:.1%}–{high:.1%}; {probed:.3f} s with the probe; "
              "target < 10 %)")  # fmt: skip
        print(f"  probe's control    : {control[len(control) // 2]:7.1%}  over the engine's "
              f"solve (median of {repeat}: {control[0]:.1%}–{control[-1]:.1%})")  # fmt: skip
        print(f"  10⁶ designs        : {st * 1e6 / designs / 60:7.1f} min projected")
        if dask:
            t = time.perf_counter()
            run_study(s, out / "dask.parquet", scheduler="dask")
            remote = time.perf_counter() - t
            print(f"  Dask, local cluster: {remote:7.1f} s, efficiency {st / remote:.2f} "
                  "(local time / Dask time, same cores)")  # fmt: skip


def on_device(designs: int = 10**9, poses: int = POSES, call: int = 10**6, repeat: int = 1) -> None:
    """The study on the device (``backend="cuda"``), DESIGNS designs in calls of ``call``,
    against the CPU engine's samples/s (see the module's text)."""
    from excavkin.execution import Execution, use
    from excavkin.studies.fused import evaluate_fused

    s = study(1)
    mech = excavkin.load(s.model)
    pose_set = Poses({"crank": np.linspace(0.0, 2 * np.pi, poses)}, {"crank": 31.4}, {})
    k = min(call, designs)
    rng = np.random.default_rng(0)
    drawn = {name: rng.uniform(lo, hi, k) for name, (lo, hi) in s.bounds.items()}
    n = designs * poses
    m = min(n, 2 * 10**6)
    crank = np.resize(np.linspace(0.0, 2 * np.pi, poses), m)

    def engine() -> None:
        mech.solve({"crank": crank}, {"crank": 31.4}, backend="numba")

    def gpu() -> None:
        with use(Execution(backend="cuda")):
            for start in range(0, designs, k):
                part = {name: v[: min(k, designs - start)] for name, v in drawn.items()}
                evaluate_fused(mech, part, pose_set, s.metrics)

    with use(Execution(backend="cuda")):
        got = evaluate_fused(mech, drawn, pose_set, s.metrics)  # (the kernels compiled)
    with use(Execution(backend="numba")):
        want = evaluate_fused(mech, drawn, pose_set, s.metrics)
    engine()
    gaps = []
    for metric in s.metrics:
        a, b = got[metric.name].to_numpy(), want[metric.name].to_numpy()
        scale = max(float(np.nanmax(np.abs(b), initial=0.0)), 1e-300)
        same = np.array_equal(np.isnan(a), np.isnan(b))
        gaps.append(float(np.nanmax(np.abs(a - b), initial=0.0)) / scale if same else np.inf)
    times: dict[str, list[float]] = {"engine": [], "device": []}
    for _ in range(repeat):
        for name, run in (("engine", engine), ("device", gpu)):
            t = time.perf_counter()
            run()
            times[name].append(time.perf_counter() - t)
    e, g = min(times["engine"]), min(times["device"])
    print(f"study on the device: {designs:,} designs × {poses} poses of the four-bar, "
          f"{len(s.metrics)} metrics, calls of {k:,} designs, best of {repeat}")  # fmt: skip
    print(f"  CPU engine, one design: {e:9.3f} s  {m / e / 1e6:9.2f} M samples/s ({m:,} samples)")
    print(f"  device study          : {g:9.3f} s  {n / g / 1e6:9.2f} M samples/s  "
          f"{designs / g:14,.0f} designs/s")  # fmt: skip
    print(f"  ratio                 : {(n / g) / (m / e):9.2f}  (device samples/s / engine's)")
    print(f"  10⁹ designs           : {g * 1e9 / designs / 60:9.1f} min projected")
    print(f"  against the CPU study : largest difference {max(gaps):.2e} of a metric's scale, "
          f"rows equal to the bit: {got.equals(want)}")  # fmt: skip


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    reps = next((int(a.split("=")[1]) for a in sys.argv[1:] if a.startswith("--repeat=")), 0)
    if "--device" in sys.argv:
        P = next((int(a.split("=")[1]) for a in sys.argv[1:] if a.startswith("--poses=")), POSES)
        K = next((int(a.split("=")[1]) for a in sys.argv[1:] if a.startswith("--call=")), 10**6)
        on_device(int(float(args[0])) if args else 10**9, P, K, reps or 1)
    else:
        main(int(args[0]) if args else 20_000, "--dask" in sys.argv, reps or 3)
