"""``excavkin solve`` streams its table: the file equals the whole result's table, the checks
that decide whether it is kept come at the end with the whole result's words, and a run
stopped halfway leaves neither the file nor a temporary one."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

import excavkin
from excavkin.cli import main
from excavkin.cli.input_table import InputTable, read_inputs
from excavkin.kinematics.solve import BLOCK
from excavkin.outputs.tables import write_table
from tests.conftest import EXAMPLES

FOURBAR = str(EXAMPLES / "fourbar.toml")


@pytest.fixture
def small_parts(monkeypatch: pytest.MonkeyPatch) -> None:
    """Parts of 4 096 samples, so that a short sweep streams in many."""
    monkeypatch.setattr(excavkin.mechanism, "PART_BYTES", 8 * 76 * 4096)


def _run(*args: str) -> object:
    return CliRunner().invoke(main, list(args))


@pytest.mark.usefixtures("small_parts")
@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_the_streamed_file_is_the_whole_results_table(tmp_path: Path, suffix: str) -> None:
    n = BLOCK + 9000
    out = tmp_path / f"f{suffix}"
    r = _run(
        "solve", FOURBAR, "--sweep", f"crank=0deg:1000deg:{n}", "--rate", "crank=3rad/s",
        "--forces", "--units-row", "-q", "-o", str(out),
    )  # fmt: skip
    assert r.exit_code == 0, r.output  # type: ignore[attr-defined]
    assert f"wrote {n} samples × 57 columns" in r.output  # type: ignore[attr-defined]
    mech = excavkin.load(FOURBAR)
    q = np.linspace(0.0, np.radians(1000.0), n)
    whole = mech.solve({"crank": q}, {"crank": 3.0}, loads=mech.loads)
    want = tmp_path / f"w{suffix}"
    write_table(whole.to_frame(), want, units_row=True)
    if suffix == ".csv":
        assert out.read_bytes() == want.read_bytes()
    else:
        import pyarrow.parquet as pq

        assert pq.read_table(out).equals(pq.read_table(want))
        assert pq.read_schema(out).metadata == pq.read_schema(want).metadata
        assert pq.ParquetFile(out).metadata.num_row_groups > 10
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([out.name, want.name])


@pytest.mark.usefixtures("small_parts")
def test_the_smooth_continuation_streamed_from_a_table_of_inputs(tmp_path: Path) -> None:
    """--continuation smooth goes over the inputs several times (here a table read in
    batches, from its start each time): the file is the whole smooth result's table, and the
    change points are warned of in its order."""
    model = tmp_path / "p.toml"  # a parallelogram: a change point every half turn
    model.write_text(
        Path(FOURBAR)
        .read_text()
        .replace("A  = [0, 40]", "A  = [0, 100]")
        .replace("B  = [110, 90]", "B  = [100, 100]")
        .replace('"A-B"  = 120', '"A-B"  = 100')
        .replace('"O4-B" = 90', '"O4-B" = 100')
    )
    mech = excavkin.load(model)
    n = BLOCK + 5000
    q = np.linspace(-0.3, 4 * np.pi, n)
    source = tmp_path / "in.parquet"
    pd.DataFrame({"crank": q}).to_parquet(source)
    out = tmp_path / "s.csv"
    r = _run("solve", str(model), "--inputs", str(source), "--continuation", "smooth", "-q",
             "--keep-going", "-o", str(out))  # fmt: skip
    assert r.exit_code == 0, r.output  # type: ignore[attr-defined]
    whole = mech.solve({"crank": q}, continuation="smooth")
    assert len(whole.change_points) >= 3
    warned = [line for line in r.output.splitlines() if "change point" in line]  # type: ignore[attr-defined]
    assert warned == [f"excavkin: warning: {cp.describe()}" for cp in whole.change_points]
    want = tmp_path / "w.csv"
    write_table(whole.to_frame(), want)
    assert out.read_bytes() == want.read_bytes()


@pytest.mark.usefixtures("small_parts")
def test_failing_samples_are_told_as_the_whole_result_tells_them(tmp_path: Path) -> None:
    """A non-Grashof four-bar fails in many parts: without --keep-going nothing is written,
    with the whole result's summary; with it, the same words as a warning and the file."""
    model = tmp_path / "nongrashof.toml"
    model.write_text(Path(FOURBAR).read_text().replace('"O4-B" = 90', '"O4-B" = 90\n"O2-A" = 95'))
    n = 3 * 4096 + 17
    out = tmp_path / "x.csv"
    args = ["solve", str(model), "--sweep", f"crank=0deg:720deg:{n}", "-q", "-o", str(out)]
    whole = excavkin.load(model).solve({"crank": np.linspace(0.0, np.radians(720.0), n)})
    assert not whole.status.all_ok
    r = _run(*args)
    assert r.exit_code == 3  # type: ignore[attr-defined]
    assert f"excavkin: error: {whole.summary()}. Nothing was written" in r.output  # type: ignore[attr-defined]
    assert list(tmp_path.iterdir()) == [model]
    r = _run(*args, "--keep-going")
    assert r.exit_code == 0  # type: ignore[attr-defined]
    assert f"excavkin: warning: {whole.summary()} (rows marked" in r.output  # type: ignore[attr-defined]
    table = pd.read_csv(out)
    assert (table["status"] == whole.status.labels()).all()


