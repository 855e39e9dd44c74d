"""A rope over sheaves of several parts (issue 26): a block reeved over sheaves is a path that
visits its two blocks in turn, each visit one of the block's sheaves (all of one radius). Its
length at three orders against the tangents constructed in 40-digit arithmetic (mpmath), the
published four-part block of tests/reference/test_rope_examples.py reeved over real sheaves,
the tension against moments by hand, the power balance, the sensitivities (the blocks' sheave
radii included) against 8th-order differences, and the file's checks and write-back."""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from excavkin import Gravity, Mechanism, Model, PointForce, Rope
from excavkin.errors import ModelError
from excavkin.io.toml_model import loads_model
from excavkin.model.entities import Body
from excavkin.units import to_si
from tests.crossmethod.test_rope_sheaves import WEIGHTS, mp_length, tangent

mp.mp.dps = 40

#: the luffing rope: from the winch's lead A over the fixed sheave S to the mast block M, then
#: four parts between M and the boom's tip block T, dead-ended at M's centre
PATH = ("A", "S", "M", "T", "M", "T", "M")
RADII = (0.2, 0.15, 0.12, 0.15, 0.12)
WRAPS = ("cw", "cw", "cw", "cw", "cw")


def luffing(radii: tuple[float, ...] = RADII, mass: bool = True) -> Model:
    """A boom O–T pivoted at O, luffed by a winch rope reeved four parts between the mast
    block M and the tip block T."""
    rope = Rope("luff", PATH, mode="winch", drum_radius=0.25, gear_ratio=20.0, radii=radii,
                wraps=WRAPS)  # fmt: skip
    return Model(
        "luffing boom on a reeved rope",
        {"O": (0.0, 0.0), "A": (-2.0, 0.3), "S": (-1.5, 3.5), "M": (-0.5, 4.0), "T": (4.0, 3.0)},
        (
            Body("ground", ("O", "A", "S", "M"), ground=True),
            Body(
                "boom",
                ("O", "T"),
                mass=50.0 if mass else None,
                inertia=40.0 if mass else None,
                center_of_mass=(2.0, 1.5) if mass else None,
            ),
        ),  # fmt: skip
        ropes=(rope,),
        gravity=Gravity() if mass else None,
    )


def signed(radii: tuple[float, ...] = RADII) -> list[float]:
    return [0.0, *(-r for r in radii), 0.0]  # every wrap clockwise


def test_the_length_at_three_orders_against_mpmath() -> None:
    """Along the solved motion the rope's length, by the tangents constructed in 40-digit
    arithmetic over every visit of the blocks, is the winch's payout θ·R/i, and its first and
    second derivatives along the solved velocity and acceleration are θ̇·R/i and θ̈·R/i."""
    mech = Mechanism(luffing(mass=False))
    assert mech.plan.has_newton
    theta = mech.plan.input_sketch[0] + np.linspace(-60.0, 60.0, 7)
    w, e = 4.0, -1.5
    res = mech.solve({"luff": theta}, {"luff": w}, {"luff": e})
    assert res.status.all_ok
    names = mech.plan.points
    x, v, a = res.positions, res.velocities, res.accelerations
    ms = [mp.mpf(s) for s in signed()]
    for i in range(len(theta)):

        def length(t, i=i):  # type: ignore[no-untyped-def]
            pts = []
            for p in PATH:
                k = names.index(p)
                pts.append(tuple(
                    mp.mpf(float(x[i, k, c])) + t * float(v[i, k, c])
                    + t * t / 2 * float(a[i, k, c]) for c in (0, 1)
                ))  # fmt: skip
            return mp_length(pts, ms)

        ratio = 0.25 / 20.0
        assert float(length(0)) == pytest.approx(theta[i] * ratio, rel=1e-13)
        assert float(mp.diff(length, 0)) == pytest.approx(w * ratio, rel=1e-13)
        assert float(mp.diff(length, 0, 2)) == pytest.approx(e * ratio, rel=1e-12)


