"""``columns=`` / ``--columns``: only the columns asked, each equal to the bit to the same
column of the whole table, in the model's order, with ``status``, their kinds and units."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
from click.testing import CliRunner

import excavkin
from excavkin.cli import main
from excavkin.errors import InputError, UnknownNameError
from excavkin.kinematics.columns import select_columns
from excavkin.outputs.tables import select_frame, write_table
from tests.conftest import EXAMPLES

FOURBAR = str(EXAMPLES / "fourbar.toml")
ASKED = ["B.*", "*.x", "crank.*"]


def _same_bits(got: pd.DataFrame, want: pd.DataFrame) -> None:
    """The same columns in the same order, floats equal bit for bit (NaN included)."""
    assert list(got.columns) == list(want.columns)
    for name in got.columns:
        a, b = got[name].to_numpy(), want[name].to_numpy()
        if a.dtype.kind == "f":
            np.testing.assert_array_equal(a.view(np.int64), b.view(np.int64), err_msg=name)
        else:
            assert list(map(str, a)) == list(map(str, b)), name


def _expected(names: list[str]) -> list[str]:
    """What ASKED selects, written out by hand from the four-bar's column names."""
    out = []
    for n in names:
        owner, _, qty = n.rpartition(".")
        if n == "status" or owner == "B" or qty == "x" or owner == "crank":
            out.append(n)
    return out


def test_select_columns_keeps_the_tables_order_and_status() -> None:
    names = ["t", "A.x", "A.y", "B.x", "B.vx", "crank.value", "crank.rate", "status"]
    assert select_columns(names, ["crank.*", "A.x", "B.*"]) == [
        "A.x", "B.x", "B.vx", "crank.value", "crank.rate", "status",
    ]  # fmt: skip
    assert select_columns(names, ["*.x", "A.x"]) == ["A.x", "B.x", "status"]  # each once
    assert select_columns(names, "t") == ["t", "status"]  # one name, not its letters
    assert select_columns(names, ["?.y"]) == ["A.y", "status"]


def test_an_unknown_column_names_the_nearest_and_an_empty_selection_is_refused() -> None:
    names = ["A.x", "B.x", "B.vx", "status"]
    with pytest.raises(UnknownNameError, match=r"no column 'B\.xx'; did you mean 'B\.x'"):
        select_columns(names, ["B.x", "B.xx"])
    with pytest.raises(UnknownNameError, match=r"no column 'C\.\*'"):
        select_columns(names, ["C.*"])
    with pytest.raises(InputError, match="at least one column"):
        select_columns(names, [])


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_selected_columns_are_the_whole_tables_to_the_bit(backend: str) -> None:
    mech = excavkin.load(FOURBAR)
    q = np.linspace(0.0, 7.0, 2001)
    result = mech.solve({"crank": q}, {"crank": 2.0}, time=q / 2.0, backend=backend)  # type: ignore[arg-type]
    whole = result.to_frame()
    got = result.to_frame(columns=ASKED)
    assert list(got.columns) == _expected(list(whole.columns))
    assert "t" not in got and got.columns[-1] == "status"
    _same_bits(got, whole[list(got.columns)])
    assert got.attrs["excavkin.kinds"] == {
        c: k for c, k in whole.attrs["excavkin.kinds"].items() if c in got
    }
    assert got.attrs["excavkin.model"] == whole.attrs["excavkin.model"]
    _same_bits(select_frame(whole, ASKED), got)


