"""The signed clearance of two segments: against a dense sampling of both segments, against
shapely, its sign and penetration depth against translations that do or do not free the
segments, and its gradient against central differences."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
import shapely.affinity
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from excavkin.studies.clearance import segment_clearance

coord = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False)
point = st.tuples(coord, coord)
segments = st.tuples(point, point, point, point)


def _brute(p0, p1, q0, q1, n: int = 1201) -> float:  # type: ignore[no-untyped-def]
    """The least distance of n points spread along each segment."""
    s = np.linspace(0.0, 1.0, n)[:, None]
    a = np.asarray(p0) + s * (np.asarray(p1) - np.asarray(p0))
    b = np.asarray(q0) + s * (np.asarray(q1) - np.asarray(q0))
    d2 = ((a[:, None, :] - b[None, :, :]) ** 2).sum(-1)
    return float(np.sqrt(d2.min()))


def _lines(p0, p1, q0, q1):  # type: ignore[no-untyped-def]
    return shapely.LineString([p0, p1]), shapely.LineString([q0, q1])


@settings(max_examples=150, deadline=None, derandomize=True, database=None)
@given(segments)
def test_distance_equals_dense_sampling_and_shapely(seg: tuple) -> None:  # type: ignore[type-arg]
    p0, p1, q0, q1 = seg
    c = float(segment_clearance(p0, p1, q0, q1))  # type: ignore[arg-type]
    a, b = _lines(p0, p1, q0, q1)
    brute = _brute(p0, p1, q0, q1)
    # the sampling's spacing bounds how far its least distance lies above the exact one
    lengths = np.hypot(*np.subtract(p1, p0)), np.hypot(*np.subtract(q1, q0))
    step = max(lengths) / 1200
    # shapely (GEOS) takes a line of almost no length for an invalid one: compare with it where
    # both segments have a length
    proper = min(lengths) > 1e-6
    if c >= 0.0:
        assert c <= brute + 1e-12
        assert brute <= c + step + 1e-12
        if proper:
            assert_allclose(c, a.distance(b), rtol=1e-9, atol=1e-12)
    else:  # crossing: the segments meet, and shapely says so
        assert brute <= step + 1e-12
        assert a.intersects(b) and a.distance(b) == 0.0


@pytest.mark.parametrize(
    ("seg", "expected"),
    [
        (((0, 0), (1, 0), (0, 1), (1, 1)), 1.0),  # parallel, one above the other
        (((0, 0), (1, 0), (2, 0), (3, 0)), 1.0),  # collinear, apart
        (((0, 0), (2, 0), (1, 0), (3, 0)), 0.0),  # collinear, overlapping
        (((0, 0), (1, 0), (1, 0), (1, 5)), 0.0),  # touching at an end
        (((0, 0), (4, 0), (2, -1), (2, 3)), -1.0),  # crossing: 1 frees it (q0's side)
        (((0, 0), (4, 0), (1, -3), (1, 3)), -1.0),  # crossing: p0 is 1 from the other
        (((0, 0), (1, 1), (3, 0), (4, 2)), np.sqrt(5.0)),  # nearest at p1 and q0
        (((0, 0), (0, 0), (3, 4), (3, 4)), 5.0),  # two points
    ],
)
def test_known_cases(seg: tuple, expected: float) -> None:  # type: ignore[type-arg]
    p0, p1, q0, q1 = seg
    c = float(segment_clearance(p0, p1, q0, q1))  # type: ignore[arg-type]
    if expected >= 0.0:
        a, b = _lines(p0, p1, q0, q1)
        assert_allclose(c, a.distance(b), rtol=1e-12, atol=1e-15)
    assert_allclose(c, expected, rtol=1e-12, atol=1e-15)


@settings(max_examples=100, deadline=None, derandomize=True, database=None)
@given(segments, st.floats(0.0, 2 * np.pi), st.tuples(coord, coord))
def test_a_rigid_motion_and_the_order_of_the_segments_change_nothing(
    seg: tuple,  # type: ignore[type-arg]
    angle: float,
    shift: tuple[float, float],
) -> None:
    pts = np.asarray(seg, dtype=np.float64)
    c = segment_clearance(*pts)
    rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    moved = pts @ rot.T + np.asarray(shift)
    assert_allclose(segment_clearance(*moved), c, atol=1e-9)
    assert_allclose(segment_clearance(pts[2], pts[3], pts[0], pts[1]), c, atol=1e-12)
    assert_allclose(segment_clearance(pts[1], pts[0], pts[3], pts[2]), c, atol=1e-12)


CROSSING = ((0.0, 0.0), (4.0, 0.0), (2.0, -1.0), (2.0, 3.0))


@settings(max_examples=100, deadline=None, derandomize=True, database=None)
@given(segments)
@example(CROSSING)
def test_a_penetration_is_the_shortest_translation_that_frees_the_segments(
    seg: tuple,  # type: ignore[type-arg]
) -> None:
    pts = np.asarray(seg, dtype=np.float64)
    c, grad = segment_clearance(*pts, gradient=True)
    if not c < -1e-6:
        return
    depth = -float(c)
    a, b = _lines(*pts)
    # the gradient's pull on the whole first segment is the way out, of unit length
    out = grad[0] + grad[1]
    assert_allclose(np.hypot(*out), 1.0, rtol=1e-9)
    freed = shapely.affinity.translate(a, *(out * depth * (1 + 1e-6) + 0.0))
    assert not freed.intersects(b)
    # no translation shorter than the depth frees them
    for t in np.linspace(0.0, 2 * np.pi, 72, endpoint=False):
        v = np.array([np.cos(t), np.sin(t)]) * depth * (1 - 1e-6)
        assert shapely.affinity.translate(a, *v).intersects(b)


@settings(max_examples=100, deadline=None, derandomize=True, database=None)
@given(segments)
@example(CROSSING)
def test_the_gradient_equals_central_differences(seg: tuple) -> None:  # type: ignore[type-arg]
    pts = np.asarray(seg, dtype=np.float64)
    c, grad = segment_clearance(*pts, gradient=True)
    h = 1e-6
    # differences of step h measure a slope only where the geometry is far larger than h: a
    # clearance or a segment of a few h has its kinks (the nearest pair changing) inside the
    # step, and neither side's slope is what the differences see
    lengths = np.hypot(*(pts[1] - pts[0])), np.hypot(*(pts[3] - pts[2]))
    assume(min(lengths) > 1e3 * h and abs(c) > 100 * h)
    fd = np.zeros((4, 2))
    for i in range(4):
        for j in range(2):
            up, down = pts.copy(), pts.copy()
            up[i, j] += h
            down[i, j] -= h
            fd[i, j] = (segment_clearance(*up) - segment_clearance(*down)) / (2 * h)
    # where the nearest pair changes within the step (a kink), the differences straddle it
    kink = np.abs(fd - grad).max() > 1e-5
    if kink:
        for i in range(4):
            for j in range(2):
                for step in (h, -h):
                    moved = pts.copy()
                    moved[i, j] += step
                    # one-sided: the gradient is that of one side of the kink
                    one = (segment_clearance(*moved) - c) / step
                    if abs(one - grad[i, j]) < 1e-5:
                        break
                else:
                    if abs(c) > 1e-6:
                        pytest.fail(f"∂/∂{i},{j}: {grad[i, j]} vs differences {fd[i, j]}")
    else:
        assert_allclose(grad, fd, atol=1e-5)


def test_batches_broadcast_and_equal_one_at_a_time() -> None:
    rng = np.random.default_rng(5)
    pts = rng.uniform(-1, 1, (4, 7, 3, 2))
    c, grad = segment_clearance(*pts, gradient=True)
    assert c.shape == (7, 3) and grad.shape == (7, 3, 4, 2)
    for i in range(7):
        for j in range(3):
            one, g = segment_clearance(*pts[:, i, j], gradient=True)
            assert one == c[i, j]
            assert_allclose(g, grad[i, j], rtol=0, atol=0)
    # a fixed segment against a batch of others
    fixed = segment_clearance((0, 0), (1, 0), pts[2], pts[3])
    assert fixed.shape == (7, 3)
