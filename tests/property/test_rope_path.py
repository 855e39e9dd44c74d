"""Random ropes over sheaves: the closed-form length, its rate and its acceleration against a
root-finding construction of the tangents in 40-digit arithmetic, for paths of one to three
sheaves wrapped either way (seeded)."""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from excavkin.step_kinds.rope_path import rope_path, sketch_wraps
from tests.crossmethod.test_rope_sheaves import mp_length


def random_path(seed: int) -> tuple[list[tuple[float, float]], list[float]]:
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 6))  # 1 to 3 sheaves
    angles = np.sort(rng.uniform(0.0, 2 * np.pi, n))
    radius = rng.uniform(2.0, 5.0, n)
    pts = [
        (float(r * np.cos(a)), float(r * np.sin(a))) for r, a in zip(radius, angles, strict=True)
    ]
    signs = rng.choice([-1.0, 1.0], n)
    sizes = rng.uniform(0.05, 0.4, n)
    signed = [0.0, *(float(s * r) for s, r in zip(signs[1:-1], sizes[1:-1], strict=True)), 0.0]
    return pts, signed


@pytest.mark.parametrize("seed", range(12))
def test_random_paths_against_mpmath(seed: int) -> None:
    pts, signed = random_path(seed)
    wraps0 = sketch_wraps(pts, signed)
    geo = rope_path([(np.array([x]), np.array([y])) for x, y in pts], signed, wraps0)
    assert np.isfinite(geo.length).all()
    rng = np.random.default_rng(100 + seed)
    vel, acc = rng.standard_normal((len(pts), 2)), rng.standard_normal((len(pts), 2))
    msigned = [mp.mpf(s) for s in signed]

    def length(t):  # type: ignore[no-untyped-def]
        moved = [
            (mp.mpf(x) + t * vel[k, 0] + t * t / 2 * acc[k, 0],
             mp.mpf(y) + t * vel[k, 1] + t * t / 2 * acc[k, 1])
            for k, (x, y) in enumerate(pts)
        ]  # fmt: skip
        return mp_length(moved, msigned)

    assert float(geo.length[0]) == pytest.approx(float(length(0)), rel=1e-14)
    v = [(np.array([a]), np.array([b])) for a, b in vel]
    a = [(np.array([p]), np.array([q])) for p, q in acc]
    d1, d2 = mp.diff(length, 0), mp.diff(length, 0, 2)
    assert float(geo.rate(v)[0]) == pytest.approx(float(d1), rel=1e-12, abs=1e-13)
    scale = max(abs(float(d2)), 1.0)
    assert abs(float((geo.rate(a) + geo.curvature(v))[0]) - float(d2)) < 1e-11 * scale
