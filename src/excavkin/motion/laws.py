"""Rest-to-rest motion laws for a driver moving a stroke ``H`` in a time ``T``.

Every law is written in normalised form, ``u = (t - t0) / T`` in ``[0, 1]``::

    s(t) = H * f(u)          v(t) = H / T * f'(u)
    a(t) = H / T**2 * f''(u) j(t) = H / T**3 * f'''(u)

with ``f(0) = 0``, ``f(1) = 1`` and ``f'(0) = f'(1) = 0``. The peak coefficients
``C_v = max|f'|``, ``C_a = max|f''|`` and ``C_j = max|f'''|`` are exact (see
[`MotionLaw.coefficients`][excavkin.motion.laws.MotionLaw.coefficients] and
``docs/motion-laws.md``).

Conventions
-----------
* SI units: ``H`` in m (or rad for an angular driver), ``T`` and ``t`` in s.
* Outside ``[t0, t0 + T]`` a law holds its end values: ``s = 0`` before, ``s = H`` after,
  ``v = a = j = 0``. The closed interval ``[t0, t0 + T]`` uses the formulas, so the values
  *at* the ends show the soft shocks: for the cubic law ``a(t0) = 6 H / T**2`` while
  ``a`` just before ``t0`` is 0.
* Jerk is the analytic derivative of ``a`` inside each piece. Where ``a`` jumps (the ends of
  the cubic and harmonic laws, the corners of the trapezoidal law) the Dirac part of the jerk
  is **not** represented; the jumps are reported by
  [`MotionLaw.acceleration_jumps`][excavkin.motion.laws.MotionLaw.acceleration_jumps] and
  by the values of ``a`` at the ends.
* Piecewise laws use left-closed pieces ``[u_k, u_k+1)``; the last piece is closed. At an
  interior breakpoint the value of the right piece is returned.

::

    s ^                      ____ H
      |                 _.-''
      |             _.-'
      |         _.-'
      |____..-''
      +--------+------------------+--> t
      0       t0               t0 + T
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any, ClassVar, NamedTuple

import numpy as np
import numpy.typing as npt

__all__ = [
    "LAW_NAMES",
    "AccelerationJump",
    "CubicLaw",
    "CycloidalLaw",
    "Dwell",
    "HarmonicLaw",
    "ModifiedSineLaw",
    "ModifiedTrapezoidLaw",
    "MotionLaw",
    "MotionState",
    "PeakCoefficients",
    "Poly345Law",
    "Poly4567Law",
    "Profile",
    "SCurveLaw",
    "Segment",
    "TrapezoidalLaw",
    "dwell",
    "get_law",
]

FloatArray = npt.NDArray[np.float64]
_Shape = tuple[FloatArray, FloatArray, FloatArray, FloatArray]

_PI = math.pi


class MotionState(NamedTuple):
    """Displacement and its first three time derivatives of a driver.

    Attributes
    ----------
    s : ndarray, shape (n,)
        Displacement [m or rad].
    v : ndarray, shape (n,)
        Velocity [m/s or rad/s].
    a : ndarray, shape (n,)
        Acceleration [m/s² or rad/s²].
    j : ndarray, shape (n,)
        Jerk [m/s³ or rad/s³] (analytic inside pieces; Dirac parts at jumps of ``a`` are
        not represented).
    """

    s: FloatArray
    v: FloatArray
    a: FloatArray
    j: FloatArray


class PeakCoefficients(NamedTuple):
    """Dimensionless peaks of a normalised law.

    ``max|v| = c_v * |H| / T``, ``max|a| = c_a * |H| / T**2``, ``max|j| = c_j * |H| / T**3``
    (jerk inside the pieces; Dirac parts at jumps of ``a`` are excluded).
    """

    c_v: float
    c_a: float
    c_j: float


class AccelerationJump(NamedTuple):
    """A finite jump of acceleration (a *soft shock*).

    Attributes
    ----------
    time : float
        Where the jump happens [s].
    where : str
        Human-readable location ("start", "end", "u = 0.25", "join 1 (...)").
    a_before, a_after : float
        One-sided accelerations just before and just after ``time``.
    """

    time: float
    where: str
    a_before: float
    a_after: float

    @property
    def jump(self) -> float:
        """``a_after - a_before``."""
        return self.a_after - self.a_before


def _piece_index(u: FloatArray, inner: tuple[float, ...], left: bool) -> npt.NDArray[np.intp]:
    """Index of the piece each ``u`` falls in (left-closed pieces unless ``left``)."""
    side: Any = "left" if left else "right"
    return np.searchsorted(np.asarray(inner, dtype=np.float64), u, side=side)


@dataclass(frozen=True, slots=True)
class MotionLaw:
    """Base of the rest-to-rest motion laws.

    Parameters
    ----------
    stroke : float
        Signed stroke ``H`` [m or rad]. A negative stroke is a return.
    duration : float
        Duration ``T > 0`` [s].
    start : float, keyword-only
        Start time ``t0`` [s], default 0.

    Notes
    -----
    Subclasses implement ``_shape(u, left)`` returning ``f, f', f'', f'''`` on ``u`` in
    ``[0, 1]`` and may declare interior breakpoints in ``_inner_breakpoints``.
    """

    stroke: float
    duration: float
    start: float = field(default=0.0, kw_only=True)

    name: ClassVar[str] = "law"

    def __post_init__(self) -> None:
        if not math.isfinite(self.stroke):
            raise ValueError(f"{type(self).__name__}: stroke must be finite, got {self.stroke!r}")
        if not (math.isfinite(self.duration) and self.duration > 0.0):
            raise ValueError(
                f"{type(self).__name__}: duration must be finite and > 0, got {self.duration!r}"
            )
        if not math.isfinite(self.start):
            raise ValueError(f"{type(self).__name__}: start must be finite, got {self.start!r}")
        self._validate()

    def _validate(self) -> None:
        """Check law-specific parameters (hook for subclasses)."""

    # -- to be provided by subclasses -------------------------------------------------------
    def _shape(self, u: FloatArray, left: bool = False) -> _Shape:
        raise NotImplementedError

    @property
    def _inner_breakpoints(self) -> tuple[float, ...]:
        return ()

    @property
    def coefficients(self) -> PeakCoefficients:
        """Exact peak coefficients ``C_v, C_a, C_j`` of the normalised law."""
        raise NotImplementedError

    # -- common API --------------------------------------------------------------------------
    @property
    def end(self) -> float:
        """End time ``t0 + T`` [s]."""
        return self.start + self.duration

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Normalised piece boundaries ``u`` including 0 and 1, sorted."""
        return (0.0, *self._inner_breakpoints, 1.0)

    @property
    def peak_velocity(self) -> float:
        """``C_v |H| / T`` [m/s]."""
        return self.coefficients.c_v * abs(self.stroke) / self.duration

    @property
    def peak_acceleration(self) -> float:
        """``C_a |H| / T²`` [m/s²]."""
        return self.coefficients.c_a * abs(self.stroke) / self.duration**2

    @property
    def peak_jerk(self) -> float:
        """``C_j |H| / T³`` [m/s³] (inside pieces)."""
        return self.coefficients.c_j * abs(self.stroke) / self.duration**3

    def normalised(self, u: npt.ArrayLike) -> _Shape:
        """Normalised law ``f(u), f'(u), f''(u), f'''(u)`` for ``u`` in ``[0, 1]``.

        Parameters
        ----------
        u : array_like, shape (n,)
            Normalised time; values are clipped to ``[0, 1]``.

        Returns
        -------
        tuple of 4 ndarray, each shape (n,)
        """
        uu = np.clip(np.asarray(u, dtype=np.float64), 0.0, 1.0)
        return self._shape(uu)

    def evaluate(self, t: npt.ArrayLike) -> MotionState:
        """Displacement, velocity, acceleration and jerk at times ``t``.

        Parameters
        ----------
        t : array_like, shape (n,)
            Times [s]. Any shape is accepted and preserved.

        Returns
        -------
        MotionState
            ``s, v, a, j``, each of shape (n,). Before ``start``: ``s = 0``; after
            ``start + duration``: ``s = H``; outside the interval ``v = a = j = 0``.
        """
        tt = np.asarray(t, dtype=np.float64)
        h, T = self.stroke, self.duration
        before = tt < self.start
        after = tt > self.end
        inside = ~(before | after)
        u = np.clip((tt - self.start) / T, 0.0, 1.0)
        f0, f1, f2, f3 = self._shape(u)
        zero = np.zeros_like(tt)
        s = np.where(before, 0.0, np.where(after, h, h * f0))
        v = np.where(inside, (h / T) * f1, zero)
        a = np.where(inside, (h / T**2) * f2, zero)
        j = np.where(inside, (h / T**3) * f3, zero)
        return MotionState(s, v, a, j)

    def acceleration_jumps(self, rtol: float = 1e-9) -> tuple[AccelerationJump, ...]:
        """Jumps of acceleration (soft shocks), the ends included (rest outside).

        Parameters
        ----------
        rtol : float
            A jump is reported when ``|Δa| > rtol * max(C_a, 1) * |H| / T²``.

        Returns
        -------
        tuple of AccelerationJump
            In time order; empty for laws without soft shocks.
        """
        edges = np.unique(np.asarray(self.breakpoints, dtype=np.float64))
        a_left = self._shape(edges, left=True)[2].copy()
        a_right = self._shape(edges, left=False)[2].copy()
        a_left[0] = 0.0
        a_right[-1] = 0.0
        scale = abs(self.stroke) / self.duration**2
        tol = rtol * max(self.coefficients.c_a, 1.0) * scale
        out: list[AccelerationJump] = []
        for k, ub in enumerate(edges):
            before = float(a_left[k]) * scale * math.copysign(1.0, self.stroke)
            after = float(a_right[k]) * scale * math.copysign(1.0, self.stroke)
            if abs(after - before) > tol:
                where = "start" if k == 0 else "end" if k == len(edges) - 1 else f"u = {ub:.6g}"
                out.append(
                    AccelerationJump(self.start + float(ub) * self.duration, where, before, after)
                )
        return tuple(out)


