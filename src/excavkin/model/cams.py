"""A disc cam's lift law: the follower's travel as a periodic function of the cam's turn.

The law is given as a table of (turn, lift) over one turn, from 0 to 2π with the same lift at
both ends, and interpolated by the periodic cubic spline through it (continuous travel, velocity
and acceleration). Its evaluation is written in plain arithmetic on the turn, so that it runs on
arrays and on the dual numbers of the sensitivities alike (the interval is found from the
value; the polynomial carries the derivative).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.errors import InputError

__all__ = ["Law", "LiftLaw", "evaluate", "lift_law", "with_lifts"]

#: a lift law: the turn (rad, an array or a dual number) → (s, ds/dθ, d²s/dθ²), periodic in 2π
Law = Callable[[Any], tuple[Any, Any, Any]]

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True, slots=True, eq=False)
class LiftLaw:
    """The periodic cubic spline of a lift table.

    Attributes
    ----------
    knots : ndarray, shape (m + 1,)
        The table's turns, 0 … 2π (rad).
    coef : ndarray, shape (4, m)
        Per interval, the coefficients of ``t³, t², t, 1`` with ``t`` the turn past its knot.
    pieces : tuple of (c3, c2, c1, c0), optional
        The same coefficients where the table's lifts are design parameters (`with_lifts`):
        per interval, each a float, an array of one value per sample or a dual number; None
        (the default) for the table's own, ``coef``.
    """

    knots: np.ndarray
    coef: np.ndarray
    pieces: tuple[tuple[Any, Any, Any, Any], ...] | None = None

    def __call__(self, theta: Any) -> tuple[Any, Any, Any]:
        """The lift and its first and second derivatives with respect to the turn.

        Parameters
        ----------
        theta : float, ndarray or dual number
            The cam's turn from its sketch (rad, any number of turns).

        Returns
        -------
        (s, ds/dθ, d²s/dθ²)
            m, m/rad, m/rad², each shaped as ``theta``.
        """
        value = np.asarray(getattr(theta, "val", theta), dtype=np.float64)
        turns = np.floor(value / TWO_PI)
        u = theta - TWO_PI * turns
        uv = value - TWO_PI * turns
        k = np.clip(np.searchsorted(self.knots, uv, side="right") - 1, 0, self.coef.shape[1] - 1)
        t = u - self.knots[k]
        if self.pieces is None:
            c3, c2, c1, c0 = (self.coef[j][k] for j in range(4))
        else:  # each sample's piece picked from the per-sample (or dual) coefficients
            c3, c2, c1, c0 = self.pieces[0]
            for j, (p3, p2, p1, p0) in enumerate(self.pieces[1:], start=1):
                on = k == j
                c3, c2 = np.where(on, p3, c3), np.where(on, p2, c2)
                c1, c0 = np.where(on, p1, c1), np.where(on, p0, c0)
        s = ((c3 * t + c2) * t + c1) * t + c0
        s1 = (3.0 * c3 * t + 2.0 * c2) * t + c1
        s2 = 6.0 * c3 * t + 2.0 * c2
        return s, s1, s2

    def take(self, index: Any) -> LiftLaw:
        """The law with its per-sample coefficients taken at ``index``.

        Parameters
        ----------
        index : slice or ndarray of int
            The samples taken.

        Returns
        -------
        LiftLaw
            ``self`` where no coefficient is per sample.
        """
        if self.pieces is None or not any(np.ndim(c) for p in self.pieces for c in p):
            return self
        pieces = tuple(tuple(c[index] if np.ndim(c) else c for c in p) for p in self.pieces)
        return LiftLaw(self.knots, self.coef, pieces)  # type: ignore[arg-type]

    def varies(self) -> bool:
        """Whether a coefficient holds one value per sample (or is a dual number)."""
        return self.pieces is not None and any(
            np.ndim(c) or hasattr(c, "tan") for p in self.pieces for c in p
        )


def _basis(knots: np.ndarray) -> np.ndarray:
    """The periodic spline's coefficients per unit lift at each row: shape (4, m, m), the
    coefficients being linear in the lifts (row m is row 0); made once per table's turns."""
    return _basis_of(tuple(float(k) for k in knots))


@functools.lru_cache(maxsize=32)
def _basis_of(turns: tuple[float, ...]) -> np.ndarray:
    from scipy.interpolate import CubicSpline

    knots = np.array(turns)
    m = knots.size - 1
    out = np.empty((4, m, m))
    for i in range(m):
        unit = np.zeros(m + 1)
        unit[i] = 1.0
        if i == 0:
            unit[m] = 1.0
        out[:, :, i] = CubicSpline(knots, unit, bc_type="periodic").c
    out.flags.writeable = False  # (shared by every law of these turns)
    return out


def with_lifts(law: LiftLaw, lifts: tuple[Any, ...]) -> LiftLaw:
    """A table's law with its lifts replaced (design parameters): the same knots, and each
    coefficient the same linear function of the lifts as the spline's.

    Parameters
    ----------
    law : LiftLaw
        The table's law (`lift_law`).
    lifts : tuple
        The lift at each row but the last (which repeats the first): floats, arrays of one
        value per sample, or dual numbers.

    Returns
    -------
    LiftLaw
        With ``pieces`` (its ``coef`` the table's own, for its shape).
    """
    basis = _basis(law.knots)
    m = basis.shape[1]
    pieces = []
    for k in range(m):
        piece = []
        for j in range(4):
            acc: Any = 0.0
            for i in range(m):
                b = float(basis[j, k, i])
                if b != 0.0:
                    acc = lifts[i] * b + acc
            piece.append(acc)
        pieces.append(tuple(piece))
    return LiftLaw(law.knots, law.coef, tuple(pieces))  # type: ignore[arg-type]


def lift_law(table: tuple[tuple[float, float], ...] | Law) -> Law:
    """The lift law of a table (the periodic cubic spline through it) or of a function.

    Parameters
    ----------
    table : tuple of (float, float), or callable
        (turn in rad, lift in m), the turns from 0 to 2π strictly increasing, the last lift
        equal to the first (checked by `validate`); or a function of the turn returning
        ``(s, ds/dθ, d²s/dθ²)`` in m, periodic in 2π, written in NumPy operations so that it
        takes arrays (and the dual numbers of the force sensitivities).

    Returns
    -------
    callable
        A `LiftLaw`, or the function itself.
    """
    from scipy.interpolate import CubicSpline

    if callable(table):
        return table
    x = np.array([a for a, _ in table], dtype=np.float64)
    y = np.array([s for _, s in table], dtype=np.float64)
    spline = CubicSpline(x, y, bc_type="periodic")
    return LiftLaw(x, np.asarray(spline.c, dtype=np.float64))


def evaluate(law: Law, theta: Any, name: str) -> tuple[Any, Any, Any]:
    """A lift law at the turn ``theta``; a function law refuses a dual number.

    A table's spline carries the derivatives of a dual turn itself; a function's would need its
    third derivative (the tangent of ``d²s/dθ²``), which it does not give.

    Parameters
    ----------
    law : callable
        From `lift_law`.
    theta : float, ndarray or dual number
        The cam's turn (rad).
    name : str
        The cam's name, for the message.

    Returns
    -------
    (s, ds/dθ, d²s/dθ²)

    Raises
    ------
    InputError
        ``theta`` is a dual number and the law a function.
    """
    if not isinstance(law, LiftLaw) and hasattr(theta, "tan"):
        raise InputError(
            f"cam {name!r}: its lift law is a function, so its sensitivities are not "
            "available (they need its third derivative); give the law as a table [turn, lift]"
        )
    return law(theta)
