"""Fuzz every command and subcommand of the CLI: garbage files, garbage option values, garbage
numbers.

Each command starts from a small valid command line (:data:`BASE`); one case replaces its file
with garbage, or one of its options (found by introspecting the command, so a new option is
fuzzed without a change here) with a garbage value. Every case must end in success, in exit 2
with one ``excavkin: error:`` line, or in exit 3 for samples that do not solve (``solve``,
``simulate``, ``report``; ``excavator ik`` out of reach) — never a traceback, never a hang. A
test keeps :data:`BASE` equal to the commands ``excavkin --help`` and each group's help list,
so that a new command cannot go unfuzzed. Deterministic (derandomised) and small, so that CI
sees the same cases in a few tens of seconds.
"""

from __future__ import annotations

import contextlib
import time
from pathlib import Path

import click
import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import excavkin
from excavkin.cli import main

FUZZ = settings(
    max_examples=4,
    derandomize=True,
    deadline=None,
    database=None,
    suppress_health_check=list(HealthCheck),
)
#: seconds a case may take (the slowest valid command line here takes about 10)
BOUND = 30.0

#: the study and machine study, small enough to run in a fuzz case (written by :func:`folder`)
STUDY = (
    excavkin.example_path("crank_rocker")
    .read_text()
    .replace('model = "fourbar"', f'model = "{excavkin.example_path("fourbar")}"')
    .replace("samples = 4096", "samples = 4")
    .replace('crank = "0 deg:360 deg:181"', 'crank = "0 deg:360 deg:7"')
)
MACHINE_STUDY = (
    excavkin.example_path("excavator_bucket_linkage")
    .read_text()
    .replace("samples = 4096", "samples = 4")
    .replace('bucket_cyl = "1645 mm:2765 mm:57"', 'bucket_cyl = "1645 mm:2765 mm:5"')
)
LOADER_STUDY = (
    excavkin.example_path("wheel_loader_breakout")
    .read_text()
    .replace("samples = 64", "samples = 2")
    .replace("maxiter = 30", "maxiter = 2\npopsize = 4")
)
CRANE_STUDY = (
    excavkin.example_path("telescopic_crane_counterweight")
    .read_text()
    .replace("samples = 8", "samples = 2")
    .replace("maxiter = 6", "maxiter = 1")
)

#: the shovel's drive study, cut to the figures that need no envelope and no dig
SHOVEL_STUDY = """
[study]
machine = "mining_shovel_machine"
method = "sobol"
samples = 2
[parameters]
"hoist.gear_ratio" = [70, 90]
[metrics]
hoist_speed = { column = "hoist.speed" }
pull = { column = "hoist.pull" }
"""

