"""The compiled kernels' arctangent (``excavkin.kinematics.fast_atan2``) against 50-digit
arithmetic, and equal to ``math.atan2`` at every special value."""

from __future__ import annotations

import itertools
import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from excavkin.kinematics import compiled, fast_atan2

numba = pytest.importorskip("numba")
_scalar = fast_atan2.compiled()


@pytest.fixture(scope="module")
def batch() -> object:
    f = _scalar

    @numba.njit
    def run(y: np.ndarray, x: np.ndarray) -> np.ndarray:  # pragma: no cover
        out = np.empty(x.size)
        for i in range(x.size):
            out[i] = f(y[i], x[i])
        return out

    return run


def _points(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Every octant at any size, the whole exponent range, and the reduction's seam
    (|y| / |x| near 1/2) and its far side (near 1)."""
    rng = np.random.default_rng(7)
    th = rng.uniform(-np.pi, np.pi, n)
    r = 10.0 ** rng.uniform(-8, 8, n)
    wide_x = 10.0 ** rng.uniform(-300, 300, n) * rng.choice([-1, 1], n)
    wide_y = 10.0 ** rng.uniform(-300, 300, n) * rng.choice([-1, 1], n)
    seam_x = rng.uniform(-1, 1, n)
    seam_y = seam_x * rng.choice([0.5, 1.0], n) * (1 + rng.uniform(-1e-3, 1e-3, n))
    subnormal = rng.uniform(-1, 1, n) * 1e-310
    x = np.concatenate([r * np.cos(th), wide_x, seam_x, subnormal, seam_y])
    y = np.concatenate([r * np.sin(th), wide_y, seam_y, subnormal[::-1], seam_x])
    return y, x


def test_within_two_units_in_the_last_place(batch) -> None:
    y, x = _points(4000)
    got = batch(y, x)
    mp.mp.dps = 50
    worst = 0.0
    for yi, xi, gi in zip(y.tolist(), x.tolist(), got.tolist(), strict=True):
        exact = mp.atan2(mp.mpf(yi), mp.mpf(xi))
        ulp = math.ulp(abs(float(exact))) if exact else 5e-324
        worst = max(worst, float(abs(mp.mpf(gi) - exact)) / ulp)
    assert worst <= 2.0, worst
    # against NumPy (the NumPy path's arctan2): within 4 units, i.e. 1e-15 of an angle's scale
    ref = np.arctan2(y, x)
    assert np.all(np.abs(got - ref) <= 4 * np.spacing(np.abs(ref)))


def test_special_values_as_math_atan2(batch) -> None:
    special = [0.0, -0.0, 1.0, -1.0, 0.5, -2.0, math.inf, -math.inf, math.nan, 5e-324, -5e-324,
               2.2e-308, 1e308, -1.7976931348623157e308, 1e300, 3e-300]  # fmt: skip
    pairs = list(itertools.product(special, special))
    got = batch(np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs]))
    for (y, x), g in zip(pairs, got.tolist(), strict=True):
        want = math.atan2(y, x)
        if math.isnan(want):
            assert math.isnan(g), (y, x, g)
            continue
        assert math.copysign(1.0, g) == math.copysign(1.0, want), (y, x, g, want)
        assert abs(g - want) <= 2 * math.ulp(want), (y, x, g, want)


def test_the_generated_kernel_calls_no_libm_arctangent() -> None:
    import excavkin

    plan = excavkin.load(excavkin.example_path("excavator")).plan
    text = compiled.source(plan)
    assert "math.atan2" not in text
    assert text.count(f"{fast_atan2.NAME}(") == 1 + 12  # its definition, and twelve angles


@settings(max_examples=3000, deadline=None)
@given(
    st.floats(allow_nan=True, allow_infinity=True), st.floats(allow_nan=True, allow_infinity=True)
)
def test_any_pair_of_doubles_as_math_atan2(y: float, x: float) -> None:
    """Any two doubles, NaN and infinities included: NaN where math.atan2 gives NaN, else its
    sign and within 2 units in the last place of it."""
    got = _scalar(y, x)
    want = math.atan2(y, x)
    if math.isnan(want):
        assert math.isnan(got)
        return
    assert math.copysign(1.0, got) == math.copysign(1.0, want)
    assert abs(got - want) <= 2 * math.ulp(want) + 2 * 5e-324
