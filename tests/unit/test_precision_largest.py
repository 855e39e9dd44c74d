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
