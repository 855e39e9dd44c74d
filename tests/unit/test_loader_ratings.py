"""The wheel loader's ratings against independent computations: breakout force (SAE J732 /
ISO 14397-2) by the engine's body-by-body equilibrium and by the equilibrium of the bucket,
bell crank and tilt link written here; static tipping load (SAE J732 / ISO 14397-1), straight
and at full turn, by a whole-machine moment balance written here."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from excavkin.kinetostatics import PointForce, Torque
from excavkin.loader.breakout import BEHIND_EDGE, breakout
from excavkin.loader.capacity import capacity
from excavkin.loader.dimensions import dimensions
from excavkin.loader.machine import Loader, floor_angle
from excavkin.loader.machine_file import load_machine
from excavkin.loader.tipping import ROC_FACTOR, static_tipping, tipping_loads
from tests.conftest import EXAMPLES

MACHINE = EXAMPLES / "wheel_loader_machine.toml"
G0 = 9.80665


@pytest.fixture(scope="module")
def loader() -> Loader:
    return load_machine(MACHINE)


def _variant(tmp_path: Path, *swaps: tuple[str, str]) -> Loader:
    text = MACHINE.read_text(encoding="utf-8")
    for old, new in swaps:
        assert old in text
        text = text.replace(old, new, 1)
    (tmp_path / "wheel_loader.toml").write_text(
        (EXAMPLES / "wheel_loader.toml").read_text(encoding="utf-8"), encoding="utf-8"
    )
    path = tmp_path / "m.toml"
    path.write_text(text, encoding="utf-8")
    return load_machine(path)


def _cross(a: np.ndarray, b: np.ndarray) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _bodies(loader: Loader, pos: np.ndarray) -> dict[str, tuple[float, np.ndarray]]:
    """Each moving body's mass and centre of mass at a pose, moved rigidly from the model's
    sketch by hand (two points of the body fix its motion)."""
    model = loader.mechanism.model
    sketch = {k: np.array(v, dtype=float) for k, v in model.points.items()}
    out = {}
    for b in model.bodies:
        if b.ground or not b.mass:
            continue
        p0, p1 = b.points[0], b.points[1]
        a0, a1 = sketch[p0], sketch[p1]
        q0, q1 = pos[loader.index(p0)], pos[loader.index(p1)]
        t = math.atan2(*(q1 - q0)[::-1]) - math.atan2(*(a1 - a0)[::-1])
        c, s = math.cos(t), math.sin(t)
        r = np.array(b.center_of_mass) - a0
        out[b.name] = (b.mass, q0 + np.array([c * r[0] - s * r[1], s * r[0] + c * r[1]]))
    return out


# ---------------------------------------------------------------- breakout
def test_breakout_pose_and_point(loader) -> None:
    b = breakout(loader)
    res = loader.solve(b.lengths[None, :])
    assert floor_angle(loader, res.positions)[0] == pytest.approx(0.0, abs=1e-12)
    edge = res.positions[0, loader.index("W")]
    assert edge[1] == pytest.approx(loader.ground_line, abs=1e-9)  # within 20 mm: on it
    assert_allclose(b.point, edge - [BEHIND_EDGE, 0.0], atol=1e-12)


def test_tilt_breakout_by_the_equilibrium_of_bucket_link_and_bell_crank(loader) -> None:
    """The tilt cylinder at working pressure pushes the bell crank at G; the bell crank turns
    about E, the tilt link (with its weight) carries the force to the bucket at I, and the
    bucket turns about its hinge pin B against the test force at Q and its weight."""
    b = breakout(loader)
    assert b.tilt.limiting == "tilt"
    pos = loader.solve(b.lengths[None, :]).positions[0]
    P = {n: pos[loader.index(n)] for n in ("B", "E", "F", "G", "H", "I")}
    bodies = _bodies(loader, pos)
    g = loader.gravity
    tilt = loader.cylinders[1]
    f = loader.circuits["tilt"].working * math.pi / 4 * tilt.bore**2
    axis = (P["G"] - P["F"]) / math.hypot(*(P["G"] - P["F"]))
    f_G = f * axis + np.array([0.0, -0.5 * tilt.mass * g])  # push + half the cylinder's weight
    m_l, c_l = bodies["tilt_link"]
    w_l = np.array([0.0, -m_l * g])
    m_b, c_b = bodies["bell_crank"]
    w_b = np.array([0.0, -m_b * g])
    # unknowns x = (R_H, R_I): forces of the bell crank and of the bucket on the link
    A = np.zeros((4, 4))
    rhs = np.zeros(4)
    A[0, [0, 2]] = 1.0  # link, x
    rhs[0] = -w_l[0]
    A[1, [1, 3]] = 1.0  # link, y
    rhs[1] = -w_l[1]
    hi = P["I"] - P["H"]
    A[2, 2:] = [-hi[1], hi[0]]  # link, moment about H
    rhs[2] = -_cross(c_l - P["H"], w_l)
    he = P["H"] - P["E"]
    A[3, :2] = [he[1], -he[0]]  # bell crank about E: −(H−E) × R_H
    rhs[3] = -(_cross(P["G"] - P["E"], f_G) + _cross(c_b - P["E"], w_b))
    R = np.linalg.solve(A, rhs)
    R_I = R[2:]
    m_k, c_k = bodies["bucket"]
    # bucket about B: −(I−B)×R_I + (Q−B)×(0, −F) + (c_k−B)×(0, −m_k g) = 0
    moment = -_cross(P["I"] - P["B"], R_I) + _cross(c_k - P["B"], np.array([0.0, -m_k * g]))
    F = moment / (b.point[0] - P["B"][0])
    assert b.tilt.force == pytest.approx(F, rel=1e-10)
    assert b.tilt.cylinder_force[1] == pytest.approx(f, rel=1e-12)


@pytest.mark.parametrize("circuit", ["tilt", "lift"])
def test_breakout_by_the_engines_kinetostatics(loader, circuit) -> None:
    """At the breakout force, the engine's body-by-body equilibrium gives each cylinder the
    force the virtual-work computation gives: the working one at working pressure where it
    binds, the holding one within its port relief."""
    b = breakout(loader)
    row = getattr(b, circuit)
    res = loader.solve(b.lengths[None, :])
    W = res.positions[0, loader.index("W")]
    Fv = np.array([0.0, -row.force])  # the restraint's force on the bucket
    loads = [
        *loader.weight_loads(),
        PointForce("test", "bucket", "W", Fv),
        Torque("shift", "bucket", _cross(b.point - W, Fv)),  # the same force moved to Q
    ]
    fr = loader.mechanism.forces(res, loads)
    lift_f, tilt_f = fr.force("lift_cyl")[0], fr.force("tilt_cyl")[0]
    if circuit == "lift":
        assert lift_f == pytest.approx(row.cylinder_force[0], rel=1e-9)
        assert tilt_f == pytest.approx(row.cylinder_force[1], rel=1e-9)
        lift = loader.cylinders[0]
        assert 0.0 < lift_f < loader.circuits["lift"].working * lift.bore_area
        pull, push = loader.cylinders[1].force_limits(loader.circuits["tilt"].relief)
        assert pull <= tilt_f <= push
    else:  # through the tilt circuit the block, not the lift cylinders, carries the arm
        assert tilt_f == pytest.approx(row.cylinder_force[1], rel=1e-9)


def test_lift_breakout_is_capped_by_tipping_about_the_front_axle(loader) -> None:
    """The restraint's reaction, F down at Q, lifts the rear wheels when its moment about the
    front axle equals the whole machine's: F·x_Q = −g·Σ m·x (x from the front axle)."""
    b = breakout(loader)
    assert b.lift.limiting == "tipping (front axle)"
    assert b.lift.hydraulic > b.lift.force
    pos = loader.solve(b.lengths[None, :]).positions[0]
    ch = loader.chassis
    moment = sum(m * c[0] for m, c in _bodies(loader, pos).values())
    for cyl, (p, q) in zip(loader.cylinders, loader.pins.cyl_ends, strict=True):
        moment += 0.5 * cyl.mass * (pos[loader.index(p), 0] + pos[loader.index(q), 0])
    for part in (ch.front_frame, ch.rear_frame, ch.counterweight):
        moment += part.mass * part.x
    F = -loader.gravity * moment / (b.point[0] - ch.front_axle[0])
    assert b.lift.force == pytest.approx(F, rel=1e-10)
    assert b.lift.tipping == pytest.approx(F, rel=1e-10)


