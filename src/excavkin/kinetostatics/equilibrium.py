r"""Equilibrium of every moving body and every pin: one sparse linear system per sample.

Unknowns (DESIGN.md §5)::

    F[p, b] = (Fx, Fy)  the force the pin at point p exerts on body b, for every body at p
    f[e]                the axial force of each driven or locked linear element (> 0 pushes
                        its two points apart; a rope in tension is negative)
    N[s]                the normal force of each slider, along perp(l2 − l1), on the slider's
                        point (its reaction −N acts on the body that carries the line)
    τ[d]                the torque of each rotary driver on its body (−τ on its reference body)
    W[k], N[k], M[k]    each rack's tooth force along its guide, its guide's normal force
                        (both at the pitch point) and couple, on the rack (the carrier takes
                        −N, −M, the pinion −W)
    W[c], N[c], M[c]    each cam's contact force on its follower along the common normal
                        (through the instant centre of the cam and the follower; −W on the
                        cam), and its follower's guide force at the follower's first point and
                        couple (as a rack's; the carrier takes −N, −M)
    W[g]                the tangential tooth force of each gear pair: +W·t on gear 2 and −W·t
                        on gear 1 at the pitch point, t = perp(O2 − O1)/|O2 − O1| (its
                        radial part, |W|·tan φ along the line of centres, is added to the
                        pivots' pin forces afterwards: `excavkin.kinetostatics.gears`)
    T[r]                the tension of each rope over sheaves: it pulls the pin at path point
                        k with T·(u_k − u_{k−1}), u_k its free segments' directions
                        (`excavkin.step_kinds.rope_path`)

Equations, with the known loads ``R_b`` (applied loads + d'Alembert inertia, force and moment
about the body's first point p0)::

    pin p   :  Σ_b F[p, b] − Σ_e f[e]·u_e(p) − Σ_s N[s]·n_s = 0      (2 per pin)
    body b  :  Σ_p F[p, b] − Σ_s N[s]·n_s              = −R_b        (force, 2 per body)
               Σ_p (r_p − r_p0) × F[p, b] + τ terms − Σ_s (r_P − r_p0) × N[s]·n_s = −M_b

where u_e(p) is the unit vector along the element pointing *away* from p (the element pushes
the pin at p along −u_e(p) when f > 0)::

         f > 0                              n_s = perp(l2 − l1)/|l2 − l1|
    p o<=====[cylinder]=====>o q           ^
      ← pushes       pushes →              |  N > 0 pushes P this way
                                   l1 o----P-----------o l2   (line on the carrier)

A pin is a point shared by two or more bodies, or a point of one body where an element or a
slider acts; the ground's equilibrium is not written, so the force of each pin on the ground is
an output. With a model whose driver count equals its mobility the system is square.

These equations, with the unknowns named as above, define the forces and their conventions;
`excavkin.kinetostatics.structured` solves them along the solve plan, step by step from the
last, in time linear in the model's size. Here they are assembled as a matrix
(`dense_matrix`) for the check that a model is statically determinate and for the dense
per-sample solve kept for cross-checks (``solve_forces(method="dense")``), and for a model
with gear pairs, racks or cams whose meshes the plan cannot take
(`excavkin.kinetostatics.structured.along_plan`; `dense_solve` on dual numbers).

A model whose solve plan builds (`excavkin.structure.builder.compile_plan`) is statically
determinate: each constraint is used by exactly one step, so the equilibrium's matrix is
block-triangular with one generically regular block per step; only a Newton group's block is
checked, at random positions. A model without a plan (redundant joints, an undriven freedom),
or with gear pairs, racks or cams, gets the rank check of the whole matrix, whose message
names the joints involved.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal, TypeAlias, cast

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import ExcavkinError, MobilityError
from excavkin.model.cams import Law, evaluate, lift_law
from excavkin.model.entities import Model
from excavkin.model.gears import gear_pivots, pivot_on, rack_side
from excavkin.model.validate import validate
from excavkin.step_kinds.rope_path import segment_directions
from excavkin.structure.builder import compile_plan
from excavkin.structure.plan import SolvePlan

__all__ = [
    "CamContact",
    "StaticallyIndeterminateError",
    "StaticsSystem",
    "Unknown",
    "compile_statics",
    "dense_block_solve",
    "dense_matrix",
    "dense_solve",
]


class StaticallyIndeterminateError(MobilityError):
    """The equilibrium equations do not determine the joint forces (redundant joints), or some
    loads cannot be balanced (an undriven freedom). The message names the joints involved."""


class _Var:
    """Stand-in for a per-sample value: the rows' structure (`assemble_rows` without positions)."""

    __slots__ = ()

    def __repr__(self) -> str:
        return "VAR"


VAR = _Var()
Entry: TypeAlias = "float | F | _Var"
#: A per-chunk value: a constant (float) or one value per sample (shape (c,)).
Value: TypeAlias = "float | F"


