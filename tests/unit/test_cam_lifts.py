"""A cam's lift table as design parameters (issue 26): ``CAM.lift.K`` is the lift of row K
(row 0 also sets the last, a turn on). The spline's coefficients are linear in the lifts, so a
family of designs solves each design's own law, NumPy and compiled alike, and the motion's and
the forces' derivatives by each lift are exact: against 8th-order differences, and a family
against each design built as its own model."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import excavkin

DATA = Path(__file__).parents[1] / "reference" / "data"
CASES = {
    "translating roller": ("disc_cam.toml", ""),
    "translating flat": ("disc_cam.toml", 'face = "flat"'),
    "oscillating roller": ("cam_rocker.toml", ""),
}


def text(case: str) -> str:
    file, face = CASES[case]
    out = (DATA / file).read_text()
    return out.replace('face = "roller"', face) if face else out


def load(case: str) -> excavkin.Mechanism:
    return excavkin.loads(text(case), CASES[case][0])


def test_each_row_but_the_last_is_a_parameter() -> None:
    mech = load("translating roller")
    lifts = {k: v for k, v in mech.parameters.items() if ".lift." in k}
    assert list(lifts) == [f"lift.lift.{k}" for k in range(12)]
    assert lifts["lift.lift.5"] == pytest.approx(0.020, rel=1e-15)
    rocker = load("oscillating roller")
    assert rocker.parameters["swing.lift.4"] == pytest.approx(np.radians(15.0), rel=1e-15)
    from excavkin.structure.design import parameter_kind

    assert parameter_kind("swing.lift.4", rocker.model) == "angle"
    assert parameter_kind("lift.lift.4", mech.model) == "length"


@pytest.mark.parametrize("case", sorted(CASES))
def test_lift_sensitivities_equal_8th_order_differences(case: str) -> None:
    sys.path.insert(0, str(Path(__file__).parents[1] / "property"))
    from test_sensitivities import differences

    mech = load(case)
    prefix = "swing" if "oscillating" in case else "lift"
    names = [f"{prefix}.lift.{k}" for k in (0, 1, 3)]
    values = {"shaft": mech.sketch_values()["shaft"] + np.array([0.3, 1.9, 4.0, -2.5])}
    rates = {"shaft": 0.07}
    res = mech.solve(values, rates=rates, sensitivities=names, loads="model")
    table = res.to_frame()
    ends = (".Fx", ".Fy", ".torque", ".contact", ".guide")
    forces = [c for c in table.columns if c.endswith(ends)]
    force_scale = max(np.abs(table[c].to_numpy()).max() for c in forces)
    moved = 0
    for name in names:
        step = 1e-3 if prefix == "swing" else 1e-4
        for col, ref in differences(mech, values, rates, {}, name, step).items():
            exact = res.sensitivity(col, name)
            own = force_scale if col in forces or col.endswith((".Rx", ".Ry", ".couple")) else 0
            scale = max(np.abs(ref).max(), 1e-3 * max(np.abs(table[col]).max(), own, 1e-3))
            assert np.abs(exact - ref).max() / scale < 1e-8, (name, col)
            moved += col.endswith(".contact") and np.abs(ref).max() > 1e-3
    assert moved  # the contact force moves with the lifts, and was checked


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_family_of_lifts_equals_each_design_as_its_own_model(case: str) -> None:
    mech = load(case)
    prefix = "swing" if "oscillating" in case else "lift"
    row, name = 3, f"{prefix}.lift.3"
    nominal = mech.parameters[name]
    given = nominal * np.array([0.8, 1.0, 1.3])
    q = mech.sketch_values()["shaft"] + np.array([0.7, 2.2, 5.1])
    kw = {"rates": {"shaft": 3.0}, "accels": {"shaft": -1.5}}
    family = {
        b: mech.solve({"shaft": q}, params={name: given}, backend=b, **kw)
        for b in ("numpy", "numba")
    }
    forces = mech.forces(family["numpy"], loads=mech.model.loads)
    for k, value in enumerate(given):
        rows = list(mech.model.cams[0].lift)
        rows[row] = (rows[row][0], float(value))
        import dataclasses

        cam = dataclasses.replace(mech.model.cams[0], lift=tuple(rows))
        alone = excavkin.Mechanism(dataclasses.replace(mech.model, cams=(cam,)))
        own = alone.solve({"shaft": q[k : k + 1]}, **kw)
        own_forces = alone.forces(own, loads=alone.model.loads)
        for b, res in family.items():
            for field in ("positions", "velocities", "accelerations"):
                want = getattr(own, field)[0]
                assert_allclose(getattr(res, field)[k], want, rtol=0, atol=1e-12, err_msg=b)
        assert_allclose(forces.cam_force[k], own_forces.cam_force[0], rtol=1e-11, atol=1e-10)


def test_compiled_lift_tangents_equal_numpy_ones() -> None:
    mech = load("translating roller")
    names = [f"lift.lift.{k}" for k in range(12)]
    q = {"shaft": mech.sketch_values()["shaft"] + np.linspace(-9.0, 9.0, 300)}
    kw = {"rates": {"shaft": 3.0}, "accels": {"shaft": -2.0}, "sensitivities": names}
    a = mech.solve(q, backend="numpy", **kw)
    b = mech.solve(q, backend="numba", **kw)
    for name in names:
        for field in ("positions", "velocities", "accelerations"):
            x, y = getattr(b.tangents[name], field), getattr(a.tangents[name], field)
            assert np.abs(y).max() > 0
            assert np.abs(x - y).max() <= 1e-12 * np.abs(y).max(), (name, field)


def test_a_lift_is_written_back_and_row_0_closes_the_table(tmp_path: Path) -> None:
    from excavkin.io.model_write import model_text_with
    from excavkin.io.toml_model import loads_model

    for case, values in (
        ("translating roller", {"lift.lift.0": 0.001, "lift.lift.5": 0.021}),
        ("oscillating roller", {"swing.lift.0": np.radians(1.0), "swing.lift.4": np.radians(16)}),
    ):
        path = tmp_path / "cam.toml"
        path.write_text(text(case))
        model = loads_model(model_text_with(path, values), "cam.toml")
        lifts = [s for _, s in model.cams[0].lift]
        first, other = values.items()
        assert lifts[0] == pytest.approx(first[1], rel=1e-12)
        assert lifts[-1] == pytest.approx(first[1], rel=1e-12)
        assert lifts[int(other[0].rsplit(".", 1)[1])] == pytest.approx(other[1], rel=1e-12)