def test_tension_and_the_tip_blocks_pin_by_hand() -> None:
    """A weight W at the tip: about O, T·Σ cross(T, u_k − u_{k−1}) over the tip block's two
    sheaves = W·x_T, each direction by mpmath's tangents; the tip block's pin carries the sum
    of its sheaves' resultants."""
    mech = Mechanism(luffing(mass=False))
    theta = mech.plan.input_sketch[0] + np.linspace(-40.0, 40.0, 5)
    kin = mech.solve({"luff": theta})
    f = mech.forces(kin, [PointForce("w", "boom", "T", (0.0, -1000.0))])
    t = f.tension("luff")
    k_tip = mech.plan.points.index("T")
    ms = [mp.mpf(s) for s in signed()]
    fixed = {"A": (-2.0, 0.3), "S": (-1.5, 3.5), "M": (-0.5, 4.0)}
    for i in range(len(theta)):
        tx, ty = (mp.mpf(float(c)) for c in kin.positions[i, k_tip])
        pts = [(tx, ty) if p == "T" else tuple(mp.mpf(c) for c in fixed[p]) for p in PATH]
        alphas = [tangent(pts[k], ms[k], pts[k + 1], ms[k + 1]) for k in range(len(PATH) - 1)]
        fx = fy = mp.mpf(0)
        for k, p in enumerate(PATH):
            if p == "T":  # the rope pulls the sheave along its leaving and arriving segments
                fx += mp.cos(alphas[k]) - mp.cos(alphas[k - 1])
                fy += mp.sin(alphas[k]) - mp.sin(alphas[k - 1])
        hand = 1000 * tx / (tx * fy - ty * fx)
        assert float(t[i]) == pytest.approx(float(hand), rel=1e-12)
        np.testing.assert_allclose(
            f.pin("T", "boom")[i], (float(t[i] * fx), float(t[i] * fy)), rtol=1e-11, atol=1e-9
        )
    # four parts hold the tip: the rope's tension is near a quarter of what one part would need
    assert 0.2 < float(t[2] / (f.pin("T", "boom")[2] @ f.pin("T", "boom")[2]) ** 0.5) < 0.3


def test_power_balances_with_inertia_gravity_and_a_load() -> None:
    mech = Mechanism(luffing())
    theta = mech.plan.input_sketch[0] + np.linspace(-80.0, 80.0, 17)
    res = mech.solve(
        {"luff": theta}, {"luff": -25.0}, {"luff": 9.0},
        loads=[*mech.loads, PointForce("hook", "boom", "T", (0.0, -800.0))],
    )  # fmt: skip
    assert res.ok.all()
    assert np.max(res.power_balance().relative) < 1e-9


@pytest.mark.parametrize("name", ["luff.radius.M", "luff.radius.T", "T.x", "M.y", "boom.mass"])
def test_sensitivities_against_8th_order_differences(name: str) -> None:
    """A block's sheave radius moves every sheave of the block (each visit of its point)."""
    mech = Mechanism(luffing())
    assert (mech.parameters["luff.radius.M"], mech.parameters["luff.radius.T"]) == (0.15, 0.12)
    values = {"luff": mech.plan.input_sketch[0] + np.linspace(-50.0, 50.0, 4)}
    rates = {"luff": 2.0}
    res = mech.solve(values, rates=rates, sensitivities=[name], loads="model")
    table = res.to_frame()
    step = 1e-3 if ".radius." in name else 3e-4 * (
        mech.parameters[name] if name.endswith(".mass") else mech.plan.scale
    )  # fmt: skip
    tables = []
    for k in range(-4, 5):
        moved = {name: mech.parameters[name] + k * step}
        tables.append(mech.solve(values, rates=rates, params=moved, loads="model").to_frame())
    for col in ("luff.tension", "luff.torque", "T.boom.Fx", "O.boom.Fy", "T.x", "T.vy", "T.ay"):
        fd = sum(w * t[col].to_numpy() for w, t in zip(WEIGHTS, tables, strict=True)) / step
        exact = res.sensitivity(col, name)
        floor = 1e-3 * max(np.abs(table[col].to_numpy()).max(), 1e-3) / mech.plan.scale
        scale = max(np.abs(fd).max(), floor)
        assert np.abs(exact - fd).max() / scale < 1e-8, (col, name)


