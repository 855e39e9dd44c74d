"""The loader's rating poses, found with the engine: the tilt length that sets the bucket floor
at an angle, the lift length that sets the hinge pin at a height, and the ground pose (floor
level, cutting edge on the ground).

One-dimensional conditions are solved by bisection over the cylinder's stroke, vectorised over
the poses (each step one engine solve of all of them); the ground pose by Newton's method on the
two cylinder lengths with the engine's exact transfer functions. A condition no length within
the stroke meets gives NaN, never a clipped pose.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from excavkin.arrays import BoolArray as B
from excavkin.arrays import FloatArray as F
from excavkin.errors import ModelError
from excavkin.loader.machine import Loader, floor_angle, floor_angle_rate, transfer

#: bisection steps: the stroke halved this often (well below 1e-12 m)
_STEPS = 60
#: points of the grid that brackets a condition
_GRID = 257


def _bracket(values: F, target: F) -> tuple[NDArray[np.intp], B]:
    """Indices (n,) of the first grid interval where ``values - target`` changes sign, and
    whether there is one."""
    d = values - target[:, None]
    s = np.sign(d)
    change = (s[:, :-1] * s[:, 1:] <= 0.0) & np.isfinite(d[:, :-1]) & np.isfinite(d[:, 1:])
    found = change.any(axis=1)
    return np.argmax(change, axis=1), np.asarray(found)


def tilt_for_angle(machine: Loader, lift: ArrayLike, angle: ArrayLike) -> F:
    """The tilt-cylinder length that sets the bucket floor at ``angle``, at each lift length.

    Parameters
    ----------
    machine : Loader
    lift : array_like, shape (n,)
        Lift-cylinder lengths (m).
    angle : array_like, shape (n,) or scalar
        Floor angles (rad; 0 level, > 0 rolled back).

    Returns
    -------
    ndarray, shape (n,)
        Tilt lengths (m); NaN where no length within the stroke reaches the angle.
    """
    Ll = np.atleast_1d(np.asarray(lift, dtype=np.float64))
    n = len(Ll)
    target = np.broadcast_to(np.asarray(angle, dtype=np.float64), (n,)).copy()
    lo, hi = machine.lengths_min[1], machine.lengths_max[1]
    grid = np.linspace(lo, hi, _GRID)

    def angles(lift_: F, tilt: F) -> F:
        res = machine.solve(np.column_stack([lift_, tilt]))
        a = floor_angle(machine, res.positions)
        return np.where(res.status.ok, a, np.nan)

    vals = angles(np.repeat(Ll, _GRID), np.tile(grid, n)).reshape(n, _GRID)
    k, found = _bracket(vals, target)
    a = grid[k]
    b = grid[np.minimum(k + 1, _GRID - 1)]
    fa = vals[np.arange(n), k] - target
    for _ in range(_STEPS):
        m = 0.5 * (a + b)
        fm = angles(Ll, m) - target
        left = np.sign(fm) == np.sign(fa)
        a, fa = np.where(left, m, a), np.where(left, fm, fa)
        b = np.where(left, b, m)
    return np.where(found, 0.5 * (a + b), np.nan)


def assembling_tilt(machine: Loader, lift: ArrayLike) -> F:
    """A tilt length that assembles the linkage at each lift length: the one nearest
    mid-stroke of a grid over the stroke (what the hinge pin's position, which the lift arm
    alone sets, is solved with).

    Parameters
    ----------
    machine : Loader
    lift : array_like, shape (n,)
        Lift-cylinder lengths (m).

    Returns
    -------
    ndarray, shape (n,)
        Tilt lengths (m); NaN where none within the stroke assembles.
    """
    Ll = np.atleast_1d(np.asarray(lift, dtype=np.float64))
    n = len(Ll)
    lo, hi = machine.lengths_min[1], machine.lengths_max[1]
    grid = np.linspace(lo, hi, _GRID)
    res = machine.solve(np.column_stack([np.repeat(Ll, _GRID), np.tile(grid, n)]))
    ok = res.status.ok.reshape(n, _GRID)
    dist = np.where(ok, np.abs(grid - 0.5 * (lo + hi)), np.inf)
    k = np.argmin(dist, axis=1)
    return np.where(ok.any(axis=1), grid[k], np.nan)


def lift_for_hinge_height(machine: Loader, height: float) -> float:
    """The lift-cylinder length that sets the hinge pin ``height`` above the ground.

    The hinge pin moves with the lift arm alone; each lift length is solved with a tilt length
    that assembles there ([`assembling_tilt`][excavkin.loader.poses.assembling_tilt]).

    Parameters
    ----------
    machine : Loader
    height : float
        Above the ground line (m).

    Returns
    -------
    float
        The lift length (m); NaN where no length within the stroke reaches the height.
    """
    lo, hi = machine.lengths_min[0], machine.lengths_max[0]
    ib = machine.index(machine.pins.hinge)

    def heights(lift: F) -> F:
        tilt = assembling_tilt(machine, lift)
        res = machine.solve(np.column_stack([lift, np.where(np.isfinite(tilt), tilt, 0.0)]))
        y = res.positions[:, ib, 1] - machine.ground_line
        return np.where(res.status.ok & np.isfinite(tilt), y, np.nan)

    grid = np.linspace(lo, hi, _GRID)
    k, found = _bracket(heights(grid)[None, :], np.array([height]))
    if not found[0]:
        return float("nan")
    a, b = grid[k[0]], grid[k[0] + 1]
    fa = heights(np.array([a]))[0] - height
    for _ in range(_STEPS):
        m = 0.5 * (a + b)
        fm = heights(np.array([m]))[0] - height
        if np.sign(fm) == np.sign(fa):
            a, fa = m, fm
        else:
            b = m
    return float(0.5 * (a + b))


def ground_pose(machine: Loader, *, tol: float = 1e-12, iterations: int = 30) -> F:
    """The lengths that set the bucket floor level with the cutting edge on the ground.

    Newton's method on (floor angle, edge height) over (lift, tilt), with the engine's exact
    transfer functions, from the lowest lift with the floor level.

    Parameters
    ----------
    machine : Loader
    tol : float
        On both residuals (rad, m).
    iterations : int
        Most Newton steps.

    Returns
    -------
    ndarray, shape (2,)
        Lift and tilt lengths (m).

    Raises
    ------
    ModelError
        Naming the machine file, where the edge cannot reach the ground with the floor
        level within the strokes (it stays above the ground at the lowest lift).
    """
    lift = machine.lowest()
    tilt = float(tilt_for_angle(machine, np.array([lift]), 0.0)[0])
    L = np.array([[lift, tilt]])
    ie = machine.index(machine.linkage.edge)
    for _ in range(iterations):
        tr = transfer(machine, L)
        if not tr.ok[0]:
            break
        r = np.array(
            [
                floor_angle(machine, tr.positions)[0],
                tr.positions[0, ie, 1] - machine.ground_line,
            ]
        )
        if np.all(np.abs(r) <= tol):
            break
        J = np.vstack([floor_angle_rate(machine, tr)[0], tr.d[0, ie, 1, :]])
        L = L - np.linalg.solve(J, r)[None, :]
    ok = (
        tr.ok[0]
        and np.all(np.abs(r) <= 1e-9)
        and np.all(L[0] >= machine.lengths_min - 1e-9)
        and np.all(L[0] <= machine.lengths_max + 1e-9)
    )
    if not ok:
        raise ModelError(
            "no pose within the strokes sets the bucket floor level with the cutting edge on "
            "the ground (the edge stays above the ground at the lowest lift, or the tilt stroke "
            "cannot level the floor there): check the strokes against the linkage",
            table="cylinders",
            source=machine.source,
        )
    return np.asarray(L[0])
