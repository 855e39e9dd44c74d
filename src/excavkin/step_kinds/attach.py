"""A point of a body with two known points, by the body's frame.

``P = A + s·(B − A) + t·perp(B − A)``, ``perp(v) = (−v_y, v_x)``: linear in A and B, so
velocities and accelerations follow the same formula.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.model.entities import Model
from excavkin.step_kinds.base import Emitter, Geometry, Primitive, Role, StepKind, register
from excavkin.step_kinds.dist import Index, at, varies
from excavkin.step_kinds.state import Chunk, round_output


@dataclass(frozen=True, slots=True)
class Attach:
    """``point = a + s·(b − a) + t·perp(b − a)``, ``perp(v) = (−v_y, v_x)``."""

    point: int
    a: int
    b: int
    s: float
    t: float
    body: str


@register
class AttachKind(StepKind[Attach]):
    """A point carried by its body's frame."""

    name = "attach"
    record = Attach
    compiles = True
    iterative = False

    def build(self, point: int, a: int, b: int, s: float, t: float, body: str) -> Attach:
        return Attach(point, a, b, s, t, body)

    def vary(self, st: Attach, geo: Geometry, names: tuple[str, ...], model: Model) -> Attach:
        s, t = geo.frame_coords(st.body, names[st.point], names[st.a], names[st.b])
        return dataclasses.replace(st, s=s, t=t) if varies(s) or varies(t) else st

    def take(self, st: Attach, index: Index) -> Attach:
        if np.ndim(st.s) or np.ndim(st.t):
            return dataclasses.replace(st, s=at(st.s, index), t=at(st.t, index))
        return st

    def solve(
        self, c: Chunk, st: Attach, k: int, order: int, scale: float, newton: bool = True
    ) -> F | None:
        """P = A + s·(B − A) + t·perp(B − A): linear in A and B, so every order alike."""
        s, t = st.s, st.t
        arrays = (c.x, c.v, c.a) if order else (c.x,)
        for arr in arrays:
            wx = arr[st.b, 0] - arr[st.a, 0]
            wy = arr[st.b, 1] - arr[st.a, 1]
            arr[st.point, 0] = arr[st.a, 0] + s * wx - t * wy
            arr[st.point, 1] = arr[st.a, 1] + s * wy + t * wx
        return None

    def nudge(self, c: Chunk, st: Attach, order: int) -> None:
        round_output(c, st.point, order)

    def transmission(self, st: Attach) -> int | None:
        return None

    def constants(self, st: Attach) -> list[Any]:
        return [st.s, st.t]

    def emit(self, g: Emitter, st: Attach, k: int) -> None:
        p, a, b = st.point, st.a, st.b
        g.emit(f"s = {g.const()}", f"t = {g.const()}")
        for X, Y in (("X", "Y"), ("VX", "VY"), ("AX", "AY")):
            g.emit(
                f"wx = {X}{b} - {X}{a}", f"wy = {Y}{b} - {Y}{a}",
                f"{X}{p} = {X}{a} + s * wx - t * wy", f"{Y}{p} = {Y}{a} + s * wy + t * wx",
            )  # fmt: skip

    def describe(self, st: Attach, names: tuple[str, ...]) -> str:
        return f"attach   {names[st.point]} to body {st.body!r} via {names[st.a]}, {names[st.b]}"

    def label(self, st: Attach, names: tuple[str, ...], k: int) -> str:
        return f"step {k + 1}"

    def folding(self, st: Attach) -> list[tuple[int, Any]]:
        return []

    def turn(self, st: Attach, place: int, turn: Any) -> Attach:
        raise TypeError("an attached point has no dyad to turn")

    def role(self, st: Attach) -> Role:
        return Role(places=(st.point,), efforts=())

    def drawing(self, st: Attach) -> tuple[Primitive, ...]:
        return (Primitive("link", (st.a, st.point)), Primitive("link", (st.b, st.point)))