def test_each_limit_is_named_where_it_binds(tmp_path) -> None:
    # a low lift working pressure: the lift cylinders bind before tipping
    weak = _variant(tmp_path, ("working = 24.0", "working = 8.0"))
    assert breakout(weak).lift.limiting == "lift"
    # a low tilt relief holding a strong lift: the tilt cylinder yields first
    soft = _variant(
        tmp_path,
        ("[circuits.tilt]\nworking = 24.0", "[circuits.tilt]\nworking = 12.0"),
        ("relief = 27.5                     # estimate", "relief = 12.0"),
    )
    row = breakout(soft).lift
    assert row.limiting == "tilt"
    pull, push = soft.cylinders[1].force_limits(soft.circuits["tilt"].relief)
    assert min(abs(row.cylinder_force[1] - pull), abs(row.cylinder_force[1] - push)) < 1e-6 * push
    # a light machine: the tilt circuit tips it about the block under the hinge pin
    light = _variant(
        tmp_path,
        ("mass = 3000", "mass = 0"),
        ("mass = 7000", "mass = 200"),
        ("mass = 3600", "mass = 200"),
    )
    assert breakout(light).tilt.limiting == "tipping (block under the hinge pin)"


def test_breakout_table_and_summary(loader) -> None:
    b = breakout(loader)
    frame = b.to_frame()
    assert list(frame["circuit"]) == ["tilt", "lift"]
    assert frame.attrs["excavkin.units"]["force"] == "N"
    assert "kN" in b.summary() and "tipping (front axle)" in b.summary()