@dataclass(frozen=True, slots=True)
class Unknown:
    """One unknown of the system.

    Attributes
    ----------
    kind : {"pin", "element", "slider", "torque", "rope", "gear", "rack", "cam"}
    index : int
        Pin slot, element, slider or rotary-driver index in the system's lists.
    comp : int
        0 (x) or 1 (y) for a pin force, else 0.
    label : str
        For messages: ``"pin B on body 'rocker'"``.
    """

    kind: Literal["pin", "element", "slider", "torque", "rope", "gear", "rack", "cam"]
    index: int
    comp: int
    label: str


@dataclass(frozen=True, slots=True, eq=False)
class CamContact:
    """A cam and follower in the equilibrium (point and body indices).

    Attributes
    ----------
    name : str
    cam, follower, carrier : int
        Bodies.
    pivot, l1, l2, trace : int
        The cam's pivot, the guide's points (−1 for an oscillating follower) and the roller's
        centre (the follower's first point; an oscillating one's first point other than its
        pivot).
    cam_base : (int, int)
        The cam's first two points (its orientation).
    carrier_base : (int, int) or None
        The carrier's (None: the ground).
    sketch_turn : float
        The cam's angle from the carrier's orientation in the sketch (rad).
    face : float
        0 for a roller follower, else ±1: the flat face's normal is ``face·ê``.
    law : callable
        The lift law (`excavkin.model.cams.lift_law`).
    rocker : int
        An oscillating follower's pivot, −1 for a translating one.
    """

    name: str
    cam: int
    follower: int
    carrier: int
    pivot: int
    l1: int
    l2: int
    trace: int
    cam_base: tuple[int, int]
    carrier_base: tuple[int, int] | None
    sketch_turn: float
    face: float
    law: Law
    rocker: int = -1

    @property
    def unknowns(self) -> int:
        """3 (contact, guide force, guide couple) for a translating follower; 1 (contact)
        for an oscillating one, whose pivot is a pin."""
        return 3 if self.rocker < 0 else 1


@dataclass(frozen=True, slots=True)
class StaticsSystem:
    """The equilibrium system of a model, compiled once.

    Attributes
    ----------
    points, bodies : tuple of str
        Names in model order (the same order as the solve plan's).
    ground : int
    base : tuple of (int, int)
        Each body's first two points (moment reference p0 and orientation).
    moving : tuple of int
        Body indices whose equilibrium is written.
    nodes : tuple of int
        Point indices of the pins.
    slots : tuple of (int, int)
        (point, body) of every pin force unknown, in point order then body order.
    elements : tuple of (str, int, int, int)
        Name, first point, second point and plan-element index of each driven or locked element.
    sliders : tuple of (str, int, int, int, int)
        Name, point, l1, l2 and carrier body of each slider.
    rotary : tuple of (str, int, int)
        Name, driven body and reference body of each rotary driver.
    ropes : tuple of (str, tuple of int, tuple of float)
        Name, path points and signed sheave radii of each rope over sheaves.
    unknowns : tuple of Unknown
    rows : tuple of str
        Equation labels.
    gears : tuple of (str, int, int, int, int, float, float, float)
        Name, gear 1 and gear 2 (body indices), their pivots (point indices), the pitch
        point's fraction λ (at ``O1 + λ·(O2 − O1)``), tan φ and the radial part's sense σ (+1
        external, −1 internal) of each gear pair.
    carriers : tuple of int
        The carrier body of each gear pair.
    racks : tuple of (str, int, int, int, int, int, int, float, float, float)
        Name, rack, pinion and carrier (body indices), the pinion's pivot and the guide's two
        points (point indices), the side σ, the pitch radius and tan φ of each rack; its
        unknowns are W (comp 0), N (1) and M (2).
    cams : tuple of CamContact
        Each cam and follower; its unknowns are W (comp 0), N (1) and M (2).
    """

    points: tuple[str, ...]
    bodies: tuple[str, ...]
    ground: int
    base: tuple[tuple[int, int], ...]
    moving: tuple[int, ...]
    nodes: tuple[int, ...]
    slots: tuple[tuple[int, int], ...]
    elements: tuple[tuple[str, int, int, int], ...]
    sliders: tuple[tuple[str, int, int, int, int], ...]
    rotary: tuple[tuple[str, int, int], ...]
    unknowns: tuple[Unknown, ...]
    rows: tuple[str, ...]
    ropes: tuple[tuple[str, tuple[int, ...], tuple[float, ...]], ...] = ()
    gears: tuple[tuple[str, int, int, int, int, float, float, float], ...] = ()
    carriers: tuple[int, ...] = ()
    racks: tuple[tuple[str, int, int, int, int, int, int, float, float, float], ...] = ()
    cams: tuple[CamContact, ...] = ()

    @property
    def size(self) -> int:
        """Number of unknowns (and equations)."""
        return len(self.unknowns)

    @property
    def meshes(self) -> bool:
        """Whether the model has gear pairs, racks or cams (their tooth, contact and guide
        forces are unknowns of the dense blocks of their steps:
        `excavkin.kinetostatics.structured`)."""
        return bool(self.gears or self.racks or self.cams)

    def slot_cols(self) -> tuple[int, ...]:
        """Column of the x component of each pin slot (y is the next one)."""
        return tuple(2 * k for k in range(len(self.slots)))

    @property
    def element_col0(self) -> int:
        """Column of the first element force."""
        return 2 * len(self.slots)

    @property
    def slider_col0(self) -> int:
        """Column of the first slider normal force."""
        return self.element_col0 + len(self.elements)

    @property
    def torque_col0(self) -> int:
        """Column of the first rotary-driver torque."""
        return self.slider_col0 + len(self.sliders)

    @property
    def rope_col0(self) -> int:
        """Column of the first tension of a rope over sheaves."""
        return self.torque_col0 + len(self.rotary)

    @property
    def gear_col0(self) -> int:
        """Column of the first gear pair's tooth force."""
        return self.rope_col0 + len(self.ropes)

    @property
    def cam_col0(self) -> int:
        """Column of the first cam's contact force (then its guide's normal force and couple
        for a translating follower: `cam_cols`)."""
        return self.rack_col0 + 3 * len(self.racks)

    @property
    def cam_cols(self) -> tuple[int, ...]:
        """The column of each cam's contact force (a translating follower's guide force and
        couple follow it)."""
        out, col = [], self.cam_col0
        for cm in self.cams:
            out.append(col)
            col += cm.unknowns
        return tuple(out)

    @property
    def rack_col0(self) -> int:
        """Column of the first rack's tooth force (then its guide's normal force and couple,
        three columns a rack)."""
        return self.gear_col0 + len(self.gears)


