"""Gear pairs, trains, racks and cams solved along the solve plan against the dense solve.

* the four reference models (a planetary train, a rack on a swinging arm, a disc cam with a
  translating follower, a cam with an oscillating follower), at random inputs, rates and
  accelerations, with a torque on the last body and gravity: every force column — pins,
  drivers, tooth, contact and guide forces — equal to the dense per-sample LAPACK solve's to
  1e-10 of its scale, and no sample singular;
* each of them is taken along the plan (its mesh steps' blocks are square), and a model the
  plan could not take (forced here) is solved densely with the same forces;
* the compiled back-substitution gives the NumPy path's forces for the gear train and the rack
  (a cam's lift law is not traced: it runs in NumPy).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import excavkin
from excavkin.kinematics.result import KinematicResult
from excavkin.kinetostatics import ForceResult, Gravity, Torque, solve_forces
from excavkin.kinetostatics import solve as solve_module
from excavkin.kinetostatics.structured import along_plan

DATA = Path(__file__).parents[1] / "reference" / "data"
MODELS = ["planetary_21_43_108", "rack_on_arm", "disc_cam", "cam_rocker"]


def motion(name: str, n: int = 400) -> tuple[excavkin.Mechanism, KinematicResult]:
    """The model at n random inputs, rates and accelerations."""
    mech = excavkin.load(DATA / f"{name}.toml")
    rng = np.random.default_rng(7)
    drivers = [d.name for d in mech.model.rotary]
    q = {d: rng.uniform(-3.0, 3.0, n) for d in drivers}
    rates = {d: rng.normal(size=n) for d in drivers}
    accels = {d: rng.normal(size=n) for d in drivers}
    return mech, mech.solve(q, rates=rates, accels=accels)


def loads(mech: excavkin.Mechanism) -> list[Torque | Gravity]:
    last = [b.name for b in mech.model.bodies if not b.ground][-1]
    return [Torque("load", last, 0.7), Gravity()]


def frame(res: ForceResult) -> dict[str, np.ndarray]:
    """Every numeric force column."""
    df = res.to_frame()
    return {c: np.asarray(df[c], dtype=float) for c in df.columns if df[c].dtype.kind == "f"}


def assert_same(a: ForceResult, b: ForceResult, rtol: float = 1e-10) -> None:
    fa, fb = frame(a), frame(b)
    assert fa.keys() == fb.keys()
    scale = max(float(np.nanmax(np.abs(v))) for v in fb.values())
    for c in fa:
        assert np.isfinite(fa[c]).all(), c
        np.testing.assert_allclose(fa[c], fb[c], rtol=0.0, atol=rtol * scale, err_msg=c)
    np.testing.assert_array_equal(a.singular, b.singular)


@pytest.mark.parametrize("name", MODELS)
def test_along_the_plan_equals_the_dense_solve(name: str) -> None:
    mech, res = motion(name)
    assert along_plan(res.plan, mech.statics) is not None
    sparse = solve_forces(res, loads(mech), system=mech.statics, backend="numpy")
    dense = solve_forces(res, loads(mech), system=mech.statics, method="dense")
    assert not dense.singular.any()
    assert_same(sparse, dense)
    # the meshes carry load: a wrong tooth force would show
    meshes = np.concatenate(
        [sparse.gear_force.ravel(), sparse.rack_force.ravel(), sparse.cam_force.ravel()]
    )
    assert np.abs(meshes).max() > 1e-3


@pytest.mark.parametrize("name", MODELS)
def test_a_model_the_plan_cannot_take_is_solved_densely(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    mech, res = motion(name, 100)
    along = solve_forces(res, loads(mech), system=mech.statics, backend="numpy")
    monkeypatch.setattr(solve_module, "along_plan", lambda plan, sy: None)
    dense = solve_forces(res, loads(mech), system=mech.statics, chunk=37)
    assert_same(dense, along)


@pytest.mark.parametrize("name", ["planetary_21_43_108", "rack_on_arm"])
def test_compiled_equals_numpy(name: str) -> None:
    mech, res = motion(name, 300)
    numpy_path = solve_forces(res, loads(mech), system=mech.statics, backend="numpy")
    kernel = solve_forces(res, loads(mech), system=mech.statics, backend="numba")
    assert_same(kernel, numpy_path, rtol=1e-14)