@pytest.mark.usefixtures("small_parts")
def test_a_bad_row_deep_in_the_inputs_stops_the_stream_and_leaves_nothing(tmp_path: Path) -> None:
    """The table is read as the solve goes: a value that is not a number in its third block
    stops the run after parts were written; neither the file nor a temporary one is left."""
    n = 3 * BLOCK
    q = np.linspace(0.0, 6.0, n).astype(str)
    q[2 * BLOCK + 100] = "abc"
    source = tmp_path / "in.csv"
    source.write_text("crank\n" + "\n".join(q) + "\n")
    out = tmp_path / "o.parquet"
    r = _run("solve", FOURBAR, "--inputs", str(source), "-q", "-o", str(out))
    assert r.exit_code == 2, r.output  # type: ignore[attr-defined]
    assert "column 'crank' holds a value that is not a number" in r.output  # type: ignore[attr-defined]
    assert list(tmp_path.iterdir()) == [source]


def test_an_error_in_the_middle_of_the_stream_leaves_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Whatever stops the solve halfway (here an error after two parts): no file, no
    temporary."""
    real = excavkin.Mechanism.solve_stream

    def two_parts(self, *args, **kwargs):  # type: ignore[no-untyped-def]
        for k, part in enumerate(real(self, *args, size=1000, **kwargs)):
            if k == 2:
                raise MemoryError
            yield part

    monkeypatch.setattr(excavkin.Mechanism, "solve_stream", two_parts)
    for suffix in (".csv", ".parquet"):
        out = tmp_path / f"x{suffix}"
        r = _run("solve", FOURBAR, "--sweep", "crank=0:1:5000", "-q", "-o", str(out))
        assert r.exit_code == 2 and "not enough memory" in r.output  # type: ignore[attr-defined]
        assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_inputs_read_in_batches_are_the_inputs_read_whole(tmp_path: Path, suffix: str) -> None:
    mech = excavkin.load(FOURBAR)
    rng = np.random.default_rng(3)
    frame = pd.DataFrame(
        {
            "t": np.arange(1000) * 0.01,
            "crank": rng.uniform(-7, 7, 1000),
            "crank.rate": rng.normal(size=1000) * 1e-300,
            "crank.accel": rng.normal(size=1000) * 1e300,
        }
    )
    path = tmp_path / f"in{suffix}"
    if suffix == ".csv":  # with the units row --units-row writes, skipped
        path.write_text(
            "t,crank,crank.rate,crank.accel\ns,rad,rad/s,rad/s^2\n"
            + frame.to_csv(index=False, header=False)
        )
    else:
        frame.to_parquet(path)
    whole = read_inputs(mech, str(path), batch=1 << 20)
    np.testing.assert_array_equal(whole[0]["crank"], frame["crank"].to_numpy(), strict=True)
    np.testing.assert_array_equal(whole[2]["crank"], frame["crank.accel"].to_numpy())
    np.testing.assert_array_equal(whole[3], frame["t"].to_numpy())
    for batch in (1, 7, 333):
        table = InputTable(mech, str(path), batch=batch)
        assert table.n == 1000
        for start, stop in ((0, 10), (10, 500), (500, 503), (503, 1000), (0, 1000)):
            window = table.window(start, stop)
            for name, want in zip(
                ("crank", "crank.rate", "crank.accel", "t"),
                (whole[0]["crank"], whole[1]["crank"], whole[2]["crank"], whole[3]),
                strict=True,
            ):
                np.testing.assert_array_equal(window[name], want[start:stop], strict=True)


def test_a_billion_samples_are_not_refused_for_memory(tmp_path: Path) -> None:
    """A sweep is made part by part: 10⁹ samples cost nothing until solved; only the disk
    can refuse them (here: 10¹⁵ samples)."""
    from excavkin.cli.common import parse_sweep
    from excavkin.sweeps import Linspace

    sweep = parse_sweep("0deg:360deg:1000000000", "angle", "--sweep crank", lazy=True)
    assert isinstance(sweep, Linspace) and sweep.size == 10**9
    np.testing.assert_array_equal(
        sweep.values(10**9 - 2, 10**9), [sweep.at(np.array([10**9 - 2]))[0], 2 * np.pi]
    )
    r = _run("solve", FOURBAR, "--sweep", f"crank=0:1:{10**15}", "-o", str(tmp_path / "x.csv"))
    assert r.exit_code == 2 and "GiB on disk" in r.output  # type: ignore[attr-defined]
    assert not list(tmp_path.iterdir())


def test_a_parquet_table_that_may_not_fit_is_warned_of_and_tried(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Parquet compresses: too little disk for its values uncompressed is a warning, not a
    refusal (a CSV table, which does not compress, is refused)."""
    import shutil
    from collections import namedtuple

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda path: usage(2**40, 0, 1000))
    out = tmp_path / "x.parquet"
    r = _run("solve", FOURBAR, "--sweep", "crank=0:1:50", "-q", "-o", str(out))
    assert r.exit_code == 0 and "uncompressed" in r.output and "may stop" in r.output  # type: ignore[attr-defined]
    assert len(pd.read_parquet(out)) == 50
    r = _run("solve", FOURBAR, "--sweep", "crank=0:1:50", "-q", "-o", str(tmp_path / "x.csv"))
    assert r.exit_code == 2 and "or write Parquet" in r.output  # type: ignore[attr-defined]
    assert not (tmp_path / "x.csv").exists()
