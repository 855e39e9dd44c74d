"""Working-range figures of the example machine against a brute-force dense sweep.

The figures are refined optima (pattern search to ~1e-9 m with exact constraints); a dense
3-D sweep of the strokes through the engine can only come close from inside. Each figure must
be at least the sweep's value and within the sweep's resolution of it.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely

import excavkin
from excavkin.excavator.machine import Machine, forward, inverse
from excavkin.excavator.machine_file import load_machine
from excavkin.excavator.ranges import WorkingRanges, sweep, working_ranges

N = 51  # sweep points per stroke: spacing ≤ 30 mm of stroke


@pytest.fixture(scope="module")
def machine() -> Machine:
    return load_machine(excavkin.example_path("excavator_machine"))


@pytest.fixture(scope="module")
def ranges(machine: Machine) -> WorkingRanges:
    return working_ranges(machine)


@pytest.fixture(scope="module")
def cloud(machine: Machine) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    pose = sweep(machine, N)
    assert pose.ok.all()
    return pose.tip, pose.bucket_angle, pose.lengths


def test_unconstrained_extremes(ranges: WorkingRanges, cloud) -> None:  # type: ignore[no-untyped-def]
    tip, _, _ = cloud
    for key, brute in (
        ("max_digging_reach", tip[:, 0].max()),
        ("max_digging_depth", -tip[:, 1].min()),
        ("max_cutting_height", tip[:, 1].max()),
    ):
        f = ranges.figure(key).value
        assert brute - 1e-9 <= f <= brute + 0.02, key


def test_reach_at_ground_line(ranges: WorkingRanges, cloud) -> None:  # type: ignore[no-untyped-def]
    tip, _, _ = cloud
    band = np.abs(tip[:, 1]) < 0.03
    brute = tip[band, 0].max()
    f = ranges.figure("max_reach_ground")
    assert abs(f.tip[1]) < 1e-9
    assert brute - 0.01 <= f.value <= brute + 0.05


@pytest.fixture(scope="module")
def fine(machine: Machine):  # type: ignore[no-untyped-def]
    lo, hi = machine.lengths_min, machine.lengths_max
    b, a, k = np.meshgrid(
        np.linspace(lo[0], hi[0], 81),
        np.linspace(lo[1], hi[1], 81),
        np.linspace(lo[2], hi[2], 81),
        indexing="ij",
    )
    return forward(machine, np.stack([b, a, k], axis=-1).reshape(-1, 3))


def test_hanging_bucket_figures(machine: Machine, ranges: WorkingRanges, fine) -> None:  # type: ignore[no-untyped-def]
    """Max dumping height: a dense 3-D sweep, keeping the poses within 1° of hanging."""
    f = ranges.figure("max_dumping_height")
    assert np.isclose(f.bucket_angle, -np.pi / 2, atol=1e-9)
    hang = np.abs(fine.bucket_angle + np.pi / 2) < np.radians(1.0)
    brute = fine.tip[hang, 1].max()
    # within 1° of hanging the tip is at most r·(1 − cos 1°) ≈ 0.2 mm higher
    assert brute - 1e-3 <= f.value <= brute + 0.03
    g = ranges.figure("min_dumping_height")
    hi = machine.lengths_max
    assert np.isclose(g.lengths[0], hi[0]) and np.isclose(g.lengths[1], hi[1])


def test_vertical_wall_depth(machine: Machine, ranges: WorkingRanges, fine) -> None:  # type: ignore[no-untyped-def]
    """AF: the deepest tip with the teeth (lip → tip, from the engine's points) within 0.5° of
    straight down, over a dense 3-D sweep; the reported pose has them exactly vertical."""
    f = ranges.figure("max_vertical_wall_depth")
    pose = forward(machine, f.lengths[None, :])
    teeth = pose.tip[0] - pose.lip[0]
    assert abs(np.arctan2(teeth[1], teeth[0]) + np.pi / 2) < 1e-9
    assert pose.within_stroke[0]
    d = fine.tip - fine.lip
    vertical = np.abs(np.arctan2(d[:, 1], d[:, 0]) + np.pi / 2) < np.radians(0.5)
    brute = -fine.tip[vertical, 1].min()
    # 0.5° of bucket turn moves the tip by at most r·0.5° ≈ 13 mm
    assert brute - 0.015 <= f.value <= brute + 0.03
    assert f.value < ranges.figure("max_digging_depth").value


def test_level_bottom(machine: Machine, ranges: WorkingRanges, cloud) -> None:  # type: ignore[no-untyped-def]
    """At the reported depth the sweep reaches both ends of a 2.44 m level cut (to within its
    resolution), and 5 cm deeper it spans less than 2.44 m."""
    tip, _, _ = cloud
    f = ranges.figure("level_bottom_depth")
    y = machine.ground_line - f.value
    ends = ranges.extra["level_bottom"]
    assert np.isclose(ends[1, 0] - ends[0, 0], machine.level_bottom)
    band = np.abs(tip[:, 1] - y) < 0.03
    assert tip[band, 0].max() - tip[band, 0].min() >= machine.level_bottom - 0.1
    deeper = np.abs(tip[:, 1] - (y - 0.05)) < 0.01
    assert tip[deeper, 0].max() - tip[deeper, 0].min() < machine.level_bottom
    assert f.value < ranges.figure("max_digging_depth").value


def test_envelope_contains_the_sweep(ranges: WorkingRanges, cloud) -> None:  # type: ignore[no-untyped-def]
    """Every swept tip lies inside the envelope or within its chord error (0.2 mm) of it."""
    tip, _, _ = cloud
    poly = shapely.Polygon(ranges.envelope)
    assert poly.is_valid and poly.exterior.is_ccw
    out = ~shapely.contains_xy(poly, tip[:, 0], tip[:, 1])
    if out.any():
        assert shapely.distance(shapely.points(tip[out]), poly.exterior).max() < 2e-4
    assert ranges.envelope[:, 0].max() <= ranges.figure("max_digging_reach").tip[0] + 1e-6
    assert ranges.envelope[:, 1].min() >= -ranges.figure("max_digging_depth").value - 1e-6


def test_envelope_is_the_reachable_boundary(machine: Machine, ranges: WorkingRanges) -> None:
    """Closed-form inverse kinematics, independent of the union construction: 5 mm inside
    each envelope vertex some bucket angle is reachable within the strokes; 0.5 mm outside
    none is (0.5 mm: the envelope's chord error is below 0.2 mm)."""
    env = ranges.envelope
    prev, nxt = np.roll(env, 1, axis=0), np.roll(env, -1, axis=0)
    d1, d2 = env - prev, nxt - env
    cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    turn = np.abs(np.arctan2(cross, np.einsum("ij,ij->i", d1, d2)))
    smooth = np.flatnonzero(turn < np.radians(10.0))
    pick = smooth[:: max(1, smooth.size // 150)]
    t = nxt[pick] - prev[pick]
    inward = np.stack([-t[:, 1], t[:, 0]], axis=-1) / np.hypot(t[:, 0], t[:, 1])[:, None]
    beta = np.linspace(-np.pi, np.pi, 6001)  # step 1 mrad: the window 5 mm in is wider

    def reachable(points: np.ndarray) -> np.ndarray:
        tips = np.repeat(points, beta.size, axis=0)
        sol = inverse(machine, tips, np.tile(beta, len(points)))
        return np.asarray(sol.valid.any(axis=1).reshape(len(points), -1).any(axis=1))

    assert reachable(env[pick] + 5e-3 * inward).all()
    assert not reachable(env[pick] - 5e-4 * inward).any()


def test_swept_region_of_a_long_edged_polygon() -> None:
    """The polar sweep against brute force: a 1 × 6 m rectangle turned 1 rad about the origin,
    as the union of 2001 turned copies (which can only fall short, by ≤ 6·(0.5 mrad)²/2)."""
    from shapely import affinity

    from excavkin.excavator.ranges import _swept

    box = shapely.box(1.0, -3.0, 2.0, 3.0)
    for swing in (1.0, -1.0):
        swept = _swept(box, np.zeros(2), swing)
        copies = shapely.unary_union(
            [
                affinity.rotate(box, t, origin=(0.0, 0.0), use_radians=True)
                for t in np.linspace(0.0, swing, 2001)
            ]
        )
        assert swept.is_valid
        assert abs(swept.area - copies.area) < 1e-3 * copies.area
        assert shapely.symmetric_difference(swept, copies).area < 5e-3  # of 16.3 m²
