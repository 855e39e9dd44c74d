"""Tables written fast and whole: CSV text that reads back to the same doubles, Parquet with
its units, a table streamed part by part equal to the table written at once, and nothing left
behind when a stream stops."""

from __future__ import annotations

import io
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import excavkin
from excavkin.kinematics.solve import BLOCK
from excavkin.outputs.tables import TableWriter, write_table, write_tables

FOURBAR = excavkin.example_path("fourbar")


def _digits(text: str) -> str:
    """The significant digits of a number's text."""
    mantissa = re.split("[eE]", text.lstrip("-"))[0].replace(".", "")
    return mantissa.lstrip("0").rstrip("0") or "0"


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(allow_nan=False, allow_infinity=False), min_size=1, max_size=300))
def test_csv_floats_are_the_shortest_text_of_the_same_double(tmp_path_factory, values) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path_factory.mktemp("csv") / "f.csv"
    values = np.array(values, dtype=np.float64)
    write_table(pd.DataFrame({"x": values, "y": values[::-1]}), out, force=True)
    lines = out.read_text().splitlines()
    assert lines[0] == "x,y" and len(lines) == values.size + 1
    for line, want in zip(lines[1:], values, strict=True):
        text = line.split(",")[0]
        got = float(text)
        assert got == want and math.copysign(1.0, got) == math.copysign(1.0, want), text
        assert _digits(text) == _digits(repr(float(want))), (text, repr(float(want)))
        assert re.search(r"[.eE]", text), text  # a float to every reader, never an integer
    back = pd.read_csv(out)
    assert back["x"].dtype == np.float64
    np.testing.assert_array_equal(back["x"].to_numpy(), values)


def test_csv_text_as_pandas_wrote_it(tmp_path: Path) -> None:
    """NaN an empty field, infinities as inf and -inf, headers and labels as they are (quoted
    only where needed), a units row when asked; read back, the same table as pandas' own."""
    frame = pd.DataFrame(
        {
            "A.x": [0.5, np.nan, np.inf, -np.inf, -0.0],
            "B.vy": [1.0, 2.0, 3.0, 4.0, 5.0],
            "status": pd.Categorical(["ok", "ok", "x, y", 'say "no"', "ok"]),
        }
    )
    frame.attrs["excavkin.kinds"] = {"A.x": "length", "B.vy": "velocity"}
    out = tmp_path / "t.csv"
    write_table(frame, out, units_row=True)
    lines = out.read_text().splitlines()
    assert lines[:2] == ["A.x,B.vy,status", "m,m/s,"]
    assert lines[2:] == [
        "0.5,1.0,ok",
        ",2.0,ok",
        'inf,3.0,"x, y"',
        '-inf,4.0,"say ""no"""',
        "-0.0,5.0,ok",
    ]
    ours = pd.read_csv(out, skiprows=[1])
    theirs = pd.read_csv(io.StringIO(frame.to_csv(index=False)))
    pd.testing.assert_frame_equal(ours, theirs, check_exact=True)
    plain = frame.iloc[[0, 1, 4]]
    write_table(plain, out, force=True)
    assert out.read_text().splitlines() == [
        "A.x,B.vy,status",
        "0.5,1.0,ok",
        ",2.0,ok",
        "-0.0,5.0,ok",
    ]


def test_a_table_without_rows(tmp_path: Path) -> None:
    """A table of no rows (a run without shocks): its header, and its columns in Parquet."""
    frame = pd.DataFrame({"t": np.array([], dtype=float), "what": np.array([], dtype=object)})
    write_table(frame, tmp_path / "e.csv")
    assert (tmp_path / "e.csv").read_text() == "t,what\n"
    write_table(frame, tmp_path / "e.parquet")
    assert list(pd.read_parquet(tmp_path / "e.parquet").columns) == ["t", "what"]
    with pytest.raises(excavkin.errors.ExcavkinError, match="no table"):
        write_tables([], tmp_path / "none.parquet")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["e.csv", "e.parquet"]


