"""Racks and pinions: the ``[racks]`` table, the rack step's closed forms on a fixed and on a
turning carrier (NumPy and compiled), the guide and tooth forces, the power balance and exact
sensitivities."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin.errors import ModelError
from excavkin.model.entities import PointForce, Torque

ARM = (
    (Path(__file__).parents[1] / "reference" / "data" / "rack_on_arm.toml")
    .read_text()
    .replace('radius = "40 mm"', "RACK_KEYS")
)


def arm(keys: str = 'radius = "40 mm"') -> excavkin.Mechanism:
    return excavkin.loads(ARM.replace("RACK_KEYS", keys), "arm.toml")


def samples(n: int, seed: int = 5) -> tuple[dict[str, np.ndarray], ...]:
    rng = np.random.default_rng(seed)
    q = {"swing": rng.uniform(-3, 3, n), "motor": rng.uniform(-40, 40, n)}
    qd = {k: rng.uniform(-2, 2, n) for k in q}
    qdd = {k: rng.uniform(-5, 5, n) for k in q}
    return q, qd, qdd


def test_the_rack_travels_r_per_radian_of_the_pinion_on_its_turning_guide() -> None:
    mech = arm()
    assert "M = 3·(4 − 1) − 2·3 − 0 − 1 higher pair = 2" in mech.plan.mobility.describe()
    q, qd, qdd = samples(50)
    res = mech.solve(q, rates=qd, accels=qdd)
    assert res.status.all_ok
    sk = mech.sketch_values()
    # independently: in the arm's frame R1 is at (300 + 0.04·(q − q0)·1000, −60) mm (the rack
    # below the pinion: a counter-clockwise pinion moves it forwards), turned by the swing
    s = 0.3 + 0.04 * (q["motor"] - sk["motor"])
    th = q["swing"] - sk["swing"]
    x = s * np.cos(th) + 0.06 * np.sin(th)
    y = s * np.sin(th) - 0.06 * np.cos(th)
    assert_allclose(res.point("R1")[0], np.stack([x, y], axis=1), atol=1e-15)
    # rates: differentiate the same closed form by hand
    sd = 0.04 * qd["motor"]
    w, wd = qd["swing"], qdd["swing"]
    vx = sd * np.cos(th) - w * y
    vy = sd * np.sin(th) + w * x
    assert_allclose(res.point("R1")[1], np.stack([vx, vy], axis=1), atol=1e-13)
    sdd = 0.04 * qdd["motor"]
    ax = sdd * np.cos(th) - 2 * sd * w * np.sin(th) - wd * y - w * w * x
    ay = sdd * np.sin(th) + 2 * sd * w * np.cos(th) + wd * x - w * w * y
    assert_allclose(res.point("R1")[2], np.stack([ax, ay], axis=1), atol=1e-12)
    assert_allclose(res.body("bar")[1], qd["swing"], rtol=1e-14)


def test_compiled_and_numpy_agree() -> None:
    mech = arm()
    q, qd, qdd = samples(3000)
    r0 = mech.solve(q, rates=qd, accels=qdd, backend="numpy")
    r1 = mech.solve(q, rates=qd, accels=qdd, backend="numba")
    for name in ("positions", "velocities", "accelerations"):
        assert_allclose(getattr(r1, name), getattr(r0, name), rtol=1e-14, atol=1e-13)
    loads = [PointForce("dig", "bar", "R2", (-3e3, 1e3)), Torque("brake", "pinion", 5.0)]
    f0 = mech.forces(r0, loads=loads, backend="numpy")
    f1 = mech.forces(r0, loads=loads, backend="numba")
    assert_allclose(f1.rack_force, f0.rack_force, rtol=1e-12, atol=1e-9)
    assert_allclose(f1.pin_force, f0.pin_force, rtol=1e-12, atol=1e-9)


def test_power_balances_and_the_forces_are_those_of_the_rack() -> None:
    mech = arm()
    q, qd, qdd = samples(300)
    res = mech.solve(q, rates=qd, accels=qdd, loads="model")
    assert np.abs(res.power_balance().relative).max() < 1e-9
    # statics, no gravity: a push along the guide on the rack is the tooth force, and the
    # pinion's motor holds W·r; the guide takes W·tan φ, pressing the rack on its guide
    still = mech.solve(q)
    push = 2e3
    forces = []
    for k in range(len(q["swing"])):
        th = q["swing"][k] - mech.sketch_values()["swing"]
        forces.append((-push * math.cos(th), -push * math.sin(th)))
    f = mech.forces(still, loads=[PointForce("dig", "bar", "R2", np.array(forces))])
    assert_allclose(f.column("crowd.tooth"), push, rtol=1e-12)
    assert_allclose(f.torque("motor"), push * 0.04, rtol=1e-12)
    assert_allclose(f.column("crowd.guide"), push * math.tan(math.radians(20)), rtol=1e-12)
    # the pinion's pin takes the tooth force and its radial part: |F| = W / cos φ
    pin = f.pin_force[:, f.pins.index(("P", "pinion"))]
    assert_allclose(np.hypot(pin[:, 0], pin[:, 1]), push / math.cos(math.radians(20)), rtol=1e-12)


def test_sensitivities_equal_8th_order_differences() -> None:
    sys.path.insert(0, str(Path(__file__).parents[1] / "property"))
    from test_sensitivities import differences

    mech = arm()
    values = {"swing": np.array([0.1, 0.6, -1.0]), "motor": np.array([1.5, 9.0, -7.0])}
    rates = {"swing": 0.07, "motor": 0.07}
    names = ["P.x", "G2.y", "R1.y", "bar.mass", "O.y"]
    res = mech.solve(values, rates=rates, sensitivities=names, loads="model")
    table = res.to_frame()
    forces = [c for c in table.columns if c.endswith((".Fx", ".Fy", ".torque", ".tooth", ".guide"))]
    force_scale = max(np.abs(table[c].to_numpy()).max() for c in forces)
    for name in names:
        step = 3e-4 * (3.0 if name == "bar.mass" else mech.plan.scale)
        for col, ref in differences(mech, values, rates, {}, name, step).items():
            exact = res.sensitivity(col, name)
            own = force_scale if col in forces or col.endswith((".Rx", ".Ry", ".couple")) else 0
            scale = max(np.abs(ref).max(), 1e-3 * max(np.abs(table[col]).max(), own, 1e-3))
            assert np.abs(exact - ref).max() / scale < 1e-8, (name, col)


@pytest.mark.parametrize(
    ("keys", "message"),
    [
        ('radius = "-4 mm"', "pitch radius must be positive"),
        ('radius = "4 mm"\npressure_angle = "90 deg"', "pressure angle must be in"),
        ('radius = "4 mm"\nspeed = 1', "unknown key speed"),
    ],
)
def test_bad_rack_entries_are_refused_by_name(keys: str, message: str) -> None:
    with pytest.raises(ModelError, match=message) as info:
        arm(keys)
    assert "crowd" in str(info.value)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('along = ["G1", "G2"]', 'along = ["G1", "F"]', "two different points of the carrier"),
        ("R1 = [300, -60]", "R1 = [300, 0]", "does not show on which side"),
        ('carrier = "arm"', 'carrier = "bar"', "three different bodies"),
        ('bar = { points = ["R1", "R2"]', 'bar = { points = ["R1", "R2", "G1"]', "shares G1 with"),
    ],
)
def test_a_rack_that_does_not_fit_its_guide_is_refused(old: str, new: str, message: str) -> None:
    text = ARM.replace("RACK_KEYS", 'radius = "40 mm"').replace(old, new)
    with pytest.raises(ModelError, match=message):
        excavkin.loads(text, "arm.toml")


@pytest.mark.parametrize("name", ["rack_on_arm.toml", "planetary_21_43_108.toml"])
def test_compiled_sensitivities_equal_numpy_ones(name: str) -> None:
    from excavkin.execution import Execution
    from excavkin.kinematics.sensitivity import solve_tangents

    mech = excavkin.load(Path(__file__).parents[1] / "reference" / "data" / name)
    rng = np.random.default_rng(1)
    q = {k: v + rng.uniform(-3, 3, 3000) for k, v in mech.sketch_values().items()}
    res = mech.solve(q, rates={k: 1.3 for k in q}, accels={k: -0.4 for k in q})
    names = [k for k in mech.parameters if not k.endswith(("mass", "inertia"))][:6]
    a = solve_tangents(res, names, execution=Execution("numpy"))
    b = solve_tangents(res, names, execution=Execution("numba"))
    for k in names:
        for arr in ("positions", "velocities", "accelerations"):
            assert_allclose(getattr(b[k], arr), getattr(a[k], arr), rtol=1e-12, atol=1e-12)


GEARED = """
schema_version = 1
name = "rack driven through a gear pair"
[units]
length = "mm"
[points]
M = [0, 0]
MA = [0, 30]
O = [150, 0]
A = [150, 40]
G1 = [0, -100]
G2 = [400, -100]
R1 = [100, -60]
R2 = [300, -60]
[bodies]
frame = { points = ["M", "O", "G1", "G2"], ground = true }
motor_gear = { points = ["M", "MA"], mass = "0.5 kg", inertia = "2e-4 kg*m^2" }
pinion = { points = ["O", "A"], mass = "1 kg", inertia = "0.001 kg*m^2", center_of_mass = [150, 0] }
bar = { points = ["R1", "R2"], mass = "3 kg", inertia = "0.05 kg*m^2" }
[drivers.motor]
type = "rotary"
body = "motor_gear"
pivot = "M"
[gears.drive]
gears = ["motor_gear", "pinion"]
ratio = 2
[racks.crowd]
rack = "bar"
pinion = "pinion"
along = ["G1", "G2"]
radius = "40 mm"
[loads.push]
type = "force"
body = "bar"
point = "R2"
value = ["-300 N", "0 N"]
[gravity]
"""


def test_a_pinion_radius_and_a_gear_ratio_move_the_rack_by_their_own_values() -> None:
    mech = excavkin.loads(GEARED, "geared.toml")
    assert mech.parameters["crowd.radius"] == 0.04 and mech.parameters["drive.ratio"] == 2.0
    radius, ratio = np.array([0.04, 0.05, 0.03, -0.01]), np.array([2.0, 1.5, 3.0, 2.0])
    q = np.full(4, 3.0)
    res = mech.solve({"motor": q}, params={"crowd.radius": radius, "drive.ratio": ratio})
    # independently: from the sketch (q0 = π/2) the pinion turns −Δq/ratio, and the rack, to
    # the right of the guide's direction from the pinion (σ = −1), by −r·Δq/ratio along it
    assert res.status.ok.tolist() == [True, True, True, False]
    travel = res.point("R1")[0][:3, 0] - 0.1
    assert_allclose(travel, -radius[:3] * (q[:3] - math.pi / 2) / ratio[:3], rtol=1e-13)


@pytest.mark.parametrize("name", ["crowd.radius", "drive.ratio"])
def test_radius_and_ratio_sensitivities_equal_8th_order_differences(name: str) -> None:
    sys.path.insert(0, str(Path(__file__).parents[1] / "property"))
    from test_sensitivities import differences

    mech = excavkin.loads(GEARED, "geared.toml")
    values = {"motor": np.array([0.3, 1.0, 7.0, -6.0])}
    rates = {"motor": 0.07}
    for backend in ("numpy", "numba"):
        res = mech.solve(values, rates=rates, sensitivities=[name], loads="model", backend=backend)
        table = res.to_frame()
        forces = [c for c in table.columns if c.endswith((".Fx", ".Fy", ".torque", ".tooth"))]
        force_scale = max(np.abs(table[c].to_numpy()).max() for c in forces)
        step = 1e-4 if name == "crowd.radius" else 1e-3
        moved = 0
        for col, ref in differences(mech, values, rates, {}, name, step).items():
            exact = res.sensitivity(col, name)
            own = force_scale if col in forces or col.startswith(("crowd.", "drive.")) else 0.0
            scale = max(np.abs(ref).max(), 1e-3 * max(np.abs(table[col]).max(), own, 1e-3))
            assert np.abs(exact - ref).max() / scale < 1e-8, (backend, col)
            moved += col == "motor.torque" and np.abs(ref).max() > 1.0
        assert moved  # the motor's torque moves with the radius and the ratio, and was checked


def test_a_pinion_radius_family_equals_each_design_as_its_own_model() -> None:
    import dataclasses

    mech = excavkin.loads(GEARED, "geared.toml")
    radius, ratio = np.array([0.04, 0.05, 0.03]), np.array([2.0, 1.5, 3.0])
    q = np.array([3.0, -2.0, 5.0])
    fam = mech.solve({"motor": q}, rates={"motor": 0.3}, loads="model",
                     params={"crowd.radius": radius, "drive.ratio": ratio}).to_frame()  # fmt: skip
    for k in range(3):
        model = mech.model
        model = dataclasses.replace(
            model,
            racks=(dataclasses.replace(model.racks[0], radius=float(radius[k])),),
            gears=(dataclasses.replace(model.gears[0], ratio=float(ratio[k])),),
        )
        own = excavkin.Mechanism(model).solve({"motor": q[k : k + 1]}, rates={"motor": 0.3},
                                               loads="model").to_frame()  # fmt: skip
        for col in own.columns:
            if own[col].dtype.kind == "f":
                ref = own[col].iloc[0]
                assert abs(fam[col].iloc[k] - ref) <= 1e-12 * max(1.0, abs(ref)), col


def test_a_pinion_radius_is_written_back(tmp_path: Path) -> None:
    from excavkin.io.model_write import model_text_with

    src = tmp_path / "geared.toml"
    src.write_text(GEARED)
    text = model_text_with(src, {"crowd.radius": 0.045})
    (rk,) = excavkin.loads(text, "geared.toml").model.racks
    assert rk.radius == pytest.approx(0.045, rel=1e-15) and 'radius = "45' in text