def _structure(model: Model) -> StaticsSystem:
    points = tuple(model.points)
    pidx = {n: i for i, n in enumerate(points)}
    bodies = tuple(b.name for b in model.bodies)
    bidx = {n: i for i, n in enumerate(bodies)}
    ground = next(i for i, b in enumerate(model.bodies) if b.ground)
    base = tuple(
        (pidx[b.points[0]], pidx[b.points[1]])
        if len(b.points) >= 2
        else (pidx[b.points[0]], pidx[b.points[0]])
        for b in model.bodies
    )
    moving = tuple(j for j in range(len(bodies)) if j != ground)
    owners: dict[int, list[int]] = {i: [] for i in range(len(points))}
    for j, b in enumerate(model.bodies):
        for p in b.points:
            owners[pidx[p]].append(j)
    elements = tuple(
        (ld.name, pidx[ld.between[0]], pidx[ld.between[1]], k)
        for k, ld in enumerate(model.linear)
        if ld.mode != "free"
    )
    sliders = []
    for s in model.sliders:
        carriers = [
            j
            for j, b in enumerate(model.bodies)
            if s.along[0] in b.points and s.along[1] in b.points
        ]
        sliders.append((s.name, pidx[s.point], pidx[s.along[0]], pidx[s.along[1]], carriers[0]))
    rotary = tuple((d.name, bidx[d.body], bidx[d.reference]) for d in model.rotary)
    ropes = sheaved_ropes(model, pidx)
    acted = {e[1] for e in elements} | {e[2] for e in elements} | {s[1] for s in sliders}
    acted |= {p for r in ropes for p in r[1]}
    nodes = tuple(i for i in range(len(points)) if len(owners[i]) >= 2 or i in acted)
    slots = tuple((i, j) for i in nodes for j in owners[i])
    unknowns: list[Unknown] = []
    for k, (i, j) in enumerate(slots):
        for c in (0, 1):
            unknowns.append(Unknown("pin", k, c, f"pin {points[i]} on body {bodies[j]!r}"))
    unknowns += [
        Unknown("element", k, 0, f"linear element {e[0]!r}") for k, e in enumerate(elements)
    ]
    unknowns += [Unknown("slider", k, 0, f"slider {s[0]!r}") for k, s in enumerate(sliders)]
    unknowns += [Unknown("torque", k, 0, f"rotary driver {d[0]!r}") for k, d in enumerate(rotary)]
    unknowns += [Unknown("rope", k, 0, f"rope {r[0]!r}") for k, r in enumerate(ropes)]
    gears, gear_carriers = _gear_pairs(model, pidx, bidx)
    unknowns += [Unknown("gear", k, 0, f"gear pair {g[0]!r}") for k, g in enumerate(gears)]
    racks = _racks(model, pidx, bidx)
    unknowns += [
        Unknown("rack", k, c, f"rack {rk[0]!r} ({what})")
        for k, rk in enumerate(racks)
        for c, what in enumerate(("tooth", "guide", "guide couple"))
    ]
    cams = _cams(model, pidx, bidx)
    unknowns += [
        Unknown("cam", k, c, f"cam {cm.name!r} ({what})")
        for k, cm in enumerate(cams)
        for c, what in enumerate(("contact", "guide", "guide couple")[: cm.unknowns])
    ]
    rows = [f"pin {points[i]} ({'xy'[c]})" for i in nodes for c in (0, 1)]
    for j in moving:
        rows += [
            f"body {bodies[j]!r} (force x)",
            f"body {bodies[j]!r} (force y)",
            f"body {bodies[j]!r} (moment)",
        ]
    return StaticsSystem(
        points,
        bodies,
        ground,
        base,
        moving,
        nodes,
        tuple(slots),
        elements,
        tuple(sliders),
        rotary,
        tuple(unknowns),
        tuple(rows),
        ropes=ropes,
        gears=gears,
        carriers=gear_carriers,
        racks=racks,
        cams=cams,
    )