# --------------------------------------------------------------------------------------------
# Single-formula laws
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class CubicLaw(MotionLaw):
    """The paper's cubic law (Pasika & Koruniak, Eqs. (4)–(6)).

    ``f = 3u² − 2u³``, ``f' = 6u(1 − u)``, ``f'' = 6 − 12u``, ``f''' = −12``.
    So ``s = H(3t²/T² − 2t³/T³)``, ``v = 6H/T·(t/T)(1 − t/T)``, ``a = 6H/T²·(1 − 2t/T)``.
    Soft shocks: ``a`` jumps by ``+6H/T²`` at ``t0`` and by ``+6H/T²`` (from ``−6H/T²``
    to 0) at ``t0 + T``. ``C_v = 1.5``, ``C_a = 6``, ``C_j = 12``.
    """

    name: ClassVar[str] = "cubic"

    def _shape(self, u: FloatArray, left: bool = False) -> _Shape:
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

    def _shape(self, u: FloatArray, left: bool = False) -> _Shape:
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

    def _shape(self, u: FloatArray, left: bool = False) -> _Shape:
        w = 1.0 - u
        f0 = u**4 * (35.0 + u * (-84.0 + u * (70.0 - 20.0 * u)))
        f1 = 140.0 * u**3 * w**3
        f2 = 420.0 * u**2 * w**2 * (1.0 - 2.0 * u)
        f3 = 840.0 * u * w * (1.0 - 5.0 * u + 5.0 * u * u)
        return f0, f1, f2, f3

    @property
    def coefficients(self) -> PeakCoefficients:
        return PeakCoefficients(35.0 / 16.0, 84.0 * math.sqrt(5.0) / 25.0, 52.5)


