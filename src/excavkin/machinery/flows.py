r"""Flows and speeds of a machine's cylinders: stroke times from the pumps' flows, hydraulic power.

**Speeds.** Each function (a cylinder role) moved alone receives the summed flow ``Q`` of every
pump that feeds it (the pumps' confluence); with ``count`` cylinders acting together the areas
are those of all of them (`Cylinder.bore_area`, `Cylinder.annulus_area`)::

    v_extend = Q / A_bore        v_retract = Q / A_annulus        t = stroke / v

Leakage, valve pressure drops, pump regulation (power limiting at high pressure) and
cushioning are left out: the speeds are the no-load, full-flow speeds of spec sheets.

**Power.** Along a motion the power of cylinder c is ``f_c·L̇_c`` with ``f_c`` the cylinder force
of the kinetostatics ([`Mechanism.forces`][excavkin.mechanism.Mechanism.forces]) and ``L̇_c`` its
rate from the kinematics. With
the outlet side drained, the inlet pressure is ``p = f/A_bore`` extending and ``−f/A_annulus``
retracting, the inlet flow ``Q = A·|L̇|``, and the pump's hydraulic power ``p·Q = f·L̇``. A
negative ``p`` means an overrunning load: the load drives the cylinder and the outlet (meter-out)
throttle carries it.

The pumps, and the roles a family's pumps feed, are the records of `excavkin.machinery.pumps`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.machinery.cylinders import Cylinder, cylinder_lengths
from excavkin.machinery.machine import HydraulicMachine, MovingMachine
from excavkin.machinery.pumps import Hydraulics


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
    """Rod speed of ``cylinder`` (all ``count`` of them together) fed ``flow``.

    Parameters
    ----------
    cylinder : Cylinder
    flow : float or ndarray
        Flow into the cylinders (m³/s).
    direction : {"extend", "retract"}
        ``Q/A_bore`` extending, ``Q/A_annulus`` retracting.

    Returns
    -------
    ndarray
        Rod speed (m/s), the shape of ``flow``.
    """
    area = cylinder.bore_area if direction == "extend" else cylinder.annulus_area
    return np.asarray(flow, dtype=np.float64) / area


def strokes(machine: HydraulicMachine, hydraulics: Hydraulics | None = None) -> tuple[Stroke, ...]:
    """Speeds and full-stroke times of each cylinder role, each moved alone.

    Parameters
    ----------
    machine : HydraulicMachine
        The machine (an excavator's boom, arm and bucket).
    hydraulics : Hydraulics, optional
        Pump flows and swing to use instead of the machine's own ``[hydraulics]``.

    Returns
    -------
    tuple of Stroke
        One per role, in the machine's order, fed the flow of every pump that feeds it.

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
class Power:
    """Hydraulic power along a motion of n samples (per function, k of them; SI).

    Attributes
    ----------
    force : ndarray, shape (n, k)
        Cylinder forces of the kinetostatics (N, > 0 pushing), all ``count`` cylinders together.
    rate : ndarray, shape (n, k)
        Cylinder length rates (m/s).
    power : ndarray, shape (n, k)
        ``force·rate`` (W).
    pressure : ndarray, shape (n, k)
        Inlet pressure with the outlet drained (Pa): ``f/A_bore`` extending, ``−f/A_annulus``
        retracting; negative for an overrunning load. 0 where the cylinder stands still.
    flow : ndarray, shape (n, k)
        Inlet flow ``A·|rate|`` (m³/s).
    pump_power : ndarray, shape (n, k)
        ``pressure·flow`` (W), equal to ``power``.
    total : ndarray, shape (n,)
        Sum of ``power`` over the functions (W).
    """

    force: F
    rate: F
    power: F
    pressure: F
    flow: F
    pump_power: F
    total: F


def motion_power(
    machine: MovingMachine, lengths: ArrayLike, rates: ArrayLike, *, gravity: bool = True
) -> Power:
    """Hydraulic power of the cylinders along a motion, from the engine's kinematics and
    kinetostatics (the machine's weight and the inertia of the motion, no soil force).

    Parameters
    ----------
    machine : MovingMachine
        An excavator's [`Machine`][excavkin.excavator.machine.Machine], say.
    lengths, rates : array_like, shape (n, k)
        Cylinder lengths (m) and their rates (m/s), one column per role; accelerations are
        taken as zero.
    gravity : bool
        Include the machine's weight (its ``weight_loads()``).

    Returns
    -------
    Power
    """
    L = cylinder_lengths(lengths, machine.roles)
    R = np.broadcast_to(np.asarray(rates, dtype=np.float64), L.shape)
    res = machine.solve(L, R)
    loads = machine.weight_loads() if gravity else []
    fr = machine.mechanism.forces(res, loads)
    force = np.stack([fr.force(c.driver) for c in machine.cylinders], axis=1)
    return power_of(machine, force, R)


def power_of(machine: HydraulicMachine, force: ArrayLike, rates: ArrayLike) -> Power:
    """`Power` from cylinder forces and rates.

    Parameters
    ----------
    machine : HydraulicMachine
        Its cylinders' areas.
    force : array_like, shape (n, k)
        Cylinder forces (N, > 0 pushing), all ``count`` cylinders of a role together.
    rates : array_like, shape (n, k)
        Cylinder length rates (m/s).

    Returns
    -------
    Power
    """
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


def hydraulics_of(machine: HydraulicMachine, hydraulics: Hydraulics | None = None) -> Hydraulics:
    """The given hydraulics, or the machine's own.

    Parameters
    ----------
    machine : HydraulicMachine
    hydraulics : Hydraulics, optional

    Returns
    -------
    Hydraulics

    Raises
    ------
    InputError
        Naming the machine, where neither is given.
    """
    h = hydraulics if hydraulics is not None else machine.hydraulics
    if h is None:
        raise InputError(
            f"the machine {machine.name!r} has no [hydraulics] table (pump flows and swing): "
            "add one to its machine file"
        )
    return h