def _gear_pairs(
    model: Model, pidx: dict[str, int], bidx: dict[str, int]
) -> tuple[tuple[tuple[str, int, int, int, int, float, float, float], ...], tuple[int, ...]]:
    """Each gear pair's bodies, pivots, pitch fraction, tan φ and radial sense; its carrier."""
    out = []
    for g in model.gears:
        p1, p2 = gear_pivots(model, g)
        out.append(
            (
                g.name,
                bidx[g.gears[0]],
                bidx[g.gears[1]],
                pidx[p1],
                pidx[p2],
                g.pitch_fraction,
                math.tan(g.pressure_angle),
                -1.0 if g.internal else 1.0,
            )
        )
    return tuple(out), tuple(bidx[g.carrier] for g in model.gears)


def _racks(
    model: Model, pidx: dict[str, int], bidx: dict[str, int]
) -> tuple[tuple[str, int, int, int, int, int, int, float, float, float], ...]:
    """Each rack's bodies, pivot, guide, side, pitch radius and tan φ."""
    out = []
    for rk in model.racks:
        pivot = pivot_on(model, rk.pinion, rk.carrier, f"racks.{rk.name}", "pinion")
        out.append(
            (
                rk.name,
                bidx[rk.rack],
                bidx[rk.pinion],
                bidx[rk.carrier],
                pidx[pivot],
                pidx[rk.along[0]],
                pidx[rk.along[1]],
                rack_side(model, rk),
                rk.radius,
                math.tan(rk.pressure_angle),
            )
        )
    return tuple(out)


def _cams(model: Model, pidx: dict[str, int], bidx: dict[str, int]) -> tuple[CamContact, ...]:
    """Each cam's bodies, points, sketch turn, face and lift law."""
    out = []
    sk = model.points
    for cm in model.cams:
        pivot = pivot_on(model, cm.cam, cm.carrier, f"cams.{cm.name}", "cam")
        cam, carrier = model.body(cm.cam), model.body(cm.carrier)
        follower = model.body(cm.follower)
        rocker = -1
        if cm.along is None:
            swing = pivot_on(model, cm.follower, cm.carrier, f"cams.{cm.name}", "follower")
            rocker = pidx[swing]
            trace = next(n for n in follower.points if n != swing)
            guide = (-1, -1)
        else:
            trace = follower.points[0]
            guide = (pidx[cm.along[0]], pidx[cm.along[1]])
        (c0x, c0y), (c1x, c1y) = sk[cam.points[0]], sk[cam.points[1]]
        kx, ky = 1.0, 0.0
        if not carrier.ground:
            (k0x, k0y), (k1x, k1y) = sk[carrier.points[0]], sk[carrier.points[1]]
            kx, ky = k1x - k0x, k1y - k0y
        cx, cy = c1x - c0x, c1y - c0y
        face = 0.0
        if cm.face == "flat" and cm.along is not None:
            (ax, ay), (bx, by) = sk[cm.along[0]], sk[cm.along[1]]
            dot = (sk[trace][0] - sk[pivot][0]) * (bx - ax)
            face = math.copysign(1.0, dot + (sk[trace][1] - sk[pivot][1]) * (by - ay))
        out.append(
            CamContact(
                cm.name,
                bidx[cm.cam],
                bidx[cm.follower],
                bidx[cm.carrier],
                pidx[pivot],
                guide[0],
                guide[1],
                pidx[trace],
                (pidx[cam.points[0]], pidx[cam.points[1]]),
                None if carrier.ground else (pidx[carrier.points[0]], pidx[carrier.points[1]]),
                math.atan2(kx * cy - ky * cx, kx * cx + ky * cy),
                face,
                lift_law(cm.lift),
                rocker,
            )
        )
    return tuple(out)


