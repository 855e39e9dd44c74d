"""A machine's masses as points: each moving body's centre of mass and half of each cylinder's
mass at either end pin, each a fixed linear combination of the model's points, so that their
positions (and derivatives) at a batch of poses are one ``einsum`` over the engine's."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.machinery.cylinders import Cylinder

if TYPE_CHECKING:
    from excavkin.mechanism import Mechanism


@dataclass(frozen=True, slots=True)
class MassPoints:
    """A machine's masses as points, each a fixed linear combination of the model's points.

    Attributes
    ----------
    names : tuple of str
        A body's name, or ``"<cylinder driver>@<pin>"`` for half a cylinder's mass.
    mass : ndarray, shape (k,)
        kg.
    coef : ndarray, shape (k, 2, n_points, 2)
        ``position[k, a] = Σ coef[k, a, p, b]·point[p, b]``.
    """

    names: tuple[str, ...]
    mass: F
    coef: F

    def locate(self, points: F) -> F:
        """Positions (or their derivatives) of the mass points from those of the model's points.

        Parameters
        ----------
        points : ndarray, shape (n, n_points, 2) or (n, n_points, 2, m)

        Returns
        -------
        ndarray, shape (n, k, 2) or (n, k, 2, m)
        """
        return np.asarray(np.einsum("kapb,npb...->nka...", self.coef, points))


def mass_points(
    mechanism: Mechanism, cylinders: Sequence[Cylinder], ends: Sequence[tuple[str, str]]
) -> MassPoints:
    """The masses of a mechanism's bodies and of its cylinders as points.

    Parameters
    ----------
    mechanism : Mechanism
        Its bodies' masses and centres of mass are the engine's own (`MassProperties`).
    cylinders : sequence of Cylinder
        Their ``mass`` is lumped half at each end pin (none where it is 0).
    ends : sequence of (str, str)
        Each cylinder's end pins (base, rod end), in the order of ``cylinders``.

    Returns
    -------
    MassPoints
    """
    from excavkin.kinetostatics.inertia import MassProperties

    plan = mechanism.plan
    props = MassProperties.from_plan(plan)
    n_pts = len(plan.points)
    names: list[str] = []
    masses: list[float] = []
    rows: list[F] = []
    for j, body in enumerate(plan.model.bodies):
        if props.mass[j] <= 0.0:
            continue
        p0, p1 = (int(i) for i in props.base[j])
        s, t = (float(v) for v in props.com[j])
        c = np.zeros((2, n_pts, 2))
        # S = P0 + s·(P1 − P0) + t·perp(P1 − P0), perp(w) = (−w_y, w_x)
        c[0, p0, 0] += 1.0 - s
        c[0, p1, 0] += s
        c[0, p0, 1] += t
        c[0, p1, 1] -= t
        c[1, p0, 1] += 1.0 - s
        c[1, p1, 1] += s
        c[1, p1, 0] += t
        c[1, p0, 0] -= t
        names.append(body.name)
        masses.append(float(props.mass[j]))
        rows.append(c)
    for cyl, pins in zip(cylinders, ends, strict=True):
        if cyl.mass <= 0.0:
            continue
        for pin in pins:
            c = np.zeros((2, n_pts, 2))
            i = plan.points.index(pin)
            c[0, i, 0] = c[1, i, 1] = 1.0
            names.append(f"{cyl.driver}@{pin}")
            masses.append(0.5 * cyl.mass)
            rows.append(c)
    coef = np.stack(rows) if rows else np.zeros((0, 2, n_pts, 2))
    return MassPoints(tuple(names), np.array(masses, dtype=np.float64), coef)
