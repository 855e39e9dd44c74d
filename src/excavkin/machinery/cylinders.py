"""Hydraulic cylinders and the circuits that feed them (SI records shared by every family).

A machine's cylinders come in the order of its family's roles (an excavator's
``("boom", "arm", "bucket")``); arrays of their pin-to-pin lengths have shape ``(n, k)`` with k
the number of roles. A cylinder force > 0 pushes (extends), DESIGN.md §5.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError


@dataclass(frozen=True, slots=True)
class Circuit:
    """Pressures of one hydraulic circuit (Pa).

    Attributes
    ----------
    name : str
    working : float
        Working (main relief) pressure: what the pump can push into the working cylinder.
    relief : float
        Port (overload) relief pressure: the most a holding cylinder can resist before it
        yields (ISO 6015 "maximum relief circuit hydraulic pressure").
    """

    name: str
    working: float
    relief: float


@dataclass(frozen=True, slots=True)
class Cylinder:
    """A hydraulic cylinder (or ``count`` identical ones acting together), SI units.

    Attributes
    ----------
    role : str
        Its role among those its family declares (an excavator's ``"boom"``, ``"arm"``,
        ``"bucket"``).
    driver : str
        The linear driver of the general model it is.
    retracted, stroke : float
        Pin-to-pin length fully retracted, and stroke (m).
    bore, rod : float
        Piston and rod diameters (m).
    circuit : str
        Name of its `Circuit`.
    count : int
        Identical cylinders in parallel (two boom cylinders on most crawler excavators).
    dig : {"extend", "retract"}
        Which motion digs (crowds the stick, curls the bucket) — extension on a backhoe.
    mass : float
        Mass of all ``count`` cylinders with their oil (kg), lumped half at each end pin
        (its centre of mass at mid-length); 0 where the model's bodies already carry it.
    """

    role: str
    driver: str
    retracted: float
    stroke: float
    bore: float
    rod: float
    circuit: str
    count: int = 1
    dig: Literal["extend", "retract"] = "extend"
    mass: float = 0.0

    @property
    def extended(self) -> float:
        """Pin-to-pin length fully extended (m)."""
        return self.retracted + self.stroke

    @property
    def bore_area(self) -> float:
        """Piston-side area of all ``count`` cylinders (m²)."""
        return self.count * math.pi / 4.0 * self.bore**2

    @property
    def annulus_area(self) -> float:
        """Rod-side (annulus) area of all ``count`` cylinders (m²)."""
        return self.count * math.pi / 4.0 * (self.bore**2 - self.rod**2)

    def force_limits(self, pressure: float | F) -> tuple[float | F, float | F]:
        """Largest pull (≤ 0) and push (≥ 0) at ``pressure``: ``(−p·A_rod, p·A_bore)`` (N).

        Parameters
        ----------
        pressure : float or ndarray
            The circuit's pressure (Pa).

        Returns
        -------
        pull, push : float or ndarray
            The annulus side's pull (≤ 0) and the bore side's push (≥ 0), N.
        """
        return -pressure * self.annulus_area, pressure * self.bore_area


def cylinder_lengths(lengths: ArrayLike, roles: Sequence[str]) -> F:
    """Cylinder lengths as an array of shape (n, k), one column per role; refuses other shapes.

    Parameters
    ----------
    lengths : array_like, shape (n, k)
        Pin-to-pin lengths (m), in the order of ``roles``.
    roles : sequence of str
        The family's roles, k of them (named in the message).

    Returns
    -------
    ndarray, shape (n, k)

    Raises
    ------
    InputError
        Another shape.
    """
    L = np.asarray(lengths, dtype=np.float64)
    k = len(roles)
    if L.ndim != 2 or L.shape[1] != k:
        raise InputError(
            f"cylinder lengths must have shape (n, {k}) ({', '.join(roles)}), got {L.shape}"
        )
    return L
