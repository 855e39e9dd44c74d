"""Closed-form step kernels, vectorised over a chunk of samples.

State lives in struct-of-arrays form: ``x[i, 0]`` is the x coordinate of point i over the chunk
(a contiguous row), likewise velocities ``v`` and accelerations ``a``. Each kernel computes its
point's position and, when ``order == 2``, its velocity and acceleration by solving the
*differentiated* constraints — never by finite differences.

Two-distances step (RRR dyad; either side may be a driven length)::

    (P−A)·(P−A) = d1²                 (P−B)·(P−B) = d2²
    (P−A)·(Ṗ−Ȧ) = d1·ḋ1               (P−B)·(Ṗ−Ḃ) = d2·ḋ2
    (P−A)·(P̈−Ä) = d1·d̈1 + ḋ1² − |Ṗ−Ȧ|²   and the same for B

One 2×2 matrix ``[(P−A)ᵀ; (P−B)ᵀ]`` serves both orders; its determinant cross(P−A, P−B)
vanishes exactly at a dead position, which is reported instead of huge or NaN rates.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.structure.plan import Attach, Dist, Dyad, Fixed, Rotate, SliderStep


class Code(IntEnum):
    """Per-sample status codes."""

    OK = 0
    NO_CLOSURE = 1
    SINGULAR = 2
    NO_CONVERGENCE = 3
    BRANCH_CHANGED = 4
    BAD_INPUT = 5
    BAD_LENGTH = 6
    NOT_FINITE = 7
    UNDETERMINED = 8
    IMPRECISE = 9
    BAD_DESIGN = 10


@dataclass(slots=True)
class Chunk:
    """Views of the solve arrays for one chunk of samples."""

    x: F  # (n_points, 2, c)
    v: F
    a: F
    q: F  # (n_inputs, c)
    qd: F
    qdd: F
    trans: F  # (n_trans, c)
    status: NDArray[np.int8]  # (c,)
    failed: NDArray[np.int16]  # (c,)
    close_tol: float
    singular_tol: float
    #: how far each sample is from a dead position of a Newton group (the Jacobian's
    #: determinant over its rows' norms), where the solve keeps it
    near: F | None = None
    #: the precision check's emulated rounding: per-sample ±units by which each step's
    #: cancelling quantity (a dyad's or slider's squared half-chord) and its output are moved
    nudge: F | None = None


def flag(c: Chunk, mask: NDArray[np.bool_], code: Code, step: int) -> None:
    """Give ``code`` to the samples in ``mask`` that are still OK (the first failure wins)."""
    hit = mask & (c.status == 0)
    if hit.any():
        c.status[hit] = code
        c.failed[hit] = step


def dist(c: Chunk, d: Dist) -> tuple[F | float, F | float, F | float]:
    """A distance and its first and second time derivatives."""
    if d.kind == "fixed":
        if c.x.dtype != np.float64:  # a wider solve: products of lengths in its own precision
            return c.x.dtype.type(d.value), 0.0, 0.0
        return d.value, 0.0, 0.0
    return c.q[d.input], c.qd[d.input], c.qdd[d.input]


def fixed(c: Chunk, st: Fixed, order: int) -> None:
    """Ground points: constant, at rest."""
    for i, (px, py) in zip(st.points, st.coords, strict=True):
        c.x[i, 0] = px
        c.x[i, 1] = py
        if order:
            c.v[i] = 0.0
            c.a[i] = 0.0


def rotate(c: Chunk, st: Rotate, order: int) -> None:
    """A point of a driven body about its pivot: θ = θ_ref + q."""
    x, v, a = c.x, c.v, c.a
    q = c.q[st.input]
    r = st.radius
    if st.ref is None:
        th = q
    else:
        b0, b1 = st.ref
        rx = x[b1, 0] - x[b0, 0]
        ry = x[b1, 1] - x[b0, 1]
        th = q + np.arctan2(ry, rx)
    cs, sn = np.cos(th), np.sin(th)
    x[st.point, 0] = x[st.pivot, 0] + r * cs
    x[st.point, 1] = x[st.pivot, 1] + r * sn
    if not order:
        return
    thd, thdd = c.qd[st.input], c.qdd[st.input]
    if st.ref is not None:
        b0, b1 = st.ref
        rvx, rvy = v[b1, 0] - v[b0, 0], v[b1, 1] - v[b0, 1]
        rax, ray = a[b1, 0] - a[b0, 0], a[b1, 1] - a[b0, 1]
        r2 = rx * rx + ry * ry
        w_ref = (rx * rvy - ry * rvx) / r2
        thd = thd + w_ref
        thdd = thdd + (rx * ray - ry * rax - 2.0 * (rx * rvx + ry * rvy) * w_ref) / r2
    v[st.point, 0] = v[st.pivot, 0] - r * thd * sn
    v[st.point, 1] = v[st.pivot, 1] + r * thd * cs
    a[st.point, 0] = a[st.pivot, 0] - r * (thdd * sn + thd * thd * cs)
    a[st.point, 1] = a[st.pivot, 1] + r * (thdd * cs - thd * thd * sn)


def attach(c: Chunk, st: Attach, order: int) -> None:
    """P = A + s·(B − A) + t·perp(B − A): linear in A and B, so every order alike."""
    s, t = st.s, st.t
    arrays = (c.x, c.v, c.a) if order else (c.x,)
    for arr in arrays:
        wx = arr[st.b, 0] - arr[st.a, 0]
        wy = arr[st.b, 1] - arr[st.a, 1]
        arr[st.point, 0] = arr[st.a, 0] + s * wx - t * wy
        arr[st.point, 1] = arr[st.a, 1] + s * wy + t * wx


def dyad(c: Chunk, st: Dyad, order: int, k: int) -> None:
    """Two distances: P from A (d1) and B (d2) on the sketch's side of A→B."""
    x, v, a = c.x, c.v, c.a
    ax, ay, bx, by = x[st.a, 0], x[st.a, 1], x[st.b, 0], x[st.b, 1]
    d1, d1d, d1dd = dist(c, st.da)
    d2, d2d, d2dd = dist(c, st.db)
    ex = bx - ax
    ey = by - ay
    l2 = ex * ex + ey * ey
    kk = (d1 * d1 - d2 * d2 + l2) / (2.0 * l2)
    h2 = d1 * d1 / l2 - kk * kk
    if c.nudge is not None:  # the rounding of the cancelling difference, emulated
        h2 = h2 + c.nudge * (d1 * d1 / l2 + kk * kk)
    # `not >=` also catches NaN: A and B coincide (l2 = 0), so the dyad has no base
    low = ~(h2 >= c.close_tol)
    if low.any():
        # partners that coincide with equal distances leave P anywhere on a circle: that is
        # undetermined, not a failure to close
        size = np.abs(d1) + np.abs(d2)
        loose = ~(l2 > (1e-12 * size) ** 2) & (np.abs(d1 - d2) <= 1e-12 * size)
        flag(c, low & loose, Code.UNDETERMINED, k)
        bad = ~(h2 >= -c.close_tol)
        flag(c, bad, Code.NO_CLOSURE, k)
        h2 = np.where(bad, np.nan, np.maximum(h2, 0.0))
    h = st.sign * np.sqrt(h2)
    px = ax + kk * ex - h * ey
    py = ay + kk * ey + h * ex
    x[st.point, 0] = px
    x[st.point, 1] = py
    r1x, r1y = px - ax, py - ay
    r2x, r2y = px - bx, py - by
    det = r1x * r2y - r1y * r2x
    c.trans[st.index] = np.arctan2(np.abs(det), r1x * r2x + r1y * r2y)
    if not order:
        return
    sing = ~(np.abs(det) > c.singular_tol * np.abs(d1 * d2))  # NaN counts as singular
    if sing.any():
        flag(c, sing, Code.SINGULAR, k)
        det = np.where(sing, np.nan, det)
    inv = 1.0 / det
    vax, vay, vbx, vby = v[st.a, 0], v[st.a, 1], v[st.b, 0], v[st.b, 1]
    f1 = r1x * vax + r1y * vay + d1 * d1d
    f2 = r2x * vbx + r2y * vby + d2 * d2d
    vpx = (f1 * r2y - f2 * r1y) * inv
    vpy = (r1x * f2 - r2x * f1) * inv
    v[st.point, 0] = vpx
    v[st.point, 1] = vpy
    wx, wy = vpx - vax, vpy - vay
    ux, uy = vpx - vbx, vpy - vby
    f1 = r1x * a[st.a, 0] + r1y * a[st.a, 1] + d1 * d1dd + d1d * d1d - (wx * wx + wy * wy)
    f2 = r2x * a[st.b, 0] + r2y * a[st.b, 1] + d2 * d2dd + d2d * d2d - (ux * ux + uy * uy)
    a[st.point, 0] = (f1 * r2y - f2 * r1y) * inv
    a[st.point, 1] = (r1x * f2 - r2x * f1) * inv


