"""The rope-shovel wing against independent computations (issue 27, the electric mining shovel).

* the envelope's figures against a brute-force grid of the box, its poses against the rope's
  and the crowd's lengths measured by hand from the solved points (tangents and wrap);
* the hoist's and the crowd's efforts along a dig by virtual work, from the engine's transfer
  functions, against the general kinetostatics (1e-9);
* the power balance: the motors' power is the rise of the front's potential and kinetic energy
  plus the work against the digging resistance (1e-9);
* a rope never pushes: a hoist that would have to push is a status, never ok;
* the boom's suspension-rope tension and foot-pin load by a moment and force balance written
  here, from the front's free body and the hoist rope's two free segments.
"""

from __future__ import annotations

import numpy as np
import pytest

from excavkin.kinetostatics import Gravity, PointForce
from excavkin.shovel.dig import dig
from excavkin.shovel.envelope import envelope
from excavkin.shovel.loads import boom_loads
from excavkin.shovel.machine import Shovel
from excavkin.shovel.machine_file import load_machine


@pytest.fixture(scope="module")
def shovel() -> Shovel:
    return load_machine("mining_shovel_machine")


def _rot(a: np.ndarray) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)


def _cross(w: np.ndarray, r: np.ndarray) -> np.ndarray:
    """ω × r in the plane, ω shape (n,), r shape (n, 2)."""
    return np.stack([-w * r[:, 1], w * r[:, 0]], axis=1)


def _cg(mech, res, body):
    """Position, velocity, acceleration of a body's centre of mass, by rigid-body motion from
    its first point (not the engine's own centre-of-mass kinematics)."""
    b = next(b for b in mech.model.bodies if b.name == body)
    pts = mech.model.points
    a0 = np.arctan2(*(np.subtract(pts[b.points[1]], pts[b.points[0]])[::-1]))
    ang, w, e = res.body(body)
    p, v, a = res.point(b.points[0])
    r = np.einsum("nij,j->ni", _rot(ang - a0), np.subtract(b.center_of_mass, pts[b.points[0]]))
    vel = v + _cross(w, r)
    acc = a + _cross(e, r) - (w**2)[:, None] * r
    return p + r, vel, acc


def _tangent(c: np.ndarray, radius: float, p: np.ndarray, side: float) -> np.ndarray:
    """Unit direction from the point p to its tangent point on a circle (centre c), on the
    side ``side`` (+1: the circle's centre to the direction's right)."""
    d = c - p
    dist = np.hypot(d[:, 0], d[:, 1])
    ang = np.arctan2(d[:, 1], d[:, 0]) + side * np.arcsin(radius / dist)
    return np.stack([np.cos(ang), np.sin(ang)], axis=1)


def _rope_by_hand(shovel: Shovel, res) -> np.ndarray:
    """The hoist rope's length from the solved points: two tangents and the clockwise wrap."""
    rope = next(r for r in shovel.mechanism.model.ropes if r.name == shovel.hoist.rope)
    a, c, b = (res.point(p)[0] for p in rope.path)
    r = rope.radii[0]
    u1 = _tangent(c, r, a, +1.0)  # the rope runs over the top: the sheave to its right
    u2 = _tangent(c, r, b, -1.0)  # from the bail up the front of the sheave
    t1 = a + u1 * np.sqrt(np.sum((c - a) ** 2, 1) - r**2)[:, None]
    t2 = b + u2 * np.sqrt(np.sum((c - b) ** 2, 1) - r**2)[:, None]
    l1, l2 = np.hypot(*(t1 - a).T), np.hypot(*(t2 - b).T)
    ang1, ang2 = (np.arctan2(*(t - c).T[::-1]) for t in (t1, t2))
    wrap = np.mod(ang1 - ang2, 2 * np.pi)  # clockwise from t1 to t2
    return l1 + r * wrap + l2


