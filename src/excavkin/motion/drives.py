"""Drives used by the seed papers: a crank at constant speed and a rope winch.

Both return a `MotionState` (generalised coordinate and its
first three time derivatives), so they can feed a kinematic solver like any motion law.

Conventions
-----------
* Crank (MO-100 hammer, Eremyants & Raiymbekova): ``φ(t) = φ0 + ω t``, ``ω`` constant
  (CCW positive, rad/s), for all ``t`` (no start/stop). The hammer runs at
  ``ω1 = 31.416 s⁻¹`` (5 Hz, period 0.2 s).
* Rope winch (EO-4112 drag rope, Maksimov §3.1)::

      v_rope = ω_motor · R_drum / (i · a_p)

  ``i``: gear ratio motor → drum (``ω_drum = ω_motor / i``), ``a_p``: pulley-block
  multiplicity. ``v_rope > 0`` means the winch **hauls in** (rope winds onto the drum), so the
  working rope length decreases: ``v_rope = −dL/dt``, ``L(t) = L0 − ∫ v_rope dt``.

::

        drum (R_drum)         pulley block (a_p)
      .--.   i                ___
     ( () )<==== motor ω      |  |====> F ... E   L = |FE| shrinks when hauling in
      '--'                    '--'
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from excavkin.arrays import FloatArray
from excavkin.motion.laws import MotionLaw, MotionState

__all__ = ["ConstantSpeedCrank", "RopeWinch", "rope_speed"]


@dataclass(frozen=True, slots=True)
class ConstantSpeedCrank:
    """A crank turning at constant angular speed.

    Parameters
    ----------
    omega : float
        Angular speed ``ω`` [rad/s], CCW positive.
    phi0 : float
        Angle at ``t = 0`` [rad].

    Examples
    --------
    >>> crank = ConstantSpeedCrank(31.416)
    >>> round(crank.period, 6)
    0.2
    """

    omega: float
    phi0: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.omega) and math.isfinite(self.phi0)):
            raise ValueError(
                f"ConstantSpeedCrank: omega and phi0 must be finite, got {self.omega!r}, "
                f"{self.phi0!r}"
            )

    @property
    def period(self) -> float:
        """``2π/|ω|`` [s] (``inf`` if ``ω = 0``)."""
        return math.inf if self.omega == 0.0 else 2.0 * math.pi / abs(self.omega)

    def angle(self, t: npt.ArrayLike) -> FloatArray:
        """``φ0 + ω t`` [rad], shape (n,) for ``t`` of shape (n,)."""
        return self.phi0 + self.omega * np.asarray(t, dtype=np.float64)

    def evaluate(self, t: npt.ArrayLike) -> MotionState:
        """Angle, rate, acceleration and jerk at times ``t``.

        Parameters
        ----------
        t : array_like, shape (n,)
            Times [s].

        Returns
        -------
        MotionState
            ``s = φ0 + ω t`` [rad], ``v = ω`` [rad/s], ``a = 0``, ``j = 0``; shape (n,).
        """
        tt = np.asarray(t, dtype=np.float64)
        zero = np.zeros_like(tt)
        return MotionState(self.phi0 + self.omega * tt, np.full_like(tt, self.omega), zero, zero)


def rope_speed(
    motor_speed: npt.ArrayLike,
    drum_radius: float,
    gear_ratio: float,
    pulley_multiplicity: float,
) -> FloatArray:
    """Rope speed ``v = ω_motor R_drum / (i a_p)`` (Maksimov §3.1), vectorised.

    Parameters
    ----------
    motor_speed : array_like, shape (n,)
        Motor angular speed ``ω_motor`` [rad/s]; positive hauls in.
    drum_radius : float
        Drum radius ``R_drum`` [m].
    gear_ratio : float
        ``i = ω_motor / ω_drum``.
    pulley_multiplicity : float
        Pulley-block multiplicity ``a_p`` (1 without a block).

    Returns
    -------
    ndarray, shape (n,)
        Rope speed [m/s], positive when the rope winds onto the drum (``= −dL/dt``).
    """
    return (
        np.asarray(motor_speed, dtype=np.float64) * drum_radius / (gear_ratio * pulley_multiplicity)
    )


@dataclass(frozen=True, slots=True)
class RopeWinch:
    """Winch drive of a rope: motor → gear ``i`` → drum ``R`` → pulley block ``a_p``.

    Parameters
    ----------
    motor_speed : float or None
        Constant motor speed ``ω_motor`` [rad/s] (positive hauls in), or ``None`` when
        ``motor_law`` is given.
    drum_radius : float
        ``R_drum > 0`` [m].
    gear_ratio : float
        ``i > 0``, motor speed / drum speed.
    pulley_multiplicity : float
        ``a_p >= 1``.
    initial_length : float, keyword-only
        Rope length ``L0`` at ``start`` [m]. Default 0 (then ``rope_length`` is ``−hauled``).
    start : float, keyword-only
        Time [s] at which the hauled length is 0 (constant-speed case). Default 0.
    motor_law : MotionLaw or None, keyword-only
        Law of the motor **angle** [rad]; its velocity is the motor speed ramp (for instance a
        `TrapezoidalLaw` gives ramp-up, constant speed,
        ramp-down). Exclusive with ``motor_speed``; see `ramped`.

    Notes
    -----
    The drive is linear with ratio ``k = R_drum / (i a_p)`` [m/rad], so the hauled-in rope
    length is ``k θ_motor`` and all its derivatives scale by ``k``. Rope length
    ``L(t) = L0 − hauled(t)`` decreases while hauling in (``v_rope > 0``), following
    Maksimov's ``v_тк = −d(FE)/dt``. With a constant ``motor_speed`` the motion holds for all
    ``t`` (``hauled = v_rope (t − start)``, negative before ``start``).

    Examples
    --------
    >>> w = RopeWinch(100.0, 0.5, 25.0, 2.0, initial_length=12.0)
    >>> w.rope_speed
    1.0
    >>> float(w.rope_length([3.0])[0])
    9.0
    """

    motor_speed: float | None
    drum_radius: float
    gear_ratio: float
    pulley_multiplicity: float = 1.0
    initial_length: float = field(default=0.0, kw_only=True)
    start: float = field(default=0.0, kw_only=True)
    motor_law: MotionLaw | None = field(default=None, kw_only=True)

    def __post_init__(self) -> None:
        if (self.motor_speed is None) == (self.motor_law is None):
            raise ValueError("RopeWinch: give exactly one of motor_speed and motor_law")
        if self.motor_speed is not None and not math.isfinite(self.motor_speed):
            raise ValueError(f"RopeWinch: motor_speed must be finite, got {self.motor_speed!r}")
        if not (math.isfinite(self.drum_radius) and self.drum_radius > 0.0):
            raise ValueError(f"RopeWinch: drum_radius must be > 0, got {self.drum_radius!r}")
        if not (math.isfinite(self.gear_ratio) and self.gear_ratio > 0.0):
            raise ValueError(f"RopeWinch: gear_ratio must be > 0, got {self.gear_ratio!r}")
        if not (math.isfinite(self.pulley_multiplicity) and self.pulley_multiplicity >= 1.0):
            raise ValueError(
                f"RopeWinch: pulley_multiplicity must be >= 1, got {self.pulley_multiplicity!r}"
            )

    @classmethod
    def ramped(
        cls,
        motor_law: MotionLaw,
        drum_radius: float,
        gear_ratio: float,
        pulley_multiplicity: float = 1.0,
        *,
        initial_length: float = 0.0,
    ) -> RopeWinch:
        """Winch whose motor angle follows ``motor_law`` (stroke in rad)."""
        return cls(
            None,
            drum_radius,
            gear_ratio,
            pulley_multiplicity,
            initial_length=initial_length,
            start=motor_law.start,
            motor_law=motor_law,
        )

    @property
    def ratio(self) -> float:
        """Transmission ratio ``k = R_drum / (i a_p)`` [m/rad]."""
        return self.drum_radius / (self.gear_ratio * self.pulley_multiplicity)

    @property
    def rope_speed(self) -> float:
        """Constant rope speed ``ω_motor R_drum / (i a_p)`` [m/s] (hauling in > 0).

        Raises
        ------
        ValueError
            For a ramped winch; use ``evaluate(t).v``.
        """
        if self.motor_speed is None:
            raise ValueError("RopeWinch.rope_speed: the winch is ramped; use evaluate(t).v")
        return self.motor_speed * self.ratio

    def evaluate(self, t: npt.ArrayLike) -> MotionState:
        """Hauled-in rope length and its derivatives at times ``t``.

        Parameters
        ----------
        t : array_like, shape (n,)
            Times [s].

        Returns
        -------
        MotionState
            ``s``: hauled-in length [m] (``L0 − L``), ``v``: rope speed ``v_rope`` [m/s],
            ``a`` [m/s²], ``j`` [m/s³]; each shape (n,).
        """
        tt = np.asarray(t, dtype=np.float64)
        k = self.ratio
        if self.motor_law is not None:
            m = self.motor_law.evaluate(tt)
            return MotionState(k * m.s, k * m.v, k * m.a, k * m.j)
        v = self.rope_speed
        zero = np.zeros_like(tt)
        return MotionState(v * (tt - self.start), np.full_like(tt, v), zero, zero.copy())

    def rope_length(self, t: npt.ArrayLike) -> FloatArray:
        """Rope length ``L(t) = L0 − hauled(t)`` [m], shape (n,); decreases when hauling in."""
        return self.initial_length - self.evaluate(t).s