@dataclass(frozen=True, slots=True)
class CycloidalLaw(MotionLaw):
    """Cycloidal law: ``f = u − sin(2πu)/(2π)``.

    ``f' = 1 − cos 2πu``, ``f'' = 2π sin 2πu``, ``f''' = 4π² cos 2πu``.
    ``a = 0`` at both ends; ``C_v = 2``, ``C_a = 2π``, ``C_j = 4π²``.
    """

    name: ClassVar[str] = "cycloidal"

    def _shape(self, u: FloatArray, left: bool = False) -> _Shape:
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

    def _shape(self, u: FloatArray, left: bool = False) -> _Shape:
        x = _PI * u
        f0 = 0.5 * (1.0 - np.cos(x))
        f1 = 0.5 * _PI * np.sin(x)
        f2 = 0.5 * _PI**2 * np.cos(x)
        f3 = -0.5 * _PI**3 * np.sin(x)
        return f0, f1, f2, f3

    @property
    def coefficients(self) -> PeakCoefficients:
        return PeakCoefficients(0.5 * _PI, 0.5 * _PI**2, 0.5 * _PI**3)


@dataclass(frozen=True, slots=True)
class Dwell(MotionLaw):
    """A dwell: ``s = 0`` over ``[t0, t0 + T]``; ``stroke`` must be 0 (see `dwell`)."""

    name: ClassVar[str] = "dwell"

    def _validate(self) -> None:
        if self.stroke != 0.0:
            raise ValueError(f"Dwell: stroke must be 0, got {self.stroke!r}")

    def _shape(self, u: FloatArray, left: bool = False) -> _Shape:
        z = np.zeros_like(u)
        return z, z.copy(), z.copy(), z.copy()

    @property
    def coefficients(self) -> PeakCoefficients:
        return PeakCoefficients(0.0, 0.0, 0.0)


def dwell(duration: float, *, start: float = 0.0) -> Dwell:
    """A `Dwell` of the given ``duration`` [s] starting at ``start`` [s]."""
    return Dwell(0.0, duration, start=start)


# --------------------------------------------------------------------------------------------
# Piecewise laws
# --------------------------------------------------------------------------------------------

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

    def _shape(self, u: FloatArray, left: bool = False) -> _Shape:
        k = _piece_index(u, self._inner_breakpoints, left)
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

    def _shape(self, u: FloatArray, left: bool = False) -> _Shape:
        k = _piece_index(u, self._inner_breakpoints, left)
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


