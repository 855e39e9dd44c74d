"""Disc cams and translating followers: the ``[cams]`` table, the follower's lift, velocity and
acceleration from the lift law, the contact force along the common normal (by virtual work),
the power balance and exact sensitivities."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.interpolate import CubicSpline

import excavkin
from excavkin.errors import ModelError
from excavkin.model.entities import PointForce

CAM = Path(__file__).parents[1] / "reference" / "data" / "disc_cam.toml"
TEXT = CAM.read_text()
TABLE = [0, 2, 8, 14, 18, 20, 20, 18, 14, 8, 2, 0, 0]


def law() -> CubicSpline:
    """The lift law, built here on its own: the periodic cubic spline of the table (m)."""
    return CubicSpline(np.radians(np.arange(0, 361, 30)), np.array(TABLE) / 1e3, bc_type="periodic")


def cam(old: str = "", new: str = "") -> excavkin.Mechanism:
    return excavkin.loads(TEXT.replace(old, new) if old else TEXT, "cam.toml")


def test_the_follower_rises_by_the_lift_law_at_every_turn() -> None:
    mech = cam()
    assert "− 2·2 − 0 − 1 higher pair = 1" in mech.plan.mobility.describe()
    rng = np.random.default_rng(11)
    turn = rng.uniform(-20.0, 20.0, 200)
    w, e = rng.uniform(-30, 30, 200), rng.uniform(-50, 50, 200)
    q0 = mech.sketch_values()["shaft"]
    res = mech.solve({"shaft": q0 + turn}, rates={"shaft": w}, accels={"shaft": e})
    assert res.status.all_ok
    s = law()
    u = np.mod(turn, 2 * np.pi)
    x, v, a = res.point("F1")
    assert_allclose(x[:, 0], 0.0, atol=1e-15)
    assert_allclose(x[:, 1], 0.06 + s(u), atol=1e-15)
    assert_allclose(v[:, 1], s(u, 1) * w, rtol=1e-12, atol=1e-15)
    assert_allclose(a[:, 1], s(u, 2) * w * w + s(u, 1) * e, rtol=1e-12, atol=1e-13)


def test_the_cam_torque_is_the_load_times_the_lift_slope() -> None:
    """Statics by virtual work: T·dθ = F·ds, so the shaft needs T = F·s'(θ) to hold a load F
    down the guide; the contact force is F / cos α along the common normal, tan α = s'/(s_B),
    s_B the roller centre's height above the shaft (a radial follower)."""
    mech = cam()
    turn = np.radians(np.linspace(0.0, 360.0, 73))
    res = mech.solve({"shaft": mech.sketch_values()["shaft"] + turn})
    f = mech.forces(res, loads=[PointForce("spring", "follower", "F2", (0.0, -80.0))])
    s = law()
    assert_allclose(f.torque("shaft"), 80.0 * s(turn, 1), rtol=1e-10, atol=1e-12)
    height = 0.06 + s(turn)
    alpha = np.arctan2(s(turn, 1), height)
    assert_allclose(f.column("lift.contact"), 80.0 / np.cos(alpha), rtol=1e-12)
    assert_allclose(np.abs(f.column("lift.guide")), 80.0 * np.abs(np.tan(alpha)), atol=1e-10)
    assert_allclose(f.column("lift.couple"), 0.0, atol=1e-12)


