"""Fuzz the readers: malformed model files, machine files and command-line values.

Every case must end in success or in exit 2 with one ``excavkin: error:`` line naming the file —
never a traceback, never a hang. Deterministic (derandomised) so that CI sees the same cases.
"""

from __future__ import annotations

import time
from pathlib import Path

from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import excavkin
from excavkin.cli import main
from tests.property.test_pose_sets import STUDY as POSE_SETS_STUDY

FUZZ = settings(
    max_examples=150,
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
MODEL = excavkin.example_path("slider_crank").read_text()
MACHINE = excavkin.example_path("excavator_machine").read_text()
EXCAVATOR = excavkin.example_path("excavator").read_text()

#: what a careless or hostile file puts where a value should be
VALUES = st.one_of(
    st.sampled_from(
        [
            "true",
            "1.0",
            "-1",
            "0",
            "1e308",
            "-1e308",
            "nan",
            "inf",
            '"9**9**9 mm"',
            '"1 mm**99"',
            '"(((mm)))"',
            '""',
            '"mm"',
            '"12 parsecs"',
            "[]",
            "[1]",
            "[1, 2, 3]",
            "{}",
            "{ a = 1 }",
            '"' + "x" * 300 + '"',
            "[[[[[[[[[[1]]]]]]]]]]",
            '"30 deg"',
            "99999999999999999999",
            '"\\u0000"',
            "1979-05-27",
        ]
    ),
    st.floats(allow_nan=True, allow_infinity=True).map(lambda x: repr(x).replace("inf", "inf")),
    st.text(alphabet="0123456789e.-+ mkgsNPadr/*^()", max_size=12).map(lambda t: f'"{t}"'),
)


def mutate(text: str, data: st.DataObject) -> str:
    """Replace the value of one `key = value` line, delete a line, or add junk."""
    lines = text.splitlines()
    k = data.draw(st.integers(0, len(lines) - 1), label="line")
    action = data.draw(st.sampled_from(["value", "delete", "junk", "duplicate"]), label="action")
    line = lines[k]
    if action == "value" and "=" in line:
        key = line.split("=", 1)[0]
        lines[k] = f"{key}= {data.draw(VALUES, label='value')}"
    elif action == "delete":
        del lines[k]
    elif action == "duplicate":
        lines.insert(k, line)
    else:
        lines.insert(k, data.draw(st.sampled_from(["[", "]]", "x =", "= 1", "[points", "\x00"])))
    return "\n".join(lines) + "\n"


def check_outcome(args: list[str], path: str) -> None:
    start = time.perf_counter()
    r = CliRunner().invoke(main, args)
    seconds = time.perf_counter() - start
    assert r.exception is None or isinstance(r.exception, SystemExit), (
        f"{type(r.exception).__name__}: {r.exception}"
    )
    assert r.exit_code in (0, 2, 3), r.output
    if r.exit_code == 2:
        assert r.output.startswith("excavkin: error:") and path in r.output, r.output
    assert seconds < 20


@FUZZ
@given(data=st.data())
def test_mutated_models(tmp_path_factory, data) -> None:
    folder = tmp_path_factory.mktemp("model")
    path = folder / "m.toml"
    path.write_text(mutate(MODEL, data))
    check_outcome(["check", str(path)], str(path))


@FUZZ
@given(data=st.data())
def test_mutated_machine_files(tmp_path_factory, data) -> None:
    folder = tmp_path_factory.mktemp("machine")
    (folder / "excavator.toml").write_text(EXCAVATOR)
    path = folder / "machine.toml"
    path.write_text(mutate(MACHINE, data))
    check_outcome(["excavator", "ik", str(path), "--x", "7m", "--y", "-1.5m"], str(path))


@FUZZ
@given(raw=st.binary(max_size=400))
def test_random_bytes(tmp_path_factory, raw: bytes) -> None:
    path = tmp_path_factory.mktemp("bytes") / "b.toml"
    path.write_bytes(raw)
    check_outcome(["check", str(path)], str(path))


@FUZZ
@given(
    start=VALUES.map(lambda v: v.strip('"')),
    stop=VALUES.map(lambda v: v.strip('"')),
    n=st.sampled_from(["5", "0", "-3", "1e30", "x", "2.5", str(10**30), "1"]),
    rate=VALUES.map(lambda v: v.strip('"')),
)
def test_command_line_values(tmp_path_factory, start: str, stop: str, n: str, rate: str) -> None:
    out = tmp_path_factory.mktemp("cli") / "o.csv"
    args = [
        "solve",
        "slider_crank",
        "-q",
        "--sweep",
        f"crank={start}:{stop}:{n}",
        "--rate",
        f"crank={rate}",
        "-o",
        str(out),
    ]
    check_writes_or_refuses(args, Path(out))


def check_writes_or_refuses(args: list[str], out: Path) -> None:
    """Success, or one clear error with nothing written; never a traceback, never a hang."""
    start_t = time.perf_counter()
    r = CliRunner().invoke(main, args)
    assert r.exception is None or isinstance(r.exception, SystemExit), r.exception
    assert r.exit_code in (0, 2, 3) and time.perf_counter() - start_t < 20
    if r.exit_code:
        assert "excavkin: error:" in r.output and not out.exists(), r.output


#: a model with design variables, referred to from points, lengths and a body's mass
DESIGNED = (
    excavkin.example_path("fourbar")
    .read_text()
    .replace('"A-B"  = 120', '"A-B"  = "coupler"')
    .replace("O4 = [100, 0]", 'O4 = ["span", 0]')
    .replace('mass = "0.6 kg"', 'mass = "rocker_mass"')
    + '\n[design.coupler]\nvalue = "120 mm"\nbounds = ["110 mm", "130 mm"]\n'
    + "\n[design.span]\nvalue = 100\n"
    + '\n[design.rocker_mass]\nkind = "mass"\nvalue = "0.6 kg"\n'
)


def test_the_designed_model_reads() -> None:
    mech = excavkin.loads(DESIGNED, "designed.toml")
    assert set(mech.design_variables) == {"coupler", "span", "rocker_mass"}


@FUZZ
@given(data=st.data())
def test_mutated_design_variables(tmp_path_factory, data) -> None:
    path = tmp_path_factory.mktemp("designed") / "d.toml"
    path.write_text(mutate(DESIGNED, data))
    check_outcome(["check", str(path)], str(path))


@FUZZ
@given(
    param=st.sampled_from(["A-B", "O4.x", "rocker.mass", "B@rocker.x", "A-C", "", "A-B.x"]),
    start=VALUES.map(lambda v: v.strip('"')),
    stop=VALUES.map(lambda v: v.strip('"')),
    tol=VALUES.map(lambda v: v.strip('"')),
)
def test_design_command_line_values(tmp_path_factory, param, start, stop, tol) -> None:  # type: ignore[no-untyped-def]
    """--param and --tol take the same hostile values as --sweep: success or one clear error,
    and nothing written on an error."""
    folder = tmp_path_factory.mktemp("designs")
    out = folder / "o.csv"
    for args in (
        [
            "solve",
            "fourbar",
            "-q",
            "--sweep",
            "crank=0:1:3",
            "--param",
            f"{param}={start}:{stop}:3",
            "-o",
            str(out),
        ],
        [
            "tolerance",
            "fourbar",
            "--sweep",
            "crank=0:1:3",
            "--tol",
            f"{param}={tol}",
            "--draws",
            "50",
            "-o",
            str(out),
        ],
    ):
        check_writes_or_refuses(args, out)
        out.unlink(missing_ok=True)


def _base_lines(text: str) -> list[int]:
    """Indices of the lines of the [base…] and [lift] tables and of the cylinders' masses."""
    out, inside = [], False
    for k, line in enumerate(text.splitlines()):
        if line.startswith("["):
            inside = line.startswith(("[base", "[lift"))
        if inside or line.startswith("mass = "):
            out.append(k)
    return out


#: the example machine with a lowered blade, outriggers and a lifting hook, all fuzzed
BASE_MACHINE = (
    MACHINE
    + "\n[base.blade]\nposition = 2600\nwidth = 2500\n"
    + "\n[base.outriggers]\npoints = [[-1825, 2200], [-1825, -2200]]\n"
    + '\n[lift]\npoint = "L"\n'
)


def mutate_base(text: str, data: st.DataObject) -> str:
    """Like :func:`mutate`, on a line of the base-machine and lift tables."""
    lines = text.splitlines()
    k = data.draw(st.sampled_from(_base_lines(text)), label="line")
    action = data.draw(st.sampled_from(["value", "delete", "junk", "duplicate"]), label="action")
    line = lines[k]
    if action == "value" and "=" in line:
        lines[k] = f"{line.split('=', 1)[0]}= {data.draw(VALUES, label='value')}"
    elif action == "delete":
        del lines[k]
    elif action == "duplicate":
        lines.insert(k, line)
    else:
        lines.insert(k, data.draw(st.sampled_from(["[", "x =", "[base.x]", "[lift]", "\x00"])))
    return "\n".join(lines) + "\n"


@FUZZ
@given(data=st.data())
def test_mutated_base_tables(tmp_path_factory, data) -> None:
    folder = tmp_path_factory.mktemp("base")
    (folder / "excavator.toml").write_text(EXCAVATOR)
    path = folder / "machine.toml"
    path.write_text(mutate_base(BASE_MACHINE, data))
    check_outcome(["excavator", "ik", str(path), "--x", "7m", "--y", "-1.5m"], str(path))


@settings(FUZZ, max_examples=12)
@given(data=st.data())
def test_mutated_base_tables_through_the_lift_table(tmp_path_factory, data) -> None:
    """The same files all the way through a lift table: a table, or one clear error."""
    folder = tmp_path_factory.mktemp("lift")
    (folder / "excavator.toml").write_text(EXCAVATOR)
    path = folder / "machine.toml"
    path.write_text(mutate_base(BASE_MACHINE, data))
    check_outcome(["excavator", "lift", str(path), "--step", "3m"], str(path))


#: the example machine on wheels (an oscillating front axle) with a blade and outriggers
WHEELED_MACHINE = (
    "\n".join(
        line
        for line in MACHINE.splitlines()
        if not line.startswith(("track_length", "gauge", "shoe_width"))
    )
    + "\n[base.undercarriage.front_axle]\nposition = 1250\ntread = 2400\noscillating = true\n"
    + "\n[base.undercarriage.rear_axle]\nposition = -1250\ntread = 2400\n"
    + "\n[base.blade]\nposition = 2600\nwidth = 2500\n"
    + "\n[base.outriggers]\npoints = [[-1825, 2200], [-1825, -2200]]\n"
)


@settings(FUZZ, max_examples=12)
@given(data=st.data())
def test_mutated_wheeled_base_through_the_lift_table(tmp_path_factory, data) -> None:
    """A wheeled base, mutated, all the way through a lift table: a table, or one clear error."""
    folder = tmp_path_factory.mktemp("wheels")
    (folder / "excavator.toml").write_text(EXCAVATOR)
    path = folder / "machine.toml"
    path.write_text(mutate_base(WHEELED_MACHINE, data))
    check_outcome(["excavator", "lift", str(path), "--step", "3m"], str(path))


#: the built-in study, small enough to run in every fuzz case
STUDY = (
    excavkin.example_path("crank_rocker")
    .read_text()
    .replace("samples = 4096", "samples = 16")
    .replace('crank = "0 deg:360 deg:181"', 'crank = "0 deg:360 deg:13"')
)


@settings(FUZZ, max_examples=60)
@given(data=st.data())
def test_mutated_study_files(tmp_path_factory, data) -> None:  # type: ignore[no-untyped-def]
    """A mutated study file runs or is refused naming the file; a feasible design's metrics
    are finite."""
    import numpy as np
    import pandas as pd

    folder = tmp_path_factory.mktemp("study")
    path = folder / "s.toml"
    path.write_text(mutate(STUDY, data))
    out = folder / "s.parquet"
    assert "[optimize]" in STUDY  # the reader of that table is fuzzed too (below)
    check_outcome(["study", str(path), "-o", str(out), "-q", "--force"], str(path))
    if out.exists():
        table = pd.read_parquet(out)
        metrics = [c for c in table.columns if c not in ("design", "feasible", "status")]
        ok = table[table["feasible"]]
        assert np.isfinite(ok[metrics].to_numpy(dtype=float)).all()
    check_outcome(["optimize", str(path), "--force"], str(path))


#: a study with named pose sets and clearance metrics (tests/property/test_pose_sets.py)
SETS_STUDY = POSE_SETS_STUDY.replace("samples = 48", "samples = 8") + (
    '\n[optimize]\nobjective = "gamma_min"\nsense = "max"\nmaxiter = 20\n'
)


@settings(FUZZ, max_examples=40)
@given(data=st.data())
def test_mutated_study_files_with_pose_sets(tmp_path_factory, data) -> None:  # type: ignore[no-untyped-def]
    """A mutated study with several pose sets and clearances runs or is refused naming the
    file, through the study and the optimiser."""
    folder = tmp_path_factory.mktemp("sets")
    path = folder / "s.toml"
    path.write_text(mutate(SETS_STUDY, data))
    assert "[pose_sets." in SETS_STUDY and "clearance" in SETS_STUDY
    check_outcome(["study", str(path), "-o", str(folder / "s.parquet"), "-q", "--force"], str(path))
    check_outcome(["optimize", str(path), "-q", "--write-model", str(folder / "m.toml")], str(path))


#: the built-in machine study, small enough to run in every fuzz case
MACHINE_STUDY = (
    excavkin.example_path("excavator_bucket_linkage")
    .read_text()
    .replace("samples = 4096", "samples = 8")
    .replace('bucket_cyl = "1645 mm:2765 mm:57"', 'bucket_cyl = "1645 mm:2765 mm:9"')
)


@settings(FUZZ, max_examples=40)
@given(data=st.data())
def test_mutated_machine_study_files(tmp_path_factory, data) -> None:  # type: ignore[no-untyped-def]
    """A mutated machine study runs or is refused naming the file, through the design of
    experiments and the optimiser; a feasible design's metrics are finite."""
    import numpy as np
    import pandas as pd

    folder = tmp_path_factory.mktemp("machine-study")
    path = folder / "s.toml"
    path.write_text(mutate(MACHINE_STUDY, data))
    out = folder / "s.parquet"
    assert "[optimize]" in MACHINE_STUDY and "samples = 8" in MACHINE_STUDY
    check_outcome(["excavator", "study", str(path), "-o", str(out), "-q", "--force"], str(path))
    if out.exists():
        table = pd.read_parquet(out)
        metrics = [c for c in table.columns if c not in ("design", "feasible", "status")]
        ok = table[table["feasible"]]
        assert np.isfinite(ok[metrics].to_numpy(dtype=float)).all()
    check_outcome(
        ["excavator", "optimize", str(path), "--method", "slsqp", "-o", str(folder / "b.csv"),
         "--force"],
        str(path),
    )  # fmt: skip


#: pieces of option values: numbers, units, separators and junk
_PIECES = st.sampled_from(
    ["1.2", "-3", "0", "1e400", "nan", "inf", "2700", " ", ",", "m", "mm", "kPa", "deg", "kg/m^3",
     "=", "cohesion", "density", "friction", "blows", "x", "\x00", "é", "1,2", ":"]
)  # fmt: skip


@settings(FUZZ, max_examples=40)
@given(
    width=st.lists(_PIECES, max_size=4).map("".join),
    param=st.lists(_PIECES, max_size=5).map("".join),
    start=st.lists(_PIECES, max_size=6).map("".join),
    depth=st.lists(_PIECES, max_size=3).map("".join),
)
def test_dig_options_run_or_are_refused(width: str, param: str, start: str, depth: str) -> None:
    """`excavkin excavator dig` with junk in its options: a table, or one clear error
    naming what is wrong; never a traceback, never a hang."""
    cases = (
        ["--width", width or "1.2m"],
        ["--width", "1.2m", "--param", param],
        ["--width", "1.2m", "--from", start, "--to", "2700,2170,2205 mm"],
        ["--width", "1.2m", "--depth", depth],
    )
    for extra in cases:
        began = time.perf_counter()
        r = CliRunner().invoke(main, ["excavator", "dig", "excavator_machine", "--samples", "5",
                                      *extra])  # fmt: skip
        assert r.exception is None or isinstance(r.exception, SystemExit), (
            f"{extra}: {type(r.exception).__name__}: {r.exception}"
        )
        assert r.exit_code in (0, 2), (extra, r.output)
        if r.exit_code == 2:
            assert "Error" in r.output or r.output.startswith("excavkin: error:"), r.output
        assert time.perf_counter() - began < 20