#: a small valid command line of every command; "{d}" is a scratch folder, "{study}",
#: "{machine_study}", "{loader_study}", "{crane_study}" and "{shovel_study}" the files above
BASE: dict[str, list[str]] = {
    "check": ["fourbar"],
    "demo": ["--model", "slider_crank", "--out-dir", "{d}/demo"],
    "optimize": ["{study}", "--force"],
    "report": ["slider_crank", "--sweep", "crank=0:1:5", "-o", "{d}/r.html", "--force", "-q"],
    "simulate": ["fourbar", "--drive", "crank=crank:31.416rad/s", "--duration", "0.1s",
                 "--samples", "5", "-o", "{d}/s.csv", "--force"],
    "solve": ["fourbar", "--sweep", "crank=0:1:5", "-o", "{d}/o.csv", "--force", "-q",
              "--backend", "auto", "--columns", "B.*,crank.value"],
    "study": ["{study}", "-o", "{d}/s.parquet", "--force", "-q", "--backend", "auto"],
    "tolerance": ["fourbar", "--sweep", "crank=0:1:3", "--tol", "A-B=0.1mm", "--draws", "20",
                  "--backend", "auto"],
    "crane chart": ["knuckle_crane_machine", "--step", "2m", "--second", "2234mm"],
    "crane range": ["telescopic_crane_machine", "--samples", "3"],
    "crane study": ["{crane_study}", "-o", "{d}/c.parquet", "--force", "-q"],
    "crane optimize": ["{crane_study}", "--write-machine", "{d}/c.toml", "--force"],
    "crane report": ["knuckle_crane_machine", "--samples", "3", "-o", "{d}/c.html", "--force",
                     "-q"],
    "crane supports": ["telescopic_crane_machine", "--radius", "8m", "--load", "1t",
                       "--samples", "5"],
    "excavator cycle": ["excavator_machine"],
    "excavator dig": ["excavator_machine", "--width", "1.2m", "--samples", "5"],
    "excavator forces": ["excavator_machine", "--samples", "3"],
    "excavator ik": ["excavator_machine", "--x", "7m", "--y", "-1.5m"],
    "excavator lift": ["excavator_machine", "--step", "3m"],
    "excavator optimize": ["{machine_study}", "--method", "slsqp", "-o", "{d}/b.csv", "--force"],
    "excavator pins": ["excavator_machine", "--samples", "3"],
    "excavator ranges": ["excavator_machine"],
    "excavator report": ["excavator_machine", "--samples", "2", "-o", "{d}/e.html", "--force",
                         "-q"],
    "excavator stability": ["excavator_machine", "--samples", "3"],
    "excavator study": ["{machine_study}", "-o", "{d}/m.parquet", "--force", "-q"],
    "loader breakout": ["wheel_loader_machine"],
    "loader capacity": ["wheel_loader_machine", "--samples", "5"],
    "loader cycle": ["wheel_loader_machine", "--load", "1000"],
    "loader pins": ["wheel_loader_machine", "--samples", "3"],
    "loader lift": ["wheel_loader_tp_machine", "--samples", "5"],
    "loader ranges": ["wheel_loader_machine"],
    "loader report": ["wheel_loader_machine", "--samples", "3", "-o", "{d}/l.html", "--force",
                      "-q"],
    "loader tipping": ["wheel_loader_machine"],
    "loader study": ["{loader_study}", "-o", "{d}/l.parquet", "--force", "-q"],
    "loader optimize": ["{loader_study}", "-o", "{d}/l.csv", "--write-machine", "{d}/l.toml",
                        "--force", "-q"],
    "shovel envelope": ["mining_shovel_machine", "--samples", "5"],
    "shovel haul": ["eo4112_machine", "--samples", "5", "--load", "3", "-8"],
    "shovel dig": ["mining_shovel_machine", "--samples", "5"],
    "shovel loads": ["mining_shovel_machine", "--samples", "5"],
    "shovel report": ["mining_shovel_machine", "--samples", "5", "-o", "{d}/sh.html", "--force",
                      "-q"],
    "shovel stability": ["mining_shovel_machine", "--samples", "5"],
    "shovel study": ["{shovel_study}", "-o", "{d}/sh.parquet", "--force", "-q"],
    "reproduce arm": ["--out-dir", "{d}/arm"],
    "reproduce mo100": ["--out-dir", "{d}/mo100", "--samples", "36"],
    "reproduce pasika": ["--out-dir", "{d}/pasika", "--samples", "11"],
    "reproduce pasika-laws": ["--out-dir", "{d}/laws", "--intervals", "10"],
    "reproduce rope-shovel": ["--out-dir", "{d}/rope", "--samples", "11"],
}  # fmt: skip

#: exit 3 (samples that do not solve) is an answer of these commands
SAMPLE_FAILURES = {"solve", "simulate", "report", "excavator ik"}

#: garbage where a value goes: numbers out of range, junk units, separators, control bytes
GARBAGE = st.one_of(
    st.sampled_from(
        ["", " ", "0", "-0", "-1", "2.5", "1e400", "-1e400", "nan", "inf", "-inf", "1e9",
         "100000000000000000000", "0x10", "1_000", "١٢", "1,5", "1:2:3", "0:1:1e30",
         "-1:1:100000000000", "a=b", "=", "crank=", "=1", "A-B=-1m", "crank=nan:1:3",
         "9**9**9 mm", "1 mm**99", "12 parsecs", "m", "kg", "30 deg", "-3 bar", "1 m/s",
         "\x00", "\n", "é", "x" * 300, "udp://x:1", "tcp://127.0.0.1:", "dask://", "-", "--",
         "--force", "/dev/null", "/", ".", "..", "nonexistent/x.csv", "x.txt", "x.csv",
         "x.parquet", "x.png", "x.html", "fourbar", "excavator_machine", "crank_rocker"]
    ),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(min_value=-(10**30), max_value=10**30).map(str),
    st.text(alphabet="0123456789e.-+ :,=mkgsNPadr/*^()x", max_size=16),
)  # fmt: skip

