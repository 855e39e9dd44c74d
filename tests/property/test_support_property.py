"""Random supports of the machinery layer's one support model, random poses and loads.

Hypothesis draws a machine on two frames (an axle or tracks on the fixed one, an axle, a blade
or pads on the turning one, an oscillating rear axle or not), masses of both frames, a front
mass point, a turning angle and loads. At each draw:

* every contact point lies inside or on every tipping line, and the polygon's vertices are
  contact points, counter-clockwise;
* at the tipping load the whole machine's moment about the named line vanishes, and about every
  line it is negative at 99.9 % of it (moments recomputed here from the masses and the load);
* the slipping load makes the horizontal push equal friction times the normal load.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from hypothesis import event, given, settings
from hypothesis import strategies as st

from excavkin.machinery.base import Contact, Mass, Support, axle, blade, outriggers, track
from excavkin.machinery.equilibrium import equilibrium
from excavkin.machinery.masses import MassPoints

G = 9.80665
AXIS, GROUND = 0.3, -0.5


@dataclass
class Stand:
    support: Support


@dataclass
class Machine:
    base: Stand
    mass_points: MassPoints
    swing_axis: float = AXIS
    ground_line: float = GROUND
    gravity: float = G
    source: str | None = None


@st.composite
def supports(draw: st.DrawFn) -> Support:
    length = st.floats(0.5, 4.0)
    fixed_kind = draw(st.sampled_from(["tracks", "axle"]))
    contacts: list[Contact] = []
    if fixed_kind == "tracks":
        gauge, shoe = draw(length), draw(st.floats(0.2, 0.8))
        centre, run = draw(st.floats(-1.0, 1.0)), draw(length)
        contacts += [
            track("right track", centre, -0.5 * gauge, run, shoe),
            track("left track", centre, 0.5 * gauge, run, shoe),
        ]
    else:
        osc = draw(st.booleans())
        contacts.append(axle("rear", draw(st.floats(-3.0, -0.5)), draw(length), oscillating=osc))
    turning = draw(st.sampled_from(["axle", "blade", "pads", "none"]))
    if turning == "axle" or (turning == "none" and fixed_kind == "axle"):
        contacts.append(axle("front", draw(st.floats(0.5, 3.0)), draw(length), turns=True))
    elif turning == "blade":
        contacts.append(blade(draw(st.floats(0.5, 3.0)), draw(length), turns=True))
    elif turning == "pads":
        pads = draw(st.lists(st.tuples(st.floats(-3, 3), st.floats(-3, 3)), min_size=1, max_size=4))
        contacts.append(outriggers(pads, turns=True))
    if fixed_kind == "tracks" and draw(st.booleans()):
        contacts.append(blade(draw(st.floats(1.0, 3.0)), draw(length)))
    masses = st.floats(100.0, 5000.0)
    x = st.floats(-2.0, 2.0)
    return Support(
        (Mass("upper", draw(masses), draw(x), 1.0),),
        (Mass("lower", draw(masses), draw(x), 0.5), Mass("weight", draw(masses), draw(x), 0.7)),
        tuple(contacts),
        draw(st.floats(0.05, 1.5)),
        draw(st.sampled_from(["direction", "contacts"])),
    )


def _moments(support: Support, front: np.ndarray, point: np.ndarray, f: np.ndarray,
             angle: float, lam: float) -> list[tuple[str, float]]:  # fmt: skip
    """The whole machine's moment about each tipping line, tipping outwards, with the load λ
    (two edges may share a name: by direction, two slanted front-left edges)."""
    d = np.array([math.cos(angle), math.sin(angle)])
    out = []
    for ln in support.tipping_lines(AXIS, angle):
        n, c = np.array(ln.normal), ln.offset
        total = 0.0
        for m, x in [(800.0, front[0]), *[(k.mass, k.x) for k in support.turning]]:
            total += m * G * ((x - AXIS) * (n @ d) - c)
        for k in support.fixed:
            total += k.mass * G * ((k.x - AXIS) * n[0] - c)
        arm = -f[1] * ((point[0] - AXIS) * (n @ d) - c) + f[0] * (n @ d) * (point[1] - GROUND)
        out.append((ln.name, total + lam * arm))
    return out


@settings(max_examples=150, deadline=None, derandomize=True, database=None)
@given(
    support=supports(),
    angle=st.floats(-math.pi, math.pi),
    front=st.tuples(st.floats(0.0, 4.0), st.floats(0.0, 3.0)),
    point=st.tuples(st.floats(-1.0, 8.0), st.floats(-1.0, 4.0)),
    direction=st.floats(-math.pi, math.pi),
)
def test_a_random_support_holds_its_points_and_balances_at_the_tipping_load(
    support: Support,
    angle: float,
    front: tuple[float, float],
    point: tuple[float, float],
    direction: float,
) -> None:
    try:
        poly, _ = support.support_polygon(AXIS, angle)
    except Exception as exc:  # a degenerate draw: only "no area" is allowed
        assert "no area" in str(exc)
        event("no area")
        return
    pts, _ = support.contact_points(AXIS, angle)
    lines = support.tipping_lines(AXIS, angle)
    for ln in lines:
        assert np.all(pts @ np.array(ln.normal) <= ln.offset + 1e-9)
    assert all(np.min(np.hypot(*(pts - v).T)) == 0.0 for v in poly)
    area = 0.5 * np.sum(poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1])
    assert area > 0.0

    f = np.array([math.cos(direction), math.sin(direction)])
    coef = np.zeros((1, 2, 1, 2))
    coef[0, 0, 0, 0] = coef[0, 1, 0, 1] = 1.0
    machine = Machine(Stand(support), MassPoints(("front",), np.array([800.0]), coef))
    fr, pt = np.array([front]), np.array([point])
    s = equilibrium(machine, fr[:, None, :], pt, f, angle)
    lam = float(s.tipping_load[0])
    unloaded = _moments(support, fr[0], pt[0], f, angle, 0.0)
    scale = G * s.mass * 10.0  # N·m: the weight on a 10 m lever
    worst = max(unloaded, key=lambda t: t[1])
    if worst[1] > 0.0:  # tips by itself, about the line of the largest moment
        event("tips by itself")
        assert lam == 0.0 and s.tipping_line[0] == worst[0]
    elif math.isinf(lam):
        event("never tips")
        assert s.tipping_line[0] == ""
    else:
        event("tips under the load")
        at = _moments(support, fr[0], pt[0], f, angle, lam)
        assert min(abs(m) for name, m in at if name == s.tipping_line[0]) <= 1e-9 * scale
        below = _moments(support, fr[0], pt[0], f, angle, lam * 0.999)
        assert max(m for _, m in below) < 1e-9 * scale
    total = s.mass * G
    mu = support.friction
    assert mu is not None
    slip = float(s.slipping_load[0])
    if math.isfinite(slip):
        assert abs(slip * abs(f[0]) - mu * (total - slip * f[1])) <= 1e-9 * total
    else:
        assert abs(f[0]) + mu * f[1] <= 0.0