@dataclass(frozen=True, slots=True)
class TrapezoidalLaw(MotionLaw):
    """Trapezoidal velocity (constant acceleration, cruise, constant deceleration).

    With ``τ = accel_fraction`` (``0 < τ ≤ 1/2``), ``V = 1/(1 − τ)`` and ``A = V/τ``::

        [0, τ]        f = A u²/2                 f' = A u      f'' = A
        [τ, 1 − τ]    f = A τ²/2 + V (u − τ)      f' = V        f'' = 0
        [1 − τ, 1]    f = 1 − A (1 − u)²/2        f' = A(1 − u) f'' = −A

    ``f''' = 0`` inside the pieces. Soft shocks (jumps of ``a``) at **four** points:
    ``u = 0, τ, 1 − τ, 1`` (three when ``τ = 1/2``: the two middle jumps merge into one
    jump of ``−2A``). ``C_v = V``, ``C_a = A``, ``C_j = 0``.

    Parameters
    ----------
    stroke, duration, start
        See [`MotionLaw`][excavkin.motion.laws.MotionLaw].
    accel_fraction : float
        Fraction of ``T`` spent accelerating (and, equally, decelerating). Default 1/3.
    """

    accel_fraction: float = 1.0 / 3.0

    name: ClassVar[str] = "trapezoidal"

    def _validate(self) -> None:
        if not (0.0 < self.accel_fraction <= 0.5):
            raise ValueError(
                f"TrapezoidalLaw: accel_fraction must be in (0, 0.5], got {self.accel_fraction!r}"
            )

    @classmethod
    def from_max_velocity(
        cls, stroke: float, duration: float, v_max: float, *, start: float = 0.0
    ) -> TrapezoidalLaw:
        """Trapezoidal law whose cruise speed is ``v_max`` [m/s].

        Requires ``|H|/T < v_max ≤ 2|H|/T``; then ``τ = 1 − |H|/(v_max T)``.
        """
        if not (math.isfinite(duration) and duration > 0.0):
            raise ValueError(f"TrapezoidalLaw: duration must be > 0, got {duration!r}")
        mean = abs(stroke) / duration
        if not (mean < v_max <= 2.0 * mean):
            raise ValueError(
                f"TrapezoidalLaw: v_max = {v_max!r} must satisfy |H|/T = {mean!r} < v_max "
                f"<= 2|H|/T = {2.0 * mean!r}"
            )
        return cls(stroke, duration, start=start, accel_fraction=1.0 - mean / v_max)

    @property
    def _inner_breakpoints(self) -> tuple[float, ...]:
        return (self.accel_fraction, 1.0 - self.accel_fraction)

    def _shape(self, u: FloatArray, left: bool = False) -> _Shape:
        k = _piece_index(u, self._inner_breakpoints, left)
        tau = self.accel_fraction
        V = 1.0 / (1.0 - tau)
        A = V / tau
        w = 1.0 - u
        conds = [k == 0, k == 1, k == 2]
        f0 = np.select(
            conds, [0.5 * A * u * u, 0.5 * A * tau * tau + V * (u - tau), 1.0 - 0.5 * A * w * w]
        )
        f1 = np.select(conds, [A * u, np.full_like(u, V), A * w])
        f2 = np.select(conds, [np.full_like(u, A), np.zeros_like(u), np.full_like(u, -A)])
        return f0, f1, f2, np.zeros_like(u)

    @property
    def coefficients(self) -> PeakCoefficients:
        V = 1.0 / (1.0 - self.accel_fraction)
        return PeakCoefficients(V, V / self.accel_fraction, 0.0)