def test_envelope_against_a_brute_force_grid_and_the_poses_by_hand(shovel):
    env = envelope(shovel, samples=21)
    n = 61
    gl, gs = np.meshgrid(
        np.linspace(*shovel.hoist.length, n), np.linspace(*shovel.crowd.extension, n), indexing="ij"
    )
    res = shovel.solve(gl.ravel(), gs.ravel())
    tip = res.point(shovel.front.teeth)[0]
    hinge = res.point(shovel.front.door_hinge)[0]
    grid = {
        "cutting height": np.nanmax(tip[:, 1]),
        "cutting radius": np.nanmax(tip[:, 0]),
        "dump height": np.nanmax(hinge[:, 1]) - shovel.dipper.door_length,
    }
    for name, best in grid.items():
        # no grid pose beats the figure; the grid comes within its step's reach of it
        assert best <= env[name] + 1e-9, name
        assert env[name] - best < 0.05, name
    # each figure's pose is the box's: its rope and crowd, measured by hand from the points
    for f in env.figures:
        pose = shovel.solve(np.array([f.length]), np.array([f.extension]))
        np.testing.assert_allclose(_rope_by_hand(shovel, pose), f.length, rtol=0, atol=1e-9)
        p, hf = pose.point("P")[0], pose.point("HF")[0]
        np.testing.assert_allclose(np.hypot(*(hf - p).T), f.extension, rtol=0, atol=1e-9)
    floor = env.figure("radius at floor level")
    pose = shovel.solve(np.array([floor.length]), np.array([floor.extension]))
    assert abs(pose.point(shovel.front.teeth)[0][0, 1]) < 1e-9
    # brute force on the floor: per crowd extension, the rope putting the tip on the ground by
    # bisection (not the envelope's Newton), over the extensions that reach it
    s = np.linspace(*shovel.crowd.extension, 23)
    lo, hi = np.full_like(s, 38.0), np.full_like(s, shovel.hoist.length[1])
    y_lo = shovel.solve(lo, s).point(shovel.front.teeth)[0][:, 1]
    for _ in range(45):
        mid = 0.5 * (lo + hi)
        y = shovel.solve(mid, s).point(shovel.front.teeth)[0][:, 1]
        same = np.sign(y) == np.sign(y_lo)
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    tip = shovel.solve(lo, s).point(shovel.front.teeth)[0]
    on = np.abs(tip[:, 1]) < 1e-6
    assert on.sum() >= 3
    assert np.max(tip[on, 0]) <= floor.value + 1e-6
    assert floor.value - np.max(tip[on, 0]) < 0.3


def _virtual_work(shovel: Shovel, res, loads) -> tuple[np.ndarray, np.ndarray]:
    """Generalised forces of the loads on the hoist motor's angle and the crowd's slide, from
    the engine's transfer functions: τ = −Σ F·∂p/∂θ, F_crowd = −Σ F·∂p/∂s."""
    mech, rope, crowd = shovel.mechanism, shovel.hoist.rope, shovel.crowd.driver
    inputs = {rope: res.driver(rope)[0], crowd: res.driver(crowd)[0]}
    out = []
    for unit in ((1.0, 0.0), (0.0, 1.0)):
        n = inputs[crowd].size
        tf = mech.solve(inputs, rates={rope: np.full(n, unit[0]), crowd: np.full(n, unit[1])})
        q = np.zeros(n)
        for load in loads:
            if isinstance(load, Gravity):
                for b in mech.model.bodies:
                    if b.ground or not b.mass:
                        continue
                    _, v, _ = _cg(mech, tf, b.name)
                    q -= b.mass * load.g * (v @ np.asarray(load.direction))
            else:
                _, v, _ = tf.point(load.point)
                q -= np.sum(np.broadcast_to(load.value, v.shape) * v, axis=1)
        out.append(q)
    return out[0], out[1]


