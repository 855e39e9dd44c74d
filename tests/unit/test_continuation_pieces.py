"""Pieces of the Newton continuation's bookkeeping (`excavkin.kinematics.solve`) against
their plain definitions: each sample's nearest solved sample behind it, input differences the
shorter way round, and the samples taken out of a block."""

from __future__ import annotations

import numpy as np
import pytest

from excavkin.kinematics.solve import _at, _behind, _behind_each, wrapped_difference


@pytest.mark.parametrize("seed", range(20))
def test_behind_each_is_behind_for_every_sample(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 5000))
    k0 = int(rng.integers(0, n))
    picked = rng.choice(n, int(rng.integers(0, n)), replace=True)
    solved = np.unique(np.concatenate([[k0], picked]))
    np.testing.assert_array_equal(_behind_each(solved, n, k0), _behind(solved, np.arange(n), k0))


def test_behind_each_at_the_ends() -> None:
    """Only k0 solved: every sample starts from it; every sample solved: each from itself."""
    np.testing.assert_array_equal(_behind_each(np.array([3]), 7, 3), np.zeros(7))
    np.testing.assert_array_equal(_behind_each(np.arange(7), 7, 2), np.arange(7))


class _Plan:
    input_kinds = ("angle", "length")


def test_wrapped_difference_is_the_shorter_way_round() -> None:
    rng = np.random.default_rng(7)
    d = np.vstack([rng.uniform(-40.0, 40.0, 20_000), rng.uniform(-40.0, 40.0, 20_000)])
    d[0, :3] = [0.5, -np.pi, 1e-300]  # within ±π: left exactly as it is
    got = wrapped_difference(d, _Plan())  # type: ignore[arg-type]
    np.testing.assert_array_equal(got[1], d[1])  # a length is not wrapped
    np.testing.assert_array_equal(got[0, :3], d[0, :3])
    assert np.all(np.abs(got[0]) <= np.pi)
    turns = (d[0] - got[0]) / (2 * np.pi)
    np.testing.assert_allclose(turns, np.round(turns), rtol=0, atol=1e-12)
    ref = np.angle(np.exp(1j * d[0]))  # the same pose as the complex form's
    np.testing.assert_allclose(np.cos(got[0] - ref), 1.0, rtol=0, atol=1e-14)
    with np.errstate(invalid="ignore"):
        odd = wrapped_difference(np.array([[np.nan, np.inf], [1.0, 2.0]]), _Plan())  # type: ignore[arg-type]
    assert np.isnan(odd[0]).all()


def test_at_takes_samples_from_a_view_in_batch_last_layout() -> None:
    rng = np.random.default_rng(3)
    whole = rng.standard_normal((7, 2, 1000))
    block = whole[:, :, 200:600]
    idx = np.array([5, 0, 399, 17, 17])
    got = _at(block, idx)
    np.testing.assert_array_equal(got, np.take(block, idx, axis=-1))
    assert got.flags.c_contiguous
    assert np.shares_memory(_at(block, slice(3, 9)), whole)