@dataclass(frozen=True, slots=True)
class SCurveLaw(MotionLaw):
    """Jerk-limited S-curve (seven phases of constant jerk).

    Phases (durations) ``Tj, Tc, Tj, Tv, Tj, Tc, Tj`` with jerks ``+J, 0, −J, 0, −J, 0, +J``;
    the acceleration phase lasts ``Ta = 2Tj + Tc``. Normalised by ``T``:
    ``Ta = α T`` (``accel_fraction``), ``Tj = β Ta`` (``jerk_fraction``), and::

        V = 1/(1 − α),   A = V/(α(1 − β)),   J = A/(α β)      (in units of H/T^k)

    ``a`` and ``v`` are continuous, ``a = 0`` at the ends (no soft shock); the jerk jumps.
    ``C_v = V``, ``C_a = A``, ``C_j = J``. ``Tc = 0`` when ``β = 1/2`` (``a_max`` not
    reached); ``Tv = 0`` when ``α = 1/2`` (``v_max`` not reached).

    Use `from_limits` to get the time-optimal law for limits ``v_max, a_max, j_max``
    (then ``T`` is an output).

    Parameters
    ----------
    stroke, duration, start
        See [`MotionLaw`][excavkin.motion.laws.MotionLaw].
    accel_fraction : float
        ``α = Ta/T`` in ``(0, 1/2]``. Default 1/2 (no cruise).
    jerk_fraction : float
        ``β = Tj/Ta`` in ``(0, 1/2]``. Default 1/4.
    """

    accel_fraction: float = 0.5
    jerk_fraction: float = 0.25

    name: ClassVar[str] = "s-curve"

    def _validate(self) -> None:
        if not (0.0 < self.accel_fraction <= 0.5):
            raise ValueError(
                f"SCurveLaw: accel_fraction must be in (0, 0.5], got {self.accel_fraction!r}"
            )
        if not (0.0 < self.jerk_fraction <= 0.5):
            raise ValueError(
                f"SCurveLaw: jerk_fraction must be in (0, 0.5], got {self.jerk_fraction!r}"
            )

    @classmethod
    def from_limits(
        cls,
        stroke: float,
        v_max: float,
        a_max: float,
        j_max: float,
        *,
        start: float = 0.0,
    ) -> SCurveLaw:
        """Time-optimal rest-to-rest S-curve for the limits ``v_max, a_max, j_max``.

        Parameters
        ----------
        stroke : float
            Signed stroke ``H`` [m], ``H != 0``.
        v_max, a_max, j_max : float
            Positive limits [m/s, m/s², m/s³].
        start : float
            Start time [s].

        Returns
        -------
        SCurveLaw
            With ``duration`` the minimum time ``T``.

        Notes
        -----
        With ``D = |H|``:

        1. ``a_max`` reachable under ``v_max`` iff ``v_max j_max >= a_max²``; then
           ``Tj = a_max/j_max``, ``Tc = v_max/a_max − Tj``; else ``Tj = sqrt(v_max/j_max)``,
           ``Tc = 0``. ``Ta = 2Tj + Tc``, ``Tv = D/v_max − Ta``.
        2. If ``Tv < 0`` the cruise speed is not reached, ``Tv = 0`` and the peak speed ``v``
           solves ``D = v Ta(v)``: with ``a_max`` reached (``D >= 2 a_max³/j_max²``),
           ``v = (a/2)(sqrt(a²/j² + 4D/a) − a/j)``, ``Tj = a/j``, ``Tc = v/a − a/j``;
           otherwise ``Tj = (D/(2 j))^(1/3)``, ``Tc = 0``.
        3. ``T = 2 Ta + Tv``.
        """
        for nm, val in (("v_max", v_max), ("a_max", a_max), ("j_max", j_max)):
            if not (math.isfinite(val) and val > 0.0):
                raise ValueError(f"SCurveLaw.from_limits: {nm} must be finite and > 0, got {val!r}")
        if not (math.isfinite(stroke) and stroke != 0.0):
            raise ValueError(
                f"SCurveLaw.from_limits: stroke must be finite and != 0, got {stroke!r}"
            )
        dist = abs(stroke)
        v, a, j = v_max, a_max, j_max
        if v * j >= a * a:
            tj, tc = a / j, v / a - a / j
        else:
            tj, tc = math.sqrt(v / j), 0.0
        ta = 2.0 * tj + tc
        tv = dist / v - ta
        if tv < 0.0:
            tv = 0.0
            if dist >= 2.0 * a**3 / j**2:
                vp = 0.5 * a * (math.sqrt(a * a / (j * j) + 4.0 * dist / a) - a / j)
                tj, tc = a / j, max(vp / a - a / j, 0.0)
            else:
                tj, tc = (dist / (2.0 * j)) ** (1.0 / 3.0), 0.0
            ta = 2.0 * tj + tc
        T = 2.0 * ta + tv
        return cls(
            stroke,
            T,
            start=start,
            accel_fraction=min(ta / T, 0.5),
            jerk_fraction=min(tj / ta, 0.5),
        )

    def _phases(self) -> tuple[FloatArray, FloatArray]:
        """Normalised phase start times (8,) and start states (7, 4): f, f', f'', f'''."""
        al, be = self.accel_fraction, self.jerk_fraction
        V = 1.0 / (1.0 - al)
        A = V / (al * (1.0 - be))
        J = A / (al * be)
        tj = al * be
        tc = al - 2.0 * tj
        tv = 1.0 - 2.0 * al
        dur = (tj, tc, tj, tv, tj, tc, tj)
        jerk = (J, 0.0, -J, 0.0, -J, 0.0, J)
        starts = np.zeros(8)
        states = np.zeros((7, 4))
        s = v = a = 0.0
        for k in range(7):  # seven phases, not samples
            states[k] = (s, v, a, jerk[k])
            d = dur[k]
            s, v, a = (
                s + v * d + a * d * d / 2.0 + jerk[k] * d**3 / 6.0,
                v + a * d + jerk[k] * d * d / 2.0,
                a + jerk[k] * d,
            )
            starts[k + 1] = starts[k] + d
        starts[-1] = 1.0
        return starts, states

    @property
    def _inner_breakpoints(self) -> tuple[float, ...]:
        starts, _ = self._phases()
        return tuple(float(x) for x in starts[1:-1])

    def _shape(self, u: FloatArray, left: bool = False) -> _Shape:
        starts, states = self._phases()
        # By symmetry f(u) = 1 - f(1 - u); f' is even, f'' odd and f''' even about u = 1/2.
        # The second half is evaluated mirrored, so that f(1) = 1 and f'(1) = f''(1) = 0
        # hold exactly. Mirroring swaps the side of the one-sided limits at breakpoints.
        mirror = u > 0.5
        um = np.where(mirror, 1.0 - u, u)
        inner = tuple(float(x) for x in starts[1:-1])
        k = np.where(mirror ^ left, _piece_index(um, inner, True), _piece_index(um, inner, False))
        tau = um - starts[k]
        s0, v0, a0, j0 = states[k, 0], states[k, 1], states[k, 2], states[k, 3]
        g0 = s0 + tau * (v0 + tau * (a0 / 2.0 + tau * j0 / 6.0))
        g1 = v0 + tau * (a0 + tau * j0 / 2.0)
        g2 = a0 + tau * j0
        f0 = np.where(mirror, 1.0 - g0, g0)
        f2 = np.where(mirror, -g2, g2)
        return f0, g1, f2, j0.astype(np.float64, copy=True)

    @property
    def coefficients(self) -> PeakCoefficients:
        al, be = self.accel_fraction, self.jerk_fraction
        V = 1.0 / (1.0 - al)
        A = V / (al * (1.0 - be))
        return PeakCoefficients(V, A, A / (al * be))

    @property
    def phase_durations(self) -> tuple[float, ...]:
        """The seven phase durations ``Tj, Tc, Tj, Tv, Tj, Tc, Tj`` [s]."""
        starts, _ = self._phases()
        return tuple(float(x) * self.duration for x in np.diff(starts))


