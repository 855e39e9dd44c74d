r"""A wheel loader: its front linkage, cylinders, bucket and chassis.

A [`Loader`][excavkin.loader.machine.Loader] is a general
[`Mechanism`][excavkin.mechanism.Mechanism] whose two driven linear drivers are the lift and
tilt cylinders, plus what a loader designer adds: which bodies are the lift arm and the bucket,
the bucket's cutting edge and heel, its rated capacity and the rated load's centre of gravity,
and the chassis (axles, tyres, articulation, frame masses). Every position and transfer
function comes from the general engine; this module arranges its inputs and reads its outputs.

Conventions (SI; side view, x forward, y up, angles CCW from +x)::

            F ── tilt cylinder ── G            Z-bar: extending the tilt cylinder turns the
           /                     /|            bell crank E–G–H back at the bottom, which
      A (lift-arm pin)     bell  E|            pulls the tilt link H–I and rolls the bucket
       \  \   lift arm    crank   H──── I      back about the hinge pin B
        C  D ─────────────────── B  (bucket)
                                 K______W      heel K, cutting edge W
     ══════════════ ground ═══(front axle)════════════════

* Cylinder lengths are pin-to-pin, in the order ``("lift", "tilt")``: arrays of shape (n, 2).
* The **bucket frame**: origin at the hinge pin B, x along the floor from the heel to the
  cutting edge, y at +90° from it (up when the bucket sits level). The rated load's centre of
  gravity is given in it.
* The **floor angle** is the direction of heel → edge, CCW from +x: 0 level, > 0 rolled back
  (the edge above the heel), < 0 dumping.
* The **chassis**: the front frame (front axle, the linkage's pins) turns about the vertical
  articulation joint relative to the rear frame (rear axle, engine, cab, counterweight).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray as F
from excavkin.kinematics import KinematicResult
from excavkin.kinematics.summary import batch_repr
from excavkin.machinery.base import Mass, Support, axle
from excavkin.machinery.cylinder_machine import CylinderMachine
from excavkin.machinery.cylinders import Circuit, Cylinder, cylinder_lengths
from excavkin.machinery.masses import MassPoints, mass_points
from excavkin.machinery.pumps import Hydraulics
from excavkin.mechanism import Mechanism

if TYPE_CHECKING:
    from excavkin.machinery.base import Base

#: The two cylinders of a loader front, in the order of every ``(n, 2)`` array.
ROLES: tuple[str, str] = ("lift", "tilt")


class LoaderHydraulics(Hydraulics):
    """A loader's pumps: they feed the lift and the tilt cylinders (no swing)."""

    roles: ClassVar[tuple[str, ...]] = ROLES
    has_swing: ClassVar[bool] = False


@dataclass(frozen=True, slots=True)
class Linkage:
    """Names, in the general model, of the lift arm, the bucket and the bucket's points.

    Attributes
    ----------
    lift_arm, bucket : str
        Bodies of the model.
    edge : str
        The cutting edge (a point of the bucket; its lowest point in side view).
    heel : str
        A point of the bucket's floor behind the edge: heel → edge is the floor.
    """

    lift_arm: str
    bucket: str
    edge: str
    heel: str


@dataclass(frozen=True, slots=True)
class Bucket:
    """The bucket's ratings.

    Attributes
    ----------
    capacity : float
        Rated (heaped) capacity per ISO 7546 / SAE J742 (m³).
    width : float
        Width over the cutting edge (m).
    load_cg : tuple of float
        The rated load's centre of gravity (the centroid of the rated volume) in the bucket
        frame (module docstring) (m).
    """

    capacity: float
    width: float
    load_cg: tuple[float, float]


