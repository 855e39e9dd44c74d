"""The CUDA backend (excavkin.gpu) against NumPy, in numba's CUDA simulator: the same generated
sources, one thread a sample, give the kinematics, the tangents and the forces of the examples
— failing samples and families of designs included — as the NumPy path does.

The simulator must be chosen before numba is imported (``NUMBA_ENABLE_CUDASIM=1``), so each
check runs in a fresh interpreter, with a cache folder of its own."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

SCRIPT = r"""
import json, sys
import numpy as np
import excavkin
from excavkin import backends

def sweep(mech, n, wide):
    out = {}
    for k, v in mech.sketch_values().items():
        span = (0.3 if mech.input_kind(k) == "angle" else 0.03 * v) * (8.0 if wide else 1.0)
        out[k] = v + span * np.sin(np.linspace(0.0, 6.0, n) + len(k))
    return out

def gap(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if not np.array_equal(np.isnan(a), np.isnan(b)):
        return float("inf")
    scale = np.maximum(np.nanmax(np.abs(b), axis=0, initial=0.0), 1e-300)
    return float(np.max(np.nan_to_num(np.abs(a - b)) / scale, initial=0.0))

report = {"available": backends.available()["cuda"], "cases": {}}
for name in sys.argv[1:]:
    mech = excavkin.load(excavkin.example_path(name))
    for wide in (False, True):
        values = sweep(mech, 48, wide)
        rates = {k: 0.4 for k in values}
        names = [p for p in mech.parameters if not p.endswith((".mass", ".inertia"))][:2]
        loads = list(mech.loads) or [excavkin.Gravity()]
        got = {
            b: mech.solve(values, rates, sensitivities=names, loads=loads, backend=b)
            for b in ("numpy", "cuda")
        }
        gpu, ref = got["cuda"], got["numpy"]
        k, r = gpu.kinematics, ref.kinematics
        case = {
            "status": bool(np.array_equal(k.status.code, r.status.code)),
            "failed": int((~r.status.ok).sum()),
            "kinematics": max(gap(getattr(k, f), getattr(r, f)) for f in (
                "positions", "velocities", "accelerations", "body_angle", "body_omega",
                "body_epsilon", "transmission")),
            "tangents": max(gap(k.tangents[p].positions, r.tangents[p].positions)
                            for p in names),
            "forces": max(gap(getattr(gpu, f), getattr(ref, f))
                          for f in ("pin_force", "element_force", "driver_torque")),
        }
        report["cases"][f"{name}{' wide' if wide else ''}"] = case
# a family of designs (one column of constants per sample), some of which do not close
fb = excavkin.load(excavkin.example_path("fourbar"))
q = {"crank": np.linspace(0.0, 6.0, 40)}
params = {"A-B": np.linspace(0.5, 4.0, 40) * fb.parameters["A-B"]}
a = fb.solve(q, params=params, backend="cuda", chunk=16)  # three passes, the last short
b = fb.solve(q, params=params, backend="numpy")
report["cases"]["fourbar designs"] = {
    "status": bool(np.array_equal(a.status.code, b.status.code)),
    "failed": int((~b.status.ok).sum()),
    "kinematics": max(gap(a.positions, b.positions), gap(a.accelerations, b.accelerations)),
    "tangents": 0.0, "forces": 0.0,
}
print(json.dumps(report))
"""


def simulate(tmp_path: Path, *names: str) -> dict[str, object]:
    env = {
        **os.environ,
        "NUMBA_ENABLE_CUDASIM": "1",
        "EXCAVKIN_CACHE_DIR": str(tmp_path / "kernels"),
        "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]),
    }
    r = subprocess.run(
        [sys.executable, "-c", SCRIPT, *names], env=env, capture_output=True, text=True,
        timeout=900,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr[-3000:]
    return json.loads(r.stdout.strip().splitlines()[-1])  # type: ignore[no-any-return]


@pytest.mark.parametrize("names", [("fourbar", "slider_crank"), ("excavator",)])
def test_the_simulated_gpu_agrees_with_numpy(tmp_path: Path, names: tuple[str, ...]) -> None:
    report = simulate(tmp_path, *names)
    assert report["available"] is None  # the simulator stands in for a GPU
    cases = report["cases"]
    assert isinstance(cases, dict)
    assert any(c["failed"] for c in cases.values())  # a sweep wide enough to fail somewhere
    for label, case in cases.items():
        assert case["status"], label
        for part in ("kinematics", "tangents", "forces"):
            assert case[part] <= 1e-12, (label, part, case[part])


def test_the_cli_runs_on_the_simulated_gpu(tmp_path: Path) -> None:
    env = {
        **os.environ,
        "NUMBA_ENABLE_CUDASIM": "1",
        "EXCAVKIN_CACHE_DIR": str(tmp_path / "kernels"),
        "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]),
    }
    out = tmp_path / "o.csv"
    args = ["solve", "fourbar", "--sweep", "crank=0:6:50", "-o", str(out), "--backend"]
    for backend in ("cuda", "numpy"):
        r = subprocess.run(
            [sys.executable, "-m", "excavkin", *args, backend, "--forces", "--force"],
            env=env, capture_output=True, text=True, timeout=600,
        )  # fmt: skip
        assert r.returncode == 0, r.stderr
        if backend == "cuda":
            cuda_table = out.read_text()
    numpy_table = out.read_text()
    import io

    import numpy as np
    import pandas as pd

    a, b = (pd.read_csv(io.StringIO(t)) for t in (cuda_table, numpy_table))
    assert list(a.columns) == list(b.columns)
    assert (a["status"] == b["status"]).all()
    x, y = (t.select_dtypes("number").to_numpy() for t in (a, b))
    scale = np.maximum(np.nanmax(np.abs(y), axis=0), 1e-300)
    assert np.nanmax(np.abs(x - y) / scale) <= 1e-12
