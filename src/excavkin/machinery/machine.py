"""What the machinery layer asks of a family's machine: protocols (a family's machine derives
from [`CylinderMachine`][excavkin.machinery.cylinder_machine.CylinderMachine], which provides
most of them).

A family's machine (the excavator's [`Machine`][excavkin.excavator.machine.Machine], a wheel
loader's, a crane's) is a general [`Mechanism`][excavkin.mechanism.Mechanism] plus its
cylinders in the order of the roles the family declares, their circuits and pumps and, for the
whole-machine answers, its base. The shared analyses (stroke times, buckling, tipping and
slipping, the stroke search) read a machine only through these attributes, so a family needs
no more than to provide them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Protocol

from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray as F
from excavkin.machinery.cylinders import Circuit, Cylinder

if TYPE_CHECKING:
    from excavkin.kinematics import KinematicResult
    from excavkin.machinery.base import Base
    from excavkin.machinery.masses import MassPoints
    from excavkin.machinery.pumps import Hydraulics
    from excavkin.mechanism import Mechanism
    from excavkin.model.entities import Load


class Strokes(Protocol):
    """A machine's stroke limits, one entry per cylinder role."""

    @property
    def lengths_min(self) -> F:
        """Fully retracted pin-to-pin lengths, shape (k,) (m)."""
        ...

    @property
    def lengths_max(self) -> F:
        """Fully extended pin-to-pin lengths, shape (k,) (m)."""
        ...


class HydraulicMachine(Strokes, Protocol):
    """A machine with hydraulic cylinders: its roles, cylinders, circuits and pumps."""

    @property
    def name(self) -> str:
        """For messages."""
        ...

    @property
    def roles(self) -> tuple[str, ...]:
        """The roles its family declares, in the order of every ``(n, k)`` array."""
        ...

    @property
    def cylinders(self) -> Sequence[Cylinder]:
        """One per role, in the order of ``roles``."""
        ...

    @property
    def circuits(self) -> Mapping[str, Circuit]:
        """The circuits by name (each cylinder names its own)."""
        ...

    @property
    def hydraulics(self) -> Hydraulics | None:
        """Pumps, swing and rod material; None where the machine file has none."""
        ...


class MovingMachine(HydraulicMachine, Protocol):
    """A machine whose motion the engine solves: what hydraulic power along a motion reads."""

    @property
    def mechanism(self) -> Mechanism:
        """The general mechanism its cylinders drive."""
        ...

    def solve(self, lengths: ArrayLike, rates: ArrayLike | None = None) -> KinematicResult:
        """The engine's kinematics at cylinder lengths and their rates.

        Parameters
        ----------
        lengths : array_like, shape (n, k)
            The cylinders' lengths (m), one column per role.
        rates : array_like, shape (n, k) or (k,), optional
            Their rates (m/s); default zero, a machine at rest.

        Returns
        -------
        KinematicResult
        """
        ...

    def weight_loads(self) -> list[Load]:
        """Its weight as loads of the general kinetostatics.

        Returns
        -------
        list of Load
        """
        ...


class StandingMachine(Protocol):
    """A machine on the ground: what tipping and slipping read."""

    @property
    def base(self) -> Base | None:
        """What the machine stands on (its ``support``: the masses of its two frames and its
        contact elements); None where the machine file has none."""
        ...

    @property
    def source(self) -> str | None:
        """The machine file, for messages."""
        ...

    @property
    def gravity(self) -> float:
        """g (m/s²), along −y."""
        ...

    @property
    def swing_axis(self) -> float:
        """Abscissa of the axis the front turns about in plan (m): the swing axis, an
        articulation joint."""
        ...

    @property
    def ground_line(self) -> float:
        """Height of the ground line in the model's plane (m)."""
        ...

    @property
    def mass_points(self) -> MassPoints:
        """The masses that turn with the front (bodies and cylinders) as points."""
        ...