def cam_normal(cm: CamContact, x: Any) -> tuple[Any, Any, Any, Any, Any, Any, Any, Any]:
    """A cam's contact geometry at positions ``x``: the guide's unit vector ê, the contact
    normal n (on the follower) and the instant centre I of the cam and the follower, through
    which the contact force acts: ``I = O − s'(θ)·perp(ê)``, with θ the cam's turn from the
    sketch (from the positions, modulo a turn: the law is periodic) and, for a roller, ``n``
    from I to the roller's centre, for a flat face ``n = ±ê``. For an oscillating follower (ê
    is returned as 0) I is ``(Oc − ψ'·Of)/(1 − ψ')`` and the force acts at the roller's centre
    B along ``(B − Oc) − ψ'·(B − Of)`` (I is returned as B: a point of the line).

    Parameters
    ----------
    cm : CamContact
        The cam.
    x : ndarray or dual number, shape (n_points, 2, c)
        Positions.

    Returns
    -------
    tuple
        ``ex, ey, nx, ny, ix, iy, bx, by``: ê, n, I and the follower's first point.
    """
    c0, c1 = cm.cam_base
    cx, cy = x[c1, 0] - x[c0, 0], x[c1, 1] - x[c0, 1]
    if cm.carrier_base is None:
        turn = np.arctan2(cy, cx)
    else:
        k0, k1 = cm.carrier_base
        kx, ky = x[k1, 0] - x[k0, 0], x[k1, 1] - x[k0, 1]
        turn = np.arctan2(kx * cy - ky * cx, kx * cx + ky * cy)
    _, s1, _ = evaluate(cm.law, turn - cm.sketch_turn, cm.name)
    bx, by = x[cm.trace, 0], x[cm.trace, 1]
    if cm.rocker >= 0:  # n along (B − Oc) − ψ'·(B − Of): from I, (Oc − ψ'·Of)/(1 − ψ'), to B
        f = cm.rocker
        nx = bx - x[cm.pivot, 0] - s1 * (bx - x[f, 0])
        ny = by - x[cm.pivot, 1] - s1 * (by - x[f, 1])
        inv = 1.0 / np.sqrt(nx * nx + ny * ny)
        return 0.0, 0.0, nx * inv, ny * inv, bx, by, bx, by
    ex, ey = x[cm.l2, 0] - x[cm.l1, 0], x[cm.l2, 1] - x[cm.l1, 1]
    inv = 1.0 / np.sqrt(ex * ex + ey * ey)
    ex, ey = ex * inv, ey * inv
    ix, iy = x[cm.pivot, 0] + s1 * ey, x[cm.pivot, 1] - s1 * ex
    if cm.face:
        nx, ny = cm.face * ex, cm.face * ey
    else:
        nx, ny = bx - ix, by - iy
        inv = 1.0 / np.sqrt(nx * nx + ny * ny)
        nx, ny = nx * inv, ny * inv
    return ex, ey, nx, ny, ix, iy, bx, by


def sheaved_ropes(
    model: Model, pidx: dict[str, int]
) -> tuple[tuple[str, tuple[int, ...], tuple[float, ...]], ...]:
    """Each rope over sheaves: its name, path points and signed sheave radii (0 at the ends).

    Parameters
    ----------
    model : Model
    pidx : dict
        Point indices by name.

    Returns
    -------
    tuple of (str, tuple of int, tuple of float)
    """
    out = []
    for r in model.ropes:
        if r.over_sheaves:
            signed = tuple(s if w == "ccw" else -s for s, w in zip(r.radii, r.wraps, strict=True))
            out.append((r.name, tuple(pidx[p] for p in r.path), (0.0, *signed, 0.0)))
    return tuple(out)


def assemble_rows(sy: StaticsSystem, x: F | None) -> list[dict[int, Entry]]:
    """The coefficient rows of the equilibrium equations, one dict of column → entry per row.

    Parameters
    ----------
    sy : StaticsSystem
        The system's rows and unknowns.
    x : ndarray, shape (n_points, 2, c), or None
        Point positions of a chunk of c samples; None for the structure only (unknown
        entries are ``VAR``).

    Returns
    -------
    list of dict
        Row k's entries by column.
    """
    rows: list[dict[int, Entry]] = [{} for _ in sy.rows]
    node_row = {i: 2 * k for k, i in enumerate(sy.nodes)}
    body_row = {j: 2 * len(sy.nodes) + 3 * m for m, j in enumerate(sy.moving)}

    def diff(i: int, k: int, c: int) -> Entry:
        return VAR if x is None else x[k, c] - x[i, c]

    for k, (i, j) in enumerate(sy.slots):
        r = node_row[i]
        rows[r][2 * k] = 1.0
        rows[r + 1][2 * k + 1] = 1.0
        if j in body_row:
            rb = body_row[j]
            rows[rb][2 * k] = 1.0
            rows[rb + 1][2 * k + 1] = 1.0
            i0 = sy.base[j][0]
            if i != i0:  # moment about p0: (r_p − r_p0) × F = dx·Fy − dy·Fx
                dy = diff(i0, i, 1)
                rows[rb + 2][2 * k] = dy if isinstance(dy, _Var) else -dy
                rows[rb + 2][2 * k + 1] = diff(i0, i, 0)
    col = sy.element_col0
    for k, (_, p, q, _) in enumerate(sy.elements):
        if x is None:
            ux: Entry = VAR
            uy: Entry = VAR
        else:
            dx, dy = x[q, 0] - x[p, 0], x[q, 1] - x[p, 1]
            inv = 1.0 / np.sqrt(dx * dx + dy * dy)
            ux, uy = dx * inv, dy * inv
        # node p: the element pushes p along −u (term −f·(−u) = +u); node q: along +u (−u)
        for node, sign in ((p, 1.0), (q, -1.0)):
            r = node_row[node]
            rows[r][col + k] = ux if isinstance(ux, _Var) else sign * ux
            rows[r + 1][col + k] = uy if isinstance(uy, _Var) else sign * uy
    col = sy.slider_col0
    for k, (_, pt, l1, l2, carrier) in enumerate(sy.sliders):
        if x is None:
            nx: Entry = VAR
            ny: Entry = VAR
        else:
            ex, ey = x[l2, 0] - x[l1, 0], x[l2, 1] - x[l1, 1]
            inv = 1.0 / np.sqrt(ex * ex + ey * ey)
            nx, ny = -ey * inv, ex * inv
        r = node_row[pt]
        neg_nx = nx if isinstance(nx, _Var) else -nx
        neg_ny = ny if isinstance(ny, _Var) else -ny
        rows[r][col + k] = neg_nx
        rows[r + 1][col + k] = neg_ny
        if carrier in body_row:
            rb = body_row[carrier]
            rows[rb][col + k] = neg_nx
            rows[rb + 1][col + k] = neg_ny
            i0 = sy.base[carrier][0]
            if x is None:
                rows[rb + 2][col + k] = VAR
            else:  # moment of −N·n at P about p0: −(dx·ny − dy·nx)
                dx, dy = x[pt, 0] - x[i0, 0], x[pt, 1] - x[i0, 1]
                rows[rb + 2][col + k] = dy * nx - dx * ny
    col = sy.torque_col0
    for k, (_, body, ref) in enumerate(sy.rotary):
        if body in body_row:
            rows[body_row[body] + 2][col + k] = 1.0
        if ref in body_row:
            rows[body_row[ref] + 2][col + k] = -1.0
    col = sy.rope_col0
    for k, (_, path, signed) in enumerate(sy.ropes):
        # the rope pulls the pin at path point j with T·(u_j − u_{j−1}): the entry is minus that
        if x is None:
            for node in path:
                r = node_row[node]
                rows[r][col + k] = rows[r + 1][col + k] = VAR
            continue
        dirs = segment_directions([(x[p, 0], x[p, 1]) for p in path], signed)
        last = len(path) - 1
        for j, node in enumerate(path):
            r = node_row[node]
            for c, u in enumerate(dirs):
                entry: Any = -u[j] if j == 0 else u[j - 1] if j == last else u[j - 1] - u[j]
                old: Any = rows[r + c].get(col + k)
                rows[r + c][col + k] = entry if old is None else old + entry
    _gear_rows(sy, x, rows, body_row)
    _rack_rows(sy, x, rows, body_row)
    _cam_rows(sy, x, rows, body_row)
    return rows


