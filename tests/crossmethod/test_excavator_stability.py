"""Tipping and slipping of the excavator against a hand equilibrium of the whole machine.

The hand equilibrium is written here from scratch, in 3-D: every mass of the machine (each body
of the front at its pose, each cylinder's two halves, the upper structure, the counterweight
and the undercarriage, read with ``tomllib`` from the example files) and the load as forces at
3-D points; the moment of each about a tipping line is ``((r − r₀) × F)·t`` with t along the
line, and the tipping load the λ that makes the sum vanish. The bodies' centres of mass are
carried from the sketch by each body's own rigid motion (its first two points). Only the front's
point positions come from the engine.

A second route takes the front's pull on the upper structure from the general kinetostatics
(the pin force at the boom foot and the boom cylinder's force at its base, with the load and
the front's weights applied to the front): at the tipping load, the upper structure's moment
about the tipping line must vanish.
"""

from __future__ import annotations

import dataclasses
import tomllib

import numpy as np
import pytest

import excavkin
from excavkin.errors import ModelError
from excavkin.excavator.machine import Circuit, Machine
from excavkin.excavator.machine_file import load_machine
from excavkin.excavator.stability import (
    base_rated_force,
    capped_tool_forces,
    stability,
)
from excavkin.kinetostatics import Gravity, PointForce
from excavkin.machinery.base import axle
from tests.conftest import EXAMPLES

G = 9.80665


@pytest.fixture(scope="module")
def machine() -> Machine:
    return load_machine(excavkin.example_path("excavator_machine"))


def _files() -> tuple[dict, dict]:
    model = tomllib.loads((EXAMPLES / "excavator.toml").read_text(encoding="utf-8"))
    mach = tomllib.loads((EXAMPLES / "excavator_machine.toml").read_text(encoding="utf-8"))
    return model, mach