# ---------------------------------------------------------------- static tipping load
def _hand_tipping(loader: Loader, lift: float, gamma: float) -> tuple[float, str]:
    """Whole-machine moments about each edge of the support triangle (front tyres turned by
    γ with the front frame about the articulation joint, the rear axle's pivot fixed)."""
    ch = loader.chassis
    pos = loader.solve([[lift, loader.lengths_max[1]]]).positions[0]
    xj = ch.articulation
    c, s = math.cos(gamma), math.sin(gamma)

    def front(x: float, v: float = 0.0) -> np.ndarray:
        return np.array([c * (x - xj) - s * v, s * (x - xj) + c * v])

    masses = [(m, front(p[0])) for m, p in _bodies(loader, pos).values()]
    for cyl, (p, q) in zip(loader.cylinders, loader.pins.cyl_ends, strict=True):
        masses += [(0.5 * cyl.mass, front(pos[loader.index(k), 0])) for k in (p, q)]
    masses.append((ch.front_frame.mass, front(ch.front_frame.x)))
    masses += [(m.mass, np.array([m.x - xj, 0.0])) for m in (ch.rear_frame, ch.counterweight)]
    # the rated load: B + R(floor)·cg, by hand from the solved hinge pin, edge and heel
    B, W, K = (pos[loader.index(n)] for n in ("B", "W", "K"))
    a = math.atan2(*(W - K)[::-1])
    x, y = loader.bucket.load_cg
    load = front(B[0] + math.cos(a) * x - math.sin(a) * y)
    fl, fr = front(0.0, 1.125), front(0.0, -1.125)
    pivot = np.array([ch.rear_axle - xj, 0.0])
    best, name = math.inf, ""
    for p, q, label in ((fr, fl, "front axle"), (fl, pivot, "left"), (pivot, fr, "right")):
        t = (q - p) / math.hypot(*(q - p))
        n = np.array([t[1], -t[0]])  # outward for a counter-clockwise triangle
        arm = n @ (load - p)
        if arm > 0:
            w = -sum(m * (n @ (r - p)) for m, r in masses) / arm
            if w < best:
                best, name = w, label
    return best, name


@pytest.mark.parametrize("case", ["straight", "full_turn"])
def test_static_tipping_by_a_whole_machine_moment_balance(loader, case) -> None:
    t = static_tipping(loader)
    row = getattr(t, case)
    hand, line = _hand_tipping(loader, row.lengths[0], row.articulation)
    assert line == "front axle" and row.line == "front axle"
    assert row.load == pytest.approx(hand, rel=1e-10)
    assert row.lengths[1] == loader.lengths_max[1]  # full rollback
    # the most forward (least stable) point of the lift: no lift length does worse
    grid = np.linspace(loader.lengths_min[0], loader.lengths_max[0], 801)
    loads, _ = tipping_loads(loader, grid, row.articulation)
    assert np.nanmin(loads) >= row.load * (1 - 1e-9)


def test_full_turn_tips_sooner_and_rates_the_machine(loader) -> None:
    t = static_tipping(loader)
    assert t.full_turn.articulation == pytest.approx(math.radians(40))
    assert t.full_turn.load < t.straight.load
    assert t.rated_operating_capacity == pytest.approx(ROC_FACTOR * t.full_turn.load)
    assert t.density == pytest.approx(t.rated_operating_capacity / 3.0)
    frame = t.to_frame()
    assert frame.attrs["excavkin.units"]["tipping_load"] == "kg"
    assert "rated operating capacity" in t.summary()


