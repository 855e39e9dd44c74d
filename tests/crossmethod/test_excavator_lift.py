"""Lift capacity (ISO 10567) against independent routes.

* each posture against the forward kinematics (the load point where the table says, the bucket
  curled, the strokes kept);
* each cell's hydraulic capacity against the general kinetostatics: the load hung at the load
  point with the front's weights (``Mechanism.solve(..., loads=...)``) must put the named
  cylinder exactly at its limit and keep the others within theirs;
* each cell's tipping load against the hand equilibrium of the whole machine
  (``test_excavator_stability.hand_tipping``);
* the rating: the lesser of 75 % of the tipping load and 87 % of the hydraulic capacity.
"""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from excavkin.excavator.lift import (
    HYDRAULIC_FACTOR,
    TIPPING_FACTOR,
    LiftTable,
    curl_length,
    cylinder_limits,
    hydraulic_lift,
    lift_capacity,
    lift_poses,
    lift_table,
)
from excavkin.excavator.machine import Circuit, Machine, forward
from excavkin.excavator.machine_file import load_machine, loads_machine
from excavkin.kinetostatics import Gravity, PointForce
from tests.conftest import EXAMPLES
from tests.crossmethod.test_excavator_stability import _moving_cylinder_halves, hand_tipping

G = 9.80665


@pytest.fixture(scope="module")
def machine() -> Machine:
    return load_machine(excavkin.example_path("excavator_machine"))


@pytest.fixture(scope="module")
def table(machine: Machine) -> LiftTable:
    return lift_table(machine)


def test_postures_reach_the_cells(machine: Machine, table: LiftTable) -> None:
    ok = table.reachable.ravel()
    assert ok.sum() >= 20
    L = table.lengths.reshape(-1, 3)[ok]
    pose = forward(machine, L)
    assert pose.ok.all() and pose.within_stroke.all()
    q = pose.result.point("Q")[0]
    rr, hh = np.meshgrid(table.radii, table.heights)
    np.testing.assert_allclose(q[:, 0], rr.ravel()[ok], rtol=0, atol=1e-12)
    np.testing.assert_allclose(q[:, 1], hh.ravel()[ok], rtol=0, atol=1e-12)
    np.testing.assert_allclose(L[:, 2], curl_length(machine), rtol=0, atol=1e-9)
    # the stick pivot above the line boom foot → load point
    a, f = pose.result.point("A")[0], pose.result.point("F")[0]
    cross = (q[:, 0] - a[:, 0]) * (f[:, 1] - a[:, 1]) - (q[:, 1] - a[:, 1]) * (f[:, 0] - a[:, 0])
    assert np.all(cross > 0)
    # an unreachable cell lies beyond the row's largest reach, or well away from every load
    # point of a fine scan of the boom and arm strokes with the bucket curled
    lo, hi = machine.lengths_min, machine.lengths_max
    b, s = np.meshgrid(np.linspace(lo[0], hi[0], 401), np.linspace(lo[1], hi[1], 401))
    scan = forward(machine, np.column_stack([b.ravel(), s.ravel(), np.full(b.size, L[0, 2])]))
    reach = scan.result.point("Q")[0][scan.ok]
    beyond = rr > table.max_reach[:, None]
    for x, y in zip(rr[~table.reachable & ~beyond], hh[~table.reachable & ~beyond], strict=True):
        assert np.min(np.hypot(reach[:, 0] - x, reach[:, 1] - y)) > 0.05  # ~3 cm apart


def test_hydraulic_capacity_is_the_kinetostatic_limit(machine: Machine, table: LiftTable) -> None:
    ok = table.reachable.ravel()
    L = table.lengths.reshape(-1, 3)[ok]
    hyd = hydraulic_lift(machine, L)
    np.testing.assert_array_equal(hyd.load, table.capacity.hydraulic.load[ok])
    _check_against_kinetostatics(machine, L, hyd.load, hyd.limiting)
    assert set(hyd.limiting) == {"boom", "arm"}  # the arm holds the deep, close cells
    # the lifting boom cylinder at working pressure on its bore, the others at port relief
    lo, hi = cylinder_limits(machine, "boom", "working")
    boom, arm = machine.cylinders[0], machine.cylinders[1]
    assert hi[0] == pytest.approx(34.3e6 * boom.bore_area, rel=1e-15)
    assert lo[1] == pytest.approx(-39.2e6 * arm.annulus_area, rel=1e-15)
    relief = hydraulic_lift(machine, L, pressure="relief")
    boom_bound = hyd.limiting == "boom"
    np.testing.assert_allclose(
        relief.load[boom_bound] - hyd.load[boom_bound],
        (39.2e6 - 34.3e6) * boom.bore_area / _boom_share(machine, L[boom_bound]),
        rtol=1e-9,
    )


def _boom_share(machine: Machine, L: np.ndarray) -> np.ndarray:
    """∂y_Q/∂L_boom by central differences of the forward kinematics."""
    h = 1e-6
    e = np.array([h, 0.0, 0.0])
    yp = forward(machine, L + e).result.point("Q")[0][:, 1]
    ym = forward(machine, L - e).result.point("Q")[0][:, 1]
    return (yp - ym) / (2 * h)


