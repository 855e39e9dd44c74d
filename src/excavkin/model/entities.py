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
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

LinearMode = Literal["driven", "locked", "free"]


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
    """The angle of ``body`` about ``pivot``, measured from the orientation of ``reference``."""

    name: str
    body: str
    pivot: str
    reference: str


@dataclass(frozen=True, slots=True)
class LinearDriver:
    """The distance between two points: a hydraulic cylinder, a rope or a strut.

    Attributes
    ----------
    mode : {"driven", "locked", "free"}
        ``driven``: the length is an input. ``locked``: a rigid link at its sketch length (or its
        ``[lengths]`` entry). ``free``: passive, its length follows the mechanism and is reported.
    """

    name: str
    between: tuple[str, str]
    mode: LinearMode = "driven"


@dataclass(frozen=True, slots=True)
class Slider:
    """``point`` stays on the line through ``along[0]`` and ``along[1]`` (points of one body)."""

    name: str
    point: str
    along: tuple[str, str]


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
    """

    name: str
    points: dict[str, tuple[float, float]]
    bodies: tuple[Body, ...]
    rotary: tuple[RotaryDriver, ...] = ()
    linear: tuple[LinearDriver, ...] = ()
    sliders: tuple[Slider, ...] = ()
    lengths: dict[tuple[str, str], float] = field(default_factory=dict)
    source: str | None = None

    def __hash__(self) -> int:
        return hash((self.name, tuple(self.points), self.bodies, self.rotary, self.linear))

    @property
    def ground(self) -> Body:
        """The fixed body."""
        return next(b for b in self.bodies if b.ground)

    @property
    def inputs(self) -> tuple[str, ...]:
        """Names of the drivers whose values are inputs: rotary ones and driven linear ones."""
        return tuple(d.name for d in self.rotary) + tuple(
            d.name for d in self.linear if d.mode == "driven"
        )

    def body(self, name: str) -> Body:
        """The body called ``name``."""
        for b in self.bodies:
            if b.name == name:
                return b
        raise KeyError(name)
