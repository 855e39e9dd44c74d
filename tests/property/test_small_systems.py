"""The batched LU of the Newton groups against LAPACK, sample by sample.

Random batches of well- and ill-conditioned matrices (condition numbers up to 1e14, built as
U·diag(s)·Vᵀ from a seeded generator): the solution agrees with ``numpy.linalg.solve`` to a
few units of round-off times the condition number, the backward error is a few units of
round-off (in double and in long double), the signed Hadamard ratio agrees with ``slogdet``
over the rows' norms, and a singular, zero-row or NaN sample is flagged without touching its
neighbours.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from excavkin.kinematics.small_systems import Factors

EPS = float(np.finfo(np.float64).eps)


def batch(seed: int, m: int, n: int, log_cond: float, dtype: type = np.float64) -> np.ndarray:
    """n random m×m matrices, shape (m, m, n), each with 2-norm condition 10**log_cond and
    rows of unequal sizes (the row scaling is part of what the factorisation handles)."""
    rng = np.random.default_rng(seed)
    out = np.empty((m, m, n), dtype=dtype)
    for j in range(n):
        u, _ = np.linalg.qr(rng.standard_normal((m, m)))
        v, _ = np.linalg.qr(rng.standard_normal((m, m)))
        s = np.logspace(0.0, -log_cond, m) if m > 1 else np.ones(1)
        rows = np.exp(rng.uniform(-3.0, 3.0, m))[:, None]
        out[:, :, j] = rows * (u * s) @ v.T
    return out


def by_sample(a: np.ndarray) -> np.ndarray:
    """(m, m, n) → (n, m, m), LAPACK's layout."""
    return np.ascontiguousarray(np.moveaxis(a, -1, 0))


def hadamard(a: np.ndarray) -> np.ndarray:
    """det / ∏ row norms, by slogdet, per sample."""
    sign, logdet = np.linalg.slogdet(by_sample(a))
    rows = np.linalg.norm(by_sample(a), axis=2)
    return sign * np.exp(logdet - np.log(rows).sum(axis=1))  # type: ignore[no-any-return]


sizes = st.integers(1, 9)
seeds = st.integers(0, 2**32 - 1)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(seed=seeds, m=sizes, n=st.integers(1, 40), log_cond=st.floats(0.0, 14.0))
def test_solutions_agree_with_lapack_to_round_off_times_the_condition(
    seed: int, m: int, n: int, log_cond: float
) -> None:
    a = batch(seed, m, n, log_cond)
    b = np.random.default_rng(seed + 1).standard_normal((m, n))
    lu = Factors(a)
    x = lu.solve(b)
    want = np.linalg.solve(by_sample(a), by_sample(b[:, None, :]))[..., 0].T
    cond = np.linalg.cond(by_sample(a))
    # forward error of a backward-stable solve: a few m·eps·cond, for ours and LAPACK's alike
    err = np.abs(x - want).max(axis=0) / np.abs(want).max(axis=0)
    assert (err <= 16 * m * EPS * cond).all(), (err / (EPS * cond)).max()
    ratio = hadamard(a)
    assert (np.sign(lu.ratio) == np.sign(ratio)).all()
    np.testing.assert_allclose(lu.ratio, ratio, rtol=16 * m * EPS * cond.max(), atol=0)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(seed=seeds, m=sizes, n=st.integers(1, 30), log_cond=st.floats(0.0, 14.0))
def test_backward_error_is_round_off_in_double_and_in_long_double(
    seed: int, m: int, n: int, log_cond: float
) -> None:
    for dtype in (np.float64, np.longdouble):
        eps = float(np.finfo(dtype).eps)
        a = batch(seed, m, n, log_cond, dtype)
        b = np.random.default_rng(seed + 2).standard_normal((m, n)).astype(dtype)
        x = Factors(a).solve(b)
        assert x.dtype == dtype
        resid = b - np.einsum("ijn,jn->in", a, x)
        # normwise backward error, row by row (the rows' scales differ by e⁶)
        size = np.abs(a).sum(axis=1) * np.abs(x).max(axis=0) + np.abs(b)
        eta = (np.abs(resid) / size).max(axis=0).astype(np.float64)
        assert (eta <= 32 * m * eps).all(), (dtype, (eta / eps).max())