def _check_against_kinetostatics(
    machine: Machine, L: np.ndarray, load: np.ndarray, limiting: np.ndarray
) -> None:
    drivers = machine.drivers
    body = next(
        b.name
        for b in machine.mechanism.model.bodies
        if machine.lift_point in b.points and not b.ground
    )
    res = machine.mechanism.solve(
        {d: L[:, i] for i, d in enumerate(drivers)},
        {d: np.zeros(len(L)) for d in drivers},
        loads=[
            PointForce("load", body, machine.lift_point, np.column_stack([0 * load, -load])),
            Gravity(G),
            *_moving_cylinder_halves(machine),
        ],
    )
    lo, hi = cylinder_limits(machine, "boom", "working")
    roles = ["boom", "arm", "bucket"]
    for c, d in enumerate(drivers):
        f = res.force(d)
        named = limiting == roles[c]
        at = np.where(f[named] > 0, hi[c], lo[c])
        np.testing.assert_allclose(f[named], at, rtol=1e-9)
        assert np.all(f <= hi[c] * (1 + 1e-9)) and np.all(f >= lo[c] * (1 + 1e-9))


def test_a_weak_arm_relief_limits_and_is_named(machine: Machine, table: LiftTable) -> None:
    weak = dict(machine.circuits)
    weak["arm"] = Circuit("arm", 5e6, 6e6)
    m2 = Machine(
        machine.mechanism,
        machine.front,
        {c.role: c for c in machine.cylinders},
        weak,
        base=machine.base,
    )
    ok = table.reachable.ravel()
    L = table.lengths.reshape(-1, 3)[ok]
    hyd = hydraulic_lift(m2, L)
    assert (hyd.limiting == "arm").sum() >= 0.8 * len(L)
    assert np.all(hyd.load <= table.capacity.hydraulic.load[ok] * (1 + 1e-12))
    _check_against_kinetostatics(m2, L, hyd.load, hyd.limiting)


@pytest.mark.parametrize("over", ["front", "side"])
def test_tipping_and_rating_of_each_cell(machine: Machine, table: LiftTable, over: str) -> None:
    ok = table.reachable.ravel()
    L = table.lengths.reshape(-1, 3)[ok]
    swing = 0.0 if over == "front" else np.pi / 2
    lam, line, _ = hand_tipping(machine, L, "Q", np.array([0.0, -1.0]), swing)
    cap = table.capacity
    np.testing.assert_allclose(cap.tipping[over][ok], lam, rtol=1e-12)
    assert set(line) == {"front" if over == "front" else "left side"}
    h = cap.hydraulic.load[ok]
    rated = np.minimum(TIPPING_FACTOR * lam, HYDRAULIC_FACTOR * h)
    np.testing.assert_allclose(table.rated(over).ravel()[ok], rated, rtol=1e-12)
    star = HYDRAULIC_FACTOR * h < TIPPING_FACTOR * lam
    np.testing.assert_array_equal(table.hydraulic_limited(over).ravel()[ok], star)
    assert star.any() and (~star).any()  # both kinds of cell in the example's table
    assert np.all(np.isnan(table.rated(over).ravel()[~ok]))


def test_max_reach_is_the_edge_of_the_reachable(machine: Machine, table: LiftTable) -> None:
    r = table.max_reach
    assert np.all(np.isfinite(r))
    y = machine.ground_line + table.heights
    _, inside = lift_poses(machine, np.column_stack([r - 1e-5, y]))
    _, outside = lift_poses(machine, np.column_stack([r + 1e-5, y]))
    assert inside.all() and not outside.any()
    at = lift_capacity(machine, table.max_reach_lengths)
    np.testing.assert_array_equal(at.rated["front"], table.at_max_reach.rated["front"])
    # the least capacity of a row is at its largest radius
    for over in ("front", "side"):
        rows = np.where(table.reachable, table.rated(over), np.inf).min(axis=1)
        assert np.all(table.at_max_reach.rated[over] <= rows * (1 + 1e-9))


def test_a_hook_on_the_bucket(machine: Machine) -> None:
    text = (
        (EXAMPLES / "excavator_machine.toml")
        .read_text(encoding="utf-8")
        .replace(
            'model = "excavator.toml"', f'model = "{(EXAMPLES / "excavator.toml").as_posix()}"'
        )
    )
    hook = loads_machine(text + '\n[lift]\npoint = "L"\n', "m.toml")
    target = np.array([[5.0, 1.0], [6.5, -1.0], [4.0, 3.0]])
    L, ok = lift_poses(hook, target)
    assert ok.all()
    pose = forward(hook, L)
    np.testing.assert_allclose(pose.result.point("L")[0], target, rtol=0, atol=1e-12)
    hyd = hydraulic_lift(hook, L)
    _check_against_kinetostatics(hook, L, hyd.load, hyd.limiting)
