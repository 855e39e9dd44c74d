"""A study solved and reduced on the device (``backend="cuda"``, `excavkin.studies.device`)
against the CPU's compiled study (``backend="numba"``), in numba's CUDA simulator: the same
table, to the bit, for every reduction a study file can name — with failing poses, a
design that builds no mechanism, samples near a dead position (solved again and checked on
the host, patched into the device's state), pose sets with a held driver, inputs refused
sample by sample, and a set taken in several chunks of designs; a clearance metric (not
one row of the state) keeps the blocks' solve.

The simulator must be chosen before numba is imported (``NUMBA_ENABLE_CUDASIM=1``), so each
check runs in a fresh interpreter, with a cache folder of its own."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

import excavkin
from excavkin.kinematics.solve import BLOCK
from excavkin.studies import device
from excavkin.studies.metrics import Metric, clearance_metric

ROOT = Path(__file__).resolve().parents[2]

SCRIPT = r"""
import json, sys
import numpy as np
import pandas as pd
import excavkin
from excavkin.execution import Execution, use
from excavkin.kinematics import precision
from excavkin.studies import device, fused
from excavkin.studies.design_space import sample_designs
from excavkin.studies.fused import evaluate_fused
from excavkin.studies.metrics import REDUCTIONS, Constraint, Metric, Poses

calls = {"scan": [], "reduce": 0, "cpu_study": 0}
scan, reduce_ = device.DeviceState.scan, device.DeviceState.reduce
solve_compiled = fused._solve_set_compiled

def spy_scan(self, near_at):
    got = scan(self, near_at)
    calls["scan"].append(int(got[0].size))
    return got

def spy_reduce(self, *args):
    calls["reduce"] += 1
    return reduce_(self, *args)

def spy_compiled(*args):
    calls["cpu_study"] += 1
    return solve_compiled(*args)

device.DeviceState.scan = spy_scan
device.DeviceState.reduce = spy_reduce
fused._solve_set_compiled = spy_compiled

def both(mech, designs, poses, metrics, constraints=(), pose_sets=None):
    with use(Execution(backend="numba")):
        ref = evaluate_fused(mech, designs, poses, metrics, constraints, pose_sets)
    on_cpu = calls["cpu_study"]
    with use(Execution(backend="cuda")):
        got = evaluate_fused(mech, designs, poses, metrics, constraints, pose_sets)
    assert calls["cpu_study"] == on_cpu  # the device's own path, not the CPU's study
    pd.testing.assert_frame_equal(got, ref, check_exact=True)
    return ref

case = sys.argv[1]
report = {}
if case == "fourbar":
    mech = excavkin.load(excavkin.example_path("fourbar"))
    bounds = {"A-B": (-0.01, 0.16), "O4-B": (0.05, 0.12), "O4.x": (0.08, 0.13)}
    designs = sample_designs(bounds, 10, "sobol", 1)
    # a design that builds no mechanism (a coupler of no length), and poses just inside a
    # partly failing design's dead position: found by bisection on the CPU
    designs["A-B"][0] = 0.0
    grid = np.linspace(0.0, 2 * np.pi, 400)
    every = mech.solve(
        {"crank": np.tile(grid, 10)}, params={k: np.repeat(v, 400) for k, v in designs.items()},
        backend="numpy",
    ).status.ok.reshape(10, 400)
    which = next(i for i in range(10) if 0 < every[i].sum() < 400)  # its crank cannot turn
    one = {k: np.repeat(v[which : which + 1], 2) for k, v in designs.items()}

    def closes(theta):
        r = mech.solve({"crank": np.array([theta, theta])}, params=one, backend="numpy")
        return bool(r.status.ok[0])

    ok = every[which]
    edge = next(i for i in range(len(grid) - 1) if ok[i] and not ok[i + 1])
    lo, hi = grid[edge], grid[edge + 1]
    for _ in range(45):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if closes(mid) else (lo, mid)
    near = lo - np.array([1e-9, 1e-7, 1e-5, 1e-3])
    p_base = 14
    crank = np.concatenate([np.linspace(0.0, 2 * np.pi, p_base), near])
    p = crank.size
    poses = Poses({"crank": crank}, {"crank": 12.0}, {"crank": 3.0})
    target = tuple(np.linspace(0.9, 1.1, p))
    metrics = [Metric(f"g_{h}", "B.transmission", h) for h in REDUCTIONS if h != "sumsq"]
    metrics += [
        Metric("swing", "rocker.angle", "change"), Metric("dx", "B.x", "change"),
        Metric("fit", "B.transmission", "sumsq", target),
        Metric("off", "rocker.omega", "absmax", (0.5,)), Metric("vy", "B.vy", "mean"),
        Metric("first_ay", "B.ay", "first"), Metric("rate", "crank.rate", "mean"),
        Metric("low_coupler", "coupler.angle", "argmin"),
    ]
    constraints = [Constraint("g_min", low=0.4), Constraint("swing", high=2.0)]
    ref = both(mech, designs, poses, metrics, constraints)
    report["failed"] = ref["poses_failed"].tolist()
    report["status"] = ref["status"].tolist()
