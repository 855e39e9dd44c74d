"""A point of a driven body about its pivot: ``θ = θ_ref + q``.

``point = pivot + radius·(cos θ, sin θ)``; with a moving reference body (``ref``, its base
vector b0→b1 at angle θ_ref), ``θ̇ = q̇ + ω_ref`` and ``θ̈ = q̈ + ε_ref``.
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
class Rotate:
    """``point = pivot + radius·(cos θ, sin θ)``, ``θ = θ_ref + q[input]``."""

    point: int
    pivot: int
    radius: float
    input: int
    ref: tuple[int, int] | None
    driver: str


@register
class RotateKind(StepKind[Rotate]):
    """A rotary driver's body."""

    name = "rotate"
    record = Rotate
    compiles = True
    iterative = False

    def build(
        self,
        point: int,
        pivot: int,
        radius: float,
        input: int,
        ref: tuple[int, int] | None,
        driver: str,
    ) -> Rotate:
        return Rotate(point, pivot, radius, input, ref, driver)

    def vary(self, st: Rotate, geo: Geometry, names: tuple[str, ...], model: Model) -> Rotate:
        body = next(d.body for d in model.rotary if d.name == st.driver)
        radius = geo.distance(body, names[st.point], names[st.pivot])
        return dataclasses.replace(st, radius=radius) if varies(radius) else st

    def take(self, st: Rotate, index: Index) -> Rotate:
        return dataclasses.replace(st, radius=at(st.radius, index)) if np.ndim(st.radius) else st

    def solve(
        self, c: Chunk, st: Rotate, k: int, order: int, scale: float, newton: bool = True
    ) -> F | None:
        """A point of a driven body about its pivot: θ = θ_ref + q."""
        x, v, a = c.x, c.v, c.a
        q = c.q[st.input]
        r = st.radius
        if st.ref is None:
            th = q
        else:
            b0, b1 = st.ref
            rx = x[b1, 0] - x[b0, 0]
            ry = x[b1, 1] - x[b0, 1]
            th = q + np.arctan2(ry, rx)
        cs, sn = np.cos(th), np.sin(th)
        x[st.point, 0] = x[st.pivot, 0] + r * cs
        x[st.point, 1] = x[st.pivot, 1] + r * sn
        if not order:
            return None
        thd, thdd = c.qd[st.input], c.qdd[st.input]
        if st.ref is not None:
            b0, b1 = st.ref
            rvx, rvy = v[b1, 0] - v[b0, 0], v[b1, 1] - v[b0, 1]
            rax, ray = a[b1, 0] - a[b0, 0], a[b1, 1] - a[b0, 1]
            r2 = rx * rx + ry * ry
            w_ref = (rx * rvy - ry * rvx) / r2
            thd = thd + w_ref
            thdd = thdd + (rx * ray - ry * rax - 2.0 * (rx * rvx + ry * rvy) * w_ref) / r2
        v[st.point, 0] = v[st.pivot, 0] - r * thd * sn
        v[st.point, 1] = v[st.pivot, 1] + r * thd * cs
        a[st.point, 0] = a[st.pivot, 0] - r * (thdd * sn + thd * thd * cs)
        a[st.point, 1] = a[st.pivot, 1] + r * (thdd * cs - thd * thd * sn)
        return None

    def nudge(self, c: Chunk, st: Rotate, order: int) -> None:
        round_output(c, st.point, order)

    def transmission(self, st: Rotate) -> int | None:
        return None

    def constants(self, st: Rotate) -> list[Any]:
        return [st.radius]

    def emit(self, g: Emitter, st: Rotate, k: int) -> None:
        p, o, i = st.point, st.pivot, st.input
        atan2 = g.atan2
        g.emit(f"r = {g.const()}", f"th = q[{i}, i]")
        if st.ref is not None:
            b0, b1 = st.ref
            g.emit(f"rx = X{b1} - X{b0}", f"ry = Y{b1} - Y{b0}", f"th = th + {atan2}(ry, rx)")
        g.emit(
            "cs = math.cos(th)", "sn = math.sin(th)",
            f"X{p} = X{o} + r * cs", f"Y{p} = Y{o} + r * sn",
            f"thd = qd[{i}, i]", f"thdd = qdd[{i}, i]",
        )  # fmt: skip
        if st.ref is not None:
            b0, b1 = st.ref
            g.emit(
                f"rvx = VX{b1} - VX{b0}", f"rvy = VY{b1} - VY{b0}",
                f"rax = AX{b1} - AX{b0}", f"ray = AY{b1} - AY{b0}",
                "r2 = rx * rx + ry * ry",
                "w_ref = (rx * rvy - ry * rvx) / r2",
                "thd = thd + w_ref",
                "thdd = thdd + (rx * ray - ry * rax - 2.0 * (rx * rvx + ry * rvy) * w_ref) / r2",
            )  # fmt: skip
        g.emit(
            f"VX{p} = VX{o} - r * thd * sn", f"VY{p} = VY{o} + r * thd * cs",
            f"AX{p} = AX{o} - r * (thdd * sn + thd * thd * cs)",
            f"AY{p} = AY{o} + r * (thdd * cs - thd * thd * sn)",
        )  # fmt: skip

    def describe(self, st: Rotate, names: tuple[str, ...]) -> str:
        ref = "ground" if st.ref is None else f"{names[st.ref[0]]}→{names[st.ref[1]]}"
        return (
            f"rotate   {names[st.point]} about {names[st.pivot]} by driver "
            f"{st.driver!r} (from {ref}, r = {st.radius:.6g} m)"
        )

    def label(self, st: Rotate, names: tuple[str, ...], k: int) -> str:
        return f"step {k + 1}"

    def folding(self, st: Rotate) -> list[tuple[int, Any]]:
        return []

    def turn(self, st: Rotate, place: int, turn: Any) -> Rotate:
        raise TypeError("a rotary driver's step has no dyad to turn")

    def role(self, st: Rotate) -> Role:
        return Role(places=(st.point,), efforts=(st.input,))

    def drawing(self, st: Rotate) -> tuple[Primitive, ...]:
        return (Primitive("arc", (st.pivot, st.point), driven=True),)
