"""``solve_stream(..., columns=...)`` solves only the columns asked (issue 28, item 4): the
compiled kernel writes out their rows alone, yet every column asked and every sample's status,
error estimate and change point equal the full solve's to the bit — the status is the whole
sample's, whatever the columns asked. The rows not asked are never written, and a part's
result refuses them by name."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import excavkin
from excavkin.errors import InputError, UnknownNameError
from excavkin.kinematics import compiled
from excavkin.kinematics import solve as solve_module
from excavkin.kinematics.selection import SelectedResult, asked_names, kept_rows, resting_rows
from excavkin.kinematics.solve import BLOCK
from excavkin.kinematics.vectorise import written_rows
from excavkin.mechanism import SolvedPart
from tests.models import parallelogram

FOURBAR = excavkin.example_path("fourbar")


def _same(whole: excavkin.KinematicResult, parts: list[SolvedPart], asked: list[str]) -> None:
    """The parts' tables are the whole's columns asked, bit for bit, and every status, failed
    step, error estimate and change point is the whole's."""
    got = pd.concat([p.to_frame() for p in parts], ignore_index=True)
    want = whole.to_frame(columns=asked)
    assert list(got.columns) == list(want.columns)
    for name in want.columns:
        a, b = got[name].to_numpy(), want[name].to_numpy()
        if name == "status":
            assert (a == b).all()
        else:
            np.testing.assert_array_equal(a.view(np.int64), b.view(np.int64), err_msg=name)
    for field in ("code", "step"):
        joined = np.concatenate([getattr(p.result.status, field) for p in parts])
        np.testing.assert_array_equal(joined, getattr(whole.status, field), strict=True)
    error = np.concatenate([p.result.error_estimate for p in parts])
    assert whole.error_estimate is not None
    np.testing.assert_array_equal(error, whole.error_estimate, strict=True)
    found = [cp for p in parts for cp in p.result.change_points]
    order = [c.point for c in whole.change_points]
    found.sort(key=lambda cp: order.index(cp.point))
    assert found == list(whole.change_points)


#: what the arrays of a solve of some columns hold before it (`marked`)
MARK = 12345.0

Arrays = dict[str, np.ndarray]


@pytest.fixture
def marked(monkeypatch: pytest.MonkeyPatch) -> list[Arrays]:
    """The arrays of every solve of some columns, each holding `MARK` before it where its
    kernel may write (never zero, as no solved value would be): a row that still holds it
    after was not written."""
    made = solve_module._unwritten
    out: list[Arrays] = []

    def marking(plan, n, rows, rest):  # type: ignore[no-untyped-def]
        ws = made(plan, n, rows, rest)
        arrays = {"x": ws.x, "v": ws.v, "a": ws.a, "trans": ws.trans}
        arrays |= {"body": ws.derived.body, "element": ws.derived.element}
        for name, lead in rows:
            arrays[name][lead] = MARK
        out.append(arrays)
        return ws

    monkeypatch.setattr(solve_module, "_unwritten", marking)
    return out


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_flagged_dead_and_bad_samples_across_a_block_boundary(
    backend: str, marked: list[Arrays]
) -> None:
    """The MO-100 through its change point where a block ends: samples flagged imprecise on
    both sides (checked against their blocks' scales, solved again whole), a dead one, a NaN
    and an infinite input; positions asked alone, whose status reads the rates. No row is
    written out but those asked and the transmission angles."""
    if backend == "numba":
        pytest.importorskip("numba")
    mech = excavkin.load(excavkin.example_path("mo100_hammer"))
    name = mech.inputs[0]
    n = BLOCK + 5000
    th = (np.arange(n) - BLOCK) * 2.5e-5
    th[7] = np.nan
    th[BLOCK + 4000] = np.inf
    whole = mech.solve({name: th}, backend=backend)
    assert {0, 2, 9}.issubset(set(whole.status.code.tolist()))
    assert len(whole.change_points) == 1
    asked = ["B.x", "B.y"]
    for size, chunk in ((BLOCK, None), (2 * BLOCK, 3000)):  # (3000: chunks of 2048)
        parts = list(
            mech.solve_stream({name: th}, size=size, columns=asked, backend=backend, chunk=chunk)
        )
        _same(whole, parts, asked)
    if backend == "numpy":
        assert not marked
        return
    plan = mech.plan
    rows, n_rows = written_rows(compiled.kernel_source(plan, keep=True))
    keep = kept_rows(plan, rows, n_rows, set(asked))
    b = plan.points.index("B")
    angles = {("trans", (i,)) for i in range(len(plan.transmissions))}
    assert {key for key, row in rows.items() if keep[row]} == {
        ("x", (b, 0)),
        ("x", (b, 1)),
    } | angles
    assert len(marked) == 3  # (two parts of a block, then one of two)
    for arrays in marked:
        for (array, lead), row in rows.items():
            assert (arrays[array][lead] == MARK).all() != bool(keep[row]), (array, lead)
    assert not (whole.accelerations == MARK).any()