#: garbage where a file goes: its text (or bytes), or a name for a folder / a missing path
FILES = st.one_of(
    st.binary(max_size=200),
    st.sampled_from(
        ["", "schema_version = 1\n", "[study]\n", "x = \n", "\ufeff[", "[[[[[[[[[[[[[[[[",
         "schema_version = 2\n", 'schema_version = 1\nmodel = "nowhere.toml"\n',
         "#" * 2_000_001, "FOLDER", "MISSING", "/dev/null"]
    ),
    st.sampled_from(["fourbar", "excavator_machine", "crank_rocker", "excavator"]).map(
        lambda name: excavkin.example_path(name).read_text()
    ),
)  # fmt: skip


def commands() -> dict[str, click.Command]:
    """Every command of the CLI by its path (``excavator dig``), as its help lists them."""
    ctx = click.Context(main)
    out: dict[str, click.Command] = {}
    for name in main.list_commands(ctx):
        cmd = main.get_command(ctx, name)
        assert cmd is not None
        if isinstance(cmd, click.Group):
            sub = click.Context(cmd, parent=ctx)
            for child in cmd.list_commands(sub):
                found = cmd.get_command(sub, child)
                assert found is not None
                out[f"{name} {child}"] = found
        else:
            out[name] = cmd
    return out


COMMANDS = commands()


#: the command's argument (its file or built-in name), as an "option" to fuzz
ARGUMENT = "<argument>"


def options(path: str) -> list[str]:
    """The options of a command that take a value (the longest spelling of each), and
    :data:`ARGUMENT` where it takes one."""
    found = sorted(
        max(p.opts, key=len)
        for p in COMMANDS[path].params
        if isinstance(p, click.Option) and not p.is_flag and p.name != "help"
    )
    return found + ([ARGUMENT] if takes_a_file(path) else [])


def takes_a_file(path: str) -> bool:
    return any(isinstance(p, click.Argument) for p in COMMANDS[path].params)


def test_every_command_is_fuzzed() -> None:
    assert sorted(BASE) == sorted(COMMANDS)
    assert all(options(path) for path in COMMANDS)


def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("fuzz")
    (d / "study.toml").write_text(STUDY)
    (d / "machine_study.toml").write_text(MACHINE_STUDY)
    (d / "loader_study.toml").write_text(LOADER_STUDY)
    (d / "crane_study.toml").write_text(CRANE_STUDY)
    (d / "shovel_study.toml").write_text(SHOVEL_STUDY)
    return d


def base_args(path: str, d: Path) -> list[str]:
    fill = {"d": str(d), "study": str(d / "study.toml"),
            "machine_study": str(d / "machine_study.toml"),
            "loader_study": str(d / "loader_study.toml"),
            "crane_study": str(d / "crane_study.toml"),
            "shovel_study": str(d / "shovel_study.toml")}  # fmt: skip
    return [*path.split(), *(a.format(**fill) for a in BASE[path])]


def check(path: str, args: list[str], d: Path) -> None:
    """Success, one clear error, or (for a solve) failed samples; never a traceback or a hang."""
    began = time.perf_counter()
    with contextlib.chdir(d):  # relative outputs land in the scratch folder
        r = CliRunner().invoke(main, args)
    seconds = time.perf_counter() - began
    assert r.exception is None or isinstance(r.exception, SystemExit), (
        f"{args!r}: {type(r.exception).__name__}: {r.exception}"
    )
    assert "Traceback" not in r.output, (args, r.output)
    allowed = {0, 2, 3} if path in SAMPLE_FAILURES else {0, 2}
    assert r.exit_code in allowed, (args, r.exit_code, r.output)
    if r.exit_code == 2:
        assert "excavkin: error:" in r.output, (args, r.output)
    assert seconds < BOUND, (args, seconds)