def _cam_rows(
    sy: StaticsSystem, x: F | None, rows: list[dict[int, Entry]], body_row: dict[int, int]
) -> None:
    """Each cam's contact force W·n through the instant centre I (on the follower; −W·n on
    the cam), its guide's force N·perp(ê) at the follower's first point (on the follower;
    the opposite on the carrier) and its guide's couple M."""
    for cm, w in zip(sy.cams, sy.cam_cols, strict=True):
        n, m = w + 1, w + 2
        geo = None if x is None else cam_normal(cm, x)
        forces = ((cm.follower, w, 1.0), (cm.cam, w, -1.0), (cm.follower, n, 1.0),
                  (cm.carrier, n, -1.0))[: 2 if cm.rocker >= 0 else 4]  # fmt: skip
        for body, c, sign in forces:
            if body not in body_row:
                continue
            rb = body_row[body]
            if geo is None:
                for row in (rb, rb + 1, rb + 2):
                    rows[row][c] = VAR
                continue
            ex, ey, nx, ny, ix, iy, bx, by = geo
            assert x is not None
            if c == w:
                ux, uy, px, py = sign * nx, sign * ny, ix, iy
            else:
                ux, uy, px, py = -sign * ey, sign * ex, bx, by
            i0 = sy.base[body][0]
            dx, dy = px - x[i0, 0], py - x[i0, 1]
            rows[rb][c] = ux
            rows[rb + 1][c] = uy
            rows[rb + 2][c] = dx * uy - dy * ux
        if cm.rocker >= 0:
            continue
        if cm.follower in body_row:
            rows[body_row[cm.follower] + 2][m] = 1.0
        if cm.carrier in body_row:
            rows[body_row[cm.carrier] + 2][m] = -1.0


def _rack_rows(
    sy: StaticsSystem, x: F | None, rows: list[dict[int, Entry]], body_row: dict[int, int]
) -> None:
    """Each rack's tooth force W·ê (on the rack; −W·ê on the pinion) and guide force N·n̂
    (on the rack; −N·n̂ on the carrier), both at the pitch point P = O + σ·r·n̂, and its
    guide's couple M (on the rack; −M on the carrier): ê along the guide, n̂ = perp(ê)."""
    col = sy.rack_col0
    for k, (_, rack, pinion, carrier, o, l1, l2, side, r, _) in enumerate(sy.racks):
        w, n, m = col + 3 * k, col + 3 * k + 1, col + 3 * k + 2
        # (body, column, sign, along the guide?) of each force; then the couples
        forces = ((rack, w, 1.0, True), (pinion, w, -1.0, True), (rack, n, 1.0, False),
                  (carrier, n, -1.0, False))  # fmt: skip
        for body, c, sign, along in forces:
            if body not in body_row:
                continue
            rb = body_row[body]
            if x is None:
                for row in (rb, rb + 1, rb + 2):
                    rows[row][c] = VAR
                continue
            ex, ey = x[l2, 0] - x[l1, 0], x[l2, 1] - x[l1, 1]
            inv = 1.0 / np.sqrt(ex * ex + ey * ey)
            ex, ey = ex * inv, ey * inv
            ux, uy = (ex, ey) if along else (-ey, ex)
            ux, uy = sign * ux, sign * uy
            i0 = sy.base[body][0]
            dx = x[o, 0] - (side * r) * ey - x[i0, 0]
            dy = x[o, 1] + (side * r) * ex - x[i0, 1]
            rows[rb][c] = ux
            rows[rb + 1][c] = uy
            rows[rb + 2][c] = dx * uy - dy * ux
        if rack in body_row:
            rows[body_row[rack] + 2][m] = 1.0
        if carrier in body_row:
            rows[body_row[carrier] + 2][m] = -1.0


