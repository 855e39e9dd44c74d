r"""The base machine under a front: masses, the ground support and its tipping lines.

The front (an excavator's boom, stick, bucket, links, cylinders) turns with the **upper
structure** about the swing axis; the **undercarriage** stays put. Positions are given in the
front's plane at swing angle 0 (the front along the tracks, over the idler end), in the model's
coordinates: x forward, y up. Seen from above, the **plan** coordinates used for the support
are centred on the swing axis: u forward along the tracks, v to the left; a swing θ > 0 turns
the front from +u towards +v (counter-clockwise seen from above)::

          v (left)
          ^        ┌──────────────────────┐  ← left track, shoe width w
          |        └──────────────────────┘
          |     ─ ─ ─ ─ ─ ─ ─ ○ ─ ─ ─ ─ ─ ─ ─ ─ ─ ─ ─ ─ ─> u (forward)      gauge G between
          |        ┌──────────────────────┐               the track centrelines
          |        └──────────────────────┘  ← right track
                   |<—— track length —————>|  idler and sprocket axes

The machine stands on the **support polygon**: the convex hull of the two tracks' footprints
(track length × shoe width, centred ``gauge/2`` either side), of a lowered blade's edge and of
outrigger pads. Each edge of that polygon is a **tipping line**: the front tipping line of a
crawler is the idler axis (the track footprint's front edge), the side tipping line the outer
edge of a track's shoes, and a lowered blade or outriggers move them outwards. All positions
are SI (m), masses kg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import ModelError


@dataclass(frozen=True, slots=True)
class Mass:
    """A lumped mass of the base machine.

    Attributes
    ----------
    name : str
    mass : float
        kg.
    x, y : float
        Centre of mass in the model's coordinates at swing angle 0 (m): x forward, y up.
    """

    name: str
    mass: float
    x: float
    y: float


@dataclass(frozen=True, slots=True)
class TippingLine:
    """One edge of the support polygon, in plan coordinates centred on the swing axis.

    Attributes
    ----------
    name : str
        ``"front"``, ``"rear"``, ``"left side"``, ``"right side"`` (or between, e.g.
        ``"front-left"``), with ``" (blade)"`` or ``" (outriggers)"`` where those carry it.
    normal : tuple of float
        Outward unit normal (u, v).
    offset : float
        ``normal · p`` of every point p on the line (m): its distance from the swing axis.
    ends : ndarray, shape (2, 2)
        Its end points (u, v) (m).
    """

    name: str
    normal: tuple[float, float]
    offset: float
    ends: F


@dataclass(frozen=True, slots=True)
class BaseMachine:
    """Upper structure, counterweight, undercarriage and ground support.

    Attributes
    ----------
    upper : Mass
        The upper structure without the front and the counterweight (turntable, engine, cab,
        tanks); turns with the front.
    counterweight : Mass
        Turns with the front.
    undercarriage : Mass
        Track frames, tracks, swing bearing's lower race; does not turn.
    track_length : float
        Distance between the idler and sprocket axes (m): the length of track on the ground.
    gauge : float
        Distance between the two tracks' centrelines (m).
    shoe_width : float
        Width of a track shoe (m).
    track_centre : float
        x of the midpoint between the idler and sprocket axes (model coordinates, m).
    blade : tuple of float or None
        A lowered blade's ground edge: (x in model coordinates, width) (m), or None.
    outriggers : tuple of (float, float)
        Outrigger pads (x in model coordinates, lateral v) (m).
    friction : float
        Coefficient of friction between the undercarriage and the ground (slipping limit).
    """

    upper: Mass
    counterweight: Mass
    undercarriage: Mass
    track_length: float
    gauge: float
    shoe_width: float
    track_centre: float
    friction: float
    blade: tuple[float, float] | None = None
    outriggers: tuple[tuple[float, float], ...] = ()

    @property
    def mass(self) -> float:
        """Mass of the base machine without the front (kg)."""
        return self.upper.mass + self.counterweight.mass + self.undercarriage.mass

    def support_polygon(self, swing_axis: float) -> tuple[F, list[str]]:
        """Vertices of the support polygon, counter-clockwise in plan (u, v) about the swing
        axis, and what each vertex belongs to.

        Parameters
        ----------
        swing_axis : float
            Abscissa of the swing axis in the model's frame (m).

        Returns
        -------
        vertices : ndarray, shape (k, 2)
            The polygon's vertices (u, v) (m), counter-clockwise, without collinear points.
        kinds : list of str
            ``"track"``, ``"blade"`` or ``"outriggers"`` for each vertex.
        """
        uc = self.track_centre - swing_axis
        half_l = 0.5 * self.track_length
        outer = 0.5 * (self.gauge + self.shoe_width)
        pts: list[tuple[float, float]] = [
            (uc + su * half_l, sv * outer) for su in (-1.0, 1.0) for sv in (-1.0, 1.0)
        ]
        kinds = ["track"] * 4
        if self.blade is not None:
            bx, width = self.blade
            pts += [(bx - swing_axis, -0.5 * width), (bx - swing_axis, 0.5 * width)]
            kinds += ["blade"] * 2
        for x, v in self.outriggers:
            pts.append((x - swing_axis, v))
            kinds.append("outriggers")
        hull = convex_hull(np.array(pts))
        return np.array([pts[i] for i in hull]), [kinds[i] for i in hull]

    def tipping_lines(self, swing_axis: float) -> tuple[TippingLine, ...]:
        """The support polygon's edges as tipping lines (see `TippingLine`).

        Parameters
        ----------
        swing_axis : float
            Abscissa of the swing axis in the model's frame (m).

        Returns
        -------
        tuple of TippingLine
            One per edge of `support_polygon`, counter-clockwise.
        """
        poly, kinds = self.support_polygon(swing_axis)
        out = []
        k = len(poly)
        for i in range(k):
            a, b = poly[i], poly[(i + 1) % k]
            t = (b - a) / math.hypot(*(b - a))
            n = (float(t[1]), float(-t[0]))  # outward for a counter-clockwise polygon
            carriers = {kinds[i], kinds[(i + 1) % k]} - {"track"}
            name = _direction_name(n) + "".join(f" ({c})" for c in sorted(carriers))
            out.append(TippingLine(name, n, float(n[0] * a[0] + n[1] * a[1]), np.array([a, b])))
        return tuple(out)


def _direction_name(n: tuple[float, float]) -> str:
    """front / rear / left side / right side, or the two between them, for a plan normal."""
    deg = math.degrees(math.atan2(n[1], n[0]))
    names = {0: "front", 90: "left side", 180: "rear", -180: "rear", -90: "right side"}
    for a, name in names.items():
        if abs(deg - a) < 1e-6:
            return name
    fore = "front" if abs(deg) < 90.0 else "rear"
    side = "left" if deg > 0.0 else "right"
    return f"{fore}-{side}"


def convex_hull(points: F) -> list[int]:
    """Indices of the convex hull of plan points (shape (k, 2)), counter-clockwise, without
    collinear points (Andrew's monotone chain)."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))

    def cross(o: int, a: int, b: int) -> float:
        pa, pb, po = points[a], points[b], points[o]
        return float((pa[0] - po[0]) * (pb[1] - po[1]) - (pa[1] - po[1]) * (pb[0] - po[0]))

    def chain(idx: list[int]) -> list[int]:
        out: list[int] = []
        for i in idx:
            while len(out) >= 2 and cross(out[-2], out[-1], i) <= 1e-12:
                out.pop()
            out.append(i)
        return out

    lower, upper = chain(order), chain(order[::-1])
    hull = lower[:-1] + upper[:-1]
    if len(hull) < 3:
        raise ModelError("the ground support has no area (check the tracks, blade and outriggers)")
    return hull