def test_a_rigid_rear_axle_widens_the_support_at_full_turn(tmp_path, loader) -> None:
    rigid = _variant(tmp_path, ('rear_axle = "oscillating"', 'rear_axle = "rigid"'))
    assert static_tipping(rigid).full_turn.load >= static_tipping(loader).full_turn.load - 1e-6


# ---------------------------------------------------------------- another linkage
DIRECT = """
[model.units]
length = "mm"
mass = "kg"
inertia = "kg*m^2"
[model.points]
O = [0, 0]
A = [-450.0, 2050.0]
C = [-1100.0, 600.0]
D = [544.7, 1283.6]
B = [2050.0, 480.0]
J = [1000.0, 1500.0]
I = [2050.0, 1080.0]
K = [1970.0, 0.0]
W = [3470.0, 0.0]
[model.bodies]
frame = { points = ["A", "C", "O"], ground = true }
[model.bodies.lift_arm]
points = ["A", "B", "D", "J"]
mass = 1900
inertia = 1800
center_of_mass = [800, 1265]
[model.bodies.bucket]
points = ["B", "I", "K", "W"]
mass = 1500
inertia = 650
center_of_mass = [2450, 450]
[model.drivers.lift_cyl]
type = "linear"
between = ["C", "D"]
mode = "driven"
[model.drivers.tilt_cyl]
type = "linear"
between = ["J", "I"]
mode = "driven"
"""


def test_a_tilt_cylinder_that_retracts_to_roll_back(tmp_path) -> None:
    """A direct linkage (inline [model]: the tilt cylinder from the lift arm to the bucket,
    above the hinge pin) rolls back by retracting: its breakout through the tilt circuit is
    the annulus side's pull at working pressure, by the bucket's moments about its hinge pin."""
    m = _variant(
        tmp_path,
        ('model = "wheel_loader.toml"', "# model inline, below"),
        ('rolls_back = "extend"', 'rolls_back = "retract"'),
        ("retracted = 1293", "retracted = 900"),
        ("stroke = 500 ", "stroke = 400 "),
        ('feeds = ["lift", "tilt"]', 'feeds = ["lift", "tilt"]\n' + DIRECT),
    )
    assert m.rollback_sign() == -1.0 and m.full_rollback() == pytest.approx(0.9)
    b = breakout(m)
    assert b.tilt.limiting == "tilt"
    pos = m.solve(b.lengths[None, :]).positions[0]
    J, I, B = (pos[m.index(n)] for n in ("J", "I", "B"))  # noqa: E741
    tilt = m.cylinders[1]
    f = m.circuits["tilt"].working * tilt.annulus_area
    F_I = f * (J - I) / math.hypot(*(J - I)) + np.array([0.0, -0.5 * tilt.mass * m.gravity])
    m_k, c_k = _bodies(m, pos)["bucket"]
    moment = _cross(I - B, F_I) + _cross(c_k - B, np.array([0.0, -m_k * m.gravity]))
    assert b.tilt.force == pytest.approx(moment / (b.point[0] - B[0]), rel=1e-10)
    assert b.tilt.cylinder_force[1] == pytest.approx(-f, rel=1e-12)
    d = dimensions(m)
    assert d["rollback at ground"] > 0.0 and math.isfinite(d["hinge-pin height at full lift"])


def test_a_bucket_that_cannot_reach_the_ground_is_named(tmp_path) -> None:
    """Lift cylinders too long to lower the arm: no breakout pose, one message naming the file."""
    from excavkin.errors import ModelError

    high = _variant(
        tmp_path, ("retracted = 1733", "retracted = 2300"), ("stroke = 1020", "stroke = 400")
    )
    with pytest.raises(ModelError, match=r"m\.toml.*cylinders.*cutting edge on the ground"):
        breakout(high)


# ---------------------------------------------------------------- lift and rollback capacity
def _engine_cylinder_forces(m: Loader, lengths: np.ndarray, point: np.ndarray, kg: float):
    """The engine's body-by-body equilibrium with a load of ``kg`` hung at ``point`` of the
    bucket (moved there from the edge by a couple)."""
    res = m.solve(lengths[None, :])
    W = res.positions[0, m.index("W")]
    Fv = np.array([0.0, -kg * m.gravity])
    loads = [
        *m.weight_loads(),
        PointForce("load", "bucket", "W", Fv),
        Torque("shift", "bucket", _cross(point - W, Fv)),
    ]
    fr = m.mechanism.forces(res, loads)
    return fr.force("lift_cyl")[0], fr.force("tilt_cyl")[0]


