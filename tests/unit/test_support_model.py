"""The machinery layer's one support model (Loaders on the same footing as excavators, item 1):
support polygons of a crawler, of a wheeled machine with an oscillating rear axle and of an
articulated one at ± its largest angle, written here by hand; the whole-machine tipping and
slipping loads of a machine standing on it, against a 3-D moment balance written from scratch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from excavkin.errors import ModelError
from excavkin.loader.machine import Loader
from excavkin.loader.machine_file import load_machine as load_loader
from excavkin.loader.stability import tipping
from excavkin.machinery.base import (
    BaseMachine,
    Contact,
    Mass,
    Support,
    axle,
    blade,
    outriggers,
    track,
)
from excavkin.machinery.equilibrium import equilibrium
from excavkin.machinery.masses import MassPoints
from tests.conftest import EXAMPLES

G = 9.80665


def _same_polygon(got: np.ndarray, expected: list[tuple[float, float]]) -> None:
    """The same vertices, counter-clockwise, starting from the least (u, v)."""
    np.testing.assert_allclose(got, np.array(expected), rtol=0, atol=1e-14)


def _lines(support: Support, axis: float, angle: float = 0.0) -> dict[str, tuple]:
    return {ln.name: (ln.normal, ln.offset) for ln in support.tipping_lines(axis, angle)}


# ------------------------------------------------------------------ support polygons
def test_a_crawlers_polygon_is_its_tracks_outer_corners() -> None:
    """Tracks 4 m long (centre 0.5 m ahead of the swing axis at x = 0.2), gauge 2.4 m, shoes
    0.6 m: the rectangle u = 0.3 ± 2, v = ±1.5; the inner corners drop out."""
    base = BaseMachine(
        Mass("upper", 5000.0, -0.3, 1.5),
        Mass("counterweight", 3000.0, -2.0, 1.6),
        Mass("undercarriage", 7000.0, 0.5, 0.5),
        track_length=4.0,
        gauge=2.4,
        shoe_width=0.6,
        track_centre=0.5,
        friction=0.5,
    )
    sup = base.support
    assert [c.name for c in sup.contacts] == ["right track", "left track"]
    assert sup.turning == (base.upper, base.counterweight)
    assert sup.fixed == (base.undercarriage,) and sup.mass == base.mass == 15000.0
    pts, _ = sup.contact_points(0.2)
    assert len(pts) == 8  # four corners a track
    poly, kinds = sup.support_polygon(0.2)
    _same_polygon(poly, [(-1.7, -1.5), (2.3, -1.5), (2.3, 1.5), (-1.7, 1.5)])
    assert kinds == ["track"] * 4
    lines = _lines(sup, 0.2)
    assert set(lines) == {"front", "rear", "left side", "right side"}
    assert lines["front"][1] == pytest.approx(2.3, abs=1e-14)
    assert lines["rear"][1] == pytest.approx(1.7, abs=1e-14)
    assert lines["left side"][1] == pytest.approx(1.5, abs=1e-14)
    # a swing machine's tracks do not turn: the polygon is the same at every swing
    for angle in (0.7, -2.0):
        np.testing.assert_array_equal(sup.support_polygon(0.2, angle)[0], poly)


def test_a_wheeled_machine_with_an_oscillating_rear_axle_stands_on_a_triangle() -> None:
    """Front tyres at x = 2, tread 2; the rear axle oscillates about a pin at x = −1: the
    support is the triangle of the two front tyres and the pin, which a rigid rear axle widens
    to a rectangle."""
    front = axle("front", 2.0, 2.0)
    osc = Support((), (), (front, axle("rear", -1.0, 2.0, oscillating=True)), None, "contacts")
    poly, kinds = osc.support_polygon(0.0)
    _same_polygon(poly, [(-1.0, 0.0), (2.0, -1.0), (2.0, 1.0)])
    assert kinds == ["pivot", "tyres", "tyres"]
    r10 = math.sqrt(10.0)
    lines = _lines(osc, 0.0)
    assert set(lines) == {
        "rear axle pivot – front-right tyre",
        "front axle",
        "front-left tyre – rear axle pivot",
    }
    np.testing.assert_allclose(lines["front axle"][0], (1.0, 0.0), atol=1e-15)
    assert lines["front axle"][1] == pytest.approx(2.0, abs=1e-15)
    # pivot (−1, 0) to the front-right tyre (2, −1): outward normal (−1, −3)/√10, offset 1/√10
    n, c = lines["rear axle pivot – front-right tyre"]
    np.testing.assert_allclose(n, (-1.0 / r10, -3.0 / r10), atol=1e-15)
    assert c == pytest.approx(1.0 / r10, abs=1e-15)
    n, c = lines["front-left tyre – rear axle pivot"]
    np.testing.assert_allclose(n, (-1.0 / r10, 3.0 / r10), atol=1e-15)
    assert c == pytest.approx(1.0 / r10, abs=1e-15)
    # named by direction (a swing machine's way) the same triangle reads front / rear-left …
    by_direction = Support((), (), osc.contacts, None, "direction")
    assert set(_lines(by_direction, 0.0)) == {"front", "rear-left", "rear-right"}
    rigid = Support((), (), (front, axle("rear", -1.0, 2.0)), None, "contacts")
    _same_polygon(
        rigid.support_polygon(0.0)[0], [(-1.0, -1.0), (2.0, -1.0), (2.0, 1.0), (-1.0, 1.0)]
    )
    assert set(_lines(rigid, 0.0)) == {
        "rear axle",
        "front axle",
        "rear-right tyre – front-right tyre",
        "front-left tyre – rear-left tyre",
    }


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_an_articulated_loader_at_its_largest_angle(sign: float) -> None:
    """The built-in loader (front axle at x = 0, tread 2.25 m, joint at x = −1.65 m, wheelbase
    3.3 m, 40°): the front tyres turn with the front frame about the joint, the rear axle's pin
    stays; turning the other way mirrors the polygon."""
    ch = load_loader(EXAMPLES / "wheel_loader_machine.toml").chassis
    assert (ch.front_axle[0], ch.tread, ch.articulation, ch.wheelbase) == pytest.approx(
        (0.0, 2.25, -1.65, 3.3), abs=1e-12
    )
    gamma = sign * ch.max_articulation
    assert abs(gamma) == pytest.approx(math.radians(40.0))
    c, s = math.cos(gamma), math.sin(gamma)

    def turned(u: float, v: float) -> tuple[float, float]:
        return (c * u - s * v, s * u + c * v)

    fl, fr, pin = turned(1.65, 1.125), turned(1.65, -1.125), (-1.65, 0.0)
    poly, _ = ch.support.support_polygon(-1.65, gamma)
    assert poly.shape == (3, 2)
    # the pin has the least u: counter-clockwise from it, front-right then front-left
    _same_polygon(poly, [pin, fr, fl])
    lines = {ln.name: ln for ln in ch.support.tipping_lines(-1.65, gamma)}
    assert set(lines) == {
        "front axle",
        "front-left tyre – rear axle pivot",
        "rear axle pivot – front-right tyre",
    }
    np.testing.assert_allclose(lines["front axle"].normal, (c, s), atol=1e-15)
    assert lines["front axle"].offset == pytest.approx(1.65, abs=1e-14)
    mirror = {ln.name: ln for ln in ch.support.tipping_lines(-1.65, -gamma)}
    a, b = lines["front-left tyre – rear axle pivot"], mirror["rear axle pivot – front-right tyre"]
    np.testing.assert_allclose(a.normal, (b.normal[0], -b.normal[1]), atol=1e-15)
    assert a.offset == pytest.approx(b.offset, abs=1e-15)


def test_contacts_of_the_turning_frame_turn_and_blade_and_pads_add() -> None:
    sup = Support(
        (),
        (),
        (
            track("right track", 0.0, -1.0, 3.0, 0.5),
            track("left track", 0.0, 1.0, 3.0, 0.5),
            blade(2.5, 2.0),
            outriggers([(-1.5, 1.6), (-1.5, -1.6)]),
        ),
        0.5,
    )
    # rear pads just outside the tracks (±1.25 m), a blade 2 m wide 1 m ahead of the idlers
    poly, kinds = sup.support_polygon(0.0)
    _same_polygon(
        poly, [(-1.5, -1.6), (1.5, -1.25), (2.5, -1.0), (2.5, 1.0), (1.5, 1.25), (-1.5, 1.6)]
    )
    assert kinds == ["outriggers", "track", "blade", "blade", "track", "outriggers"]
    assert list(_lines(sup, 0.0)) == [
        "front-right (outriggers)",
        "front-right (blade)",
        "front (blade)",
        "front-left (blade)",
        "front-left (outriggers)",
        "rear (outriggers)",
    ]
    # pads on the turning frame (an upper structure's stabilisers) swing with it
    swung = Support((), (), (*sup.contacts[:2], outriggers([(0.0, 3.0)], turns=True)), 0.5)
    pts, _ = swung.contact_points(0.0, math.pi / 2)
    np.testing.assert_allclose(pts[-1], (-3.0, 0.0), atol=1e-15)
    with pytest.raises(ModelError, match="no area"):
        Support((), (), (axle("front", 1.0, 2.0),)).support_polygon(0.0)
    with pytest.raises(ModelError, match="one label"):
        Contact("pad", "outriggers", 0.0, ((0.0, 1.0),), ())


# ------------------------------------------------------------------ whole-machine balance
@dataclass
class Stand:
    """What a machine stands on, for the protocol."""

    support: Support


#: the articulation joint, just behind the front axle: turned, the front frame carries the
#: load out over the lines from the front tyres to the rear pin
AXIS = 1.0


@dataclass
class Machine:
    """The least machine the layer's equilibrium reads: one front mass point (its position at
    each pose is the one model point), an axis, a ground line."""

    base: Stand | None
    mass_points: MassPoints
    swing_axis: float = AXIS
    ground_line: float = -0.3
    gravity: float = G
    source: str | None = None


FRONT_MASS = 2500.0
TREAD = 1.2
ARTICULATED = Support(
    (Mass("front frame", 3000.0, 1.2, 1.0),),
    (Mass("rear frame", 5000.0, -1.0, 1.2), Mass("counterweight", 2000.0, -2.0, 1.0)),
    (axle("front", 1.5, TREAD, turns=True), axle("rear", -1.5, TREAD, oscillating=True)),
    0.45,
    "contacts",
)


def _machine(support: Support) -> Machine:
    coef = np.zeros((1, 2, 1, 2))
    coef[0, 0, 0, 0] = coef[0, 1, 0, 1] = 1.0
    return Machine(Stand(support), MassPoints(("front",), np.array([FRONT_MASS]), coef))


def _hand(
    front: np.ndarray, point: np.ndarray, f: np.ndarray, gamma: float
) -> tuple[np.ndarray, list[str], np.ndarray, dict[str, np.ndarray]]:
    """Tipping load and line, slipping load and the centre of mass's distance inside each
    line, from 3-D moments ((r − a) × F)·t about each edge a → b of the triangle,
    t = (b − a)/|b − a|."""
    xa, yg = AXIS, -0.3
    c, s = math.cos(gamma), math.sin(gamma)

    def turned(x: float, v: float, h: float) -> np.ndarray:
        return np.array([c * (x - xa) - s * v, s * (x - xa) + c * v, h - yg])

    fl, fr = turned(1.5, 0.5 * TREAD, yg), turned(1.5, -0.5 * TREAD, yg)
    pin = np.array([-1.5 - xa, 0.0, 0.0])
    edges = [(fr, fl, "front axle"), (fl, pin, "front-left tyre – rear axle pivot")]
    edges.append((pin, fr, "rear axle pivot – front-right tyre"))
    n = len(front)
    weights = []
    for i in range(n):
        w = [(FRONT_MASS, turned(front[i, 0], 0.0, front[i, 1])), (3000.0, turned(1.2, 0.0, 1.0))]
        w += [(5000.0, np.array([-1.0 - xa, 0.0, 1.5])), (2000.0, np.array([-2.0 - xa, 0.0, 1.3]))]
        weights.append(w)
    total = 12500.0
    unit = f / np.linalg.norm(f, axis=1)[:, None]
    best, line = np.full(n, np.inf), [""] * n
    inside = {name: np.zeros(n) for _, _, name in edges}
    for i in range(n):
        load = np.array([c * unit[i, 0], s * unit[i, 0], unit[i, 1]])  # per newton
        at = turned(point[i, 0], 0.0, point[i, 1])
        com = sum(m * r for m, r in weights[i]) / total
        for a, b, name in edges:
            t = (b - a) / np.linalg.norm(b - a)
            m0 = sum(np.cross(r - a, [0.0, 0.0, -m * G]) @ t for m, r in weights[i])
            m1 = np.cross(at - a, load) @ t
            assert m0 < 0.0  # it stands without the load
            if m1 > 0.0 and -m0 / m1 < best[i]:
                best[i], line[i] = -m0 / m1, name
            outward = np.cross(t, [0.0, 0.0, 1.0])  # the edge's outward normal in plan
            inside[name][i] = (a - com) @ outward
    mu = 0.45
    den = np.abs(unit[:, 0]) + mu * unit[:, 1]
    slip = np.where(den > 0.0, mu * total * G / np.where(den > 0.0, den, 1.0), np.inf)
    return best, line, slip, inside


@pytest.mark.parametrize("gamma", [0.0, 1.0, -1.0])
def test_tipping_and_slipping_of_an_articulated_machine_by_hand(gamma: float) -> None:
    rng = np.random.default_rng(5)
    n = 30
    front = np.column_stack([rng.uniform(1.5, 3.5, n), rng.uniform(0.5, 3.0, n)])
    point = np.column_stack([rng.uniform(2.5, 5.0, n), rng.uniform(0.0, 3.0, n)])
    f = np.column_stack([rng.uniform(-0.6, 0.6, n), -np.ones(n)])
    st = equilibrium(_machine(ARTICULATED), front[:, None, :], point, f, gamma)
    lam, line, slip, inside = _hand(front, point, f, gamma)
    assert np.all(np.isfinite(lam))
    np.testing.assert_allclose(st.tipping_load, lam, rtol=1e-12)
    assert list(st.tipping_line) == line
    np.testing.assert_allclose(st.slipping_load, slip, rtol=1e-12)
    least = np.min(list(inside.values()), axis=0)
    np.testing.assert_allclose(st.margin, least, rtol=1e-12)
    named = [inside[str(name)][i] for i, name in enumerate(st.margin_line)]
    np.testing.assert_allclose(named, least, rtol=1e-12)  # the line it is measured to
    assert st.mass == pytest.approx(12500.0, abs=1e-9)
    if gamma != 0.0:  # turned far, the load tips it over a line to the rear pin at most poses
        assert sum(name != "front axle" for name in line) > n // 2


def test_a_support_without_friction_gives_no_slipping_load() -> None:
    bare = Support(ARTICULATED.turning, ARTICULATED.fixed, ARTICULATED.contacts, None, "contacts")
    front = np.array([[2.0, 1.0]])
    st = equilibrium(_machine(bare), front[:, None, :], np.array([[3.0, 1.0]]), (0.3, -1.0), 0.0)
    assert np.isnan(st.slipping_load[0]) and np.isfinite(st.tipping_load[0])


# ------------------------------------------------------------------ the loader on the layer
def _loader(tmp_path: Path, *swaps: tuple[str, str]) -> Loader:
    text = (EXAMPLES / "wheel_loader_machine.toml").read_text(encoding="utf-8")
    for old, new in swaps:
        assert old in text
        text = text.replace(old, new, 1)
    (tmp_path / "wheel_loader.toml").write_text(
        (EXAMPLES / "wheel_loader.toml").read_text(encoding="utf-8"), encoding="utf-8"
    )
    path = tmp_path / "m.toml"
    path.write_text(text, encoding="utf-8")
    return load_loader(path)


def test_the_loader_stands_on_the_layers_equilibrium(tmp_path: Path) -> None:
    """The loader's chassis is its base: the layer's equilibrium on it gives the loader's own
    tipping load of a load hung at the hinge pin, and with ``[chassis] friction`` the slipping
    load μ·W/(|f_x| + μ·f_y) of the whole machine."""
    osc = 'rear_axle = "oscillating"'
    m = _loader(tmp_path, (osc, f"{osc}\nfriction = 0.6"))
    assert m.base is m.chassis and m.chassis.friction == 0.6
    L = np.array([[m.lengths_min[0] + 0.3, m.lengths_max[1]], [m.lengths_max[0] - 0.1, 1.9]])
    res = m.solve(L)
    hinge = res.point(m.pins.hinge)[0]
    gamma = m.chassis.max_articulation
    st = equilibrium(m, res.positions, hinge, (1.0, -0.3), gamma)
    down = equilibrium(m, res.positions, hinge, (0.0, -1.0), gamma)
    own = tipping(m, res.positions, hinge, gamma)
    np.testing.assert_array_equal(down.tipping_load, own.load)
    np.testing.assert_array_equal(down.tipping_line, own.line)
    assert st.mass == pytest.approx(m.mass, rel=1e-14)
    f = np.array([1.0, -0.3]) / math.hypot(1.0, 0.3)
    slip = 0.6 * m.mass * m.gravity / (abs(f[0]) + 0.6 * f[1])
    np.testing.assert_allclose(st.slipping_load, slip, rtol=1e-13)
    assert np.all(
        np.isnan(
            equilibrium(
                load_loader(EXAMPLES / "wheel_loader_machine.toml"),
                res.positions,
                hinge,
                (1.0, -0.3),
                gamma,
            ).slipping_load
        )
    )
    with pytest.raises(ModelError, match=r"m\.toml \[chassis\] 'friction'"):
        _loader(tmp_path, (osc, f"{osc}\nfriction = -1"))
