"""Cams through the compiled plan (issue 26): a table's lift law is constants of the plan and
the generated source evaluates its spline piece by piece, so ``backend="numba"`` (and the CUDA
target, here in numba's simulator) solves translating and oscillating, roller and flat-faced
followers as NumPy does — positions, velocities, accelerations, their design tangents and the
forces (the law traced into the compiled equilibrium) —
while a law given as a function stays in NumPy, with the reason given."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin.kinematics import compiled

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "reference" / "data"
CASES = {
    "translating roller": ("disc_cam.toml", ""),
    "translating flat": ("disc_cam.toml", 'face = "flat"'),
    "oscillating roller": ("cam_rocker.toml", ""),
}
FIELDS = ("positions", "velocities", "accelerations", "body_angle", "body_omega", "body_epsilon")


def load(case: str) -> excavkin.Mechanism:
    file, face = CASES[case]
    text = (DATA / file).read_text()
    if face:
        text = text.replace('face = "roller"', face)
    return excavkin.loads(text, file)


def gap(a: np.ndarray, b: np.ndarray) -> float:
    """The largest difference over each column's largest magnitude."""
    scale = np.maximum(np.abs(b).max(axis=0), 1e-300)
    return float((np.abs(a - b) / scale).max())


def sweep(mech: excavkin.Mechanism, n: int, seed: int) -> tuple[dict, dict, dict]:
    rng = np.random.default_rng(seed)
    ((name, q0),) = mech.sketch_values().items()
    # many turns both ways, and the knots themselves (a piece's end is the next one's start)
    turns = np.concatenate([rng.uniform(-40.0, 40.0, n), np.radians(np.arange(-720, 721, 15))])
    m = turns.size
    return (
        {name: q0 + turns},
        {name: rng.uniform(-30.0, 30.0, m)},
        {name: rng.uniform(-60.0, 60.0, m)},
    )


@pytest.mark.parametrize("case", sorted(CASES))
def test_numba_solves_a_cam_as_numpy_does(case: str) -> None:
    mech = load(case)
    assert compiled.supports(mech.plan)
    q, qd, qdd = sweep(mech, 3000, 5)
    ref = mech.solve(q, rates=qd, accels=qdd, backend="numpy")
    got = mech.solve(q, rates=qd, accels=qdd, backend="numba")
    assert ref.status.all_ok and np.array_equal(got.status.code, ref.status.code)
    assert compiled.is_compiled(mech.plan)
    for field in FIELDS:
        assert gap(getattr(got, field), getattr(ref, field)) <= 1e-12, field


@pytest.mark.parametrize("case", sorted(CASES))
def test_numba_solves_a_cams_forces_as_numpy_does(case: str) -> None:
    """The traced equilibrium with the cam's law (`excavkin.kinetostatics.compiled`): every
    force and torque, the contact force included, and the power balance."""
    mech = load(case)
    q, qd, qdd = sweep(mech, 2000, 8)
    ref = mech.solve(q, rates=qd, accels=qdd, loads="model", backend="numpy")
    got = mech.solve(q, rates=qd, accels=qdd, loads="model", backend="numba")
    for field in ("pin_force", "cam_force", "driver_torque"):
        a, b = getattr(got, field), getattr(ref, field)
        assert np.abs(a - b).max() <= 1e-13 * np.abs(b).max(), field  # (a column may be 0)
    assert np.max(got.power_balance().relative) < 1e-9


@pytest.mark.parametrize("case", sorted(CASES))
def test_numba_solves_a_family_of_cam_designs_as_numpy_does(case: str) -> None:
    """One column of constants per sample: the follower's guide or pivot moved per design."""
    mech = load(case)
    q, qd, qdd = sweep(mech, 500, 6)
    n = next(iter(q.values())).size
    name = "G1.x" if "translating" in case else "P.y"
    params = {name: mech.parameters[name] + np.linspace(-0.004, 0.004, n)}
    ref = mech.solve(q, rates=qd, accels=qdd, params=params, backend="numpy")
    got = mech.solve(q, rates=qd, accels=qdd, params=params, backend="numba")
    assert ref.status.all_ok and np.array_equal(got.status.code, ref.status.code)
    for field in FIELDS:
        assert gap(getattr(got, field), getattr(ref, field)) <= 1e-12, field


@pytest.mark.parametrize("case", sorted(CASES))
def test_compiled_cam_tangents_equal_numpy_ones(case: str) -> None:
    mech = load(case)
    q, qd, _ = sweep(mech, 200, 7)
    names = [f"{p}.{c}" for p in mech.model.points for c in "xy"]
    ref = mech.solve(q, rates=qd, sensitivities=names, backend="numpy")
    got = mech.solve(q, rates=qd, sensitivities=names, backend="numba")
    for name in names:
        for field in ("positions", "velocities", "accelerations"):
            a = getattr(got.tangents[name], field)
            b = getattr(ref.tangents[name], field)
            scale = max(np.abs(b).max(), 1e-300)
            assert np.abs(a - b).max() / scale <= 1e-12, (name, field)
    moved = [n for n in names if np.abs(ref.tangents[n].accelerations).max() > 1e-6]
    assert len(moved) >= 4  # the sketch moves the follower's point's acceleration


