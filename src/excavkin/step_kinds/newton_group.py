"""What no closed-form step reaches: a higher-class group's points, solved together by
batched Newton–Raphson from the sketch (`excavkin.step_kinds.newton_solve`), with the
constraints of `excavkin.step_kinds.constraints`. It has no place in the closed-form plan's
compiled kernel; a plan with groups has kernels of its own (`excavkin.step_kinds.newton_emit`,
`excavkin.kinematics.compiled_newton`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.model.entities import Model
from excavkin.step_kinds.base import Emitter, Geometry, Primitive, Role, StepKind, register
from excavkin.step_kinds.constraints import CAngle, CDist, CFrame, Constraint, CRope, GroupDyad
from excavkin.step_kinds.dist import (
    Index,
    at,
    compiled_value,
    dist_inputs,
    take_dist,
    varies,
    vary_dist,
)
from excavkin.step_kinds.newton_emit import emit_group
from excavkin.step_kinds.newton_solve import newton_positions, newton_rates, ropes_on_sheaves
from excavkin.step_kinds.rope_path import rope_path
from excavkin.step_kinds.state import Chunk


@dataclass(frozen=True, slots=True)
class NewtonGroup:
    """Points solved together by batched Newton–Raphson, started from the sketch.

    ``dyads``: its points held by two distances alone, in the order they could be solved (each
    after the points it hangs from; `group_dyads`).
    """

    points: tuple[int, ...]
    constraints: tuple[Constraint, ...]
    dyads: tuple[GroupDyad, ...] = ()


@register
class NewtonGroupKind(StepKind[NewtonGroup]):
    """A group solved by iteration."""

    name = "newton"
    record = NewtonGroup
    compiles = False
    iterative = True

    def build(
        self,
        points: tuple[int, ...],
        constraints: tuple[Constraint, ...],
        dyads: tuple[GroupDyad, ...] = (),
    ) -> NewtonGroup:
        return NewtonGroup(points, constraints, dyads)

    def vary(
        self, st: NewtonGroup, geo: Geometry, names: tuple[str, ...], model: Model
    ) -> NewtonGroup:
        cons = []
        for con in st.constraints:
            if isinstance(con, CRope) and (signed := geo.rope_signed(con.name)) is not None:
                con = dataclasses.replace(con, signed=signed)  # its sheave radii given
            if isinstance(con, CDist):
                con = dataclasses.replace(con, dist=vary_dist(con.dist, geo, names))
            elif isinstance(con, CRope) and con.dist.kind == "fixed":  # a locked rope's length
                pts = [geo.sketch[names[p]] for p in con.points]
                length = rope_path(pts, con.signed, con.wraps0).length
                if varies(length):
                    con = dataclasses.replace(con, dist=dataclasses.replace(con.dist, value=length))
            elif isinstance(con, CRope):  # a winch's: its length per motor angle
                con = dataclasses.replace(con, dist=vary_dist(con.dist, geo, names))
            elif isinstance(con, CFrame) and con.body:
                s, t = geo.frame_coords(con.body, names[con.p], names[con.a], names[con.b])
                if varies(s) or varies(t):
                    con = dataclasses.replace(con, s=s, t=t)
            cons.append(con)
        return dataclasses.replace(st, constraints=tuple(cons))

    def take(self, st: NewtonGroup, index: Index) -> NewtonGroup:
        cons = []
        changed = False
        for con in st.constraints:
            if isinstance(con, CRope) and any(np.ndim(r) for r in con.signed):
                cut = tuple(at(r, index) if np.ndim(r) else r for r in con.signed)
                con = dataclasses.replace(con, signed=cut)
                changed = True
            if isinstance(con, CDist | CRope) and np.ndim(con.dist.value):
                con = dataclasses.replace(con, dist=take_dist(con.dist, index))
                changed = True
            elif isinstance(con, CFrame) and (np.ndim(con.s) or np.ndim(con.t)):
                con = dataclasses.replace(con, s=at(con.s, index), t=at(con.t, index))
                changed = True
            cons.append(con)
        dyads = st.dyads
        if any(np.ndim(d.sign) for d in dyads):  # a smooth continuation's sides, per sample
            dyads = tuple(dataclasses.replace(d, sign=at(d.sign, index)) for d in dyads)
            changed = True
        return dataclasses.replace(st, constraints=tuple(cons), dyads=dyads) if changed else st

    def solve(
        self, c: Chunk, st: NewtonGroup, k: int, order: int, scale: float, newton: bool = True
    ) -> F | None:
        """Newton iterations for the positions (unless ``newton`` is False), then the rates
        by one factorisation of the Jacobian; returns its determinant's sign (order 2)."""
        if newton:
            newton_positions(c, st, k, scale)
            ropes_on_sheaves(c, st, k)
        if order:
            return newton_rates(c, st, k)
        return None

    def nudge(self, c: Chunk, st: NewtonGroup, order: int) -> None:
        return None  # emulated in its residuals (`newton_solve`), not on its output

    def transmission(self, st: NewtonGroup) -> int | None:
        return None

    def constants(self, st: NewtonGroup) -> list[Any]:
        out: list[Any] = []
        for con in st.constraints:
            if isinstance(con, CDist | CRope):
                out.append(compiled_value(con.dist))
            if isinstance(con, CFrame):
                out += [con.s, con.t]
            if isinstance(con, CRope):
                out += [*con.signed, *con.wraps0]
        return out + [d.sign for d in st.dyads]

    def emit(self, g: Emitter, st: NewtonGroup, k: int) -> None:
        mode = getattr(g, "newton", None)  # a Newton plan's kernel says which
        if mode is None:
            raise TypeError(f"step {k} ({type(st).__name__}) cannot be compiled")
        emit_group(g, st, k, mode)

    def describe(self, st: NewtonGroup, names: tuple[str, ...]) -> str:
        return (
            f"newton   {', '.join(names[i] for i in st.points)} together "
            f"({len(st.constraints)} constraints)"
        )

    def label(self, st: NewtonGroup, names: tuple[str, ...], k: int) -> str:
        return f"group {', '.join(names[i] for i in st.points)}"

    def folding(self, st: NewtonGroup) -> list[tuple[int, Any]]:
        return list(enumerate(st.dyads))

    def turn(self, st: NewtonGroup, place: int, turn: Any) -> NewtonGroup:
        d = st.dyads[place]
        signed = dataclasses.replace(d, sign=d.sign * turn)
        return dataclasses.replace(st, dyads=(*st.dyads[:place], signed, *st.dyads[place + 1 :]))

    def role(self, st: NewtonGroup) -> Role:
        efforts: list[int] = []
        for con in st.constraints:
            if isinstance(con, CDist | CRope):
                efforts += dist_inputs(con.dist)
            elif isinstance(con, CAngle):
                efforts.append(con.input)
        return Role(places=st.points, efforts=tuple(efforts))

    def drawing(self, st: NewtonGroup) -> tuple[Primitive, ...]:
        out = [Primitive("group", st.points)]
        for con in st.constraints:
            if isinstance(con, CDist):
                out.append(Primitive("link", (con.q, con.p), driven=con.dist.kind == "input"))
            elif isinstance(con, CFrame):
                out += [Primitive("link", (con.a, con.p)), Primitive("link", (con.b, con.p))]
            elif isinstance(con, CAngle):
                out.append(Primitive("arc", (con.pivot, con.p), driven=True))
            elif isinstance(con, CRope):
                driven = con.dist.kind == "input"
                out += [
                    Primitive("link", (p, q), driven=driven)
                    for p, q in zip(con.points, con.points[1:], strict=False)
                ]
            else:
                out.append(Primitive("slide", (con.l1, con.l2, con.p)))
        return tuple(out)
