r"""Hydraulics of an excavator front: cylinder speeds from pump flow, stroke and cycle times,
hydraulic power along a motion, and the buckling check of each cylinder.

**Speeds.** Each function (boom, arm, bucket) moved alone receives the summed flow ``Q`` of every
pump that feeds it (the pumps' confluence); with ``count`` cylinders acting together the areas
are those of all of them (`Cylinder.bore_area`, `Cylinder.annulus_area`)::

    v_extend = Q / A_bore        v_retract = Q / A_annulus        t = stroke / v

Leakage, valve pressure drops, pump regulation (power limiting at high pressure) and
cushioning are left out: the speeds are the no-load, full-flow speeds of spec sheets.

**Cycle.** A dig–swing–dump cycle is four phases, each made of full strokes (a conservative
choice: operators use partial strokes) and a swing at constant speed through the dig-to-dump
angle (acceleration and braking left out)::

    dig     arm and bucket in their digging direction        t_dig  = t_arm,dig + t_bkt,dig
    raise   boom up (cylinder extending), swing to dump      t_boom,up,  t_swing = θ / ω
    dump    arm and bucket back                              t_dump = t_arm,back + t_bkt,back
    return  swing back, boom down                            t_swing,  t_boom,down

``sequential`` adds every motion (one at a time, an upper bound); ``overlapped`` lets the swing
overlap the boom in the raise and return phases, ``max(t_boom, t_swing)``, as operators do.

**Power.** Along a motion the power of cylinder c is ``f_c·L̇_c`` with ``f_c`` the cylinder force
of the kinetostatics ([`Mechanism.forces`][excavkin.mechanism.Mechanism.forces]) and ``L̇_c`` its
rate from the kinematics. With
the outlet side drained, the inlet pressure is ``p = f/A_bore`` extending and ``−f/A_annulus``
retracting, the inlet flow ``Q = A·|L̇|``, and the pump's hydraulic power ``p·Q = f·L̇``. A
negative ``p`` means an overrunning load: the load drives the cylinder and the outlet (meter-out)
throttle carries it.

**Buckling.** Each cylinder is taken as a pinned–pinned column (K = 1) of its pin-to-pin length
L, made of the **rod alone** (diameter d, A = πd²/4, I = πd⁴/64, r = d/4): the tube is stiffer
than the rod, so leaving it out errs on the safe side. With slenderness λ = K·L/r
(Shigley's *Mechanical Engineering Design*, §4-12 "Long columns with central loading" and
§4-13 "Intermediate-length columns with central loading")::

    Euler    P_cr = π²·E·I / (K·L)²                         λ ≥ λ_1 = √(2π²E/σ_y)
    Johnson  P_cr = A·σ_y·(1 − σ_y·λ² / (4π²·E))             λ < λ_1

and both give A·σ_y/2 at λ_1. The safety factor is ``P_cr / P`` for a compressive force P of one
cylinder (infinite where the cylinder pulls).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.excavator.machine import ROLES, Cylinder, Machine, as_lengths

#: steel defaults of the buckling check: Young's modulus and the rod's yield stress (Pa), a
#: quenched and tempered C45-class rod steel
STEEL_E, ROD_YIELD = 210e9, 500e6


@dataclass(frozen=True, slots=True)
class Pump:
    """A pump: its flow (m³/s) and the functions (``"boom"``, ``"arm"``, ``"bucket"``) it feeds."""

    name: str
    flow: float
    feeds: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Hydraulics:
    """Pumps, swing and rod material of a machine (SI).

    Attributes
    ----------
    pumps : tuple of Pump
    swing_speed : float
        Swing speed of the upper structure (rad/s).
    swing_angle : float
        Swing angle from dig to dump (rad).
    modulus, rod_yield : float
        Young's modulus and yield stress of the cylinder rods (Pa), for buckling.
    """

    pumps: tuple[Pump, ...]
    swing_speed: float
    swing_angle: float
    modulus: float = STEEL_E
    rod_yield: float = ROD_YIELD

    def __post_init__(self) -> None:
        for name, value in (
            ("swing_speed", self.swing_speed),
            ("swing_angle", self.swing_angle),
            ("modulus", self.modulus),
            ("rod_yield", self.rod_yield),
        ):
            if not (math.isfinite(value) and value > 0.0):
                raise InputError(f"{name} must be positive and finite, not {value!r}")
        for p in self.pumps:
            if not (math.isfinite(p.flow) and p.flow > 0.0):
                raise InputError(f"pump {p.name!r}: flow must be positive, not {p.flow!r}")
            if not p.feeds or any(f not in ROLES for f in p.feeds):
                raise InputError(
                    f"pump {p.name!r} must feed some of {', '.join(ROLES)}, not {p.feeds!r}"
                )
        unfed = [r for r in ROLES if not any(r in p.feeds for p in self.pumps)]
        if unfed:
            raise InputError(f"no pump feeds the {', '.join(unfed)} cylinder(s)")

    def flow(self, role: str) -> float:
        """The flow reaching the function ``role`` moved alone: the sum over its pumps.

        Parameters
        ----------
        role : {"boom", "arm", "bucket"}
            The function.

        Returns
        -------
        float
            The summed flow of every pump that feeds it (m³/s).

        Raises
        ------
        InputError
            Another role.
        """
        if role not in ROLES:
            raise InputError(f"role must be one of {', '.join(ROLES)}, not {role!r}")
        return float(sum(p.flow for p in self.pumps if role in p.feeds))


@dataclass(frozen=True, slots=True)
class Stroke:
    """Speeds and full-stroke times of one function.

    Attributes
    ----------
    role : str
    flow : float
        Flow into the cylinders (m³/s).
    extend_speed, retract_speed : float
        Rod speeds (m/s).
    extend_time, retract_time : float
        Full-stroke times (s).
    """

    role: str
    flow: float
    extend_speed: float
    retract_speed: float
    extend_time: float
    retract_time: float


def cylinder_speed(
    cylinder: Cylinder, flow: float | F, direction: Literal["extend", "retract"]
) -> F:
    """Rod speed of ``cylinder`` (all ``count`` of them together) fed ``flow`` (m³/s): ``Q/A_bore``
    extending, ``Q/A_annulus`` retracting (m/s)."""
    area = cylinder.bore_area if direction == "extend" else cylinder.annulus_area
    return np.asarray(flow, dtype=np.float64) / area


def strokes(machine: Machine, hydraulics: Hydraulics | None = None) -> tuple[Stroke, ...]:
    """Speeds and full-stroke times of the boom, arm and bucket, each moved alone.

    Parameters
    ----------
    machine : Machine
        The excavator.
    hydraulics : Hydraulics, optional
        Pump flows and swing to use instead of the machine's own ``[hydraulics]``.

    Returns
    -------
    tuple of Stroke
        Boom, arm and bucket, fed the flow of every pump that feeds them.

    Raises
    ------
    InputError
        The machine has no hydraulics.
    """
    h = hydraulics_of(machine, hydraulics)
    out = []
    for c in machine.cylinders:
        q = h.flow(c.role)
        ve = float(cylinder_speed(c, q, "extend"))
        vr = float(cylinder_speed(c, q, "retract"))
        out.append(Stroke(c.role, q, ve, vr, c.stroke / ve, c.stroke / vr))
    return tuple(out)


@dataclass(frozen=True, slots=True)
class Cycle:
    """A dig–swing–dump cycle estimate (s); see the module's docstring for the model.

    Attributes
    ----------
    dig, boom_up, swing, dump, boom_down : float
        Times of the motions: arm and bucket digging, boom raising, one swing (dig to dump),
        arm and bucket back, boom lowering.
    sequential : float
        Every motion one after the other: ``dig + boom_up + swing + dump + swing + boom_down``.
    overlapped : float
        The swing overlapping the boom: ``dig + max(boom_up, swing) + dump + max(swing,
        boom_down)``.
    """

    dig: float
    boom_up: float
    swing: float
    dump: float
    boom_down: float
    sequential: float
    overlapped: float


def cycle_time(machine: Machine, hydraulics: Hydraulics | None = None) -> Cycle:
    """The dig–swing–dump cycle estimate of ``machine`` (full strokes, constant swing speed).

    Parameters
    ----------
    machine : Machine
        The excavator.
    hydraulics : Hydraulics, optional
        Pump flows and swing to use instead of the machine's own ``[hydraulics]``.

    Returns
    -------
    Cycle
        The times of each motion and of the cycle, sequential and overlapped (s).

    Raises
    ------
    InputError
        The machine has no hydraulics.
    """
    h = hydraulics_of(machine, hydraulics)
    s = dict(zip(ROLES, strokes(machine, h), strict=True))
    cyl = dict(zip(ROLES, machine.cylinders, strict=True))

    def digging(role: str, dig: bool) -> float:
        extend = (cyl[role].dig == "extend") == dig
        return s[role].extend_time if extend else s[role].retract_time

    dig = digging("arm", True) + digging("bucket", True)
    dump = digging("arm", False) + digging("bucket", False)
    up, down = s["boom"].extend_time, s["boom"].retract_time
    swing = h.swing_angle / h.swing_speed
    return Cycle(
        dig,
        up,
        swing,
        dump,
        down,
        dig + up + swing + dump + swing + down,
        dig + max(up, swing) + dump + max(swing, down),
    )


@dataclass(frozen=True, slots=True)
class Power:
    """Hydraulic power along a motion of n samples (per function; SI).

    Attributes
    ----------
    force : ndarray, shape (n, 3)
        Cylinder forces of the kinetostatics (N, > 0 pushing), all ``count`` cylinders together.
    rate : ndarray, shape (n, 3)
        Cylinder length rates (m/s).
    power : ndarray, shape (n, 3)
        ``force·rate`` (W).
    pressure : ndarray, shape (n, 3)
        Inlet pressure with the outlet drained (Pa): ``f/A_bore`` extending, ``−f/A_annulus``
        retracting; negative for an overrunning load. 0 where the cylinder stands still.
    flow : ndarray, shape (n, 3)
        Inlet flow ``A·|rate|`` (m³/s).
    pump_power : ndarray, shape (n, 3)
        ``pressure·flow`` (W), equal to ``power``.
    total : ndarray, shape (n,)
        Sum of ``power`` over the three functions (W).
    """

    force: F
    rate: F
    power: F
    pressure: F
    flow: F
    pump_power: F
    total: F


def motion_power(
    machine: Machine, lengths: ArrayLike, rates: ArrayLike, *, gravity: bool = True
) -> Power:
    """Hydraulic power of the cylinders along a motion, from the engine's kinematics and
    kinetostatics (the front's weight and the inertia of the motion, no soil force).

    Parameters
    ----------
    machine : Machine
    lengths, rates : array_like, shape (n, 3)
        Cylinder lengths (m) and their rates (m/s); accelerations are taken as zero.
    gravity : bool
        Include the front's weight
        ([`Machine.weight_loads`][excavkin.excavator.machine.Machine.weight_loads]).

    Returns
    -------
    Power
    """
    L = as_lengths(lengths)
    R = np.broadcast_to(np.asarray(rates, dtype=np.float64), L.shape)
    res = machine.solve(L, R)
    loads = machine.weight_loads() if gravity else []
    fr = machine.mechanism.forces(res, loads)
    force = np.stack([fr.force(d) for d in machine.drivers], axis=1)
    return power_of(machine, force, R)


def power_of(machine: Machine, force: ArrayLike, rates: ArrayLike) -> Power:
    """`Power` from cylinder forces (N) and rates (m/s), both shape (n, 3)."""
    f = np.asarray(force, dtype=np.float64)
    R = np.broadcast_to(np.asarray(rates, dtype=np.float64), f.shape)
    bore = np.array([c.bore_area for c in machine.cylinders])
    ann = np.array([c.annulus_area for c in machine.cylinders])
    extending = R > 0.0
    area = np.where(extending, bore, ann)
    pressure = np.where(extending, f / bore, np.where(R < 0.0, -f / ann, 0.0))
    flow = area * np.abs(R)
    power = f * R
    return Power(f, R, power, pressure, flow, pressure * flow, power.sum(axis=1))


@dataclass(frozen=True, slots=True)
class Buckling:
    """Buckling check of one cylinder (one of ``count``) under a compressive force.

    Attributes
    ----------
    role : str
    length : ndarray, shape (n,)
        Pin-to-pin length, the column's effective length (m; K = 1).
    force : ndarray, shape (n,)
        Compressive force of one cylinder (N); ≤ 0 means the cylinder pulls.
    slenderness : ndarray, shape (n,)
        K·L/r of the rod.
    transition : float
        √(2π²E/σ_y): Euler at and above, Johnson below.
    critical : ndarray, shape (n,)
        Critical load (N).
    formula : ndarray of str, shape (n,)
        ``"Euler"`` or ``"Johnson"``.
    safety : ndarray, shape (n,)
        ``critical / force``; inf where the cylinder pulls.
    """

    role: str
    length: F
    force: F
    slenderness: F
    transition: float
    critical: F
    formula: np.ndarray
    safety: F


def buckling(
    cylinder: Cylinder,
    length: ArrayLike,
    force: ArrayLike,
    *,
    modulus: float = STEEL_E,
    rod_yield: float = ROD_YIELD,
) -> Buckling:
    """Euler / Johnson buckling check of one cylinder: the rod alone, pinned–pinned, over the
    pin-to-pin ``length`` (m), under ``force`` (N, compressive > 0, one cylinder).

    Parameters
    ----------
    cylinder : Cylinder
        The cylinder; its rod diameter sets the column's section.
    length : array_like, shape (n,) or scalar
        Pin-to-pin length, the effective length (m; K = 1).
    force : array_like, shape (n,) or scalar
        Compressive force on one cylinder (N); ≤ 0 means it pulls. Broadcast to ``length``.
    modulus : float, default 210e9
        Young's modulus of the rod (Pa).
    rod_yield : float, default 500e6
        Yield stress of the rod (Pa).

    Returns
    -------
    Buckling
        Slenderness, critical load, formula used and safety factor per sample.

    Raises
    ------
    InputError
        A non-positive modulus or yield stress, or a non-positive length.
    """
    if not (modulus > 0.0 and rod_yield > 0.0 and math.isfinite(modulus * rod_yield)):
        raise InputError("the modulus and the yield stress must be positive")
    L = np.atleast_1d(np.asarray(length, dtype=np.float64))
    P = np.broadcast_to(np.asarray(force, dtype=np.float64), L.shape)
    if not np.all(L > 0.0):
        raise InputError("the cylinder lengths must be positive")
    d = cylinder.rod
    area, inertia, radius = math.pi * d**2 / 4.0, math.pi * d**4 / 64.0, d / 4.0
    lam = L / radius
    lam1 = math.sqrt(2.0 * math.pi**2 * modulus / rod_yield)
    euler = math.pi**2 * modulus * inertia / L**2
    johnson = area * rod_yield * (1.0 - rod_yield * lam**2 / (4.0 * math.pi**2 * modulus))
    is_euler = lam >= lam1
    crit = np.where(is_euler, euler, johnson)
    with np.errstate(divide="ignore"):
        safety = np.where(P > 0.0, crit / np.where(P > 0.0, P, 1.0), np.inf)
    return Buckling(
        cylinder.role,
        L,
        np.array(P),
        lam,
        lam1,
        crit,
        np.where(is_euler, "Euler", "Johnson"),
        safety,
    )


def relief_buckling(machine: Machine, hydraulics: Hydraulics | None = None) -> tuple[Buckling, ...]:
    """Each cylinder at its port relief pressure on the bore side, fully extended: the largest
    push it can hold at its longest (the worst case of the cylinder alone)."""
    h = hydraulics_of(machine, hydraulics)
    out = []
    for c in machine.cylinders:
        p = machine.circuits[c.circuit].relief * c.bore_area / c.count
        out.append(buckling(c, c.extended, p, modulus=h.modulus, rod_yield=h.rod_yield))
    return tuple(out)


def pose_buckling(
    machine: Machine,
    lengths: ArrayLike,
    cylinder_force: ArrayLike,
    hydraulics: Hydraulics | None = None,
) -> tuple[Buckling, ...]:
    """Each cylinder's check at poses ``lengths`` (shape (n, 3)) under the forces of all
    ``count`` cylinders ``cylinder_force`` (shape (n, 3), N, > 0 pushing), e.g. those of
    [`tool_forces`][excavkin.excavator.forces.tool_forces] at the rated poses."""
    h = hydraulics_of(machine, hydraulics)
    L = as_lengths(lengths)
    f = np.broadcast_to(np.asarray(cylinder_force, dtype=np.float64), L.shape)
    return tuple(
        buckling(c, L[:, i], f[:, i] / c.count, modulus=h.modulus, rod_yield=h.rod_yield)
        for i, c in enumerate(machine.cylinders)
    )


def hydraulics_of(machine: Machine, hydraulics: Hydraulics | None = None) -> Hydraulics:
    """The given hydraulics, or the machine's own; an error naming the machine if it has none."""
    h = hydraulics if hydraulics is not None else machine.hydraulics
    if h is None:
        raise InputError(
            f"the machine {machine.name!r} has no [hydraulics] table (pump flows and swing): "
            "add one to its machine file"
        )
    return h