def test_a_cam_whose_law_is_a_function_stays_in_numpy_and_says_why() -> None:
    sys.path.insert(0, str(ROOT / "tests" / "unit"))
    from test_cams import _with_law, eccentric

    mech = excavkin.Mechanism(_with_law(eccentric))
    assert not compiled.supports(mech.plan)
    q = {"shaft": mech.sketch_values()["shaft"] + np.linspace(0.0, 9.0, 50)}
    with pytest.raises(excavkin.InputError, match="cam 'lift', whose lift law is a function"):
        mech.solve(q, backend="numba")
    auto = mech.solve(q, rates={"shaft": 2.0}, backend="auto")
    assert_allclose(auto.positions, mech.solve(q, rates={"shaft": 2.0}).positions, atol=0)


SCRIPT = r"""
import json, sys
import numpy as np
import excavkin
from excavkin import backends

def gap(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    scale = np.maximum(np.abs(b).max(axis=0), 1e-300)
    return float((np.abs(a - b) / scale).max())

report = {"available": backends.available()["cuda"], "cases": {}}
for path, face in json.loads(sys.argv[1]):
    text = open(path).read()
    if face:
        text = text.replace('face = "roller"', face)
    mech = excavkin.loads(text, path)
    (name, q0), = mech.sketch_values().items()
    turns = np.linspace(-20.0, 20.0, 96)
    values, rates = {name: q0 + turns}, {name: 3.0 * np.cos(turns)}
    accels = {name: 5.0 * np.sin(turns)}
    names = [f"{p}.{c}" for p in list(mech.model.points)[:2] for c in "xy"]
    got = {b: mech.solve(values, rates, accels, sensitivities=names, loads="model", backend=b)
           for b in ("numpy", "cuda")}
    a, b = got["cuda"], got["numpy"]
    ak, bk = a.kinematics, b.kinematics
    report["cases"][f"{path} {face}"] = {
        "status": bool(np.array_equal(ak.status.code, bk.status.code)),
        "kinematics": max(gap(getattr(ak, f), getattr(bk, f))
                          for f in ("positions", "velocities", "accelerations")),
        "tangents": max(gap(getattr(ak.tangents[p], f), getattr(bk.tangents[p], f))
                        for p in names for f in ("positions", "velocities", "accelerations")),
        "forces": max(float(np.abs(getattr(a, f) - getattr(b, f)).max()
                            / np.abs(getattr(b, f)).max())
                      for f in ("pin_force", "cam_force", "driver_torque")),
    }
print(json.dumps(report))
"""


def test_the_simulated_gpu_solves_cams_as_numpy_does(tmp_path: Path) -> None:
    env = {
        **os.environ,
        "NUMBA_ENABLE_CUDASIM": "1",
        "EXCAVKIN_CACHE_DIR": str(tmp_path / "kernels"),
        "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]),
    }
    cases = [(str(DATA / file), face) for file, face in CASES.values()]
    r = subprocess.run(
        [sys.executable, "-c", SCRIPT, json.dumps(cases)], env=env, capture_output=True,
        text=True, timeout=900,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr[-3000:]
    report = json.loads(r.stdout.strip().splitlines()[-1])
    assert report["available"] is None  # the simulator stands in for a GPU
    assert len(report["cases"]) == len(CASES)
    for label, case in report["cases"].items():
        assert case["status"], label
        assert case["kinematics"] <= 1e-12, (label, case)
        assert case["tangents"] <= 1e-12, (label, case)
        assert case["forces"] <= 1e-12, (label, case)


def long_table(rows: int) -> excavkin.Mechanism:
    """The disc cam with a table of ``rows`` rows (a lift of 10·(1 − cos θ) mm)."""
    import re

    turns = np.linspace(0.0, 360.0, rows)
    lifts = 10.0 * (1.0 - np.cos(np.radians(turns)))
    rows_text = ", ".join(
        f"[{float(a)!r}, {float(b)!r}]" for a, b in zip(turns, lifts, strict=True)
    )
    given = (DATA / "disc_cam.toml").read_text()
    text = re.sub(r"lift = \[\[0, 0\].*?\[360, 0\]\]", f"lift = [{rows_text}]", given, flags=re.S)
    return excavkin.loads(text, "long.toml")


def test_a_long_table_compiles_branch_free_and_only_when_asked() -> None:
    """The piece is picked by arithmetic (weights of 1 and 0), not by a branch per knot: a
    table of hundreds of rows once put thousands of branches in the kernel, past the
    compiler's recursion limit. Its pieces count towards the size the automatic choice
    compiles unasked (`excavkin.kinematics.compiled.size`)."""
    from excavkin import backends
    from excavkin.kinematics.compiled import AUTO_POINTS, job, size, source

    mech = long_table(361)
    text = source(mech.plan)
    law = text[text.index("turns = ") : text.index("lift = ")]
    assert "if " not in law and law.count(">=") == 359
    assert size(mech.plan) == len(mech.plan.points) + 180 > AUTO_POINTS
    assert backends.choose("auto", job(mech.plan), 10**6).name == "numpy"
    assert size(load("translating roller").plan) == 6 + 6
