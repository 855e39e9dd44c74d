"""Compile a model into a :class:`SolvePlan`: ordered closed-form steps, once per model.

The unknowns are point positions. Starting from the ground's points, steps are chosen greedily,
each needing only points already known (DESIGN.md §3):

=========  ==================================================  ================================
step       known                                               gives
=========  ==================================================  ================================
Fixed      —                                                   the ground's points
Rotate     pivot, reference orientation, driver angle          the driven body's point
Attach     two known points of the same body                   any other point of that body
Dyad       A, B and distances |PA|, |PB| (body, cylinder,      P, on the sketch's side of AB
           rope; fixed or driven)                              (RRR dyad, internal driving link)
Slider     A, |PA|, a line through two known points            P on the line (RRP)
Newton     what is left: a higher-class group                  all its points, by Newton–Raphson
=========  ==================================================  ================================

Every constraint of the model is used by exactly one step; one left over means the model is
over-constrained somewhere, and the error names it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

from excavkin.errors import AssemblyError, MobilityError
from excavkin.model.entities import Model
from excavkin.model.validate import Mobility, mobility
from excavkin.structure.shapes import BodyShape, body_shape


@dataclass(frozen=True, slots=True)
class Dist:
    """A distance used by a step: fixed (a body or a locked element) or an input's value."""

    kind: Literal["fixed", "input"]
    value: float
    input: int = -1
    label: str = ""


@dataclass(frozen=True, slots=True)
class Fixed:
    """Ground points at their coordinates."""

    points: tuple[int, ...]
    coords: tuple[tuple[float, float], ...]


@dataclass(frozen=True, slots=True)
class Rotate:
    """``point = pivot + radius·(cos θ, sin θ)``, ``θ = θ_ref + q[input]``."""

    point: int
    pivot: int
    radius: float
    input: int
    ref: tuple[int, int] | None
    driver: str


@dataclass(frozen=True, slots=True)
class Attach:
    """``point = a + s·(b − a) + t·perp(b − a)``, ``perp(v) = (−v_y, v_x)``."""

    point: int
    a: int
    b: int
    s: float
    t: float
    body: str


@dataclass(frozen=True, slots=True)
class Dyad:
    """``|P − A| = da``, ``|P − B| = db``; ``sign`` = sign of cross(B − A, P − A) at the sketch."""

    point: int
    a: int
    b: int
    da: Dist
    db: Dist
    sign: float
    index: int


@dataclass(frozen=True, slots=True)
class SliderStep:
    """``|P − A| = da`` and P on the line l1→l2; ``sign`` = side of A's foot P lies on."""

    point: int
    a: int
    da: Dist
    l1: int
    l2: int
    sign: float
    index: int
    slider: str


@dataclass(frozen=True, slots=True)
class CDist:
    """Newton constraint ``|p − q|² = d²``."""

    p: int
    q: int
    dist: Dist


@dataclass(frozen=True, slots=True)
class CFrame:
    """Newton constraint (two equations) ``p = a + s·(b − a) + t·perp(b − a)``."""

    p: int
    a: int
    b: int
    s: float
    t: float


@dataclass(frozen=True, slots=True)
class CLine:
    """Newton constraint ``cross(l2 − l1, p − l1) = 0``."""

    p: int
    l1: int
    l2: int


@dataclass(frozen=True, slots=True)
class CAngle:
    """Newton constraint ``cross(R(q)·e_ref, p − pivot) = 0`` (e_ref = +x for the ground)."""

    p: int
    pivot: int
    ref: tuple[int, int] | None
    input: int


Constraint = CDist | CFrame | CLine | CAngle


@dataclass(frozen=True, slots=True)
class NewtonGroup:
    """Points solved together by batched Newton–Raphson, started from the sketch."""

    points: tuple[int, ...]
    constraints: tuple[Constraint, ...]


