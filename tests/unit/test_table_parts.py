"""A table as a folder of Parquet parts (`excavkin.outputs.table_parts`): the same table as
one file, its rows in order, made whole or not at all, and a user's folder never replaced."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

import excavkin
from excavkin.cli import main
from excavkin.io.files import OutputError
from excavkin.outputs.table_parts import PART, check_parts_target, write_parts
from excavkin.outputs.tables import write_tables
from excavkin.sweeps import Linspace


@pytest.fixture(scope="module")
def pieces() -> list[pd.DataFrame]:
    """The four-bar's table in 7 parts of uneven length."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    sweep = {"crank": Linspace(0.0, 6.0 * np.pi, 5_000)}
    frames = [part.to_frame() for part in mech.solve_stream(sweep, size=977)]
    assert len(frames) == 6
    return [*frames, frames[-1].iloc[:0]]  # an empty part too


def test_the_parts_are_the_table_written_as_one_file(
    pieces: list[pd.DataFrame], tmp_path: Path
) -> None:
    folder = write_parts(pieces, tmp_path / "t", threads=3)
    write_tables(pieces, tmp_path / "one.parquet")
    assert sorted(os.listdir(folder)) == [PART.format(k) for k in range(len(pieces))]
    parts, one = pq.read_table(folder), pq.read_table(tmp_path / "one.parquet")
    assert parts.equals(one)
    assert parts.schema.metadata == one.schema.metadata  # units, kinds and model kept
    assert pd.read_parquet(folder).equals(pd.read_parquet(tmp_path / "one.parquet"))


def test_threads_change_no_byte(pieces: list[pd.DataFrame], tmp_path: Path) -> None:
    a = write_parts(pieces, tmp_path / "a", threads=1)
    b = write_parts(pieces, tmp_path / "b", threads=4)
    for k in range(len(pieces)):
        assert (a / PART.format(k)).read_bytes() == (b / PART.format(k)).read_bytes()


def test_columns_select_in_every_part(pieces: list[pd.DataFrame], tmp_path: Path) -> None:
    folder = write_parts(pieces, tmp_path / "t", columns=["B.*"], threads=2)
    table = pd.read_parquet(folder)
    assert list(table.columns) == ["B.x", "B.y", "B.vx", "B.vy", "B.ax", "B.ay",
                                   "B.transmission", "status"]  # fmt: skip
    assert np.array_equal(table["B.x"], pd.concat(pieces)["B.x"])


def _failing(pieces: list[pd.DataFrame], after: int) -> Iterator[pd.DataFrame]:
    yield from pieces[:after]
    raise RuntimeError("the solve stopped")


@pytest.mark.parametrize("after", [0, 1, 4])
def test_a_stopped_stream_leaves_nothing(
    pieces: list[pd.DataFrame], tmp_path: Path, after: int
) -> None:
    with pytest.raises(RuntimeError, match="the solve stopped"):
        write_parts(_failing(pieces, after), tmp_path / "t", threads=2)
    assert os.listdir(tmp_path) == []


def test_a_stopped_stream_keeps_the_folder_it_would_replace(
    pieces: list[pd.DataFrame], tmp_path: Path
) -> None:
    folder = write_parts(pieces[:2], tmp_path / "t")
    before = {p.name: p.read_bytes() for p in folder.iterdir()}
    with pytest.raises(RuntimeError):
        write_parts(_failing(pieces, 3), folder, force=True)
    assert {p.name: p.read_bytes() for p in folder.iterdir()} == before
    assert sorted(os.listdir(tmp_path)) == ["t"]


def test_force_replaces_a_folder_of_parts(pieces: list[pd.DataFrame], tmp_path: Path) -> None:
    folder = write_parts(pieces, tmp_path / "t")
    with pytest.raises(OutputError, match="exists; pass --force"):
        write_parts(pieces[:1], folder)
    write_parts(pieces[:2], folder, force=True)
    assert sorted(os.listdir(folder)) == [PART.format(0), PART.format(1)]
    assert sorted(os.listdir(tmp_path)) == ["t"]


