"""The base of every motion law: [`MotionLaw`][excavkin.motion.laws.base.MotionLaw], the state it
returns, its peak
coefficients and its acceleration jumps.

A law is a frozen dataclass whose ``_shape`` gives the normalised shape ``f(u)`` and its first
three derivatives; [`MotionLaw`][excavkin.motion.laws.base.MotionLaw] scales them to a stroke and a
duration, holds the end
values outside ``[t0, t0 + T]`` and finds the jumps of acceleration at the breakpoints.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, ClassVar, NamedTuple

import numpy as np
import numpy.typing as npt

from excavkin.arrays import FloatArray

__all__ = [
    "AccelerationJump",
    "MotionLaw",
    "MotionState",
    "PeakCoefficients",
    "ShapeValues",
    "piece_index",
]

#: the normalised shape and its first three derivatives at ``u``: ``(f, f', f'', f''')``
ShapeValues = tuple[FloatArray, FloatArray, FloatArray, FloatArray]


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


def piece_index(u: FloatArray, inner: tuple[float, ...], left: bool) -> npt.NDArray[np.intp]:
    """Index of the piece each ``u`` falls in (left-closed pieces unless ``left``).

    Parameters
    ----------
    u : ndarray
        Normalised times in [0, 1].
    inner : tuple of float
        The law's interior breakpoints, increasing.
    left : bool
        Whether pieces are right-closed (the limit from the left at a breakpoint).

    Returns
    -------
    ndarray of intp, the shape of ``u``
    """
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
    def _shape(self, u: FloatArray, left: bool = False) -> ShapeValues:
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

    def normalised(self, u: npt.ArrayLike) -> ShapeValues:
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
