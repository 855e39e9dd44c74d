"""Laws given by limits: the trapezoidal velocity law (acceleration limited) and the S-curve
(jerk limited, built from a duration and fractions or from the limits themselves).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from excavkin.arrays import FloatArray
from excavkin.motion.laws.base import MotionLaw, PeakCoefficients, ShapeValues, piece_index


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
        See [`MotionLaw`][excavkin.motion.laws.base.MotionLaw].
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

    def _shape(self, u: FloatArray, left: bool = False) -> ShapeValues:
        k = piece_index(u, self._inner_breakpoints, left)
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
        See [`MotionLaw`][excavkin.motion.laws.base.MotionLaw].
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

    def _shape(self, u: FloatArray, left: bool = False) -> ShapeValues:
        starts, states = self._phases()
        # By symmetry f(u) = 1 - f(1 - u); f' is even, f'' odd and f''' even about u = 1/2.
        # The second half is evaluated mirrored, so that f(1) = 1 and f'(1) = f''(1) = 0
        # hold exactly. Mirroring swaps the side of the one-sided limits at breakpoints.
        mirror = u > 0.5
        um = np.where(mirror, 1.0 - u, u)
        inner = tuple(float(x) for x in starts[1:-1])
        k = np.where(mirror ^ left, piece_index(um, inner, True), piece_index(um, inner, False))
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
