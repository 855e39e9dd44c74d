"""Rigid-body shapes: each point's coordinates in its body's own frame.

A body's frame has its origin at the body's first point and its x axis towards the second.
Shapes come from the sketch, except where ``[lengths]`` overrides a distance: then the body is
rebuilt by triangulation — the first two points, then every further point from its distances to
those two, on the same side of the base line as in the sketch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from excavkin.errors import AssemblyError, ModelError
from excavkin.model.entities import Body, Model

_EPS = 2.220446049250313e-16


@dataclass(frozen=True, slots=True)
class BodyShape:
    """Local coordinates of a body's points.

    Attributes
    ----------
    local : dict
        ``{point: (x, y)}`` in the body frame, metres.
    com : tuple or None
        Centre of mass as (s, t) in units of the base vector p0→p1:
        ``S = p0 + s·(p1 − p0) + t·perp(p1 − p0)``.
    """

    body: str
    local: dict[str, tuple[float, float]]
    com: tuple[float, float] | None

    def distance(self, p: str, q: str) -> float:
        """Distance between two points of the body, m."""
        (x1, y1), (x2, y2) = self.local[p], self.local[q]
        return math.hypot(x2 - x1, y2 - y1)

    def frame_coords(self, p: str, a: str, b: str) -> tuple[float, float]:
        """(s, t) with ``P = A + s·(B − A) + t·perp(B − A)`` for points of this body."""
        ax, ay = self.local[a]
        bx, by = self.local[b]
        px, py = self.local[p]
        wx, wy = bx - ax, by - ay
        rx, ry = px - ax, py - ay
        w2 = wx * wx + wy * wy
        return (rx * wx + ry * wy) / w2, (wx * ry - wy * rx) / w2


def _override(model: Model, p: str, q: str) -> float | None:
    return model.lengths.get((p, q), model.lengths.get((q, p)))


def body_shape(model: Model, body: Body) -> BodyShape:
    """Build the shape of ``body`` from the sketch and the ``[lengths]`` overrides."""
    pts = body.points
    sk = model.points
    src = model.source
    if len(pts) == 1:
        return BodyShape(body.name, {pts[0]: (0.0, 0.0)}, None)
    p0, p1 = pts[0], pts[1]
    (x0, y0), (x1, y1) = sk[p0], sk[p1]
    ux, uy = x1 - x0, y1 - y0
    sketch_len = math.hypot(ux, uy)
    if sketch_len == 0.0:
        raise ModelError(
            f"its first two points {p0} and {p1} coincide in the sketch",
            table="bodies",
            entry=body.name,
            source=src,
        )
    ex, ey = ux / sketch_len, uy / sketch_len
    defining = {frozenset((p0, p1))}
    d01 = _override(model, p0, p1) or sketch_len
    local: dict[str, tuple[float, float]] = {p0: (0.0, 0.0), p1: (d01, 0.0)}
    for pi in pts[2:]:
        defining |= {frozenset((p0, pi)), frozenset((p1, pi))}
        rx, ry = sk[pi][0] - x0, sk[pi][1] - y0
        sx, sy = rx * ex + ry * ey, ex * ry - ey * rx  # sketch coordinates in the body frame
        o0, o1 = _override(model, p0, pi), _override(model, p1, pi)
        if o0 is None and o1 is None and d01 == sketch_len:
            local[pi] = (sx, sy)
            continue
        d0 = o0 if o0 is not None else math.hypot(sx, sy)
        d1 = o1 if o1 is not None else math.hypot(sx - sketch_len, sy)
        x = (d0 * d0 - d1 * d1 + d01 * d01) / (2.0 * d01)
        h2 = d0 * d0 - x * x
        if h2 < -1e-12 * d0 * d0:
            raise AssemblyError(
                f"distances {p0}-{pi} = {d0:.6g} m, {p1}-{pi} = {d1:.6g} m and {p0}-{p1} = "
                f"{d01:.6g} m cannot form a triangle",
                table="bodies",
                entry=body.name,
                source=src,
            )
        side = 1.0 if sy >= 0.0 else -1.0
        # a point on the base line: h² is then round-off, and its square root would put the
        # point ~1e-8·d off the line; snap it when the distances say collinear to round-off
        if abs(h2) <= 64 * _EPS * d0 * d0:
            h2 = 0.0
        local[pi] = (x, side * math.sqrt(max(h2, 0.0)))
    for p, q in model.lengths:
        if p in pts and q in pts and frozenset((p, q)) not in defining:
            raise ModelError(
                f"{p}-{q} is not one of body {body.name!r}'s defining distances (its first two "
                "points to each other, and each further point to those two); list the points "
                "in another order or give those distances",
                table="lengths",
                entry=f"{p}-{q}",
                source=src,
            )
    com = None
    if body.center_of_mass is not None:
        cx, cy = body.center_of_mass[0] - x0, body.center_of_mass[1] - y0
        com = ((cx * ux + cy * uy) / sketch_len**2, (ux * cy - uy * cx) / sketch_len**2)
    return BodyShape(body.name, local, com)
