r"""A rope shovel: its front mechanism, hoist and crowd drives, dipper and base.

A [`Shovel`][excavkin.shovel.machine.Shovel] is a general
[`Mechanism`][excavkin.mechanism.Mechanism] with two inputs — the hoist winch (a rope over the
boom-point sheave, `docs/ropes.md`) and the crowd (the handle's slide along its rack's pitch
line) — plus what a shovel designer adds: the motors (count, rated torque and speed), the gear
ratios, the hoist drum's and the crowd pinion's radii, the ranges of the hoist rope and of the
crowd, the payload and the base. Every position, rate and force comes from the general engine;
this module converts the drives' units and names the parts.

Conventions (SI; side view, x forward from the slew axis, y up from the ground)::

                                          T  boom-point sheave
           GA  suspension ropes     BP __o
            *-----------------------*    \   hoist rope (over T to the bail BL)
            |          boom        /      \
     D o    |     S shipper shaft /        o BL
       hoist drum  o--P===== handle ======HF  dipper
                 BF  boom foot                 \__ K teeth

* **hoist**: the rope's length L from the drum's take-off over the sheave to the bail; the
  engine's input is the hoist motor's angle θ = L·i/R (i the gear ratio, R the drum radius),
  so a positive motor speed pays rope out (lowers the dipper) and a hoist hauls in. The engine's
  rope is all the hoist ropes together (``ropes`` in parallel): its tension is the bail pull.
* **crowd**: the handle's slide s, the distance along the rack's pitch line from the saddle's
  pitch point to the handle's front end (> 0, growing as the dipper crowds out): the model's
  crowd driver. The pinion turns on the shipper shaft, carried by the boom, and meshes with the
  rack at the pitch point, r (its pitch radius) from the shaft: the rack's travel relative to
  the saddle is Δs = −σ·r·Δ(θp − θsaddle) (σ = +1 with the rack to the left of the handle's
  direction from the shaft, as `docs/gears.md` draws it), so the crowd motor's angle (> 0
  crowds out, i motor turns per pinion turn) is θm = i·(s/r − σ·θsaddle) + const: the handle
  slides as the saddle turns with the crowd motor held (the crowd–hoist interaction).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray as F
from excavkin.kinematics import KinematicResult
from excavkin.kinetostatics import ForceResult, Gravity, PointForce
from excavkin.machinery.base import BaseMachine
from excavkin.machinery.masses import MassPoints, mass_points
from excavkin.mechanism import Mechanism
from excavkin.model.entities import Load
from excavkin.shovel.boom import Boom, HoistBalance


@dataclass(frozen=True, slots=True)
class Motor:
    """The motors of one drive, all alike.

    Attributes
    ----------
    count : int
        Motors driving together.
    torque : float
        Each motor's rated (peak digging) torque (N·m).
    speed : float
        Each motor's rated speed (rad/s).
    """

    count: int
    torque: float
    speed: float

    @property
    def power(self) -> float:
        """The drive's rated power, all its motors (W)."""
        return self.count * self.torque * self.speed


@dataclass(frozen=True, slots=True)
class Hoist:
    """The hoist: motors, gearing, drum and the rope the model runs over the boom point.

    Attributes
    ----------
    rope : str
        The model's winch rope (drum take-off → boom-point sheave → bail).
    motor : Motor
    gear_ratio : float
        Motor turns per drum turn.
    drum_radius : float
        To the rope's centre line (m).
    ropes : int
        Hoist ropes in parallel (the model's rope is all of them: its tension is the bail pull).
    length : tuple of float
        The rope's shortest and longest length (m): the hoist's range.
    """

    rope: str
    motor: Motor
    gear_ratio: float
    drum_radius: float
    ropes: int
    length: tuple[float, float]

    def angle(self, length: ArrayLike) -> F:
        """The motor's angle for a rope length, θ = L·i/R.

        Parameters
        ----------
        length : array_like
            Rope length (m).

        Returns
        -------
        ndarray
            Motor angle (rad).
        """
        return np.asarray(length, dtype=float) * self.gear_ratio / self.drum_radius

    @property
    def pull(self) -> float:
        """The bail pull at the motors' rated torque, T = n·τ·i/R (N)."""
        return self.motor.count * self.motor.torque * self.gear_ratio / self.drum_radius

    @property
    def speed(self) -> float:
        """The rope speed at the motors' rated speed, v = ω·R/i (m/s)."""
        return self.motor.speed * self.drum_radius / self.gear_ratio


