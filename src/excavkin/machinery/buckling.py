r"""Buckling of hydraulic cylinders: Euler and Johnson columns.

Each cylinder is taken as a pinned–pinned column (K = 1) of its pin-to-pin length
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

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.machinery.cylinders import Cylinder, cylinder_lengths
from excavkin.machinery.flows import hydraulics_of
from excavkin.machinery.machine import HydraulicMachine
from excavkin.machinery.pumps import ROD_YIELD, STEEL_E, Hydraulics


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


def relief_buckling(
    machine: HydraulicMachine, hydraulics: Hydraulics | None = None
) -> tuple[Buckling, ...]:
    """Each cylinder at its port relief pressure on the bore side, fully extended: the largest
    push it can hold at its longest (the worst case of the cylinder alone).

    Parameters
    ----------
    machine : HydraulicMachine
    hydraulics : Hydraulics, optional
        The rod material to use instead of the machine's own.

    Returns
    -------
    tuple of Buckling
        One per cylinder role, one sample each.
    """
    h = hydraulics_of(machine, hydraulics)
    out = []
    for c in machine.cylinders:
        p = machine.circuits[c.circuit].relief * c.bore_area / c.count
        out.append(buckling(c, c.extended, p, modulus=h.modulus, rod_yield=h.rod_yield))
    return tuple(out)


def pose_buckling(
    machine: HydraulicMachine,
    lengths: ArrayLike,
    cylinder_force: ArrayLike,
    hydraulics: Hydraulics | None = None,
) -> tuple[Buckling, ...]:
    """Each cylinder's check at poses ``lengths`` under the forces of all ``count`` cylinders
    ``cylinder_force``, e.g. those of [`tool_forces`][excavkin.excavator.forces.tool_forces]
    at the rated poses.

    Parameters
    ----------
    machine : HydraulicMachine
    lengths : array_like, shape (n, k)
        Cylinder lengths (m), one column per role.
    cylinder_force : array_like, shape (n, k)
        Forces of all ``count`` cylinders of each role (N, > 0 pushing).
    hydraulics : Hydraulics, optional
        The rod material to use instead of the machine's own.

    Returns
    -------
    tuple of Buckling
        One per cylinder role, n samples each.
    """
    h = hydraulics_of(machine, hydraulics)
    L = cylinder_lengths(lengths, machine.roles)
    f = np.broadcast_to(np.asarray(cylinder_force, dtype=np.float64), L.shape)
    return tuple(
        buckling(c, L[:, i], f[:, i] / c.count, modulus=h.modulus, rod_yield=h.rod_yield)
        for i, c in enumerate(machine.cylinders)
    )
