"""P on the line l1→l2 at distance d from A (RRP dyad).

Constraints, with u = l2 − l1 and g = P − l1::

    cross(u, g) = 0                         (P − A)·(P − A) = d²
    cross(u, Ṗ) = cross(u, l̇1) − cross(u̇, g)
    cross(u, P̈) = cross(u, l̈1) − cross(ü, g) − 2·cross(u̇, ġ)
    (P − A)·Ṗ = (P − A)·Ȧ + d·ḋ
    (P − A)·P̈ = (P − A)·Ä + d·d̈ + ḋ² − |Ṗ − Ȧ|²

The determinant is −u·(P − A): the dead position has the link square to the slide.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.model.entities import Model
from excavkin.step_kinds.base import Emitter, Geometry, Primitive, Role, StepKind, register
from excavkin.step_kinds.dist import (
    Dist,
    Index,
    compiled_value,
    describe_dist,
    dist_inputs,
    take_dist,
    vary_dist,
)
from excavkin.step_kinds.state import Chunk, Code, dist, flag, round_output


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


@register
class SliderKind(StepKind[SliderStep]):
    """A point on a slide, at a distance from a known point."""

    name = "slider"
    record = SliderStep
    compiles = True
    iterative = False

    def build(
        self,
        point: int,
        a: int,
        da: Dist,
        l1: int,
        l2: int,
        sign: float,
        index: int,
        slider: str,
    ) -> SliderStep:
        return SliderStep(point, a, da, l1, l2, sign, index, slider)

    def vary(
        self, st: SliderStep, geo: Geometry, names: tuple[str, ...], model: Model
    ) -> SliderStep:
        return dataclasses.replace(st, da=vary_dist(st.da, geo, names))

    def take(self, st: SliderStep, index: Index) -> SliderStep:
        return dataclasses.replace(st, da=take_dist(st.da, index)) if np.ndim(st.da.value) else st

    def solve(
        self, c: Chunk, st: SliderStep, k: int, order: int, scale: float, newton: bool = True
    ) -> F | None:
        """P on the line l1→l2 at distance d from A (RRP dyad)."""
        x, v, a = c.x, c.v, c.a
        l1x, l1y = x[st.l1, 0], x[st.l1, 1]
        ux = x[st.l2, 0] - l1x
        uy = x[st.l2, 1] - l1y
        lu = np.sqrt(ux * ux + uy * uy)
        ex, ey = ux / lu, uy / lu
        ax, ay = x[st.a, 0], x[st.a, 1]
        gx, gy = ax - l1x, ay - l1y
        foot = gx * ex + gy * ey
        off = ex * gy - ey * gx
        d, dd, ddd = dist(c, st.da)
        s2 = (d * d - off * off) / (d * d)
        if c.nudge is not None:
            s2 = s2 + c.nudge * (1.0 + off * off / (d * d))
        low = ~(s2 >= c.close_tol)  # NaN too: the slide's two points coincide
        if low.any():
            bad = ~(s2 >= -c.close_tol)
            flag(c, bad, Code.NO_CLOSURE, k)
            s2 = np.where(bad, np.nan, np.maximum(s2, 0.0))
        along = foot + st.sign * np.abs(d) * np.sqrt(s2)
        px = l1x + along * ex
        py = l1y + along * ey
        x[st.point, 0] = px
        x[st.point, 1] = py
        r1x, r1y = px - ax, py - ay
        dot = ux * r1x + uy * r1y
        c.trans[st.index] = np.arctan2(np.abs(dot), np.abs(ux * r1y - uy * r1x))
        if not order:
            return None
        det = -dot
        sing = ~(np.abs(det) > c.singular_tol * lu * np.abs(d))
        if sing.any():
            flag(c, sing, Code.SINGULAR, k)
            det = np.where(sing, np.nan, det)
        inv = 1.0 / det
        gx, gy = px - l1x, py - l1y
        udx = v[st.l2, 0] - v[st.l1, 0]
        udy = v[st.l2, 1] - v[st.l1, 1]
        vl1x, vl1y = v[st.l1, 0], v[st.l1, 1]
        vax, vay = v[st.a, 0], v[st.a, 1]
        f1 = (ux * vl1y - uy * vl1x) - (udx * gy - udy * gx)
        f2 = r1x * vax + r1y * vay + d * dd
        vpx = (f1 * r1y - ux * f2) * inv
        vpy = (-uy * f2 - r1x * f1) * inv
        v[st.point, 0] = vpx
        v[st.point, 1] = vpy
        gdx, gdy = vpx - vl1x, vpy - vl1y
        uddx = a[st.l2, 0] - a[st.l1, 0]
        uddy = a[st.l2, 1] - a[st.l1, 1]
        wx, wy = vpx - vax, vpy - vay
        f1 = (
            (ux * a[st.l1, 1] - uy * a[st.l1, 0])
            - (uddx * gy - uddy * gx)
            - 2.0 * (udx * gdy - udy * gdx)
        )
        f2 = r1x * a[st.a, 0] + r1y * a[st.a, 1] + d * ddd + dd * dd - (wx * wx + wy * wy)
        a[st.point, 0] = (f1 * r1y - ux * f2) * inv
        a[st.point, 1] = (-uy * f2 - r1x * f1) * inv
        return None

    def nudge(self, c: Chunk, st: SliderStep, order: int) -> None:
        round_output(c, st.point, order)

    def transmission(self, st: SliderStep) -> int | None:
        return st.index

    def constants(self, st: SliderStep) -> list[Any]:
        return [compiled_value(st.da), st.sign]

    def emit(self, g: Emitter, st: SliderStep, k: int) -> None:
        p, a, l1, l2 = st.point, st.a, st.l1, st.l2
        atan2 = g.atan2
        d, dd, ddd = g.dist(st.da, "d")
        g.emit(
            f"sign = {g.const()}",
            f"ux = X{l2} - X{l1}", f"uy = Y{l2} - Y{l1}",
            "lu = math.sqrt(ux * ux + uy * uy)",
            "ex = ux / lu", "ey = uy / lu",
            f"gx = X{a} - X{l1}", f"gy = Y{a} - Y{l1}",
            "foot = gx * ex + gy * ey",
            "off = ex * gy - ey * gx",
            "s2 = (d * d - off * off) / (d * d)",
            "if not (s2 >= close_tol):",
            "    if not (s2 >= -close_tol):",
        )  # fmt: skip
        g.flag("True", Code.NO_CLOSURE, k, "        ")
        g.emit(
            "        s2 = nan",
            "    else:",
            "        s2 = max(s2, 0.0)",
            "along = foot + sign * abs(d) * math.sqrt(s2)",
            f"X{p} = X{l1} + along * ex", f"Y{p} = Y{l1} + along * ey",
            f"r1x = X{p} - X{a}", f"r1y = Y{p} - Y{a}",
            "dot = ux * r1x + uy * r1y",
            f"T{st.index} = {atan2}(abs(dot), abs(ux * r1y - uy * r1x))",
            f"S{st.index} = abs(dot) / (lu * abs(d))",
            "det = -dot",
            "if not (abs(det) > singular_tol * lu * abs(d)):",
        )  # fmt: skip
        g.flag("True", Code.SINGULAR, k, "    ")
        g.emit(
            "    det = nan",
            "inv = 1.0 / det",
            f"gx = X{p} - X{l1}", f"gy = Y{p} - Y{l1}",
            f"udx = VX{l2} - VX{l1}", f"udy = VY{l2} - VY{l1}",
            f"f1 = (ux * VY{l1} - uy * VX{l1}) - (udx * gy - udy * gx)",
            f"f2 = r1x * VX{a} + r1y * VY{a}" + (f" + {d} * {dd}" if dd else ""),
            "vpx = (f1 * r1y - ux * f2) * inv", "vpy = (-uy * f2 - r1x * f1) * inv",
            f"VX{p} = vpx", f"VY{p} = vpy",
            f"gdx = vpx - VX{l1}", f"gdy = vpy - VY{l1}",
            f"uddx = AX{l2} - AX{l1}", f"uddy = AY{l2} - AY{l1}",
            f"wx = vpx - VX{a}", f"wy = vpy - VY{a}",
            f"f1 = (ux * AY{l1} - uy * AX{l1}) - (uddx * gy - uddy * gx)"
            " - 2.0 * (udx * gdy - udy * gdx)",
            f"f2 = r1x * AX{a} + r1y * AY{a}"
            + (f" + {d} * {ddd} + {dd} * {dd}" if dd else "") + " - (wx * wx + wy * wy)",
            f"AX{p} = (f1 * r1y - ux * f2) * inv", f"AY{p} = (-uy * f2 - r1x * f1) * inv",
        )  # fmt: skip
        g.finite.append((st.index, k))

    def describe(self, st: SliderStep, names: tuple[str, ...]) -> str:
        return (
            f"slider   {names[st.point]} on line {names[st.l1]}→{names[st.l2]} "
            f"({st.slider!r}) at {describe_dist(st.da)} from {names[st.a]}, "
            f"branch {'+' if st.sign > 0 else '−'}"
        )

    def label(self, st: SliderStep, names: tuple[str, ...], k: int) -> str:
        return f"slider {st.slider!r} ({names[st.point]} on {names[st.l1]}→{names[st.l2]})"

    def folding(self, st: SliderStep) -> list[tuple[int, Any]]:
        return []

    def turn(self, st: SliderStep, place: int, turn: Any) -> SliderStep:
        raise TypeError("a slider's side is not followed through change points")

    def role(self, st: SliderStep) -> Role:
        return Role(places=(st.point,), efforts=dist_inputs(st.da))

    def drawing(self, st: SliderStep) -> tuple[Primitive, ...]:
        return (
            Primitive("slide", (st.l1, st.l2, st.point)),
            Primitive("link", (st.a, st.point), driven=st.da.kind == "input"),
        )
