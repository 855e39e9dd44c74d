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

Gear, rack and cam steps place a point as a function of the rotary inputs, so their constraints
would hand the meshes' forces to the drivers, not to the bodies across the mesh. Their blocks
are written with the meshes' own unknowns instead: the bodies these steps
place are grouped — one gear train's (its steps share a mesh), two a gear pair joins, a rack, a
cam's follower — and each group's block holds its points' balance with the internal forces
that keep each body it places rigid (the distance to a known point of the body, or between its
first two placed points; a frame for the others) and its meshes' unknowns: each gear pair's
tangential tooth force W, each rack's tooth force, guide force and couple, each cam's contact
force (and a translating follower's guide force and couple). A unit of each acts on every body
of its mesh as the pin equations put it (at the pitch point, through the instant centre, at the
follower's point), written as forces at two points of the body placed by then (the force at
the first, its moment a couple of forces at both): statically equivalent, so the pin forces
follow as above. The block is dense (a planetary train's carrier and planet share one; two
points and four unknowns for a rack or a follower), and spans every step from the group's
first to its last. A model where a mesh acts on a body placed after the group, or whose blocks
are not square, is not taken along the plan (`along_plan`: None) and is solved densely.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.kinetostatics.equilibrium import (
    CamContact,
    StaticsSystem,
    Value,
    cam_normal,
    dense_block_solve,
)
from excavkin.step_kinds import CamRockerStep, CamStep, GearStep, RackStep
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
    "along_plan",
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
    kind : {"dist", "frame_x", "frame_y", "angle", "line", "rope", "gear", "rack", "cam"}
    points : tuple of int
        The points it touches (see the module docstring for each kind's order; a mesh's: two
        points of each body it acts on).
    owners : tuple of int
        Per touched point, the body its force there acts on, or PIN.
    column : int
        The unknown of the equilibrium system it gives (an element's force, a slider's normal
        force, a driver's torque, a rope's tension, a tooth, contact or guide force or
        couple), or −1 (a body's internal force).
    mesh : tuple or CamContact, optional
        A mesh's entry of the system (``gears``, ``racks``, ``cams``).
    part : int
        Which of a rack's or cam's unknowns: 0 tooth or contact force, 1 guide force, 2
        guide couple.
    signed : tuple of float
        A rope's signed sheave radius at each of its points (0 at its ends); empty otherwise.
    """

    kind: str
    points: tuple[int, ...]
    owners: tuple[int, ...]
    column: int
    mesh: Any = None
    part: int = 0
    signed: tuple[float, ...] = ()


@dataclass(frozen=True, slots=True)
class Block:
    """One step of the plan for the back-substitution: its points and its constraints."""

    points: tuple[int, ...]
    scalars: tuple[Scalar, ...]
    can_be_singular: bool
    dense: bool = False


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
        The system is of another model than the plan, or its gear pairs', racks' or cams'
        forces cannot be solved along it (`along_plan`).
    """
    if plan.points != sy.points or plan.bodies != sy.bodies:
        raise InputError("the equilibrium system belongs to another model than the solve plan")
    make = _Scalars(plan, sy)
    pieces = [make.block(st) for st in plan.steps]
    blocks = _mesh_blocks(plan, sy, pieces) if sy.meshes else [b for b in pieces if b]
    slot_of = {s: k for k, s in enumerate(sy.slots)}
    return StructuredSystem(sy, tuple(blocks), slot_of)


class _Scalars:
    """The constraint scalars of a plan's steps, with the unknowns' columns they carry."""

    def __init__(self, plan: SolvePlan, sy: StaticsSystem) -> None:
        self.plan, self.sy = plan, sy
        self.body = {name: j for j, name in enumerate(sy.bodies)}
        self.element_col = {e[3]: sy.element_col0 + k for k, e in enumerate(sy.elements)}
        self.by_pair = {frozenset((el.p, el.q)): k for k, el in enumerate(plan.elements)}
        self.by_input = {el.input: k for k, el in enumerate(plan.elements) if el.mode == "driven"}
        self.rotary = {name: (sy.torque_col0 + k, b, r) for k, (name, b, r) in enumerate(sy.rotary)}
        self.sliders = {
            (pt, l1, l2): (sy.slider_col0 + k, carrier)
            for k, (_, pt, l1, l2, carrier) in enumerate(sy.sliders)
        }

    def dist(self, p: int, q: int, d: Dist) -> Scalar:
        if d.body:
            j = self.body[d.body]
            return Scalar("dist", (p, q), (j, j), -1)
        k = self.by_input[d.input] if d.kind == "input" else self.by_pair[frozenset((p, q))]
        return Scalar("dist", (p, q), (PIN, PIN), self.element_col[k])

    def frame(self, p: int, a: int, b: int, name: str) -> tuple[Scalar, Scalar]:
        j = self.body[name]
        return (
            Scalar("frame_x", (p, a, b), (j, j, j), -1),
            Scalar("frame_y", (p, a, b), (j, j, j), -1),
        )

    def angle(self, p: int, pivot: int, ref: tuple[int, int] | None, driver: str) -> Scalar:
        col, driven, reference = self.rotary[driver]
        if ref is None:
            return Scalar("angle", (p, pivot), (driven, driven), col)
        return Scalar("angle", (p, pivot, *ref), (driven, driven, reference, reference), col)

    def line(self, p: int, l1: int, l2: int) -> Scalar:
        col, carrier = self.sliders[(p, l1, l2)]
        return Scalar("line", (p, l1, l2), (PIN, carrier, carrier), col)

    def block(self, st: object) -> Block | None:
        """The step's block (None: a ground step, or a mesh's, which `_mesh_blocks` makes)."""
        if isinstance(st, Fixed | GearStep | RackStep | CamStep | CamRockerStep):
            return None
        if isinstance(st, Rotate):
            _, driven, _ = self.rotary[st.driver]
            radius = Scalar("dist", (st.point, st.pivot), (driven, driven), -1)
            return Block(
                (st.point,), (radius, self.angle(st.point, st.pivot, st.ref, st.driver)), False
            )
        if isinstance(st, Attach):
            return Block((st.point,), self.frame(st.point, st.a, st.b, st.body), False)
        if isinstance(st, Dyad):
            pair = (self.dist(st.point, st.a, st.da), self.dist(st.point, st.b, st.db))
            return Block((st.point,), pair, True)
        if isinstance(st, SliderStep):
            pair = (self.dist(st.point, st.a, st.da), self.line(st.point, st.l1, st.l2))
            return Block((st.point,), pair, True)
        assert isinstance(st, NewtonGroup)
        return Block(st.points, tuple(self.group_scalars(st)), True)

    def group_scalars(self, st: NewtonGroup) -> list[Scalar]:
        scalars: list[Scalar] = []
        for c in st.constraints:
            if isinstance(c, CDist):
                scalars.append(self.dist(c.p, c.q, c.dist))
            elif isinstance(c, CFrame):
                scalars.extend(self.frame(c.p, c.a, c.b, c.body))
            elif isinstance(c, CLine):
                scalars.append(self.line(c.p, c.l1, c.l2))
            elif isinstance(c, CRope):
                scalars.append(_rope(self.sy, c))
            else:
                assert isinstance(c, CAngle)
                scalars.append(self.angle(c.p, c.pivot, c.ref, self.plan.inputs[c.input]))
        return scalars


def along_plan(plan: SolvePlan, sy: StaticsSystem) -> StructuredSystem | None:
    """`compile_structured`, or None where a model's gear pairs', racks' or cams' forces
    cannot be solved along its plan (a body a mesh acts on is placed after the mesh's steps,
    or the steps' blocks are not square): such a model is solved densely.

    Parameters
    ----------
    plan : SolvePlan
        The kinematic plan.
    sy : StaticsSystem
        The equilibrium system of the plan's model.

    Returns
    -------
    StructuredSystem or None
    """
    try:
        return compile_structured(plan, sy)
    except _NotAlongPlan:
        return None


class _NotAlongPlan(InputError):
    """A mesh's forces cannot be solved along the plan (see `along_plan`)."""


def _step_points(st: Any) -> tuple[int, ...]:
    """The points a step places."""
    if isinstance(st, Fixed | NewtonGroup):
        return tuple(st.points)
    return (st.point,)


def _mesh_blocks(plan: SolvePlan, sy: StaticsSystem, pieces: list[Block | None]) -> list[Block]:
    """The blocks of a plan with gear, rack or cam steps.

    The bodies those steps place are grouped: the bodies of one gear train (steps sharing a
    mesh), those a gear pair joins, each rack and each cam follower. A group's block holds
    every step from its first to its last (with any other step between them, as a Newton
    group's): its points' balance, the internal forces that keep each body it places rigid,
    and the unknowns of its meshes — each gear pair's tooth force, each rack's and cam's
    contact, guide force and guide couple — whose forces act on two points of each body
    (statically equivalent to the force at the pitch or contact point): points of the block,
    or placed before it.
    """
    body = {name: j for j, name in enumerate(sy.bodies)}
    placed: dict[int, int] = {}
    for i, st in enumerate(plan.steps):
        for q in _step_points(st):
            placed[q] = i
    mesh_steps = [
        (i, st)
        for i, st in enumerate(plan.steps)
        if isinstance(st, GearStep | RackStep | CamStep | CamRockerStep)
    ]
    # groups of the bodies the mesh steps place (union–find)
    parent = {body[st.body]: body[st.body] for _, st in mesh_steps}

    def root(j: int) -> int:
        while parent[j] != j:
            j = parent[j]
        return j

    def union(a: int, b: int) -> None:
        parent[root(a)] = root(b)

    by_mesh: dict[str, int] = {}
    for _, st in mesh_steps:
        if isinstance(st, GearStep):
            for name in st.meshes:
                if name in by_mesh:
                    union(body[st.body], by_mesh[name])
                by_mesh[name] = body[st.body]
    for g in sy.gears:
        if g[1] in parent and g[2] in parent:
            union(g[1], g[2])
    # each mesh's unknowns: (the body whose group solves them, scalar kind, columns, entry)
    meshes: list[tuple[int, str, tuple[int, ...], Any]] = []
    for k, g in enumerate(sy.gears):
        owner = g[2] if g[2] in parent else g[1]
        meshes.append((owner, "gear", (sy.gear_col0 + k,), g))
    for k, rk in enumerate(sy.racks):
        col = sy.rack_col0 + 3 * k
        meshes.append((rk[1], "rack", (col, col + 1, col + 2), rk))
    for cm, col in zip(sy.cams, sy.cam_cols, strict=True):
        meshes.append((cm.follower, "cam", tuple(range(col, col + cm.unknowns)), cm))
    if any(owner not in parent for owner, *_ in meshes):
        raise _NotAlongPlan("a gear pair, rack or cam acts on no body its steps place")
    # each group's steps, then ranges of steps merged where they overlap
    span: dict[int, list[int]] = {}
    for i, st in mesh_steps:
        r = root(body[st.body])
        lo, hi = span.get(r, [i, i])
        span[r] = [min(lo, i), max(hi, i)]
    ranges: list[list[int]] = []
    for lo, hi in sorted(span.values()):
        if ranges and lo <= ranges[-1][1]:
            ranges[-1][1] = max(ranges[-1][1], hi)
        else:
            ranges.append([lo, hi])
    start = {lo: hi for lo, hi in ranges}
    blocks: list[Block] = []
    i = 0
    while i < len(pieces):
        if i not in start:
            piece = pieces[i]
            if piece is not None:
                blocks.append(piece)
            i += 1
            continue
        lo, hi = i, start[i]
        blocks.append(_group_block(sy, plan, (lo, hi), pieces, placed, meshes, root))
        i = hi + 1
    return blocks


def _group_block(
    sy: StaticsSystem,
    plan: SolvePlan,
    steps: tuple[int, int],
    pieces: list[Block | None],
    placed: dict[int, int],
    meshes: list[tuple[int, str, tuple[int, ...], Any]],
    root: Any,
) -> Block:
    """The dense block of the steps ``lo..hi``: see `_mesh_blocks`."""
    lo, hi = steps
    points: list[int] = []
    scalars: list[Scalar] = []
    own: dict[int, list[int]] = {}  # a mesh-placed body's points placed here, in order
    for i in range(lo, hi + 1):
        st = plan.steps[i]
        piece = pieces[i]
        if piece is not None:
            points.extend(piece.points)
            scalars.extend(piece.scalars)
        elif isinstance(st, GearStep | RackStep | CamStep | CamRockerStep):
            points.append(st.point)
            own.setdefault(sy.bodies.index(st.body), []).append(st.point)
    model_points = {j: [sy.points.index(q) for q in pts] for j, pts in _body_points(plan)}
    for j, mine in own.items():
        first = min(placed[q] for q in mine)
        known = [q for q in model_points[j] if placed.get(q, len(plan.steps)) < first]
        if known:  # turning about a known point: its distance to the first, the rest a frame
            a, b = known[0], mine[0]
            scalars.append(Scalar("dist", (b, a), (j, j), -1))
            rest = mine[1:]
        else:  # free in the plane: the first two's distance, the rest a frame
            if len(mine) < 2:
                raise _NotAlongPlan(f"body {sy.bodies[j]!r} has one point on its own")
            a, b = mine[0], mine[1]
            scalars.append(Scalar("dist", (b, a), (j, j), -1))
            rest = mine[2:]
        for q in rest:
            scalars += [
                Scalar("frame_x", (q, a, b), (j, j, j), -1),
                Scalar("frame_y", (q, a, b), (j, j, j), -1),
            ]
    groups = {root(j) for j in own}
    for owner, kind, cols, entry in meshes:
        if root(owner) not in groups:
            continue
        acting = _acting(kind, entry)
        pts: list[int] = []
        owners: list[int] = []
        for j in acting:
            if j == sy.ground:
                continue  # (its equilibrium is not written)
            two = [q for q in model_points[j] if placed.get(q, len(plan.steps)) <= hi][:2]
            if len(two) < 2:
                raise _NotAlongPlan(f"body {sy.bodies[j]!r} is placed after a mesh on it")
            pts += two
            owners += [j, j]
        for part, col in enumerate(cols):
            scalars.append(Scalar(kind, tuple(pts), tuple(owners), col, entry, part))
    if len(scalars) != 2 * len(points):
        raise _NotAlongPlan(f"a block of {len(points)} points has {len(scalars)} unknowns")
    return Block(tuple(points), tuple(scalars), True, True)


def _body_points(plan: SolvePlan) -> list[tuple[int, tuple[str, ...]]]:
    """Each body's index and its points' names."""
    return [(j, tuple(b.points)) for j, b in enumerate(plan.model.bodies)]


def _acting(kind: str, entry: Any) -> tuple[int, ...]:
    """The bodies a mesh's unknowns act on, in the order of `_mesh_actions`."""
    if kind == "gear":
        return (entry[1], entry[2])
    if kind == "rack":
        return (entry[1], entry[2], entry[3])  # rack, pinion, carrier
    assert isinstance(entry, CamContact)
    return (entry.follower, entry.cam, entry.carrier)


def _mesh_actions(sc: Scalar, x: Any) -> list[tuple[Value, Value, Value, Value, Value]]:
    """Per body of `_acting` (the ground's included), what a unit of the mesh's unknown puts on
    it: a force (fx, fy) at (qx, qy) and a couple (the conventions of
    `excavkin.kinetostatics.equilibrium`)."""
    e = sc.mesh
    if sc.kind == "gear":
        _, _, _, o1, o2, lam, _, _ = e
        ex, ey = x[o2, 0] - x[o1, 0], x[o2, 1] - x[o1, 1]
        inv = 1.0 / np.sqrt(ex * ex + ey * ey)
        tx, ty = -ey * inv, ex * inv
        qx, qy = x[o1, 0] + lam * ex, x[o1, 1] + lam * ey
        return [(_neg(tx), _neg(ty), qx, qy, 0.0), (tx, ty, qx, qy, 0.0)]
    if sc.kind == "rack":
        _, _, _, _, o, l1, l2, side, r, _ = e
        ex, ey = x[l2, 0] - x[l1, 0], x[l2, 1] - x[l1, 1]
        inv = 1.0 / np.sqrt(ex * ex + ey * ey)
        ex, ey = ex * inv, ey * inv
        px, py = x[o, 0] - (side * r) * ey, x[o, 1] + (side * r) * ex
        if sc.part == 0:  # the tooth force along the guide: rack, pinion
            return [(ex, ey, px, py, 0.0), (-ex, -ey, px, py, 0.0), (0.0, 0.0, px, py, 0.0)]
        if sc.part == 1:  # the guide's force: rack, carrier
            return [(-ey, ex, px, py, 0.0), (0.0, 0.0, px, py, 0.0), (ey, -ex, px, py, 0.0)]
        return [(0.0, 0.0, px, py, 1.0), (0.0, 0.0, px, py, 0.0), (0.0, 0.0, px, py, -1.0)]
    ex, ey, nx, ny, ix, iy, bx, by = cam_normal(e, x)
    if sc.part == 0:  # the contact force through the instant centre: follower, cam
        return [(nx, ny, ix, iy, 0.0), (-nx, -ny, ix, iy, 0.0), (0.0, 0.0, ix, iy, 0.0)]
    if sc.part == 1:  # the guide's force at the follower's first point: follower, carrier
        return [(-ey, ex, bx, by, 0.0), (0.0, 0.0, bx, by, 0.0), (ey, -ex, bx, by, 0.0)]
    return [(0.0, 0.0, bx, by, 1.0), (0.0, 0.0, bx, by, 0.0), (0.0, 0.0, bx, by, -1.0)]


def _mesh_gradients(sc: Scalar, x: Any) -> list[tuple[Value, Value]]:
    """A mesh unknown's forces at two points (p, p') of each body it acts on: the force at p,
    its moment about p (and the couple) as a couple of forces at p and p'."""
    out: list[tuple[Value, Value]] = []
    actions = _mesh_actions(sc, x)
    acting = _acting(sc.kind, sc.mesh)
    k = 0
    for j, (fx, fy, qx, qy, couple) in zip(acting, actions, strict=True):
        if k >= len(sc.owners) or sc.owners[k] != j:
            continue  # the ground
        p, q = sc.points[k], sc.points[k + 1]
        dx, dy = x[q, 0] - x[p, 0], x[q, 1] - x[p, 1]
        moment = couple
        if not (_zero(fx) and _zero(fy)):
            rx, ry = qx - x[p, 0], qy - x[p, 1]
            moment = _add(moment, _add(_mul(rx, fy), _neg(_mul(ry, fx))))
        cx: Value = 0.0
        cy: Value = 0.0
        if not _zero(moment):
            inv = moment / (dx * dx + dy * dy)
            cx, cy = -dy * inv, dx * inv
        out += [(_add(fx, _neg(cx)), _add(fy, _neg(cy))), (cx, cy)]
        k += 2
    return out


def _rope(sy: StaticsSystem, c: CRope) -> Scalar:
    """A rope's constraint: its tension (its column of the system) acts on its path's pins."""
    k = [r[0] for r in sy.ropes].index(c.name)
    return Scalar("rope", c.points, (PIN,) * len(c.points), sy.rope_col0 + k, signed=sy.ropes[k][2])


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
    if sc.mesh is not None:
        return _mesh_gradients(sc, x)
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
    if len(block.points) == 1 and not block.dense:
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