@dataclass(frozen=True, slots=True)
class Crowd:
    """The crowd: motors, gearing, the shipper shaft's pinion and the handle's rack.

    Attributes
    ----------
    driver : str
        The model's linear driver: the saddle's pitch point → the handle's front end.
    motor : Motor
    gear_ratio : float
        Motor turns per pinion turn.
    pinion_radius : float
        The pinion's pitch radius (m).
    extension : tuple of float
        The slide's shortest and longest value (m): the crowd's range.
    sigma : float
        +1 where the rack lies to the left of the handle's direction from the shipper shaft,
        −1 to the right (module docstring).
    """

    driver: str
    motor: Motor
    gear_ratio: float
    pinion_radius: float
    extension: tuple[float, float]
    sigma: float = 1.0

    @property
    def force(self) -> float:
        """The crowd force at the motors' rated torque, F = n·τ·i/r (N)."""
        return self.motor.count * self.motor.torque * self.gear_ratio / self.pinion_radius

    @property
    def speed(self) -> float:
        """The handle's speed at the motors' rated speed, v = ω·r/i (m/s)."""
        return self.motor.speed * self.pinion_radius / self.gear_ratio

    def torque(self, force: ArrayLike) -> F:
        """The motors' torque (all of them) for a tooth force on the rack, τ = W·r/i.

        Parameters
        ----------
        force : array_like
            The rack's tooth force (N, > 0 crowds out).

        Returns
        -------
        ndarray
            N·m, in the sense of the motor's angle.
        """
        return np.asarray(force, dtype=float) * self.pinion_radius / self.gear_ratio


@dataclass(frozen=True, slots=True)
class Front:
    """Names, in the general model, of the front's bodies and points.

    Attributes
    ----------
    boom, saddle, handle, dipper : str
        Bodies of the model.
    boom_foot, shipper_shaft, sheave : str
        Points of the boom: its foot pin, the shipper shaft, the boom-point sheave's centre.
    suspension : str
        The model's locked rope holding the boom.
    teeth, bail, door_hinge : str
        Points of the dipper: the tooth tip, the bail pin, the door's hinge.
    """

    boom: str
    saddle: str
    handle: str
    dipper: str
    boom_foot: str
    shipper_shaft: str
    sheave: str
    suspension: str
    teeth: str
    bail: str
    door_hinge: str


@dataclass(frozen=True, slots=True)
class Dipper:
    """The dipper's rating and door.

    Attributes
    ----------
    capacity : float
        Rated (SAE J296 struck-plus-heap) capacity (m³).
    payload : float
        Rated payload (kg).
    payload_point : str
        A point of the dipper at the payload's centre of gravity.
    door_length : float
        Hinge to the lower edge of the open door, hanging (m): the dump height is the hinge's
        height less this.
    width : float
        Cutting width over the teeth (m).
    """

    capacity: float
    payload: float
    payload_point: str
    door_length: float
    width: float


