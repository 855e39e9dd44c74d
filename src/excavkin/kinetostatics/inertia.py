"""d'Alembert inertia loads and kinetic energy from the kinematics.

A body's centre of mass S is a fixed combination of its two base points p0, p1 (its first two
points)::

    S = p0 + s·(p1 − p0) + t·perp(p1 − p0),      perp(v) = (−v_y, v_x)

The map is linear in p0 and p1, so the same (s, t) give v_S and a_S exactly from the base points'
velocities and accelerations. Per body with mass m and moment of inertia J about S:

    inertia force   −m·a_S   at S
    inertia couple  −J·ε
    dT/dt = m·a_S·v_S + J·ε·ω

A body with a mass but no centre of mass takes the centroid of its points; one with a mass but
no moment of inertia takes J = 0 (a point mass). Massless bodies (and the ground) carry none.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.kinematics.result import KinematicResult
from excavkin.structure.design import design_masses
from excavkin.structure.plan import SolvePlan

__all__ = [
    "MassProperties",
    "centre_of_mass",
    "inertia_loads",
    "kinetic_energy",
    "kinetic_energy_rate",
]


@dataclass(frozen=True, slots=True)
class MassProperties:
    """Mass properties per body in plan order (ground and massless bodies have zero mass).

    Attributes
    ----------
    mass : ndarray, shape (n_bodies,) or (n_bodies, n)
        kg (the second form: one value per sample, for a family of designs).
    inertia : ndarray, shape (n_bodies,) or (n_bodies, n)
        kg·m² about the centre of mass.
    com : ndarray, shape (n_bodies, 2) or (n_bodies, 2, n)
        (s, t) of the centre of mass on the base vector p0→p1 (see the module docstring).
    base : ndarray of int, shape (n_bodies, 2)
        Indices of p0 and p1.
    """

    mass: F
    inertia: F
    com: F
    base: np.ndarray

    @classmethod
    def of(cls, result: KinematicResult) -> MassProperties:
        """The mass properties a result was solved with: its plan's, or, for a family of
        designs whose dimensions or masses vary per sample, one value per sample."""
        given = result.parameters or {}
        if not given:
            return cls.from_plan(result.plan)
        mass, inertia, com = design_masses(result.plan.model, given, len(result))
        return cls(mass, inertia, com, np.asarray(result.plan.body_base, dtype=np.intp))

    def at(self, part: slice) -> MassProperties:
        """The samples ``part`` of per-sample properties (constant ones as they are)."""
        if self.mass.ndim == 1:
            return self
        return MassProperties(
            self.mass[:, part], self.inertia[:, part], self.com[:, :, part], self.base
        )

    @classmethod
    def from_plan(cls, plan: SolvePlan) -> MassProperties:
        """Read masses, inertias and centres of mass from the plan's model and shapes."""
        nb = len(plan.bodies)
        mass = np.zeros(nb)
        inertia = np.zeros(nb)
        com = np.zeros((nb, 2))
        for j, body in enumerate(plan.model.bodies):
            if body.ground or body.mass is None or j == plan.ground:
                continue
            mass[j] = body.mass
            inertia[j] = body.inertia or 0.0
            shape = plan.shapes[body.name]
            if shape.com is not None:
                com[j] = shape.com
            else:  # centroid of the body's points, in units of the base vector
                d01 = shape.distance(body.points[0], body.points[1])
                cx = sum(shape.local[p][0] for p in body.points) / len(body.points)
                cy = sum(shape.local[p][1] for p in body.points) / len(body.points)
                com[j] = (cx / d01, cy / d01)
        return cls(mass, inertia, com, np.asarray(plan.body_base, dtype=np.intp))

    @property
    def massive(self) -> tuple[int, ...]:
        """Indices of the bodies with a mass."""
        massive = self.mass > 0 if self.mass.ndim == 1 else (self.mass > 0).any(axis=1)
        return tuple(int(j) for j in np.flatnonzero(massive))


def _soa(result: KinematicResult) -> tuple[F, F, F]:
    """Positions, velocities, accelerations as (n_points, 2, n) views."""
    return (
        np.moveaxis(result.positions, 0, -1),
        np.moveaxis(result.velocities, 0, -1),
        np.moveaxis(result.accelerations, 0, -1),
    )


