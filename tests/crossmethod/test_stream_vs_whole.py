"""A sweep solved part by part (``Mechanism.solve_stream``) equals the sweep solved whole
(``Mechanism.solve``) to the bit: values, status, error estimates and change points, forces,
design parameters and sensitivities, Newton groups, the smooth continuation. Small parts force
many of them; sweeps longer than a block (``BLOCK``) cross the places where precision scales,
change-point searches and Newton continuations hand over."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import excavkin
from excavkin.kinematics.result import KinematicResult
from excavkin.kinematics.solve import BLOCK
from excavkin.sweeps import Linspace, grid
from tests.models import parallelogram

FOURBAR = excavkin.example_path("fourbar")


@pytest.fixture(autouse=True)
def _one_path(monkeypatch: pytest.MonkeyPatch) -> None:
    """Whole and parts on the NumPy path, whatever their sizes and whatever kernels an earlier
    test compiled: a large sweep would otherwise take the compiled loop and its parts NumPy,
    whose arctan2 (vectorised) may differ from libm's in the last bit."""
    monkeypatch.setenv("EXCAVKIN_COMPILED", "0")


def _arrays(res: KinematicResult) -> dict[str, np.ndarray]:
    out = {c.name: np.asarray(arr) for c, arr in res._columns()}
    out["status.code"] = res.status.code
    out["status.step"] = res.status.step
    if res.error_estimate is not None:
        out["error_estimate"] = res.error_estimate
    return out


def assert_same(whole: KinematicResult, parts: list[excavkin.mechanism.SolvedPart]) -> None:
    """The parts put together are the whole, bit for bit (NaN where NaN)."""
    assert [p.start for p in parts] == list(np.cumsum([0] + [len(p.result) for p in parts])[:-1])
    assert parts[-1].stop == len(whole) == parts[0].total
    kin = [getattr(p.result, "kinematics", p.result) for p in parts]
    want = _arrays(whole)
    got = [_arrays(k) for k in kin]
    assert set(got[0]) == set(want)
    for name, arr in want.items():
        joined = np.concatenate([g[name] for g in got])
        np.testing.assert_array_equal(joined, arr, err_msg=name, strict=True)
    found = [cp for k in kin for cp in k.change_points]
    order = [c.point for c in whole.change_points]
    found.sort(key=lambda cp: order.index(cp.point))  # plan order, then samples
    assert found == list(whole.change_points)


def test_kinematics_over_blocks_and_small_parts() -> None:
    mech = excavkin.load(FOURBAR)
    n = 2 * BLOCK + 12345
    q = {"crank": Linspace(0.0, 6.0 * np.pi, n)}
    rate = {"crank": Linspace(1.0, 5.0, n)}
    whole = mech.solve({"crank": np.asarray(q["crank"])}, rate, time=np.arange(n) * 1e-3)
    assert whole.status.all_ok
    for size in (1000, BLOCK, 3 * BLOCK):
        parts = list(mech.solve_stream(q, rate, time=np.arange(n) * 1e-3, size=size))
        assert max(len(p.result) for p in parts) <= size
        assert_same(whole, parts)


def test_compiled_parts_equal_the_compiled_whole() -> None:
    """The compiled loop too: parts of any size equal the whole to the bit."""
    pytest.importorskip("numba")
    mech = excavkin.load(FOURBAR)
    n = 2 * BLOCK + 12345
    q = {"crank": Linspace(0.0, 6.0 * np.pi, n)}
    rate = {"crank": Linspace(1.0, 5.0, n)}
    whole = mech.solve({"crank": np.asarray(q["crank"])}, rate, backend="numba")
    for size in (1000, BLOCK + 7):
        parts = list(mech.solve_stream(q, rate, size=size, backend="numba"))
        assert_same(whole, parts)


def test_failures_and_a_flagged_sample_across_a_block_boundary() -> None:
    """The MO-100 through its change point (θ = 0) exactly where one block ends: samples flagged
    for lost precision on both sides, a dead position, and a change point across the boundary;
    non-finite inputs and a refused length in other parts."""
    mech = excavkin.load(excavkin.example_path("mo100_hammer"))
    name = mech.inputs[0]
    n = BLOCK + 5000
    th = (np.arange(n) - BLOCK) * 2.5e-5  # θ = 0 at the first sample of the second block
    th[7] = np.nan
    th[BLOCK + 4000] = np.inf
    whole = mech.solve({name: th})
    codes = set(whole.status.code[BLOCK - 100 : BLOCK + 100].tolist())
    assert {0, 9}.issubset(codes)  # ok and "rates lose precision" either side of the boundary
    assert [(cp.before, cp.after) for cp in whole.change_points] == [(BLOCK - 1, BLOCK + 1)]
    assert whole.status.code[BLOCK] == 2  # exactly dead
    for size in (977, BLOCK):
        assert_same(whole, list(mech.solve_stream({name: th}, size=size)))


