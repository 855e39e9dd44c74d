"""Two distances: P from A and B on the sketch's side of A→B (RRR dyad; either side may be a
driven length).

::

    (P−A)·(P−A) = d1²                 (P−B)·(P−B) = d2²
    (P−A)·(Ṗ−Ȧ) = d1·ḋ1               (P−B)·(Ṗ−Ḃ) = d2·ḋ2
    (P−A)·(P̈−Ä) = d1·d̈1 + ḋ1² − |Ṗ−Ȧ|²   and the same for B

One 2×2 matrix ``[(P−A)ᵀ; (P−B)ᵀ]`` serves both orders; its determinant cross(P−A, P−B)
vanishes exactly at a dead position, which is reported instead of huge or NaN rates.
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
    at,
    compiled_value,
    describe_dist,
    dist_inputs,
    take_dist,
    vary_dist,
)
from excavkin.step_kinds.state import Chunk, Code, dist, flag, round_output


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


@register
class DyadKind(StepKind[Dyad]):
    """A point held by two distances."""

    name = "dyad"
    record = Dyad
    compiles = True
    iterative = False

    def build(
        self, point: int, a: int, b: int, da: Dist, db: Dist, sign: float, index: int
    ) -> Dyad:
        return Dyad(point, a, b, da, db, sign, index)

    def vary(self, st: Dyad, geo: Geometry, names: tuple[str, ...], model: Model) -> Dyad:
        return dataclasses.replace(
            st, da=vary_dist(st.da, geo, names), db=vary_dist(st.db, geo, names)
        )

    def take(self, st: Dyad, index: Index) -> Dyad:
        if np.ndim(st.sign) or np.ndim(st.da.value) or np.ndim(st.db.value):
            return dataclasses.replace(
                st,
                da=take_dist(st.da, index),
                db=take_dist(st.db, index),
                sign=at(st.sign, index),
            )
        return st

    def solve(
        self, c: Chunk, st: Dyad, k: int, order: int, scale: float, newton: bool = True
    ) -> F | None:
        """Two distances: P from A (d1) and B (d2) on the sketch's side of A→B."""
        x, v, a = c.x, c.v, c.a
        ax, ay, bx, by = x[st.a, 0], x[st.a, 1], x[st.b, 0], x[st.b, 1]
        d1, d1d, d1dd = dist(c, st.da)
        d2, d2d, d2dd = dist(c, st.db)
        ex = bx - ax
        ey = by - ay
        l2 = ex * ex + ey * ey
        kk = (d1 * d1 - d2 * d2 + l2) / (2.0 * l2)
        h2 = d1 * d1 / l2 - kk * kk
        if c.nudge is not None:  # the rounding of the cancelling difference, emulated
            h2 = h2 + c.nudge * (d1 * d1 / l2 + kk * kk)
        # `not >=` also catches NaN: A and B coincide (l2 = 0), so the dyad has no base
        low = ~(h2 >= c.close_tol)
        if low.any():
            # partners that coincide with equal distances leave P anywhere on a circle: that is
            # undetermined, not a failure to close
            size = np.abs(d1) + np.abs(d2)
            loose = ~(l2 > (1e-12 * size) ** 2) & (np.abs(d1 - d2) <= 1e-12 * size)
            flag(c, low & loose, Code.UNDETERMINED, k)
            bad = ~(h2 >= -c.close_tol)
            flag(c, bad, Code.NO_CLOSURE, k)
            h2 = np.where(bad, np.nan, np.maximum(h2, 0.0))
        h = st.sign * np.sqrt(h2)
        px = ax + kk * ex - h * ey
        py = ay + kk * ey + h * ex
        x[st.point, 0] = px
        x[st.point, 1] = py
        r1x, r1y = px - ax, py - ay
        r2x, r2y = px - bx, py - by
        det = r1x * r2y - r1y * r2x
        c.trans[st.index] = np.arctan2(np.abs(det), r1x * r2x + r1y * r2y)
        if not order:
            return None
        sing = ~(np.abs(det) > c.singular_tol * np.abs(d1 * d2))  # NaN counts as singular
        if sing.any():
            flag(c, sing, Code.SINGULAR, k)
            det = np.where(sing, np.nan, det)
        inv = 1.0 / det
        vax, vay, vbx, vby = v[st.a, 0], v[st.a, 1], v[st.b, 0], v[st.b, 1]
        f1 = r1x * vax + r1y * vay + d1 * d1d
        f2 = r2x * vbx + r2y * vby + d2 * d2d
        vpx = (f1 * r2y - f2 * r1y) * inv
        vpy = (r1x * f2 - r2x * f1) * inv
        v[st.point, 0] = vpx
        v[st.point, 1] = vpy
        wx, wy = vpx - vax, vpy - vay
        ux, uy = vpx - vbx, vpy - vby
        f1 = r1x * a[st.a, 0] + r1y * a[st.a, 1] + d1 * d1dd + d1d * d1d - (wx * wx + wy * wy)
        f2 = r2x * a[st.b, 0] + r2y * a[st.b, 1] + d2 * d2dd + d2d * d2d - (ux * ux + uy * uy)
        a[st.point, 0] = (f1 * r2y - f2 * r1y) * inv
        a[st.point, 1] = (r1x * f2 - r2x * f1) * inv
        return None

    def nudge(self, c: Chunk, st: Dyad, order: int) -> None:
        round_output(c, st.point, order)

    def transmission(self, st: Dyad) -> int | None:
        return st.index

    def constants(self, st: Dyad) -> list[Any]:
        return [compiled_value(st.da), compiled_value(st.db), st.sign]

    def emit(self, g: Emitter, st: Dyad, k: int) -> None:
        p, a, b = st.point, st.a, st.b
        atan2 = g.atan2
        d1, d1d, d1dd = g.dist(st.da, "d1")
        d2, d2d, d2dd = g.dist(st.db, "d2")
        g.emit(
            f"sign = {g.const()}",
            f"ex = X{b} - X{a}", f"ey = Y{b} - Y{a}",
            "l2 = ex * ex + ey * ey",
            "kk = (d1 * d1 - d2 * d2 + l2) / (2.0 * l2)",
            "h2 = d1 * d1 / l2 - kk * kk",
            "if not (h2 >= close_tol):",
            "    size = abs(d1) + abs(d2)",
            "    tiny = 1e-12 * size",
        )  # fmt: skip
        g.flag("not (l2 > tiny * tiny) and abs(d1 - d2) <= tiny", Code.UNDETERMINED, k, "    ")
        g.emit("    if not (h2 >= -close_tol):")
        g.flag("True", Code.NO_CLOSURE, k, "        ")
        g.emit(
            "        h2 = nan",
            "    else:",
            "        h2 = max(h2, 0.0)",
            "h = sign * math.sqrt(h2)",
            f"X{p} = X{a} + kk * ex - h * ey", f"Y{p} = Y{a} + kk * ey + h * ex",
            f"r1x = X{p} - X{a}", f"r1y = Y{p} - Y{a}",
            f"r2x = X{p} - X{b}", f"r2y = Y{p} - Y{b}",
            "det = r1x * r2y - r1y * r2x",
            f"T{st.index} = {atan2}(abs(det), r1x * r2x + r1y * r2y)",
            f"S{st.index} = abs(det) / abs(d1 * d2)",
            "if not (abs(det) > singular_tol * abs(d1 * d2)):",
        )  # fmt: skip
        g.flag("True", Code.SINGULAR, k, "    ")
        g.emit(
            "    det = nan",
            "inv = 1.0 / det",
            f"f1 = r1x * VX{a} + r1y * VY{a}" + (f" + {d1} * {d1d}" if d1d else ""),
            f"f2 = r2x * VX{b} + r2y * VY{b}" + (f" + {d2} * {d2d}" if d2d else ""),
            "vpx = (f1 * r2y - f2 * r1y) * inv", "vpy = (r1x * f2 - r2x * f1) * inv",
            f"VX{p} = vpx", f"VY{p} = vpy",
            f"wx = vpx - VX{a}", f"wy = vpy - VY{a}",
            f"ux = vpx - VX{b}", f"uy = vpy - VY{b}",
            f"f1 = r1x * AX{a} + r1y * AY{a}"
            + (f" + {d1} * {d1dd} + {d1d} * {d1d}" if d1d else "") + " - (wx * wx + wy * wy)",
            f"f2 = r2x * AX{b} + r2y * AY{b}"
            + (f" + {d2} * {d2dd} + {d2d} * {d2d}" if d2d else "") + " - (ux * ux + uy * uy)",
            f"AX{p} = (f1 * r2y - f2 * r1y) * inv", f"AY{p} = (r1x * f2 - r2x * f1) * inv",
        )  # fmt: skip
        g.finite.append((st.index, k))

    def describe(self, st: Dyad, names: tuple[str, ...]) -> str:
        return (
            f"dyad     {names[st.point]} from {names[st.a]} ({describe_dist(st.da)}) and "
            f"{names[st.b]} ({describe_dist(st.db)}), branch {'+' if st.sign > 0 else '−'}"
        )

    def label(self, st: Dyad, names: tuple[str, ...], k: int) -> str:
        return f"dyad {names[st.point]} (from {names[st.a]} and {names[st.b]})"

    def folding(self, st: Dyad) -> list[tuple[int, Any]]:
        return [(-1, st)]

    def turn(self, st: Dyad, place: int, turn: Any) -> Dyad:
        return dataclasses.replace(st, sign=st.sign * turn)

    def role(self, st: Dyad) -> Role:
        return Role(places=(st.point,), efforts=dist_inputs(st.da, st.db))

    def drawing(self, st: Dyad) -> tuple[Primitive, ...]:
        return (
            Primitive("link", (st.a, st.point), driven=st.da.kind == "input"),
            Primitive("link", (st.b, st.point), driven=st.db.kind == "input"),
        )