def test_a_users_folder_or_file_is_never_replaced(
    pieces: list[pd.DataFrame], tmp_path: Path
) -> None:
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep")
    (mine / PART.format(0)).write_text("not a part")
    with pytest.raises(OutputError, match="holds other files than a table's parts"):
        write_parts(pieces, mine, force=True)
    assert (mine / "notes.txt").read_text() == "keep"
    a_file = tmp_path / "file"
    a_file.write_text("keep")
    with pytest.raises(OutputError, match="not a folder"):
        write_parts(pieces, a_file, force=True)
    assert a_file.read_text() == "keep"


@pytest.mark.parametrize(
    ("name", "message"),
    [("t.csv", "parts are Parquet"), ("missing/t", "does not exist")],
)
def test_targets_refused_before_any_work(tmp_path: Path, name: str, message: str) -> None:
    with pytest.raises(OutputError, match=message):
        check_parts_target(tmp_path / name, force=True)


def test_no_part_other_columns_or_bad_threads(pieces: list[pd.DataFrame], tmp_path: Path) -> None:
    with pytest.raises(OutputError, match="no table to write"):
        write_parts([], tmp_path / "t")
    with pytest.raises(OutputError, match="other columns"):
        write_parts([pieces[0], pieces[1].iloc[:, :3]], tmp_path / "t")
    for threads in (0, 1.5, True):
        with pytest.raises(OutputError, match="threads must be a whole number"):
            write_parts(pieces, tmp_path / "t", threads=threads)  # type: ignore[arg-type]
    assert os.listdir(tmp_path) == []


def test_a_killed_runs_folder_is_removed_by_the_next_write(
    pieces: list[pd.DataFrame], tmp_path: Path
) -> None:
    gone = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)  # fmt: skip
    leftover = tmp_path / f".t.excavkin-{int(gone.stdout)}.tmp"
    leftover.mkdir()
    (leftover / PART.format(0)).write_bytes(b"half")
    write_parts(pieces[:1], tmp_path / "t")
    assert sorted(os.listdir(tmp_path)) == ["t"]


@settings(max_examples=25, deadline=None)
@given(st.lists(st.integers(0, 1_300), min_size=1, max_size=6), st.integers(1, 4))
def test_any_cut_of_a_table_reads_back_whole(cuts: list[int], threads: int) -> None:
    import tempfile

    rng = np.random.default_rng(len(cuts))
    total = sum(cuts)
    frame = pd.DataFrame({"a.x": rng.normal(size=total), "status": ["ok"] * total})
    frame.attrs["excavkin.kinds"] = {"a.x": "length"}
    at = np.cumsum([0, *cuts])
    frames = [frame.iloc[a:b] for a, b in zip(at[:-1], at[1:], strict=True)]
    for f in frames:
        f.attrs = frame.attrs
    with tempfile.TemporaryDirectory() as tmp:
        folder = write_parts(frames, Path(tmp) / "t", threads=threads)
        back = pd.read_parquet(folder)
    assert len(back) == total
    assert np.array_equal(back["a.x"], frame["a.x"])
    assert list(back["status"]) == ["ok"] * total


def test_the_command_writes_parts(tmp_path: Path) -> None:
    runner = CliRunner()
    args = ["solve", "fourbar", "--sweep", "crank=0deg:360deg:3000", "-q"]
    done = runner.invoke(main, [*args, "-o", str(tmp_path / "t"), "--parts"])
    assert done.exit_code == 0, done.output
    assert "3000 samples × 38 columns" in done.output
    runner.invoke(main, [*args, "-o", str(tmp_path / "one.parquet")])
    assert pq.read_table(tmp_path / "t").equals(pq.read_table(tmp_path / "one.parquet"))
    again = runner.invoke(main, [*args, "-o", str(tmp_path / "t"), "--parts"])
    assert again.exit_code == 2
    assert again.output.strip().endswith("exists; pass --force to replace it")
    csv_row = runner.invoke(main, [*args, "-o", str(tmp_path / "u"), "--parts", "--units-row"])
    assert csv_row.exit_code == 2
    assert "--units-row is a CSV header row" in csv_row.output
    assert sorted(os.listdir(tmp_path)) == ["one.parquet", "t"]