@dataclass(frozen=True, slots=True)
class Chassis:
    """Axles, tyres, articulation and the masses of the frames (model coordinates, SI).

    Attributes
    ----------
    wheelbase : float
        Front axle to rear axle (m).
    front_axle : tuple of float
        Centre of the front axle (x, y) in the model's plane (m).
    tread : float
        Track width: tyre centre to tyre centre across an axle (m).
    tyre_radius : float
        Static loaded radius (m): the ground line lies this far below the front axle.
    articulation : float
        x of the vertical articulation joint (m).
    max_articulation : float
        The largest articulation angle, either way (rad).
    front_frame : Mass
        The front frame (with the front axle and its tyres): turns with the articulation.
    rear_frame : Mass
        The rear frame (engine, cab, rear axle and tyres, tanks), the counterweight apart.
    counterweight : Mass
    oscillating : bool
        The rear axle swings about a longitudinal pin (its support is one point under the
        pin); otherwise it is rigid (two tyre contacts).
    friction : float or None
        Coefficient of friction between the tyres and the ground (the slipping limit of the
        machinery layer's equilibrium); None where the file gives none.
    """

    wheelbase: float
    front_axle: tuple[float, float]
    tread: float
    tyre_radius: float
    articulation: float
    max_articulation: float
    front_frame: Mass
    rear_frame: Mass
    counterweight: Mass
    oscillating: bool = True
    friction: float | None = None

    @property
    def support(self) -> Support:
        """The machinery layer's support model: the front frame and its axle's tyres turn
        with the articulation; the rear frame, the counterweight and the rear axle (its pivot
        where it oscillates) do not. Tipping lines are named by the contacts they join."""
        return Support(
            (self.front_frame,),
            (self.rear_frame, self.counterweight),
            (
                axle("front", self.front_axle[0], self.tread, turns=True),
                axle("rear", self.rear_axle, self.tread, oscillating=self.oscillating),
            ),
            self.friction,
            "contacts",
        )

    @property
    def ground_line(self) -> float:
        """Height of the ground in the model's plane (m)."""
        return self.front_axle[1] - self.tyre_radius

    @property
    def rear_axle(self) -> float:
        """x of the rear axle (m)."""
        return self.front_axle[0] - self.wheelbase

    @property
    def front_most(self) -> float:
        """x of the foremost point of the tyres (m): where dump reach is measured from."""
        return self.front_axle[0] + self.tyre_radius


@dataclass(frozen=True, slots=True)
class Pins:
    """Point names of the pins, found from the model's topology.

    Attributes
    ----------
    lift_arm_pin : str
        Frame – lift arm.
    hinge : str
        Lift arm – bucket (the bucket hinge pin).
    cyl_ends : tuple of (str, str)
        Per role: the cylinder's (base, rod end).
    """

    lift_arm_pin: str
    hinge: str
    cyl_ends: tuple[tuple[str, str], ...]


