"""A disc cam's lift law: the follower's travel as a periodic function of the cam's turn.

The law is given as a table of (turn, lift) over one turn, from 0 to 2π with the same lift at
both ends, and interpolated by the periodic cubic spline through it (continuous travel, velocity
and acceleration). Its evaluation is written in plain arithmetic on the turn, so that it runs on
arrays and on the dual numbers of the sensitivities alike (the interval is found from the
value; the polynomial carries the derivative).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.errors import InputError

__all__ = ["Law", "LiftLaw", "evaluate", "lift_law"]

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
    """

    knots: np.ndarray
    coef: np.ndarray

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
        c3, c2, c1, c0 = (self.coef[j][k] for j in range(4))
        s = ((c3 * t + c2) * t + c1) * t + c0
        s1 = (3.0 * c3 * t + 2.0 * c2) * t + c1
        s2 = 6.0 * c3 * t + 2.0 * c2
        return s, s1, s2


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