def test_a_flat_faced_follower_is_pushed_square_to_its_face() -> None:
    mech = cam('face = "roller"', 'face = "flat"')
    turn = np.radians(np.linspace(0.0, 360.0, 37))
    res = mech.solve({"shaft": mech.sketch_values()["shaft"] + turn})
    f = mech.forces(res, loads=[PointForce("spring", "follower", "F2", (0.0, -80.0))])
    s = law()
    assert_allclose(f.column("lift.contact"), 80.0, rtol=1e-12)
    assert_allclose(f.column("lift.guide"), 0.0, atol=1e-10)
    # the contact is s'(θ) off the axis: the guide's couple holds it
    assert_allclose(np.abs(f.column("lift.couple")), 80.0 * np.abs(s(turn, 1)), atol=1e-12)
    assert_allclose(f.torque("shaft"), 80.0 * s(turn, 1), rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("face", ["roller", "flat"])
def test_power_balances_with_inertia_and_gravity(face: str) -> None:
    mech = cam('face = "roller"', f'face = "{face}"')
    rng = np.random.default_rng(2)
    n = 300
    q = mech.sketch_values()["shaft"] + rng.uniform(-9, 9, n)
    res = mech.solve(
        {"shaft": q}, rates={"shaft": rng.uniform(-40, 40, n)},
        accels={"shaft": rng.uniform(-90, 90, n)}, loads="model",
    )  # fmt: skip
    assert np.abs(res.power_balance().relative).max() < 1e-9


def test_a_plan_with_a_cam_compiles_and_its_forces_run_in_numpy() -> None:
    """A table's lift law compiles (tests/crossmethod/test_cams_compiled.py holds the two paths
    together); the forces of a cam are solved in NumPy."""
    mech = cam()
    from excavkin.kinematics.compiled import supports

    assert supports(mech.plan)
    q = mech.sketch_values()["shaft"] + np.linspace(0, 7, 5000)
    res = mech.solve({"shaft": q}, rates={"shaft": 3.0}, loads="model")
    assert res.kinematics.status.all_ok


def test_the_forces_of_a_cam_compile_unless_its_law_is_a_function() -> None:
    """A table's law is traced into the compiled forces (equal to NumPy's); a function's is
    not: ``auto`` solves those forces in NumPy, and ``numba`` asked by name is refused with the
    reason, not run silently another way."""
    from excavkin.errors import InputError

    mech = cam()
    q = mech.sketch_values()["shaft"] + np.linspace(0, 7, 5000)
    kin = mech.solve({"shaft": q}, rates={"shaft": 3.0}, backend="numpy")
    loads = mech.model.loads
    compiled = mech.forces(kin, loads=loads, backend="numba")
    ref = mech.forces(kin, loads=loads, backend="numpy")
    assert_allclose(compiled.cam_force, ref.cam_force, rtol=1e-14, atol=1e-12)
    assert_allclose(compiled.pin_force, ref.pin_force, rtol=1e-14, atol=1e-12)
    by_function = excavkin.Mechanism(_with_law(eccentric))
    kin = by_function.solve({"shaft": by_function.sketch_values()["shaft"] + q[:50]})
    auto = by_function.forces(kin, loads=[PointForce("w", "valve", "F2", (0.0, -5.0))])
    assert np.isfinite(auto.cam_force).all()
    with pytest.raises(InputError, match="a cam whose lift law is a function"):
        by_function.forces(kin, loads=[PointForce("w", "valve", "F2", (0.0, -5.0))],
                           backend="numba")  # fmt: skip


@pytest.mark.parametrize("face", ["roller", "flat"])
def test_sensitivities_equal_8th_order_differences(face: str) -> None:
    sys.path.insert(0, str(Path(__file__).parents[1] / "property"))
    from test_sensitivities import differences

    mech = cam('face = "roller"', f'face = "{face}"')
    q0 = mech.sketch_values()["shaft"]
    values = {"shaft": q0 + np.array([0.3, 1.9, 4.0, -2.5])}
    rates = {"shaft": 0.07}
    names = ["F1.x", "G2.x", "O.y", "follower.mass", "C1.y"]
    res = mech.solve(values, rates=rates, sensitivities=names, loads="model")
    table = res.to_frame()
    forces = [
        c for c in table.columns if c.endswith((".Fx", ".Fy", ".torque", ".contact", ".guide"))
    ]
    force_scale = max(np.abs(table[c].to_numpy()).max() for c in forces)
    for name in names:
        step = 3e-4 * (0.5 if name == "follower.mass" else mech.plan.scale)
        for col, ref in differences(mech, values, rates, {}, name, step).items():
            exact = res.sensitivity(col, name)
            own = force_scale if col in forces or col.endswith((".Rx", ".Ry", ".couple")) else 0
            scale = max(np.abs(ref).max(), 1e-3 * max(np.abs(table[col]).max(), own, 1e-3))
            assert np.abs(exact - ref).max() / scale < 1e-8, (name, col)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("[330, 0], [360, 0]]", "[330, 0], [360, 1]]", "must equal the lift at 0"),
        ("[[0, 0], [30, 2]", "[[0, 0], [30, 2], [20, 3]", "increase strictly"),
        ("[330, 0], [360, 0]]", "[330, 0], [350, 0]]", "runs from 0 to 360 deg"),
        ('face = "roller"', 'face = "knife"', "face must be 'roller' or 'flat'"),
        ('along = ["G1", "G2"]', 'along = ["G1", "C1"]', "two different points of the carrier"),
        ('follower = "follower"', 'follower = "disc"', "three different bodies"),
        ('face = "roller"', 'face = "roller"\nspring = 1', "unknown key spring"),
    ],
)
def test_bad_cam_entries_are_refused_by_name(old: str, new: str, message: str) -> None:
    with pytest.raises(ModelError, match=message) as info:
        cam(old, new)
    assert "lift" in str(info.value)


