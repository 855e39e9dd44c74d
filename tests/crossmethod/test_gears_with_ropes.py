"""A motor-driven gear pair beside a boom that a winch rope hoists (a gear train turns by rotary
drivers only): the meshes' dense block and the rope's tension in one equilibrium, their columns
one after the other. The plan-following solve equals the whole matrix per sample, the compiled
one equals it, and the power balances (the winch's, the motor's, the brake's, gravity's and the
inertia's), for a rope between two blocks (a driven element) and over a sheave (a Newton
group's rope constraint)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin.kinetostatics.solve import solve_forces
from excavkin.kinetostatics.structured import along_plan

MODEL = """
schema_version = 1
name = "a gear pair and a hoisted boom"
[units]
length = "mm"
[points]
P = [0, 0]
O1 = [400, -500]
O2 = [700, -500]
T = [1000, 0]
A = [400, -400]
B = [700, -300]
H = [-300, 800]
S = [300, 1200]
[bodies]
frame = { points = ["P", "H", "S", "O1", "O2"], ground = true }
boom = { points = ["P", "T"], mass = "20 kg", inertia = "2 kg*m^2", \
center_of_mass = [500, 50] }
pinion = { points = ["O1", "A"], mass = "1 kg", inertia = "0.01 kg*m^2", \
center_of_mass = [405, -497] }
wheel = { points = ["O2", "B"], mass = "2 kg", inertia = "0.05 kg*m^2", \
center_of_mass = [710, -490] }
[drivers.motor]
type = "rotary"
body = "pinion"
pivot = "O1"
[gears.mesh]
gears = ["pinion", "wheel"]
radii = [100, 200]
pressure_angle = "20 deg"
[ropes.hoist]
ROPE
mode = "winch"
[loads.brake]
type = "torque"
body = "wheel"
value = "25 N*m"
[gravity]
"""

BETWEEN = 'path = ["H", "T"]\ndrum_radius = "200 mm"\ngear_ratio = 10'
SHEAVE = 'path = ["H", "S", "T"]\nradii = ["50 mm"]\nwraps = ["cw"]\ndrum_radius = "200 mm"'


@pytest.mark.parametrize("rope", [BETWEEN, SHEAVE], ids=["between", "sheave"])
def test_the_winch_balances_the_wheel_and_the_plan_equals_the_matrix(rope: str) -> None:
    mech = excavkin.loads(MODEL.replace("ROPE", rope), "winch_gears.toml")
    mob = mech.plan.mobility  # the motor and the winch; the sheaved rope counts as an element
    assert (mob.mobility, mob.links, mob.gear_pairs) == (2, 6, 1)
    assert mech.inputs == ("motor", "hoist")
    q0 = mech.sketch_values()
    rng = np.random.default_rng(5)
    n = 300
    q = {"motor": rng.uniform(-9, 9, n), "hoist": q0["hoist"] * rng.uniform(0.8, 1.2, n)}
    res = mech.solve(
        q,
        rates={k: rng.uniform(-2, 2, n) for k in q},
        accels={k: rng.uniform(-5, 5, n) for k in q},
    )
    assert res.status.all_ok
    assert along_plan(res.plan, mech.statics) is not None
    loads = mech.model.loads + ((mech.model.gravity,) if mech.model.gravity else ())
    sparse = solve_forces(res, loads, system=mech.statics, backend="numpy")
    dense = solve_forces(res, loads, system=mech.statics, method="dense")
    assert not sparse.singular.any()
    scale = float(np.abs(dense.pin_force).max())
    assert_allclose(sparse.pin_force, dense.pin_force, rtol=0, atol=1e-10 * scale)
    assert_allclose(sparse.gear_force, dense.gear_force, rtol=0, atol=1e-10 * scale)
    assert_allclose(sparse.tension("hoist"), dense.tension("hoist"), rtol=0, atol=1e-10 * scale)
    assert np.abs(sparse.gear_force).min() > 1.0 and np.abs(sparse.tension("hoist")).min() > 1.0
    # the winch's power (its motor's torque times speed), the brake's and gravity's and the
    # inertia's balance: a wrong tooth or rope force would show
    assert np.abs(sparse.power_balance().relative).max() < 1e-9
    # the compiled back-substitution traces the same blocks
    kernel = solve_forces(res, loads, system=mech.statics, backend="numba")
    assert_allclose(kernel.pin_force, sparse.pin_force, rtol=0, atol=1e-12 * scale)
    assert_allclose(kernel.gear_force, sparse.gear_force, rtol=0, atol=1e-12 * scale)
    assert_allclose(kernel.tension("hoist"), sparse.tension("hoist"), rtol=0, atol=1e-12 * scale)


@pytest.mark.parametrize("rope", [BETWEEN, SHEAVE], ids=["between", "sheave"])
def test_sensitivities_of_tooth_and_tension_equal_8th_order_differences(rope: str) -> None:
    sys.path.insert(0, str(Path(__file__).parents[1] / "property"))
    from test_sensitivities import differences

    mech = excavkin.loads(MODEL.replace("ROPE", rope), "winch_gears.toml")
    q0 = mech.sketch_values()
    values = {
        "motor": np.array([0.3, 2.0, -5.0]),
        "hoist": q0["hoist"] * np.array([0.9, 0.97, 1.1]),
    }
    rates = {"motor": 0.4, "hoist": -0.2}
    names = ["O2.x", "T.y", "H.x", "S.y", "wheel.mass", "boom.center_of_mass.x"]
    res = mech.solve(values, rates=rates, sensitivities=names, loads="model")
    table = res.to_frame()
    ends = (".Fx", ".Fy", ".torque", ".tooth", ".tension")
    forces = [c for c in table.columns if c.endswith(ends)]
    assert "mesh.tooth" in forces and "hoist.tension" in forces
    force_scale = max(np.abs(table[c].to_numpy()).max() for c in forces)
    for name in names:
        step = 3e-4 * (20.0 if name.endswith("mass") else mech.plan.scale)
        for col, ref in differences(mech, values, rates, {}, name, step).items():
            exact = res.sensitivity(col, name)
            own = force_scale if col in forces or col.endswith((".Rx", ".Ry")) else 0.0
            # (an absolute floor: the wheel turns at a constant rate, its ε is round-off)
            scale = max(np.abs(ref).max(), 1e-3 * max(np.abs(table[col]).max(), own, 0.1))
            assert np.abs(exact - ref).max() / scale < 1e-8, (name, col)