def test_hoist_and_crowd_by_virtual_work(shovel):
    d = dig(shovel, samples=9, fill=0.7)
    static = shovel.solve(d.length, d.extension)
    loads = [*shovel.weight_loads(0.7), PointForce("soil", "dipper", "K", (-3e5, -1e5))]
    fr = shovel.mechanism.forces(static, loads)
    tau, push = _virtual_work(shovel, static, loads)
    scale = np.max(np.abs(tau))
    np.testing.assert_allclose(fr.winch_torque(shovel.hoist.rope), tau, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(
        fr.force(shovel.crowd.driver), push, rtol=0, atol=1e-9 * np.max(np.abs(push))
    )
    # the hoist's torque is the bail pull through the drum and the gears: τ = −T·R/i
    T = fr.tension(shovel.hoist.rope)
    np.testing.assert_allclose(
        tau, -T * shovel.hoist.drum_radius / shovel.hoist.gear_ratio, rtol=1e-9
    )


def test_motor_power_is_the_energy_rise_plus_the_digging_work(shovel):
    d = dig(shovel, samples=15, fill=1.0)
    kin = d.forces.kinematics
    mech = shovel.mechanism
    g = shovel.gravity
    rise = np.zeros(d.time.size)
    for b in mech.model.bodies:
        if b.ground or not b.mass:
            continue
        _, v, a = _cg(mech, kin, b.name)
        _, w, e = kin.body(b.name)
        rise += b.mass * g * v[:, 1] + b.mass * np.sum(v * a, axis=1) + b.inertia * w * e
    _, v_pc, _ = kin.point(shovel.dipper.payload_point)
    rise += shovel.dipper.payload * g * v_pc[:, 1]  # the payload as a weight
    _, v_tip, _ = kin.point(shovel.front.teeth)
    speed = np.hypot(*v_tip.T)
    u = v_tip / speed[:, None]
    soil = -d.resistance_along[:, None] * u + d.resistance_normal[:, None] * np.stack(
        [u[:, 1], -u[:, 0]], 1
    )
    against = -np.sum(soil * v_tip, axis=1)
    motors = d.hoist_power + d.crowd_power
    np.testing.assert_allclose(motors, rise + against, rtol=0, atol=1e-9 * np.max(np.abs(motors)))
    assert np.all(against > 0)
    # the motors' power from their torque and speed: the hoist's rated speed hauling in
    omega = shovel.hoist.motor.speed
    np.testing.assert_allclose(
        d.hoist_power, -d.hoist_torque * shovel.hoist.motor.count * omega, rtol=1e-12
    )


class _Upside(Shovel):
    """The shovel with gravity turned upwards: the hoist would have to push."""

    def weight_loads(self, fill=1.0):
        return [Gravity(self.gravity, direction=(0.0, 1.0))]


def test_a_hoist_that_would_push_is_a_status_never_ok(shovel):
    up = _Upside(shovel.mechanism, shovel.front, shovel.hoist, shovel.crowd, shovel.dipper,
                 shovel.base, shovel.gravity, shovel.name)  # fmt: skip
    d = dig(up, samples=7)
    assert np.all(d.bail_pull < 0)
    assert not d.ok.any()
    assert set(d.status) == {"slack rope 'hoist' (it would have to push)"}
    assert "not ok: 7 rows, slack rope 'hoist'" in d.summary()
    normal = dig(shovel, samples=7)
    assert normal.ok[0]


def _mirrored(shovel: Shovel) -> Shovel:
    """The shovel mirrored top to bottom: the rack to the right of the handle (σ = −1), the
    hoist rope turning counter-clockwise over its sheave."""
    import dataclasses

    from excavkin import Mechanism

    m = shovel.mechanism.model
    model = dataclasses.replace(
        m,
        points={k: (x, -y) for k, (x, y) in m.points.items()},
        bodies=tuple(
            dataclasses.replace(b, center_of_mass=(b.center_of_mass[0], -b.center_of_mass[1]))
            if b.center_of_mass is not None
            else b
            for b in m.bodies
        ),
        ropes=tuple(
            dataclasses.replace(r, wraps=tuple("ccw" if w == "cw" else "cw" for w in r.wraps))
            for r in m.ropes
        ),
    )
    crowd = dataclasses.replace(shovel.crowd, sigma=-1.0)
    return Shovel(Mechanism(model), shovel.front, shovel.hoist, crowd, shovel.dipper, None,
                  shovel.gravity, "mirrored")  # fmt: skip


@pytest.mark.parametrize("mirror", [False, True])
def test_the_pinion_on_the_boom_by_the_fronts_own_statics(shovel, mirror):
    """Static poses: the rack's tooth force W and the bail pull T' from the front's free body
    (saddle, handle, dipper): its moments about the shipper shaft (the rope at the bail, W along
    the pitch line through P, the weights, payload and a digging force) and the handle and
    dipper's forces along the guide (the saddle's normal force has none). Mirrored, the rack
    lies to the right of the handle (σ = −1) and the rope turns the other way."""
    from excavkin.shovel.dig import pinion_efforts

    d = dig(shovel, samples=9, fill=0.6)
    if mirror:
        shovel = _mirrored(shovel)
    mech, g, fnt = shovel.mechanism, shovel.gravity, shovel.front
    static = shovel.solve(d.length, d.extension)
    assert static.status.ok.all()
    soil = np.array([-4e5, -1.5e5])
    loads = [*shovel.weight_loads(0.6), PointForce("soil", "dipper", "K", tuple(soil))]
    fr = mech.forces(static, loads)
    inputs = {"hoist": shovel.hoist.angle(d.length), "crowd": d.extension}
    one, zero = np.ones(9), np.zeros(9)
    a = mech.solve(inputs, rates={"hoist": zero, "crowd": one}).body("saddle")[1]
    b = mech.solve(inputs, rates={"hoist": one, "crowd": zero}).body("saddle")[1]
    eff = pinion_efforts(shovel, fr.force("crowd"), fr.winch_torque("hoist"), a, b)

    S, P, HF = (static.point(k)[0] for k in ("S", "P", "HF"))
    u = (HF - P) / np.hypot(*(HF - P).T)[:, None]
    rope = next(r for r in mech.model.ropes if r.name == "hoist")
    sheave, bail = static.point("T")[0], static.point("BL")[0]
    # the rope's pull on the bail: towards its tangent point, the sheave on its left (cw wrap)
    t_bail = _tangent(sheave, rope.radii[0], bail, 1.0 if mirror else -1.0)

    def m_s(at, f):
        return (at[:, 0] - S[:, 0]) * f[:, 1] - (at[:, 1] - S[:, 1]) * f[:, 0]

    ext_m = np.zeros(9)  # moments about S and forces along u of the given loads
    ext_u = np.zeros(9)
    for body in (fnt.saddle, fnt.handle, fnt.dipper):
        cg, _, _ = _cg(mech, static, body)
        w = np.stack(
            [np.zeros(9), -next(x for x in mech.model.bodies if x.name == body).mass * g * one], 1
        )
        ext_m += m_s(cg, w)
        if body != fnt.saddle:
            ext_u += np.sum(w * u, axis=1)
    pc, tip = static.point("PC")[0], static.point("K")[0]
    wp = np.stack([np.zeros(9), -shovel.dipper.payload * 0.6 * g * one], 1)
    fs = np.broadcast_to(soil, (9, 2))
    ext_m += m_s(pc, wp) + m_s(tip, fs)
    ext_u += np.sum(wp * u, 1) + np.sum(fs * u, 1)
    # unknowns T' (along t_bail at the bail) and W (along u, through P):
    #   T'·m(t) + W·m(u at P) + ext_m = 0,    T'·(t·u) + W + ext_u = 0
    m_t, m_w, tu = m_s(bail, t_bail), m_s(P, u), np.sum(t_bail * u, 1)
    det = m_t - m_w * tu
    pull = (-ext_m + m_w * ext_u) / det
    tooth = -ext_u - pull * tu
    np.testing.assert_allclose(eff.pull, pull, rtol=1e-9)
    np.testing.assert_allclose(eff.tooth, tooth, rtol=0, atol=1e-9 * np.max(np.abs(tooth)))
    # the pinion matters: the driver between saddle and handle is not the rack's tooth force
    assert np.max(np.abs(eff.tooth - fr.force("crowd"))) > 1e3


def test_boom_loads_by_an_independent_balance(shovel):
    """Along a dig (inertia, payload, soil): the shipper shaft's force from the front's free
    body, the sheave's from the bail pull over the rope's two tangents, the crowd drive's couple,
    the boom's weight; its moment about the foot gives the suspension ropes' tension, its force
    balance the foot pin."""
    d = dig(shovel, samples=11, fill=0.5)
    lb = boom_loads(shovel, d)
    kin = d.forces.kinematics
    mech, g, fnt = shovel.mechanism, shovel.gravity, shovel.front
    n = d.time.size
    rope = next(r for r in mech.model.ropes if r.name == shovel.hoist.rope)
    drum, sheave, bail = (kin.point(p)[0] for p in rope.path)
    r = rope.radii[0]
    to_drum = -_tangent(sheave, r, drum, +1.0)
    to_bail = -_tangent(sheave, r, bail, -1.0)
    T = d.bail_pull
    # the front (saddle, handle, dipper; the massless pinion): what it puts on the boom at S
    on_shaft = T[:, None] * (-to_bail)
    for body in (fnt.saddle, fnt.handle, fnt.dipper):
        b = next(x for x in mech.model.bodies if x.name == body)
        _, _, acc = _cg(mech, kin, body)
        on_shaft += b.mass * (np.array([0.0, -g]) - acc)
    on_shaft[:, 1] -= shovel.dipper.payload * g * d.fill
    _, v_tip, _ = kin.point(fnt.teeth)
    u = v_tip / np.hypot(*v_tip.T)[:, None]
    on_shaft += -d.resistance_along[:, None] * u + d.resistance_normal[:, None] * np.stack(
        [u[:, 1], -u[:, 0]], 1
    )
    np.testing.assert_allclose(
        lb.shipper_shaft, on_shaft, rtol=0, atol=1e-9 * np.max(np.abs(on_shaft))
    )
    sheave_force = T[:, None] * (to_drum + to_bail)
    np.testing.assert_allclose(
        lb.sheave, sheave_force, rtol=0, atol=1e-9 * np.max(np.abs(sheave_force))
    )
    couple = (
        shovel.crowd.sigma * shovel.crowd.gear_ratio * d.crowd_torque * shovel.crowd.motor.count
    )
    boom = next(b for b in mech.model.bodies if b.name == fnt.boom)
    cg, _, _ = _cg(mech, kin, fnt.boom)
    bf, s_pt = kin.point(fnt.boom_foot)[0], kin.point(fnt.shipper_shaft)[0]
    ga, bp = kin.point("GA")[0], kin.point("BP")[0]
    u_s = (ga - bp) / np.hypot(*(ga - bp).T)[:, None]

    def moment(p, f):
        return (p[:, 0] - bf[:, 0]) * f[:, 1] - (p[:, 1] - bf[:, 1]) * f[:, 0]

    weight = np.stack([np.zeros(n), -boom.mass * g * np.ones(n)], 1)  # the boom does not move
    known = moment(s_pt, on_shaft) + moment(sheave, sheave_force) + moment(cg, weight) + couple
    tension = -known / moment(bp, u_s)
    foot = -(on_shaft + sheave_force + weight + tension[:, None] * u_s)
    ok = lb.ok
    assert ok.sum() >= 8
    np.testing.assert_allclose(lb.suspension, tension, rtol=1e-9)
    np.testing.assert_allclose(lb.boom_foot, foot, rtol=0, atol=1e-9 * np.max(np.abs(foot)))
    assert np.all(tension[ok] > 0)


def test_tipping_payload_by_moments_about_the_front_of_the_tracks(shovel):
    from excavkin.shovel.stability import stability

    d = dig(shovel, samples=7)
    st = stability(shovel, d)
    kin = d.forces.kinematics
    base = shovel.base
    front = base.track_centre + 0.5 * base.track_length  # the idlers' axis
    moment = np.zeros(d.time.size)
    for b in shovel.mechanism.model.bodies:
        if b.ground or not b.mass:
            continue
        cg, _, _ = _cg(shovel.mechanism, kin, b.name)
        moment += b.mass * (cg[:, 0] - front)
    for part in (base.upper, base.counterweight, base.undercarriage):
        moment += part.mass * (part.x - front)
    x_pc = kin.point(shovel.dipper.payload_point)[0][:, 0]
    assert np.all(moment < 0) and np.all(x_pc > front)
    np.testing.assert_allclose(st.tipping_payload, -moment / (x_pc - front), rtol=1e-12)
    assert set(st.payload_line) == {"front"}
    assert np.all(st.tipping_payload > st.payload)