def _map(arr: F, j0: int, j1: int, s: float, t: float) -> tuple[F, F]:
    wx = arr[j1, 0] - arr[j0, 0]
    wy = arr[j1, 1] - arr[j0, 1]
    return arr[j0, 0] + s * wx - t * wy, arr[j0, 1] + s * wy + t * wx


def centre_of_mass(result: KinematicResult, mass: MassProperties | None = None) -> tuple[F, F, F]:
    """Position, velocity and acceleration of every body's centre of mass.

    Parameters
    ----------
    result : KinematicResult
    mass : MassProperties, optional
        Default: from ``result.plan``.

    Returns
    -------
    position, velocity, acceleration : ndarray, shape (n, n_bodies, 2)
        NaN for bodies without a mass and for the ground.
    """
    mp = mass or MassProperties.of(result)
    x, v, a = _soa(result)
    n = len(result)
    out = np.full((3, len(mp.mass), 2, n), np.nan)
    for j in mp.massive:
        j0, j1 = mp.base[j]
        s, t = mp.com[j]
        for k, arr in enumerate((x, v, a)):
            out[k, j, 0], out[k, j, 1] = _map(arr, j0, j1, s, t)
    return (np.moveaxis(out[0], -1, 0), np.moveaxis(out[1], -1, 0), np.moveaxis(out[2], -1, 0))


def inertia_loads(result: KinematicResult, mass: MassProperties | None = None) -> tuple[F, F]:
    """d'Alembert inertia force (at the centre of mass) and couple of every body.

    Parameters
    ----------
    result : KinematicResult
    mass : MassProperties, optional

    Returns
    -------
    force : ndarray, shape (n, n_bodies, 2)
        ``−m·a_S``, N; zero for massless bodies and the ground.
    couple : ndarray, shape (n, n_bodies)
        ``−J·ε``, N·m.
    """
    mp = mass or MassProperties.of(result)
    _, _, a = _soa(result)
    n = len(result)
    force = np.zeros((len(mp.mass), 2, n))
    couple = np.zeros((len(mp.mass), n))
    eps = np.moveaxis(result.body_epsilon, 0, -1)
    for j in mp.massive:
        j0, j1 = mp.base[j]
        s, t = mp.com[j]
        ax, ay = _map(a, j0, j1, s, t)
        force[j, 0] = -mp.mass[j] * ax
        force[j, 1] = -mp.mass[j] * ay
        couple[j] = -mp.inertia[j] * eps[j]
    return np.moveaxis(force, -1, 0), couple.T


def kinetic_energy(result: KinematicResult, mass: MassProperties | None = None) -> F:
    """Kinetic energy ``Σ ½·m·|v_S|² + ½·J·ω²``, J, shape (n,)."""
    mp = mass or MassProperties.of(result)
    _, v, _ = _soa(result)
    om = np.moveaxis(result.body_omega, 0, -1)
    out = np.zeros(len(result))
    for j in mp.massive:
        j0, j1 = mp.base[j]
        vx, vy = _map(v, j0, j1, *mp.com[j])
        out += 0.5 * mp.mass[j] * (vx * vx + vy * vy) + 0.5 * mp.inertia[j] * om[j] * om[j]
    return out


def kinetic_energy_rate(result: KinematicResult, mass: MassProperties | None = None) -> F:
    """Rate of change of the kinetic energy ``dT/dt = Σ m·a_S·v_S + J·ε·ω``, W, shape (n,)."""
    mp = mass or MassProperties.of(result)
    _, v, a = _soa(result)
    om = np.moveaxis(result.body_omega, 0, -1)
    eps = np.moveaxis(result.body_epsilon, 0, -1)
    out = np.zeros(len(result))
    for j in mp.massive:
        j0, j1 = mp.base[j]
        s, t = mp.com[j]
        vx, vy = _map(v, j0, j1, s, t)
        ax, ay = _map(a, j0, j1, s, t)
        out += mp.mass[j] * (ax * vx + ay * vy) + mp.inertia[j] * eps[j] * om[j]
    return out
