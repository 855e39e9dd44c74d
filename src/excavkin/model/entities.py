"""Frozen records that describe a planar mechanism, in SI units.

Conventions (drawn in ``docs/conventions.md``)::

        y
        ^        B (second point)
        |       /
        |      /  body orientation = angle of A->B, CCW from +x
        |     /
        |    A (first point)
        +----------------> x

* A point shared by two or more bodies is a revolute joint.
* A body's orientation is the direction from its first listed point to its second; the ground's
  is global +x.
* A rotary driver's value is the angle, CCW, from the reference body's orientation to the
  vector pivot -> first point of the driven body that is not the pivot.
* A linear driver's value is the distance between its two points (a hydraulic cylinder or a
  rope); ``mode`` says whether it is an input (``driven``), a rigid strut at its sketch length
  (``locked``) or passive, its length following the mechanism (``free``).
* A slider keeps a point on the line through two points of another body.
* A rope ([`Rope`][excavkin.model.entities.Rope]) reeved ``parts`` times between two blocks
  is also a linear element of the model, of the rope's name, between its blocks: it pulls
  them together with ``parts`` times its tension and never pushes. A winch rope's input is its
  motor's angle (a positive angle pays rope out); a locked rope keeps its length.
* Loads ([`PointForce`][excavkin.model.entities.PointForce],
[`Torque`][excavkin.model.entities.Torque], [`Gravity`][excavkin.model.entities.Gravity]) act on
bodies; a force acts at
  one of the body's points, in global axes. Gravity acts at each body's centre of mass, along
  ``direction`` (default −y), with ``g`` = 9.80665 m/s² unless given.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal, TypeAlias

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from excavkin.kinematics.result import KinematicResult

LinearMode = Literal["driven", "locked", "free"]
RopeMode = Literal["winch", "locked"]
Wrap = Literal["ccw", "cw"]

#: A load's value: a constant, an array with one row per sample, or a function of the
#: kinematic result returning either (see [`PointForce`][excavkin.model.entities.PointForce] and
#: [`Torque`][excavkin.model.entities.Torque]).
LoadValue: TypeAlias = "ArrayLike | Callable[[KinematicResult], ArrayLike]"

#: Standard gravity, m/s².
STANDARD_GRAVITY = 9.80665


@dataclass(frozen=True, slots=True)
class Body:
    """A rigid set of points.

    Attributes
    ----------
    name : str
    points : tuple of str
        At least two; the first two set the body's orientation.
    ground : bool
        The fixed frame. Exactly one body is ground.
    mass : float or None
        kg.
    inertia : float or None
        Moment of inertia about the centre of mass, kg·m².
    center_of_mass : tuple of float or None
        In sketch coordinates, m.
    """

    name: str
    points: tuple[str, ...]
    ground: bool = False
    mass: float | None = None
    inertia: float | None = None
    center_of_mass: tuple[float, float] | None = None


@dataclass(frozen=True, slots=True)
class RotaryDriver:
    """The angle of ``body`` about ``pivot``, measured from the orientation of ``reference``.

    Attributes
    ----------
    name : str
        The input's name.
    body : str
        The driven body.
    pivot : str
        A point of ``body``, the centre of the rotation.
    reference : str
        The body the angle is measured from (the ground: an absolute angle). The angle (rad,
        counter-clockwise) runs from its orientation to the vector pivot → the first point of
        ``body`` that is not the pivot.
    """

    name: str
    body: str
    pivot: str
    reference: str


@dataclass(frozen=True, slots=True)
class LinearDriver:
    """The distance between two points: a hydraulic cylinder, a rope or a strut.

    Attributes
    ----------
    name : str
        The element's name (the input's, when driven).
    between : (str, str)
        Its two end points; its value is their distance (m), its force > 0 pushes them
        apart.
    mode : {"driven", "locked", "free"}
        ``driven``: the length is an input. ``locked``: a rigid link at its sketch length (or its
        ``[lengths]`` entry). ``free``: passive, its length follows the mechanism and is reported.
    stroke : (float, float) or None
        The shortest and longest pin-to-pin length the element can take (a cylinder's
        retracted length and that plus its stroke), m; default sweeps stay within it.
    """

    name: str
    between: tuple[str, str]
    mode: LinearMode = "driven"
    stroke: tuple[float, float] | None = None


@dataclass(frozen=True, slots=True)
class Rope:
    """A rope reeved ``parts`` times between two blocks, or run over sheaves; wound on a winch
    or locked.

    The rope runs ``parts`` times between the blocks at ``path[0]`` and ``path[1]``, so its
    length is ``L = parts·d + L0`` with ``d`` the blocks' distance and ``L0`` what lies off
    the blocks (constant). It pulls the blocks together with ``parts·T`` (T ≥ 0 its tension)
    and never pushes: a sample where it would have to is slack, not ok.

    ``winch``: the rope comes off a drum of radius ``drum_radius`` driven by a motor through
    ``gear_ratio`` (motor turns per drum turn). The motor's angle θ is the input, counted from
    the blocks together; a positive rate pays rope out: ``d = θ·R/(i·parts)``, so the blocks
    part at ``ω·R/(i·parts)`` (the sketch's θ is ``d_sketch·i·parts/R``).

    ``locked``: a pendant or suspension rope of fixed length (its sketch length, or its
    ``[lengths]`` entry).

    The model lists it also as a linear element of its name between its blocks (driven for
    a winch, locked otherwise): a [`Model`][excavkin.model.entities.Model] adds that element.

    Over sheaves (a ``path`` of more than two points, one part): the rope runs from
    ``path[0]`` over a sheave of radius ``radii[k]`` centred at each inner point, turning
    counter-clockwise (``"ccw"``: the sheave on the rope's left as it runs from the first point
    to the last) or clockwise around it, to ``path[-1]``. Its length is the sum of its free
    tangent segments and its arcs on the sheaves; a winch's length is ``θ·R/i``. A block of
    several parts is reeved over sheaves by a path that visits its two blocks in turn (each
    visit one of the block's sheaves, all of one radius).

    Attributes
    ----------
    name : str
        The rope's name (the winch motor's input, for a winch).
    path : tuple of str
        The two blocks (points) the rope runs between, or its two ends with the centres of
        the sheaves it runs over between them, in order.
    parts : int
        Parts of the rope between the blocks (the block's multiplicity), ≥ 1.
    mode : {"winch", "locked"}
    drum_radius : float or None
        m; a winch's drum radius (to the rope's centre line).
    gear_ratio : float
        Motor turns per drum turn (> 0), for a winch.
    radii : tuple of float
        m; each sheave's radius (to the rope's centre line), one per inner point of ``path``.
    wraps : tuple of {"ccw", "cw"}
        The way the rope turns around each sheave, one per inner point of ``path``.
    """

    name: str
    path: tuple[str, ...]
    parts: int = 1
    mode: RopeMode = "locked"
    drum_radius: float | None = None
    gear_ratio: float = 1.0
    radii: tuple[float, ...] = ()
    wraps: tuple[Wrap, ...] = ()

    @property
    def over_sheaves(self) -> bool:
        """Whether the rope runs over sheaves (a path of more than two points)."""
        return len(self.path) > 2

    @property
    def ratio(self) -> float:
        """The blocks' distance (over sheaves: the rope's length) per motor angle,
        ``R/(i·parts)`` (m/rad); 0 for a locked rope."""
        if self.mode != "winch" or self.drum_radius is None:
            return 0.0
        return self.drum_radius / (self.gear_ratio * self.parts)

    def element(self) -> LinearDriver:
        """The linear element the rope is between its blocks.

        Returns
        -------
        LinearDriver
            Of the rope's name, between its blocks: driven for a winch, locked otherwise.
        """
        ends = (self.path[0], self.path[-1])
        return LinearDriver(self.name, ends, "driven" if self.mode == "winch" else "locked")


@dataclass(frozen=True, slots=True)
class Slider:
    """``point`` stays on the line through ``along[0]`` and ``along[1]`` (points of one body).

    Attributes
    ----------
    name : str
        The slider's name.
    point : str
        The sliding point, of another body than the line's.
    along : (str, str)
        Two points of one body that set the line.
    """

    name: str
    point: str
    along: tuple[str, str]


@dataclass(frozen=True, slots=True, eq=False)
class PointForce:
    """A force on ``body`` applied at its point ``point``, in global axes, N.

    Attributes
    ----------
    name : str
    body : str
    point : str
        One of the body's points (its velocity is the body's velocity there).
    value : array_like or callable
        ``(Fx, Fy)`` shape (2,), constant; shape (n, 2), one row per sample; or a function
        ``f(result: KinematicResult)`` returning either — e.g. a digging resistance opposing the
        tip's velocity.
    """

    name: str
    body: str
    point: str
    value: LoadValue


@dataclass(frozen=True, slots=True, eq=False)
class Torque:
    """A couple on ``body`` (counter-clockwise positive), N·m, and its reaction on ``reaction``.

    Attributes
    ----------
    name : str
    body : str
    value : float, array_like or callable
        A scalar; shape (n,), one value per sample; or ``f(result: KinematicResult)`` returning
        either.
    reaction : str or None
        A body that receives the opposite couple (a motor between two bodies); ``None`` for an
        external couple.
    """

    name: str
    body: str
    value: LoadValue
    reaction: str | None = None


@dataclass(frozen=True, slots=True)
class Gravity:
    """Weight ``m·g·direction`` of every body with a mass, at its centre of mass.

    Attributes
    ----------
    g : float
        m/s²; default standard gravity 9.80665.
    direction : tuple of float
        Unit vector, default ``(0, −1)``; normalised if not unit.
    """

    g: float = STANDARD_GRAVITY
    direction: tuple[float, float] = (0.0, -1.0)


Load: TypeAlias = PointForce | Torque | Gravity


@dataclass(frozen=True, slots=True)
class GearPair:
    """Two bodies whose rotations are coupled by meshing gears, about pivots on a carrier.

    With each body's angle measured from the carrier's orientation, their changes from the
    sketch keep ``Δ(θ2 − θc) = e·Δ(θ1 − θc)``: the train value ``e = −1/ratio`` for an external
    pair (they turn opposite ways), ``+1/ratio`` for an internal one (a pinion in a ring gear).
    A rack is not a gear pair (see the docs).

    Attributes
    ----------
    name : str
        The mesh's name.
    gears : (str, str)
        The two gear bodies; each shares exactly one point with ``carrier``, its pivot (the
        pitch circle's centre).
    carrier : str
        The body that carries both pivots: the ground, or a moving arm (a planet carrier).
    ratio : float
        ``r2 / r1`` (= z2 / z1), the speed ratio ``|ω1 − ωc| / |ω2 − ωc|``, > 0.
    internal : bool
        ``True``: one gear is a ring with internal teeth (the larger radius) and the other runs
        inside it.
    pressure_angle : float
        rad, in [0, π/2): the line of action's angle to the common tangent of the pitch
        circles (default 20°).
    radii : (float, float) or None
        The pitch radii r1, r2 (m), when given: the sketch's distance of the pivots must be
        ``r1 + r2`` (external) or ``|r1 − r2|`` (internal).
    """

    name: str
    gears: tuple[str, str]
    carrier: str
    ratio: float
    internal: bool = False
    pressure_angle: float = 0.3490658503988659
    radii: tuple[float, float] | None = None

    @property
    def train_value(self) -> float:
        """``e``: the change of gear 2's angle per change of gear 1's, relative to the
        carrier (−1/ratio external, +1/ratio internal)."""
        return (1.0 if self.internal else -1.0) / self.ratio

    @property
    def pitch_fraction(self) -> float:
        """``λ``: the pitch point is ``O1 + λ·(O2 − O1)`` (1/(1 + ratio) external,
        1/(1 − ratio) internal)."""
        return 1.0 / (1.0 - self.ratio if self.internal else 1.0 + self.ratio)


@dataclass(frozen=True, slots=True)
class RackPinion:
    """A rack that translates along a guide on ``carrier``, driven by a pinion pivoted on it.

    The rack is a prismatic pair with the carrier (its guide runs along ``along``) and meshes
    with the pinion: its travel along the guide is ``Δs = −σ·r·Δ(θp − θc)``, σ = +1 when the
    rack lies to the left of the guide's direction from the pinion's pivot, −1 to the right
    (the pinion turning counter-clockwise moves a rack below it forwards).

    Attributes
    ----------
    name : str
        The mesh's name.
    rack : str
        The rack body (it shares no point with the carrier).
    pinion : str
        The pinion body; it shares exactly one point with the carrier, its pivot.
    carrier : str
        The body that carries the pinion's pivot and the rack's guide (the ground, or a
        moving body).
    along : (str, str)
        Two points of the carrier: the guide's direction.
    radius : float
        The pinion's pitch radius, m (> 0).
    pressure_angle : float
        rad, in [0, π/2) (default 20°).
    """

    name: str
    rack: str
    pinion: str
    carrier: str
    along: tuple[str, str]
    radius: float
    pressure_angle: float = 0.3490658503988659


@dataclass(frozen=True, slots=True)
class CamFollower:
    """A disc cam turning on ``carrier`` and a follower translating in a guide on it, or
    oscillating about a pivot on it.

    The follower's travel along its guide (its angle about its pivot, counter-clockwise, for an
    oscillating one) is the lift law ``s(θ)`` of the cam's turn θ from its sketch, relative to
    the carrier and counter-clockwise (a table over one turn, interpolated by a periodic cubic
    spline; see `excavkin.model.cams`). At the sketch the follower is where it is drawn, at
    the lift ``s(0)``.

    Attributes
    ----------
    name : str
        The pair's name.
    cam : str
        The cam body; it shares exactly one point with the carrier, its pivot.
    follower : str
        The translating body (it shares no point with the carrier), or the oscillating one (it
        shares one, its pivot). With ``face = "roller"`` its first point other than a pivot is
        the roller's centre (a knife edge: a roller of radius 0), whose motion the law gives.
    carrier : str
        The body that carries the cam's pivot and the follower's guide.
    along : (str, str) or None
        Two points of the carrier: the guide's direction; None for an oscillating follower.
    lift : tuple of (float, float), or callable
        (turn in rad, lift in m, or in rad for an oscillating follower) from 0 to 2π, strictly
        increasing, the last lift equal to the first; or (in Python) a function of the turn
        (rad, any number of turns) returning ``(s, ds/dθ, d²s/dθ²)``, written in NumPy
        operations.
    face : {"roller", "flat"}
        A roller (or knife-edge) follower, or a flat face square to the guide (translating
        followers only).
    """

    name: str
    cam: str
    follower: str
    carrier: str
    along: tuple[str, str] | None
    lift: tuple[tuple[float, float], ...] | Callable[[Any], tuple[Any, Any, Any]]
    face: Literal["roller", "flat"] = "roller"


@dataclass(frozen=True, slots=True)
class DesignVariable:
    """A named design variable of a model file: one value that several entries refer to.

    Attributes
    ----------
    name : str
    value : float
        Nominal value, SI.
    kind : {"length", "mass", "inertia"}
    bounds : (float, float) or None
        Lower and upper bound, SI (for design studies).
    targets : tuple of str
        The parameters that refer to it (``"A-B"``, ``"O4.x"``, ``"rocker.mass"``).
    """

    name: str
    value: float
    kind: str
    bounds: tuple[float, float] | None
    targets: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Model:
    """A planar mechanism as described by its user, in SI units.

    Attributes
    ----------
    name : str
    points : dict
        Sketch coordinates ``{name: (x, y)}`` in m: an assembled configuration that also fixes
        each dyad's assembly branch.
    bodies : tuple of Body
    rotary : tuple of RotaryDriver
    linear : tuple of LinearDriver
    sliders : tuple of Slider
    lengths : dict
        Exact distances ``{(p, q): metres}`` that override the sketch.
    source : str or None
        The file it was read from, for messages.
    loads : tuple of PointForce or Torque
        External loads that `forces` applies by default.
    gravity : Gravity or None
        Gravity, when the model enables it (``None``: off).
    design : tuple of DesignVariable
        The file's named design variables and the entries that refer to them.
    gears : tuple of GearPair
        Meshing gear pairs: higher pairs, one freedom each.
    racks : tuple of RackPinion
        Racks and pinions: a prismatic pair and a mesh each.
    cams : tuple of CamFollower
        Disc cams and translating followers: a prismatic pair and a contact each.
    ropes : tuple of Rope
        Ropes between blocks; each is also in ``linear`` (added when absent), as the element
        of its name between its blocks.
    """

    name: str
    points: dict[str, tuple[float, float]]
    bodies: tuple[Body, ...]
    rotary: tuple[RotaryDriver, ...] = ()
    linear: tuple[LinearDriver, ...] = ()
    sliders: tuple[Slider, ...] = ()
    lengths: dict[tuple[str, str], float] = field(default_factory=dict)
    source: str | None = None
    loads: tuple[PointForce | Torque, ...] = ()
    gravity: Gravity | None = None
    design: tuple[DesignVariable, ...] = ()
    gears: tuple[GearPair, ...] = ()
    racks: tuple[RackPinion, ...] = ()
    cams: tuple[CamFollower, ...] = ()
    ropes: tuple[Rope, ...] = ()

    def __post_init__(self) -> None:
        if self.ropes:
            object.__setattr__(self, "linear", with_rope_elements(self.linear, self.ropes))

    def __hash__(self) -> int:
        return hash(
            (self.name, tuple(self.points), self.bodies, self.rotary, self.linear, self.ropes)
        )

    @property
    def ground(self) -> Body:
        """The fixed body."""
        return next(b for b in self.bodies if b.ground)

    @property
    def inputs(self) -> tuple[str, ...]:
        """Names of the drivers whose values are inputs: rotary ones, driven linear ones (a
        winch rope between two blocks among them), then winch ropes over sheaves."""
        return (
            tuple(d.name for d in self.rotary)
            + tuple(d.name for d in self.linear if d.mode == "driven")
            + tuple(r.name for r in self.ropes if r.mode == "winch" and r.over_sheaves)
        )

    def body(self, name: str) -> Body:
        """The body called ``name``.

        Parameters
        ----------
        name : str
            One of the bodies' names.

        Returns
        -------
        Body

        Raises
        ------
        KeyError
            No body of that name.
        """
        for b in self.bodies:
            if b.name == name:
                return b
        raise KeyError(name)

    def bodies_at(self) -> dict[str, list[Body]]:
        """Each point's bodies, in the model's order (a point of no body is absent).

        Returns
        -------
        dict
            ``{point: [Body, ...]}``, built anew on each call in one pass over the bodies.
        """
        out: dict[str, list[Body]] = {}
        for b in self.bodies:
            for n in dict.fromkeys(b.points):
                out.setdefault(n, []).append(b)
        return out


def rope_line(rope: Rope) -> str:
    """A rope in one line, as ``excavkin check`` lists it.

    Parameters
    ----------
    rope : Rope

    Returns
    -------
    str
        ``"hoist winch, 2 parts A–B, drum R 0.25 m, i = 20"`` and the like.
    """
    if rope.over_sheaves:
        sheaves = ", ".join(
            f"{p} (r {r:g} m, {w})"
            for p, r, w in zip(rope.path[1:-1], rope.radii, rope.wraps, strict=False)
        )
        where = f"{rope.path[0]} over {sheaves} to {rope.path[-1]}"
    else:
        where = f"{rope.parts} part{'s' if rope.parts != 1 else ''} {'–'.join(rope.path)}"
    drum = (
        f", drum R {rope.drum_radius:g} m, i = {rope.gear_ratio:g}" if rope.mode == "winch" else ""
    )
    return f"{rope.name} {rope.mode}, {where}{drum}"


def with_rope_elements(
    linear: tuple[LinearDriver, ...], ropes: tuple[Rope, ...]
) -> tuple[LinearDriver, ...]:
    """The linear elements with each rope's own added, where none of its name is there.

    Parameters
    ----------
    linear : tuple of LinearDriver
        The model's linear elements.
    ropes : tuple of Rope
        Its ropes.

    Returns
    -------
    tuple of LinearDriver
        ``linear``, then the element (`Rope.element`) of each rope not in it, in order.
    """
    names = {d.name for d in linear}
    return linear + tuple(
        r.element() for r in ropes if r.name not in names and r.path and not r.over_sheaves
    )
