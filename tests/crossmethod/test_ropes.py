"""Ropes against independent computations: the seeds' winch relation reproduced by a solved
model (not by its formula), the slack boundary by hand, power balance with inertia, and the
exact design sensitivities of the tension and the winch torque against 8th-order differences."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from excavkin import Gravity, Mechanism, Model, PointForce, Rope
from excavkin.io.toml_model import load_model
from excavkin.model.entities import Body
from excavkin.papers.rope_shovel import reference as ref
from tests.conftest import EXAMPLES

#: 8th-order central-difference weights for the first derivative (offsets −4 … 4)
WEIGHTS = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])

HOIST = Rope("hoist", ("A", "B"), parts=2, mode="winch", drum_radius=0.25, gear_ratio=20.0)


def boom(rope: Rope = HOIST, mass: bool = True) -> Model:
    """A boom O–B pivoted on the ground at O, held at its tip B by a rope from the mast A."""
    return Model(
        "boom",
        {"O": (0.0, 0.0), "A": (-1.0, 3.0), "B": (1.5, 2.0)},
        (
            Body("ground", ("O", "A"), ground=True),
            Body(
                "boom",
                ("O", "B"),
                mass=120.0 if mass else None,
                inertia=60.0 if mass else None,
                center_of_mass=(0.8, 1.0) if mass else None,
            ),
        ),
        ropes=(rope,),
        gravity=Gravity() if mass else None,
    )


def test_seeds_winch_relation_by_the_solved_model() -> None:
    """EO4112_DRIVE (motor 750 rpm, drum 0.25 m, i = 20, two-fall block): the drag rope of the
    rope-shovel example as a winch of those numbers, turned at the motor's speed, hauls in at
    the reference's v = ω·R/(i·a_p), and the mechanism moves as the length-driven example."""
    d = ref.EO4112_DRIVE
    base = load_model(EXAMPLES / "rope_shovel.toml")
    winch = Rope("drag", ("F", "E"), int(d.multiplicity), "winch", d.r_drum, d.gear_ratio)
    model = dataclasses.replace(
        base, linear=tuple(e for e in base.linear if e.name != "drag"), ropes=(winch,)
    )
    by_length, by_motor = Mechanism(base), Mechanism(model)
    length = by_length.plan.input_sketch[0] + np.linspace(-0.4, 0.4, 41)
    theta = length / winch.ratio
    omega = -d.omega_motor  # hauling in
    eps = 3.0  # rad/s², the motor speeding up
    motor = by_motor.solve({"drag": theta}, {"drag": omega}, {"drag": eps})
    v_rope = float(ref.rope_speed(d.omega_motor, d.r_drum, d.gear_ratio, d.multiplicity)[0])
    assert motor.status.all_ok
    frame = motor.to_frame()
    np.testing.assert_allclose(frame["drag.rate"], omega, rtol=0)  # the motor's speed
    np.testing.assert_allclose(-frame["drag.length_rate"], v_rope, rtol=4e-16)  # one rounding
    lengths = by_length.solve({"drag": length}, {"drag": -v_rope}, {"drag": eps * winch.ratio})
    assert lengths.status.all_ok
    np.testing.assert_allclose(motor.positions, lengths.positions, rtol=0, atol=1e-12)
    np.testing.assert_allclose(motor.velocities, lengths.velocities, rtol=0, atol=1e-12)
    np.testing.assert_allclose(motor.accelerations, lengths.accelerations, rtol=0, atol=1e-11)


