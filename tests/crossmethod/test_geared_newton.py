"""The generic solver with gears, racks and cams (issue 26): ``method="newton"`` places the
bodies of the higher pairs in closed form — their angles and travels are linear in the inputs
(`excavkin.model.gears`) — and everything else in one Newton group, so a model with a gear
train can be cross-checked: a gear pair whose wheel drives a four-bar, and a rack on a
turning arm that pushes a link, solved both ways at three orders, forces and their power
balance, and the sensitivities of the Newton plan against 8th-order differences."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import excavkin
from excavkin.io.toml_model import loads_model
from excavkin.step_kinds import GearStep, NewtonGroup, RackStep

ROOT = Path(__file__).resolve().parents[2]
PAIR = (ROOT / "tests" / "unit" / "test_gears.py").read_text()

#: the gear pair of tests/unit/test_gears.py, its wheel's pin C driving a rocker E–D by a
#: coupler C–D
GEARED_FOURBAR = """
schema_version = 1
name = "gear pair driving a four-bar"
[units]
length = "mm"
[points]
O1 = [0, 0]
O2 = [300, 0]
A = [0, 100]
B = [300, 200]
C = [250, 60]
D = [520, 260]
E = [560, 20]
[bodies]
frame = { points = ["O1", "O2", "E"], ground = true }
pinion = { points = ["O1", "A"], mass = "1 kg", inertia = "0.01 kg*m^2", center_of_mass = [5, 3] }
wheel = { points = ["O2", "B", "C"], mass = "2 kg", inertia = "0.05 kg*m^2", \
center_of_mass = [320, 10] }
coupler = { points = ["C", "D"], mass = "0.8 kg", inertia = "0.02 kg*m^2" }
rocker = { points = ["E", "D"], mass = "0.6 kg", inertia = "0.01 kg*m^2" }
[drivers.motor]
type = "rotary"
body = "pinion"
pivot = "O1"
[gears.mesh]
gears = ["pinion", "wheel"]
radii = [100, 200]
pressure_angle = "25 deg"
[loads.brake]
type = "torque"
body = "rocker"
value = "10 N*m"
[gravity]
"""

#: the rack on a turning arm of tests/reference/data/rack_on_arm.toml, the rack's end R2
#: pushing a link K–R3 pinned to the frame at K
RACK = (ROOT / "tests" / "reference" / "data" / "rack_on_arm.toml").read_text()
RACK_LINK = (
    RACK.replace("R2 = [700, -60]", "R2 = [700, -60]\nR3 = [850, -350]\nK = [1100, -300]")
    .replace('frame = { points = ["O", "F"]', 'frame = { points = ["O", "F", "K"]')
    .replace(
        "[drivers.swing]",
        'link = { points = ["R2", "R3"], mass = "1 kg", inertia = "0.01 kg*m^2" }\n'
        'lever = { points = ["K", "R3"], mass = "1 kg", inertia = "0.02 kg*m^2" }\n'
        "[drivers.swing]",
    )
)

CASES = {"geared four-bar": GEARED_FOURBAR, "rack pushing a link": RACK_LINK}


def both(case: str) -> tuple[excavkin.Mechanism, excavkin.Mechanism]:
    text = CASES[case]
    closed = excavkin.Mechanism(loads_model(text, "m.toml"))
    newton = excavkin.Mechanism(loads_model(text, "m.toml"), method="newton")
    return closed, newton


def sweep(mech: excavkin.Mechanism, n: int) -> tuple[dict, dict, dict]:
    t = np.linspace(0.0, 1.0, n)
    span = 0.6 if "motor" in mech.sketch_values() and "swing" not in mech.sketch_values() else 0.1
    q = {
        k: v + span * np.sin(2 * np.pi * t + j)
        for j, (k, v) in enumerate(mech.sketch_values().items())
    }
    qd = {k: 1.5 * np.cos(3 * t + j) for j, k in enumerate(q)}
    qdd = {k: -2.0 * np.sin(5 * t + j) for j, k in enumerate(q)}
    return q, qd, qdd


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_newton_plan_holds_the_meshes_in_closed_form_and_solves_the_rest(case: str) -> None:
    closed, newton = both(case)
    kinds = {type(st) for st in newton.plan.steps}
    assert NewtonGroup in kinds and (GearStep in kinds or RackStep in kinds)
    assert NewtonGroup not in {type(st) for st in closed.plan.steps}
    q, qd, qdd = sweep(closed, 41)
    a = closed.solve(q, qd, qdd, loads="model")
    b = newton.solve(q, qd, qdd, loads="model")
    assert a.ok.all() and b.ok.all()
    scale = closed.plan.scale
    for field in ("positions", "velocities", "accelerations"):
        x, y = getattr(b.kinematics, field), getattr(a.kinematics, field)
        assert np.abs(x - y).max() <= 1e-11 * max(np.abs(y).max(), scale), field
    for field in ("pin_force", "driver_torque"):
        x, y = getattr(b, field), getattr(a, field)
        assert np.abs(x - y).max() <= 1e-9 * np.abs(y).max(), field
    assert np.max(b.power_balance().relative) < 1e-9


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_newton_plans_sensitivities_equal_8th_order_differences(case: str) -> None:
    sys.path.insert(0, str(ROOT / "tests" / "property"))
    from test_sensitivities import differences

    _, mech = both(case)
    q, _, _ = sweep(mech, 4)
    rates = {k: 0.07 for k in q}
    names = (
        ["D.x", "E.y", "coupler.mass"] if "four-bar" in case else ["R3.x", "K.y", "crowd.radius"]
    )
    res = mech.solve(q, rates=rates, sensitivities=names, loads="model")
    table = res.to_frame()
    forces = [c for c in table.columns if c.endswith((".Fx", ".Fy", ".torque", ".tooth"))]
    force_scale = max(np.abs(table[c].to_numpy()).max() for c in forces)
    for name in names:
        size = abs(mech.parameters[name])
        step = (
            1e-3
            if name.endswith(".radius")
            else 3e-4 * (size if name.endswith(".mass") else mech.plan.scale)
        )
        for col, ref in differences(mech, q, rates, {}, name, step).items():
            exact = res.sensitivity(col, name)
            own = force_scale if col in forces or col.endswith((".Rx", ".Ry", ".guide")) else 0
            least = 1.0 if col.endswith(".angle") else 1e-3  # an angle near 0 is not small
            floor = 1e-3 * max(np.abs(table[col].to_numpy()).max(), own, least) / mech.plan.scale
            scale = max(np.abs(ref).max(), floor)
            assert np.abs(exact - ref).max() / scale < 1e-8, (name, col)