elif case == "pose sets":
    mech = excavkin.load(excavkin.example_path("wheel_loader"))
    sketch, par = mech.sketch_values(), mech.parameters
    bounds = {"G.x": (par["G.x"] - 0.05, par["G.x"] + 0.05), "G.y": (par["G.y"] - 0.1, par["G.y"])}
    designs = sample_designs(bounds, 5, "halton", 2)
    # a driven length of zero and one not a number: refused sample by sample, on the device
    lift = np.append(sketch["lift_cyl"] + np.linspace(-0.5, 1.0, 7), [0.0, np.nan])
    poses = Poses({"lift_cyl": lift}, {}, {})
    tilt = Poses(
        {"tilt_cyl": sketch["tilt_cyl"] + np.linspace(-0.2, 0.2, 5),
         "lift_cyl": sketch["lift_cyl"]}, {"tilt_cyl": 0.05}, {},
    )
    metrics = [
        Metric("reach", "W.x", "max"), Metric("tilt_at_top", "bucket.angle", "last"),
        Metric("bucket_swing", "bucket.angle", "change", poses="tilt"),
        Metric("w_rate", "W.vy", "absmax", poses="tilt"),
    ]
    ref = both(mech, designs, poses, metrics, pose_sets={"tilt": tilt})
    report["failed"] = ref["poses_failed"].tolist()
    report["status"] = ref["status"].tolist()
elif case == "run_study":  # a study file's run: its chunks on two threads, each on the device
    import dataclasses, tempfile
    from excavkin.studies.study import Study, run_study
    s = Study(
        model=excavkin.example_path("fourbar"),
        bounds={"A-B": (-0.01, 0.16), "O4-B": (0.07, 0.11)},
        poses=Poses({"crank": np.linspace(0.0, 2 * np.pi, 6)}, {"crank": 3.0}, {}),
        metrics=(Metric("g", "B.transmission", "min"), Metric("w", "rocker.omega", "absmax")),
        samples=12,
    )
    with tempfile.TemporaryDirectory() as tmp:
        tables = {}
        for backend in ("numba", "cuda"):
            out = run_study(s, f"{tmp}/{backend}.parquet", execution=Execution(workers=2),
                            backend=backend, chunk_samples=24)  # four designs a chunk
            tables[backend] = pd.read_parquet(out)
    pd.testing.assert_frame_equal(tables["cuda"], tables["numba"], check_exact=True)
    report["failed"] = tables["cuda"]["poses_failed"].tolist()
    report["status"] = tables["cuda"]["status"].tolist()
