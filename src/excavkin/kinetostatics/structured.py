r"""The equilibrium solved along the solve plan: back-substitution over its steps, linear in size.

The solve plan (`excavkin.structure.plan`) orders the constraints: each step fixes its own
points from points already known, and every constraint is used by exactly one step. Written
as constraint equations ``g(x) = 0`` of the point coordinates, the equilibrium of the moving
points is

    Σ_c λ_c ∇_p g_c + L_p = 0        for every moving point p (2 equations)

with one multiplier λ_c per scalar constraint and ``L_p`` the applied loads and d'Alembert
inertia at p. A constraint of step s touches the points of s and points known before it, so
the transposed Jacobian is block-triangular in the plan's order: taking the steps last to
first, the multipliers of step s solve the small system of its own points' balance,

    Σ_{c ∈ s} λ_c ∇_{P_s} g_c = −(L_{P_s} + Σ_{c after s} λ_c ∇_{P_s} g_c)

— 2×2 for a rotate, attach, dyad or slider point (attach: the identity), a dense block for a
Newton group — vectorised over the samples. The cost is linear in the model's size.

The constraints, their gradients and the forces they stand for (``perp(v) = (−v_y, v_x)``)::

    distance |P − Q|          ∇_P = u = (P − Q)/|P − Q|, ∇_Q = −u;  λ = the element's axial
                              force f (> 0 pushes apart), or a body's internal force
    frame  P = a + s·v + t·perp(v), v = b − a   (a body's point attached to two others)
                              ∇_P = I, ∇_a = −(1 − s)·I + t·Jᵀ, ∇_b = −s·I − t·Jᵀ per row
    angle  θ(P − pivot) − θ(r1 − r0) − q      ∇_P = perp(d)/|d|² = −∇_pivot, d = P − pivot;
                              ∇_r1 = −perp(e)/|e|² = −∇_r0;  λ = the driver's torque τ
    line   cross(e, P − l1)/|e|, e = l2 − l1  ∇_P = n = perp(e)/|e|; ∇_l2 = −perp(w)/|e|,
                              ∇_l1 = (perp(w) − perp(e))/|e|, w = P − l1;  λ = the slider's N
    rope   −L, L a rope's length over sheaves   ∇_{c_k} = u_k − u_{k−1}, u_k its free segments'
                              directions (`excavkin.step_kinds.rope_path`);  λ = its tension T,
                              pulling each path point's pin

Each set of forces a constraint puts on a body is statically equivalent to what the pin
equations of `excavkin.kinetostatics.equilibrium` put on it: a driver's forces at P and the
pivot are a couple τ (at r0, r1 a couple −τ on the reference body); a slider's forces at l1
and l2 are the reaction −N·n at P's place. So are the loads: a body's force and moment about
its first point p0 act as the force at p0 and a couple of forces at p0 and p1. The pin forces
then follow without any further solve: the force of the pin at p on a moving body b balances
everything that acts on b at p,

    F[p, b] = −(loads of b at p + Σ_{c of b} λ_c ∇_p g_c)

(a constraint of b: its shape's distances and frames, the couples of the drivers on it, the
reactions of the sliders it carries), and the ground's share follows from the pin's balance,
``Σ_b F[p, b] = the forces of the elements and sliders on the pin``. The results equal the
pin equations' solution to round-off (a statically determinate model has one).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.kinetostatics.equilibrium import StaticsSystem, Value, dense_block_solve
from excavkin.step_kinds.rope_path import segment_directions
from excavkin.structure.plan import (
    Attach,
    CAngle,
    CDist,
    CFrame,
    CLine,
    CRope,
    Dist,
    Dyad,
    Fixed,
    NewtonGroup,
    Rotate,
    SliderStep,
    SolvePlan,
)

__all__ = [
    "Arithmetic",
    "determinate",
    "StructuredSystem",
    "back_substitute",
    "compile_structured",
    "solve_structured",
]

#: the owner of a constraint's force at a point: a body index, or PIN (the point's own pin:
#: an element's or a slider's force, which acts on the pin and not on a body)
PIN = -1

#: a dyad or slider point is singular where the sine of its two directions is below this
SINGULAR_SINE = 1e-12


@dataclass(frozen=True, slots=True)
class Scalar:
    """One scalar constraint of a step.

    Attributes
    ----------
    kind : {"dist", "frame_x", "frame_y", "angle", "line", "rope"}
    points : tuple of int
        The points it touches (see the module docstring for each kind's order).
    owners : tuple of int
        Per touched point, the body its force there acts on, or PIN.
    column : int
        The unknown of the equilibrium system it gives (an element's force, a slider's normal
        force, a driver's torque, a rope's tension), or −1 (a body's internal force).
    signed : tuple of float
        A rope's signed sheave radius at each of its points (0 at its ends); empty otherwise.
    """

    kind: str
    points: tuple[int, ...]
    owners: tuple[int, ...]
    column: int
    signed: tuple[float, ...] = ()


@dataclass(frozen=True, slots=True)
class Block:
    """One step of the plan for the back-substitution: its points and its constraints."""

    points: tuple[int, ...]
    scalars: tuple[Scalar, ...]
    can_be_singular: bool


@dataclass(frozen=True, slots=True)
class StructuredSystem:
    """The plan's steps as blocks of the equilibrium, with the output layout of ``system``.

    Attributes
    ----------
    system : StaticsSystem
        The unknowns' layout (pin slots, elements, sliders, rotary drivers).
    blocks : tuple of Block
        In the plan's order (solved last to first).
    slot_of : dict of (int, int) to int
        The pin slot of (point, body).
    """

    system: StaticsSystem
    blocks: tuple[Block, ...]
    slot_of: dict[tuple[int, int], int]


def compile_structured(plan: SolvePlan, sy: StaticsSystem) -> StructuredSystem:
    """The blocks of the back-substitution, from a plan and the equilibrium system's layout.

    Parameters
    ----------
    plan : SolvePlan
        The kinematic plan whose steps order the constraints.
    sy : StaticsSystem
        The equilibrium system of the plan's model (its unknowns' layout).

    Returns
    -------
    StructuredSystem

    Raises
    ------
    InputError
        The system is of another model than the plan.
    """
    if plan.points != sy.points or plan.bodies != sy.bodies:
        raise InputError("the equilibrium system belongs to another model than the solve plan")
    body = {name: j for j, name in enumerate(sy.bodies)}
    element_col = {e[3]: sy.element_col0 + k for k, e in enumerate(sy.elements)}
    by_pair = {frozenset((el.p, el.q)): k for k, el in enumerate(plan.elements)}
    by_input = {el.input: k for k, el in enumerate(plan.elements) if el.mode == "driven"}
    rotary = {name: (sy.torque_col0 + k, b, r) for k, (name, b, r) in enumerate(sy.rotary)}
    sliders = {
        (pt, l1, l2): (sy.slider_col0 + k, carrier)
        for k, (_, pt, l1, l2, carrier) in enumerate(sy.sliders)
    }

    def dist(p: int, q: int, d: Dist) -> Scalar:
        if d.body:
            j = body[d.body]
            return Scalar("dist", (p, q), (j, j), -1)
        k = by_input[d.input] if d.kind == "input" else by_pair[frozenset((p, q))]
        return Scalar("dist", (p, q), (PIN, PIN), element_col[k])

    def frame(p: int, a: int, b: int, name: str) -> tuple[Scalar, Scalar]:
        j = body[name]
        return (
            Scalar("frame_x", (p, a, b), (j, j, j), -1),
            Scalar("frame_y", (p, a, b), (j, j, j), -1),
        )

    def angle(p: int, pivot: int, ref: tuple[int, int] | None, driver: str) -> Scalar:
        col, driven, reference = rotary[driver]
        if ref is None:
            return Scalar("angle", (p, pivot), (driven, driven), col)
        return Scalar("angle", (p, pivot, *ref), (driven, driven, reference, reference), col)

    def line(p: int, l1: int, l2: int) -> Scalar:
        col, carrier = sliders[(p, l1, l2)]
        return Scalar("line", (p, l1, l2), (PIN, carrier, carrier), col)

    blocks: list[Block] = []
    for st in plan.steps:
        if isinstance(st, Fixed):
            continue
        if isinstance(st, Rotate):
            col, driven, _ = rotary[st.driver]
            radius = Scalar("dist", (st.point, st.pivot), (driven, driven), -1)
            blocks.append(
                Block((st.point,), (radius, angle(st.point, st.pivot, st.ref, st.driver)), False)
            )
        elif isinstance(st, Attach):
            blocks.append(Block((st.point,), frame(st.point, st.a, st.b, st.body), False))
        elif isinstance(st, Dyad):
            pair = (dist(st.point, st.a, st.da), dist(st.point, st.b, st.db))
            blocks.append(Block((st.point,), pair, True))
        elif isinstance(st, SliderStep):
            blocks.append(
                Block(
                    (st.point,),
                    (dist(st.point, st.a, st.da), line(st.point, st.l1, st.l2)),
                    True,
                )
            )
        else:
            assert isinstance(st, NewtonGroup)
            scalars: list[Scalar] = []
            for c in st.constraints:
                if isinstance(c, CDist):
                    scalars.append(dist(c.p, c.q, c.dist))
                elif isinstance(c, CFrame):
                    scalars.extend(frame(c.p, c.a, c.b, c.body))
                elif isinstance(c, CLine):
                    scalars.append(line(c.p, c.l1, c.l2))
                elif isinstance(c, CRope):
                    scalars.append(_rope(sy, c))
                else:
                    assert isinstance(c, CAngle)
                    driver = plan.inputs[c.input]
                    scalars.append(angle(c.p, c.pivot, c.ref, driver))
            blocks.append(Block(st.points, tuple(scalars), True))
    slot_of = {s: k for k, s in enumerate(sy.slots)}
    return StructuredSystem(sy, tuple(blocks), slot_of)


def _rope(sy: StaticsSystem, c: CRope) -> Scalar:
    """A rope's constraint: its tension (its column of the system) acts on its path's pins."""
    col = sy.rope_col0 + [r[0] for r in sy.ropes].index(c.name)
    return Scalar("rope", c.points, (PIN,) * len(c.points), col, c.signed)


def determinate(plan: SolvePlan, sy: StaticsSystem, seed: int = 20240601) -> bool:
    """Whether the plan shows the equilibrium determinate: every closed-form step's block is
    regular wherever the step assembles, and each Newton group's block has full rank at
    random positions of the points.

    Parameters
    ----------
    plan : SolvePlan
        A plan of the system's model.
    sy : StaticsSystem
        The equilibrium system's layout.
    seed : int
        For the random positions.

    Returns
    -------
    bool
    """
    ss = compile_structured(plan, sy)
    groups = [b for b in ss.blocks if len(b.points) > 1]
    if not groups:
        return True
    rng = np.random.default_rng(seed)
    sketch = np.asarray(plan.sketch, dtype=np.float64)
    span = float(np.ptp(sketch, axis=0).max()) if len(sketch) > 1 else 1.0
    x = (sketch + (span if span > 0 else 1.0) * rng.standard_normal(sketch.shape))[:, :, None]
    for block in groups:
        pos = {q: i for i, q in enumerate(block.points)}
        m = 2 * len(block.points)
        a = np.zeros((m, m))
        for col, sc in enumerate(block.scalars):
            for q, (gx, gy) in zip(sc.points, _gradients(sc, x), strict=True):
                if q in pos:
                    a[2 * pos[q], col] += float(np.asarray(gx).ravel()[0])
                    a[2 * pos[q] + 1, col] += float(np.asarray(gy).ravel()[0])
        if not np.isfinite(a).all():  # (a rope with no tangent there): the whole-matrix check
            return False
        sv = np.linalg.svd(a, compute_uv=False)
        if sv[-1] <= m * np.finfo(float).eps * 1e3 * sv[0]:
            return False
    return True


def _add(a: Value, b: Value) -> Value:
    if isinstance(b, float) and b == 0.0:
        return a
    if isinstance(a, float) and a == 0.0:
        return b
    return a + b


def _mul(a: Value, b: Value) -> Value:
    if isinstance(a, float):
        if a == 0.0:
            return 0.0
        if a == 1.0:
            return b
    if isinstance(b, float):
        if b == 0.0:
            return 0.0
        if b == 1.0:
            return a
    return a * b


def _neg(a: Value) -> Value:
    if isinstance(a, float) and a == 0.0:
        return 0.0
    return -a


def _zero(a: Value) -> bool:
    return isinstance(a, float) and a == 0.0


def _gradients(sc: Scalar, x: F) -> list[tuple[Value, Value]]:
    """∇g of one scalar constraint at each of its points (in ``sc.points`` order)."""
    k = sc.kind
    p = sc.points
    if k == "dist":
        dx, dy = x[p[0], 0] - x[p[1], 0], x[p[0], 1] - x[p[1], 1]
        inv = 1.0 / np.sqrt(dx * dx + dy * dy)
        ux, uy = dx * inv, dy * inv
        return [(ux, uy), (-ux, -uy)]
    if k in ("frame_x", "frame_y"):
        s, t = _frame(x, p)
        if k == "frame_x":  # g_x = Px − ax − s·(bx − ax) + t·(by − ay)
            return [(1.0, 0.0), (s - 1.0, -t), (-s, t)]
        return [(0.0, 1.0), (t, s - 1.0), (-t, -s)]  # g_y = Py − ay − s·(by − ay) − t·(bx − ax)
    if k == "angle":
        dx, dy = x[p[0], 0] - x[p[1], 0], x[p[0], 1] - x[p[1], 1]
        inv = 1.0 / (dx * dx + dy * dy)
        gx, gy = -dy * inv, dx * inv
        out: list[tuple[Value, Value]] = [(gx, gy), (-gx, -gy)]
        if len(p) == 4:
            out += _reference(x, p)
        return out
    if k == "rope":  # ∇(−L) = u_k − u_{k−1}: the tension's pull per unit at each path point
        ux, uy = segment_directions([(x[q, 0], x[q, 1]) for q in p], sc.signed)
        last = len(p) - 1
        return [
            (ux[0], uy[0])
            if j == 0
            else (_neg(ux[j - 1]), _neg(uy[j - 1]))
            if j == last
            else (ux[j] - ux[j - 1], uy[j] - uy[j - 1])
            for j in range(len(p))
        ]
    assert k == "line"
    ex, ey = x[p[2], 0] - x[p[1], 0], x[p[2], 1] - x[p[1], 1]
    wx, wy = x[p[0], 0] - x[p[1], 0], x[p[0], 1] - x[p[1], 1]
    inv = 1.0 / np.sqrt(ex * ex + ey * ey)
    nx, ny = -ey * inv, ex * inv
    qx, qy = -wy * inv, wx * inv  # perp(w)/|e|
    return [(nx, ny), (qx - nx, qy - ny), (-qx, -qy)]


def _frame(x: F, p: tuple[int, ...]) -> tuple[Value, Value]:
    """(s, t) of P = a + s·v + t·perp(v), v = b − a, from the positions (a family of designs
    has its own per sample)."""
    vx, vy = x[p[2], 0] - x[p[1], 0], x[p[2], 1] - x[p[1], 1]
    wx, wy = x[p[0], 0] - x[p[1], 0], x[p[0], 1] - x[p[1], 1]
    inv = 1.0 / (vx * vx + vy * vy)
    return (wx * vx + wy * vy) * inv, (vx * wy - vy * wx) * inv


def _reference(x: F, p: tuple[int, ...]) -> list[tuple[Value, Value]]:
    """∇ of an angle constraint at its reference body's r0 and r1 (``p[2]``, ``p[3]``)."""
    ex, ey = x[p[3], 0] - x[p[2], 0], x[p[3], 1] - x[p[2], 1]
    inv = 1.0 / (ex * ex + ey * ey)
    hx, hy = -ey * inv, ex * inv
    return [(hx, hy), (-hx, -hy)]


class Arithmetic:
    """What the back-substitution does beyond arithmetic, on NumPy arrays (or dual numbers):
    flag the singular samples and solve a Newton group's dense block. The compiled path's
    trace (`excavkin.kinetostatics.compiled`) has its own.

    Parameters
    ----------
    c : int
        Samples in the chunk.
    rel_tol : float
        A dense block's sample is singular where a pivot is below ``rel_tol`` times the
        block's largest entry.
    """

    def __init__(self, c: int, rel_tol: float = 1e-12) -> None:
        self.c = c
        self.rel_tol = rel_tol
        self.singular = np.zeros(c, dtype=bool)

    def flag(self, det: Value) -> None:
        """Mark the samples where ``det``, the sine of a point's two directions, is 0.

        Parameters
        ----------
        det : float or ndarray, shape (c,)
        """
        self.singular |= np.asarray(np.abs(det) <= SINGULAR_SINE)

    def dense(self, a: list[list[Value]], b: list[Value]) -> list[Value]:
        """The solution of ``a·y = b``, partial pivoting, one system per sample.

        Parameters
        ----------
        a : list of list of (float or ndarray, shape (c,))
        b : list of (float or ndarray, shape (c,))

        Returns
        -------
        list of ndarray, shape (c,)
        """
        y, singular = dense_block_solve(a, b, self.c, self.rel_tol)
        self.singular |= singular
        return list(y)


def back_substitute(
    ss: StructuredSystem,
    x: F,
    rhs_body: Sequence[tuple[Value, Value, Value]],
    ops: Arithmetic,
) -> list[Value]:
    """The unknowns of the equilibrium, by back-substitution over the plan's steps.

    Runs on NumPy arrays, dual numbers or the compiled path's symbols alike: only
    arithmetic, ``np.sqrt`` and the two operations of ``ops``.

    Parameters
    ----------
    ss : StructuredSystem
        From `compile_structured`.
    x : ndarray, shape (n_points, 2, c)
        Point positions.
    rhs_body : list of (float or ndarray, ...)
        Per moving body (in ``system.moving`` order), the known force x, y and moment about its
        first point (`excavkin.kinetostatics.body_loads.body_loads`).
    ops : Arithmetic
        Flags singular samples and solves dense blocks.

    Returns
    -------
    list
        One value per unknown, in the equilibrium system's order (a float where it is 0).
    """
    sy = ss.system
    f = _Forces(ss.slot_of)
    # the loads: each body's force at p0, its moment as a couple of forces at p0 and p1
    for j, (fx, fy, mz) in zip(sy.moving, rhs_body, strict=True):
        i0, i1 = sy.base[j]
        gx: Value = 0.0
        gy: Value = 0.0
        if not _zero(mz):
            dx, dy = x[i1, 0] - x[i0, 0], x[i1, 1] - x[i0, 1]
            inv = mz / (dx * dx + dy * dy)
            gx, gy = -dy * inv, dx * inv
            f.add(i1, j, gx, gy, True)
        f.add(i0, j, _add(fx, _neg(gx)), _add(fy, _neg(gy)), True)
    out: list[Value] = [0.0] * sy.size
    for block in reversed(ss.blocks):
        _solve_block(block, x, f, ops, out)
    return _pin_forces(sy, f, out)


class _Forces:
    """The forces known so far, point by point: at each point (its balance's known part), on
    each pin slot's body (what it takes from its pin), on each pin (the elements' and sliders'
    forces)."""

    def __init__(self, slot_of: dict[tuple[int, int], int]) -> None:
        self.slot_of = slot_of
        self.acc: dict[int, list[Value]] = {}
        self.att: dict[int, list[Value]] = {}
        self.pin: dict[int, list[Value]] = {}

    @staticmethod
    def _put(into: dict[int, list[Value]], key: int, fx: Value, fy: Value) -> None:
        old = into.get(key)
        if old is None:
            into[key] = [fx, fy]
        else:
            old[0], old[1] = _add(old[0], fx), _add(old[1], fy)

    def add(self, point: int, owner: int, fx: Value, fy: Value, into_acc: bool) -> None:
        """A force (fx, fy) at ``point`` on ``owner`` (a body, or PIN); ``into_acc``: the
        point's balance is still to solve."""
        if _zero(fx) and _zero(fy):
            return
        if into_acc:
            self._put(self.acc, point, fx, fy)
        if owner == PIN:
            self._put(self.pin, point, fx, fy)
            return
        k = self.slot_of.get((point, owner))
        if k is not None:
            self._put(self.att, k, fx, fy)


def _solve_block(block: Block, x: F, f: _Forces, ops: Arithmetic, out: list[Value]) -> None:
    """One step's multipliers from its points' balance; their forces added to ``f``, the
    unknowns they are put in ``out``."""
    if len(block.points) == 1:
        p = block.points[0]
        known = f.acc.get(p)
        if known is None:
            return  # nothing acts on the point: its constraints carry no force
        rx, ry = _neg(known[0]), _neg(known[1])
        first = block.scalars[0]
        if first.kind == "frame_x":  # attach: ∇_P g = I, so λ = r
            _attach(first, x, rx, ry, f)
            return
        grads = [_gradients(sc, x) for sc in block.scalars]
        (ax, ay), (bx, by) = (_at(sc, g, p) for sc, g in zip(block.scalars, grads, strict=True))
        det = ax * by - ay * bx
        lam: list[Value] = [(rx * by - bx * ry) / det, (ax * ry - ay * rx) / det]
        if block.can_be_singular:  # two unit directions: det is their sine
            ops.flag(det)
    else:
        grads = [_gradients(sc, x) for sc in block.scalars]
        pos = {q: i for i, q in enumerate(block.points)}
        m = 2 * len(block.points)
        a: list[list[Value]] = [[0.0] * m for _ in range(m)]
        for col, (sc, g) in enumerate(zip(block.scalars, grads, strict=True)):
            for q, (gx, gy) in zip(sc.points, g, strict=True):
                if q in pos:
                    a[2 * pos[q]][col] = _add(a[2 * pos[q]][col], gx)
                    a[2 * pos[q] + 1][col] = _add(a[2 * pos[q] + 1][col], gy)
        b: list[Value] = []
        for q in block.points:
            known = f.acc.get(q, [0.0, 0.0])
            b += [_neg(known[0]), _neg(known[1])]
        lam = ops.dense(a, b)
    own = block.points
    for sc, g, lm in zip(block.scalars, grads, lam, strict=True):
        if sc.column >= 0:
            out[sc.column] = lm
        for q, owner, (gx, gy) in zip(sc.points, sc.owners, g, strict=True):
            f.add(q, owner, _mul(lm, gx), _mul(lm, gy), q not in own)


def _at(sc: Scalar, g: list[tuple[Value, Value]], p: int) -> tuple[Value, Value]:
    """A scalar constraint's gradient at point ``p``: its first point's for a closed-form
    step (its own point comes first), else summed over where ``p`` is among its points (a
    one-point Newton group's distance of a body, or its rope)."""
    if sc.points[0] == p:
        return g[0]
    gx: Value = 0.0
    gy: Value = 0.0
    for q, (ex, ey) in zip(sc.points, g, strict=True):
        if q == p:
            gx, gy = _add(gx, ex), _add(gy, ey)
    return gx, gy


def _pin_forces(sy: StaticsSystem, f: _Forces, out: list[Value]) -> list[Value]:
    """``out`` with the pin forces: on a moving body, minus what else acts on it at the pin;
    on the ground, from the pin's balance (Σ_b F[p, b] = the elements' and sliders' forces)."""
    on_ground: list[tuple[int, int]] = []
    others: dict[int, list[int]] = {}
    for k, (i, j) in enumerate(sy.slots):
        if j == sy.ground:
            on_ground.append((k, i))
            continue
        fx, fy = f.att.get(k, [0.0, 0.0])
        out[2 * k], out[2 * k + 1] = _neg(fx), _neg(fy)
        others.setdefault(i, []).append(k)
    for k, i in on_ground:
        fx, fy = f.pin.get(i, [0.0, 0.0])
        for kk in others.get(i, ()):
            fx, fy = _add(fx, _neg(out[2 * kk])), _add(fy, _neg(out[2 * kk + 1]))
        out[2 * k], out[2 * k + 1] = fx, fy
    return out


def _attach(sc: Scalar, x: F, lx: Value, ly: Value, f: _Forces) -> None:
    """The forces of an attach step's frame constraint (multipliers ``λ = (lx, ly)``): λ on the
    point, and on a and b ``(∇_a g)ᵀλ``, ``(∇_b g)ᵀλ`` (their sum is −λ)."""
    p, a, b = sc.points
    j = sc.owners[0]
    s, t = _frame(x, sc.points)
    fbx = _neg(_add(s * lx, t * ly))
    fby = _add(t * lx, _neg(s * ly))
    f.add(p, j, lx, ly, False)
    f.add(a, j, _neg(_add(lx, fbx)), _neg(_add(ly, fby)), True)
    f.add(b, j, fbx, fby, True)


def solve_structured(
    ss: StructuredSystem,
    x: F,
    rhs_body: Sequence[tuple[Value, Value, Value]],
    *,
    rel_tol: float = 1e-12,
) -> tuple[F, np.ndarray]:
    """Solve the equilibrium of one chunk of samples by back-substitution over the plan.

    Parameters
    ----------
    ss : StructuredSystem
        From `compile_structured`.
    x : ndarray, shape (n_points, 2, c)
        Point positions of the chunk.
    rhs_body : list of (float or ndarray, ...)
        Per moving body (in ``system.moving`` order), the known force x, y and moment about its
        first point (`excavkin.kinetostatics.body_loads.body_loads`).
    rel_tol : float
        A Newton group's sample is singular where a pivot of its block is below ``rel_tol``
        times the block's largest entry.

    Returns
    -------
    solution : ndarray, shape (n_unknowns, c)
        The unknowns in the equilibrium system's order.
    singular : ndarray of bool, shape (c,)
    """
    c = x.shape[-1]
    ops = Arithmetic(c, rel_tol)
    sol = back_substitute(ss, x, rhs_body, ops)
    out = np.empty((len(sol), c))
    for col, val in enumerate(sol):
        out[col] = val
    return out, ops.singular
