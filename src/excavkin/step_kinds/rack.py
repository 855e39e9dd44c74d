"""A point of a rack that its pinion moves along its guide: ``s = s0 + Σ c_i q_i``.

The rack translates along a guide on its carrier, through the points ``l1 → l2`` of the
carrier, with ``D = l2 − l1`` (a constant length ``d``: the carrier is rigid). In the guide's
frame at the pinion's pivot ``o`` a point of the rack is::

    X = o + (s·D + b·perp(D)) / d,     perp(D) = (−Dy, Dx)

with ``b`` its constant offset from the pinion's line along the guide and ``s`` its travel,
a linear function of the rotary inputs with constant coefficients
(`excavkin.model.gears.GearTrain.travel`). Its rates follow by differentiating that closed form
(d is constant in time)::

    Ẋ = ȯ + (ṡ·D + s·Ḋ + b·perp(Ḋ)) / d
    Ẍ = ö + (s̈·D + 2ṡ·Ḋ + s·D̈ + b·perp(D̈)) / d
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.model.entities import Model
from excavkin.model.gears import rack_side
from excavkin.step_kinds.base import Emitter, Geometry, Primitive, Role, StepKind, register
from excavkin.step_kinds.dist import Index, at, varies
from excavkin.step_kinds.gear import sketch_input_angle, train_coefficients
from excavkin.step_kinds.state import Chunk, round_output


@dataclass(frozen=True, slots=True)
class RackStep:
    """``X = o + (s·D + b·perp(D))/d``, ``s = offset + Σ coef[k]·q[inputs[k]]``,
    ``D = x[l2] − x[l1]``; ``rack`` names the rack and pinion, ``body`` the rack body."""

    point: int
    origin: int
    l1: int
    l2: int
    offset: float
    across: float
    inputs: tuple[int, ...]
    coef: tuple[Any, ...]
    rack: str
    body: str


def _frame(sk: Any, names: tuple[str, ...], st: RackStep) -> tuple[Any, Any]:
    """(along, across) of the step's point in the guide's frame at its origin, in a sketch."""
    (ax, ay), (bx, by) = sk[names[st.l1]], sk[names[st.l2]]
    dx, dy = bx - ax, by - ay
    d = np.hypot(dx, dy)
    px = sk[names[st.point]][0] - sk[names[st.origin]][0]
    py = sk[names[st.point]][1] - sk[names[st.origin]][1]
    return (px * dx + py * dy) / d, (dx * py - dy * px) / d


@register
class RackKind(StepKind[RackStep]):
    """A rack moved by its pinion along its guide."""

    name = "rack"
    record = RackStep
    compiles = True
    iterative = False

    def build(
        self,
        point: int,
        origin: int,
        l1: int,
        l2: int,
        offset: float,
        across: float,
        inputs: tuple[int, ...],
        coef: tuple[float, ...],
        rack: str,
        body: str,
    ) -> RackStep:
        return RackStep(point, origin, l1, l2, offset, across, inputs, coef, rack, body)

    def vary(self, st: RackStep, geo: Geometry, names: tuple[str, ...], model: Model) -> RackStep:
        sk = geo.sketch
        offset, across = _frame(sk, names, st)
        rk = next(r for r in model.racks if r.name == st.rack)
        radius = geo.rack_radius(rk.name)
        if geo.train() is None:  # the plan's own turns, at the pitch radius given
            given = radius is not rk.radius
            coef = tuple(c * (radius / rk.radius) for c in st.coef) if given else st.coef
        else:
            scale = -rack_side(model, rk) * radius
            coef = train_coefficients(geo, model, rk.pinion, rk.carrier, st.inputs, st.coef, scale)
        rotary = {d.name: k for k, d in enumerate(model.rotary)}
        for i, c in zip(st.inputs, coef, strict=True):
            offset = offset - c * sketch_input_angle(sk, model, rotary[model.inputs[i]])
        if not (varies(offset) or varies(across) or any(varies(c) for c in coef)):
            return st
        return dataclasses.replace(st, offset=offset, across=across, coef=coef)

    def take(self, st: RackStep, index: Index) -> RackStep:
        if not (np.ndim(st.offset) or np.ndim(st.across) or any(np.ndim(c) for c in st.coef)):
            return st
        return dataclasses.replace(
            st,
            offset=at(st.offset, index) if np.ndim(st.offset) else st.offset,
            across=at(st.across, index) if np.ndim(st.across) else st.across,
            coef=tuple(at(c, index) if np.ndim(c) else c for c in st.coef),
        )

    def solve(
        self, c: Chunk, st: RackStep, k: int, order: int, scale: float, newton: bool = True
    ) -> F | None:
        """A point of a rack along its guide: s = s0 + Σ c_i q_i."""
        x, v, a = c.x, c.v, c.a
        s: Any = st.offset
        for i, co in zip(st.inputs, st.coef, strict=True):
            s = s + co * c.q[i]
        b = st.across
        dx, dy = x[st.l2, 0] - x[st.l1, 0], x[st.l2, 1] - x[st.l1, 1]
        inv = 1.0 / np.hypot(dx, dy)
        x[st.point, 0] = x[st.origin, 0] + (s * dx - b * dy) * inv
        x[st.point, 1] = x[st.origin, 1] + (s * dy + b * dx) * inv
        if not order:
            return None
        sd: Any = 0.0
        sdd: Any = 0.0
        for i, co in zip(st.inputs, st.coef, strict=True):
            sd = sd + co * c.qd[i]
            sdd = sdd + co * c.qdd[i]
        vx, vy = v[st.l2, 0] - v[st.l1, 0], v[st.l2, 1] - v[st.l1, 1]
        ax, ay = a[st.l2, 0] - a[st.l1, 0], a[st.l2, 1] - a[st.l1, 1]
        o = st.origin
        v[st.point, 0] = v[o, 0] + (sd * dx + s * vx - b * vy) * inv
        v[st.point, 1] = v[o, 1] + (sd * dy + s * vy + b * vx) * inv
        a[st.point, 0] = a[o, 0] + (sdd * dx + 2.0 * sd * vx + s * ax - b * ay) * inv
        a[st.point, 1] = a[o, 1] + (sdd * dy + 2.0 * sd * vy + s * ay + b * ax) * inv
        return None

    def nudge(self, c: Chunk, st: RackStep, order: int) -> None:
        round_output(c, st.point, order)

    def transmission(self, st: RackStep) -> int | None:
        return None

    def constants(self, st: RackStep) -> list[Any]:
        return [st.offset, st.across, *st.coef]

    def emit(self, g: Emitter, st: RackStep, k: int) -> None:
        p, o, l1, l2 = st.point, st.origin, st.l1, st.l2
        g.emit(f"s = {g.const()}", f"b = {g.const()}", "sd = 0.0", "sdd = 0.0")
        for i in st.inputs:
            g.emit(
                f"mesh_c = {g.const()}",
                f"s = s + mesh_c * q[{i}, i]",
                f"sd = sd + mesh_c * qd[{i}, i]",
                f"sdd = sdd + mesh_c * qdd[{i}, i]",
            )
        g.emit(
            f"dx = X{l2} - X{l1}", f"dy = Y{l2} - Y{l1}",
            "inv = 1.0 / math.sqrt(dx * dx + dy * dy)",
            f"X{p} = X{o} + (s * dx - b * dy) * inv",
            f"Y{p} = Y{o} + (s * dy + b * dx) * inv",
            f"rvx = VX{l2} - VX{l1}", f"rvy = VY{l2} - VY{l1}",
            f"rax = AX{l2} - AX{l1}", f"ray = AY{l2} - AY{l1}",
            f"VX{p} = VX{o} + (sd * dx + s * rvx - b * rvy) * inv",
            f"VY{p} = VY{o} + (sd * dy + s * rvy + b * rvx) * inv",
            f"AX{p} = AX{o} + (sdd * dx + 2.0 * sd * rvx + s * rax - b * ray) * inv",
            f"AY{p} = AY{o} + (sdd * dy + 2.0 * sd * rvy + s * ray + b * rax) * inv",
        )  # fmt: skip

    def describe(self, st: RackStep, names: tuple[str, ...]) -> str:
        terms = " ".join(
            f"{'+' if co >= 0 else '−'} {abs(co):.6g}·q{i}"
            for i, co in zip(st.inputs, (float(np.max(c)) for c in st.coef), strict=True)
        )
        return (
            f"rack     {names[st.point]} along {names[st.l1]}→{names[st.l2]} from "
            f"{names[st.origin]}: body {st.body!r} moved by {st.rack!r} (s = s0 {terms} m)"
        )

    def label(self, st: RackStep, names: tuple[str, ...], k: int) -> str:
        return f"step {k + 1} (rack {st.rack})"

    def folding(self, st: RackStep) -> list[tuple[int, Any]]:
        return []

    def turn(self, st: RackStep, place: int, turn: Any) -> RackStep:
        raise TypeError("a rack's step has no dyad to turn")

    def role(self, st: RackStep) -> Role:
        return Role(places=(st.point,), efforts=())

    def drawing(self, st: RackStep) -> tuple[Primitive, ...]:
        return (Primitive("slide", (st.point, st.l1, st.l2)),)
