"""The signed distance of two segments in the plane, vectorised, with its gradient: the
clearance between two parts of a mechanism drawn as lines (a cylinder's pin-to-pin line, a
body's edge).

Two segments P = p0p1 and Q = q0q1 that do not cross are nearest at an endpoint of one of
them, so their distance is the least of the four endpoint-to-segment distances

    d = min(dist(p0, Q), dist(p1, Q), dist(q0, P), dist(q1, P)).

Where they cross, that same least value is the depth of their penetration: the set of
translations v that keep them meeting, P − Q = {p − q}, is a parallelogram whose sides are
p0 − Q, p1 − Q, P − q0 and P − q1, and the origin lies inside it; the shortest translation
that separates them reaches the nearest side, at the distance of the origin from it, which is
the distance of that endpoint from the other segment. The signed clearance is therefore
``+d`` where the segments do not cross and ``−d`` where they do: continuous, zero where they
touch, and the shortest translation of one segment that frees it from the other where it is
negative.

Its gradient: at the endpoint-to-segment pair (point a, segment bc, nearest at
x = b + t (c − b)) that attains the minimum, with n the unit vector from x towards a, the
envelope theorem gives ∂d/∂a = ±n, ∂d/∂b = ∓(1 − t) n and ∂d/∂c = ∓t n (the sign the
clearance's). Where x lies inside bc, n is bc's normal on a's side, which stays exact where
a lies on bc's line (d = 0): there the clearance grows as a moves towards its own segment's
other end (the segments come apart) and falls as it moves away (they cross), so n points to
that end's side.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray as F


def _cross(u: F, v: F) -> F:
    return np.asarray(u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0])


def point_segment(p: F, a: F, b: F) -> tuple[F, F, F]:
    """The distance of points from segments, where on the segment the nearest point lies, and
    the vector from it to the point.

    Parameters
    ----------
    p, a, b : ndarray, shape (..., 2)
        The points, and the segments' two ends.

    Returns
    -------
    distance : ndarray, shape (...)
    t : ndarray, shape (...)
        The nearest point is ``a + t (b − a)``, 0 ≤ t ≤ 1 (0 for a segment of no length).
    offset : ndarray, shape (..., 2)
        ``p`` less the nearest point.
    """
    ab = b - a
    l2 = np.einsum("...i,...i->...", ab, ab)
    ap = p - a
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.clip(np.einsum("...i,...i->...", ap, ab) / np.where(l2 > 0.0, l2, 1.0), 0.0, 1.0)
    offset = ap - t[..., None] * ab
    return np.hypot(offset[..., 0], offset[..., 1]), t, offset


def segment_clearance(
    p0: ArrayLike, p1: ArrayLike, q0: ArrayLike, q1: ArrayLike, *, gradient: bool = False
) -> F | tuple[F, F]:
    """The signed clearance of segments p0p1 and q0q1: their distance where they do not cross,
    less the depth of their penetration where they do (module docstring).

    Parameters
    ----------
    p0, p1, q0, q1 : array_like, shape (..., 2)
        The two segments' ends (broadcast together).
    gradient : bool
        Return the gradient too.

    Returns
    -------
    clearance : ndarray, shape (...)
        The distance (≥ 0), or minus the shortest translation that separates crossing
        segments (< 0).
    grad : ndarray, shape (..., 4, 2)
        With ``gradient``: ∂clearance/∂(p0, p1, q0, q1), each an (x, y) pair.
    """
    p0, p1, q0, q1 = np.broadcast_arrays(
        *(np.asarray(v, dtype=np.float64) for v in (p0, p1, q0, q1))
    )
    # the four endpoint-to-segment pairs: (point, segment's start, its end)
    pairs = ((p0, q0, q1), (p1, q0, q1), (q0, p0, p1), (q1, p0, p1))
    found = [point_segment(a, b, c) for a, b, c in pairs]
    dist = np.stack([d for d, _, _ in found])
    k = np.argmin(dist, axis=0)
    d = np.take_along_axis(dist, k[None], axis=0)[0]
    # crossing: each segment's ends lie strictly on either side of the other's line
    o1, o2 = _cross(q1 - q0, p0 - q0), _cross(q1 - q0, p1 - q0)
    o3, o4 = _cross(p1 - p0, q0 - p0), _cross(p1 - p0, q1 - p0)
    crossing = (o1 * o2 < 0.0) & (o3 * o4 < 0.0)
    sign = np.where(crossing, -1.0, 1.0)
    value = np.asarray(sign * d)
    if not gradient:
        return value
    t = np.take_along_axis(np.stack([t for _, t, _ in found]), k[None], axis=0)[0]
    offset = np.take_along_axis(np.stack([o for _, _, o in found]), k[None, ..., None], axis=0)[0]
    # the way the clearance grows as the point moves: from the nearest point towards it where
    # that is an end of the segment; the segment's normal where it is inside, turned to the
    # point's side (to its own segment's other end's where the point lies on the line: moving
    # towards it frees the segments, moving away makes them cross)
    others = (p1, p0, q1, q0)
    point = np.stack([a for a, _, _ in pairs])
    start = np.stack([b for _, b, _ in pairs])
    end = np.stack([c for _, _, c in pairs])
    other = np.stack(others)

    def chosen(stacked: F) -> F:
        return np.asarray(np.take_along_axis(stacked, k[None, ..., None], axis=0)[0])

    a, b, c, o = chosen(point), chosen(start), chosen(end), chosen(other)
    along = c - b
    length = np.hypot(along[..., 0], along[..., 1])
    side = _cross(along, a - b)
    side = np.where(side == 0.0, _cross(along, o - b), side)
    with np.errstate(invalid="ignore", divide="ignore"):
        normal = np.stack([-along[..., 1], along[..., 0]], axis=-1) / length[..., None]
        to_end = offset / d[..., None]
    inside = (t > 0.0) & (t < 1.0) & (length > 0.0)
    n = np.where(inside[..., None], normal * np.sign(side)[..., None], to_end)
    n = np.where((inside | (d > 0.0))[..., None], n, 0.0) * sign[..., None]
    on_point = n
    on_start = -(1.0 - t)[..., None] * n
    on_end = -t[..., None] * n
    grad = np.zeros((*value.shape, 4, 2))
    # which of p0, p1, q0, q1 is the point, the segment's start and its end, for each pair
    roles = ((0, 2, 3), (1, 2, 3), (2, 0, 1), (3, 0, 1))
    for j, (i_point, i_start, i_end) in enumerate(roles):
        here = (k == j)[..., None]
        grad[..., i_point, :] += np.where(here, on_point, 0.0)
        grad[..., i_start, :] += np.where(here, on_start, 0.0)
        grad[..., i_end, :] += np.where(here, on_end, 0.0)
    return value, grad
