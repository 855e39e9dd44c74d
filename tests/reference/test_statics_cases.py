"""Hand-solved statics and kinetostatics cases against the general equilibrium solver.

Each case is solved in closed form in this file, independently of the engine, following the
textbook method cited in its docstring; only the point positions (and, for the d'Alembert case,
Norton's closed-form kinematics) are shared.

References
----------
* J. J. Uicker, G. R. Pennock, J. E. Shigley, *Theory of Machines and Mechanisms*, 5th ed.,
  Oxford University Press 2017, ch. 13 "Static force analysis": two-force members (the force is
  along the line of the two pins, equal and opposite), free-body diagrams link by link.
* R. L. Norton, *Design of Machinery*, 5th ed., McGraw-Hill 2012: ch. 11 "Dynamic force
  analysis", §11.5 the four-bar (d'Alembert: −m·a_G and −I_G·α per link, pin forces
  F_12 … F_14, driving torque T_12); ch. 13 "Engine dynamics", the gas torque of the
  slider-crank, exact form ``T_g = F_g·r·sin θ·(1 + (r/l)·cos θ / sqrt(1 − (r/l)²·sin² θ))``.
* I. I. Artobolevsky, *Theory of Mechanisms and Machines* (kinetostatics of Assur groups): the
  RRR dyad's pin force from the moment equations of its two links, then the driving link.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from excavkin.kinetostatics import Gravity, PointForce, Torque
from excavkin.mechanism import Mechanism
from excavkin.model import Body, LinearDriver, Model, RotaryDriver, Slider
from tests.reference.test_fourbar_closed_form import norton_fourbar


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


# ---------------------------------------------------------------- two-force member (cylinder)
def test_boom_held_by_cylinder_two_force_member() -> None:
    """A boom pinned to the frame at O, held by a locked... driven cylinder C–D, weight at E.

    Uicker/Pennock/Shigley ch. 13: the cylinder carries no load between its pins, so it is a
    two-force member — its force acts along C–D. Moments of the boom about O give it::

        (D − O) × (f·u_CD) + (E − O) × W = 0,   u_CD = (D − C)/|D − C|
        f = −((E − O) × W) / ((D − O) × u_CD)

    and the boom's force balance gives the pin O: F_O = −W − f·u_CD. With the boom horizontal
    and the weight downward, the cylinder pushes (f > 0).
    """
    o, c, d, e = (0.0, 0.0), (0.4, -0.9), (1.2, 0.0), (3.0, 0.0)
    model = Model(
        "boom",
        {"O": o, "C": c, "D": d, "E": e},
        (Body("frame", ("O", "C"), ground=True), Body("boom", ("O", "D", "E"))),
        linear=(LinearDriver("cyl", ("C", "D")),),
    )
    mech = Mechanism(model)
    w = np.array([0.0, -20e3])
    kin = mech.solve({"cyl": math.dist(c, d)}, {"cyl": 0.0})
    res = mech.forces(kin, [PointForce("load", "boom", "E", w)])
    u = (np.array(d) - np.array(c)) / math.dist(c, d)
    f = -_cross(np.array(e) - np.array(o), w) / _cross(np.array(d) - np.array(o), u)
    assert f > 0
    assert_allclose(res.force("cyl"), [f], rtol=1e-13)
    assert_allclose(res.pin("O", "boom")[0], -w - f * u, rtol=1e-13)
    # the cylinder's force reaches the boom through the pin at D, along C→D
    assert_allclose(res.pin("D", "boom")[0], f * u, rtol=1e-13)
    assert_allclose(res.pin("C", "frame")[0], -f * u, rtol=1e-13)
    # the frame carries the whole weight
    assert_allclose(res.resultant("frame")[0], w, rtol=1e-13, atol=1e-9)


# ------------------------------------------------------------------ loaded four-bar at rest
def _fourbar_with_tip(theta2: float) -> tuple[Mechanism, dict[str, np.ndarray]]:
    """Crank 40 mm, coupler 120 mm, rocker 90 mm, ground 100 mm; rocker tip P beyond B."""
    a, b, c, d = 0.040, 0.120, 0.090, 0.100
    k = norton_fourbar(np.array([theta2]), 0.0, 0.0, -1.0)
    t3, t4 = float(k["t3"][0]), float(k["t4"][0])
    pts = {
        "O2": np.array([0.0, 0.0]),
        "O4": np.array([d, 0.0]),
        "A": a * np.array([math.cos(theta2), math.sin(theta2)]),
    }
    pts["B"] = pts["A"] + b * np.array([math.cos(t3), math.sin(t3)])
    pts["P"] = pts["O4"] + 1.5 * c * np.array([math.cos(t4), math.sin(t4)])  # on the rocker
    model = Model(
        "loaded four-bar",
        {n: (float(p[0]), float(p[1])) for n, p in pts.items()},
        (
            Body("ground", ("O2", "O4"), ground=True),
            Body("crank", ("O2", "A")),
            Body("coupler", ("A", "B")),
            Body("rocker", ("O4", "B", "P")),
        ),
        rotary=(RotaryDriver("crank", "crank", "O2", "ground"),),
    )
    return Mechanism(model), pts


@pytest.mark.parametrize("theta2_deg", [30.0, 75.0, 140.0, 250.0])
def test_loaded_fourbar_at_rest(theta2_deg: float) -> None:
    """A force on the rocker of a four-bar at rest; the coupler is a two-force member.

    Uicker/Pennock/Shigley ch. 13 (four-bar static force analysis): with no load on the
    coupler its tension f acts along A→B (u). Rocker moments about O4::

        (B − O4) × (−f·u) + (P − O4) × F_P = 0  →  f = ((P − O4) × F_P) / ((B − O4) × u)

    crank moments about O2 give the holding torque T = −(A − O2) × (f·u), and the force
    balances of the rocker and the crank give the ground pins.
    """
    mech, p = _fourbar_with_tip(math.radians(theta2_deg))
    fp = np.array([-150.0, -400.0])
    kin = mech.solve({"crank": math.radians(theta2_deg)}, {"crank": 0.0})
    res = mech.forces(kin, [PointForce("push", "rocker", "P", fp)])
    u = (p["B"] - p["A"]) / np.linalg.norm(p["B"] - p["A"])
    f = _cross(p["P"] - p["O4"], fp) / _cross(p["B"] - p["O4"], u)
    torque = -_cross(p["A"] - p["O2"], f * u)
    assert_allclose(res.torque("crank"), [torque], rtol=1e-12)
    assert_allclose(res.pin("B", "rocker")[0], -f * u, rtol=1e-12)
    assert_allclose(res.pin("A", "coupler")[0], -f * u, rtol=1e-12)
    assert_allclose(res.pin("B", "coupler")[0], f * u, rtol=1e-12)
    assert_allclose(res.pin("O4", "rocker")[0], f * u - fp, rtol=1e-12)
    assert_allclose(res.pin("O2", "crank")[0], -f * u, rtol=1e-12)
    # the coupler is a two-force member: its pin forces lie along A–B
    assert abs(_cross(res.pin("A", "coupler")[0], u)) < 1e-12 * abs(f)


# ---------------------------------------------------------------- slider-crank, gas force
@pytest.mark.parametrize("theta_deg", [20.0, 60.0, 90.0, 135.0, 200.0, 300.0])
def test_slider_crank_gas_force(theta_deg: float) -> None:
    """In-line slider-crank at rest under a gas force P on the piston (toward the crank).

    Norton ch. 13 (engine dynamics, gas force and gas torque) and Uicker/Pennock/Shigley
    ch. 13: with rod angle φ, ``sin φ = (r/l)·sin θ``, the connecting rod (a two-force member
    when massless) is compressed by ``P/cos φ``, the cylinder wall pushes the piston sideways
    with ``N = P·tan φ`` and the gas torque on the crank is::

        T_g = P·r·sin(θ + φ)/cos φ = P·r·sin θ·(1 + (r/l)·cos θ / sqrt(1 − (r/l)²·sin² θ))

    The driver holding the crank supplies −T_g.
    """
    r, l_, pg = 0.050, 0.180, 12e3
    th = math.radians(theta_deg)
    phi = math.asin(r / l_ * math.sin(th))
    a = (r * math.cos(th), r * math.sin(th))
    b = (r * math.cos(th) + l_ * math.cos(phi), 0.0)
    model = Model(
        "in-line slider-crank",
        {"O": (0.0, 0.0), "G1": (-0.1, 0.0), "G2": (0.4, 0.0), "A": a, "B": b},
        (
            Body("ground", ("O", "G1", "G2"), ground=True),
            Body("crank", ("O", "A")),
            Body("rod", ("A", "B")),
        ),
        rotary=(RotaryDriver("crank", "crank", "O", "ground"),),
        sliders=(Slider("piston", "B", ("G1", "G2")),),
    )
    mech = Mechanism(model)
    kin = mech.solve({"crank": th}, {"crank": 0.0})
    res = mech.forces(kin, [PointForce("gas", "rod", "B", (-pg, 0.0))])
    tg = pg * r * math.sin(th + phi) / math.cos(phi)
    tg_norton = (
        pg
        * r
        * math.sin(th)
        * (1 + r / l_ * math.cos(th) / math.sqrt(1 - (r / l_ * math.sin(th)) ** 2))
    )
    assert_allclose(tg, tg_norton, rtol=1e-13)
    assert_allclose(res.torque("crank"), [-tg], rtol=1e-12, atol=1e-9)
    assert_allclose(res.force("piston"), [pg * math.tan(phi)], rtol=1e-12, atol=1e-9)
    rod_force = res.pin("A", "rod")[0]  # the crank pin pushes the rod toward the piston
    assert_allclose(np.hypot(*rod_force), pg / math.cos(phi), rtol=1e-12)
    assert_allclose(res.pin("A", "crank")[0], -rod_force, rtol=1e-12)


# ------------------------------------------------------- four-bar, closed-form d'Alembert
def _dalembert_fourbar(t2: np.ndarray, w2: float, al2: float) -> dict[str, np.ndarray]:
    """Closed-form kinetostatics of a four-bar with three massive links (Assur-group method).

    Kinematics: Norton's closed forms (θ3, θ4, ω3, ω4, α3, α4). Per link i with mass m_i,
    centre of mass at distance/angle (p_i, δ_i) from its first pin and inertia J_i::

        a_Si = a_pivot + α_i × r_Si − ω_i²·r_Si       (rigid-body acceleration)
        R_i  = m_i·(g − a_Si)                          (weight + d'Alembert force)
        M_i  = r_Si × R_i − J_i·α_i                    (about the link's first pin)

    Dyad (coupler 3, rocker 4), unknown pin force F on the rocker at B (−F on the coupler)::

        rocker about O4:   (B − O4) × F + M_4 = 0
        coupler about A:  −(B − A) × F + M_3 = 0

    a 2×2 system solved by Cramer's rule. Then the coupler's force balance gives the pin A on
    the coupler, F_A3 = −R_3 + F; the crank gets F_A2 = −F_A3, its moment about O2 gives the
    driving torque T = −(A − O2) × F_A2 − M_2, and F_O2 = −R_2 − F_A2; F_O4 = −R_4 − F.
    """
    a, b, c, d = 0.040, 0.120, 0.090, 0.100
    k = norton_fourbar(t2, w2, al2, -1.0)
    t3, t4, w3, w4, al3, al4 = k["t3"], k["t4"], k["w3"], k["w4"], k["al3"], k["al4"]
    g = np.array([0.0, -9.80665])

    def unit(t: np.ndarray) -> np.ndarray:
        return np.stack([np.cos(t), np.sin(t)], axis=-1)

    def perp(v: np.ndarray) -> np.ndarray:
        return np.stack([-v[..., 1], v[..., 0]], axis=-1)

    o2 = np.zeros((t2.size, 2))
    pa = a * unit(t2)
    pb = pa + b * unit(t3)
    o4 = np.array([d, 0.0]) + 0.0 * pa
    aa = al2 * perp(pa) - w2**2 * pa
    links = {  # mass, J, COM offset (along, across the link) from its first pin
        2: (0.30, 6.0e-5, (0.5 * a, 0.004)),
        3: (0.70, 9.0e-4, (0.45 * b, -0.010)),
        4: (0.60, 4.5e-4, (0.6 * c, 0.015)),
    }
    ang = {2: t2, 3: t3, 4: t4}
    om = {2: w2 + 0.0 * t2, 3: w3, 4: w4}
    al = {2: al2 + 0.0 * t2, 3: al3, 4: al4}
    base_acc = {2: 0.0 * pa, 3: aa, 4: 0.0 * pa}
    loads = {}
    for i, (m, j, (s, t)) in links.items():
        r = s * unit(ang[i]) + t * perp(unit(ang[i]))
        acc = base_acc[i] + al[i][:, None] * perp(r) - (om[i] ** 2)[:, None] * r
        rf = m * (g - acc)
        loads[i] = (rf, _cross(r, rf) - j * al[i])
    (r2, m2), (r3, m3), (r4, m4) = loads[2], loads[3], loads[4]
    e1, e2 = pb - o4, pb - pa
    # [[-e1y, e1x], [e2y, -e2x]] · F = [-M4, -M3]
    a11, a12, a21, a22 = -e1[:, 1], e1[:, 0], e2[:, 1], -e2[:, 0]
    det = a11 * a22 - a12 * a21
    fx = (-m4 * a22 + m3 * a12) / det
    fy = (-a11 * m3 + a21 * m4) / det
    f = np.stack([fx, fy], axis=-1)
    fa3 = -r3 + f
    fa2 = -fa3
    torque = -_cross(pa - o2, fa2) - m2
    return {
        "B.rocker": f,
        "B.coupler": -f,
        "A.coupler": fa3,
        "A.crank": fa2,
        "O2.crank": -r2 - fa2,
        "O4.rocker": -r4 - f,
        "torque": torque,
        "t3": t3,
        "pa": pa,
        "pb": pb,
        "links": links,
    }  # type: ignore[dict-item]


def test_fourbar_dalembert_closed_form() -> None:
    """The general solver against the closed-form d'Alembert solution of a four-bar.

    Norton §11.5 (four-bar dynamic force analysis) solved group by group as in Artobolevsky:
    see :func:`_dalembert_fourbar`. Crank at 25 rad/s accelerating at 400 rad/s², three
    massive links with off-axis centres of mass, gravity; one full turn.
    """
    t2 = np.radians(np.arange(0.0, 360.0, 7.5))
    w2, al2 = 25.0, 400.0
    ref = _dalembert_fourbar(t2, w2, al2)
    a, b, c, d = 0.040, 0.120, 0.090, 0.100
    pa0, pb0 = ref["pa"][12], ref["pb"][12]  # the sketch: the solver's branch at 90°
    links = ref["links"]
    sk = {"O2": (0.0, 0.0), "A": tuple(pa0), "B": tuple(pb0), "O4": (d, 0.0)}

    def com(p0: np.ndarray, p1: np.ndarray, s: float, t: float) -> tuple[float, float]:
        u = (p1 - p0) / np.linalg.norm(p1 - p0)
        q = p0 + s * u + t * np.array([-u[1], u[0]])
        return float(q[0]), float(q[1])

    bodies = []
    for name, i, p0, p1 in (
        ("crank", 2, "O2", "A"),
        ("coupler", 3, "A", "B"),
        ("rocker", 4, "O4", "B"),
    ):
        m, j, (s, t) = links[i]
        bodies.append(
            Body(
                name,
                (p0, p1),
                mass=m,
                inertia=j,
                center_of_mass=com(np.array(sk[p0]), np.array(sk[p1]), s, t),
            )
        )
    model = Model(
        "massive four-bar",
        sk,
        (Body("ground", ("O2", "O4"), ground=True), *bodies),
        rotary=(RotaryDriver("crank", "crank", "O2", "ground"),),
        lengths={("O2", "A"): a, ("A", "B"): b, ("O4", "B"): c},
    )
    mech = Mechanism(model)
    kin = mech.solve({"crank": t2}, {"crank": w2}, {"crank": al2})
    assert kin.status.all_ok
    assert_allclose(kin.body("coupler")[0], np.angle(np.exp(1j * ref["t3"])), atol=1e-12)
    res = mech.forces(kin, [Gravity()])
    scale = max(float(np.abs(ref["A.crank"]).max()), 1.0)
    for key in ("B.rocker", "B.coupler", "A.coupler", "A.crank", "O2.crank", "O4.rocker"):
        point, body = key.split(".")
        assert_allclose(res.pin(point, body), ref[key], rtol=0, atol=1e-12 * scale, err_msg=key)
    assert_allclose(
        res.torque("crank"), ref["torque"], rtol=0, atol=1e-12 * float(np.abs(ref["torque"]).max())
    )


def test_rotary_torque_between_bodies_reaction() -> None:
    """A couple with a reaction body and a driver whose reference is a moving body balance.

    Two links in series on a ground pivot, the second driven relative to the first: the
    static holding torque of the relative driver equals minus the moment of the load about the
    joint, and the base driver carries the whole moment about the ground pivot (Uicker ch. 13,
    free bodies link by link).
    """
    model = Model(
        "two-link arm",
        {"O": (0.0, 0.0), "J": (0.5, 0.0), "E": (0.5, 0.4), "G": (-0.3, 0.0)},
        (
            Body("base", ("O", "G"), ground=True),
            Body("upper", ("O", "J")),
            Body("fore", ("J", "E")),
        ),
        rotary=(
            RotaryDriver("shoulder", "upper", "O", "base"),
            RotaryDriver("elbow", "fore", "J", "upper"),
        ),
    )
    mech = Mechanism(model)
    kin = mech.solve(rates={"shoulder": 0.0, "elbow": 0.0})
    w = np.array([30.0, -100.0])
    res = mech.forces(kin, [PointForce("w", "fore", "E", w), Torque("c", "fore", 7.0, "upper")])
    e, j = np.array([0.5, 0.4]), np.array([0.5, 0.0])
    # elbow: moment about J of the load on the forearm, plus the 7 N·m couple on it
    assert_allclose(res.torque("elbow"), [-(_cross(e - j, w) + 7.0)], rtol=1e-13)
    # shoulder: the couple between the links is internal to upper + fore
    assert_allclose(res.torque("shoulder"), [-_cross(e, w)], rtol=1e-13)
    assert_allclose(res.resultant("base")[0], w, rtol=1e-13)