def test_lift_capacity_by_the_engines_kinetostatics(loader) -> None:
    c = capacity(loader, 21)
    assert c.lift_limit[-1] == "lift" and c.lift[-1] == pytest.approx(c.to_full_height)
    for k in range(21):
        lift_f, tilt_f = _engine_cylinder_forces(loader, c.lengths[k], c.point[k], c.lift[k])
        push = loader.circuits["lift"].working * loader.cylinders[0].bore_area
        if c.lift_limit[k] == "lift":
            assert lift_f == pytest.approx(push, rel=1e-9)
        else:  # tipping binds first: the cylinders still have margin, and it is the machine's
            assert c.lift_limit[k] == "tipping (front axle)"
            assert lift_f < push
            assert c.lift[k] == pytest.approx(c.tipping[k], rel=1e-12)
        pull, hold = loader.cylinders[1].force_limits(loader.circuits["tilt"].relief)
        assert pull <= tilt_f <= hold * (1 + 1e-9)
    frame = c.to_frame()
    assert frame.attrs["excavkin.units"]["lift_capacity"] == "kg"
    assert "lift capacity to full height" in c.summary()


def test_rollback_capacity_by_the_engines_kinetostatics(tmp_path) -> None:
    weak = _variant(
        tmp_path,
        ("[circuits.tilt]\nworking = 24.0", "[circuits.tilt]\nworking = 10.0"),
    )
    c = capacity(weak, 11)
    assert "tilt" in set(c.rollback_limit)
    for k in np.flatnonzero(c.rollback_limit == "tilt"):
        _, tilt_f = _engine_cylinder_forces(weak, c.lengths[k], c.point[k], c.rollback[k])
        push = weak.circuits["tilt"].working * weak.cylinders[1].bore_area
        assert tilt_f == pytest.approx(push, rel=1e-9)


PARALLEL = """
[model.units]
length = "mm"
mass = "kg"
inertia = "kg*m^2"
[model.points]
O = [0, 0]
A = [-450.0, 2050.0]
C = [-1100.0, 600.0]
D = [544.7, 1283.6]
B = [2050.0, 480.0]
F = [-450.0, 2650.0]
I = [2050.0, 1080.0]
K = [1970.0, 0.0]
W = [3470.0, 0.0]
[model.bodies.frame]
points = ["A", "C", "F", "O"]
ground = true
[model.bodies.lift_arm]
points = ["A", "B", "D"]
mass = 1900
inertia = 1800
center_of_mass = [800, 1265]
[model.bodies.bucket]
points = ["B", "I", "K", "W"]
mass = 1500
inertia = 650
center_of_mass = [2450, 450]
[model.drivers.lift_cyl]
type = "linear"
between = ["C", "D"]
mode = "driven"
[model.drivers.tilt_cyl]
type = "linear"
between = ["F", "I"]
mode = "driven"
"""


def test_a_parallel_lift_linkage_keeps_its_bucket_level(tmp_path) -> None:
    """A parallel-lift linkage (inline [model]): the tilt link F–I as long as the lift arm A–B
    with |AF| = |BI| parallel is a parallelogram, so the floor keeps its angle over the whole
    lift; its tilt cylinder retracts to roll back, and the ratings run on it."""
    m = _variant(
        tmp_path,
        ('model = "wheel_loader.toml"', "# model inline, below"),
        ('rolls_back = "extend"', 'rolls_back = "retract"'),
        ("retracted = 1293", "retracted = 2700"),
        ('feeds = ["lift", "tilt"]', 'feeds = ["lift", "tilt"]\n' + PARALLEL),
    )
    ab = math.hypot(2.5, 1.57)
    lift = np.linspace(m.lengths_min[0], m.lengths_max[0], 41)
    res = m.solve(np.column_stack([lift, np.full_like(lift, ab)]))
    assert res.status.ok.all()
    assert_allclose(floor_angle(m, res.positions), 0.0, atol=1e-12)
    d = dimensions(m)
    assert math.isfinite(d["rollback at full lift"]) and math.isfinite(
        d["dump clearance at 45 deg"]
    )
    for f in d.figures:  # a figure is NaN only where its pose does not assemble
        assert math.isfinite(f.value) == bool(m.solve(f.lengths[None, :]).status.ok[0]), f.name
    b = breakout(m)
    assert b.tilt.force > 0.0 and b.lift.force > 0.0
    assert static_tipping(m).full_turn.load < static_tipping(m).straight.load