class Shovel:
    """A rope shovel: a general mechanism plus the hoist and crowd drives, dipper and base.

    Parameters
    ----------
    mechanism : Mechanism
        The front, with the hoist rope's drum radius and gear ratio the machine file's.
    front : Front
    hoist : Hoist
    crowd : Crowd
    dipper : Dipper
    base : BaseMachine or None
        The revolving frame and the crawlers (the machinery layer's base), or None.
    gravity : float
        m/s².
    name : str
    source : str or None
        The machine file.
    """

    def __init__(
        self,
        mechanism: Mechanism,
        front: Front,
        hoist: Hoist,
        crowd: Crowd,
        dipper: Dipper,
        base: BaseMachine | None,
        gravity: float,
        name: str,
        source: str | None = None,
    ) -> None:
        self.mechanism = mechanism
        self.front = front
        self.hoist = hoist
        self.crowd = crowd
        self.dipper = dipper
        self.base = base
        self.gravity = gravity
        self.name = name
        self.source = source

    def __repr__(self) -> str:
        return (
            f"Shovel({self.name!r}: hoist {self.hoist.pull / 1e3:.0f} kN at "
            f"{self.hoist.speed:.2f} m/s, crowd {self.crowd.force / 1e3:.0f} kN at "
            f"{self.crowd.speed:.2f} m/s, payload {self.dipper.payload / 1e3:.0f} t)"
        )

    @property
    def swing_axis(self) -> float:
        """x of the slew axis (m): the model's origin."""
        return 0.0

    @property
    def ground_line(self) -> float:
        """Height of the ground in the model's plane (m): the model's x axis."""
        return 0.0

    @property
    def mass_points(self) -> MassPoints:
        """The front's masses as points: each moving body's centre of mass (no cylinders)."""
        return mass_points(self.mechanism, (), ())

    @property
    def front_mass(self) -> float:
        """The moving front's mass: the model's moving bodies (kg)."""
        return float(sum(b.mass or 0.0 for b in self.mechanism.model.bodies if not b.ground))

    def solve(
        self,
        length: ArrayLike,
        extension: ArrayLike,
        length_rate: ArrayLike | None = None,
        extension_rate: ArrayLike | None = None,
    ) -> KinematicResult:
        """Solve the front at hoist-rope lengths and crowd extensions (one batch).

        Parameters
        ----------
        length : array_like, shape (n,)
            Hoist rope length (m).
        extension : array_like, shape (n,)
            Crowd slide (m).
        length_rate, extension_rate : array_like, shape (n,), optional
            Their rates (m/s); both or neither. Without them the result's rates are the
            transfer functions (unit input rates) and its forces static.

        Returns
        -------
        KinematicResult
            The hoist input is the motor's angle (rad): its rate is the motor's speed.
        """
        theta = self.hoist.angle(length)
        inputs = {self.hoist.rope: theta, self.crowd.driver: np.asarray(extension, float)}
        if length_rate is None and extension_rate is None:
            return self.mechanism.solve(inputs)
        if length_rate is None or extension_rate is None:
            raise ValueError("give both rates or neither")
        rates = {
            self.hoist.rope: self.hoist.angle(length_rate),
            self.crowd.driver: np.asarray(extension_rate, float),
        }
        return self.mechanism.solve(inputs, rates)

    def weight_loads(self, fill: ArrayLike = 1.0) -> list[Load]:
        """The front's weight and the payload's as loads of the general kinetostatics.

        Parameters
        ----------
        fill : float or array_like, shape (n,)
            The payload's fraction (0 empty, 1 the rated payload).

        Returns
        -------
        list of Gravity or PointForce
            ``Gravity`` on the model's bodies, then ``payload`` at the payload point.
        """
        w = -self.dipper.payload * self.gravity * np.asarray(fill, dtype=float)
        value = np.stack([np.zeros_like(w), w], axis=-1) if w.ndim else (0.0, float(w))
        return [
            Gravity(self.gravity),
            PointForce("payload", self.front.dipper, self.dipper.payload_point, value),
        ]


def table_attrs(machine: str, kinds: dict[str, str]) -> dict[str, object]:
    """``frame.attrs`` of a shovel result's table: the machine's name, each column's kind and
    its SI unit (``excavkin.model``, ``excavkin.kinds``, ``excavkin.units``), as every
    excavkin table records them.

    Parameters
    ----------
    machine : str
        The machine's name.
    kinds : dict of str to str
        Column → kind (``"length"``, ``"force"``, …).

    Returns
    -------
    dict
    """
    from excavkin.kinematics.columns import si_unit

    return {
        "excavkin.model": machine,
        "excavkin.kinds": dict(kinds),
        "excavkin.units": {c: si_unit(k) for c, k in kinds.items()},
    }