class Loader(CylinderMachine):
    """A wheel loader: a general mechanism plus cylinders, circuits, bucket and chassis.

    Parameters
    ----------
    mechanism : Mechanism
        Two driven linear drivers (the lift and tilt cylinders) and no other input; the lift
        arm is pinned to the ground (the front frame) and the bucket to the lift arm.
    linkage : Linkage
    cylinders : mapping of str to Cylinder
        Keys ``"lift"`` and ``"tilt"``; each ``dig`` says which motion raises the lift arm
        (``"extend"`` on most loaders) and which rolls the bucket back (``"extend"`` on a Z-bar).
    circuits : mapping of str to Circuit
    bucket : Bucket
    chassis : Chassis
    carry_height : float
        Height of the hinge pin above the ground in the carry position (m).
    gravity : float
        g (m/s²), along −y.
    hydraulics : LoaderHydraulics, optional
    name, source : str
        For messages.

    Raises
    ------
    ModelError
        Naming the table and entry of a name, topology or number that does not fit.
    """

    ROLES = ROLES

    def __init__(
        self,
        mechanism: Mechanism,
        linkage: Linkage,
        cylinders: Mapping[str, Cylinder],
        circuits: Mapping[str, Circuit],
        bucket: Bucket,
        chassis: Chassis,
        *,
        carry_height: float = 0.4,
        gravity: float = 9.80665,
        hydraulics: LoaderHydraulics | None = None,
        name: str = "",
        source: str | None = None,
    ) -> None:
        self.mechanism = mechanism
        self.linkage = linkage
        self.circuits = dict(circuits)
        self.bucket = bucket
        self.chassis = chassis
        self.carry_height = float(carry_height)
        self.gravity = float(gravity)
        self.hydraulics = hydraulics
        self.name = name or mechanism.name
        self.source = source
        for role in ROLES:
            if role not in cylinders:
                raise self._err(f"the {role} cylinder is missing", f"cylinders.{role}")
        self.cylinders: tuple[Cylinder, Cylinder] = (cylinders["lift"], cylinders["tilt"])
        for c in self.cylinders:
            self._check_cylinder(c)
        inputs = mechanism.plan.inputs
        extra = [n for n in inputs if n not in {c.driver for c in self.cylinders}]
        if extra:
            raise self._err(
                f"the model has inputs besides the lift and tilt cylinders: {', '.join(extra)}",
                "cylinders",
            )
        self.pins = self._find_pins()
        self._mass_points: MassPoints | None = None
        self._check_strokes()

    # ---- construction checks
    def _find_pins(self) -> Pins:
        model = self.mechanism.model
        lk = self.linkage
        bodies = {b.name: set(b.points) for b in model.bodies}
        for key in ("lift_arm", "bucket"):
            if getattr(lk, key) not in bodies:
                raise self._err(f"no body {getattr(lk, key)!r} in the model", "linkage", key)
        for key in ("edge", "heel"):
            if getattr(lk, key) not in bodies[lk.bucket]:
                raise self._err(
                    f"{getattr(lk, key)!r} is not a point of the bucket {lk.bucket!r}",
                    "linkage",
                    key,
                )
        ground = set(model.ground.points)

        def common(a: set[str], b: set[str], what: str, key: str) -> str:
            both = sorted(a & b)
            if len(both) != 1:
                raise self._err(
                    f"the {what} must share exactly one pin, found {both or 'none'}",
                    "linkage",
                    key,
                )
            return both[0]

        arm_pin = common(ground, bodies[lk.lift_arm], "frame and the lift arm", "lift_arm")
        hinge = common(bodies[lk.lift_arm], bodies[lk.bucket], "lift arm and bucket", "bucket")
        drivers = {d.name: d for d in model.linear}
        ends = tuple(drivers[c.driver].between for c in self.cylinders)
        pos = self.mechanism.assembly.positions
        pts = self.mechanism.plan.points
        heel, edge = (pos[pts.index(n)] for n in (lk.heel, lk.edge))
        if math.hypot(*(edge - heel)) < 1e-6:
            raise self._err("the heel coincides with the cutting edge", "linkage", "heel")
        return Pins(arm_pin, hinge, ends)

    def _check_strokes(self) -> None:
        """Refuse strokes that never assemble the linkage (each swept with the other at the
        model's sketch length), naming the cylinder."""
        sketch = self.mechanism.sketch_values()
        for c in self.cylinders:
            values: dict[str, F | float] = dict(sketch)
            values[c.driver] = np.linspace(c.retracted, c.extended, 41)
            if not self.mechanism.solve(values).status.ok.any():
                raise self._err(
                    f"no length of cylinder {c.driver!r} within its stroke "
                    f"({c.retracted * 1e3:.0f} to {c.extended * 1e3:.0f} mm) assembles the "
                    "linkage with the other cylinder at the model's sketch; check its retracted "
                    "length and stroke against the model's pins",
                    f"cylinders.{c.role}",
                    "retracted",
                )

    # ---- what the machinery layer reads
    @property
    def base(self) -> Base | None:
        """Its `chassis`: what it stands on (the machinery layer's equilibrium reads its
        ``support``)."""
        return self.chassis

    @property
    def ground_line(self) -> float:
        """Height of the ground in the model's plane (m)."""
        return self.chassis.ground_line

    @property
    def swing_axis(self) -> float:
        """x of the articulation joint (m): what turns the front in plan."""
        return self.chassis.articulation

    @property
    def mass_points(self) -> MassPoints:
        """The linkage's masses as points: each body's centre of mass and each cylinder's
        mass, half at either end pin."""
        if self._mass_points is None:
            self._mass_points = mass_points(self.mechanism, self.cylinders, self.pins.cyl_ends)
        return self._mass_points

    @property
    def linkage_mass(self) -> float:
        """Mass of the linkage: the model's moving bodies and the cylinders (kg)."""
        return float(self.mass_points.mass.sum())

    @property
    def mass(self) -> float:
        """Operating mass: the linkage, both frames and the counterweight (kg)."""
        ch = self.chassis
        return self.linkage_mass + ch.front_frame.mass + ch.rear_frame.mass + ch.counterweight.mass

    def raise_sign(self) -> float:
        """+1 where extending the lift cylinder raises the lift arm, −1 otherwise.

        Returns
        -------
        float
        """
        return 1.0 if self.cylinders[0].dig == "extend" else -1.0

    def rollback_sign(self) -> float:
        """+1 where extending the tilt cylinder rolls the bucket back, −1 otherwise.

        Returns
        -------
        float
        """
        return 1.0 if self.cylinders[1].dig == "extend" else -1.0

    def full_lift(self) -> float:
        """The lift cylinder's length at full lift (m).

        Returns
        -------
        float
        """
        c = self.cylinders[0]
        return c.extended if c.dig == "extend" else c.retracted

    def lowest(self) -> float:
        """The lift cylinder's length with the lift arm fully lowered (m).

        Returns
        -------
        float
        """
        c = self.cylinders[0]
        return c.retracted if c.dig == "extend" else c.extended

    def full_rollback(self) -> float:
        """The tilt cylinder's length at full rollback (m).

        Returns
        -------
        float
        """
        c = self.cylinders[1]
        return c.extended if c.dig == "extend" else c.retracted

    def full_dump(self) -> float:
        """The tilt cylinder's length at full dump (m).

        Returns
        -------
        float
        """
        c = self.cylinders[1]
        return c.retracted if c.dig == "extend" else c.extended

    def __repr__(self) -> str:
        return f"Loader({self.name!r}, cylinders={list(self.drivers)})"