Step = Fixed | Rotate | Attach | Dyad | SliderStep | NewtonGroup


@dataclass(frozen=True, slots=True)
class Element:
    """A linear element (cylinder, rope, strut) as the solver sees it."""

    name: str
    p: int
    q: int
    mode: Literal["driven", "locked", "free"]
    input: int
    length: float


@dataclass(frozen=True, slots=True)
class SolvePlan:
    """Everything the kinematic kernels need, in index form.

    Attributes
    ----------
    points : tuple of str
        Point names; index i is row i of the position arrays.
    bodies : tuple of str
        Body names; ground included.
    body_base : tuple of (int, int)
        The first two points of each body (``(-1, -1)`` for a one-point ground).
    inputs : tuple of str
        Driver names whose values are inputs (rotary first, then driven linear).
    input_kinds : tuple of str
        ``"angle"`` or ``"length"`` per input.
    input_sketch : tuple of float
        Each input's value at the sketch.
    elements : tuple of Element
    transmissions : tuple of str
        Point names of the dyads and sliders, whose transmission angles are reported.
    steps : tuple of Step
    sketch : tuple of (float, float)
        The sketch as the user drew it (before re-assembly to exact lengths).
    scale : float
        A characteristic size of the mechanism (m), for tolerances.
    """

    model: Model
    points: tuple[str, ...]
    bodies: tuple[str, ...]
    ground: int
    body_base: tuple[tuple[int, int], ...]
    inputs: tuple[str, ...]
    input_kinds: tuple[str, ...]
    input_sketch: tuple[float, ...]
    elements: tuple[Element, ...]
    transmissions: tuple[str, ...]
    steps: tuple[Step, ...]
    sketch: tuple[tuple[float, float], ...]
    shapes: dict[str, BodyShape]
    mobility: Mobility
    scale: float
    method: str = "closed-form"
    notes: tuple[str, ...] = field(default=())

    @property
    def has_newton(self) -> bool:
        """Whether any step is solved iteratively."""
        return any(isinstance(s, NewtonGroup) for s in self.steps)

    def describe(self) -> str:
        """The plan as text, one step a line, in the order it runs."""
        name = self.points.__getitem__
        lines = []
        for k, st in enumerate(self.steps, 1):
            if isinstance(st, Fixed):
                text = f"fixed    {', '.join(name(i) for i in st.points)} (ground)"
            elif isinstance(st, Rotate):
                ref = "ground" if st.ref is None else f"{name(st.ref[0])}→{name(st.ref[1])}"
                text = (
                    f"rotate   {name(st.point)} about {name(st.pivot)} by driver "
                    f"{st.driver!r} (from {ref}, r = {st.radius:.6g} m)"
                )
            elif isinstance(st, Attach):
                text = (
                    f"attach   {name(st.point)} to body {st.body!r} via {name(st.a)}, {name(st.b)}"
                )
            elif isinstance(st, Dyad):
                text = (
                    f"dyad     {name(st.point)} from {name(st.a)} ({_d(st.da)}) and "
                    f"{name(st.b)} ({_d(st.db)}), branch {'+' if st.sign > 0 else '−'}"
                )
            elif isinstance(st, SliderStep):
                text = (
                    f"slider   {name(st.point)} on line {name(st.l1)}→{name(st.l2)} "
                    f"({st.slider!r}) at {_d(st.da)} from {name(st.a)}, "
                    f"branch {'+' if st.sign > 0 else '−'}"
                )
            else:
                text = (
                    f"newton   {', '.join(name(i) for i in st.points)} together "
                    f"({len(st.constraints)} constraints)"
                )
            lines.append(f"{k:3d}. {text}")
        return "\n".join(lines)


def _d(d: Dist) -> str:
    if d.kind == "input":
        return f"driver {d.label!r}"
    return f"{d.label} {d.value:.6g} m"


def _override(model: Model, p: str, q: str) -> float | None:
    return model.lengths.get((p, q), model.lengths.get((q, p)))


