r"""The base machine under a front: masses, the ground support and its tipping lines.

**One support model for every family.** A machine stands on the ground through two frames
that turn against each other about a vertical **axis** at model abscissa ``x_a``:

* a swing machine (an excavator): the **upper structure** (with the front and the
  counterweight) turns by the swing angle about the swing axis on the **undercarriage**;
* an articulated machine (a wheel loader): the **front frame** (with the front axle and the
  linkage) turns by the articulation angle about the articulation joint on the **rear frame**.

[`Support`][excavkin.machinery.base.Support] holds the masses of either frame (the front's
own masses come from its mechanism at each pose) and its **contact elements**
([`Contact`][excavkin.machinery.base.Contact]): a track, an axle's two tyres, an oscillating
axle's pivot, outrigger pads, a lowered blade, each a set of ground contact points in the frame
it belongs to. The pose (the angle θ between the frames) places them, and the **support
polygon** is the convex hull of every contact point; each of its edges is a **tipping line**.
An oscillating axle touches through its pivot only: the axle swings about it, so the tyres
carry no moment about the machine's long axis.

Positions are given in the front's plane at angle 0 (x forward, y up, in the model's
coordinates). Seen from above, the **plan** coordinates are centred on the axis and fixed to the
frame that does not turn: u forward, v to the left. A point of the turning frame at abscissa x
and lateral offset v lies in plan at R(θ)·(x − x_a, v); a point of the fixed frame at
(x − x_a, v). For a crawler at swing angle 0 (the front over the idler end of the tracks)::

          v (left)
          ^        ┌──────────────────────┐  ← left track, shoe width w
          |        └──────────────────────┘
          |     ─ ─ ─ ─ ─ ─ ─ ○ ─ ─ ─ ─ ─ ─ ─ ─ ─ ─ ─ ─ ─> u (forward)      gauge G between
          |        ┌──────────────────────┐               the track centrelines
          |        └──────────────────────┘  ← right track
                   |<—— track length —————>|  idler and sprocket axes

The front tipping line of a crawler is the idler axis (the track footprint's front edge), the
side tipping line the outer edge of a track's shoes, and a lowered blade or outriggers move them
outwards. Lines are named by their direction in plan (``"front"``, ``"left side"``,
``"front-left (blade)"``) on a swing machine, whose support polygon does not turn, and by the
contact points they join (``"front axle"``, ``"rear axle pivot – front-left tyre"``) on an
articulated one, whose polygon changes shape with the angle.

Each family builds a `Support` from its machine file: the excavator's ``[base]`` table is a
[`BaseMachine`][excavkin.machinery.base.BaseMachine] (crawler tracks, optional blade and
outrigger pads), the loader's ``[chassis]`` its ``Chassis``. Whole-machine equilibrium
([`equilibrium`][excavkin.machinery.equilibrium.equilibrium]) reads only the `Support`. All
positions are SI (m), masses kg.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal, Protocol

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import ModelError

#: contact kinds of the running gear: a swing machine's lines through them carry no suffix
RUNNING_GEAR = frozenset({"track", "tyres", "pivot"})


@dataclass(frozen=True, slots=True)
class Mass:
    """A lumped mass of the base machine.

    Attributes
    ----------
    name : str
    mass : float
        kg.
    x, y : float
        Centre of mass in the model's coordinates at angle 0 (m): x forward, y up.
    """

    name: str
    mass: float
    x: float
    y: float


@dataclass(frozen=True, slots=True)
class TippingLine:
    """One edge of the support polygon, in plan coordinates centred on the axis.

    Attributes
    ----------
    name : str
        On a swing machine ``"front"``, ``"rear"``, ``"left side"``, ``"right side"`` (or
        between, e.g. ``"front-left"``), with ``" (blade)"`` or ``" (outriggers)"`` where those
        carry it; on an articulated machine the contact element both its ends belong to
        (``"front axle"``) or the two contact points it joins (``"A – B"``).
    normal : tuple of float
        Outward unit normal (u, v).
    offset : float
        ``normal · p`` of every point p on the line (m): its distance from the axis.
    ends : ndarray, shape (2, 2)
        Its end points (u, v) (m).
    """

    name: str
    normal: tuple[float, float]
    offset: float
    ends: F


@dataclass(frozen=True, slots=True)
class Contact:
    """One support element: where it touches the ground, in the frame it belongs to.

    Attributes
    ----------
    name : str
        ``"left track"``, ``"front axle"``, ``"rear axle pivot"``, ``"blade"``, …
    kind : str
        ``"track"``, ``"tyres"``, ``"pivot"``, ``"blade"``, ``"outriggers"`` or another
        (``"block"``); tracks, tyres and pivots are the running gear (`RUNNING_GEAR`).
    x : float
        Reference abscissa in the model's plane at angle 0 (m).
    points : tuple of (float, float)
        Its ground contact points: offset along the frame from ``x`` and lateral offset, to the
        left (m).
    labels : tuple of str
        What each point is (``"front-left tyre"``), one per point.
    turns : bool
        It belongs to the frame that turns (an upper structure, a front frame); otherwise to
        the fixed one (an undercarriage, a rear frame).
    """

    name: str
    kind: str
    x: float
    points: tuple[tuple[float, float], ...]
    labels: tuple[str, ...]
    turns: bool = False

    def __post_init__(self) -> None:
        if not self.points or len(self.labels) != len(self.points):
            raise ModelError(f"contact {self.name!r} needs one label for each of its points")


def track(name: str, centre: float, lateral: float, length: float, width: float) -> Contact:
    """A crawler track's footprint: the four corners of its shoes on the ground.

    Parameters
    ----------
    name : str
    centre : float
        Abscissa of the midpoint between its idler and sprocket axes (m).
    lateral : float
        Lateral offset of its centreline, to the left (m).
    length : float
        Idler to sprocket axes (m): the length on the ground.
    width : float
        Shoe width (m).

    Returns
    -------
    Contact
        Kind ``"track"``, on the fixed frame.
    """
    half_l, half_w = 0.5 * length, 0.5 * width
    pts = tuple((su * half_l, lateral + sv * half_w) for su in (-1.0, 1.0) for sv in (-1.0, 1.0))
    return Contact(name, "track", centre, pts, (name,) * 4)


def axle(
    name: str, x: float, tread: float, *, oscillating: bool = False, turns: bool = False
) -> Contact:
    """An axle's support: its two tyres, or the pivot of an oscillating axle.

    Parameters
    ----------
    name : str
        ``"front"`` or ``"rear"``: the contact is ``"NAME axle"`` (or ``"NAME axle pivot"``), its
        tyres ``"NAME-left tyre"`` and ``"NAME-right tyre"``.
    x : float
        Abscissa of the axle (m).
    tread : float
        Tyre centre to tyre centre (m); the tyres touch the ground under their centres.
    oscillating : bool
        The axle swings about a longitudinal pin: one contact point under the pin.
    turns : bool
        It belongs to the turning frame.

    Returns
    -------
    Contact
    """
    if oscillating:
        pivot = f"{name} axle pivot"
        return Contact(pivot, "pivot", x, ((0.0, 0.0),), (pivot,), turns)
    half = 0.5 * tread
    return Contact(
        f"{name} axle",
        "tyres",
        x,
        ((0.0, half), (0.0, -half)),
        (f"{name}-left tyre", f"{name}-right tyre"),
        turns,
    )


def blade(x: float, width: float, *, turns: bool = False) -> Contact:
    """A lowered blade's ground edge.

    Parameters
    ----------
    x : float
        Abscissa of the edge (m).
    width : float
        Its width (m), centred on the machine's long axis.
    turns : bool
        It belongs to the turning frame.

    Returns
    -------
    Contact
        Kind ``"blade"``.
    """
    half = 0.5 * width
    return Contact("blade", "blade", x, ((0.0, -half), (0.0, half)), ("blade",) * 2, turns)


def outriggers(pads: Sequence[tuple[float, float]], *, turns: bool = False) -> Contact:
    """Outrigger pads (or stabilisers).

    Parameters
    ----------
    pads : sequence of (float, float)
        Each pad's abscissa and lateral offset, to the left (m).
    turns : bool
        They belong to the turning frame.

    Returns
    -------
    Contact
        Kind ``"outriggers"``.
    """
    pts = tuple((float(x), float(v)) for x, v in pads)
    return Contact("outriggers", "outriggers", 0.0, pts, ("outriggers",) * len(pts), turns)


@dataclass(frozen=True, slots=True)
class Support:
    """The whole machine on the ground: the masses of its two frames, its contact elements
    and the ground's friction (module docstring).

    Attributes
    ----------
    turning : tuple of Mass
        Masses that turn with the front besides the front's own (an upper structure and its
        counterweight; a front frame).
    fixed : tuple of Mass
        Masses of the frame that does not turn (an undercarriage; a rear frame and its
        counterweight).
    contacts : tuple of Contact
    friction : float or None
        Coefficient of friction between the running gear and the ground (the slipping limit);
        None where the machine file gives none.
    naming : {"direction", "contacts"}
        How tipping lines are named: by their direction in plan (a swing machine) or by the
        contact points they join (an articulated one).
    """

    turning: tuple[Mass, ...]
    fixed: tuple[Mass, ...]
    contacts: tuple[Contact, ...]
    friction: float | None = None
    naming: Literal["direction", "contacts"] = "direction"

    @property
    def mass(self) -> float:
        """Mass of the base machine without the front (kg)."""
        return sum(m.mass for m in self.turning) + sum(m.mass for m in self.fixed)

    def with_contacts(self, extra: Sequence[Contact]) -> Support:
        """The same machine with further contact elements (a block under the bucket).

        Parameters
        ----------
        extra : sequence of Contact

        Returns
        -------
        Support
        """
        return dataclasses.replace(self, contacts=(*self.contacts, *extra))

    def contact_points(self, axis: float, angle: float = 0.0) -> tuple[F, list[tuple[int, int]]]:
        """Every contact point in plan at a pose, and whose it is.

        Parameters
        ----------
        axis : float
            Abscissa of the axis between the frames in the model's plane (m).
        angle : float
            The turning frame's angle (rad; > 0 counter-clockwise seen from above).

        Returns
        -------
        points : ndarray, shape (k, 2)
            (u, v) (m), element by element in the order of `contacts`.
        owners : list of (int, int)
            Each point's element and its index there.
        """
        c, s = math.cos(angle), math.sin(angle)
        pts: list[tuple[float, float]] = []
        owners: list[tuple[int, int]] = []
        for e, ct in enumerate(self.contacts):
            u0 = ct.x - axis
            for i, (du, v) in enumerate(ct.points):
                u = u0 + du
                pts.append((c * u - s * v, s * u + c * v) if ct.turns else (u, v))
                owners.append((e, i))
        return np.array(pts, dtype=np.float64), owners

    def support_polygon(self, axis: float, angle: float = 0.0) -> tuple[F, list[str]]:
        """Vertices of the support polygon, counter-clockwise in plan, and the kind of the
        contact each belongs to.

        Parameters
        ----------
        axis : float
            Abscissa of the axis between the frames in the model's plane (m).
        angle : float
            The turning frame's angle (rad).

        Returns
        -------
        vertices : ndarray, shape (k, 2)
            The polygon's vertices (u, v) (m), counter-clockwise, without collinear points.
        kinds : list of str
            The `Contact.kind` of each vertex.
        """
        pts, owners = self.contact_points(axis, angle)
        hull = convex_hull(pts)
        return pts[hull], [self.contacts[owners[i][0]].kind for i in hull]

    def tipping_lines(self, axis: float, angle: float = 0.0) -> tuple[TippingLine, ...]:
        """The support polygon's edges as tipping lines (see `TippingLine`).

        Parameters
        ----------
        axis : float
            Abscissa of the axis between the frames in the model's plane (m).
        angle : float
            The turning frame's angle (rad).

        Returns
        -------
        tuple of TippingLine
            One per edge of `support_polygon`, counter-clockwise.
        """
        pts, owners = self.contact_points(axis, angle)
        hull = convex_hull(pts)
        out = []
        for i, j in zip(hull, hull[1:] + hull[:1], strict=True):
            a, b = pts[i], pts[j]
            t = (b - a) / math.hypot(*(b - a))
            n = (float(t[1]), float(-t[0]))  # outward for a counter-clockwise polygon
            out.append(
                TippingLine(
                    self._line_name(n, owners[i], owners[j]),
                    n,
                    float(n[0] * a[0] + n[1] * a[1]),
                    np.array([a, b]),
                )
            )
        return tuple(out)

    def _line_name(self, n: tuple[float, float], a: tuple[int, int], b: tuple[int, int]) -> str:
        ca, cb = self.contacts[a[0]], self.contacts[b[0]]
        if self.naming == "direction":
            carriers = {ca.kind, cb.kind} - RUNNING_GEAR
            return _direction_name(n) + "".join(f" ({c})" for c in sorted(carriers))
        if a[0] == b[0]:
            return ca.name
        return f"{ca.labels[a[1]]} – {cb.labels[b[1]]}"


class Base(Protocol):
    """What a family's machine stands on: anything that builds a `Support`."""

    @property
    def support(self) -> Support:
        """The common support model."""
        ...