def test_every_base_command_line_runs(tmp_path_factory) -> None:
    """The starting points are valid: a case that fails fails for its garbage."""
    d = folder(tmp_path_factory)
    for path in ("solve", "excavator ik", "study", "tolerance"):
        r = CliRunner().invoke(main, base_args(path, d))
        assert r.exit_code == 0, (path, r.output)


@pytest.mark.parametrize("path", sorted(p for p in BASE if takes_a_file(p)))
@FUZZ
@given(content=FILES)
def test_garbage_files(tmp_path_factory, path: str, content: str | bytes) -> None:
    """The file a command reads holds garbage, is a folder, a device or missing: refused,
    naming it (a valid file of another kind included: a machine where a model goes)."""
    d = folder(tmp_path_factory)
    args = base_args(path, d)
    target = d / "garbage.toml"
    if content == "FOLDER":
        target.mkdir()
    elif content == "/dev/null":
        target = Path("/dev/null")
    elif content != "MISSING":
        (target.write_bytes if isinstance(content, bytes) else target.write_text)(content)
    # the command's file is its first word after the command's name
    args[len(path.split())] = str(target)
    check(path, args, d)


#: commands whose valid run takes seconds (a figure, a dense sweep): fewer cases
SLOW = {"demo", "excavator cycle", "excavator forces", "excavator ranges", "excavator report",
        "excavator stability", "loader report",
        *(p for p in BASE if p.startswith("reproduce "))}  # fmt: skip


@pytest.mark.parametrize("path", sorted(set(BASE) - SLOW))
@FUZZ
@given(data=st.data())
def test_garbage_option_values(tmp_path_factory, path: str, data: st.DataObject) -> None:
    """One option of a command (any of them, found by introspection), or its argument, takes
    a garbage value: the command runs, or refuses naming what is wrong."""
    garbage_option_value(tmp_path_factory, path, data)


@pytest.mark.parametrize("path", sorted(SLOW))
@settings(FUZZ, max_examples=2)
@given(data=st.data())
def test_garbage_option_values_of_slow_commands(
    tmp_path_factory, path: str, data: st.DataObject
) -> None:
    """As :func:`test_garbage_option_values`, fewer cases."""
    garbage_option_value(tmp_path_factory, path, data)


def garbage_option_value(
    tmp_path_factory: pytest.TempPathFactory, path: str, data: st.DataObject
) -> None:
    d = folder(tmp_path_factory)
    option = data.draw(st.sampled_from(options(path)), label="option")
    value = data.draw(GARBAGE, label="value")
    args = base_args(path, d)
    if option == ARGUMENT:
        args[len(path.split())] = value
    else:
        args += [option, value]
    check(path, args, d)


#: the commands that take ``--backend`` (where the solves run)
BACKEND_COMMANDS = sorted(p for p in BASE if "--backend" in options(p))


def test_the_commands_that_solve_take_a_backend() -> None:
    assert {"solve", "study", "tolerance"} <= set(BACKEND_COMMANDS)


@pytest.mark.parametrize("path", BACKEND_COMMANDS)
@FUZZ
@given(value=st.one_of(GARBAGE, st.sampled_from(["auto", "numpy", "cuda", "NUMBA", " numpy"])))
def test_garbage_backends(tmp_path_factory, path: str, value: str) -> None:
    """``--backend`` with any value: the command runs, or refuses naming the option (an
    unknown name, or cuda where no GPU is usable) with exit 2."""
    d = folder(tmp_path_factory)
    args = [*base_args(path, d), "--backend", value]
    check(path, args, d)
    if value == "cuda":
        with contextlib.chdir(d):
            r = CliRunner().invoke(main, args)
        assert r.exit_code == 0 or "--backend cuda: " in r.output, r.output