def test_the_lift_law_is_read_with_units() -> None:
    text = TEXT.replace('angle = "deg"', "").replace("lift = [[0, 0]", 'lift = [["0 deg", "0 mm"]')
    with pytest.raises(ModelError, match="needs a unit"):
        excavkin.loads(text, "cam.toml")  # bare turns without a default angle unit
    assert math.isclose(cam().model.cams[0].lift[1][0], math.radians(30.0))


def _with_law(law: object) -> excavkin.Model:
    from excavkin import Body, CamFollower, Model, RotaryDriver

    return Model(
        name="cam by a function",
        points={"O": (0.0, 0.0), "G1": (0.0, -0.1), "G2": (0.0, 0.3), "C": (0.02, 0.0),
                "F1": (0.0, 0.035), "F2": (0.0, 0.2)},
        bodies=(Body("frame", ("O", "G1", "G2"), ground=True), Body("cam", ("O", "C")),
                Body("valve", ("F1", "F2"), mass=0.3)),
        rotary=(RotaryDriver("shaft", body="cam", pivot="O", reference="frame"),),
        cams=(CamFollower("lift", "cam", "valve", "frame", ("G1", "G2"), law),),  # type: ignore[arg-type]
    )  # fmt: skip


def eccentric(theta):  # type: ignore[no-untyped-def]
    """An eccentric's lift, 10 mm peak to peak: s = 5 mm·(1 − cos θ)."""
    return 0.005 * (1 - np.cos(theta)), 0.005 * np.sin(theta), 0.005 * np.cos(theta)


def test_a_lift_function_drives_the_follower_but_refuses_sensitivities() -> None:
    mech = excavkin.Mechanism(_with_law(eccentric))
    q = mech.sketch_values()["shaft"] + np.linspace(0, 9, 10)
    res = mech.solve({"shaft": q}, rates={"shaft": 4.0})
    turn = np.linspace(0, 9, 10)
    assert_allclose(res.point("F1")[0][:, 1], 0.035 + 0.005 * (1 - np.cos(turn)), atol=1e-15)
    assert_allclose(res.point("F1")[1][:, 1], 0.02 * np.sin(turn), atol=1e-15)
    with pytest.raises(excavkin.InputError, match="lift law is a function"):
        mech.solve({"shaft": q}, sensitivities=["F1.y"])


def test_a_lift_function_that_is_not_periodic_is_refused() -> None:
    with pytest.raises(ModelError, match="must be periodic"):
        excavkin.Mechanism(_with_law(lambda t: (t, 1.0 + 0 * t, 0 * t)))
    with pytest.raises(ModelError, match="failed at the turn 0: ZeroDivisionError"):
        excavkin.Mechanism(_with_law(lambda t: (1 / 0, 0, 0)))


ROCKER = Path(__file__).parents[1] / "reference" / "data" / "cam_rocker.toml"
SWING = [0, 2, 7, 12, 15, 12, 6, 1, 0]


def swing_law() -> CubicSpline:
    """The oscillating follower's law, built here on its own (rad per rad of the cam)."""
    return CubicSpline(np.radians(np.arange(0, 361, 45)), np.radians(SWING), bc_type="periodic")