def hand_tension(b: np.ndarray, w: float, parts: int) -> np.ndarray:
    """Moments about O of a weight w at B and of the rope's parts·T from B towards A."""
    a = np.array([-1.0, 3.0])
    u = (a - b) / np.linalg.norm(a - b, axis=1)[:, None]
    arm = b[:, 0] * u[:, 1] - b[:, 1] * u[:, 0]
    return np.asarray(w * b[:, 0] / (parts * arm))


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_slack_rope_is_never_ok(backend: str) -> None:
    """A weight at the boom's tip: the rope holds it while the tip is right of the pivot and
    would have to push once it is left of it. The boundary is the vertical boom, the blocks
    then sqrt(1.25) m apart (by hand); there the tension changes sign."""
    mech = Mechanism(boom(mass=False))
    boundary = np.sqrt(1.0**2 + 0.5**2) / HOIST.ratio
    theta = boundary + np.array([-30.0, -1e-3, 1e-3, 30.0, 100.0])
    kin = mech.solve({"hoist": theta})
    f = mech.forces(kin, [PointForce("w", "boom", "B", (0.0, -1000.0))], backend=backend)
    tension = f.tension("hoist")
    np.testing.assert_allclose(
        tension, hand_tension(kin.positions[:, 2], 1000.0, 2), rtol=1e-12, atol=1e-9
    )
    assert list(np.sign(tension)) == [-1, -1, 1, 1, 1]
    assert list(f.slack) == [True, True, False, False, False]
    assert list(f.ok) == [False, False, True, True, True]
    labels = f.status_labels()
    assert labels[0] == "slack rope 'hoist' (it would have to push)"
    frame = f.to_frame()
    assert list(frame["status"])[:3] == [labels[0], labels[1], "ok"]
    np.testing.assert_allclose(frame["hoist.tension"], tension)
    assert "slack rope 'hoist'" in f.summary()
    # the winch's torque does the rope's work: −T·R/i
    np.testing.assert_allclose(f.winch_torque("hoist"), -tension * 0.25 / 20.0, rtol=1e-15)


def test_power_balance_with_inertia() -> None:
    mech = Mechanism(boom())
    theta = mech.plan.input_sketch[0] + np.linspace(-80.0, 80.0, 33)
    res = mech.solve({"hoist": theta}, {"hoist": -30.0}, {"hoist": 12.0}, loads="model")
    assert res.ok.all()
    pb = res.power_balance()
    assert np.max(pb.relative) < 1e-9
    # the winch's power is its torque times the motor's speed
    np.testing.assert_allclose(res.winch_torque("hoist") * -30.0, pb.driver, rtol=1e-12, atol=1e-9)


def differences(mech, values, rates, name, step):  # type: ignore[no-untyped-def]
    tables = []
    for k in range(-4, 5):
        moved = {name: mech.parameters[name] + k * step}
        res = mech.solve(values, rates=rates, params=moved, loads="model")
        assert res.kinematics.status.all_ok
        tables.append(res.to_frame())
    cols = [c for c in tables[0].columns if tables[0][c].dtype.kind == "f"]
    return {
        c: sum(w * t[c].to_numpy() for w, t in zip(WEIGHTS, tables, strict=True)) / step
        for c in cols
    }


def test_sensitivities_against_8th_order_differences() -> None:
    mech = Mechanism(boom())
    # (off the sketch: a sample given exactly at it is taken as held there, moving with it)
    values = {"hoist": mech.plan.input_sketch[0] + np.linspace(-60.0, 60.0, 6)}
    rates = {"hoist": 2.0}
    names = ["A.x", "A.y", "B.x", "B.y", "boom.mass"]
    res = mech.solve(values, rates=rates, sensitivities=names, loads="model")
    table = res.to_frame()
    for name in names:
        step = 3e-4 * (mech.parameters[name] if name.endswith(".mass") else mech.plan.scale)
        fd = differences(mech, values, rates, name, step)
        for col in ("hoist.tension", "hoist.torque", "hoist.force", "O.boom.Fx", "B.x"):
            exact = res.sensitivity(col, name)
            floor = 1e-3 * max(np.abs(table[col].to_numpy()).max(), 1e-3) / mech.plan.scale
            scale = max(np.abs(fd[col]).max(), floor)
            assert np.abs(exact - fd[col]).max() / scale < 1e-8, (col, name)


@pytest.mark.parametrize("sheaved", [False, True])
def test_a_held_winch_in_a_family_of_designs_holds_each_design_s_sketch(sheaved: bool) -> None:
    """A winch not given a value is held at its sketch: each design's own sketch length over
    R/(i·n), so that every design is drawn at its sketch."""
    if sheaved:
        rope = Rope("hoist", ("A", "B", "O2"), mode="winch", drum_radius=0.25, gear_ratio=20.0,
                    radii=(0.2,), wraps=("cw",))  # fmt: skip
        model = dataclasses.replace(
            boom(rope, mass=False),
            points={
                "O": (0.0, 0.0),
                "A": (-1.0, 3.0),
                "B": (1.5, 2.0),
                "O2": (-2.0, 0.5),
            },  # fmt: skip
            bodies=(Body("ground", ("O", "A", "O2"), ground=True), Body("boom", ("O", "B"))),
        )
    else:
        model = boom(mass=False)
    mech = Mechanism(model)
    res = mech.solve({}, params={"B.x": np.array([1.5, 1.6]), "B.y": np.array([2.0, 1.9])})
    assert res.status.all_ok
    np.testing.assert_allclose(res.positions[:, 2], [(1.5, 2.0), (1.6, 1.9)], atol=1e-12)