@dataclass(frozen=True, slots=True)
class BaseMachine:
    """A swing machine's base: upper structure, counterweight, undercarriage on tracks (a
    crawler) or axles (a wheeled machine) and ground support (the excavator machine file's
    ``[base]`` table).

    Attributes
    ----------
    upper : Mass
        The upper structure without the front and the counterweight (turntable, engine, cab,
        tanks); turns with the front.
    counterweight : Mass
        Turns with the front.
    undercarriage : Mass
        Track frames and tracks (or axles and tyres), swing bearing's lower race; does not
        turn.
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
    axles : tuple of Contact
        A wheeled undercarriage's axles (`axle` contacts of the undercarriage: two tyres, or
        the pivot of an oscillating axle) instead of tracks; where given, ``track_length``,
        ``gauge`` and ``shoe_width`` are 0 and no track stands on the ground.
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
    axles: tuple[Contact, ...] = ()

    @property
    def mass(self) -> float:
        """Mass of the base machine without the front (kg)."""
        return self.upper.mass + self.counterweight.mass + self.undercarriage.mass

    @property
    def support(self) -> Support:
        """The common support model: the upper structure and the counterweight turn, the
        undercarriage stands on two tracks (or its axles), a lowered blade and outrigger pads
        (all on the undercarriage)."""
        half_g = 0.5 * self.gauge
        contacts = list(self.axles) or [
            track("right track", self.track_centre, -half_g, self.track_length, self.shoe_width),
            track("left track", self.track_centre, half_g, self.track_length, self.shoe_width),
        ]
        if self.blade is not None:
            contacts.append(blade(*self.blade))
        if self.outriggers:
            contacts.append(outriggers(self.outriggers))
        return Support(
            (self.upper, self.counterweight),
            (self.undercarriage,),
            tuple(contacts),
            self.friction,
            "direction",
        )

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
        return self.support.support_polygon(swing_axis)

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
        return self.support.tipping_lines(swing_axis)


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
    """Indices of the convex hull of plan points, counter-clockwise, without collinear points
    (Andrew's monotone chain).

    Parameters
    ----------
    points : ndarray, shape (k, 2)

    Returns
    -------
    list of int
        Counter-clockwise from the point of least (u, v).

    Raises
    ------
    ModelError
        Where the points span no area.
    """
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
        raise ModelError(
            "the ground support has no area (check the tracks or axles, blade and outriggers)"
        )
    return hull
