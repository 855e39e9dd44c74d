"""Excavator tool forces and Jacobian against independent routes.

* the cylinder-space Jacobian against central differences of the engine's positions;
* the handbook lever formulas (arm F = F_cyl·a/b, bucket F = F_cyl·c·e/(d·r), e.g.
  Bošnjak et al. and the usual excavator-design texts) against the virtual-work tool force and
  against the general kinetostatics (``Mechanism.solve(..., loads=...)``) at several poses;
* the holding cylinders' forces against the general kinetostatics with gravity;
* holding-pressure capping on a constructed case;
* the rated (standard-position) forces against the right-angle lever, the handbook formula
  swept densely, and a dense grid of the free strokes.
"""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from excavkin.excavator.forces import (
    RatedForce,
    handbook_forces,
    rated_force,
    tool_forces,
)
from excavkin.excavator.machine import Circuit, Machine, forward, jacobian
from excavkin.excavator.machine_file import load_machine
from excavkin.kinetostatics import Gravity, PointForce


@pytest.fixture(scope="module")
def machine() -> Machine:
    return load_machine(excavkin.example_path("excavator_machine"))


def _poses(machine: Machine, n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    lo, hi = machine.lengths_min + 0.02, machine.lengths_max - 0.02
    return lo + rng.random((n, 3)) * (hi - lo)


def test_jacobian_matches_central_differences(machine: Machine) -> None:
    L = _poses(machine, 50, 3)
    jac = jacobian(machine, L)
    h = 1e-4
    for c in range(3):
        e = np.eye(3)[c] * h
        fp, fm = forward(machine, L + e), forward(machine, L - e)
        fp2, fm2 = forward(machine, L + 2 * e), forward(machine, L - 2 * e)

        def d(a: np.ndarray, b: np.ndarray, a2: np.ndarray, b2: np.ndarray) -> np.ndarray:
            return (8 * (a - b) - (a2 - b2)) / (12 * h)

        dtip = d(fp.tip, fm.tip, fp2.tip, fm2.tip)
        wrap = lambda x: np.angle(np.exp(1j * x))  # noqa: E731
        dbeta = (
            8 * wrap(fp.bucket_angle - fm.bucket_angle) - wrap(fp2.bucket_angle - fm2.bucket_angle)
        ) / (12 * h)
        np.testing.assert_allclose(jac.matrix[:, :2, c], dtip, rtol=0, atol=1e-7)
        np.testing.assert_allclose(jac.matrix[:, 2, c], dbeta, rtol=0, atol=1e-7)
    assert np.all(np.isfinite(jac.condition)) and np.all(jac.condition >= 1.0)


@pytest.mark.parametrize("at", ["lip", "tip"])
def test_handbook_levers_equal_virtual_work(machine: Machine, at: str) -> None:
    L = _poses(machine, 200, 5)
    arm_hb, bucket_hb = handbook_forces(machine, L, at=at)  # type: ignore[arg-type]
    arm = tool_forces(machine, L, "arm", at=at, gravity=False)  # type: ignore[arg-type]
    bucket = tool_forces(machine, L, "bucket", at=at, gravity=False)  # type: ignore[arg-type]
    np.testing.assert_allclose(arm.uncapped, arm_hb, rtol=1e-10)
    np.testing.assert_allclose(bucket.uncapped, bucket_hb, rtol=1e-10)


@pytest.mark.parametrize("working", ["arm", "bucket"])
def test_handbook_levers_against_general_kinetostatics(machine: Machine, working: str) -> None:
    """Load the lip with the handbook force, perpendicular to its lever; the engine's
    kinetostatics must return the working cylinder's force at working pressure."""
    L = _poses(machine, 8, 17)
    arm_hb, bucket_hb = handbook_forces(machine, L, at="lip")
    f_hb = arm_hb if working == "arm" else bucket_hb
    tf = tool_forces(machine, L, working, at="lip", gravity=False)  # type: ignore[arg-type]
    soil = -f_hb[:, None] * tf.direction  # force of the soil on the bucket
    mech = machine.mechanism
    drivers = machine.drivers
    res = mech.solve(
        {d: L[:, i] for i, d in enumerate(drivers)},
        {d: np.zeros(len(L)) for d in drivers},
        loads=[PointForce("soil", machine.front.bucket, machine.front.lip, soil)],
    )
    k = 1 if working == "arm" else 2
    cyl = machine.cylinders[k]
    f_cyl = machine.circuit(working).working * cyl.bore_area
    np.testing.assert_allclose(res.force(drivers[k]), f_cyl, rtol=1e-9)
    # the holding cylinders carry what the virtual-work solution says they carry
    tf_unc = tf.cylinder_force / tf.force[:, None]  # holding force per newton of tool force
    for h in range(3):
        if h != k:
            np.testing.assert_allclose(
                res.force(drivers[h]), tf_unc[:, h] * f_hb, rtol=1e-8, atol=1e-6 * f_cyl
            )


def _cylinder_weights(machine: Machine) -> list[PointForce]:
    """Half of each cylinder's weight on each end pin that moves (the machine file's reading
    of a cylinder's mass), on a body holding the pin."""
    bodies = [b for b in machine.mechanism.model.bodies if not b.ground]
    out = []
    for cyl, ends in zip(machine.cylinders, machine.pins.cyl_ends, strict=True):
        for pin in ends:
            body = next((b.name for b in bodies if pin in b.points), None)
            if body is not None:
                w = (0.0, -0.5 * cyl.mass * machine.gravity)
                out.append(PointForce(f"{cyl.driver}@{pin}", body, pin, w))
    assert sum(c.mass for c in machine.cylinders) > 0.0  # the example's cylinders weigh
    return out


def test_holding_forces_with_gravity_match_kinetostatics(machine: Machine) -> None:
    L = _poses(machine, 8, 23)
    tf = tool_forces(machine, L, "bucket", at="tip", gravity=True)
    soil = -tf.force[:, None] * tf.direction
    mech = machine.mechanism
    drivers = machine.drivers
    res = mech.solve(
        {d: L[:, i] for i, d in enumerate(drivers)},
        {d: np.zeros(len(L)) for d in drivers},
        loads=[
            PointForce("soil", machine.front.bucket, machine.front.tip, soil),
            Gravity(machine.gravity),
            *_cylinder_weights(machine),
        ],
    )
    for h in range(3):
        np.testing.assert_allclose(
            res.force(drivers[h]), tf.cylinder_force[:, h], rtol=1e-8, atol=1e-3
        )


def test_holding_pressure_caps_the_tool_force(machine: Machine) -> None:
    """A weak bucket relief: the arm-cylinder tool force is capped where the bucket cylinder
    would have to hold more than its relief allows, and the bucket is named."""
    L = _poses(machine, 300, 31)
    free = tool_forces(machine, L, "arm", gravity=False)
    weak = dict(machine.circuits)
    weak["bucket"] = Circuit("bucket", 1e6, 2e6)  # 20 bar relief
    m2 = Machine(machine.mechanism, machine.front, {c.role: c for c in machine.cylinders}, weak)
    capped = tool_forces(m2, L, "arm", gravity=False)
    hit = capped.limiting == "bucket"
    assert hit.sum() > 50
    assert np.all(capped.force <= free.force * (1 + 1e-12))
    assert np.all(capped.force[hit] < free.force[hit])
    bkt = m2.cylinders[2]
    lo, hi = bkt.force_limits(2e6)
    f_b = capped.cylinder_force[hit, 2]
    at_limit = np.isclose(f_b, hi, rtol=1e-9) | np.isclose(f_b, lo, rtol=1e-9)
    assert at_limit.all()
    # the uncapped value is the working cylinder's own limit, unchanged
    np.testing.assert_allclose(capped.uncapped, free.uncapped, rtol=1e-12)
    # a constructed pose: with the relief lowered to what the bucket holds at half the free
    # force, the capped force is exactly half
    k = int(np.flatnonzero(free.limiting == "arm")[0])
    need = free.cylinder_force[k, 2] * 0.5
    relief = need / (bkt.bore_area if need > 0 else -bkt.annulus_area)
    weak["bucket"] = Circuit("bucket", min(relief, 34.3e6), relief)
    m3 = Machine(machine.mechanism, machine.front, {c.role: c for c in machine.cylinders}, weak)
    half = tool_forces(m3, L[k : k + 1], "arm", gravity=False)
    np.testing.assert_allclose(half.force[0], 0.5 * free.force[k], rtol=1e-10)
    assert half.limiting[0] == "bucket"


# ------------------------------------------------------------------ rated (standard) forces
@pytest.fixture(scope="module")
def rated(machine: Machine) -> dict[tuple[str, str], RatedForce]:
    return {
        (w, at): rated_force(machine, w, at=at)  # type: ignore[arg-type]
        for w in ("arm", "bucket")
        for at in ("lip", "tip")
    }


def _sketch(machine: Machine, name: str) -> np.ndarray:
    plan = machine.mechanism.plan
    return machine.mechanism.assembly.positions[plan.points.index(name)]


@pytest.mark.parametrize("at", ["lip", "tip"])
def test_rated_arm_force_is_the_right_angle_lever(
    machine: Machine, rated: dict[tuple[str, str], RatedForce], at: str
) -> None:
    """The arm cylinder's moment about the stick pivot F is F_cyl·|FE|·sin∠(FE, cylinder),
    largest when the cylinder meets FE at a right angle: L*² = |BF|² − |FE|² (B its base on
    the boom, E its eye on the stick), the moment F_cyl·|FE|."""
    r = rated[("arm", at)]
    base, eye = machine.pins.cyl_ends[1]
    f = _sketch(machine, machine.pins.stick_pivot)
    bf = np.hypot(*(_sketch(machine, base) - f))
    fe = np.hypot(*(_sketch(machine, eye) - f))
    lo, hi = machine.lengths_min[1], machine.lengths_max[1]
    right = np.sqrt(bf**2 - fe**2)
    assert lo < right < hi  # the example reaches it; otherwise the end stop nearer to it
    assert abs(r.lengths[1] - right) < 1e-5
    f_cyl = machine.cylinders[1].force_limits(machine.circuit("arm").working)[1]
    np.testing.assert_allclose(r.moment, f_cyl * fe, rtol=1e-9)
    np.testing.assert_allclose(r.uncapped * r.radius, r.moment, rtol=1e-12)
    # the bucket sits where the bucket force is rated
    assert abs(r.lengths[2] - rated[("bucket", at)].lengths[2]) < 1e-9


@pytest.mark.parametrize("at", ["lip", "tip"])
def test_rated_bucket_force_is_the_handbook_maximum(
    machine: Machine, rated: dict[tuple[str, str], RatedForce], at: str
) -> None:
    """The handbook's F_cyl·c·e/(d·r) over a dense sweep of the bucket stroke alone."""
    r = rated[("bucket", at)]
    lo, hi = machine.lengths_min, machine.lengths_max
    k = np.linspace(lo[2], hi[2], 20001)
    L = np.column_stack([np.full_like(k, r.lengths[0]), np.full_like(k, r.lengths[1]), k])
    _, bucket = handbook_forces(machine, L, at=at)  # type: ignore[arg-type]
    j = int(np.argmax(bucket))
    assert bucket[j] - 1e-9 * bucket[j] <= r.uncapped <= bucket[j] * (1 + 1e-7)
    assert abs(r.lengths[2] - k[j]) < 2 * (hi[2] - lo[2]) / 20000
    radius = machine.lip_radius if at == "lip" else machine.tip_radius
    np.testing.assert_allclose(r.radius, radius, rtol=1e-12)


@pytest.mark.parametrize("working", ["arm", "bucket"])
def test_rated_force_is_the_best_held_position(
    machine: Machine, rated: dict[tuple[str, str], RatedForce], working: str
) -> None:
    """At the rated pose no cylinder exceeds its relief, the limiting one is at it, and no
    boom (or, for the bucket force, stick) position on a dense grid does better."""
    r = rated[(working, "lip")]
    tf = tool_forces(machine, r.lengths[None, :], working, gravity=False)  # type: ignore[arg-type]
    assert tf.force[0] == r.force and r.force <= r.uncapped
    for c, cyl in enumerate(machine.cylinders):
        lo, hi = cyl.force_limits(machine.circuits[cyl.circuit].relief)
        assert lo * (1 + 1e-9) <= tf.cylinder_force[0, c] <= hi * (1 + 1e-9)
    for name in r.limiting.split("+"):
        if name == working:
            continue
        h = ("boom", "arm", "bucket").index(name)
        lo, hi = machine.cylinders[h].force_limits(machine.circuit(name).relief)
        assert np.isclose(tf.cylinder_force[0, h], lo, rtol=1e-6) or np.isclose(
            tf.cylinder_force[0, h], hi, rtol=1e-6
        )
    lo, hi = machine.lengths_min, machine.lengths_max
    b = np.linspace(lo[0], hi[0], 201)
    a = np.linspace(lo[1], hi[1], 201) if working == "bucket" else np.array([r.lengths[1]])
    B, A = np.meshgrid(b, a, indexing="ij")
    L = np.column_stack([B.ravel(), A.ravel(), np.full(B.size, r.lengths[2])])
    grid = tool_forces(machine, L, working, gravity=False)  # type: ignore[arg-type]
    assert np.nanmax(grid.force) <= r.force * (1 + 1e-9)
    assert np.nanmax(grid.force) >= r.force * (1 - 2e-3)