@pytest.mark.parametrize("sheaved", [False, True])
def test_drum_radius_and_gear_ratio_as_design_parameters(sheaved: bool) -> None:
    """A family of winch designs equals the models built with each drum and gear ratio; the
    exact sensitivities to them, of the motion, the tension and the motor's torque, equal
    8th-order differences of whole solves."""
    if sheaved:
        rope = Rope("hoist", ("A", "B", "O2"), mode="winch", drum_radius=0.25, gear_ratio=20.0,
                    radii=(0.2,), wraps=("cw",))  # fmt: skip

        def build(r: Rope) -> Model:
            return dataclasses.replace(
                boom(r),
                points={"O": (0.0, 0.0), "A": (-1.0, 3.0), "B": (1.5, 2.0), "O2": (-2.0, 0.5)},
                bodies=(
                    Body("ground", ("O", "A", "O2"), ground=True),
                    Body("boom", ("O", "B"), mass=120.0, inertia=60.0, center_of_mass=(0.8, 1.0)),
                ),
            )
    else:
        rope = HOIST

        def build(r: Rope) -> Model:
            return boom(r)

    mech = Mechanism(build(rope))
    assert mech.parameters["hoist.drum_radius"] == 0.25
    assert mech.parameters["hoist.gear_ratio"] == 20.0
    theta = mech.plan.input_sketch[0] + np.array([-40.0, -15.0, 25.0])
    radii, ratios = np.array([0.25, 0.26, 0.24]), np.array([20.0, 19.0, 21.0])
    family = mech.solve(
        {"hoist": theta}, {"hoist": 2.0}, params={"hoist.drum_radius": radii,
                                                  "hoist.gear_ratio": ratios},
        loads="model",
    )  # fmt: skip
    for k in range(3):
        one = dataclasses.replace(rope, drum_radius=float(radii[k]), gear_ratio=float(ratios[k]))
        alone = Mechanism(build(one)).solve(
            {"hoist": theta[k : k + 1]}, {"hoist": 2.0}, loads="model"
        )
        a, b = family.to_frame().iloc[k], alone.to_frame().iloc[0]
        for col in ("B.x", "B.vy", "hoist.tension", "hoist.torque", "O.boom.Fx"):
            assert a[col] == pytest.approx(b[col], rel=1e-12, abs=1e-12), (k, col)
    names = ["hoist.drum_radius", "hoist.gear_ratio"]
    values = {"hoist": theta}
    res = mech.solve(values, {"hoist": 2.0}, sensitivities=names, loads="model")
    for name in names:
        step = 3e-4 * mech.parameters[name]
        tables = [
            mech.solve(values, {"hoist": 2.0}, params={name: mech.parameters[name] + k * step},
                       loads="model").to_frame()
            for k in range(-4, 5)
        ]  # fmt: skip
        for col in ("B.x", "B.vy", "hoist.tension", "hoist.torque", "O.boom.Fy"):
            fd = sum(w * t[col].to_numpy() for w, t in zip(WEIGHTS, tables, strict=True)) / step
            exact = res.sensitivity(col, name)
            scale = max(np.abs(fd).max(), 1e-3 * np.abs(tables[4][col]).max() / 0.25)
            assert np.abs(exact - fd).max() / scale < 1e-8, (col, name)


def test_a_family_of_winches_compiled_equals_numpy() -> None:
    mech = Mechanism(boom(HOIST))
    theta = mech.plan.input_sketch[0] + np.linspace(-40.0, 40.0, 9)
    params = {
        "hoist.drum_radius": np.linspace(0.24, 0.26, 9),
        "hoist.gear_ratio": np.linspace(19.0, 21.0, 9),
    }
    names = ["hoist.drum_radius", "B.x"]
    runs = [
        mech.solve({"hoist": theta}, {"hoist": 2.0}, params=params, backend=c, sensitivities=names)
        for c in ("numpy", "numba")
    ]
    np.testing.assert_allclose(runs[1].positions, runs[0].positions, rtol=0, atol=1e-14)
    np.testing.assert_allclose(runs[1].accelerations, runs[0].accelerations, rtol=0, atol=1e-13)
    for col in ("B.x", "B.vy", "hoist.length"):
        for name in names:
            np.testing.assert_allclose(
                runs[1].sensitivity(col, name), runs[0].sensitivity(col, name), atol=1e-13
            )
