"""A dig's available force and geometry against independent routes.

* the directed force of the cylinders equals the ISO 6015 tool force where the two coincide
  (only the working cylinder moves, the load along its own motion);
* at the directed force, the general kinetostatics with that soil load and gravity gives the
  same cylinder forces, and the limiting cylinder sits at its pressure limit;
* the motion direction against central differences of the lip's positions along the path;
* the resistance, the margin and the stall point against the models and the caps evaluated
  point by point.
"""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from excavkin.errors import InputError
from excavkin.excavator.dig import default_dig, dig, dig_path
from excavkin.excavator.forces import directed_force, tool_forces
from excavkin.excavator.machine import ROLES, Machine
from excavkin.excavator.machine_file import load_machine
from excavkin.excavator.soil import SOILS, Tool, resistance
from excavkin.excavator.stability import stability
from excavkin.kinetostatics import Gravity, PointForce
from tests.crossmethod.test_excavator_forces import _cylinder_weights


@pytest.fixture(scope="module")
def machine() -> Machine:
    return load_machine(excavkin.example_path("excavator_machine"))


@pytest.mark.parametrize("working", ["arm", "bucket"])
def test_directed_force_is_the_tool_force_of_one_cylinder(machine: Machine, working: str) -> None:
    rng = np.random.default_rng(11)
    lo, hi = machine.lengths_min + 0.02, machine.lengths_max - 0.02
    L = lo + rng.random((30, 3)) * (hi - lo)
    tf = tool_forces(machine, L, working, gravity=True)  # type: ignore[arg-type]
    w = ROLES.index(working)
    rates = np.zeros_like(L)
    rates[:, w] = 1.0 if machine.cylinders[w].dig == "extend" else -1.0
    df = directed_force(machine, L, tf.direction, rates)
    np.testing.assert_allclose(df.force, tf.force, rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(df.limiting, tf.limiting)
    np.testing.assert_allclose(df.cylinder_force, tf.cylinder_force, rtol=1e-12, atol=1e-6)


def test_directed_force_against_the_kinetostatics(machine: Machine) -> None:
    rng = np.random.default_rng(5)
    lo, hi = machine.lengths_min + 0.05, machine.lengths_max - 0.05
    L = lo + rng.random((12, 3)) * (hi - lo)
    ang = rng.uniform(0, 2 * np.pi, 12)
    e = np.column_stack([np.cos(ang), np.sin(ang)])
    rates = rng.normal(size=(12, 3))
    df = directed_force(machine, L, e, rates)
    good = np.isfinite(df.force) & (df.force > 0)
    assert good.sum() >= 8
    drivers = machine.drivers
    res = machine.mechanism.solve(
        {d: L[good, i] for i, d in enumerate(drivers)},
        {d: np.zeros(good.sum()) for d in drivers},
        loads=[
            PointForce(
                "soil", machine.front.bucket, machine.front.lip, -df.force[good, None] * e[good]
            ),
            Gravity(machine.gravity),
            *_cylinder_weights(machine),
        ],
    )
    for c in range(3):
        np.testing.assert_allclose(
            res.force(drivers[c]), df.cylinder_force[good, c], rtol=1e-8, atol=1e-3
        )
    # the limiting cylinder is at its limit: working pressure if it drives, else its relief
    for k in np.flatnonzero(good):
        c = ROLES.index(str(df.limiting[k]))
        cyl = machine.cylinders[c]
        circ = machine.circuits[cyl.circuit]
        p = circ.working if df.driving[k, c] else circ.relief
        pull, push = cyl.force_limits(p)
        f = df.cylinder_force[k, c]
        assert np.isclose(f, push, rtol=1e-9) or np.isclose(f, pull, rtol=1e-9)


def test_dig_geometry_and_margin_point_by_point(machine: Machine) -> None:
    L = default_dig(machine, 201, depth=0.45)
    s, tool = SOILS["clay"], Tool(1.1)
    d = dig(machine, L, s, tool, "balovnev")
    # the start is on the ground line and the deepest point 0.45 m below it
    assert abs(d.depth[0]) < 2e-3 and abs(d.depth[-1]) < 2e-3
    assert abs(np.max(d.depth) - 0.45) < 5e-3
    # the motion direction: central differences of the lip along the path
    v = np.gradient(d.point, axis=0)
    t = v / np.hypot(v[:, 0], v[:, 1])[:, None]
    np.testing.assert_allclose(d.direction[1:-1], t[1:-1], atol=2e-4)
    # the resistance is the model's at the path's depth and cutting angle
    r = resistance("balovnev", d.depth, d.rake, s, tool)
    np.testing.assert_allclose(d.resistance.along, r.along, rtol=1e-14)
    R = r.along[:, None] * d.direction
    n = np.column_stack([-d.direction[:, 1], d.direction[:, 0]])
    n *= np.sign(n[:, 1])[:, None]
    R += r.normal[:, None] * n
    np.testing.assert_allclose(d.required, np.hypot(R[:, 0], R[:, 1]), rtol=1e-12)
    # available: the least of the cylinders' cap and the base's along R
    df = directed_force(machine, L, d.load, np.gradient(L, axis=0))
    st = stability(machine, L, machine.front.lip, -d.load)
    cap = np.minimum(df.force, np.minimum(st.tipping_load, st.slipping_load))
    np.testing.assert_allclose(d.available, cap, rtol=1e-12)
    np.testing.assert_allclose(d.margin, d.available - d.required, rtol=1e-12)
    inside = d.depth > 0
    stalls = np.flatnonzero(inside & (d.margin < 0))
    assert d.stall == (stalls[0] if len(stalls) else -1)


def test_a_tangential_crowd_has_the_arm_tool_force_available(
    machine: Machine,
) -> None:
    """Zelenin's resistance with no normal part along an arm-only crowd: the load is along the
    arm's own motion and the available force is the ISO 6015 arm tool force, where neither
    tipping nor slipping caps it first."""
    lo, hi = machine.lengths_min, machine.lengths_max
    mid = 0.5 * (lo + hi)
    L = dig_path(machine, [mid[0] - 0.25, lo[1], mid[2]], [mid[0] - 0.25, hi[1], mid[2]], 61)
    d = dig(machine, L, SOILS["heavy_clay"], Tool(1.2), "zelenin")
    tf = tool_forces(machine, L, "arm")
    inside = d.depth > 0
    assert inside.sum() > 10
    np.testing.assert_allclose(d.load[inside], tf.direction[inside], atol=1e-12)
    hydraulic = np.char.find(d.limiting.astype(str), "ing") < 0  # neither tipping nor slipping
    assert hydraulic.sum() > 5
    np.testing.assert_allclose(d.available[hydraulic], tf.force[hydraulic], rtol=1e-12)


def test_bad_digs_are_refused(machine: Machine) -> None:
    lo, hi = machine.lengths_min, machine.lengths_max
    with pytest.raises(InputError, match="strokes at sample"):
        dig_path(machine, lo - 0.1, hi, 11)
    with pytest.raises(InputError, match="at least 3"):
        dig_path(machine, lo, hi, 2)
    with pytest.raises(InputError, match="unknown motion law"):
        dig_path(machine, lo, hi, 11, law="sinusoid")
    with pytest.raises(InputError, match="depth"):
        default_dig(machine, 11, depth=-0.2)
    with pytest.raises(InputError, match="swing"):
        dig(machine, default_dig(machine, 11), SOILS["sand"], Tool(1.0), swing="rear")


@pytest.mark.parametrize("samples", [3, 5, 41])
def test_the_default_dig_reaches_its_depth_whatever_the_samples(
    machine: Machine, samples: int
) -> None:
    """The default dig's straight path in cylinder space, followed densely, goes 0.5 m below
    the ground line at its deepest (to the boom-end search's interpolation, 0.1 mm), however
    few points the dig is sampled at."""
    from excavkin.excavator.machine import forward

    L = default_dig(machine, samples, depth=0.5)
    u = np.linspace(0.0, 1.0, 4001)[:, None]
    lip = forward(machine, L[0] + u * (L[-1] - L[0])).lip
    deepest = machine.ground_line - np.nanmin(lip[:, 1])
    assert deepest == pytest.approx(0.5, abs=1e-4)