def _gear_rows(
    sy: StaticsSystem, x: F | None, rows: list[dict[int, Entry]], body_row: dict[int, int]
) -> None:
    """Each gear pair's tooth force in the force and moment rows of its two gears: +W·t on
    gear 2, −W·t on gear 1, at the pitch point P = O1 + λ·(O2 − O1)."""
    col = sy.gear_col0
    for k, (_, b1, b2, o1, o2, lam, _, _) in enumerate(sy.gears):
        for body, sign in ((b1, -1.0), (b2, 1.0)):
            if body not in body_row:
                continue
            rb = body_row[body]
            if x is None:
                for r in (rb, rb + 1, rb + 2):
                    rows[r][col + k] = VAR
                continue
            ex, ey = x[o2, 0] - x[o1, 0], x[o2, 1] - x[o1, 1]
            inv = 1.0 / np.sqrt(ex * ex + ey * ey)
            tx, ty = sign * (-ey * inv), sign * (ex * inv)
            i0 = sy.base[body][0]
            dx = x[o1, 0] + lam * ex - x[i0, 0]
            dy = x[o1, 1] + lam * ey - x[i0, 1]
            rows[rb][col + k] = tx
            rows[rb + 1][col + k] = ty
            rows[rb + 2][col + k] = dx * ty - dy * tx


def compile_statics(
    model: Model, *, seed: int = 20240601, plan: SolvePlan | None = None
) -> StaticsSystem:
    """Build the equilibrium system of ``model`` and check that it is statically determinate.

    A model whose solve plan builds is determinate (a Newton group's block is checked at random
    positions); otherwise the generic rank of the whole system is checked at random positions
    of the points (any positions: the equilibrium matrix depends only on them): a rank deficit
    there holds at every configuration, and is reported with the joints involved.

    Parameters
    ----------
    model : Model
    seed : int
        For the random positions of the rank checks (reproducible).
    plan : SolvePlan, optional
        The model's solve plan, if compiled already (compiled here if not given).

    Returns
    -------
    StaticsSystem

    Raises
    ------
    StaticallyIndeterminateError
        Redundant joints (forces the equations leave free) or an undriven freedom (loads the
        joints cannot carry), naming them.
    """
    sy = _structure(model)
    from excavkin.kinetostatics.structured import determinate  # (it solves this system)

    if plan is None:
        try:
            validate(model)
            plan = compile_plan(model)
        except ExcavkinError:
            plan = None
    if plan is None or sy.meshes or not determinate(plan, sy, seed):
        _check_rank(sy, model, seed)
    return sy


def dense_matrix(sy: StaticsSystem, x: F) -> F:
    """The equilibrium matrix for each sample, shape (n, n_rows, n_unknowns).

    Parameters
    ----------
    x : ndarray, shape (n_points, 2, n)
        Point positions.
    """
    n = x.shape[-1]
    rows = assemble_rows(sy, x)
    out = np.zeros((n, len(sy.rows), len(sy.unknowns)))
    for r, row in enumerate(rows):
        for c, v in row.items():
            out[:, r, c] = v  # type: ignore[assignment]
    return out


def dense_solve(
    sy: StaticsSystem,
    x: F,
    rhs_body: list[tuple[Value, Value, Value]],
    *,
    rel_tol: float = 1e-12,
) -> tuple[list[F], np.ndarray]:
    """The whole equilibrium of a chunk of samples by Gaussian elimination (`dense_block_solve`).

    The sensitivities' path (on dual numbers, which LAPACK cannot take) for a model with gear
    pairs, racks or cams whose meshes the plan cannot take
    (`excavkin.kinetostatics.structured.along_plan`).

    Parameters
    ----------
    sy : StaticsSystem
        The equilibrium system.
    x : ndarray or dual number, shape (n_points, 2, c)
        Point positions of the chunk.
    rhs_body : list of (float or ndarray, ...)
        Per moving body (in ``sy.moving`` order), the known force x, y and moment about its
        first point (`excavkin.kinetostatics.body_loads.body_loads`).
    rel_tol : float
        A sample is singular where a pivot is below ``rel_tol`` times the largest entry.

    Returns
    -------
    solution : list of ndarray or dual number, shape (c,)
        One entry per unknown, in the system's order.
    singular : ndarray of bool, shape (c,)
    """
    rows = assemble_rows(sy, x)
    a: list[list[Entry]] = [[row.get(col, 0.0) for col in range(sy.size)] for row in rows]
    b: list[Entry] = [0.0] * (2 * len(sy.nodes))
    for fx, fy, mz in rhs_body:
        b += [-fx, -fy, -mz]
    return _dense_solve(a, b, x.shape[-1], rel_tol)


