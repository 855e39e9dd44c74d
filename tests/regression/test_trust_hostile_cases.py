"""Trust and the first hour: the cases a hostile fuzz run of every command found. Each ends in
one clear message naming the file, the entry or the option, and exit 2 (a closed stdout: quietly;
an ik target out of reach: exit 3) — never a traceback, never a hang."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest
from click.testing import CliRunner

import excavkin
from excavkin.cli import main

ROOT = Path(__file__).resolve().parents[2]
STUDY = (
    excavkin.example_path("crank_rocker")
    .read_text()
    .replace('model = "fourbar"', f'model = "{excavkin.example_path("fourbar")}"')
    .replace("samples = 4096", "samples = 8")
    .replace('crank = "0 deg:360 deg:181"', 'crank = "0 deg:360 deg:13"')
)


def run(*args: str) -> tuple[int, str]:
    r = CliRunner().invoke(main, list(args))
    assert r.exception is None or isinstance(r.exception, SystemExit), r.exception
    assert "Traceback" not in r.output
    return r.exit_code, r.output


def refused(*args: str) -> str:
    """The one error line of a refused command line (exit 2)."""
    code, out = run(*args)
    assert code == 2, out
    assert out.startswith("excavkin: error:") and out.count("\n") == 1, out
    return out


def run_process(*args: str, timeout: float = 60.0, **kw: object) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    return subprocess.run(
        [sys.executable, "-m", "excavkin", *args],
        capture_output=True, text=True, timeout=timeout, env=env, **kw,  # type: ignore[call-overload]
    )  # fmt: skip


def study_file(tmp_path: Path, text: str = STUDY) -> str:
    path = tmp_path / "s.toml"
    path.write_text(text)
    return str(path)


# ---- tracebacks


@pytest.mark.parametrize("name", ["design", "status", "feasible", "poses_failed"])
def test_a_metric_named_after_a_study_column_is_refused(tmp_path, name) -> None:
    path = study_file(tmp_path, STUDY.replace("rocker_top =", f"{name} ="))
    out = refused("study", path, "-o", str(tmp_path / "s.parquet"), "-q")
    assert path in out and f"'{name}'" in out and "reserved" in out
    assert not (tmp_path / "s.parquet").exists()


def test_a_scheduler_of_an_unsupported_protocol_is_refused_by_the_option(tmp_path) -> None:
    out = refused("study", study_file(tmp_path), "-o", str(tmp_path / "s.parquet"), "-q",
                  "--scheduler", "udp://x:1")  # fmt: skip
    assert "--scheduler udp://x:1" in out and "unsupported protocol 'udp'" in out
    for bad in ("x", "tcp://host", "tcp://host:0", "tcp://:8786"):
        out = refused("study", study_file(tmp_path), "-q", "--scheduler", bad)
        assert f"--scheduler {bad}" in out


def test_an_unreachable_scheduler_is_named_within_its_timeout(tmp_path, monkeypatch) -> None:
    pytest.importorskip("distributed")
    import excavkin.studies.study as study_module

    monkeypatch.setattr(study_module, "SCHEDULER_TIMEOUT", 1.0)
    began = time.perf_counter()
    out = refused("study", study_file(tmp_path), "-o", str(tmp_path / "s.parquet"), "-q",
                  "--scheduler", "tcp://127.0.0.1:1")  # fmt: skip
    assert time.perf_counter() - began < 20
    assert "--scheduler tcp://127.0.0.1:1" in out and "cannot be reached within 1 s" in out
    assert "memory" not in out and not (tmp_path / "s.parquet").exists()


def test_an_unknown_rope_is_named_with_the_option(tmp_path) -> None:
    out = refused("report", "excavator", "--rope", "boom_cy", "-o", str(tmp_path / "r.html"))
    assert "--rope" in out and "did you mean 'boom_cyl'" in out
    assert not (tmp_path / "r.html").exists()
    out = refused("report", "fourbar", "--rope", "nope", "-o", str(tmp_path / "r.html"))
    assert "--rope" in out and "'nope'" in out


@pytest.mark.parametrize("command", ["forces", "stability", "pins"])
def test_a_huge_grid_of_the_excavator_commands_is_refused_up_front(command) -> None:
    out = refused("excavator", command, "excavator_machine", "--samples", "100000000")
    assert "--samples 100,000,000" in out and "at most 101" in out


# ---- crash and hangs


def test_check_of_dev_zero_is_refused_without_reading_it() -> None:
    r = run_process("check", "/dev/zero", timeout=60)
    assert r.returncode == 2 and r.stderr.startswith("excavkin: error: /dev/zero: a device")


@pytest.mark.parametrize(
    "args",
    [["check", "{}"], ["excavator", "ranges", "{}"], ["study", "{}"], ["report", "{}"]],
)
def test_a_fifo_is_refused_not_waited_on(tmp_path, args) -> None:
    fifo = tmp_path / "m.toml"
    os.mkfifo(fifo)
    r = run_process(*[a.format(fifo) for a in args], timeout=60)
    assert r.returncode == 2 and "FIFO" in r.stderr and str(fifo) in r.stderr, r.stderr


def test_a_fifo_or_a_folder_as_an_input_table_is_refused(tmp_path) -> None:
    fifo = tmp_path / "in.csv"
    os.mkfifo(fifo)
    out = refused("solve", "fourbar", "--inputs", str(fifo), "-o", str(tmp_path / "o.csv"))
    assert f"--inputs {fifo}: a FIFO" in out
    (tmp_path / "d.csv").mkdir()
    out = refused("solve", "fourbar", "--inputs", str(tmp_path / "d.csv"), "-o",
                  str(tmp_path / "o.csv"))  # fmt: skip
    assert "'--inputs'" in out and "is a directory" in out


def test_a_model_named_by_a_machine_file_is_read_within_the_limit(tmp_path) -> None:
    (tmp_path / "big.toml").write_bytes(b"#" * 2_000_001)
    machine = excavkin.example_path("excavator_machine").read_text()
    path = tmp_path / "m.toml"
    path.write_text(machine.replace('model = "excavator.toml"', 'model = "big.toml"'))
    out = refused("excavator", "ranges", str(path))
    assert f"{path} 'model'" in out and "2,000,001 bytes" in out and "at most 2,000,000" in out


def test_dig_with_a_hundred_million_samples_is_refused_up_front() -> None:
    out = refused("excavator", "dig", "excavator_machine", "--width", "1.2m",
                  "--samples", "100000000")  # fmt: skip
    assert "--samples 100,000,000" in out and "at most 100,000" in out


def test_a_count_beyond_memory_is_refused_naming_the_option(monkeypatch) -> None:
    import excavkin.cli.common as common

    monkeypatch.setattr(common, "available_memory", lambda: 2**30)
    out = refused("excavator", "forces", "excavator_machine", "--samples", "61")
    assert "--samples 61" in out and "226,981 poses" in out and "1.0 GiB" in out


def test_tolerance_with_a_billion_draws_is_refused_up_front(tmp_path) -> None:
    out = refused("tolerance", "fourbar", "--sweep", "crank=0:1:3", "--tol", "A-B=0.1mm",
                  "--draws", "1000000000", "-o", str(tmp_path / "t.csv"))  # fmt: skip
    assert "--draws 1,000,000,000" in out and "more than 1,000,000,000" in out
    assert "at most 333,333,333" in out and not (tmp_path / "t.csv").exists()


def test_simulate_with_too_many_samples_is_refused_up_front(tmp_path) -> None:
    out = refused("simulate", "fourbar", "--drive", "crank=crank:31.416rad/s", "--duration",
                  "1s", "--samples", "100000000", "-o", str(tmp_path / "s.csv"))  # fmt: skip
    assert "--samples 100,000,000" in out and "at most 10,000,000" in out


def test_an_optimisation_of_hours_and_hours_is_refused_up_front(tmp_path) -> None:
    big = STUDY.replace('sense = "min"', 'sense = "min"\nmaxiter = 100000\npopsize = 10000')
    path = study_file(tmp_path, big)
    out = refused("optimize", path, "-o", str(tmp_path / "b.csv"))
    assert f"{path} [optimize] 'maxiter'" in out and "more than 10,000,000,000" in out
    assert not (tmp_path / "b.csv").exists()


# ---- bad input accepted


@pytest.mark.parametrize(
    ("header", "says"),
    [("crank,crank", "'crank' appears twice"),
     ("crank,crank.value", "'crank' and 'crank.value' both give the value of 'crank'")],
)  # fmt: skip
def test_an_inputs_table_with_an_ambiguous_column_is_refused(tmp_path, header, says) -> None:
    table = tmp_path / "in.csv"
    table.write_text(f"{header}\n0,1\n1,2\n")
    out = refused("solve", "fourbar", "-q", "--inputs", str(table), "-o", str(tmp_path / "o.csv"))
    assert f"--inputs {table}" in out and says in out and not (tmp_path / "o.csv").exists()


def test_a_study_without_poses_is_refused_and_an_empty_table_asks_for_the_sketch(
    tmp_path,
) -> None:
    head, rest = STUDY.split("[poses]")
    without = head + rest[rest.index("[metrics]") :]
    out = refused("study", study_file(tmp_path, without), "-q")
    assert "[poses]" in out and "empty [poses] table" in out
    path = study_file(tmp_path, without.replace("[metrics]", "[poses]\n[metrics]"))
    code, out = run("study", path, "-q", "-o", str(tmp_path / "s.parquet"))
    assert code == 0, out
    assert len(pd.read_parquet(tmp_path / "s.parquet")) == 8


def test_dig_param_without_its_unit_is_refused() -> None:
    out = refused("excavator", "dig", "excavator_machine", "--width", "1.2m", "--samples", "5",
                  "--param", "cohesion=20")  # fmt: skip
    assert "--param" in out and "cohesion=20 has no unit" in out and "20 kPa" in out
    code, out = run("excavator", "dig", "excavator_machine", "--width", "1.2m", "--samples",
                    "5", "--param", "cohesion=20 kPa", "--param", "blows=9")  # fmt: skip
    assert code == 0, out


@pytest.mark.parametrize(
    ("param", "says"),
    [("density=0 kg/m^3", "density must be finite and > 0"),
     ("blows=0", "blows must be finite and > 0"),
     ("teeth=0", "teeth (Zelenin's factor, 1 for none) must be finite and > 0"),
     ("walls=-1", "walls (Zelenin's factor, 1 for none) must be finite and > 0")],
)  # fmt: skip
def test_a_soil_or_tool_that_erases_the_resistance_is_refused(param, says) -> None:
    out = refused("excavator", "dig", "excavator_machine", "--width", "1.2m", "--samples", "5",
                  "--param", param)  # fmt: skip
    assert out.startswith("excavkin: error: --param: ") and says in out


def test_ik_out_of_reach_exits_3() -> None:
    code, out = run("excavator", "ik", "excavator_machine", "--x", "30m", "--y", "0m")
    assert code == 3 and "no valid solution" in out
    code, out = run("excavator", "ik", "excavator_machine", "--x", "7m", "--y", "-1.5m")
    assert code == 0 and "valid" in out


@pytest.mark.parametrize(("kind", "value"), [("model", '["a", "b"]'), ("machine", "3")])
def test_a_description_that_is_not_a_string_is_refused(tmp_path, kind, value) -> None:
    name = "fourbar" if kind == "model" else "excavator_machine"
    path = tmp_path / "f.toml"
    (tmp_path / "excavator.toml").write_text(excavkin.example_path("excavator").read_text())
    path.write_text(f"description = {value}\n" + excavkin.example_path(name).read_text())
    args = ["check", str(path)] if kind == "model" else ["excavator", "ranges", str(path)]
    out = refused(*args)
    assert f"{path} 'description': description must be a string" in out


# ---- wrong or unnamed messages


@pytest.mark.parametrize(
    ("param", "says"),
    [("rocker.mass=-1kg", "--param rocker.mass=-1kg: a mass cannot be negative"),
     ("rocker.mass=-1kg:1kg:3", "--param rocker.mass=-1kg:1kg:3: a mass cannot be negative"),
     ("A-B=-1m", "--param A-B=-1m: a distance between two points must be positive")],
)  # fmt: skip
def test_a_negative_mass_or_length_names_the_parameter(tmp_path, param, says) -> None:
    out = refused("solve", "fourbar", "-q", "--sweep", "crank=0:1:3", "--param", param, "-o",
                  str(tmp_path / "o.csv"))  # fmt: skip
    assert says in out and "build no mechanism" not in out


def test_dig_from_to_depth_and_law_are_named_in_their_errors() -> None:
    base = ["excavator", "dig", "excavator_machine", "--width", "1.2m", "--samples", "5"]
    out = refused(*base, "--from", "9000,9000,9000 mm", "--to", "2700,2170,2205 mm")
    assert "--from '9000,9000,9000 mm' --to '2700,2170,2205 mm'" in out and "strokes" in out
    out = refused(*base, "--depth", "50m")
    assert "--depth '50m'" in out
    out = refused(*base, "--law", "bogus", "--depth", "0.5m")
    assert "--law" in out and "--depth" not in out


def test_a_machine_files_model_is_named_in_its_errors(tmp_path) -> None:
    (tmp_path / "bad.toml").write_text("schema_version = 1\n[points]\nA = [0 0]\n")
    machine = excavkin.example_path("excavator_machine").read_text()
    path = tmp_path / "m.toml"
    path.write_text(machine.replace('model = "excavator.toml"', 'model = "bad.toml"'))
    out = refused("excavator", "ranges", str(path))
    assert f"{path} 'model'" in out and "bad.toml" in out and "not valid TOML" in out


# ---- small CLI things


def test_a_closed_stdout_ends_quietly() -> None:
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    proc = subprocess.Popen(
        [sys.executable, "-m", "excavkin", "demo", "--list"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env,
    )  # fmt: skip
    assert proc.stdout is not None and proc.stderr is not None
    proc.stdout.close()  # the reader goes away before anything is written
    err = proc.stderr.read()
    assert proc.wait(timeout=60) in (0, 141) and err == b"", err


def test_study_quiet_prints_no_header(tmp_path) -> None:
    r = run_process("study", study_file(tmp_path), "-q", "-o", str(tmp_path / "s.parquet"))
    assert r.returncode == 0 and r.stderr == "", r.stderr
    assert r.stdout.startswith("wrote 8 designs")


def test_demo_list_names_every_built_in_example_by_kind() -> None:
    code, out = run("demo", "--list")
    assert code == 0
    every = excavkin.examples()
    listed = [line.split()[0] for line in out.splitlines() if line.startswith("  ")]
    assert sorted(listed) == sorted(every)
    assert out.index("machines") < out.index("excavator_machine") < out.index("studies")


def test_a_model_file_given_for_a_machine_says_so(tmp_path) -> None:
    out = refused("excavator", "ranges", str(excavkin.example_path("fourbar")))
    assert "this is a model file" in out and "a machine file is expected" in out
    assert "excavkin demo --list" in out and "fourbar.toml" in out
    out = refused("excavator", "ranges", "fourbar")
    assert "a built-in model, and a machine is expected here" in out