# --------------------------------------------------------------------------------------------
# Profiles made of segments
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Segment:
    """One segment of a `Profile`.

    Parameters
    ----------
    law : MotionLaw
        The law; its ``start`` is the absolute start time of the segment [s].
    offset : float
        Position of the driver at the start of the segment [m or rad]; the segment moves
        from ``offset`` to ``offset + law.stroke``.
    """

    law: MotionLaw
    offset: float = 0.0


@dataclass(frozen=True, slots=True)
class Profile:
    """A motion profile: consecutive segments (rise, dwell, return, ...).

    Parameters
    ----------
    segments : tuple of Segment
        Time-ordered, contiguous segments (segment ``k`` starts where ``k − 1`` ends).
    rtol : float
        Relative tolerance of the join checks (see Notes). Default 1e-9.

    Raises
    ------
    ValueError
        If there are no segments, if segments overlap or leave a gap in time, or if ``s`` or
        ``v`` jump at a join. The message names the join, the quantity and the jump.

    Notes
    -----
    At join ``k`` (end of segment ``k − 1`` = start of segment ``k``) the one-sided values
    are ``s⁻ = offset[k−1] + s_{k−1}(end)``, ``s⁺ = offset[k] + s_k(start)``, and likewise
    for ``v``. Continuity requires ``|s⁺ − s⁻| <= rtol · max(|offset|, |H|)`` and
    ``|v⁺ − v⁻| <= rtol · max(|H|/T)`` over the segments. Jumps of ``a`` (soft shocks) are
    allowed and listed by `acceleration_jumps`. Before the first segment the profile
    holds its initial position, after the last its final one (``v = a = j = 0``). At a join
    the values of the later segment are returned.

    Examples
    --------
    >>> from excavkin.motion import CycloidalLaw, Profile, dwell
    >>> p = Profile.from_laws([CycloidalLaw(0.5, 2.0), dwell(1.0), CycloidalLaw(-0.5, 2.0)])
    >>> float(p.evaluate([3.0]).s[0])
    0.5
    """

    segments: tuple[Segment, ...]
    rtol: float = 1e-9

    def __post_init__(self) -> None:
        segs = tuple(self.segments)
        object.__setattr__(self, "segments", segs)
        if not segs:
            raise ValueError("Profile: at least one segment is required")
        scale_s = max(max(abs(sg.offset), abs(sg.law.stroke)) for sg in segs)
        scale_v = max(abs(sg.law.stroke) / sg.law.duration for sg in segs)
        scale_t = max(max(abs(sg.law.start), abs(sg.law.end)) for sg in segs)
        for k in range(1, len(segs)):
            prev, cur = segs[k - 1], segs[k]
            label = self._join_label(k)
            dt = cur.law.start - prev.law.end
            if abs(dt) > self.rtol * scale_t:
                kind = "gap" if dt > 0 else "overlap"
                raise ValueError(
                    f"Profile {label}: segment {k} starts at t = {cur.law.start!r} s but segment "
                    f"{k - 1} ends at t = {prev.law.end!r} s ({kind} of {abs(dt)!r} s); "
                    "insert a dwell or fix the start times"
                )
            left = prev.law.evaluate(np.array([prev.law.end]))
            right = cur.law.evaluate(np.array([cur.law.start]))
            s_l = prev.offset + float(left.s[0])
            s_r = cur.offset + float(right.s[0])
            if abs(s_r - s_l) > self.rtol * scale_s:
                raise ValueError(
                    f"Profile {label} at t = {cur.law.start!r} s: displacement s jumps by "
                    f"{s_r - s_l:.6g} (from {s_l:.9g} to {s_r:.9g})"
                )
            v_l, v_r = float(left.v[0]), float(right.v[0])
            if abs(v_r - v_l) > self.rtol * scale_v:
                raise ValueError(
                    f"Profile {label} at t = {cur.law.start!r} s: velocity v jumps by "
                    f"{v_r - v_l:.6g} (from {v_l:.9g} to {v_r:.9g}); a hard shock"
                )

    def _join_label(self, k: int) -> str:
        a, b = self.segments[k - 1].law, self.segments[k].law
        return f"join {k} (segment {k - 1} '{a.name}' -> segment {k} '{b.name}')"

    @classmethod
    def from_laws(
        cls,
        laws: Sequence[MotionLaw],
        *,
        s0: float = 0.0,
        t0: float = 0.0,
        rtol: float = 1e-9,
    ) -> Profile:
        """Chain laws one after the other, each starting where the previous one ended.

        The laws' own ``start`` is replaced; positions accumulate from ``s0``, so a return
        is simply a law with a negative stroke.

        Parameters
        ----------
        laws : sequence of MotionLaw
            In time order.
        s0 : float
            Initial position [m or rad].
        t0 : float
            Start time of the first segment [s].
        rtol : float
            See `Profile`.
        """
        segs: list[Segment] = []
        t, s = t0, s0
        for law in laws:
            moved = replace(law, start=t)
            segs.append(Segment(moved, s))
            t = moved.end
            s = s + law.stroke
        return cls(tuple(segs), rtol=rtol)

    @property
    def start(self) -> float:
        """Start time of the first segment [s]."""
        return self.segments[0].law.start

    @property
    def end(self) -> float:
        """End time of the last segment [s]."""
        return self.segments[-1].law.end

    @property
    def duration(self) -> float:
        """``end − start`` [s]."""
        return self.end - self.start

    @property
    def joins(self) -> tuple[float, ...]:
        """Times of the joins between segments [s], shape (n_segments − 1,)."""
        return tuple(sg.law.start for sg in self.segments[1:])

    def evaluate(self, t: npt.ArrayLike) -> MotionState:
        """Displacement, velocity, acceleration and jerk of the profile at times ``t``.

        Parameters
        ----------
        t : array_like, shape (n,)
            Times [s]. Any shape is accepted and preserved.

        Returns
        -------
        MotionState
            ``s, v, a, j``, each of shape (n,).
        """
        tt = np.asarray(t, dtype=np.float64)
        starts = np.array([sg.law.start for sg in self.segments[1:]], dtype=np.float64)
        idx = np.searchsorted(starts, tt, side="right")
        s = np.empty_like(tt)
        v = np.empty_like(tt)
        a = np.empty_like(tt)
        j = np.empty_like(tt)
        for k, sg in enumerate(self.segments):  # loop over segments, not samples
            m = idx == k
            if not np.any(m):
                continue
            st = sg.law.evaluate(tt[m])
            s[m] = sg.offset + st.s
            v[m] = st.v
            a[m] = st.a
            j[m] = st.j
        return MotionState(s, v, a, j)

    def acceleration_jumps(self, rtol: float | None = None) -> tuple[AccelerationJump, ...]:
        """Jumps of acceleration at the joins, at the start and at the end (rest outside).

        Jumps inside a segment (e.g. the corners of a trapezoidal law) are listed by that
        law's [`MotionLaw.acceleration_jumps`][excavkin.motion.laws.MotionLaw.acceleration_jumps],
        not here.

        Parameters
        ----------
        rtol : float, optional
            A jump is reported when ``|Δa| > rtol · max(|H|/T²)`` over the segments.
            Defaults to the profile's ``rtol``.

        Returns
        -------
        tuple of AccelerationJump
            In time order.
        """
        tol = (self.rtol if rtol is None else rtol) * max(
            abs(sg.law.stroke) / sg.law.duration**2 for sg in self.segments
        )
        a_end = [float(sg.law.evaluate(np.array([sg.law.end])).a[0]) for sg in self.segments]
        a_start = [float(sg.law.evaluate(np.array([sg.law.start])).a[0]) for sg in self.segments]
        cand = [AccelerationJump(self.start, "start", 0.0, a_start[0])]
        for k in range(1, len(self.segments)):
            cand.append(
                AccelerationJump(
                    self.segments[k].law.start, self._join_label(k), a_end[k - 1], a_start[k]
                )
            )
        cand.append(AccelerationJump(self.end, "end", a_end[-1], 0.0))
        return tuple(c for c in cand if abs(c.jump) > tol)