def _check_rank(sy: StaticsSystem, model: Model, seed: int) -> None:
    rng = np.random.default_rng(seed)
    sk = np.asarray([model.points[p] for p in sy.points], dtype=np.float64)
    span = float(np.ptp(sk, axis=0).max()) if len(sk) > 1 else 1.0
    span = span if span > 0 else 1.0
    for _ in range(16):  # a rope over sheaves has no tangent where two sheaves overlap: redraw
        x = (sk + span * rng.standard_normal(sk.shape))[:, :, None]
        with np.errstate(invalid="ignore"):
            a = dense_matrix(sy, x)[0]
        if np.isfinite(a).all():
            break
    m, n = a.shape
    u, s, vt = np.linalg.svd(a)
    tol = max(m, n) * np.finfo(float).eps * 1e3 * (s[0] if s.size else 1.0)
    rank = int(np.sum(s > tol))
    if rank == n == m:
        return
    parts = []
    if rank < n:
        null = vt[rank:]
        weight = np.sqrt(np.sum(null * null, axis=0))
        involved = [sy.unknowns[c] for c in np.flatnonzero(weight > 1e-8)]
        joints = list(dict.fromkeys(u_.label for u_ in involved))
        parts.append(
            f"statically indeterminate: {n - rank} redundant constraint"
            f"{'s' if n - rank > 1 else ''} — the forces in {', '.join(joints)} can be in "
            "equilibrium with no load, so the equations do not fix them (remove one of these "
            "joints, or make a cylinder 'free')"
        )
    if rank < m:
        left = u[:, rank:]
        weight = np.sqrt(np.sum(left * left, axis=1))
        eqs = list(dict.fromkeys(sy.rows[r].split(" (")[0] for r in np.flatnonzero(weight > 1e-8)))
        parts.append(
            f"{m - rank} load case{'s' if m - rank > 1 else ''} cannot be balanced at "
            f"{', '.join(eqs)} (a freedom without a driver)"
        )
    raise StaticallyIndeterminateError("; ".join(parts), table="bodies", source=model.source)


def _as_array(v: Entry, c: int) -> F:
    if isinstance(v, float):
        return np.full(c, v)
    assert not isinstance(v, _Var)
    return v


def dense_block_solve(
    a: list[list[Value]], b: list[Value], c: int, rel_tol: float
) -> tuple[list[F], np.ndarray]:
    """Solve ``a·y = b`` for c samples at once by Gaussian elimination with partial pivoting.

    Parameters
    ----------
    a : list of list of (float or ndarray of shape (c,))
        The square matrix, row by row (a float: the same for every sample).
    b : list of (float or ndarray of shape (c,))
        The right-hand side.
    c : int
        Number of samples.
    rel_tol : float
        A sample is singular where a pivot is below ``rel_tol`` times the largest entry.

    Returns
    -------
    y : list of ndarray, shape (c,)
        One array per unknown.
    singular : ndarray of bool, shape (c,)
    """
    return _dense_solve(cast("list[list[Entry]]", a), cast("list[Entry]", b), c, rel_tol)


def _dense_solve(
    a: list[list[Entry]], b: list[Entry], c: int, rel_tol: float
) -> tuple[list[F], np.ndarray]:
    """Gaussian elimination with partial pivoting, vectorised over c samples (struct of arrays).

    Returns the solution (one array per unknown) and a mask of singular samples.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        return _dense_solve_unguarded(a, b, c, rel_tol)


def _dense_solve_unguarded(
    a: list[list[Entry]], b: list[Entry], c: int, rel_tol: float
) -> tuple[list[F], np.ndarray]:
    r = len(b)
    m = [[_as_array(v, c) for v in row] for row in a]
    rhs = [_as_array(v, c) for v in b]
    scale = np.zeros(c)
    for row in m:
        for v in row:  # (a dual number's value: the scale of a derivative pass is its values')
            np.maximum(scale, np.abs(getattr(v, "val", v)), out=scale)
    singular = np.zeros(c, dtype=bool)
    for k in range(r):
        for i in range(k + 1, r):
            swap = np.abs(m[i][k]) > np.abs(m[k][k])
            if swap.any():
                for j in range(k, r):
                    m[k][j], m[i][j] = (
                        np.where(swap, m[i][j], m[k][j]),
                        np.where(swap, m[k][j], m[i][j]),
                    )
                rhs[k], rhs[i] = np.where(swap, rhs[i], rhs[k]), np.where(swap, rhs[k], rhs[i])
        piv = m[k][k]
        singular |= np.abs(piv) <= rel_tol * scale
        inv = 1.0 / piv
        for i in range(k + 1, r):
            f = m[i][k] * inv
            for j in range(k + 1, r):
                m[i][j] = m[i][j] - f * m[k][j]
            rhs[i] = rhs[i] - f * rhs[k]
    sol: list[F] = [np.empty(0)] * r
    for k in range(r - 1, -1, -1):
        acc = rhs[k]
        for j in range(k + 1, r):
            acc = acc - m[k][j] * sol[j]
        sol[k] = acc / m[k][k]
    return sol, singular
