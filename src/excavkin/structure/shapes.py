"""Rigid-body shapes: each point's coordinates in its body's own frame.

A body's frame has its origin at the body's first point and its x axis towards the second.
Shapes come from the sketch, except where ``[lengths]`` overrides a distance: then the body is
rebuilt by triangulation — the first two points, then every further point from its distances to
those two, on the same side of the base line as in the sketch.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

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


Num = Any  # a float, or an array of one value per design


@dataclass(frozen=True, slots=True)
class LocalFrame:
    """A body's points in its own frame, for one design or an array of designs.

    Attributes
    ----------
    local : dict
        ``{point: (x, y)}``, floats or arrays.
    base : float or array
        Its first two points' distance in the sketch (zero where they coincide).
    triangles : dict
        ``{point: (d0, d1, d01)}`` for every further point placed by its distances to the
        first two, and ``bad`` where they cannot form a triangle.
    """

    local: dict[str, tuple[Num, Num]]
    base: Num
    triangles: dict[str, tuple[Num, Num, Num, Any]]


def local_frame(
    body: Body,
    sketch: Mapping[str, tuple[Num, Num]],
    lengths: Mapping[tuple[str, str], Num],
) -> LocalFrame:
    """The body rebuilt from the sketch and the ``[lengths]`` overrides, by triangulation: the
    first two points, then every further point from its distances to those two, on the same
    side of the base line as in the sketch. Works alike on floats (one design) and on arrays
    (one value per design); which distances are overridden is the same for every design."""

    def given(p: str, q: str) -> Num | None:
        return lengths.get((p, q), lengths.get((q, p)))

    pts = body.points
    p0, p1 = pts[0], pts[1]
    (x0, y0), (x1, y1) = sketch[p0], sketch[p1]
    ux, uy = x1 - x0, y1 - y0
    sketch_len = np.hypot(ux, uy)
    with np.errstate(divide="ignore", invalid="ignore"):
        ex, ey = ux / sketch_len, uy / sketch_len
    base_given = given(p0, p1)
    d01 = sketch_len if base_given is None else base_given
    local: dict[str, tuple[Num, Num]] = {p0: (0.0 * d01, 0.0 * d01), p1: (d01, 0.0 * d01)}
    triangles = {}
    for pi in pts[2:]:
        rx, ry = sketch[pi][0] - x0, sketch[pi][1] - y0
        sx, sy = rx * ex + ry * ey, ex * ry - ey * rx  # sketch coordinates in the body frame
        o0, o1 = given(p0, pi), given(p1, pi)
        if o0 is None and o1 is None and base_given is None:
            local[pi] = (sx, sy)
            continue
        d0 = o0 if o0 is not None else np.hypot(sx, sy)
        d1 = o1 if o1 is not None else np.hypot(sx - sketch_len, sy)
        x = (d0 * d0 - d1 * d1 + d01 * d01) / (2.0 * d01)
        h2 = d0 * d0 - x * x
        bad = h2 < -1e-12 * d0 * d0
        # a point on the base line: h² is then round-off, and its square root would put the
        # point ~1e-8·d off the line; snap it when the distances say collinear to round-off
        h2 = np.where(np.abs(h2) <= 64 * _EPS * d0 * d0, 0.0, h2)
        side = np.where(sy >= 0.0, 1.0, -1.0)
        local[pi] = (x, side * np.sqrt(np.maximum(h2, 0.0)))
        triangles[pi] = (d0, d1, d01, bad)
    return LocalFrame(local, sketch_len, triangles)


def body_shape(
    model: Model, body: Body, pairs: Iterable[tuple[str, str]] | None = None
) -> BodyShape:
    """Build the shape of ``body`` from the sketch and the ``[lengths]`` overrides.

    Parameters
    ----------
    model : Model
    body : Body
        One of the model's bodies.
    pairs : iterable of (str, str), optional
        The ``[lengths]`` keys with both points on ``body``, in the file's order (all of the
        model's are searched when not given; a caller building every body's shape passes them
        so that the work stays linear in the model's size).

    Returns
    -------
    BodyShape
    """
    pts = body.points
    sk = model.points
    src = model.source
    if len(pts) == 1:
        return BodyShape(body.name, {pts[0]: (0.0, 0.0)}, None)
    p0, p1 = pts[0], pts[1]
    frame = local_frame(body, sk, model.lengths)
    if frame.base == 0.0:
        raise ModelError(
            f"its first two points {p0} and {p1} coincide in the sketch",
            table="bodies",
            entry=body.name,
            source=src,
        )
    for pi, (d0, d1, d01, bad) in frame.triangles.items():
        if bad:
            raise AssemblyError(
                f"distances {p0}-{pi} = {d0:.6g} m, {p1}-{pi} = {d1:.6g} m and {p0}-{p1} = "
                f"{d01:.6g} m cannot form a triangle",
                table="bodies",
                entry=body.name,
                source=src,
            )
    defining = {frozenset((p0, p1))} | {frozenset((q, pi)) for pi in pts[2:] for q in (p0, p1)}
    for p, q in model.lengths if pairs is None else pairs:
        if p in pts and q in pts and frozenset((p, q)) not in defining:
            raise ModelError(
                f"{p}-{q} is not one of body {body.name!r}'s defining distances (its first two "
                "points to each other, and each further point to those two); list the points "
                "in another order or give those distances",
                table="lengths",
                entry=f"{p}-{q}",
                source=src,
            )
    local = {n: (float(x), float(y)) for n, (x, y) in frame.local.items()}
    com = None
    if body.center_of_mass is not None:
        com = com_coords(sk[p0], sk[p1], body.center_of_mass)
    return BodyShape(body.name, local, com)


def com_coords(p0: tuple[Num, Num], p1: tuple[Num, Num], com: tuple[Num, Num]) -> tuple[Num, Num]:
    """A centre of mass drawn in the sketch as (s, t) in units of the base vector p0→p1."""
    (x0, y0), (x1, y1) = p0, p1
    ux, uy = x1 - x0, y1 - y0
    cx, cy = com[0] - x0, com[1] - y0
    base2 = ux * ux + uy * uy
    return (cx * ux + cy * uy) / base2, (ux * cy - uy * cx) / base2