# --------------------------------------------------------------------------------------------
# Registry
# --------------------------------------------------------------------------------------------

_LAWS: dict[str, type[MotionLaw]] = {
    "cubic": CubicLaw,
    "345": Poly345Law,
    "4567": Poly4567Law,
    "cycloidal": CycloidalLaw,
    "harmonic": HarmonicLaw,
    "modified-trapezoid": ModifiedTrapezoidLaw,
    "modified-sine": ModifiedSineLaw,
    "trapezoidal": TrapezoidalLaw,
    "s-curve": SCurveLaw,
}

LAW_NAMES: tuple[str, ...] = tuple(_LAWS)
"""Names accepted by [`get_law`][excavkin.motion.laws.get_law]."""


def _shape_params(cls: type[MotionLaw]) -> set[str]:
    return {f.name for f in fields(cls)} - {"stroke", "duration"}


def get_law(name: str, stroke: float, duration: float | None, **params: float) -> MotionLaw:
    """Build a motion law by name.

    Parameters
    ----------
    name : str
        One of `LAW_NAMES`: ``"cubic"``, ``"345"``, ``"4567"``, ``"cycloidal"``,
        ``"harmonic"``, ``"modified-trapezoid"``, ``"modified-sine"``, ``"trapezoidal"``,
        ``"s-curve"``.
    stroke : float
        Signed stroke ``H`` [m or rad].
    duration : float or None
        Duration ``T`` [s]. Must be ``None`` for ``"s-curve"`` built from limits (``T`` is
        then an output) and a number otherwise.
    **params : float
        ``start`` for every law; ``accel_fraction`` or ``v_max`` for ``"trapezoidal"``;
        ``accel_fraction`` and ``jerk_fraction``, or ``v_max``, ``a_max`` and ``j_max``
        (all three) for ``"s-curve"``.

    Returns
    -------
    MotionLaw

    Raises
    ------
    ValueError
        Unknown ``name`` (the message lists the known names), a missing or superfluous
        ``duration``, or invalid values.
    TypeError
        Unknown or conflicting parameters.

    Examples
    --------
    >>> get_law("cycloidal", 0.8, 2.0, start=1.0).peak_velocity
    0.8
    """
    try:
        cls = _LAWS[name]
    except KeyError:
        raise ValueError(
            f"unknown motion law {name!r}; known laws: {', '.join(LAW_NAMES)}"
        ) from None
    allowed = _shape_params(cls)
    alt: set[str] = set()
    if cls is TrapezoidalLaw:
        alt = {"v_max"}
    elif cls is SCurveLaw:
        alt = {"v_max", "a_max", "j_max"}
    unknown = set(params) - allowed - alt
    if unknown:
        raise TypeError(
            f"motion law {name!r} got unknown parameter(s) {sorted(unknown)}; "
            f"allowed: {sorted(allowed | alt)}"
        )
    start = float(params.get("start", 0.0))
    used_alt = set(params) & alt
    if used_alt and set(params) & (allowed - {"start"}):
        raise TypeError(
            f"motion law {name!r}: give either {sorted(allowed - {'start'})} or "
            f"{sorted(alt)}, not both"
        )
    if cls is SCurveLaw and used_alt:
        if used_alt != alt:
            raise TypeError(
                f"motion law 's-curve' needs all of {sorted(alt)}, got {sorted(used_alt)}"
            )
        if duration is not None:
            raise ValueError(
                "motion law 's-curve' with limits v_max, a_max, j_max: the duration is an "
                "output, pass duration=None"
            )
        return SCurveLaw.from_limits(
            stroke, params["v_max"], params["a_max"], params["j_max"], start=start
        )
    if duration is None:
        raise ValueError(f"motion law {name!r} needs a duration")
    if cls is TrapezoidalLaw and used_alt:
        return TrapezoidalLaw.from_max_velocity(stroke, duration, params["v_max"], start=start)
    return cls(stroke, duration, **params)
