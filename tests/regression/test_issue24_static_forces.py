"""Issue 24: forces without given rates are static.

A swept driver given no rate moves at rate 1 in the kinematics (transfer functions), but forces
were computed at that unasked speed: the excavator's arm cylinder read +18.97 kN under its
weight where the static force is −14.92 kN. Forces now take such a driver at rest, in Python,
on the command line, in tolerances and studies, and every output says which it is.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

import excavkin
from excavkin import Body, Gravity, LinearDriver, Mechanism, Model, PointForce
from excavkin.cli import main


@pytest.fixture(scope="module")
def excavator() -> Mechanism:
    return excavkin.load("excavator")


def _boom_sweep(mech: Mechanism) -> dict[str, np.ndarray]:
    sketch = mech.sketch_values()
    return {"boom_cyl": sketch["boom_cyl"] * np.linspace(0.95, 1.05, 21)}


def test_excavator_forces_without_rates_equal_forces_at_zero_rates(excavator: Mechanism) -> None:
    values = _boom_sweep(excavator)
    static = excavator.solve(values, loads=[Gravity()])
    at_zero = excavator.solve(values, {"boom_cyl": 0.0}, loads=[Gravity()])
    assert static.static and static.at_rest == ("boom_cyl",)
    assert static.kinematics.status.all_ok
    for name in excavator.inputs:
        np.testing.assert_array_equal(static.force(name), at_zero.force(name))
    np.testing.assert_array_equal(static.pin_force, at_zero.pin_force)
    # the motion in the result is the one the forces belong to: at rest
    assert not np.any(static.kinematics.velocities)
    # the old answer (at 1 m/s of the boom cylinder) differs: it had inertia nobody asked for
    moving = excavator.solve(values, {"boom_cyl": 1.0}, loads=[Gravity()])
    assert np.max(np.abs(moving.force("arm_cyl") - static.force("arm_cyl"))) > 1e3


def test_forces_of_a_result_without_rates_are_static(excavator: Mechanism) -> None:
    values = _boom_sweep(excavator)
    kin = excavator.solve(values)
    assert kin.unit_rates == ("boom_cyl",)  # the kinematics keeps its transfer functions
    np.testing.assert_array_equal(kin.input_rates[:, 0], 1.0)
    forces = excavator.forces(kin, [Gravity()])
    at_zero = excavator.solve(values, {"boom_cyl": 0.0}, loads=[Gravity()])
    np.testing.assert_array_equal(forces.force("arm_cyl"), at_zero.force("arm_cyl"))
    assert forces.static and forces.kinematics.unit_rates == ()
    note = "static forces, no inertia (no rate given for boom_cyl: taken as 0)"
    assert forces.motion_note == note


def test_a_driver_with_a_rate_beside_one_without(excavator: Mechanism) -> None:
    """One driver moves at a given rate, another is swept without one: the forces are those of
    the motion with the second at rest, whether asked in one call or from the kinematics."""
    values = _boom_sweep(excavator)
    arm = excavator.sketch_values()["arm_cyl"] * np.linspace(0.97, 1.03, 21)
    values = {**values, "arm_cyl": arm}
    explicit = excavator.solve(
        values, {"boom_cyl": 0.0, "arm_cyl": 0.2}, {"arm_cyl": 0.5}, loads=[Gravity()]
    )
    one_call = excavator.solve(values, {"arm_cyl": 0.2}, {"arm_cyl": 0.5}, loads=[Gravity()])
    later = excavator.forces(excavator.solve(values, {"arm_cyl": 0.2}, {"arm_cyl": 0.5}),
                             [Gravity()])  # fmt: skip
    for result in (one_call, later):
        assert not result.static and result.at_rest == ("boom_cyl",)
        for name in excavator.inputs:
            np.testing.assert_allclose(
                result.force(name), explicit.force(name), rtol=1e-12, atol=1e-9
            )
        np.testing.assert_allclose(
            result.kinematics.velocities, explicit.kinematics.velocities, rtol=1e-12, atol=1e-15
        )
    assert "inertia of the given driver rates" in later.motion_note


def _boom() -> Mechanism:
    return Mechanism(
        Model(
            name="boom lifted by a cylinder",
            points={"O": (0.0, 0.0), "C": (0.4, -0.6), "D": (1.4, 0.3), "E": (3.0, 0.5)},
            bodies=(
                Body("frame", ("O", "C"), ground=True),
                Body(
                    "boom", ("O", "E", "D"), mass=1650.0, inertia=4500.0, center_of_mass=(1.5, 0.4)
                ),
            ),
            linear=(LinearDriver("cyl", between=("C", "D")),),
            loads=(PointForce("payload", "boom", "E", (0.0, -5e3)),),
            gravity=Gravity(),
        )
    )


def test_static_cylinder_force_by_virtual_work() -> None:
    """The tutorial's boom: F·δL = −Σ load·δx, with δx from the transfer functions (the
    kinematics without rates) and the centre of mass placed by hand from the sketch."""
    lift = _boom()
    stroke = lift.sketch_values()["cyl"] * np.linspace(0.95, 1.15, 9)
    forces = lift.solve({"cyl": stroke}, loads="model")
    kin = lift.solve({"cyl": stroke})
    angle, omega, _ = kin.body("boom")
    rel = np.array([1.5, 0.4])  # S in the sketch, about O; the body's line O→E at atan2(.5, 3)
    r, a0 = math.hypot(*rel), math.atan2(rel[1], rel[0]) - math.atan2(0.5, 3.0)
    vs_y = r * np.cos(angle + a0) * omega  # dy_S/dL
    ve_y = kin.point("E")[1][:, 1]  # dy_E/dL
    g = 9.80665
    virtual_work = 1650.0 * g * vs_y + 5e3 * ve_y
    np.testing.assert_allclose(forces.force("cyl"), virtual_work, rtol=1e-12)


def test_table_metadata_says_which(excavator: Mechanism) -> None:
    values = _boom_sweep(excavator)
    frame = excavator.solve(values, loads=[Gravity()]).to_frame()
    assert frame.attrs["excavkin.motion"].startswith("static forces, no inertia")
    kin = excavator.solve(values).to_frame()
    assert "transfer functions" in kin.attrs["excavkin.motion"]
    assert "excavkin.motion" not in excavator.solve(values, {"boom_cyl": 0.1}).to_frame().attrs


def test_cli_forces_without_rate_are_static(tmp_path: Path) -> None:
    runner = CliRunner()
    plain, zero = tmp_path / "plain.parquet", tmp_path / "zero.parquet"
    sweep = ["--sweep", "crank=0deg:360deg:37", "--forces", "--gravity"]
    first = runner.invoke(main, ["solve", "fourbar", *sweep, "-o", str(plain)])
    assert first.exit_code == 0, first.output
    assert "excavkin: note: static forces, no inertia (no --rate given for crank" in first.output
    second = runner.invoke(
        main, ["solve", "fourbar", *sweep, "--rate", "crank=0rad/s", "-o", str(zero)]
    )
    assert second.exit_code == 0, second.output
    a, b = pd.read_parquet(plain), pd.read_parquet(zero)
    forces = [c for c in a.columns if c.endswith((".Fx", ".Fy", ".torque"))]
    assert forces
    pd.testing.assert_frame_equal(a[forces], b[forces])
    import pyarrow.parquet as pq

    meta = pq.read_schema(plain).metadata
    assert meta[b"excavkin.motion"].startswith(b"static forces")


def test_tolerance_forces_without_rates_are_static() -> None:
    mech = excavkin.load("fourbar")
    q = np.radians(np.linspace(0.0, 360.0, 13))
    plain = excavkin.tolerance_bands(
        mech, {"crank": q}, tolerances={"A-B": "0.1 mm"}, loads="model"
    )
    zero = excavkin.tolerance_bands(
        mech, {"crank": q}, {"crank": 0.0}, tolerances={"A-B": "0.1 mm"}, loads="model"
    )
    np.testing.assert_array_equal(plain.nominal, zero.nominal)
    np.testing.assert_array_equal(plain.worst, zero.worst)
    assert plain.motion.startswith("static forces")


def test_study_force_metric_is_static() -> None:
    """A study's force metric for the same design is the static one (it read 555.6 kN where
    the static figure is 490.8 kN)."""
    from excavkin.studies.metrics import Metric, Poses, evaluate

    mech = excavkin.load("fourbar")
    q = np.radians(np.linspace(0.0, 360.0, 25))
    designs = {"A-B": np.array([0.118, 0.12, 0.122])}
    metric = [Metric("torque", "crank.torque", "absmax")]
    plain = evaluate(mech, designs, Poses({"crank": q}, {}, {}), metric, loads=[Gravity()])
    zero = evaluate(
        mech, designs, Poses({"crank": q}, {"crank": 0.0}, {}), metric, loads=[Gravity()]
    )
    np.testing.assert_array_equal(plain["torque"], zero["torque"])
    each = [
        np.max(np.abs(mech.solve({"crank": q}, {"crank": 0.0}, params={"A-B": d},
                                 loads=[Gravity()]).torque("crank")))
        for d in designs["A-B"]
    ]  # fmt: skip
    np.testing.assert_allclose(plain["torque"], each, rtol=1e-12)


def test_a_study_without_rates_says_its_force_metrics_are_static(tmp_path: Path) -> None:
    from excavkin.studies.study import run_study
    from excavkin.studies.study_file import load_study

    text = excavkin.example_path("crank_rocker").read_text()
    text = text.replace('[poses.rates]\ncrank = "300 rpm"\n', "").replace("4096", "16")
    spec = tmp_path / "static.toml"
    spec.write_text(text)
    study = load_study(spec)
    assert study.motion_note == "static forces, no inertia (no rate given for crank: taken as 0)"
    result = run_study(study, tmp_path / "static.parquet")
    frame = result.to_frame()
    assert frame.attrs["excavkin.motion"] == study.motion_note
    # each design's torque metric is the static one
    mech = excavkin.load("fourbar")
    q = np.radians(np.linspace(0.0, 360.0, 181))
    row = frame.iloc[0]
    params = {k[len("design.") :]: float(row[k]) for k in frame.columns if k.startswith("design.")}
    torque = mech.solve({"crank": q}, {"crank": 0.0}, params=params, loads="model").torque("crank")
    assert row["torque_peak"] == pytest.approx(np.max(np.abs(torque)), rel=1e-12)