@dataclass(frozen=True, slots=True)
class Drag:
    """A rope backhoe's drag winch: motors, gearing, drum and the rope's parts.

    Attributes
    ----------
    driver : str
        The model's driven linear driver: the drag rope's length from its sheave to the bucket
        (its rate is −v, hauling in shortens it).
    motor : Motor
    gear_ratio : float
        Motor turns per drum turn.
    drum_radius : float
        m.
    parts : int
        Parts of rope between the sheave's block and the bucket's (the rope's multiplicity).
    length : tuple of float or None
        The rope's shortest and longest length, sheave to bucket (m); None where the file
        gives none.
    """

    driver: str
    motor: Motor
    gear_ratio: float
    drum_radius: float
    parts: int
    length: tuple[float, float] | None = None

    @property
    def speed(self) -> float:
        """The bucket's hauling speed at the motors' rated speed, v = ω·R/(i·parts) (m/s)."""
        return self.motor.speed * self.drum_radius / (self.gear_ratio * self.parts)

    @property
    def pull(self) -> float:
        """The drag pull on the bucket at the motors' rated torque, n·τ·i·parts/R (N)."""
        return (
            self.motor.count * self.motor.torque * self.gear_ratio * self.parts / self.drum_radius
        )


class RopeBackhoe:
    """A rope backhoe: the stick hauled by a drag rope, the bucket turned by its linkage.

    Parameters
    ----------
    mechanism : Mechanism
    drag : Drag
    stick, bucket : str
        Bodies of the model.
    name : str
    source : str or None
    boom : Boom or None
        The boom's foot, weight and hoist tackle (the model's frame is the boom), or None.
    """

    def __init__(
        self,
        mechanism: Mechanism,
        drag: Drag,
        stick: str,
        bucket: str,
        name: str,
        source: str | None = None,
        boom: Boom | None = None,
    ) -> None:
        self.mechanism = mechanism
        self.drag = drag
        self.stick = stick
        self.bucket = bucket
        self.name = name
        self.source = source
        self.boom = boom

    def __repr__(self) -> str:
        return f"RopeBackhoe({self.name!r}: drag {self.drag.speed:.3f} m/s)"

    def haul(self, length: ArrayLike) -> KinematicResult:
        """The mechanism at drag-rope lengths, hauled in at the motors' rated speed.

        Parameters
        ----------
        length : array_like, shape (n,)
            The drag rope's length, sheave to bucket (m).

        Returns
        -------
        KinematicResult
        """
        q = np.asarray(length, dtype=float)
        return self.mechanism.solve(
            {self.drag.driver: q}, {self.drag.driver: np.full_like(q, -self.drag.speed)}
        )

    def attitude(self, result: KinematicResult) -> tuple[F, F]:
        """The bucket's attitude: to the stick and to the boom (the model's x axis).

        Parameters
        ----------
        result : KinematicResult
            From `haul`.

        Returns
        -------
        relative, absolute : ndarray, shape (n,)
            rad.
        """
        stick = result.body(self.stick)[0]
        bucket = result.body(self.bucket)[0]
        return bucket - stick, bucket

    def rope_tension(self, forces: ForceResult) -> F:
        """The drag rope's tension (N): the driver's pull over the rope's parts.

        Parameters
        ----------
        forces : ForceResult

        Returns
        -------
        ndarray, shape (n,)
        """
        return -forces.force(self.drag.driver) / self.drag.parts

    def hoist(self, forces: ForceResult) -> HoistBalance:
        """The boom's hoist tackle and foot pin holding the mechanism's forces and the boom's
        weight (`excavkin.shovel.boom`).

        Parameters
        ----------
        forces : ForceResult
            The general kinetostatics of the model.

        Returns
        -------
        HoistBalance
            The tackle's pull (all parts), one part's tension, the foot pin's force on the
            boom and the status (a tackle that would push is not ok).

        Raises
        ------
        InputError
            The machine file has no ``[boom]`` table.
        """
        from excavkin.errors import InputError

        if self.boom is None:
            raise InputError(f"{self.name}: no [boom] table: the boom's hoist is not described")
        return self.boom.balance(forces, self.rope_tension(forces))

    def hoist_tension(self, forces: ForceResult) -> F:
        """One part of the hoist tackle's tension (N), shape (n,): `hoist`'s ``tension``.

        Parameters
        ----------
        forces : ForceResult

        Returns
        -------
        ndarray, shape (n,)
            Negative where the tackle would have to push.
        """
        return self.hoist(forces).tension
