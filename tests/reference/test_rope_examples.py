"""Published rope and pulley-block examples, reproduced to their printed digits by solved models
(ideal sheaves: no friction, no rope stiffness).

1. A four-part block driven by a sheave (physics Q&A, jiskha.com/display.cgi?id=1342355182):
   "The rope begins at the ceiling, goes down round a pulley on the load, up to a pulley on the
   ceiling, back down around a second pulley on the load, and up to a sheave (a motor driven
   pulley) on the ceiling ... The sheave has diameter 90 mm and angular [speed] 47 rev per
   min. What is the speed with which the load is being raised?" Printed: the sheave brings in
   rope at 0.2215 m/s; four strands, so the load rises at 0.0554 m/s.
2. The Crosby Group, General Catalog, "Example B — The Reeving of Tackle Blocks": "Hoisting
   system lifting 1,000 lb. using a traveling block ... two (2) parts of load line support the
   1,000 lbs weight ... Line Pull = 1,000 lbs. ÷ 2.00 = 500 lbs. ... total load on traveling
   block C = 500 lbs. x 2.0 = 1,000 lbs."
3. A boom held by a cable (mechanics Q&A, expertsmind.com question 30118576): "The 12 m boom AB
   weighs 1 kN, the distance of [its] centre of gravity G is 6 m from A ... determine the
   tension T in [the] cable": ΣM_A = 0, T·sin 15°·12 − 2.5·12·cos 30° − 1·6·cos 30° = 0,
   printed T = 10.0382 kN (the boom at 30° to the horizontal, the cable at 15° to the boom at
   B, 2.5 kN hanging at B).
4. An open belt over two pulleys (Q&A, sarthaks.com question 509872): "Find the length of belt
   necessary to drive a pulley of 500 mm diameter running parallel at a distance of 12 m from
   the driving pulley of diameter 1600 m[m] ... (i) Length of the belt if it is open ...
   L = 27.32 m". A rope over two sheaves from a point of its straight span round both and back
   to that point is the belt.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from excavkin import Mechanism, PointForce
from excavkin.io.toml_model import loads_model
from excavkin.units import to_si

#: a load block hanging from a ceiling block, kept upright by two vertical guides
BLOCKS = """
schema_version = 1
name = "hoist block"
[units]
length = "m"
[points]
C = [0.0, 3.0]      # the ceiling block
G1 = [0.0, 0.0]     # guides of the load block
G2 = [0.5, 0.0]
H1 = [0.0, 4.0]
H2 = [0.5, 4.0]
L = [0.0, 1.0]      # the load block
L2 = [0.5, 0.5]
[bodies]
ceiling = { points = ["C", "G1", "G2", "H1", "H2"], ground = true }
load = { points = ["L", "L2"] }
[sliders.left]
point = "L"
along = ["G1", "H1"]
[sliders.right]
point = "L2"
along = ["G2", "H2"]
[ropes.hoist]
path = ["C", "L"]
mode = "winch"
"""


def hoist(parts: int, drum: str, ratio: float = 1.0) -> Mechanism:
    text = BLOCKS + f'parts = {parts}\ndrum_radius = "{drum}"\ngear_ratio = {ratio}\n'
    return Mechanism(loads_model(text, "hoist.toml"))


def test_four_part_block_raises_the_load_at_a_quarter_of_the_rope_speed() -> None:
    mech = hoist(4, "45 mm")  # diameter 90 mm
    omega = to_si("47 rpm", "angular_velocity")
    # hauling in: the motor turns the way that shortens the rope
    res = mech.solve({"hoist": mech.plan.input_sketch[0]}, {"hoist": -omega})
    assert res.status.all_ok
    v_load = float(res.point("L")[1][0, 1])
    rope = 4 * v_load  # the rope the sheave brings in: every part shortens alike
    assert f"{rope:.4f}" == "0.2215"
    assert f"{v_load:.4f}" == "0.0554"
    assert v_load == pytest.approx(omega * 0.045 / 4, rel=1e-15)


def test_two_part_traveling_block_line_pull() -> None:
    mech = hoist(2, "0.3 m", ratio=25.0)
    res = mech.solve(
        {"hoist": mech.plan.input_sketch[0]},
        loads=[PointForce("load", "load", "L", ("0 lbf", "-1000 lbf"))],
    )
    assert res.ok.all()
    lbf = to_si("1 lbf", "force")
    pull = float(res.tension("hoist")[0]) / lbf
    assert f"{pull:,.0f}" == "500"
    # the load on the traveling block: its two parts' pull, 500 lbs x 2.0
    block = -float(res.force("hoist")[0]) / lbf
    assert f"{block:,.0f}" == "1,000"
    assert pull == pytest.approx(500.0, rel=1e-13) and block == pytest.approx(1000.0, rel=1e-13)
    # and the winch holds it with the line pull times the drum radius over its gear ratio
    torque = float(res.winch_torque("hoist")[0])
    assert torque == pytest.approx(-500.0 * lbf * 0.3 / 25.0, rel=1e-13)


def test_boom_cable_tension() -> None:
    c30, s30 = math.cos(math.radians(30.0)), math.sin(math.radians(30.0))
    d = math.radians(195.0)  # the cable from B, 15° off the boom's line back towards the ground
    b = (12.0 * c30, 12.0 * s30)
    anchor = (b[0] + 20.0 * math.cos(d), b[1] + 20.0 * math.sin(d))
    text = f"""
