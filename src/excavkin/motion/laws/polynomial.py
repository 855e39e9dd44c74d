"""Polynomial laws: the cubic, the 3-4-5 and the 4-5-6-7."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from excavkin.arrays import FloatArray
from excavkin.motion.laws.base import MotionLaw, PeakCoefficients, ShapeValues


@dataclass(frozen=True, slots=True)
class CubicLaw(MotionLaw):
    """The paper's cubic law (Pasika & Koruniak, Eqs. (4)–(6)).

    ``f = 3u² − 2u³``, ``f' = 6u(1 − u)``, ``f'' = 6 − 12u``, ``f''' = −12``.
    So ``s = H(3t²/T² − 2t³/T³)``, ``v = 6H/T·(t/T)(1 − t/T)``, ``a = 6H/T²·(1 − 2t/T)``.
    Soft shocks: ``a`` jumps by ``+6H/T²`` at ``t0`` and by ``+6H/T²`` (from ``−6H/T²``
    to 0) at ``t0 + T``. ``C_v = 1.5``, ``C_a = 6``, ``C_j = 12``.
    """

    name: ClassVar[str] = "cubic"

    def _shape(self, u: FloatArray, left: bool = False) -> ShapeValues:
        f0 = u * u * (3.0 - 2.0 * u)
        f1 = 6.0 * u * (1.0 - u)
        f2 = 6.0 - 12.0 * u
        f3 = np.full_like(u, -12.0)
        return f0, f1, f2, f3

    @property
    def coefficients(self) -> PeakCoefficients:
        return PeakCoefficients(1.5, 6.0, 12.0)


@dataclass(frozen=True, slots=True)
class Poly345Law(MotionLaw):
    """3-4-5 polynomial: ``f = 10u³ − 15u⁴ + 6u⁵``.

    ``f' = 30u²(1 − u)²``, ``f'' = 60u(1 − u)(1 − 2u)``, ``f''' = 60 − 360u + 360u²``.
    ``a = 0`` at both ends (no soft shock); jerk is ``60 H/T³`` at the ends.
    ``C_v = 15/8``, ``C_a = 10/√3``, ``C_j = 60``.
    """

    name: ClassVar[str] = "345"

    def _shape(self, u: FloatArray, left: bool = False) -> ShapeValues:
        f0 = u**3 * (10.0 + u * (-15.0 + 6.0 * u))
        f1 = 30.0 * u**2 * (1.0 - u) ** 2
        f2 = 60.0 * u * (1.0 - u) * (1.0 - 2.0 * u)
        f3 = 60.0 + u * (-360.0 + 360.0 * u)
        return f0, f1, f2, f3

    @property
    def coefficients(self) -> PeakCoefficients:
        return PeakCoefficients(15.0 / 8.0, 10.0 / math.sqrt(3.0), 60.0)


@dataclass(frozen=True, slots=True)
class Poly4567Law(MotionLaw):
    """4-5-6-7 polynomial: ``f = 35u⁴ − 84u⁵ + 70u⁶ − 20u⁷``.

    ``f' = 140u³(1 − u)³``, ``f'' = 420u²(1 − u)²(1 − 2u)``,
    ``f''' = 840u(1 − u)(1 − 5u + 5u²)``. ``a = j = 0`` at both ends.
    ``C_v = 35/16``, ``C_a = 84√5/25``, ``C_j = 105/2``.
    """

    name: ClassVar[str] = "4567"

    def _shape(self, u: FloatArray, left: bool = False) -> ShapeValues:
        w = 1.0 - u
        f0 = u**4 * (35.0 + u * (-84.0 + u * (70.0 - 20.0 * u)))
        f1 = 140.0 * u**3 * w**3
        f2 = 420.0 * u**2 * w**2 * (1.0 - 2.0 * u)
        f3 = 840.0 * u * w * (1.0 - 5.0 * u + 5.0 * u * u)
        return f0, f1, f2, f3

    @property
    def coefficients(self) -> PeakCoefficients:
        return PeakCoefficients(35.0 / 16.0, 84.0 * math.sqrt(5.0) / 25.0, 52.5)