elif case == "clearance":  # not one row: the blocks solved as a solve does, on the device
    from excavkin.studies.metrics import clearance_metric
    mech = excavkin.load(excavkin.example_path("fourbar"))
    designs = sample_designs({"A-B": (0.09, 0.14), "O4-B": (0.07, 0.11)}, 4, "halton", 3)
    poses = Poses({"crank": np.linspace(0.0, 2 * np.pi, 5)}, {"crank": 3.0}, {})
    metrics = [Metric("g", "B.transmission", "min"),
               clearance_metric("gap", ("A", "B"), ("O2", "O4"))]
    ref = both(mech, designs, poses, metrics)
    report["failed"] = ref["poses_failed"].tolist()
    report["status"] = ref["status"].tolist()
else:  # several chunks of designs: blocks of 128 samples, a budget of one block a chunk
    device.BLOCK = 128
    device.CHUNK_BYTES = 1
    mech = excavkin.load(excavkin.example_path("fourbar"))
    designs = sample_designs({"A-B": (0.09, 0.14), "O4-B": (0.07, 0.11)}, 18, "halton", 3)
    poses = Poses({"crank": np.linspace(0.0, 2 * np.pi, 8)}, {"crank": 3.0}, {})
    metrics = [Metric("g", "B.transmission", h) for h in ("min", "mean", "argmax")]
    ref = both(mech, designs, poses, [Metric(m.reduce, m.column, m.reduce) for m in metrics])
    report["failed"] = ref["poses_failed"].tolist()
    report["status"] = ref["status"].tolist()
    # no designs, a set of no poses, one design at one pose
    edges = [Metric("g", "B.transmission", "min"), Metric("s", "rocker.angle", "change"),
             Metric("m", "B.x", "mean")]
    for d, p in ((0, 3), (2, 0), (1, 1)):
        crank = Poses({"crank": np.linspace(0.0, 1.0, p)}, {}, {})
        both(mech, {"A-B": np.full(d, 0.12)}, crank, edges)