schema_version = 1
name = "boom and cable"
[units]
length = "m"
[points]
A = [0.0, 0.0]
B = [{b[0]!r}, {b[1]!r}]
G = [{6.0 * c30!r}, {6.0 * s30!r}]
K = [{anchor[0]!r}, {anchor[1]!r}]
[bodies]
ground = {{ points = ["A", "K"], ground = true }}
boom = {{ points = ["A", "B", "G"] }}
[ropes.cable]
path = ["K", "B"]
mode = "winch"
drum_radius = "0.2 m"
"""
    mech = Mechanism(loads_model(text, "boom.toml"))
    res = mech.solve(
        {"cable": mech.plan.input_sketch[0]},
        loads=[
            PointForce("hook", "boom", "B", ("0 kN", "-2.5 kN")),
            PointForce("weight", "boom", "G", ("0 kN", "-1 kN")),
        ],
    )
    assert res.ok.all()
    np.testing.assert_allclose(res.kinematics.positions[0, 1], b, rtol=0, atol=1e-12)
    tension = float(res.tension("cable")[0]) / 1e3
    assert f"{tension:.4f}" == "10.0382"
    hand = (2.5 * 12.0 + 1.0 * 6.0) * c30 / (12.0 * math.sin(math.radians(15.0)))
    assert tension == pytest.approx(hand, rel=1e-12)


def test_open_belt_length() -> None:
    """The belt as a rope over sheaves: from the middle E of its upper span, clockwise round
    the driven pulley (r = 0.25 m, 12 m off), clockwise round the driver (r = 0.8 m), back to
    E. A winch of R/i = 1 m/rad on a carriage at the driven pulley's centre: its sketch angle
    is the belt's length."""
    r1, r2, x = 0.8, 0.25, 12.0
    phi = math.acos((r1 - r2) / x)  # the spans' normal: n·(c2 − c1) = r1 − r2
    e = ((r1 + r2) * math.cos(phi) / 2 + x / 2, (r1 + r2) * math.sin(phi) / 2)
    text = f"""
schema_version = 1
name = "open belt"
[units]
length = "m"
[points]
E = [{e[0]!r}, {e[1]!r}]
S1 = [0.0, 0.0]
G1 = [11.0, 0.0]
G2 = [13.0, 0.0]
G3 = [11.0, -1.0]
G4 = [13.0, -1.0]
S2 = [12.0, 0.0]
C2 = [12.5, -1.0]
[bodies]
ground = {{ points = ["S1", "E", "G1", "G2", "G3", "G4"], ground = true }}
carriage = {{ points = ["S2", "C2"] }}
[sliders.upper]
point = "S2"
along = ["G1", "G2"]
[sliders.lower]
point = "C2"
along = ["G3", "G4"]
[ropes.belt]
path = ["E", "S2", "S1", "E"]
radii = ["250 mm", "800 mm"]
wraps = ["cw", "cw"]
mode = "winch"
drum_radius = "1 m"
"""
    mech = Mechanism(loads_model(text, "belt.toml"))
    length = mech.sketch_values()["belt"] * 1.0
    assert f"{length:.2f}" == "27.32"
    exact = (
        2 * math.sqrt(x * x - (r1 - r2) ** 2)
        + math.pi * (r1 + r2)
        + 2 * (r1 - r2) * math.asin((r1 - r2) / x)
    )
    assert length == pytest.approx(exact, rel=1e-14)
    res = mech.solve({"belt": length})  # and the carriage stays where the belt holds it
    np.testing.assert_allclose(res.positions[0, 6], (12.0, 0.0), atol=1e-10)