def test_an_oscillating_follower_swings_by_its_law() -> None:
    mech = excavkin.load(ROCKER)
    assert "− 2·2 − 0 − 1 higher pair = 1" in mech.plan.mobility.describe()
    rng = np.random.default_rng(4)
    turn = rng.uniform(-15, 15, 100)
    w, e = rng.uniform(-30, 30, 100), rng.uniform(-60, 60, 100)
    res = mech.solve(
        {"shaft": mech.sketch_values()["shaft"] + turn}, rates={"shaft": w}, accels={"shaft": e}
    )
    psi = swing_law()
    u = np.mod(turn, 2 * np.pi)
    angle, omega, eps = res.body("arm")
    start = math.atan2(10.0, 100.0)
    assert_allclose(np.mod(angle - start - psi(u) + np.pi, 2 * np.pi) - np.pi, 0.0, atol=1e-14)
    assert_allclose(omega, psi(u, 1) * w, rtol=1e-12, atol=1e-14)
    assert_allclose(eps, psi(u, 2) * w * w + psi(u, 1) * e, rtol=1e-12, atol=1e-12)


def test_an_oscillating_follower_by_virtual_work_and_its_instant_centre() -> None:
    """A couple −T on the arm needs T·ψ'(θ) on the shaft; the contact force acts at the roller
    through the instant centre I = (Oc − ψ'·Of)/(1 − ψ') of cam and arm, and its moment about
    the arm's pivot holds the couple."""
    from excavkin.model.entities import Torque

    mech = excavkin.load(ROCKER)
    turn = np.radians(np.linspace(0.0, 355.0, 72))
    res = mech.solve({"shaft": mech.sketch_values()["shaft"] + turn})
    f = mech.forces(res, loads=[Torque("spring", "arm", -3.0)])
    psi1 = swing_law()(turn, 1)
    assert_allclose(f.torque("shaft"), 3.0 * psi1, rtol=1e-10, atol=1e-12)
    oc, of = np.array([0.0, 0.0]), np.array([-0.12, 0.04])
    b = res.point("B")[0]
    direction = (b - oc) - psi1[:, None] * (b - of)
    n = direction / np.hypot(direction[:, 0], direction[:, 1])[:, None]
    arm = (b - of)[:, 0] * n[:, 1] - (b - of)[:, 1] * n[:, 0]
    assert_allclose(f.column("swing.contact") * arm, 3.0, rtol=1e-12)


def test_an_oscillating_follower_balances_power_and_has_exact_sensitivities() -> None:
    sys.path.insert(0, str(Path(__file__).parents[1] / "property"))
    from test_sensitivities import differences

    mech = excavkin.load(ROCKER)
    rng = np.random.default_rng(8)
    q = mech.sketch_values()["shaft"] + rng.uniform(-9, 9, 300)
    res = mech.solve(
        {"shaft": q}, rates={"shaft": rng.uniform(-40, 40, 300)},
        accels={"shaft": rng.uniform(-90, 90, 300)}, loads="model",
    )  # fmt: skip
    assert np.abs(res.power_balance().relative).max() < 1e-9
    values = {"shaft": mech.sketch_values()["shaft"] + np.array([0.3, 1.9, 4.0, -2.5])}
    rates = {"shaft": 0.07}
    names = ["P.x", "B.y", "O.y", "arm.mass", "C1.y"]
    res = mech.solve(values, rates=rates, sensitivities=names, loads="model")
    table = res.to_frame()
    forces = [c for c in table.columns if c.endswith((".Fx", ".Fy", ".torque", ".contact"))]
    force_scale = max(np.abs(table[c].to_numpy()).max() for c in forces)
    for name in names:
        step = 3e-4 * (0.4 if name == "arm.mass" else mech.plan.scale)
        for col, ref in differences(mech, values, rates, {}, name, step).items():
            exact = res.sensitivity(col, name)
            own = force_scale if col in forces or col.endswith((".Rx", ".Ry")) else 0
            scale = max(np.abs(ref).max(), 1e-3 * max(np.abs(table[col]).max(), own, 1e-3))
            assert np.abs(exact - ref).max() / scale < 1e-8, (name, col)


def test_an_oscillating_follower_must_be_a_pivoted_roller() -> None:
    text = ROCKER.read_text()
    with pytest.raises(ModelError, match="an oscillating follower is a roller"):
        excavkin.loads(text.replace('follower = "arm"', 'follower = "arm"\nface = "flat"'), "r")
    with pytest.raises(ModelError, match="shares 0 points with its carrier"):
        excavkin.loads(
            text.replace('arm = { points = ["P", "B", "E"]', 'arm = { points = ["B", "E"]'),
            "r",
        )