def _poses(machine: Machine, n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    lo, hi = machine.lengths_min + 0.01, machine.lengths_max - 0.01
    return lo + rng.random((n, 3)) * (hi - lo)


def _masses(machine: Machine, lengths: np.ndarray) -> list[tuple[float, np.ndarray, bool]]:
    """(mass kg, model-plane positions (n, 2) m, turns with the upper structure) of every
    mass of the machine, from the example files and the engine's point positions."""
    model, mach = _files()
    mm = 1e-3
    sketch = {k: np.array(v) * mm for k, v in model["points"].items()}
    res = machine.solve(lengths)
    out = []
    for body in model["bodies"].values():
        if body.get("ground") or "mass" not in body:
            continue
        a, b = body["points"][:2]
        s0, s1 = sketch[a], sketch[b]
        c0, c1 = res.point(a)[0], res.point(b)[0]
        turn = np.arctan2(*(c1 - c0).T[::-1]) - np.arctan2(*(s1 - s0)[::-1])
        r = np.array(body["center_of_mass"]) * mm - s0
        com = c0 + np.column_stack(
            [np.cos(turn) * r[0] - np.sin(turn) * r[1], np.sin(turn) * r[0] + np.cos(turn) * r[1]]
        )
        out.append((float(body["mass"]), com, True))
    for spec in mach["cylinders"].values():
        p, q = model["drivers"][spec["driver"]]["between"]
        for pin in (p, q):
            out.append((0.5 * spec["mass"], res.point(pin)[0], True))
    n = len(lengths)
    for part in ("upper", "counterweight", "undercarriage"):
        t = mach["base"][part]
        xy = np.broadcast_to(np.array(t["center_of_mass"]) * mm, (n, 2))
        out.append((float(t["mass"]), xy, part != "undercarriage"))
    return out


def _edges() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each tipping line of the two tracks' footprint: a point on it and its outward normal
    (plan u forward, v left), centred on the swing axis."""
    _, mach = _files()
    u = mach["base"]["undercarriage"]
    half_l = 0.5e-3 * u["track_length"]
    side = 0.5e-3 * (u["gauge"] + u["shoe_width"])
    return {
        "front": (np.array([half_l, 0.0]), np.array([1.0, 0.0])),
        "rear": (np.array([-half_l, 0.0]), np.array([-1.0, 0.0])),
        "left side": (np.array([0.0, side]), np.array([0.0, 1.0])),
        "right side": (np.array([0.0, -side]), np.array([0.0, -1.0])),
    }


def _to_3d(xy: np.ndarray, swing: float, turns: bool) -> np.ndarray:
    """Model-plane points (n, 2) → (u, v, height) with the upper structure swung."""
    th = swing if turns else 0.0
    return np.column_stack([xy[:, 0] * np.cos(th), xy[:, 0] * np.sin(th), xy[:, 1]])


def hand_tipping(
    machine: Machine,
    lengths: np.ndarray,
    point: str,
    direction: np.ndarray,
    swing: float,
    edges: dict[str, tuple[np.ndarray, np.ndarray]] | None = None,
) -> tuple[np.ndarray, list[str], np.ndarray]:
    """Tipping load, its line, and the slipping load by hand (example: swing axis and ground
    line at the model's origin), about the tracks' edges or the given ones."""
    assert machine.swing_axis == 0.0 and machine.ground_line == 0.0
    masses = _masses(machine, lengths)
    n = len(lengths)
    f = direction / np.linalg.norm(direction)
    load_at = _to_3d(machine.solve(lengths).point(point)[0], swing, True)
    load = np.array([f[0] * np.cos(swing), f[0] * np.sin(swing), f[1]])  # per newton
    best = np.full(n, np.inf)
    line = [""] * n
    for name, (p0, nrm) in (_edges() if edges is None else edges).items():
        r0 = np.array([p0[0], p0[1], 0.0])
        t = np.cross([0.0, 0.0, 1.0], [nrm[0], nrm[1], 0.0])  # + tips outwards
        m0 = np.zeros(n)
        for m, xy, turns in masses:
            w = np.array([0.0, 0.0, -m * G])
            m0 += np.cross(_to_3d(xy, swing, turns) - r0, w) @ t
        m1 = np.cross(load_at - r0, load) @ t
        lam = np.where(m1 > 0, -m0 / np.where(m1 > 0, m1, 1.0), np.inf)
        assert np.all(m0 < 0)  # the example stands by itself at every pose tested
        for i in np.flatnonzero(lam < best):
            line[i] = name
        best = np.minimum(best, lam)
    weight = G * sum(m for m, _, _ in masses)
    mu = _files()[1]["base"]["friction"]
    # horizontal push = friction × normal load: λ|f_x| = μ(W − λ f_y)
    den = abs(f[0]) + mu * f[1]
    slip = np.full(n, mu * weight / den if den > 0 else np.inf)
    return best, line, slip


CASES = [
    ("Q", np.array([0.0, -1.0])),  # a load hung at the bucket pin
    ("W", np.array([0.8, 0.6])),  # a tool force at the lip, forward and up
    ("T", np.array([-1.0, -0.4])),  # at the tooth tip, back and down
]


@pytest.mark.parametrize(("point", "direction"), CASES)
@pytest.mark.parametrize("swing", [0.0, np.pi / 2, 0.45, -2.0])
def test_tipping_and_slipping_equal_hand_equilibrium(
    machine: Machine, point: str, direction: np.ndarray, swing: float
) -> None:
    L = _poses(machine, 12, 7)
    st = stability(machine, L, point, direction, swing=swing)
    lam, line, slip = hand_tipping(machine, L, point, direction, swing)
    finite = np.isfinite(lam)
    assert finite.sum() >= 6  # the test loads tip the machine at most poses
    np.testing.assert_allclose(st.tipping_load[finite], lam[finite], rtol=1e-12)
    assert np.all(np.isinf(st.tipping_load[~finite]))
    assert list(st.tipping_line[finite]) == [line[i] for i in np.flatnonzero(finite)]
    np.testing.assert_allclose(st.slipping_load, slip, rtol=1e-13)
    assert st.mass == pytest.approx(21050.0, abs=1e-9)


def test_hanging_load_tips_over_the_idler_and_the_track_edge(machine: Machine) -> None:
    L = _poses(machine, 40, 11)
    front = stability(machine, L, "Q", swing="front")
    side = stability(machine, L, "Q", swing="side")
    ahead = front.point[:, 0] > 1.825 + 0.5  # well ahead of the idler axis
    assert ahead.sum() > 20
    assert set(front.tipping_line[ahead]) == {"front"}
    assert set(side.tipping_line[ahead]) == {"left side"}
    # the side tipping line (1.49 m out) is nearer than the front one (1.825 m)
    assert np.all(side.tipping_load[ahead] < front.tipping_load[ahead])
    assert np.all(np.isinf(front.slipping_load))  # nothing horizontal, nothing slides


def test_tipping_load_balances_the_kinetostatic_pull_of_the_front(machine: Machine) -> None:
    """At the tipping load the upper structure, pulled by the front through the boom foot and
    the boom cylinders (the engine's kinetostatics with the load and the front's weights), is
    in balance about the tipping line with its own, the counterweight's and the
    undercarriage's weights."""
    L = _poses(machine, 10, 19)
    point, direction = "W", np.array([0.3, -1.0])
    for swing in (0.0, np.pi / 2):
        fin = np.isfinite(stability(machine, L, point, direction, swing=swing).tipping_load)
        assert fin.sum() >= 6
        st = stability(machine, L[fin], point, direction, swing=swing)
        lam = st.tipping_load
        load = lam[:, None] * st.direction
        mech = machine.mechanism
        drivers = machine.drivers
        res = mech.solve(
            {d: L[fin, i] for i, d in enumerate(drivers)},
            {d: np.zeros(fin.sum()) for d in drivers},
            loads=[
                PointForce("load", machine.front.bucket, point, load),
                Gravity(G),
                *_moving_cylinder_halves(machine),
            ],
        )
        foot = -res.pin("A", "boom")  # the front on the upper structure at the boom foot
        base_pin, rod_pin = machine.pins.cyl_ends[0]
        c, d = res.kinematics.point(base_pin)[0], res.kinematics.point(rod_pin)[0]
        axis = (c - d) / np.linalg.norm(c - d, axis=1)[:, None]
        cyl = res.force(drivers[0])[:, None] * axis  # the boom cylinders push C away from D
        _, mach = _files()
        forces = [(foot, res.kinematics.point("A")[0], True), (cyl, c, True)]
        weights = [
            (0.5 * mach["cylinders"]["boom"]["mass"], c, True),  # their half on the frame
            *[
                (
                    float(mach["base"][p]["mass"]),
                    np.broadcast_to(np.array(mach["base"][p]["center_of_mass"]) * 1e-3, c.shape),
                    p != "undercarriage",
                )
                for p in ("upper", "counterweight", "undercarriage")
            ],
        ]
        for m, xy, turns in weights:
            forces.append((np.broadcast_to([0.0, -m * G], xy.shape), xy, turns))
        lines = {ln: _edges()[ln] for ln in set(st.tipping_line)}
        for i in range(fin.sum()):
            p0, nrm = lines[st.tipping_line[i]]
            r0 = np.array([p0[0], p0[1], 0.0])
            t = np.cross([0.0, 0.0, 1.0], [nrm[0], nrm[1], 0.0])
            total = 0.0
            scale = 0.0
            for fxy, xy, turns in forces:
                r = _to_3d(xy[i : i + 1], swing, turns)[0]
                th = swing if turns else 0.0
                f3 = np.array([fxy[i, 0] * np.cos(th), fxy[i, 0] * np.sin(th), fxy[i, 1]])
                m = np.cross(r - r0, f3) @ t
                total += m
                scale = max(scale, abs(m))
            assert abs(total) <= 1e-10 * scale


def _moving_cylinder_halves(machine: Machine) -> list[PointForce]:
    """Half of each cylinder's weight on each end pin that moves, on a body holding it."""
    _, mach = _files()
    bodies = [b for b in machine.mechanism.model.bodies if not b.ground]
    out = []
    for cyl, ends in zip(machine.cylinders, machine.pins.cyl_ends, strict=True):
        m = mach["cylinders"][cyl.role]["mass"]
        for pin in ends:
            body = next((b.name for b in bodies if pin in b.points), None)
            if body is not None:
                out.append(PointForce(f"{cyl.driver}@{pin}", body, pin, (0.0, -0.5 * m * G)))
    return out


# ------------------------------------------------------------- a blade and outriggers
def _polygon(vertices: list[tuple[float, float]], names: list[str]) -> dict:
    """A counter-clockwise polygon's edges by hand: a point on each, its outward normal."""
    out = {}
    for k, name in enumerate(names):
        a, b = np.array(vertices[k]), np.array(vertices[(k + 1) % len(vertices)])
        t = (b - a) / np.linalg.norm(b - a)
        out[name] = (a, np.array([t[1], -t[0]]))
    return out


def test_a_lowered_blade_carries_the_tipping_by_hand(machine: Machine) -> None:
    """A blade 2.5 m wide lowered 2.6 m ahead of the swing axis, ahead of the idlers
    (1.825 m): over the front the machine tips about the blade's edge, swung 0.5 rad about the
    slanted line from the blade's corner to the left track's idler corner, each as the hand
    balance about the hexagon drawn here finds; the blade lifts the tipping load."""
    bladed = _variant(machine, blade=(2.6, 2.5))
    L = _poses(machine, 40, 29)
    s, h = 1.49, 1.825  # the tracks' outer edge and the idler axis
    hexagon = _polygon(
        [(-h, -s), (h, -s), (2.6, -1.25), (2.6, 1.25), (h, s), (-h, s)],
        ["right side", "front-right (blade)", "front (blade)", "front-left (blade)"]
        + ["left side", "rear"],
    )
    down = np.array([0.0, -1.0])
    for swing, binds in ((0.0, "front (blade)"), (0.5, "front-left (blade)")):
        st = stability(bladed, L, "Q", down, swing=swing)
        lam, line, _ = hand_tipping(bladed, L, "Q", down, swing, hexagon)
        finite = np.isfinite(lam)
        assert finite.sum() >= 20
        np.testing.assert_allclose(st.tipping_load[finite], lam[finite], rtol=1e-12)
        assert list(st.tipping_line[finite]) == [line[i] for i in np.flatnonzero(finite)]
        assert np.sum(st.tipping_line == binds) >= 10  # the blade's line binds
        plain = stability(machine, L, "Q", down, swing=swing).tipping_load
        assert np.all(st.tipping_load[finite] >= plain[finite] * (1 - 1e-12))


def test_outriggers_carry_the_tipping_over_the_side_by_hand(machine: Machine) -> None:
    """Four pads 2 m fore and aft of the swing axis and 2.4 m out, beyond the tracks
    (1.825 m, 1.49 m): the support is their rectangle, and swung over the side the machine
    tips about the left pads' line, 2.4 m out, as the hand balance finds."""
    pads = ((2.0, 2.4), (2.0, -2.4), (-2.0, 2.4), (-2.0, -2.4))
    staked = _variant(machine, outriggers=pads)
    L = _poses(machine, 40, 31)
    rectangle = _polygon(
        [(-2.0, -2.4), (2.0, -2.4), (2.0, 2.4), (-2.0, 2.4)],
        ["right side (outriggers)", "front (outriggers)", "left side (outriggers)"]
        + ["rear (outriggers)"],
    )
    for point, direction in (("Q", np.array([0.0, -1.0])), ("W", np.array([0.3, -1.0]))):
        st = stability(staked, L, point, direction, swing="side")
        lam, line, slip = hand_tipping(staked, L, point, direction, np.pi / 2, rectangle)
        finite = np.isfinite(lam)
        assert finite.sum() >= 20
        np.testing.assert_allclose(st.tipping_load[finite], lam[finite], rtol=1e-12)
        assert set(st.tipping_line[finite]) == {"left side (outriggers)"}
        assert list(st.tipping_line[finite]) == [line[i] for i in np.flatnonzero(finite)]
        np.testing.assert_allclose(st.slipping_load, slip, rtol=1e-13)


def test_a_wheeled_excavator_tips_over_its_axles_by_hand(machine: Machine) -> None:
    """On wheels: an oscillating front axle (its pin 1.25 m ahead of the swing axis) and a
    rigid rear axle (tyres 1.25 m behind, ±1.2 m): the triangle drawn here. Swung over the side
    the machine tips about the line from the front pin to the rear-left tyre, as the hand
    balance finds, with a far smaller load than on the tracks."""
    wheeled = _variant(
        machine,
        axles=(axle("front", 1.25, 2.4, oscillating=True), axle("rear", -1.25, 2.4)),
        track_length=0.0,
        gauge=0.0,
        shoe_width=0.0,
    )
    L = _poses(machine, 40, 37)
    triangle = _polygon(
        [(-1.25, -1.2), (1.25, 0.0), (-1.25, 1.2)], ["front-right", "front-left", "rear"]
    )
    for swing in (np.pi / 2, 1.2):
        st = stability(wheeled, L, "Q", swing=swing)
        lam, line, _ = hand_tipping(wheeled, L, "Q", np.array([0.0, -1.0]), swing, triangle)
        finite = np.isfinite(lam)
        assert finite.sum() >= 20
        np.testing.assert_allclose(st.tipping_load[finite], lam[finite], rtol=1e-12)
        assert list(st.tipping_line[finite]) == [line[i] for i in np.flatnonzero(finite)]
        assert np.sum(st.tipping_line == "front-left") >= 10
        tracks = stability(machine, L, "Q", swing=swing).tipping_load
        assert np.all(st.tipping_load[finite] < tracks[finite])


# ------------------------------------------------------------------ which limit binds
def _variant(machine: Machine, pressure_factor: float = 1.0, **base: object) -> Machine:
    """The machine with its base changed, and its pressures scaled."""
    assert machine.base is not None
    circuits = {
        k: Circuit(c.name, c.working * pressure_factor, c.relief * pressure_factor)
        for k, c in machine.circuits.items()
    }
    return Machine(
        machine.mechanism,
        machine.front,
        {c.role: c for c in machine.cylinders},
        circuits,
        ground_line=machine.ground_line,
        swing_axis=machine.swing_axis,
        gravity=machine.gravity,
        base=dataclasses.replace(machine.base, **base),  # type: ignore[arg-type]
    )


POSES = np.array([[2.57, 2.82, 2.007], [3.0, 2.5, 1.9], [2.2, 2.6, 2.2]])


@pytest.mark.parametrize("working", ["arm", "bucket"])
def test_each_limit_binds_and_is_named(machine: Machine, working: str) -> None:
    """Over the front the example's cylinders bind. Over the side, with three times the
    pressures on a grippy ground, the machine tips first. On ice it slides first."""
    cases = {
        "cylinder": (machine, "front"),
        "tipping": (_variant(machine, 3.0, friction=3.0), "side"),
        "slipping": (_variant(machine, friction=0.01), "side"),
    }
    for kind, (m, swing) in cases.items():
        c = capped_tool_forces(m, POSES, working, swing=swing, gravity=False)  # type: ignore[arg-type]
        hyd = c.hydraulic.force
        tip, slip = c.stability.tipping_load, c.stability.slipping_load
        np.testing.assert_array_equal(c.force, np.minimum(np.minimum(hyd, tip), slip))
        if kind == "cylinder":
            assert np.all(c.force == hyd) and np.all(np.isin(c.limiting, ["boom", "arm"]))
            np.testing.assert_array_equal(c.limiting, c.hydraulic.limiting)
        elif kind == "tipping":
            assert np.all(tip < 0.9 * np.minimum(hyd, slip))
            assert np.all(np.char.startswith(c.limiting.astype(str), "tipping ("))
            assert set(c.limiting) <= {"tipping (right side)", "tipping (left side)"}
        else:
            assert np.all(slip < 0.9 * np.minimum(hyd, tip))
            assert set(c.limiting) == {"slipping"}


def test_rated_forces_capped_by_tipping_and_slipping(machine: Machine) -> None:
    """The example's rated forces stay the cylinders'; on ice they are the slipping load at
    the best boom position, which is named."""
    r = base_rated_force(machine, "arm", at="lip")
    assert r.rated.force == pytest.approx(r.cylinders_only.force, rel=1e-9)
    assert r.rated.limiting == r.cylinders_only.limiting == "boom"
    assert r.rated.force <= min(r.tipping, r.slipping)
    ice = _variant(machine, friction=0.02)
    s = base_rated_force(ice, "arm", at="lip")
    assert s.rated.limiting == "slipping"
    assert s.rated.force == pytest.approx(s.slipping, rel=1e-12)
    assert s.rated.force < 0.5 * s.hydraulic
    # no boom position of a dense grid slides later
    lo, hi = ice.lengths_min[0], ice.lengths_max[0]
    grid = np.column_stack(
        [
            np.linspace(lo, hi, 2001),
            np.full(2001, s.rated.lengths[1]),
            np.full(2001, s.rated.lengths[2]),
        ]
    )
    c = capped_tool_forces(ice, grid, "arm", gravity=False)
    assert np.nanmax(c.force) <= s.rated.force * (1 + 1e-9)


def test_without_a_base_the_stability_is_refused(machine: Machine) -> None:
    bare = Machine(
        machine.mechanism, machine.front, {c.role: c for c in machine.cylinders}, machine.circuits
    )
    with pytest.raises(ModelError, match=r"\[base\].*no base machine"):
        stability(bare, POSES, "Q")