def test_the_fourbar_compiled_whole_and_parts() -> None:
    pytest.importorskip("numba")
    mech = excavkin.load(FOURBAR)
    n = 2 * BLOCK + 12345
    q = np.linspace(0.0, 6.0 * np.pi, n)
    rate = {"crank": np.linspace(1.0, 5.0, n)}
    whole = mech.solve({"crank": q}, rate, time=np.arange(n) * 1e-3, backend="numba")
    for asked in (["B.ax", "rocker.omega", "t"], ["*.transmission"], ["crank.*", "O4.vx"]):
        parts = list(
            mech.solve_stream({"crank": q}, rate, time=np.arange(n) * 1e-3, size=BLOCK,
                              columns=asked, backend="numba")
        )  # fmt: skip
        _same(whole, parts, asked)


def test_a_family_of_designs_one_column_of_constants_a_sample() -> None:
    pytest.importorskip("numba")
    mech = excavkin.load(FOURBAR)
    n = BLOCK + 3000
    q = {"crank": np.linspace(0.0, 4.0 * np.pi, n)}
    params = {"O4-B": np.linspace(0.05, 0.2, n)}  # some designs cannot close
    whole = mech.solve(q, params=params, backend="numba")
    assert not whole.status.all_ok
    asked = ["A.y", "rocker.epsilon", "design.*"]
    for chunk in (None, 3000):  # (chunks of 2048 samples: a block's scales from 32 shares)
        parts = list(
            mech.solve_stream(q, params=params, columns=asked, backend="numba", chunk=chunk)
        )
        _same(whole, parts, asked)


def test_the_excavator() -> None:
    pytest.importorskip("numba")
    mech = excavkin.load(excavkin.example_path("excavator"))
    n = BLOCK + 2000
    rng = np.random.default_rng(28)
    values = {}
    for k, v in mech.sketch_values().items():  # about the sketch; some out of reach
        span = 0.3 if mech.input_kind(k) == "angle" else 0.5 * v
        values[k] = v + span * (rng.random(n) - 0.5)
    rates = {name: rng.normal(0.0, 0.05, n) for name in mech.inputs}
    whole = mech.solve(values, rates, backend="numba")
    assert 0.5 < whole.status.ok.mean() < 1.0
    driven = [f"{mech.inputs[0]}.value", f"{mech.inputs[1]}.rate"]  # (their inputs, exactly)
    for asked in (["Q.*", "bucket.omega", "L.transmission", *driven], ["W.ay"]):
        parts = list(mech.solve_stream(values, rates, columns=asked, backend="numba"))
        _same(whole, parts, asked)


def test_change_points_read_their_rows() -> None:
    """A parallelogram turning three times (jumps and bends across blocks): its change points
    read positions and velocities that were not asked."""
    pytest.importorskip("numba")
    mech = excavkin.Mechanism(parallelogram())
    n = 2 * BLOCK + 999
    q = np.linspace(-0.3, 6 * np.pi, n)
    whole = mech.solve({"crank": q}, backend="numba")
    assert len(whole.change_points) >= 4
    name = mech.plan.points[-1]
    asked = [f"{name}.ax"]
    parts = list(mech.solve_stream({"crank": q}, size=BLOCK, columns=asked, backend="numba"))
    _same(whole, parts, asked)