@settings(max_examples=30, deadline=None, derandomize=True)
@given(seed=seeds, m=st.integers(2, 8), n=st.integers(1, 20), k=st.integers(1, 4))
def test_many_right_hand_sides_and_a_subset_of_samples(seed: int, m: int, n: int, k: int) -> None:
    a = batch(seed, m, n, 3.0)
    b = np.random.default_rng(seed + 3).standard_normal((m, k, n))
    lu = Factors(a)
    x = lu.solve(b)
    for col in range(k):  # each right-hand side alone, to the bit
        np.testing.assert_array_equal(x[:, col], lu.solve(b[:, col]))
    keep = np.random.default_rng(seed + 4).random(n) < 0.5
    np.testing.assert_array_equal(lu.at(keep).solve(b[..., keep]), x[..., keep])
    np.testing.assert_array_equal(lu.at(keep).ratio, lu.ratio[keep])
    # factoring in place gives the same factors
    again = Factors(a.copy(), overwrite=True)
    np.testing.assert_array_equal(again.solve(b), x)
    np.testing.assert_array_equal(again.ratio, lu.ratio)


def test_singular_samples_are_flagged_and_leave_their_neighbours_alone() -> None:
    m = 6
    a = batch(7, m, 6, 2.0)
    a[3, :, 1] = a[1, :, 1]  # two equal rows
    a[2, :, 2] = 0.0  # a zero row
    a[:, 4, 3] = 0.0  # a zero column
    a[0, 0, 4] = np.nan  # not a number
    # rank m − 1 by construction: the last singular value is zero
    u, _ = np.linalg.qr(np.random.default_rng(8).standard_normal((m, m)))
    a[:, :, 5] = (u * np.r_[np.ones(m - 1), 0.0]) @ u.T
    b = np.ones((m, 6))
    lu = Factors(a)
    assert lu.ratio[0] != 0.0 and abs(lu.ratio[0]) > 1e-6
    assert lu.ratio[1] == 0.0 and lu.ratio[2] == 0.0 and lu.ratio[3] == 0.0
    assert np.isnan(lu.ratio[4])
    assert abs(lu.ratio[5]) < 64 * EPS  # rounding leaves a trace, far below any tolerance
    # the caller's test: not (|ratio| ≥ tol) catches zero, tiny and NaN alike
    assert (~(np.abs(lu.ratio) >= 1e-13) == [False, True, True, True, True, True]).all()
    x = lu.solve(b)
    # every sample is its own: alone it gives the same bits
    for j in range(6):
        alone = Factors(a[..., j : j + 1]).solve(b[:, j : j + 1])[:, 0]
        np.testing.assert_array_equal(alone, x[:, j])
    want = np.linalg.solve(a[..., 0], b[:, 0])  # condition 100
    np.testing.assert_allclose(x[:, 0], want, rtol=0, atol=1e-12 * np.abs(want).max())


def test_pivoting_is_partial_on_the_scaled_rows() -> None:
    """A tiny leading entry is not a pivot: without exchanges this system loses every digit."""
    a = np.array([[1e-20, 1.0], [1.0, 1.0]])[:, :, None]
    b = np.array([1.0, 2.0])[:, None]
    x = Factors(a).solve(b)[:, 0]
    np.testing.assert_allclose(x, np.linalg.solve(a[..., 0], b[:, 0]), rtol=1e-15)
    # rows scaled by their norms first: a row's size does not make it the pivot
    big = np.array([[1e30, 1e30 * 1e-3], [1.0, 1.0]])[:, :, None]
    x = Factors(big).solve(np.array([1e30, 2.0])[:, None])[:, 0]
    np.testing.assert_allclose(x, np.linalg.solve(big[..., 0], [1e30, 2.0]), rtol=1e-14)
