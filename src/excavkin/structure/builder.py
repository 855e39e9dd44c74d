"""Compile a model into a `SolvePlan`, once per model.

`PlanBuilder` holds what is known so far (points, used constraints) and has one method
per step kind: `attach`, `rotate`,
`dyad`, `slider` and, for what is left, one
`newton_group`. Each ``try`` method adds at most its own kind of step and
says whether it did; `build` tries them in a fixed order until no point is
left. A new step kind (an RPR dyad, a gear pair, a cam) is one step record in
`excavkin.structure.plan`, one method here (with the candidates `learn`
offers it) and one entry in `PlanBuilder.ORDER`.

The builder never scans the whole model after a step: placing a point offers each step kind
the candidates that point may have made ready (`learn`), kept smallest
index first, so that the first ready one is the one a scan in the model's order would find
and the plan is built in time linear in the model's size.

Every constraint of the model is used by exactly one step; one left over means the model is
over-constrained somewhere, and `check_all_used` names it.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable
from typing import ClassVar, Literal

from excavkin.errors import AssemblyError, MobilityError
from excavkin.model.cams import lift_law
from excavkin.model.entities import Body, CamFollower, Model, Rope
from excavkin.model.gears import gear_train, pivot_on
from excavkin.model.validate import mobility
from excavkin.step_kinds import (
    Attach,
    CamRockerStep,
    CamStep,
    Dyad,
    Fixed,
    GearStep,
    NewtonGroup,
    RackStep,
    Rotate,
    SliderStep,
    StepKind,
    registered,
)
from excavkin.step_kinds.rope_path import rope_path, sketch_wraps
from excavkin.structure.group_dyads import group_dyads
from excavkin.structure.plan import (
    CAngle,
    CDist,
    CFrame,
    CLine,
    Constraint,
    CRope,
    Dist,
    Element,
    SolvePlan,
    Step,
)
from excavkin.structure.shapes import body_shape

#: A known partner of a point with a distance: (partner, distance, body index or −1,
#: element index or −1).
Option = tuple[str, Dist, int, int]


#: the assembly tolerance: how far, as a fraction of the sketch's size, a point may be drawn
#: from where a constraint that no length sets (a slider's line) puts it
ASSEMBLY_TOL = 1e-4


def _lengths_by_body(model: Model) -> dict[str, list[tuple[str, str]]]:
    """The ``[lengths]`` pairs with both points on each body, in the file's order."""
    bodies_at = model.bodies_at()
    out: dict[str, list[tuple[str, str]]] = {b.name: [] for b in model.bodies}
    for p, q in model.lengths:
        for body in bodies_at.get(p, ()):
            if q in body.points:
                out[body.name].append((p, q))
    return out


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
        closed-form path), but those of the bodies of gear trains, racks and cam followers
        (`PlanBuilder.held`): their gear, rack and cam steps (and the rotary drivers and
        attachments of the trains' bodies) place them first.

    Raises
    ------
    MobilityError
        A sub-chain is over- or under-constrained although the global count matches.
    AssemblyError
        The sketch does not show a branch (a dyad's point on the line of its two partners).
    """
    return PlanBuilder(model, method).build()


class PlanBuilder:
    """The state of a plan being built, with one method per step kind.

    Parameters
    ----------
    model : Model
        A validated model.
    method : {"closed-form", "newton"}
    """

    #: The closed-form step kinds, in the order they are tried after each step added.
    ORDER: ClassVar[tuple[str, ...]] = (
        "attach",
        "rotate",
        "gear",
        "rack",
        "cam",
        "dyad",
        "slider",
    )

    def __init__(self, model: Model, method: Literal["closed-form", "newton"]) -> None:
        self.model = model
        self.method = method
        self.names = tuple(model.points)
        self.idx = {n: i for i, n in enumerate(self.names)}
        self.sketch = model.points
        self.bodies = model.bodies
        pairs = _lengths_by_body(model)
        self.shapes = {b.name: body_shape(model, b, pairs[b.name]) for b in self.bodies}
        self.body_named: dict[str, Body] = {b.name: b for b in self.bodies}
        xs = [p[0] for p in self.sketch.values()]
        ys = [p[1] for p in self.sketch.values()]
        self.scale = max(max(xs) - min(xs), max(ys) - min(ys), 1e-9)
        self.in_idx = {n: i for i, n in enumerate(model.inputs)}
        self.body_index = {b.name: i for i, b in enumerate(self.bodies)}
        self.point_bodies: dict[str, list[int]] = {n: [] for n in self.names}
        for bi, b in enumerate(self.bodies):
            for n in b.points:
                self.point_bodies[n].append(bi)
        # What each newly known point may make ready, so that no step scans the whole model
        # (see `learn`): the elements at each point (filled by `add_inputs`), the
        # rotary drivers by their pivot and reference points, the sliders by their points.
        self.point_elements: dict[str, list[int]] = {n: [] for n in self.names}
        self.rotary_at: dict[str, list[int]] = {n: [] for n in self.names}
        for ri, d in enumerate(model.rotary):
            refb = self.body_named[d.reference]
            for n in {d.pivot, *(() if refb.ground else refb.points[:2])}:
                self.rotary_at[n].append(ri)
        self.slider_of_point: dict[str, list[int]] = {n: [] for n in self.names}
        self.slider_along: dict[str, list[int]] = {n: [] for n in self.names}
        for si, sl in enumerate(model.sliders):
            self.slider_of_point[sl.point].append(si)
            for n in set(sl.along):
                self.slider_along[n].append(si)
        #: known points per body
        self.body_known = [0] * len(self.bodies)
        # candidates of each step kind, smallest index first: each may be ready (it is checked
        # when taken); every ready one is among them
        self.attach_next: list[int] = []  # bodies for this pass of attach (ahead of it)
        self.attach_later: list[int] = []  # bodies behind this pass, for the next one
        self.attach_at = -1  # the body the pass of attach is at (−1 between passes)
        self.dyad_next: list[int] = []  # points, by index
        self.rotate_next: list[int] = list(range(len(model.rotary)))
        self.slider_next: list[int] = []
        self.steps: list[Step] = []
        self.known: set[str] = set()
        self.transmissions: list[str] = []
        self.used_elem: set[int] = set()
        self.used_slider: set[int] = set()
        self.used_rotary: set[int] = set()
        self.body_used = [0] * len(self.bodies)
        self.kinds: list[str] = []
        self.input_sketch: list[float] = []
        self.elements: list[Element] = []
        self.add_gear_train()

    # ---- geometry read from the model (one place each, so that it can be re-evaluated)
    def length_override(self, p: str, q: str) -> float | None:
        """The ``[lengths]`` entry for the pair, either way round, or None."""
        return self.model.lengths.get((p, q), self.model.lengths.get((q, p)))

    def orientation(self, body: str) -> tuple[float, float]:
        """Unit vector of a body's first two points in the sketch (+x for the ground)."""
        b = self.body_named[body]
        if b.ground:
            return 1.0, 0.0
        return _unit(self.sketch[b.points[1]], self.sketch[b.points[0]])

    def sketch_cross(self, a: str, b: str, p: str) -> float:
        """cross(B − A, P − A) in the sketch: which side of A→B the point P is drawn."""
        sk = self.sketch
        return _cross(
            sk[b][0] - sk[a][0], sk[b][1] - sk[a][1], sk[p][0] - sk[a][0], sk[p][1] - sk[a][1]
        )

    # ---- before the steps
    def add_inputs(self) -> None:
        """The inputs' kinds and sketch values, and every linear element."""
        sk = self.sketch
        for d in self.model.rotary:
            self.kinds.append("angle")
            p = next(n for n in self.body_named[d.body].points if n != d.pivot)
            ex, ey = self.orientation(d.reference)
            dx, dy = sk[p][0] - sk[d.pivot][0], sk[p][1] - sk[d.pivot][1]
            self.input_sketch.append(math.atan2(_cross(ex, ey, dx, dy), ex * dx + ey * dy))
        for ld in self.model.linear:
            p, q = ld.between
            override = self.length_override(p, q)
            if ld.mode == "free" and override is not None:
                raise AssemblyError(
                    "a free element's length follows the mechanism; it cannot be set in [lengths]",
                    table="lengths",
                    entry=f"{p}-{q}",
                    source=self.model.source,
                )
            length = override or math.dist(sk[p], sk[q])
            ratio = winch_ratio(self.model, ld.name)
            if ld.mode == "driven":
                self.kinds.append("angle" if ratio else "length")
                self.input_sketch.append(length / ratio if ratio else length)
            driven = ld.mode == "driven"
            index = self.in_idx.get(ld.name, -1) if driven else -1
            self.point_elements[p].append(len(self.elements))
            self.point_elements[q].append(len(self.elements))
            self.elements.append(
                Element(ld.name, self.idx[p], self.idx[q], ld.mode, index, length, ratio)
            )
        self.add_sheaved_ropes()

    def add_sheaved_ropes(self) -> None:
        """Each rope over sheaves as its constraint (`CRope`), for the Newton group; a winch's
        input (its motor's angle, the rope's length over ``R/i``)."""
        self.ropes: list[CRope] = []
        self.used_rope: set[int] = set()
        for rope in self.model.ropes:
            if not rope.over_sheaves:
                continue
            signed = (0.0, *rope_signed_radii(rope), 0.0)
            sketch = [self.sketch[n] for n in rope.path]
            wraps0 = sketch_wraps(sketch, signed)
            length = float(rope_path(sketch, signed, wraps0).length)
            if rope.mode == "winch":
                self.kinds.append("angle")
                self.input_sketch.append(length / rope.ratio)
                d = Dist(
                    "input",
                    length,
                    self.in_idx[rope.name],
                    label=rope.name,
                    scale=rope.ratio,
                    winch=rope.name,
                )
            else:
                d = Dist("fixed", length, label=f"locked rope {rope.name!r}")
            points = tuple(self.idx[n] for n in rope.path)
            self.ropes.append(CRope(points, signed, wraps0, d, rope.name))

    def check_lengths_are_dimensions(self) -> None:
        """Every ``[lengths]`` pair is on a common body or joined by a cylinder."""
        pairs = {frozenset(ld.between) for ld in self.model.linear}
        for p, q in self.model.lengths:
            on_body = any(q in self.bodies[bi].points for bi in self.point_bodies.get(p, ()))
            on_elem = frozenset((p, q)) in pairs
            if not (on_body or on_elem):
                raise AssemblyError(
                    f"{p} and {q} are on no common body and no cylinder joins them, so their "
                    "distance is not a dimension of the mechanism",
                    table="lengths",
                    entry=f"{p}-{q}",
                    source=self.model.source,
                )

    def check_sliders_on_their_lines(self) -> None:
        """Every slider's point drawn on its line, within the assembly tolerance.

        The solve puts the point on the line at its distance from its partner: a point drawn
        off the line would be moved there, along the line, by about its offset times the
        partner's height over the line divided by the point's distance from the partner's
        foot on it (tens of millimetres for a millimetre off near that foot) — so the sketch
        would not be the mechanism. Refused, with the distance, where it is more than
        `ASSEMBLY_TOL` of the sketch's size.
        """
        sk = self.sketch
        for sl in self.model.sliders:
            (x1, y1), (x2, y2), (px, py) = sk[sl.along[0]], sk[sl.along[1]], sk[sl.point]
            off = abs(_cross(x2 - x1, y2 - y1, px - x1, py - y1)) / math.dist(
                sk[sl.along[0]], sk[sl.along[1]]
            )
            if off > ASSEMBLY_TOL * self.scale:
                raise AssemblyError(
                    f"point {sl.point} is drawn {off * 1e3:.4g} mm off the line "
                    f"{sl.along[0]}→{sl.along[1]} it slides on (more than the assembly "
                    f"tolerance, {ASSEMBLY_TOL * self.scale * 1e3:.2g} mm = {ASSEMBLY_TOL:g} of "
                    "the sketch's size); the solve would move it onto the line, so draw it "
                    "there",
                    table=f"sliders.{sl.name}",
                    entry="point",
                    source=self.model.source,
                )

    # ---- the step kinds
    def fixed(self) -> None:
        """The ground's points: the sketch's own coordinates, or its shape if reshaped."""
        ground = self.model.ground
        sk = self.sketch
        g0 = ground.points[0]
        if len(ground.points) >= 2:
            gex, gey = _unit(sk[ground.points[1]], sk[g0])
        else:
            gex, gey = 1.0, 0.0
        members = set(ground.points)
        reshaped = any(p in members and q in members for p, q in self.model.lengths)
        local = self.shapes[ground.name].local
        coords = []
        for n in ground.points:
            if not reshaped:  # the sketch's own coordinates, exactly
                coords.append(sk[n])
                continue
            lx, ly = local[n]
            coords.append((sk[g0][0] + lx * gex - ly * gey, sk[g0][1] + lx * gey + ly * gex))
        self.steps.append(
            _kind(Fixed).build(tuple(self.idx[n] for n in ground.points), tuple(coords))
        )
        for n in ground.points:
            self.learn(n)

    def attach(self) -> bool:
        """Every unknown point of every body with two known points, by its body frame: one
        pass over the bodies in order (a body that becomes ready behind the pass waits for the
        next one)."""
        added = False
        heap = self.attach_next
        while heap:
            bi = heapq.heappop(heap)
            b = self.bodies[bi]
            if not 2 <= self.body_known[bi] < len(b.points):
                continue  # not ready, or attached already
            if self.method == "newton" and b.name not in self.held():
                continue  # (the generic solver holds a body outside the higher pairs)
            self.attach_at = bi
            kn = [n for n in b.points if n in self.known]
            unknown = [n for n in b.points if n not in self.known]
            if len(kn) < 2 or not unknown:
                continue
            sh = self.shapes[b.name]
            # the widest known pair: the best-conditioned frame
            a, c = max(
                ((u, v) for i, u in enumerate(kn) for v in kn[i + 1 :]),
                key=lambda uv: sh.distance(*uv),
            )
            for n in unknown:
                s, t = sh.frame_coords(n, a, c)
                self.steps.append(
                    _kind(Attach).build(self.idx[n], self.idx[a], self.idx[c], s, t, b.name)
                )
                self.learn(n)
                self.body_used[bi] += 2
            added = True
        self.attach_at = -1
        for bi in self.attach_later:
            heapq.heappush(heap, bi)
        self.attach_later.clear()
        return added

    def rotate(self) -> bool:
        """The first rotary driver whose pivot and reference are known."""
        model = self.model
        while self.rotate_next:
            ri = heapq.heappop(self.rotate_next)
            d = model.rotary[ri]
            refb = self.body_named[d.reference]
            if ri in self.used_rotary or d.pivot not in self.known:
                continue
            if self.method == "newton" and d.body not in self.held():
                continue  # (the generic solver holds a rotary driver outside a gear train)
            if not (refb.ground or all(n in self.known for n in refb.points[:2])):
                continue
            p = next(n for n in self.body_named[d.body].points if n != d.pivot)
            if p in self.known:
                continue
            ref = None if refb.ground else (self.idx[refb.points[0]], self.idx[refb.points[1]])
            radius = self.shapes[d.body].distance(p, d.pivot)
            self.steps.append(
                _kind(Rotate).build(
                    self.idx[p], self.idx[d.pivot], radius, self.in_idx[d.name], ref, d.name
                )
            )
            self.used_rotary.add(ri)
            self.learn(p)
            self.body_used[self.body_index[d.body]] += 1
            return True
        return False

    def dyad(self) -> bool:
        """The first unknown point with two known partners at known distances."""
        while self.dyad_next:
            p = self.names[heapq.heappop(self.dyad_next)]
            if p in self.known:
                continue
            opts = self.distance_options(p)
            pair = next(
                ((o1, o2) for i, o1 in enumerate(opts) for o2 in opts[i + 1 :] if o1[0] != o2[0]),
                None,
            )
            if pair is None:
                continue
            o1, o2 = pair
            a, b = o1[0], o2[0]
            cr = self.sketch_cross(a, b, p)
            if abs(cr) <= 1e-12 * self.scale * self.scale:
                raise AssemblyError(
                    f"point {p} lies on the line through {a} and {b} in the sketch, so the "
                    "sketch does not show which way the dyad is assembled; move it to the "
                    "intended side",
                    table="points",
                    entry=p,
                    source=self.model.source,
                )
            index = len(self.transmissions)
            sign = math.copysign(1.0, cr)
            self.steps.append(
                _kind(Dyad).build(self.idx[p], self.idx[a], self.idx[b], o1[1], o2[1], sign, index)
            )
            self.transmissions.append(p)
            self.consume(o1)
            self.consume(o2)
            self.learn(p)
            return True
        return False

    def slider(self) -> bool:
        """The first slider whose line is known and whose point has a known partner."""
        sk = self.sketch
        while self.slider_next:
            si = heapq.heappop(self.slider_next)
            sl = self.model.sliders[si]
            if si in self.used_slider or sl.point in self.known:
                continue
            if not all(n in self.known for n in sl.along):
                continue
            opts = self.distance_options(sl.point)
            if not opts:
                continue
            o = opts[0]
            a, p = o[0], sl.point
            l1, l2 = sl.along
            ux, uy = _unit(sk[l2], sk[l1])
            along = (sk[p][0] - sk[a][0]) * ux + (sk[p][1] - sk[a][1]) * uy
            if abs(along) <= 1e-12 * self.scale:
                raise AssemblyError(
                    f"point {p} is at the foot of the perpendicular from {a} to its slide "
                    "in the sketch, so the sketch does not show the branch",
                    table="points",
                    entry=p,
                    source=self.model.source,
                )
            idx = self.idx
            self.steps.append(
                _kind(SliderStep).build(
                    idx[p],
                    idx[a],
                    o[1],
                    idx[l1],
                    idx[l2],
                    math.copysign(1.0, along),
                    len(self.transmissions),
                    sl.name,
                )
            )
            self.transmissions.append(p)
            self.consume(o)
            self.used_slider.add(si)
            self.learn(p)
            return True
        return False

    def newton_group(self, unknown: list[str]) -> None:
        """What no closed-form step reaches, solved together by Newton–Raphson."""
        self.check_no_meshes(unknown)
        cons = self._body_constraints(unknown) + self._other_constraints(unknown)
        n_eq = sum(2 if isinstance(c, CFrame) else 1 for c in cons)
        if n_eq != 2 * len(unknown):
            what = "over" if n_eq > 2 * len(unknown) else "under"
            raise MobilityError(
                f"points {', '.join(unknown)} are {what}-constrained: {n_eq} equations for "
                f"{2 * len(unknown)} coordinates (check the drivers and joints that reach them)",
                table="bodies",
                source=self.model.source,
            )
        pts = tuple(self.idx[n] for n in unknown)
        sketch = [self.sketch[n] for n in self.names]
        dyads = group_dyads(pts, cons, sketch, self.scale)
        self.steps.append(_kind(NewtonGroup).build(pts, tuple(cons), dyads))

    def add_gear_train(self) -> None:
        """The bodies the gear trains turn (`excavkin.model.gears`), each waiting for a known
        point (see `learn`)."""
        self.train = gear_train(self.model)
        self.gear_body = {self.body_index[b] for b in self.train.placed}
        self.gear_next: list[int] = []
        self.used_gear: set[int] = set()
        # each rack waits for its pinion's pivot and its guide's points
        self.rack_next: list[int] = []
        self.rack_at: dict[str, list[int]] = {}
        self.rack_placed = [0] * len(self.model.racks)
        for k, rk in enumerate(self.model.racks):
            pivot = pivot_on(self.model, rk.pinion, rk.carrier, f"racks.{rk.name}", "pinion")
            for n in {pivot, *rk.along}:
                self.rack_at.setdefault(n, []).append(k)
        # each cam's follower likewise waits for the cam's pivot and its guide's points
        self.cam_next: list[int] = []
        self.cam_at: dict[str, list[int]] = {}
        self.cam_placed = [0] * len(self.model.cams)
        for k, cm in enumerate(self.model.cams):
            pivot = pivot_on(self.model, cm.cam, cm.carrier, f"cams.{cm.name}", "cam")
            for n in {pivot, *self.cam_guide(cm)}:
                self.cam_at.setdefault(n, []).append(k)

    def held(self) -> set[str]:
        """The bodies that ``method="newton"`` still places in closed form: those of the gear
        trains (their angles are linear in the inputs), the racks and the cams' followers."""
        out = set(self.train.angles)
        out.update(rk.rack for rk in self.model.racks)
        out.update(cm.follower for cm in self.model.cams)
        out.discard(self.model.ground.name)
        return out

    def check_no_meshes(self, unknown: list[str]) -> None:
        """Refuse a Newton group that holds a body a gear or a rack moves: its mesh is a
        relation of the inputs (`excavkin.model.gears`), which only the closed-form steps
        place."""
        moved = set(self.train.placed) | {rk.rack for rk in self.model.racks}
        moved |= {cm.follower for cm in self.model.cams}
        # a body whose two points its mesh placed is held: its others are rigid with them
        caught = [
            b.name
            for b in self.bodies
            if b.name in moved
            and set(b.points) & set(unknown)
            and sum(n in self.known for n in b.points) < 2
        ]
        if caught:
            raise MobilityError(
                f"bodies {', '.join(caught)} are moved by gears or racks, which the generic "
                "solver does not hold: place them in closed form (method 'closed-form'; each "
                "needs a point placed before it, its pivot or its guide)",
                table="gears" if self.model.gears else "racks",
                source=self.model.source,
            )

    def gear(self) -> bool:
        """The first body a gear train turns with a known point and an unknown one: its first
        unknown point about its first known one, at the angle the train gives."""
        sk = self.sketch
        while self.gear_next:
            bi = heapq.heappop(self.gear_next)
            b = self.bodies[bi]
            if bi in self.used_gear:
                continue
            anchor = next((n for n in b.points if n in self.known), None)
            point = next((n for n in b.points if n not in self.known), None)
            if anchor is None or point is None:
                continue
            terms = self.train.placed[b.name]
            offset = math.atan2(sk[point][1] - sk[anchor][1], sk[point][0] - sk[anchor][0])
            inputs, coef = [], []
            for ri, c in terms:
                if c == 0.0:
                    continue
                i = self.in_idx[self.model.rotary[ri].name]
                offset -= c * self.input_sketch[i]
                inputs.append(i)
                coef.append(c)
            self.steps.append(
                _kind(GearStep).build(
                    self.idx[point],
                    self.idx[anchor],
                    self.shapes[b.name].distance(point, anchor),
                    offset,
                    tuple(inputs),
                    tuple(coef),
                    b.name,
                    self.train.meshes[b.name],
                )
            )
            self.used_gear.add(bi)
            self.body_used[bi] += 1
            self.learn(point)
            return True
        return False

    def rack(self) -> bool:
        """The first rack whose pinion's pivot and guide are known: its first two points, at
        the travel the gear train gives (`excavkin.model.gears.GearTrain.travel`)."""
        model = self.model
        while self.rack_next:
            k = heapq.heappop(self.rack_next)
            rk = model.racks[k]
            pivot = pivot_on(model, rk.pinion, rk.carrier, f"racks.{rk.name}", "pinion")
            if self.rack_placed[k] or not all(n in self.known for n in (pivot, *rk.along)):
                continue
            body = self.body_named[rk.rack]
            if any(n in self.known for n in body.points[:2]):
                continue  # fixed otherwise: refused as over-constrained after the steps
            sk = self.sketch
            (ax, ay), (bx, by) = sk[rk.along[0]], sk[rk.along[1]]
            dx, dy = bx - ax, by - ay
            d = math.hypot(dx, dy)
            terms = self.train.travel(model, rk)
            for n in body.points[:2]:
                px, py = sk[n][0] - sk[pivot][0], sk[n][1] - sk[pivot][1]
                offset = (px * dx + py * dy) / d
                inputs, coef = [], []
                for ri, c in terms:
                    if c == 0.0:
                        continue
                    i = self.in_idx[model.rotary[ri].name]
                    offset -= c * self.input_sketch[i]
                    inputs.append(i)
                    coef.append(c)
                self.steps.append(
                    _kind(RackStep).build(
                        self.idx[n],
                        self.idx[pivot],
                        self.idx[rk.along[0]],
                        self.idx[rk.along[1]],
                        offset,
                        (dx * py - dy * px) / d,
                        tuple(inputs),
                        tuple(coef),
                        rk.name,
                        rk.rack,
                    )
                )
                self.learn(n)
            # the rack's first two points: one distance of its body, the guide and the mesh
            self.body_used[self.body_index[rk.rack]] += 1
            self.rack_placed[k] = 1
            return True
        return False

    def cam(self) -> bool:
        """The first cam whose pivot and follower's guide are known: the follower's first two
        points, at the lift of the cam's turn (`excavkin.model.cams`)."""
        model = self.model
        while self.cam_next:
            k = heapq.heappop(self.cam_next)
            cm = model.cams[k]
            pivot = pivot_on(model, cm.cam, cm.carrier, f"cams.{cm.name}", "cam")
            if self.cam_placed[k] or not all(n in self.known for n in (pivot, *self.cam_guide(cm))):
                continue
            if cm.along is None:
                if not self.cam_rocker(cm):
                    continue
                self.cam_placed[k] = 1
                return True
            body = self.body_named[cm.follower]
            if any(n in self.known for n in body.points[:2]):
                continue  # fixed otherwise: refused as over-constrained after the steps
            law = lift_law(cm.lift)
            s0 = float(law(0.0)[0])
            sk = self.sketch
            l1, l2 = self.cam_guide(cm)
            (ax, ay), (bx, by) = sk[l1], sk[l2]
            dx, dy = bx - ax, by - ay
            d = math.hypot(dx, dy)
            offset, inputs, coef = 0.0, [], []
            for ri, c in self.train.turn(cm.cam, cm.carrier):
                if c == 0.0:
                    continue
                i = self.in_idx[model.rotary[ri].name]
                offset -= c * self.input_sketch[i]
                inputs.append(i)
                coef.append(c)
            for n in body.points[:2]:
                px, py = sk[n][0] - sk[pivot][0], sk[n][1] - sk[pivot][1]
                self.steps.append(
                    _kind(CamStep).build(
                        self.idx[n],
                        self.idx[pivot],
                        self.idx[l1],
                        self.idx[l2],
                        (px * dx + py * dy) / d - s0,
                        (dx * py - dy * px) / d,
                        offset,
                        tuple(inputs),
                        tuple(coef),
                        law,
                        cm.name,
                        cm.follower,
                    )
                )
                self.learn(n)
            self.body_used[self.body_index[cm.follower]] += 1
            self.cam_placed[k] = 1
            return True
        return False

    def cam_guide(self, cm: CamFollower) -> tuple[str, ...]:
        """What places a cam's follower besides the cam's pivot: its guide's two points, or
        the oscillating follower's pivot."""
        if cm.along is not None:
            return cm.along
        return (pivot_on(self.model, cm.follower, cm.carrier, f"cams.{cm.name}", "follower"),)

    def cam_rocker(self, cm: CamFollower) -> bool:
        """An oscillating follower: its first point other than its pivot, about the pivot at
        the carrier's angle plus the lift law's (`excavkin.step_kinds.cam_rocker`); whether it
        was placed."""
        model, sk = self.model, self.sketch
        (pivot,) = self.cam_guide(cm)
        body = self.body_named[cm.follower]
        point = next(n for n in body.points if n != pivot)
        if point in self.known:
            return False  # fixed otherwise: refused as over-constrained after the steps
        law = lift_law(cm.lift)
        offset = math.atan2(sk[point][1] - sk[pivot][1], sk[point][0] - sk[pivot][0])
        offset -= float(law(0.0)[0])
        carrier = dict(self.train.angles[cm.carrier])
        turn = dict(self.train.turn(cm.cam, cm.carrier))
        turn0, inputs, a, c = 0.0, [], [], []
        for ri in sorted(carrier | turn):
            ca, ct = carrier.get(ri, 0.0), turn.get(ri, 0.0)
            if ca == 0.0 and ct == 0.0:
                continue
            i = self.in_idx[model.rotary[ri].name]
            offset -= ca * self.input_sketch[i]
            turn0 -= ct * self.input_sketch[i]
            inputs.append(i)
            a.append(ca)
            c.append(ct)
        self.steps.append(
            _kind(CamRockerStep).build(
                self.idx[point],
                self.idx[pivot],
                self.shapes[body.name].distance(point, pivot),
                offset,
                turn0,
                tuple(inputs),
                tuple(a),
                tuple(c),
                law,
                cm.name,
                cm.follower,
            )
        )
        self.body_used[self.body_index[cm.follower]] += 1
        self.learn(point)
        return True

    # ---- helpers of the step kinds
    def distance_options(self, p: str) -> list[Option]:
        """Known partners of ``p`` at a known distance: its bodies' points and its elements."""
        out: list[Option] = []
        for bi in self.point_bodies[p]:
            body = self.bodies[bi]
            for a in body.points:
                if a != p and a in self.known:
                    d = self.shapes[body.name].distance(p, a)
                    dist = Dist(
                        "fixed",
                        d,
                        label=f"body {body.name!r}",
                        pair=(self.idx[p], self.idx[a]),
                        body=body.name,
                    )
                    out.append((a, dist, bi, -1))
        for ei in self.point_elements[p]:
            el = self.elements[ei]
            if ei in self.used_elem or el.mode == "free":
                continue
            pn, qn = self.names[el.p], self.names[el.q]
            other = qn if pn == p else pn if qn == p else None
            if other is None or other not in self.known:
                continue
            out.append((other, _element_dist(el), -1, ei))
        return out

    def learn(self, n: str) -> None:
        """Mark point ``n`` known, and offer each step kind what that may have made ready: a
        body with two known points (attach); a rotary driver at the point; the unknown points
        of a body that has just got its first known point, and the other end of each element
        at the point (dyad, and a slider of such a point); a slider along the point. A body's
        later known points need no offer: its other points are attached before any dyad."""
        known = self.known
        if n in known:
            return
        known.add(n)
        offer: list[str] = []
        for bi in self.point_bodies[n]:
            b = self.bodies[bi]
            c = self.body_known[bi] = self.body_known[bi] + 1
            if b.ground:
                continue
            if 2 <= c < len(b.points):
                if bi > self.attach_at:
                    heapq.heappush(self.attach_next, bi)
                else:
                    self.attach_later.append(bi)
            elif c == 1:
                offer.extend(q for q in b.points if q not in known)
        for ei in self.point_elements[n]:
            el = self.elements[ei]
            other = self.names[el.q] if self.names[el.p] == n else self.names[el.p]
            if other not in known:
                offer.append(other)
        for q in offer:
            heapq.heappush(self.dyad_next, self.idx[q])
            for si in self.slider_of_point[q]:
                heapq.heappush(self.slider_next, si)
        for ri in self.rotary_at[n]:
            heapq.heappush(self.rotate_next, ri)
        for bi in self.point_bodies[n]:
            if bi in self.gear_body:
                heapq.heappush(self.gear_next, bi)
        for k in self.rack_at.get(n, ()):
            heapq.heappush(self.rack_next, k)
        for k in self.cam_at.get(n, ()):
            heapq.heappush(self.cam_next, k)
        for si in self.slider_along[n]:
            heapq.heappush(self.slider_next, si)

    def consume(self, option: Option) -> None:
        """Count the body or element distance a step has used."""
        _, _, bi, ei = option
        if bi >= 0:
            self.body_used[bi] += 1
        if ei >= 0:
            self.used_elem.add(ei)

    def _body_constraints(self, unknown: list[str]) -> list[Constraint]:
        cons: list[Constraint] = []
        unk = set(unknown)
        idx = self.idx
        for bi, b in enumerate(self.bodies):
            if b.ground or not unk.intersection(b.points):
                continue
            p0, p1 = b.points[0], b.points[1]
            sh = self.shapes[b.name]
            d01 = Dist(
                "fixed",
                sh.distance(p0, p1),
                label=f"body {b.name!r}",
                pair=(idx[p0], idx[p1]),
                body=b.name,
            )
            cons.append(CDist(idx[p0], idx[p1], d01))
            for pi in b.points[2:]:
                s, t = sh.frame_coords(pi, p0, p1)
                cons.append(CFrame(idx[pi], idx[p0], idx[p1], s, t, b.name))
            self.body_used[bi] += 2 * len(b.points) - 3
        return cons

    def _other_constraints(self, unknown: list[str]) -> list[Constraint]:
        cons: list[Constraint] = []
        unk = set(unknown)
        idx, model = self.idx, self.model
        in_idx = self.in_idx
        for ei, el in enumerate(self.elements):
            if ei in self.used_elem or el.mode == "free":
                continue
            if {self.names[el.p], self.names[el.q]} & unk:
                cons.append(CDist(el.p, el.q, _element_dist(el)))
                self.used_elem.add(ei)
        for si, sl in enumerate(model.sliders):
            if si not in self.used_slider and {sl.point, *sl.along} & unk:
                cons.append(CLine(idx[sl.point], idx[sl.along[0]], idx[sl.along[1]]))
                self.used_slider.add(si)
        for k, con in enumerate(self.ropes):
            if k not in self.used_rope and {self.names[p] for p in con.points} & unk:
                cons.append(con)
                self.used_rope.add(k)
        for ri, rd in enumerate(model.rotary):
            if ri in self.used_rotary:
                continue
            p = next(n for n in self.body_named[rd.body].points if n != rd.pivot)
            refb = self.body_named[rd.reference]
            ref = None if refb.ground else (idx[refb.points[0]], idx[refb.points[1]])
            involved = {p, rd.pivot} | (set() if refb.ground else set(refb.points[:2]))
            if involved & unk:
                cons.append(CAngle(idx[p], idx[rd.pivot], ref, in_idx[rd.name]))
                self.used_rotary.add(ri)
        return cons

    # ---- after the steps
    def check_all_used(self) -> None:
        """Every element, slider, rotary driver and body shape has been used by a step."""
        src = self.model.source
        for ei, el in enumerate(self.elements):
            if el.mode != "free" and ei not in self.used_elem:
                kind = "driver" if el.mode == "driven" else "locked element"
                raise MobilityError(
                    f"{kind} {el.name!r} is redundant: both its points are already fixed by the "
                    "rest of the mechanism (over-constrained; make it 'free' or remove a joint)",
                    table=f"drivers.{el.name}",
                    source=src,
                )
        for k, con in enumerate(self.ropes):
            if k not in self.used_rope:
                raise MobilityError(
                    f"rope {con.name!r} is redundant: every point of its path is already fixed "
                    "by the rest of the mechanism (over-constrained)",
                    table=f"ropes.{con.name}",
                    source=src,
                )
        for si, s in enumerate(self.model.sliders):
            if si not in self.used_slider:
                raise MobilityError(
                    f"slider {s.name!r} is redundant: its point and line are already fixed by "
                    "the rest of the mechanism (over-constrained)",
                    table=f"sliders.{s.name}",
                    source=src,
                )
        for ri, d in enumerate(self.model.rotary):
            if ri not in self.used_rotary:
                raise MobilityError(
                    f"rotary driver {d.name!r} is redundant: body {d.body!r} is already fixed by "
                    "the rest of the mechanism (over-constrained)",
                    table=f"drivers.{d.name}",
                    source=src,
                )
        for bi in sorted(self.gear_body - self.used_gear):
            name = self.bodies[bi].name
            raise MobilityError(
                f"body {name!r} is turned by its gears ({', '.join(self.train.meshes[name])}) "
                "but also fixed by the rest of the mechanism (over-constrained), or none of its "
                "points is placed before it",
                table="gears",
                source=src,
            )
        for k, rk in enumerate(self.model.racks):
            if not self.rack_placed[k]:
                raise MobilityError(
                    f"rack {rk.name!r}: body {rk.rack!r} is fixed by the rest of the mechanism "
                    "as well as by its guide and pinion (over-constrained), or its pinion's "
                    "pivot or guide is not placed before it",
                    table=f"racks.{rk.name}",
                    source=src,
                )
        for k, cm in enumerate(self.model.cams):
            if not self.cam_placed[k]:
                raise MobilityError(
                    f"cam {cm.name!r}: follower {cm.follower!r} is fixed by the rest of the "
                    "mechanism as well as by its guide and cam (over-constrained), or the cam's "
                    "pivot or the guide is not placed before it",
                    table=f"cams.{cm.name}",
                    source=src,
                )
        for bi, b in enumerate(self.bodies):
            need = 0 if b.ground else 2 * len(b.points) - 3
            if self.body_used[bi] < need:
                raise MobilityError(
                    f"body {b.name!r} is over-constrained: its points are fixed through other "
                    "bodies, so its own shape would be a redundant constraint (check its joints)",
                    table="bodies",
                    entry=b.name,
                    source=src,
                )

    def build(self) -> SolvePlan:
        """Add steps until every point is known, check every constraint is used, and freeze."""
        self.add_inputs()
        self.check_lengths_are_dimensions()
        self.check_sliders_on_their_lines()
        self.fixed()
        if self.method == "closed-form":
            tries: list[Callable[[], bool]] = [getattr(self, kind) for kind in self.ORDER]
        else:  # the higher pairs' bodies still in closed form: their angles are the inputs'
            tries = [self.attach, self.rotate, self.gear, self.rack, self.cam]
        # after any step, start again from the first kind: attach before all else
        while len(self.known) < len(self.names) and any(t() for t in tries):
            pass
        unknown = [n for n in self.names if n not in self.known]
        if unknown:
            self.newton_group(unknown)
        self.check_all_used()
        return self.freeze()

    def freeze(self) -> SolvePlan:
        """The finished plan."""
        model, idx = self.model, self.idx
        return SolvePlan(
            model=model,
            points=self.names,
            bodies=tuple(b.name for b in self.bodies),
            ground=next(i for i, b in enumerate(self.bodies) if b.ground),
            body_base=tuple(
                (idx[b.points[0]], idx[b.points[1]]) if len(b.points) >= 2 else (-1, -1)
                for b in self.bodies
            ),
            inputs=model.inputs,
            input_kinds=tuple(self.kinds),
            input_sketch=tuple(self.input_sketch),
            elements=tuple(self.elements),
            transmissions=tuple(self.transmissions),
            steps=tuple(self.steps),
            sketch=tuple(self.sketch[n] for n in self.names),
            shapes=self.shapes,
            mobility=mobility(model),
            scale=self.scale,
            method=self.method,
        )


def rope_signed_radii(rope: Rope) -> tuple[float, ...]:
    """Each sheave's signed radius σ·r of a rope over sheaves (σ = +1 counter-clockwise).

    Parameters
    ----------
    rope : Rope
        A rope over sheaves.

    Returns
    -------
    tuple of float
        m, one per inner point of its path.
    """
    return tuple(r if w == "ccw" else -r for r, w in zip(rope.radii, rope.wraps, strict=True))


def winch_ratio(model: Model, name: str) -> float:
    """The blocks' distance per motor angle of the winch rope called ``name`` (m/rad).

    Parameters
    ----------
    model : Model
        The model.
    name : str
        A linear element's name.

    Returns
    -------
    float
        ``R/(i·parts)`` of the winch rope of that name; 0.0 when it is no winch rope.
    """
    return next((r.ratio for r in model.ropes if r.name == name and not r.over_sheaves), 0.0)


def _element_dist(el: Element) -> Dist:
    """A driven element's distance is its input (a winch rope's: ``ratio`` times its motor's
    angle); a locked one's is its fixed length."""
    if el.mode == "driven" and el.ratio:
        return Dist("input", el.length, el.input, label=el.name, scale=el.ratio, winch=el.name)
    if el.mode == "driven":
        return Dist("input", el.length, el.input, label=el.name)
    return Dist("fixed", el.length, label=f"locked {el.name!r}", pair=(el.p, el.q))


def _unit(p: tuple[float, float], q: tuple[float, float]) -> tuple[float, float]:
    dx, dy = p[0] - q[0], p[1] - q[1]
    r = math.hypot(dx, dy)
    return dx / r, dy / r


def _cross(ax: float, ay: float, bx: float, by: float) -> float:
    return ax * by - ay * bx


def _kind(record: type) -> StepKind[Step]:
    """The registered kind whose steps are ``record``s: the builder makes each step by it."""
    return registered()[record]