@dataclass(frozen=True, slots=True)
class Transfer:
    """Positions and first-order transfer functions ∂(point)/∂L of every point.

    Attributes
    ----------
    lengths : ndarray, shape (n, 2)
    positions : ndarray, shape (n, n_points, 2)
    d : ndarray, shape (n, n_points, 2, 2)
        ``d[i, p, :, c]`` = ∂(position of point p)/∂L_c.
    ok : ndarray of bool, shape (n,)
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    lengths: F
    positions: F
    d: F
    ok: np.ndarray

    def point(self, machine: Loader, name: str) -> tuple[F, F]:
        """Position (n, 2) and Jacobian (n, 2, 2) of a point.

        Parameters
        ----------
        machine : Loader
        name : str

        Returns
        -------
        position, jacobian : ndarray
        """
        i = machine.index(name)
        return self.positions[:, i], self.d[:, i]


def transfer(machine: Loader, lengths: ArrayLike) -> Transfer:
    """The engine's exact transfer functions: one solve per cylinder with unit rate.

    Parameters
    ----------
    machine : Loader
    lengths : array_like, shape (n, 2)

    Returns
    -------
    Transfer
    """
    L = cylinder_lengths(lengths, ROLES)
    cols = []
    first: KinematicResult | None = None
    for c in range(2):
        res = machine.solve(L, np.eye(2)[c])
        first = first or res
        cols.append(res.velocities)
    assert first is not None
    return Transfer(L, first.positions, np.stack(cols, axis=-1), first.status.ok)


def table_attrs(machine: str, kinds: Mapping[str, str]) -> dict[str, object]:
    """``frame.attrs`` of a loader result's table: the machine's name, each column's kind and
    its SI unit (``excavkin.model``, ``excavkin.kinds``, ``excavkin.units``), as every
    excavkin table records them.

    Parameters
    ----------
    machine : str
        The machine's name.
    kinds : mapping of str to str
        Column → kind (``"length"``, ``"angle"``, ``"force"``, ``"mass"``).

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


def floor_angle(machine: Loader, positions: F) -> F:
    """The bucket floor's direction (heel → edge), CCW from +x (rad): 0 level, > 0 rolled back.

    Parameters
    ----------
    machine : Loader
    positions : ndarray, shape (n, n_points, 2)

    Returns
    -------
    ndarray, shape (n,)
    """
    v = (
        positions[:, machine.index(machine.linkage.edge)]
        - positions[:, machine.index(machine.linkage.heel)]
    )
    return np.asarray(np.arctan2(v[:, 1], v[:, 0]))


def floor_angle_rate(machine: Loader, tr: Transfer) -> F:
    """∂(floor angle)/∂L of each cylinder, shape (n, 2) (rad/m).

    Parameters
    ----------
    machine : Loader
    tr : Transfer

    Returns
    -------
    ndarray, shape (n, 2)
    """
    e, de = tr.point(machine, machine.linkage.edge)
    h, dh = tr.point(machine, machine.linkage.heel)
    v, dv = e - h, de - dh
    r2 = (v**2).sum(axis=1)
    return np.asarray((v[:, 0, None] * dv[:, 1] - v[:, 1, None] * dv[:, 0]) / r2[:, None])


def bucket_frame_point(machine: Loader, positions: F, local: tuple[float, float]) -> F:
    """A point given in the bucket frame, in the model's plane.

    Parameters
    ----------
    machine : Loader
    positions : ndarray, shape (n, n_points, 2)
    local : (float, float)
        Its coordinates in the bucket frame (m): along the floor, and at +90° from it.

    Returns
    -------
    ndarray, shape (n, 2)
    """
    a = floor_angle(machine, positions)
    c, s = np.cos(a), np.sin(a)
    b = positions[:, machine.index(machine.pins.hinge)]
    x, y = local
    return np.column_stack([b[:, 0] + c * x - s * y, b[:, 1] + s * x + c * y])