def _stream(size: int, **kwargs) -> tuple[excavkin.KinematicResult, list]:  # type: ignore[type-arg, no-untyped-def]
    mech = excavkin.load(FOURBAR)
    q = np.linspace(0.0, 12.0, BLOCK + 4321)
    q[100] = np.nan  # a failing sample
    whole = mech.solve({"crank": q}, {"crank": 3.0}, **kwargs)
    parts = mech.solve_stream({"crank": q}, {"crank": 3.0}, size=size, **kwargs)
    return whole, parts  # type: ignore[return-value]


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_a_streamed_table_is_the_table_written_whole(tmp_path: Path, suffix: str) -> None:
    whole, parts = _stream(5000, loads="model")
    at_once, streamed = tmp_path / f"whole{suffix}", tmp_path / f"parts{suffix}"
    write_table(whole.to_frame(), at_once, units_row=True)
    write_tables((p.result.to_frame() for p in parts), streamed, units_row=True)
    if suffix == ".csv":
        assert streamed.read_bytes() == at_once.read_bytes()
        return
    a, b = pq.read_table(at_once), pq.read_table(streamed)
    assert a.equals(b) and a.schema.metadata == b.schema.metadata
    assert pq.ParquetFile(streamed).metadata.num_row_groups > 10
    meta = b.schema.metadata
    units = __import__("json").loads(meta[b"excavkin.units"])
    assert units["A.x"] == "m" and units["crank.torque"] == "N*m" and units["status"] == ""
    assert meta[b"excavkin.model"] == b"crank-rocker four-bar" or meta[b"excavkin.model"]
    assert __import__("json").loads(meta[b"excavkin.kinds"])["B.ay"] == "acceleration"
    back = pd.read_parquet(streamed)
    assert list(back.columns) == list(whole.to_frame().columns)
    assert back["status"].iloc[100] == "input is NaN or infinite"


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_frames_converted_and_written_on_threads_make_the_file_of_one_thread(
    tmp_path: Path, suffix: str
) -> None:
    """The frames made Arrow arrays on one thread and encoded on another, side by side: the
    file's bytes are those of writing each frame in turn, in this thread."""
    _, parts = _stream(3000, loads="model")
    frames = [p.result.to_frame() for p in parts]
    staged, plain = tmp_path / f"staged{suffix}", tmp_path / f"plain{suffix}"
    write_tables(iter(frames), staged, units_row=True)
    with TableWriter(plain, parquet=suffix == ".parquet", units_row=True) as out:
        for frame in frames:
            out.write(frame)
    assert out.rows == sum(len(f) for f in frames) == BLOCK + 4321
    assert staged.read_bytes() == plain.read_bytes()


def test_a_part_with_other_columns_is_named_and_leaves_no_file(tmp_path: Path) -> None:
    _, parts = _stream(20000)
    frames = [p.result.to_frame() for p in parts]
    frames[2] = frames[2].drop(columns=["B.x"])
    for suffix in (".parquet", ".csv"):
        target = tmp_path / f"t{suffix}"
        with pytest.raises(excavkin.errors.ExcavkinError, match="other columns"):
            write_tables(iter(frames), target)
        assert not list(tmp_path.iterdir())


def test_a_stream_that_stops_leaves_no_file(tmp_path: Path) -> None:
    """An error while the table is made: no file, no temporary file, whatever was written."""
    whole, parts = _stream(2000)
    target = tmp_path / "t.parquet"

    def frames():  # type: ignore[no-untyped-def]
        for k, p in enumerate(parts):
            if k == 5:
                raise RuntimeError("stopped")
            yield p.result.to_frame()

    for suffix in (".parquet", ".csv"):
        target = tmp_path / f"t{suffix}"
        with pytest.raises(RuntimeError, match="stopped"):
            write_tables(frames(), target)
        assert not target.exists() and not list(tmp_path.iterdir())
        _, parts = _stream(2000)


def test_to_frame_makes_no_copy() -> None:
    """The table's columns are the result's arrays (views), forces too."""
    mech = excavkin.load(FOURBAR)
    res = mech.solve({"crank": np.linspace(0.0, 6.0, 1000)}, loads="model")
    frame = res.to_frame()
    for name, arr in (
        ("A.x", res.kinematics.positions),
        ("rocker.omega", res.kinematics.body_omega),
        ("crank.torque", res.driver_torque),
        ("B.rocker.Fx", res.pin_force),
    ):
        assert np.shares_memory(frame[name].to_numpy(), arr), name
    kin = res.kinematics.to_frame()
    assert np.shares_memory(kin["B.ay"].to_numpy(), res.kinematics.accelerations)
    assert list(kin["status"].cat.categories) == ["ok"]
