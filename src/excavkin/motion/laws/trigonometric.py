"""Trigonometric laws: the cycloidal and the harmonic (simple harmonic motion)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from excavkin.arrays import FloatArray
from excavkin.motion.laws.base import MotionLaw, PeakCoefficients, ShapeValues

_PI = math.pi


@dataclass(frozen=True, slots=True)
class CycloidalLaw(MotionLaw):
    """Cycloidal law: ``f = u − sin(2πu)/(2π)``.

    ``f' = 1 − cos 2πu``, ``f'' = 2π sin 2πu``, ``f''' = 4π² cos 2πu``.
    ``a = 0`` at both ends; ``C_v = 2``, ``C_a = 2π``, ``C_j = 4π²``.
    """

    name: ClassVar[str] = "cycloidal"

    def _shape(self, u: FloatArray, left: bool = False) -> ShapeValues:
        x = 2.0 * _PI * u
        f0 = u - np.sin(x) / (2.0 * _PI)
        f1 = 1.0 - np.cos(x)
        f2 = 2.0 * _PI * np.sin(x)
        f3 = 4.0 * _PI**2 * np.cos(x)
        return f0, f1, f2, f3

    @property
    def coefficients(self) -> PeakCoefficients:
        return PeakCoefficients(2.0, 2.0 * _PI, 4.0 * _PI**2)


@dataclass(frozen=True, slots=True)
class HarmonicLaw(MotionLaw):
    """Simple harmonic law: ``f = (1 − cos πu)/2``.

    ``f' = (π/2) sin πu``, ``f'' = (π²/2) cos πu``, ``f''' = −(π³/2) sin πu``.
    Soft shocks: ``a = ±π²/2 · H/T²`` at the ends. ``C_v = π/2``, ``C_a = π²/2``,
    ``C_j = π³/2``.
    """

    name: ClassVar[str] = "harmonic"

    def _shape(self, u: FloatArray, left: bool = False) -> ShapeValues:
        x = _PI * u
        f0 = 0.5 * (1.0 - np.cos(x))
        f1 = 0.5 * _PI * np.sin(x)
        f2 = 0.5 * _PI**2 * np.cos(x)
        f3 = -0.5 * _PI**3 * np.sin(x)
        return f0, f1, f2, f3

    @property
    def coefficients(self) -> PeakCoefficients:
        return PeakCoefficients(0.5 * _PI, 0.5 * _PI**2, 0.5 * _PI**3)