def test_change_points_across_parts_and_the_smooth_continuation() -> None:
    """A parallelogram turning three times: change points fall in several blocks; the smooth
    continuation's passes (anchor, flips) give the same as the whole."""
    mech = excavkin.Mechanism(parallelogram())
    n = 2 * BLOCK + 999
    q = np.linspace(-0.3, 6 * np.pi, n)
    for continuation in ("side", "smooth"):
        whole = mech.solve({"crank": q}, continuation=continuation)
        assert len(whole.change_points) >= 4
        parts = list(mech.solve_stream({"crank": q}, continuation=continuation, size=BLOCK // 4))
        assert_same(whole, parts)


def test_a_change_point_exactly_across_parts() -> None:
    """The fold between the last sample of one block and the first of the next is found by the
    part holding the later sample."""
    mech = excavkin.Mechanism(parallelogram())
    n = BLOCK + 10
    # the crank passes 0 (A meets O4: a jump) or π (folded flat: a bend) between samples
    # BLOCK − 1 and BLOCK; the samples near it lose precision, on both sides
    for at, shape in ((0.0, "jump"), (np.pi, "bend")):
        q = at + (np.arange(n) - BLOCK + 0.5) * 1e-6
        whole = mech.solve({"crank": q})
        assert [(c.before, c.after, c.shape) for c in whole.change_points] == [
            (BLOCK - 1, BLOCK, shape)
        ]
        assert (whole.status.code[BLOCK - 5 : BLOCK + 5] == 9).all()
        parts = list(mech.solve_stream({"crank": q}, size=BLOCK))
        assert [len(p.result.change_points) for p in parts] == [0, 1]
        assert_same(whole, parts)


def test_forces_designs_and_sensitivities() -> None:
    mech = excavkin.load(FOURBAR)
    n = BLOCK + 3000
    rng = np.random.default_rng(5)
    q = rng.uniform(0, 2 * np.pi, n)
    ab = rng.uniform(0.115, 0.125, n)
    ab[11] = -1.0  # a design that builds no mechanism
    kwargs = {
        "params": {"A-B": ab, "rocker.mass": 0.6},
        "sensitivities": ["A-B", "O4.x"],
        "loads": "model",
    }
    whole = mech.solve({"crank": q}, {"crank": 30.0}, **kwargs)
    assert whole.kinematics.status.code[11] == 10
    parts = list(mech.solve_stream({"crank": q}, {"crank": 30.0}, size=4096, **kwargs))
    assert_same(whole.kinematics, parts)
    got = pd.concat([p.result.to_frame() for p in parts], ignore_index=True)
    want = whole.to_frame()
    assert list(got.columns) == list(want.columns)
    assert any(c.startswith("d(") and c.endswith("/d(A-B)") for c in got.columns)
    for frame in (got, want):  # categories differ from part to part
        frame["status"] = frame["status"].astype(str)
    pd.testing.assert_frame_equal(got, want, check_exact=True)


@pytest.mark.parametrize("method", ["newton", "closed-form"])
def test_newton_groups_carry_their_continuation_across_blocks(method: str) -> None:
    """The generic solver continues along the sweep block after block, from the last sample
    the block before reached; solved in parts it gives the same."""
    model = excavkin.load(FOURBAR).model
    mech = excavkin.Mechanism(model, method=method)  # type: ignore[arg-type]
    n = BLOCK + 1000
    q = np.linspace(0.2, 0.6, n)  # (Newton is slow: a short sweep, a few stages a block)
    whole = mech.solve({"crank": q}, params={"O4-B": np.linspace(0.089, 0.091, n)})
    assert whole.status.all_ok
    parts = list(
        mech.solve_stream({"crank": q}, params={"O4-B": np.linspace(0.089, 0.091, n)}, size=30000)
    )
    assert_same(whole, parts)
    if method == "newton":  # the same mechanism as the closed form, to round-off
        closed = excavkin.Mechanism(model).solve(
            {"crank": q}, params={"O4-B": np.linspace(0.089, 0.091, n)}
        )
        np.testing.assert_allclose(whole.positions, closed.positions, atol=1e-12)


def test_grid_parts_are_the_product_of_the_sweeps() -> None:
    a, b, c = Linspace(0.0, 1.0, 7), Linspace(-2.0, 3.0, 5), np.array([0.5, 0.25, 1e-3])
    cols = grid(a, b, c)
    mesh = np.meshgrid(np.linspace(0.0, 1.0, 7), np.linspace(-2.0, 3.0, 5), c, indexing="ij")
    for col, want in zip(cols, mesh, strict=True):
        flat = want.ravel()
        assert col.size == flat.size == 105
        np.testing.assert_array_equal(np.asarray(col), flat, strict=True)
        for s in range(0, 105, 13):
            np.testing.assert_array_equal(col.values(s, min(s + 13, 105)), flat[s : s + 13])


finite = st.floats(
    allow_nan=False, allow_infinity=False, width=64, min_value=-1e300, max_value=1e300
)


@settings(max_examples=300, deadline=None)
@given(start=finite, stop=finite, n=st.integers(1, 3000), cut=st.integers(0, 3000))
def test_a_linspace_made_in_parts_is_numpys(start: float, stop: float, n: int, cut: int) -> None:
    lin = Linspace(start, stop, n)
    want = np.linspace(start, stop, n)
    cut = min(cut, n)
    got = np.concatenate([lin.values(0, cut), lin.values(cut, n)])
    np.testing.assert_array_equal(got, want, strict=True)


def test_lists_and_memmaps_are_inputs_too(tmp_path) -> None:  # type: ignore[no-untyped-def]
    mech = excavkin.load(FOURBAR)
    q = np.linspace(0.0, 7.0, 3000)
    path = tmp_path / "q.bin"
    q.tofile(path)
    mapped = np.memmap(path, dtype=np.float64, mode="r", shape=(3000,))
    whole = mech.solve({"crank": q.tolist()})
    assert_same(whole, list(mech.solve_stream({"crank": mapped}, size=700)))
    assert_same(whole, list(mech.solve_stream({"crank": q.tolist()}, size=700)))
    # the inputs are checked when asked for, before any part is
    with pytest.raises(excavkin.InputError, match="did you mean 'crank'"):
        mech.solve_stream({"crnk": q})
    with pytest.raises(excavkin.InputError, match="different lengths"):
        mech.solve_stream({"crank": q}, {"crank": q[:5]})
