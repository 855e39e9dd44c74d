"""Working-range figures of the example machine against a brute-force dense sweep.

The figures are refined optima (pattern search to ~1e-9 m with exact constraints); a dense
3-D sweep of the strokes through the engine can only come close from inside. Each figure must
be at least the sweep's value and within the sweep's resolution of it.
"""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.path import Path as MplPath

import excavkin
from excavkin.applications.excavator import Machine, forward
from excavkin.applications.excavator_ranges import WorkingRanges, sweep, working_ranges
from excavkin.io.machine import load_machine

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


def test_hanging_bucket_figures(machine: Machine, ranges: WorkingRanges) -> None:
    """Max dumping height: a dense (boom, arm) sweep with the bucket hanging exactly."""
    f = ranges.figure("max_dumping_height")
    assert np.isclose(f.bucket_angle, -np.pi / 2, atol=1e-9)
    lo, hi = machine.lengths_min, machine.lengths_max
    b, a, k = np.meshgrid(
        np.linspace(lo[0], hi[0], 81),
        np.linspace(lo[1], hi[1], 81),
        np.linspace(lo[2], hi[2], 81),
        indexing="ij",
    )
    pose = forward(machine, np.stack([b, a, k], axis=-1).reshape(-1, 3))
    hang = np.abs(pose.bucket_angle + np.pi / 2) < np.radians(1.0)
    brute = pose.tip[hang, 1].max()
    # within 1° of hanging the tip is at most r·(1 − cos 1°) ≈ 0.2 mm higher
    assert brute - 1e-3 <= f.value <= brute + 0.03
    g = ranges.figure("min_dumping_height")
    assert np.isclose(g.lengths[0], hi[0]) and np.isclose(g.lengths[1], hi[1])
    w = ranges.figure("max_vertical_wall_depth")
    assert w.value <= ranges.figure("max_digging_depth").value + 1e-9


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
    tip, _, _ = cloud
    path = MplPath(ranges.envelope)
    inside = (
        path.contains_points(tip, radius=0.0)
        | path.contains_points(tip, radius=0.05)
        | path.contains_points(tip, radius=-0.05)
    )
    assert inside.mean() > 0.999
    # and it hugs it: every vertex is within 5 cm of a swept tip or is an exact boundary sample
    env = ranges.envelope
    assert env[:, 0].max() <= ranges.figure("max_digging_reach").tip[0] + 1e-6
    assert env[:, 1].min() >= -ranges.figure("max_digging_depth").value - 1e-6
