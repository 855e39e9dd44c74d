"""Issue 12: every hostile or careless input gets one clear message and exit 2 — never a
traceback, never a hang — and no non-finite number reaches a row marked ok."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pint
import pytest
from click.testing import CliRunner

import excavkin
from excavkin.cli import main
from excavkin.errors import UnitError
from excavkin.outputs.tables import remove_leftovers, write_atomic

FOURBAR = excavkin.example_path("fourbar").read_text()
MACHINE = excavkin.example_path("excavator_machine").read_text()


def run(*args: str) -> tuple[int, str, float]:
    start = time.perf_counter()
    r = CliRunner().invoke(main, list(args))
    assert r.exception is None or isinstance(r.exception, SystemExit), r.exception
    return r.exit_code, r.output, time.perf_counter() - start


def model_file(tmp_path: Path, text: str | bytes, name: str = "m.toml") -> str:
    path = tmp_path / name
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text)
    return str(path)


def machine_file(tmp_path: Path, text: str) -> str:
    (tmp_path / "excavator.toml").write_text(excavkin.example_path("excavator").read_text())
    return model_file(tmp_path, text, "machine.toml")


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (FOURBAR.encode() + b"\n# \xff\xfe\n", "not UTF-8"),
        ("x = " + "[" * 5000 + "]" * 5000 + "\n" + FOURBAR, "nested"),
        (FOURBAR.replace("O4 = [100, 0]", 'O4 = ["9**9**9 mm", 0]'), "cannot read '9**9**9 mm'"),
        (
            FOURBAR.replace("A  = [0, 40]", "A  = [0, 4e-290]")
            .replace("B  = [110, 90]", "B  = [1.1e-289, 9e-290]")
            .replace("O4 = [100, 0]", "O4 = [1e-289, 0]"),
            "sketch spans",
        ),
        (FOURBAR.replace("schema_version = 1", "schema_version = 1.0"), "schema_version"),
        (FOURBAR.replace("schema_version = 1", "schema_version = true"), "schema_version"),
        (FOURBAR.replace('name = "crank-rocker four-bar"', "name = 5"), "name must be a string"),
        (
            FOURBAR.replace('name = "crank-rocker four-bar"', "name = { a = 1 }"),
            "name must be a string",
        ),
        (
            FOURBAR.replace("[drivers.crank]", "[gravity]\ndirection = [nan, 1]\n[drivers.crank]"),
            "direction must be two finite numbers",
        ),
    ],
    ids=[
        "bytes",
        "nesting",
        "unit-bomb",
        "tiny",
        "version-float",
        "version-bool",
        "name-int",
        "name-table",
        "gravity-nan",
    ],
)
def test_hostile_model_files_get_one_message(tmp_path, text, expected) -> None:
    path = model_file(tmp_path, text)
    code, out, seconds = run("check", path)
    assert code == 2 and expected in out and path in out, out
    assert out.startswith("excavkin: error:") and seconds < 5


def test_huge_models_are_refused_quickly(tmp_path) -> None:
    points = "\n".join(f"P{i} = [{i}, {i % 7}]" for i in range(20_000))
    path = model_file(tmp_path, FOURBAR.replace("[points]", "[points]\n" + points))
    code, out, seconds = run("check", path)
    assert code == 2 and "at most 10,000" in out and seconds < 5
    big = model_file(tmp_path, FOURBAR + "\n# " + "x" * 3_000_000 + "\n", "big.toml")
    code, out, seconds = run("check", big)
    assert code == 2 and "at most 2,000,000" in out and seconds < 5


@pytest.mark.parametrize(
    ("old", "new", "table", "entry"),
    [
        ("count = 2 ", "count = 99999999999999999 ", "cylinders.boom", "count"),
        ("level_bottom = 2440", "level_bottom = -5", "front", "level_bottom"),
        ("stroke = 1335", "stroke = 1e300", "cylinders.boom", "stroke"),
        ("working = 34.3 ", 'working = "9**9 MPa" ', "circuits.boom", "working"),
        ("schema_version = 1", "schema_version = 1.0", "", ""),
    ],
)
def test_machine_files_are_range_checked_naming_file_table_and_entry(
    tmp_path, old, new, table, entry
) -> None:
    assert old in MACHINE
    path = machine_file(tmp_path, MACHINE.replace(old, new, 1))
    code, out, seconds = run("excavator", "ranges", path)
    assert code == 2 and path in out and seconds < 10, out
    assert table in out and entry in out


def test_a_unit_bomb_on_the_command_line_and_absurd_sample_counts(tmp_path) -> None:
    out_csv = str(tmp_path / "x.csv")
    code, out, seconds = run("solve", "fourbar", "--sweep", "crank=0:9**9**9deg:5", "-o", out_csv)
    assert code == 2 and "cannot read" in out and seconds < 5
    code, out, seconds = run("solve", "fourbar", "--sweep", f"crank=0:1:{10**30}", "-o", out_csv)
    assert code == 2 and "split the sweep" in out and seconds < 5
    assert not Path(out_csv).exists()


def test_no_non_finite_number_on_an_ok_row(tmp_path) -> None:
    mech = excavkin.loads(FOURBAR)
    res = mech.solve({"crank": np.linspace(0.0, 1.0, 7)}, rates={"crank": 1e300})
    assert not res.status.ok.any() and "overflows" in res.summary()
    frame = res.to_frame()
    ok = frame["status"] == "ok"
    numbers = frame.drop(columns="status").to_numpy()
    assert np.isfinite(numbers[ok.to_numpy()]).all()
    code, out, _ = run(
        "solve",
        "fourbar",
        "--sweep",
        "crank=0:1:5",
        "--rate",
        "crank=1e300rad/s",
        "-o",
        str(tmp_path / "r.csv"),
    )
    assert code == 3 and "overflows" in out and not (tmp_path / "r.csv").exists()


def test_a_huge_gravity_direction_is_only_a_direction() -> None:
    text = FOURBAR.replace(
        "[drivers.crank]", "[gravity]\ndirection = [1e308, 1e308]\n[drivers.crank]"
    )
    mech = excavkin.loads(text)
    forces = mech.solve({"crank": np.linspace(0, 6, 13)}, loads="model")
    assert forces.ok.all() and np.isfinite(forces.pin_force).all()
    g = mech.model.gravity
    assert g is not None and np.allclose(g.direction, [2**-0.5, 2**-0.5], rtol=1e-15)


def test_units_in_the_python_api_from_any_registry_and_strings() -> None:
    mech = excavkin.loads(FOURBAR)
    other = pint.UnitRegistry()
    deg = np.linspace(0.0, 360.0, 5)
    a = mech.solve({"crank": deg * other.deg}, rates={"crank": "300 rpm"})
    b = mech.solve({"crank": np.radians(deg)}, rates={"crank": 300 * 2 * np.pi / 60})
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_allclose(a.velocities, b.velocities, rtol=1e-15, atol=0)
    assert np.isclose(np.degrees(mech.solve({"crank": "30 deg"}).inputs[0, 0]), 30.0)
    with pytest.raises(UnitError, match="driver 'crank'.*not an angle"):
        mech.solve({"crank": 5 * other.m})
    with pytest.raises(UnitError, match="rate of driver 'crank'"):
        mech.solve({"crank": 0.0}, rates={"crank": "3 m"})


def test_a_killed_write_leaves_no_file_and_a_later_one_cleans_up(tmp_path) -> None:
    target = tmp_path / "t.csv"
    script = textwrap.dedent(f"""
        import time
        from pathlib import Path
        from excavkin.outputs.tables import write_atomic
        def slow(tmp):
            tmp.write_text("partial")
            print("writing", flush=True)
            time.sleep(30)
        write_atomic(Path({str(target)!r}), slow)
    """)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, env=env)
    assert proc.stdout is not None and proc.stdout.readline().strip() == b"writing"
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=20) != 0
    assert not target.exists() and not list(tmp_path.glob(".t.csv.*"))
    # what a SIGKILL would leave: a temporary file whose process is gone
    stale = tmp_path / ".t.csv.excavkin-999999999.tmp.csv"
    stale.write_text("left over")
    assert remove_leftovers(target) == [stale] and not stale.exists()
    stale.write_text("left over")
    write_atomic(target, lambda tmp: tmp.write_text("whole"))
    assert target.read_text() == "whole" and not stale.exists()


def test_a_coincident_pivot_is_undetermined_not_a_failure_to_close() -> None:
    from excavkin import Mechanism
    from tests.models import parallelogram

    square = parallelogram()
    res = Mechanism(square).solve({"crank": np.radians([-1.0, 0.0, 1.0])})
    labels = res.status.labels()
    assert labels[0] == labels[2] == "ok"
    assert labels[1].startswith("undetermined (its two partners coincide) at dyad B")


def test_coincident_partners_at_unequal_distances_still_cannot_close() -> None:
    from excavkin import Mechanism
    from tests.models import fourbar_model

    # crank 100 mm onto O4, coupler 100 mm, rocker 120 mm: at crank 0, A = O4 and B cannot
    # be both 100 mm and 120 mm from that one point
    model = fourbar_model(
        {"O2": (0.0, 0.0), "A": (0.0, 0.1), "B": (0.06, 0.18), "O4": (0.1, 0.0)},
        "unequal",
        {("A", "B"): 0.1, ("O4", "B"): 0.12},
    )
    res = Mechanism(model).solve({"crank": 0.0})
    assert res.status.labels()[0].startswith("cannot close at dyad B")