def slider(c: Chunk, st: SliderStep, order: int, k: int) -> None:
    """P on the line l1→l2 at distance d from A (RRP dyad).

    Constraints, with u = l2 − l1 and g = P − l1::

        cross(u, g) = 0                         (P − A)·(P − A) = d²
        cross(u, Ṗ) = cross(u, l̇1) − cross(u̇, g)
        cross(u, P̈) = cross(u, l̈1) − cross(ü, g) − 2·cross(u̇, ġ)
        (P − A)·Ṗ = (P − A)·Ȧ + d·ḋ
        (P − A)·P̈ = (P − A)·Ä + d·d̈ + ḋ² − |Ṗ − Ȧ|²

    The determinant is −u·(P − A): the dead position has the link square to the slide.
    """
    x, v, a = c.x, c.v, c.a
    l1x, l1y = x[st.l1, 0], x[st.l1, 1]
    ux = x[st.l2, 0] - l1x
    uy = x[st.l2, 1] - l1y
    lu = np.sqrt(ux * ux + uy * uy)
    ex, ey = ux / lu, uy / lu
    ax, ay = x[st.a, 0], x[st.a, 1]
    gx, gy = ax - l1x, ay - l1y
    foot = gx * ex + gy * ey
    off = ex * gy - ey * gx
    d, dd, ddd = dist(c, st.da)
    s2 = (d * d - off * off) / (d * d)
    if c.nudge is not None:
        s2 = s2 + c.nudge * (1.0 + off * off / (d * d))
    low = ~(s2 >= c.close_tol)  # NaN too: the slide's two points coincide
    if low.any():
        bad = ~(s2 >= -c.close_tol)
        flag(c, bad, Code.NO_CLOSURE, k)
        s2 = np.where(bad, np.nan, np.maximum(s2, 0.0))
    along = foot + st.sign * np.abs(d) * np.sqrt(s2)
    px = l1x + along * ex
    py = l1y + along * ey
    x[st.point, 0] = px
    x[st.point, 1] = py
    r1x, r1y = px - ax, py - ay
    dot = ux * r1x + uy * r1y
    c.trans[st.index] = np.arctan2(np.abs(dot), np.abs(ux * r1y - uy * r1x))
    if not order:
        return
    det = -dot
    sing = ~(np.abs(det) > c.singular_tol * lu * np.abs(d))
    if sing.any():
        flag(c, sing, Code.SINGULAR, k)
        det = np.where(sing, np.nan, det)
    inv = 1.0 / det
    gx, gy = px - l1x, py - l1y
    udx = v[st.l2, 0] - v[st.l1, 0]
    udy = v[st.l2, 1] - v[st.l1, 1]
    vl1x, vl1y = v[st.l1, 0], v[st.l1, 1]
    vax, vay = v[st.a, 0], v[st.a, 1]
    f1 = (ux * vl1y - uy * vl1x) - (udx * gy - udy * gx)
    f2 = r1x * vax + r1y * vay + d * dd
    vpx = (f1 * r1y - ux * f2) * inv
    vpy = (-uy * f2 - r1x * f1) * inv
    v[st.point, 0] = vpx
    v[st.point, 1] = vpy
    gdx, gdy = vpx - vl1x, vpy - vl1y
    uddx = a[st.l2, 0] - a[st.l1, 0]
    uddy = a[st.l2, 1] - a[st.l1, 1]
    wx, wy = vpx - vax, vpy - vay
    f1 = (
        (ux * a[st.l1, 1] - uy * a[st.l1, 0])
        - (uddx * gy - uddy * gx)
        - 2.0 * (udx * gdy - udy * gdx)
    )
    f2 = r1x * a[st.a, 0] + r1y * a[st.a, 1] + d * ddd + dd * dd - (wx * wx + wy * wy)
    a[st.point, 0] = (f1 * r1y - ux * f2) * inv
    a[st.point, 1] = (-uy * f2 - r1x * f1) * inv