report["scan"] = calls["scan"]
report["reduce"] = calls["reduce"]
print(json.dumps(report))
"""


def simulate(tmp_path: Path, case: str) -> dict[str, list[object]]:
    env = {
        **os.environ,
        "NUMBA_ENABLE_CUDASIM": "1",
        "EXCAVKIN_CACHE_DIR": str(tmp_path / "kernels"),
        "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]),
    }
    r = subprocess.run(
        [sys.executable, "-c", SCRIPT, case], env=env, capture_output=True, text=True,
        timeout=900,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr[-3000:]
    return json.loads(r.stdout.strip().splitlines()[-1])  # type: ignore[no-any-return]


def test_a_study_on_the_simulated_gpu_is_the_cpus_to_the_bit(tmp_path: Path) -> None:
    report = simulate(tmp_path, "fourbar")
    failed = report["failed"]
    assert failed[0] == 18  # the design that builds no mechanism: every pose
    assert any(0 < f < 18 for f in failed)  # a design whose crank cannot turn
    assert any(f == 0 for f in failed)
    assert report["scan"] == [sum(report["scan"])] and report["scan"][0] >= 2  # near a dead one
    assert report["reduce"] == 17  # every metric reduced on the device


def test_pose_sets_and_a_held_driver_on_the_simulated_gpu(tmp_path: Path) -> None:
    report = simulate(tmp_path, "pose sets")
    assert len(report["scan"]) == 2  # one chunk a set
    assert all(f >= 2 for f in report["failed"])  # the length of zero, and the NaN
    assert any(f > 2 for f in report["failed"])  # and poses that do not close


def test_a_set_in_several_chunks_on_the_simulated_gpu(tmp_path: Path) -> None:
    report = simulate(tmp_path, "chunks")
    # 18 designs of 8 poses, 16 designs (128 samples) a chunk; then one design at one pose
    assert len(report["scan"]) == 2 + 1
    assert report["reduce"] == 3 * 2 + 3


def test_a_study_run_on_threads_on_the_simulated_gpu(tmp_path: Path) -> None:
    report = simulate(tmp_path, "run_study")
    assert len(report["scan"]) >= 3 and report["reduce"] == 2 * len(report["scan"])
    assert len(report["failed"]) == 12 and any(f == 6 for f in report["failed"])


def test_a_clearance_keeps_the_blocks_solve_on_the_simulated_gpu(tmp_path: Path) -> None:
    report = simulate(tmp_path, "clearance")
    assert report["scan"] == [] and report["reduce"] == 0  # not the device's study
    assert len(report["failed"]) == 4


def test_a_chunk_is_whole_designs_on_whole_blocks() -> None:
    for p in (1, 7, 61, 100, 128, 4096, BLOCK, 3 * BLOCK):
        unit = BLOCK // math.gcd(p, BLOCK)
        for d in (1, max(1, unit - 1), unit, 5 * unit + 3, 10**9):
            per = device.designs_per_chunk(d, p, 300)
            assert 1 <= per <= d
            assert per == d or (per * p) % BLOCK == 0  # every chunk starts on a block
            assert per == d or per * p * 300 <= max(device.CHUNK_BYTES, unit * p * 300)
    assert device.designs_per_chunk(10**9, 100, 300) == 4 * 16384  # 2 GiB of 300 B samples


def test_the_layout_finds_each_columns_row() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    lay = device.layout(mech.plan)
    n = len(mech.plan.points)
    assert lay.rows == 3 * 2 * n + len(mech.plan.transmissions) + 3 * len(mech.plan.bodies)
    # B is the third point: its x is row 4 of the positions, its vy row 5 of the velocities
    assert lay.row_of(Metric("b", "B.x", "max")) == (0, 4)
    assert lay.row_of(Metric("b", "B.vy", "max")) == (0, 2 * n + 5)
    assert lay.row_of(Metric("r", "crank.rate", "mean")) == (1, 1)  # the inputs' rates
    assert lay.row_of(clearance_metric("gap", ("A", "B"), ("O2", "O4"))) is None
    assert "rocker.angle" in lay.angles and "B.x" not in lay.angles
    kinds = lay.kinds.tolist()
    assert kinds[: 2 * n] == [0] * (2 * n) and kinds[2 * n : 4 * n] == [1] * (2 * n)


@pytest.mark.parametrize("name", ["fourbar", "slider_crank", "excavator"])
def test_the_device_source_reads_a_column_a_design(name: str) -> None:
    from excavkin.gpu import device_source
    from excavkin.kinematics import compiled

    plan = excavkin.load(excavkin.example_path(name)).plan
    text = device_source(compiled.source(plan, write_at_rest=False), by_design=True)
    assert "j = i // ks" in text and "j = i * ks" not in text
    with pytest.raises(ValueError, match="one column index"):
        device_source(text.replace("j = i // ks", "j = 0"), by_design=True)


def test_the_device_benchmark_runs_on_the_simulated_gpu(tmp_path: Path) -> None:
    """`benchmarks/bench_study.py --device` with a tiny study (a smoke test: its figures mean
    nothing in the simulator): samples/s of both, their ratio, the table the CPU's."""
    env = {
        **os.environ,
        "NUMBA_ENABLE_CUDASIM": "1",
        "EXCAVKIN_CACHE_DIR": str(tmp_path / "kernels"),
        "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]),
    }
    script = ROOT / "benchmarks" / "bench_study.py"
    args = ["--device", "5", "--poses=4", "--call=2", "--repeat=1"]
    r = subprocess.run(
        [sys.executable, str(script), *args], env=env, capture_output=True, text=True,
        timeout=600,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr[-3000:]
    out = r.stdout
    assert "5 designs × 4 poses" in out and "calls of 2 designs" in out
    assert out.count("M samples/s") == 2 and "device samples/s / engine's" in out
    assert "rows equal to the bit: True" in out
