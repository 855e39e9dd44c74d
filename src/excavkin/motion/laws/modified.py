"""The modified cam laws, built of sine and constant pieces of acceleration: the modified
trapezoid and the modified sine.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from excavkin.arrays import FloatArray
from excavkin.motion.laws.base import MotionLaw, PeakCoefficients, ShapeValues, piece_index

_PI = math.pi
_MT_C = 1.0 / (2.0 + _PI)  # modified trapezoid: A = 8π/(2 + π)
_MS_D = 1.0 / (4.0 + _PI)  # modified sine:      A = 4π²/(4 + π)


@dataclass(frozen=True, slots=True)
class ModifiedTrapezoidLaw(MotionLaw):
    """Modified trapezoid: trapezoidal acceleration with sine-shaped ramps.

    Acceleration with ``A = 8π/(2 + π)`` (``c = 1/(2 + π)``)::

        [0, 1/8]    A sin 4πu          [1/8, 3/8]  A
        [3/8, 5/8]  −A sin 4πu         [5/8, 7/8]  −A
        [7/8, 1]    A sin 4πu

    Displacement per piece::

        [0, 1/8]    c (4πu − sin 4πu) / (2π)
        [1/8, 3/8]  c (4πu² − (π − 2)u + π/16 − 1/(2π))
        [3/8, 5/8]  c ((2 + 2π)u + sin(4πu)/(2π) − π/2)
        [5/8, 7/8]  c (−4πu² + (2 + 7π)u − 33π/16 + 1/(2π))
        [7/8, 1]    c ((4πu − sin 4πu)/(2π) + π)

    ``a = 0`` at the ends; jerk continuous inside. ``C_v = 2``, ``C_a = 8π/(2 + π) ≈ 4.8881``,
    ``C_j = 32π²/(2 + π) ≈ 61.43``.
    """

    name: ClassVar[str] = "modified-trapezoid"

    @property
    def _inner_breakpoints(self) -> tuple[float, ...]:
        return (0.125, 0.375, 0.625, 0.875)

    def _shape(self, u: FloatArray, left: bool = False) -> ShapeValues:
        k = piece_index(u, self._inner_breakpoints, left)
        c, p = _MT_C, _PI
        x = 4.0 * p * u
        sx, cx = np.sin(x), np.cos(x)
        conds = [k == 0, k == 1, k == 2, k == 3, k == 4]
        f0 = np.select(
            conds,
            [
                c * (x - sx) / (2.0 * p),
                c * (4.0 * p * u * u - (p - 2.0) * u + p / 16.0 - 1.0 / (2.0 * p)),
                c * ((2.0 + 2.0 * p) * u + sx / (2.0 * p) - p / 2.0),
                c * (-4.0 * p * u * u + (2.0 + 7.0 * p) * u - 33.0 * p / 16.0 + 1.0 / (2.0 * p)),
                c * ((x - sx) / (2.0 * p) + p),
            ],
        )
        f1 = np.select(
            conds,
            [
                2.0 * c * (1.0 - cx),
                c * (8.0 * p * u - p + 2.0),
                c * (2.0 * cx + 2.0 + 2.0 * p),
                c * (-8.0 * p * u + 2.0 + 7.0 * p),
                2.0 * c * (1.0 - cx),
            ],
        )
        amp = 8.0 * p * c
        f2 = np.select(
            conds,
            [amp * sx, np.full_like(u, amp), -amp * sx, np.full_like(u, -amp), amp * sx],
        )
        jmp = 32.0 * p * p * c
        zero = np.zeros_like(u)
        f3 = np.select(conds, [jmp * cx, zero, -jmp * cx, zero, jmp * cx])
        return f0, f1, f2, f3

    @property
    def coefficients(self) -> PeakCoefficients:
        return PeakCoefficients(2.0, 8.0 * _PI * _MT_C, 32.0 * _PI**2 * _MT_C)


@dataclass(frozen=True, slots=True)
class ModifiedSineLaw(MotionLaw):
    """Modified sine: a quarter sine of period 1/2 at each end, a long sine in the middle.

    Acceleration with ``A = 4π²/(4 + π)`` (``d = 1/(4 + π)``, ``y = 4πu/3 + π/3``)::

        [0, 1/8]    A sin 4πu      [1/8, 7/8]  A sin y      [7/8, 1]  A sin 4πu

    Displacement per piece::

        [0, 1/8]    d (πu − sin(4πu)/4)
        [1/8, 7/8]  d (πu − (9/4) sin y + 2)
        [7/8, 1]    d (πu − sin(4πu)/4 + 4)

    ``a = 0`` at the ends. ``C_v = 4π/(4 + π) ≈ 1.7596``, ``C_a = 4π²/(4 + π) ≈ 5.5280``,
    ``C_j = 16π³/(4 + π) ≈ 69.47`` (at the ends).
    """

    name: ClassVar[str] = "modified-sine"

    @property
    def _inner_breakpoints(self) -> tuple[float, ...]:
        return (0.125, 0.875)

    def _shape(self, u: FloatArray, left: bool = False) -> ShapeValues:
        k = piece_index(u, self._inner_breakpoints, left)
        d, p = _MS_D, _PI
        x = 4.0 * p * u
        y = x / 3.0 + p / 3.0
        sx, cx, sy, cy = np.sin(x), np.cos(x), np.sin(y), np.cos(y)
        conds = [k == 0, k == 1, k == 2]
        f0 = np.select(
            conds,
            [
                d * (p * u - 0.25 * sx),
                d * (p * u - 2.25 * sy + 2.0),
                d * (p * u - 0.25 * sx + 4.0),
            ],
        )
        f1 = np.select(conds, [p * d * (1.0 - cx), p * d * (1.0 - 3.0 * cy), p * d * (1.0 - cx)])
        amp = 4.0 * p * p * d
        f2 = np.select(conds, [amp * sx, amp * sy, amp * sx])
        jmp = 16.0 * p**3 * d
        f3 = np.select(conds, [jmp * cx, (jmp / 3.0) * cy, jmp * cx])
        return f0, f1, f2, f3

    @property
    def coefficients(self) -> PeakCoefficients:
        return PeakCoefficients(4.0 * _PI * _MS_D, 4.0 * _PI**2 * _MS_D, 16.0 * _PI**3 * _MS_D)