def test_force_columns_are_selected_after_the_kinematic_ones() -> None:
    mech = excavkin.load(FOURBAR)
    forces = mech.solve({"crank": np.linspace(0.0, 6.0, 301)}, {"crank": 3.0}, loads="model")
    whole = forces.to_frame()
    got = forces.to_frame(columns=["*.Fx", "B.x", "crank.torque"])
    names = [c for c in whole.columns if c.endswith(".Fx")]
    assert list(got.columns) == ["B.x", *names, "crank.torque", "status"]
    _same_bits(got, whole[list(got.columns)])
    only = forces.to_frame(kinematics=False, columns=["crank.torque"])
    assert list(only.columns) == ["crank.torque"]
    with pytest.raises(UnknownNameError, match="crank.torqe"):
        forces.to_frame(columns=["crank.torqe"])


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_the_writers_write_only_the_columns_asked(tmp_path: Path, suffix: str) -> None:
    mech = excavkin.load(FOURBAR)
    whole = mech.solve({"crank": np.linspace(0.0, 6.0, 501)}).to_frame()
    out = write_table(whole, tmp_path / f"s{suffix}", columns=ASKED)
    want = write_table(whole[_expected(list(whole.columns))], tmp_path / f"w{suffix}")
    if suffix == ".csv":
        assert out.read_bytes() == want.read_bytes()
    else:
        meta = pq.read_schema(out).metadata
        kinds = json.loads(meta[b"excavkin.kinds"])
        assert list(kinds) == _expected(list(whole.columns))[:-1]
        assert json.loads(meta[b"excavkin.units"])["B.vx"] == "m/s"
        _same_bits(pd.read_parquet(out), pd.read_parquet(want))
    bad = tmp_path / f"bad{suffix}"
    with pytest.raises(UnknownNameError):
        write_table(whole, bad, columns=["nope"])
    assert sorted(tmp_path.iterdir()) == sorted([out, want])  # nothing else, no leftovers


def test_a_stream_of_selected_columns_is_the_whole_selection() -> None:
    mech = excavkin.load(FOURBAR)
    q = np.linspace(0.0, 9.0, 20_000)
    parts = list(mech.solve_stream({"crank": q}, size=4096, columns=ASKED))
    assert len(parts) > 1 and all(p.columns == tuple(ASKED) for p in parts)
    streamed = pd.concat([p.to_frame() for p in parts], ignore_index=True)
    whole = mech.solve({"crank": q}).to_frame()
    _same_bits(streamed, whole[_expected(list(whole.columns))])
    # the result gives the columns asked alone: the others were not kept
    assert list(parts[0].result.to_frame().columns) == list(streamed.columns)
    with pytest.raises(AttributeError, match="positions"):
        parts[0].result.positions  # noqa: B018
    with pytest.raises(UnknownNameError, match="B.q"):
        next(iter(mech.solve_stream({"crank": q}, size=4096, columns=["B.q"])))


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_solve_columns_on_the_command_line(tmp_path: Path, suffix: str) -> None:
    runner = CliRunner()
    common = ["solve", FOURBAR, "--sweep", "crank=0deg:720deg:3001", "-q", "--units-row"]
    whole_path, sel_path = tmp_path / f"w{suffix}", tmp_path / f"s{suffix}"
    r = runner.invoke(main, [*common, "-o", str(whole_path)])
    assert r.exit_code == 0, r.output
    r = runner.invoke(main, [*common, "-o", str(sel_path), "--columns", "B.*, *.x,crank.*"])
    assert r.exit_code == 0, r.output
    if suffix == ".csv":  # the header and the units row: those of the columns asked
        heads = [p.read_text().splitlines()[:2] for p in (whole_path, sel_path)]
        (names_w, units_w), (names_s, units_s) = ([h.split(",") for h in hs] for hs in heads)
        assert names_s == _expected(names_w)
        assert units_s == [units_w[names_w.index(n)] for n in names_s]
        assert units_s[names_s.index("B.vx")] == "m/s"
        whole = pd.read_csv(whole_path, skiprows=[1])
        got = pd.read_csv(sel_path, skiprows=[1])
    else:
        whole, got = pd.read_parquet(whole_path), pd.read_parquet(sel_path)
    assert list(got.columns) == _expected(list(whole.columns))
    assert f"× {got.shape[1]} columns" in r.output
    _same_bits(got, whole[got.columns])


@pytest.mark.parametrize(
    ("asked", "message"),
    [
        ("B.xx", "error: --columns: no column 'B.xx'; did you mean 'B.x'"),
        ("B.x,,A.x", "--columns 'B.x,,A.x': name columns"),
        ("Z*", "error: --columns: no column 'Z*'"),
    ],
)
def test_solve_refuses_an_unknown_column_and_writes_nothing(
    tmp_path: Path, asked: str, message: str
) -> None:
    out = tmp_path / "o.parquet"
    r = CliRunner().invoke(
        main, ["solve", FOURBAR, "--sweep", "crank=0:1:5", "-q", "-o", str(out), "--columns", asked]
    )
    assert r.exit_code == 2, r.output
    assert message in r.output and "Traceback" not in r.output
    assert list(tmp_path.iterdir()) == []
