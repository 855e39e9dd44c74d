"""The ground's points at their coordinates: constant, at rest."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.model.entities import Model
from excavkin.step_kinds.base import Emitter, Geometry, Primitive, Role, StepKind, register
from excavkin.step_kinds.dist import Index, Num, at, varies
from excavkin.step_kinds.state import Chunk


@dataclass(frozen=True, slots=True)
class Fixed:
    """Ground points at their coordinates."""

    points: tuple[int, ...]
    coords: tuple[tuple[float, float], ...]


def ground_coords(geo: Geometry, model: Model) -> tuple[tuple[Num, Num], ...]:
    """The ground's points as the plan builder places them: its sketch, or its shape where
    reshaped (a ``[lengths]`` entry between two of its points).

    Parameters
    ----------
    geo : Geometry
        The designs' geometry.
    model : Model
        The model.

    Returns
    -------
    tuple of (x, y)
        Each ground point's coordinates (floats, or arrays of one value per design).
    """
    ground = model.ground
    members = set(ground.points)
    reshaped = any(p in members and q in members for p, q in model.lengths)
    if not reshaped:
        return tuple(geo.sketch[n] for n in ground.points)
    g0 = ground.points[0]
    gex, gey = geo.unit(ground.points[1], g0)
    local = geo.frames[ground.name].local
    x0, y0 = geo.sketch[g0]
    return tuple(
        (x0 + local[n][0] * gex - local[n][1] * gey, y0 + local[n][0] * gey + local[n][1] * gex)
        for n in ground.points
    )


@register
class FixedKind(StepKind[Fixed]):
    """The ground."""

    name = "fixed"
    record = Fixed
    compiles = True
    iterative = False

    def build(self, points: tuple[int, ...], coords: tuple[tuple[float, float], ...]) -> Fixed:
        return Fixed(points, coords)

    def vary(self, st: Fixed, geo: Geometry, names: tuple[str, ...], model: Model) -> Fixed:
        coords = ground_coords(geo, model)
        if any(varies(c) for xy in coords for c in xy):
            return dataclasses.replace(st, coords=coords)
        return st

    def take(self, st: Fixed, index: Index) -> Fixed:
        if any(np.ndim(c) for xy in st.coords for c in xy):
            coords = tuple((at(x, index), at(y, index)) for x, y in st.coords)
            return dataclasses.replace(st, coords=coords)
        return st

    def solve(
        self, c: Chunk, st: Fixed, k: int, order: int, scale: float, newton: bool = True
    ) -> F | None:
        """Ground points: constant, at rest."""
        for i, (px, py) in zip(st.points, st.coords, strict=True):
            c.x[i, 0] = px
            c.x[i, 1] = py
            if order:
                c.v[i] = 0.0
                c.a[i] = 0.0
        return None

    def nudge(self, c: Chunk, st: Fixed, order: int) -> None:
        return None  # given, not computed: nothing rounded

    def transmission(self, st: Fixed) -> int | None:
        return None

    def constants(self, st: Fixed) -> list[Any]:
        out: list[Any] = []
        for cx, cy in st.coords:
            out += [cx, cy]
        return out

    def emit(self, g: Emitter, st: Fixed, k: int) -> None:
        for p in st.points:
            g.at_rest.add(p)
            g.emit(
                f"X{p} = {g.const()}", f"Y{p} = {g.const()}",
                f"VX{p} = 0.0", f"VY{p} = 0.0", f"AX{p} = 0.0", f"AY{p} = 0.0",
            )  # fmt: skip

    def describe(self, st: Fixed, names: tuple[str, ...]) -> str:
        return f"fixed    {', '.join(names[i] for i in st.points)} (ground)"

    def label(self, st: Fixed, names: tuple[str, ...], k: int) -> str:
        return f"step {k + 1}"

    def folding(self, st: Fixed) -> list[tuple[int, Any]]:
        return []

    def turn(self, st: Fixed, place: int, turn: Any) -> Fixed:
        raise TypeError("the ground has no dyad to turn")

    def role(self, st: Fixed) -> Role:
        return Role(places=st.points, efforts=())

    def drawing(self, st: Fixed) -> tuple[Primitive, ...]:
        return tuple(Primitive("ground", (p,)) for p in st.points)