def test_a_block_radius_in_a_family_equals_each_design_as_its_own_model() -> None:
    mech = Mechanism(luffing())
    q = mech.plan.input_sketch[0] + np.array([-30.0, 10.0, 40.0])
    radii = np.array([0.15, 0.12, 0.18])
    family = mech.solve({"luff": q}, params={"luff.radius.M": radii}, loads="model")
    for k, r in enumerate(radii):
        own = (0.2, float(r), 0.12, float(r), 0.12)
        alone = Mechanism(luffing(own)).solve({"luff": q[k : k + 1]}, loads="model")
        np.testing.assert_allclose(family.kinematics.positions[k], alone.kinematics.positions[0],
                                   rtol=0, atol=1e-12)  # fmt: skip
        assert family.tension("luff")[k] == pytest.approx(alone.tension("luff")[0], rel=1e-11)


#: the published four-part block (tests/reference/test_rope_examples.py, 1), reeved over its
#: sheaves: from the ceiling D down round a pulley on the load L, up round the ceiling's pulley
#: C, down round the load's second pulley, up to the motor's sheave (the winch, at W); each
#: pulley of radius r, coaxial in pairs, so every part hangs plumb
FOUR_PARTS = """
schema_version = 1
name = "four-part block over its sheaves"
[units]
length = "m"
[points]
C = [0.0, 3.0]
D = [-0.05, 3.0]
W = [0.05, 3.0]
G1 = [0.0, 0.0]
G2 = [0.5, 0.0]
H1 = [0.0, 4.0]
H2 = [0.5, 4.0]
L = [0.0, 1.0]
L2 = [0.5, 0.5]
[bodies]
ceiling = { points = ["C", "D", "W", "G1", "G2", "H1", "H2"], ground = true }
load = { points = ["L", "L2"] }
[sliders.left]
point = "L"
along = ["G1", "H1"]
[sliders.right]
point = "L2"
along = ["G2", "H2"]
[ropes.hoist]
path = ["D", "L", "C", "L", "W"]
radii = ["50 mm", "50 mm", "50 mm"]
wraps = ["ccw", "ccw", "ccw"]
mode = "winch"
drum_radius = "45 mm"
"""


def test_the_published_four_part_block_reeved_over_its_sheaves() -> None:
    """Printed: the 90 mm sheave at 47 rev/min brings in 0.2215 m/s of rope and the load rises
    at 0.0554 m/s; and a load W hangs on four parts, each pulling W/4 (the line pull)."""
    mech = Mechanism(loads_model(FOUR_PARTS, "four.toml"))
    omega = to_si("47 rpm", "angular_velocity")
    q = mech.plan.input_sketch[0] + np.array([0.0, -20.0, -40.0])
    res = mech.solve({"hoist": q}, {"hoist": -np.full(3, omega)},
                     loads=[PointForce("load", "load", "L", (0.0, -1000.0))])  # fmt: skip
    assert res.ok.all()
    v_load = res.kinematics.point("L")[1][:, 1]
    rope = omega * 0.045
    assert f"{rope:.4f}" == "0.2215" and f"{v_load[0]:.4f}" == "0.0554"
    np.testing.assert_allclose(v_load, rope / 4, rtol=1e-13)
    np.testing.assert_allclose(res.tension("hoist"), 250.0, rtol=1e-12)
    # the ceiling's pulley is pulled down by its two parts
    np.testing.assert_allclose(res.pin("C", "ceiling"), [[0.0, -500.0]] * 3, atol=1e-9)
    assert np.max(res.power_balance().relative) < 1e-9


def test_a_blocks_sheaves_of_two_radii_are_refused_by_name() -> None:
    text = FOUR_PARTS.replace('radii = ["50 mm", "50 mm", "50 mm"]',
                              'radii = ["50 mm", "50 mm", "60 mm"]')  # fmt: skip
    with pytest.raises(ModelError, match="sheave L: the rope runs over it again with radius"):
        loads_model(text, "four.toml")
    with pytest.raises(ModelError, match="visits its two blocks in turn"):
        loads_model(FOUR_PARTS.replace('mode = "winch"', 'parts = 2\nmode = "winch"'), "f")


def test_a_blocks_radius_is_written_back_to_each_of_its_sheaves(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from excavkin.io.model_write import model_text_with

    path = tmp_path / "four.toml"
    path.write_text(FOUR_PARTS)
    text = model_text_with(path, {"hoist.radius.L": 0.06})
    model = loads_model(text, "four.toml")
    assert model.ropes[0].radii == pytest.approx((0.06, 0.05, 0.06), rel=1e-15)