def _cross(ax: float, ay: float, bx: float, by: float) -> float:
    return ax * by - ay * bx


def compile_plan(
    model: Model, *, method: Literal["closed-form", "newton"] = "closed-form"
) -> SolvePlan:
    """Order the model's points into solve steps.

    Parameters
    ----------
    model : Model
        A validated model.
    method : {"closed-form", "newton"}
        ``"newton"`` puts every moving point into one Newton group (used to cross-check the
        closed-form path).

    Raises
    ------
    MobilityError
        A sub-chain is over- or under-constrained although the global count matches.
    AssemblyError
        The sketch does not show a branch (a dyad's point on the line of its two partners).
    """
    src = model.source
    names = tuple(model.points)
    idx = {n: i for i, n in enumerate(names)}
    sk = model.points
    bodies = model.bodies
    shapes = {b.name: body_shape(model, b) for b in bodies}
    ground_body = model.ground
    gidx = next(i for i, b in enumerate(bodies) if b.ground)
    xs = [p[0] for p in sk.values()]
    ys = [p[1] for p in sk.values()]
    scale = max(max(xs) - min(xs), max(ys) - min(ys), 1e-9)

    inputs = model.inputs
    in_idx = {n: i for i, n in enumerate(inputs)}
    kinds: list[str] = []
    sketch_vals: list[float] = []
    for d in model.rotary:
        kinds.append("angle")
        body = model.body(d.body)
        p = next(n for n in body.points if n != d.pivot)
        ex, ey = _orientation(model, d.reference)
        dx, dy = sk[p][0] - sk[d.pivot][0], sk[p][1] - sk[d.pivot][1]
        sketch_vals.append(math.atan2(_cross(ex, ey, dx, dy), ex * dx + ey * dy))
    elements: list[Element] = []
    for ld in model.linear:
        p, q = ld.between
        length = _override(model, p, q) or math.dist(sk[p], sk[q])
        if ld.mode == "free" and _override(model, p, q) is not None:
            raise AssemblyError(
                "a free element's length follows the mechanism; it cannot be set in [lengths]",
                table="lengths",
                entry=f"{p}-{q}",
                source=src,
            )
        if ld.mode == "driven":
            kinds.append("length")
            sketch_vals.append(length)
        elements.append(
            Element(
                ld.name,
                idx[p],
                idx[q],
                ld.mode,
                in_idx.get(ld.name, -1) if ld.mode == "driven" else -1,
                length,
            )
        )
    for p, q in model.lengths:
        on_body = any(p in b.points and q in b.points for b in bodies)
        on_elem = any({p, q} == set(ld.between) for ld in model.linear)
        if not (on_body or on_elem):
            raise AssemblyError(
                f"{p} and {q} are on no common body and no cylinder joins them, so their "
                "distance is not a dimension of the mechanism",
                table="lengths",
                entry=f"{p}-{q}",
                source=src,
            )

    point_bodies: dict[str, list[int]] = {n: [] for n in names}
    for bi, b in enumerate(bodies):
        for n in b.points:
            point_bodies[n].append(bi)

    # --- ground
    gshape = shapes[ground_body.name]
    g0 = ground_body.points[0]
    if len(ground_body.points) >= 2:
        gex, gey = _unit(sk[ground_body.points[1]], sk[g0])
    else:
        gex, gey = 1.0, 0.0
    gcoords = []
    ground_set = set(ground_body.points)
    reshaped = any(p in ground_set and q in ground_set for p, q in model.lengths)
    for n in ground_body.points:
        if not reshaped:  # the sketch's own coordinates, exactly
            gcoords.append(sk[n])
            continue
        lx, ly = gshape.local[n]
        gcoords.append((sk[g0][0] + lx * gex - ly * gey, sk[g0][1] + lx * gey + ly * gex))
    steps: list[Step] = [Fixed(tuple(idx[n] for n in ground_body.points), tuple(gcoords))]
    known = set(ground_body.points)

    used_elem: set[int] = set()
    used_slider: set[int] = set()
    used_rotary: set[int] = set()
    body_used = [0] * len(bodies)
    n_trans: list[str] = []

    def body_known(bi: int) -> bool:
        b = bodies[bi]
        return b.ground or all(n in known for n in b.points[:2])

    def dist_options(p: str) -> list[tuple[str, Dist, int, int]]:
        """Known partners of p with a distance: (A, Dist, body index or -1, element or -1)."""
        out: list[tuple[str, Dist, int, int]] = []
        for bi in point_bodies[p]:
            for a in bodies[bi].points:
                if a != p and a in known:
                    d = shapes[bodies[bi].name].distance(p, a)
                    out.append((a, Dist("fixed", d, label=f"body {bodies[bi].name!r}"), bi, -1))
        for ei, el in enumerate(elements):
            if ei in used_elem or el.mode == "free":
                continue
            other = names[el.q] if names[el.p] == p else names[el.p] if names[el.q] == p else None
            if other is None or other not in known:
                continue
            if el.mode == "driven":
                dist = Dist("input", el.length, el.input, label=el.name)
            else:
                dist = Dist("fixed", el.length, label=f"locked {el.name!r}")
            out.append((other, dist, -1, ei))
        return out

    def consume(option: tuple[str, Dist, int, int]) -> None:
        _, _, bi, ei = option
        if bi >= 0:
            body_used[bi] += 1
        if ei >= 0:
            used_elem.add(ei)

    if method == "closed-form":
        progress = True
        while progress and len(known) < len(names):
            progress = False
            # attach: bodies with two known points
            for bi, b in enumerate(bodies):
                if b.ground:
                    continue
                kn = [n for n in b.points if n in known]
                unknown = [n for n in b.points if n not in known]
                if len(kn) < 2 or not unknown:
                    continue
                sh = shapes[b.name]
                a, c = max(
                    ((u, v) for i, u in enumerate(kn) for v in kn[i + 1 :]),
                    key=lambda uv: sh.distance(*uv),
                )
                for n in unknown:
                    s, t = sh.frame_coords(n, a, c)
                    steps.append(Attach(idx[n], idx[a], idx[c], s, t, b.name))
                    known.add(n)
                    body_used[bi] += 2
                progress = True
            if progress:
                continue
            for ri, d in enumerate(model.rotary):
                if (
                    ri in used_rotary
                    or d.pivot not in known
                    or not body_known(
                        next(i for i, b in enumerate(bodies) if b.name == d.reference)
                    )
                ):
                    continue
                body = model.body(d.body)
                p = next(n for n in body.points if n != d.pivot)
                if p in known:
                    continue
                ref = (
                    None
                    if model.body(d.reference).ground
                    else (
                        idx[model.body(d.reference).points[0]],
                        idx[model.body(d.reference).points[1]],
                    )
                )
                steps.append(
                    Rotate(
                        idx[p],
                        idx[d.pivot],
                        shapes[d.body].distance(p, d.pivot),
                        in_idx[d.name],
                        ref,
                        d.name,
                    )
                )
                known.add(p)
                used_rotary.add(ri)
                body_used[next(i for i, b in enumerate(bodies) if b.name == d.body)] += 1
                progress = True
                break
            if progress:
                continue
            for p in names:
                if p in known:
                    continue
                opts = dist_options(p)
                pair = next(
                    (
                        (o1, o2)
                        for i, o1 in enumerate(opts)
                        for o2 in opts[i + 1 :]
                        if o1[0] != o2[0]
                    ),
                    None,
                )
                if pair is None:
                    continue
                o1, o2 = pair
                a, pb = o1[0], o2[0]
                cr = _cross(
                    sk[pb][0] - sk[a][0],
                    sk[pb][1] - sk[a][1],
                    sk[p][0] - sk[a][0],
                    sk[p][1] - sk[a][1],
                )
                if abs(cr) <= 1e-12 * scale * scale:
                    raise AssemblyError(
                        f"point {p} lies on the line through {a} and {pb} in the sketch, so the "
                        "sketch does not show which way the dyad is assembled; move it to the "
                        "intended side",
                        table="points",
                        entry=p,
                        source=src,
                    )
                sign = math.copysign(1.0, cr)
                steps.append(Dyad(idx[p], idx[a], idx[pb], o1[1], o2[1], sign, len(n_trans)))
                n_trans.append(p)
                consume(o1)
                consume(o2)
                known.add(p)
                progress = True
                break
            if progress:
                continue
            for si, sl in enumerate(model.sliders):
                if si in used_slider or sl.point in known or not all(n in known for n in sl.along):
                    continue
                opts = dist_options(sl.point)
                if not opts:
                    continue
                o = opts[0]
                a, p = o[0], sl.point
                l1, l2 = sl.along
                ux, uy = _unit(sk[l2], sk[l1])
                along = (sk[p][0] - sk[a][0]) * ux + (sk[p][1] - sk[a][1]) * uy
                if abs(along) <= 1e-12 * scale:
                    raise AssemblyError(
                        f"point {p} is at the foot of the perpendicular from {a} to its slide "
                        "in the sketch, so the sketch does not show the branch",
                        table="points",
                        entry=p,
                        source=src,
                    )
                steps.append(
                    SliderStep(
                        idx[p],
                        idx[a],
                        o[1],
                        idx[l1],
                        idx[l2],
                        math.copysign(1.0, along),
                        len(n_trans),
                        sl.name,
                    )
                )
                n_trans.append(p)
                consume(o)
                used_slider.add(si)
                known.add(p)
                progress = True
                break

    unknown = [n for n in names if n not in known]
    if unknown:
        steps.append(
            _newton_group(
                model,
                shapes,
                idx,
                unknown,
                known,
                elements,
                used_elem,
                used_slider,
                used_rotary,
                body_used,
            )
        )
    _check_all_used(model, shapes, elements, used_elem, used_slider, used_rotary, body_used)
    return SolvePlan(
        model=model,
        points=names,
        bodies=tuple(b.name for b in bodies),
        ground=gidx,
        body_base=tuple(
            (idx[b.points[0]], idx[b.points[1]]) if len(b.points) >= 2 else (-1, -1) for b in bodies
        ),
        inputs=inputs,
        input_kinds=tuple(kinds),
        input_sketch=tuple(sketch_vals),
        elements=tuple(elements),
        transmissions=tuple(n_trans),
        steps=tuple(steps),
        sketch=tuple(sk[n] for n in names),
        shapes=shapes,
        mobility=mobility(model),
        scale=scale,
        method=method,
    )


