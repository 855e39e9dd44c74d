"""The command line: outputs, exit codes, messages without tracebacks, files written whole."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from tests.conftest import EXAMPLES

FOURBAR = str(EXAMPLES / "fourbar.toml")


def run(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "excavkin", *args], capture_output=True, text=True, cwd=cwd
    )


def test_solve_writes_the_columns(tmp_path: Path) -> None:
    out = tmp_path / "fb.csv"
    r = run(
        "solve",
        FOURBAR,
        "--sweep",
        "crank=0deg:360deg:37",
        "--rate",
        "crank=31.416rad/s",
        "-o",
        str(out),
    )
    assert r.returncode == 0, r.stderr
    frame = pd.read_csv(out)
    assert len(frame) == 37
    for col in (
        "A.x",
        "B.vy",
        "B.ay",
        "rocker.angle",
        "rocker.omega",
        "rocker.epsilon",
        "crank.value",
        "crank.rate",
        "crank.accel",
        "B.transmission",
        "status",
    ):
        assert col in frame.columns
    np.testing.assert_allclose(frame["crank.value"], np.radians(np.linspace(0, 360, 37)))
    np.testing.assert_allclose(frame["crank.rate"], 31.416)
    # full precision round trip
    np.testing.assert_allclose(np.hypot(frame["A.x"], frame["A.y"]), 0.04, rtol=1e-15)


def test_parquet_and_set(tmp_path: Path) -> None:
    out = tmp_path / "sc.parquet"
    r = run("solve", str(EXAMPLES / "slider_crank.toml"), "--set", "crank=30deg", "-o", str(out))
    assert r.returncode == 0, r.stderr
    frame = pd.read_parquet(out)
    assert len(frame) == 1 and frame["crank.rate"].iloc[0] == 0.0


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--sweep", "crnk=0:1:3"], ["unknown driver 'crnk'"]),
        (["--sweep", "crank=0mm:1deg:3"], ["'0mm' is not an angle"]),
        (["--sweep", "crank=0:1"], ["START:STOP:N"]),
        (["--rate", "crank=3m/s", "--sweep", "crank=0:1:3"], ["not an angular_velocity"]),
    ],
)
def test_bad_arguments(tmp_path: Path, args: list[str], words: list[str]) -> None:
    out = tmp_path / "x.csv"
    r = run("solve", FOURBAR, *args, "-o", str(out))
    assert r.returncode == 2
    assert "Traceback" not in r.stderr
    for w in words:
        assert w in r.stderr
    assert not out.exists()


def test_bad_model_file(tmp_path: Path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text(Path(FOURBAR).read_text().replace('"A-B"  = 120', '"A-B"  = 400'))
    r = run("check", str(bad))
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert str(bad) in r.stderr and "cannot be assembled" in r.stderr
    r = run("check", str(tmp_path / "missing.toml"))
    assert r.returncode == 2 and "missing.toml: no such file" in r.stderr


def test_failing_samples_stop_unless_keep_going(tmp_path: Path) -> None:
    model = tmp_path / "nongrashof.toml"
    text = Path(FOURBAR).read_text().replace('"O4-B" = 90', '"O4-B" = 90\n"O2-A" = 95')
    model.write_text(text)
    out = tmp_path / "x.csv"
    r = run("solve", str(model), "--sweep", "crank=0deg:360deg:73", "-o", str(out))
    assert r.returncode == 3
    assert "cannot close at dyad B" in r.stderr and "Nothing was written" in r.stderr
    assert not out.exists()
    r = run("solve", str(model), "--sweep", "crank=0deg:360deg:73", "-o", str(out), "--keep-going")
    assert r.returncode == 0 and "warning" in r.stderr
    frame = pd.read_csv(out)
    assert (frame["status"] != "ok").any() and (frame["status"] == "ok").any()


def test_existing_output_is_not_overwritten(tmp_path: Path) -> None:
    out = tmp_path / "x.csv"
    out.write_text("precious")
    r = run("solve", FOURBAR, "--sweep", "crank=0:1:3", "-o", str(out))
    assert r.returncode == 2 and "exists" in r.stderr
    assert out.read_text() == "precious"
    r = run("solve", FOURBAR, "--sweep", "crank=0:1:3", "-o", str(out), "--force")
    assert r.returncode == 0
    assert len(pd.read_csv(out)) == 3
    assert not list(tmp_path.glob(".*tmp*"))  # no temporary file left behind


def test_check_prints_the_plan() -> None:
    r = run("check", FOURBAR)
    assert r.returncode == 0
    assert "mobility: M = 3·(4 − 1) − 2·4 − 0 = 1" in r.stdout
    assert "dyad     B from A" in r.stdout


def test_demo(tmp_path: Path) -> None:
    r = run("demo", "--out-dir", str(tmp_path / "demo"))
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "demo" / "fourbar.csv").exists()


def test_written_file_has_ordinary_permissions(tmp_path: Path) -> None:
    import os

    out = tmp_path / "x.csv"
    assert run("solve", FOURBAR, "--sweep", "crank=0:1:3", "-o", str(out)).returncode == 0
    umask = os.umask(0)
    os.umask(umask)
    assert out.stat().st_mode & 0o777 == 0o666 & ~umask


def test_bare_numbers_that_look_like_degrees_are_flagged(tmp_path: Path) -> None:
    r = run("solve", FOURBAR, "--sweep", "crank=0:360:3", "-o", str(tmp_path / "x.csv"))
    assert r.returncode == 0
    assert "bare numbers are radians" in r.stderr and "360deg" in r.stderr


def test_machine_file_given_to_check_points_to_the_right_command() -> None:
    r = run("check", str(EXAMPLES / "excavator_machine.toml"))
    assert r.returncode == 2
    assert "excavator machine file" in r.stderr and "excavkin excavator" in r.stderr


def test_running_out_of_memory_is_a_message(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from click.testing import CliRunner

    import excavkin
    from excavkin.cli import main

    def too_big(*args: object, **kwargs: object) -> None:
        raise MemoryError

    monkeypatch.setattr(excavkin.Mechanism, "solve", too_big)
    monkeypatch.setattr(excavkin.Mechanism, "solve_stream", too_big)
    out = tmp_path / "x.csv"
    r = CliRunner().invoke(main, ["solve", FOURBAR, "--sweep", "crank=0:1:5", "-o", str(out)])
    assert r.exit_code == 2 and "not enough memory" in r.output and "split the sweep" in r.output
    assert not out.exists()


def test_a_grid_sweep_is_the_product_of_its_sweeps(tmp_path) -> None:
    """--grid: every combination of the sweeps, the first varying slowest; each sample equals
    the same input solved alone."""
    from click.testing import CliRunner

    import excavkin
    from excavkin.cli import main

    out = tmp_path / "grid.csv"
    args = [
        "solve",
        "excavator",
        "--sweep",
        "boom_cyl=2.1m:3.2m:4",
        "--sweep",
        "arm_cyl=2.3m:3.5m:3",
        "--grid",
        "-q",
        "-o",
        str(out),
    ]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    table = pd.read_csv(out)
    boom, arm = np.meshgrid(np.linspace(2.1, 3.2, 4), np.linspace(2.3, 3.5, 3), indexing="ij")
    np.testing.assert_array_equal(table["boom_cyl.value"], boom.ravel())
    np.testing.assert_array_equal(table["arm_cyl.value"], arm.ravel())
    mech = excavkin.load(excavkin.example_path("excavator"))
    alone = mech.solve({"boom_cyl": boom.ravel(), "arm_cyl": arm.ravel()}, workers=1)
    np.testing.assert_array_equal(table["T.x"], alone.column("T.x"))


def test_inputs_from_a_table_one_row_per_sample(tmp_path) -> None:
    """--inputs: values, rates, accelerations and time per sample, from CSV (a units row
    allowed) or Parquet; the result equals the same inputs given in Python."""
    from click.testing import CliRunner

    import excavkin
    from excavkin.cli import main

    q = np.radians(np.linspace(0.0, 360.0, 25))
    table = pd.DataFrame(
        {"t": np.linspace(0, 1, 25), "crank": q, "crank.rate": 3.0 + q, "crank.accel": -q}
    )
    csv = tmp_path / "in.csv"
    csv.write_text(
        "t,crank,crank.rate,crank.accel\ns,rad,rad/s,rad/s^2\n"
        + table.to_csv(index=False, header=False)
    )
    pq = tmp_path / "in.parquet"
    table.to_parquet(pq)
    mech = excavkin.load(excavkin.example_path("fourbar"))
    want = mech.solve({"crank": q}, {"crank": 3.0 + q}, {"crank": -q}, time=table["t"], workers=1)
    for source in (csv, pq):
        out = tmp_path / f"out-{source.suffix[1:]}.csv"
        r = CliRunner().invoke(
            main, ["solve", "fourbar", "--inputs", str(source), "-q", "-o", str(out)]
        )
        assert r.exit_code == 0, r.output
        got = pd.read_csv(out)
        np.testing.assert_array_equal(got["B.ax"], want.column("B.ax"))
        np.testing.assert_array_equal(got["t"], table["t"])
    bad = tmp_path / "bad.csv"
    bad.write_text("crnk\n0.1\n")
    r = CliRunner().invoke(
        main, ["solve", "fourbar", "--inputs", str(bad), "-o", str(tmp_path / "x.csv")]
    )
    assert r.exit_code == 2 and "did you mean 'crank'" in r.output
    bad.write_text("crank\nabc\n")
    r = CliRunner().invoke(
        main, ["solve", "fourbar", "--inputs", str(bad), "-o", str(tmp_path / "x.csv")]
    )
    assert r.exit_code == 2 and "not a number" in r.output
    r = CliRunner().invoke(
        main,
        [
            "solve",
            "fourbar",
            "--inputs",
            str(csv),
            "--sweep",
            "crank=0:1:3",
            "-o",
            str(tmp_path / "x.csv"),
        ],
    )
    assert r.exit_code == 2 and "use one of them" in r.output
