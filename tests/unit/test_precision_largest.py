"""The precision check's scales: the compiled pass of `largest` gives NumPy's number, NaN
passed over, infinities, signed zeros, samples left out and strided views included."""

from __future__ import annotations

import numpy as np
import pytest

from excavkin.kinematics import precision


def numpy_largest(arr: np.ndarray, use: np.ndarray) -> float:
    per = np.fmax.reduce(np.abs(arr), axis=0)[use]
    return float(np.nanmax(per, initial=0.0))


@pytest.mark.parametrize("seed", range(6))
def test_the_compiled_largest_equals_numpys(seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("EXCAVKIN_COMPILED", raising=False)
    rng = np.random.default_rng(seed)
    n = precision.LARGEST_COMPILE_AT + 5
    whole = rng.normal(scale=10.0 ** rng.integers(-3, 4), size=(7, 2 * n))
    arr = whole[1:6, ::2]  # a strided view, as a block of a larger solve is
    arr[rng.random(arr.shape) < 0.05] = np.nan
    arr[:, rng.integers(0, n, 20)] = np.nan  # whole samples failed
    arr[0, 3] = -0.0
    if seed % 2:
        arr[2, rng.integers(0, n)] = -np.inf
    use = rng.random(n) < (0.99 if seed < 3 else 0.02)
    top = arr[:, use]
    assert precision.largest(arr, use) == numpy_largest(arr, use)
    assert precision.largest(arr, use) == float(np.nanmax(np.abs(top), initial=0.0))
    assert precision.largest(arr, np.zeros(n, dtype=bool)) == 0.0
    assert precision.largest(np.full((2, n), np.nan), use) == 0.0
    # the wider type takes NumPy's path, to the same number
    wide = arr.astype(np.longdouble)
    assert precision.largest(wide, use) == numpy_largest(arr, use)


def test_numpy_alone_where_compiling_is_off(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("EXCAVKIN_COMPILED", "0")
    arr = np.array([[1.0, -3.0, np.nan], [2.0, np.nan, -7.0]])
    assert precision.largest(arr, np.array([True, True, False])) == 3.0


def random_arrays(rng: np.random.Generator, n: int, dtype: type) -> precision.Arrays:
    """A solution of ``n`` samples of 3 points, 2 bodies, 2 elements and a transmission
    angle, with NaN (values and whole samples), infinities and signed zeros."""
    from excavkin.kinematics.result import Derived

    def some(*shape: int) -> np.ndarray:
        arr = rng.normal(scale=10.0 ** rng.integers(-3, 4), size=(*shape, n))
        arr[rng.random(arr.shape) < 0.05] = np.nan
        arr.reshape(-1, n)[:, rng.integers(0, n, 3)] = np.nan
        arr.reshape(-1)[rng.integers(0, arr.size, 2)] = -0.0
        arr.reshape(-1)[rng.integers(0, arr.size)] = -np.inf
        return arr.astype(dtype)

    return precision.Arrays(
        some(3, 2), some(3, 2), some(3, 2), some(1), Derived(some(3, 2), some(6, 2))
    )


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("dtype", [np.float64, np.longdouble])
def test_the_runs_tops_are_each_runs_tops(seed: int, dtype: type) -> None:
    """`runs_tops` of consecutive runs gives, for each run, `tops` of that run alone: the
    same numbers, for every kind, runs of one sample, runs with no sample used and an
    empty run included."""
    rng = np.random.default_rng(seed)
    counts = [1, 5, 0, 40, 17, 3, 60]
    n = sum(counts)
    arrays = random_arrays(rng, n, dtype)
    use = rng.random(n) < 0.8
    use[1:6] = False  # the second run: none used
    got = precision.runs_tops(arrays, use, counts)
    start = 0
    for c, mine in zip(counts, got, strict=True):
        part = slice(start, start + c)
        a = arrays
        here = precision.Arrays(
            a.x[..., part], a.v[..., part], a.a[..., part], a.trans[:, part],
            type(a.derived)(a.derived.body[..., part], a.derived.element[..., part]),
        )  # fmt: skip
        assert mine == precision.tops(here, use[part])
        start += c
    assert got[1] == dict.fromkeys(precision.KINDS, 0.0)
    assert got[2] == dict.fromkeys(precision.KINDS, 0.0)
    assert any(v > 0.0 for v in got[3].values())


def test_the_nudges_signs_are_each_blocks_own_draw() -> None:
    """Each block's signs, taken from one draw of the longest block's, are those drawn anew
    for that block alone."""
    counts = [3, 1, 700, 64, 0, 65536, 9]
    for seed in (1, 2):
        got = precision.nudge_signs(seed, counts)
        want = [np.random.default_rng(seed).choice([-1.0, 1.0], c) for c in counts]
        np.testing.assert_array_equal(got, np.concatenate(want))
    assert precision.nudge_signs(1, []).size == 0