def _unit(p: tuple[float, float], q: tuple[float, float]) -> tuple[float, float]:
    dx, dy = p[0] - q[0], p[1] - q[1]
    r = math.hypot(dx, dy)
    return dx / r, dy / r


def _orientation(model: Model, body: str) -> tuple[float, float]:
    b = model.body(body)
    if b.ground:
        return 1.0, 0.0
    return _unit(model.points[b.points[1]], model.points[b.points[0]])


def _newton_group(
    model: Model,
    shapes: dict[str, BodyShape],
    idx: dict[str, int],
    unknown: list[str],
    known: set[str],
    elements: list[Element],
    used_elem: set[int],
    used_slider: set[int],
    used_rotary: set[int],
    body_used: list[int],
) -> NewtonGroup:
    cons: list[Constraint] = []
    unk = set(unknown)
    names = list(model.points)
    for bi, b in enumerate(model.bodies):
        if b.ground or not unk.intersection(b.points):
            continue
        p0, p1 = b.points[0], b.points[1]
        sh = shapes[b.name]
        cons.append(
            CDist(idx[p0], idx[p1], Dist("fixed", sh.distance(p0, p1), label=f"body {b.name!r}"))
        )
        for pi in b.points[2:]:
            s, t = sh.frame_coords(pi, p0, p1)
            cons.append(CFrame(idx[pi], idx[p0], idx[p1], s, t))
        body_used[bi] += 2 * len(b.points) - 3
    for ei, el in enumerate(elements):
        if ei in used_elem or el.mode == "free":
            continue
        if {names[el.p], names[el.q]} & unk:
            d = (
                Dist("input", el.length, el.input, label=el.name)
                if el.mode == "driven"
                else Dist("fixed", el.length, label=f"locked {el.name!r}")
            )
            cons.append(CDist(el.p, el.q, d))
            used_elem.add(ei)
    for si, sl in enumerate(model.sliders):
        if si not in used_slider and {sl.point, *sl.along} & unk:
            cons.append(CLine(idx[sl.point], idx[sl.along[0]], idx[sl.along[1]]))
            used_slider.add(si)
    inputs = model.inputs
    for ri, rd in enumerate(model.rotary):
        if ri in used_rotary:
            continue
        body = model.body(rd.body)
        p = next(n for n in body.points if n != rd.pivot)
        refb = model.body(rd.reference)
        ref = None if refb.ground else (idx[refb.points[0]], idx[refb.points[1]])
        involved = {p, rd.pivot} | (set() if refb.ground else set(refb.points[:2]))
        if involved & unk:
            cons.append(CAngle(idx[p], idx[rd.pivot], ref, inputs.index(rd.name)))
            used_rotary.add(ri)
    n_eq = sum(2 if isinstance(c, CFrame) else 1 for c in cons)
    if n_eq != 2 * len(unknown):
        what = "over" if n_eq > 2 * len(unknown) else "under"
        raise MobilityError(
            f"points {', '.join(unknown)} are {what}-constrained: {n_eq} equations for "
            f"{2 * len(unknown)} coordinates (check the drivers and joints that reach them)",
            table="bodies",
            source=model.source,
        )
    return NewtonGroup(tuple(idx[n] for n in unknown), tuple(cons))