def test_a_change_point_exactly_across_parts() -> None:
    """The fold between the last sample of one block and the first of the next (a jump, then
    a bend), with the samples about it imprecise: found from the tail the block before hands
    on, its rows not asked."""
    pytest.importorskip("numba")
    mech = excavkin.Mechanism(parallelogram())
    n = BLOCK + 10
    for at in (0.0, np.pi):
        q = {"crank": at + (np.arange(n) - BLOCK + 0.5) * 1e-6}
        whole = mech.solve(q, backend="numba")
        assert len(whole.change_points) == 1 and (whole.status.code == 9).any()
        asked = ["crank.angle"]
        parts = list(mech.solve_stream(q, size=BLOCK, columns=asked, backend="numba"))
        assert [len(p.result.change_points) for p in parts] == [0, 1]
        _same(whole, parts, asked)


def test_newton_groups_keep_the_full_solve() -> None:
    """A plan with a Newton group solves every column (no compiled kernel of some), and gives
    the columns asked all the same."""
    model = excavkin.load(FOURBAR).model
    mech = excavkin.Mechanism(model, method="newton")
    n = BLOCK + 1000
    q = {"crank": np.linspace(0.2, 0.6, n)}
    whole = mech.solve(q)
    asked = ["B.vx", "rocker.angle"]
    parts = list(mech.solve_stream(q, size=30000, columns=asked))
    assert all(isinstance(p.result, SelectedResult) for p in parts)
    _same(whole, parts, asked)


def test_rows_kept_are_the_columns_and_the_checks() -> None:
    mech = excavkin.load(FOURBAR)
    plan = mech.plan
    rows, n_rows = written_rows(compiled.kernel_source(plan, keep=True))
    every = kept_rows(plan, rows, n_rows, asked_names(plan, ["*"]), change_points=False)
    assert every.sum() == len(rows)  # every written row holds some column
    keep = kept_rows(plan, rows, n_rows, {"B.ax"}, change_points=False)
    assert np.flatnonzero(keep).tolist() == [rows[("a", (plan.points.index("B"), 0))]]
    # a driven length's or a fixed point's columns are no row's: the fixed point's rates are
    # zero, made so where asked
    assert not kept_rows(plan, rows, n_rows, {"crank.value", "O2.vx"}, False).any()
    o2 = plan.points.index("O2")
    rest = resting_rows(plan, rows, {"O2.vx", "O2.ay", "B.x"})
    assert sorted(rest) == [("a", (o2, 1)), ("v", (o2, 0))]
    assert resting_rows(plan, rows, {"O2.x", "B.x", "crank.value"}) == []
    # the change points read the transmission angles (and solve a block again where a dyad
    # not kept comes near flat)
    checks = kept_rows(plan, rows, n_rows, set(), change_points=True)
    assert np.flatnonzero(checks).tolist() == sorted(
        rows[("trans", (i,))] for i in range(len(plan.transmissions))
    )


def test_a_selected_result_refuses_what_was_not_asked() -> None:
    mech = excavkin.load(FOURBAR)
    q = {"crank": np.linspace(0.0, 6.0, 5000)}
    part = next(iter(mech.solve_stream(q, columns=["B.*"])))
    res = part.result
    assert isinstance(res, SelectedResult) and len(res) == 5000
    assert res.names == ("B.x", "B.y", "B.vx", "B.vy", "B.ax", "B.ay", "B.transmission")
    assert [c.name for c in res.columns] == list(res.names)
    assert list(res.to_frame(columns=["B.x"]).columns) == ["B.x", "status"]
    np.testing.assert_array_equal(res.column("B.vx"), res.columns_named(["B.vx"])["B.vx"])
    with pytest.raises(AttributeError, match="positions: this result was solved for the col"):
        res.positions  # noqa: B018
    with pytest.raises(AttributeError, match="point"):
        res.point("B")
    for refuse in (lambda: res.column("A.x"), lambda: res.columns_named(["B.x", "A.x"])):
        with pytest.raises(InputError, match="column 'A.x' was not solved"):
            refuse()
    with pytest.raises(InputError, match="column 'A.x' was not solved"):
        res.to_frame(columns=["A.x"])
    with pytest.raises(UnknownNameError, match="nope"):
        res.column("nope")
    assert res.rows(10, 20).to_frame().shape == (10, 8)
    assert res.status.all_ok and "crank" in res.describe_sample(3)
    # sensitivities (and forces) solve every column: the part keeps the whole result
    part = next(iter(mech.solve_stream(q, columns=["B.x"], sensitivities=["O4-B"])))
    assert isinstance(part.result, excavkin.KinematicResult)
    assert list(part.to_frame().columns) == ["B.x", "status"]
