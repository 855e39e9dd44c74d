"""The known load on each moving body: the right-hand side of the equilibrium equations.

Each moving body's applied forces and couples, its weight and its d'Alembert inertia, reduced to
a force and a moment about the body's first point. The NumPy solve
(`excavkin.kinetostatics.solve`), the sensitivities
(`excavkin.kinetostatics.sensitivity`) and the compiled path's trace
(`excavkin.kinetostatics.compiled`) all evaluate these same lines, on arrays, dual numbers
or symbols.
"""

from __future__ import annotations

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.kinetostatics.equilibrium import StaticsSystem, Value
from excavkin.kinetostatics.inertia import MassProperties
from excavkin.kinetostatics.loads import EvaluatedLoads

__all__ = ["body_loads"]


def _add(a: Value, b: Value) -> Value:
    if isinstance(a, float) and a == 0.0:
        return b
    if isinstance(b, float) and b == 0.0:
        return a
    return a + b


def body_loads(
    sy: StaticsSystem,
    mp: MassProperties,
    ev: EvaluatedLoads,
    x: F,
    a: F | None,
    eps: F | None,
    sl: slice,
) -> list[tuple[Value, Value, Value]]:
    """Known force (x, y) and moment about p0 of each moving body over one chunk.

    Parameters
    ----------
    sy : StaticsSystem
        The equilibrium system (its moving bodies, in row order).
    mp : MassProperties
        Masses, centres of mass and inertias of the bodies.
    ev : EvaluatedLoads
        Gravity, point forces and couples, per sample or constant.
    x : ndarray, shape (n_points, 2, c)
        Point positions of the chunk's c samples.
    a : ndarray, shape (n_points, 2, c), or None
        Point accelerations (None: no d'Alembert force).
    eps : ndarray, shape (n_bodies, c), or None
        Body angular accelerations (None: no d'Alembert moment).
    sl : slice
        The chunk's samples in the per-sample loads.

    Returns
    -------
    list of (fx, fy, mz)
        One triple per moving body: a float where constant, else shape (c,).
    """
    out: list[tuple[Value, Value, Value]] = []
    g = ev.gravity
    by_body: dict[int, list[tuple[int, Value, Value]]] = {}
    for body, point, px, py in ev.forces:
        by_body.setdefault(body, []).append((point, px, py))
    couples: dict[int, Value] = {}
    for body, reaction, tau in ev.torques:
        t = tau if isinstance(tau, float) else tau[sl]
        couples[body] = _add(couples.get(body, 0.0), t)
        if reaction >= 0:
            couples[reaction] = _add(couples.get(reaction, 0.0), -t)
    massive = set(mp.massive)
    for j in sy.moving:
        fx: Value = 0.0
        fy: Value = 0.0
        mz: Value = couples.get(j, 0.0)
        i0, i1 = mp.base[j]
        m = mp.mass[j]
        if j in massive:
            s, t = mp.com[j]
            wx = x[i1, 0] - x[i0, 0]
            wy = x[i1, 1] - x[i0, 1]
            dx = s * wx - t * wy  # S − p0
            dy = s * wy + t * wx
            gx, gy = (0.0, 0.0) if g is None else g
            sx: Value = m * gx
            sy_: Value = m * gy
            if a is not None:
                awx = a[i1, 0] - a[i0, 0]
                awy = a[i1, 1] - a[i0, 1]
                sx = m * (gx - (a[i0, 0] + s * awx - t * awy))
                sy_ = m * (gy - (a[i0, 1] + s * awy + t * awx))
            fx, fy = sx, sy_
            if a is not None or g is not None:
                mz = _add(mz, dx * sy_ - dy * sx)
            if eps is not None and np.any(mp.inertia[j] != 0.0):
                mz = _add(mz, -mp.inertia[j] * eps[j])
        for point, px, py in by_body.get(j, ()):
            px_ = px if isinstance(px, float) else px[sl]
            py_ = py if isinstance(py, float) else py[sl]
            fx = _add(fx, px_)
            fy = _add(fy, py_)
            if point != i0:
                lx = x[point, 0] - x[i0, 0]
                ly = x[point, 1] - x[i0, 1]
                mz = _add(mz, lx * py_ - ly * px_)
        out.append((fx, fy, mz))
    return out