def _check_all_used(
    model: Model,
    shapes: dict[str, BodyShape],
    elements: list[Element],
    used_elem: set[int],
    used_slider: set[int],
    used_rotary: set[int],
    body_used: list[int],
) -> None:
    src = model.source
    for ei, el in enumerate(elements):
        if el.mode != "free" and ei not in used_elem:
            kind = "driver" if el.mode == "driven" else "locked element"
            raise MobilityError(
                f"{kind} {el.name!r} is redundant: both its points are already fixed by the rest "
                "of the mechanism (over-constrained; make it 'free' or remove a joint)",
                table=f"drivers.{el.name}",
                source=src,
            )
    for si, s in enumerate(model.sliders):
        if si not in used_slider:
            raise MobilityError(
                f"slider {s.name!r} is redundant: its point and line are already fixed by the "
                "rest of the mechanism (over-constrained)",
                table=f"sliders.{s.name}",
                source=src,
            )
    for ri, d in enumerate(model.rotary):
        if ri not in used_rotary:
            raise MobilityError(
                f"rotary driver {d.name!r} is redundant: body {d.body!r} is already fixed by the "
                "rest of the mechanism (over-constrained)",
                table=f"drivers.{d.name}",
                source=src,
            )
    for bi, b in enumerate(model.bodies):
        need = 0 if b.ground else 2 * len(b.points) - 3
        if body_used[bi] < need:
            raise MobilityError(
                f"body {b.name!r} is over-constrained: its points are fixed through other "
                "bodies, so its own shape would be a redundant constraint (check its joints)",
                table="bodies",
                entry=b.name,
                source=src,
            )
