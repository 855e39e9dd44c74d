r"""Equilibrium of every moving body and every pin: one sparse linear system per sample.

Unknowns (DESIGN.md §5)::

    F[p, b] = (Fx, Fy)  the force the pin at point p exerts on body b, for every body at p
    f[e]                the axial force of each driven or locked linear element (> 0 pushes
                        its two points apart; a rope in tension is negative)
    N[s]                the normal force of each slider, along perp(l2 − l1), on the slider's
                        point (its reaction −N acts on the body that carries the line)
    τ[d]                the torque of each rotary driver on its body (−τ on its reference body)
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
per-sample solve kept for cross-checks (``solve_forces(method="dense")``).

A model whose solve plan builds (`excavkin.structure.builder.compile_plan`) is statically
determinate: each constraint is used by exactly one step, so the equilibrium's matrix is
block-triangular with one generically regular block per step; only a Newton group's block is
checked, at random positions. A model without a plan (redundant joints, an undriven freedom)
gets the rank check of the whole matrix, whose message names the joints involved.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal, TypeAlias, cast

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import ExcavkinError, MobilityError
from excavkin.model.entities import Model
from excavkin.model.validate import validate
from excavkin.step_kinds.rope_path import segment_directions
from excavkin.structure.builder import compile_plan
from excavkin.structure.plan import SolvePlan

__all__ = [
    "StaticallyIndeterminateError",
    "StaticsSystem",
    "Unknown",
    "compile_statics",
    "dense_block_solve",
    "dense_matrix",
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
    kind : {"pin", "element", "slider", "torque", "rope"}
    index : int
        Pin slot, element, slider or rotary-driver index in the system's lists.
    comp : int
        0 (x) or 1 (y) for a pin force, else 0.
    label : str
        For messages: ``"pin B on body 'rocker'"``.
    """

    kind: Literal["pin", "element", "slider", "torque", "rope"]
    index: int
    comp: int
    label: str


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

    @property
    def size(self) -> int:
        """Number of unknowns (and equations)."""
        return len(self.unknowns)

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
    )


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
    return rows


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
    if plan is None or not determinate(plan, sy, seed):
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
