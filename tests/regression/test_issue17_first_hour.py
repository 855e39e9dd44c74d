"""Issue 17: a newcomer's first hour — built-in examples everywhere, forgiving names."""

from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

import excavkin
from excavkin.cli import main
from excavkin.errors import UnknownNameError


def run(*args: str) -> tuple[int, str]:
    r = CliRunner().invoke(main, list(args))
    return r.exit_code, r.output


def test_examples_are_listed_by_kind_and_found_by_name() -> None:
    models, machines = excavkin.examples("model"), excavkin.examples("machine")
    assert "fourbar" in models and "excavator_machine" not in models
    assert machines == [
        "eo4112_machine",
        "excavator_machine",
        "knuckle_crane_machine",
        "mining_shovel_machine",
        "synchronised_crane_machine",
        "telescopic_crane_machine",
        "wheel_loader_machine",
        "wheel_loader_tp_machine",
    ]
    assert "schema_version = 1" in excavkin.example_path("fourbar").read_text()
    with pytest.raises(excavkin.ModelError, match="did you mean 'fourbar'"):
        excavkin.example_path("fourbr")


@pytest.mark.parametrize("command", [["check"], ["solve", "-o", "x.csv"]])
def test_every_command_takes_a_built_in_name_and_suggests_close_ones(command, tmp_path) -> None:
    out_opts = lambda k: ["-q", "-o", str(tmp_path / f"{k}.csv")] if command[0] == "solve" else []  # noqa: E731
    code, out = run(command[0], "fourbar", *out_opts(1))
    assert code == 0, out
    code, out = run(command[0], "fourbr", *out_opts(2))
    assert code == 2 and "did you mean 'fourbar'" in out and "Traceback" not in out


def test_excavator_commands_take_the_built_in_machine_by_name() -> None:
    code, out = run("excavator", "ranges", "excavator_machine")
    assert code == 0 and "Maximum digging reach" in out


def test_demo_lists_every_example_by_kind_and_refuses_a_machine_file(tmp_path) -> None:
    code, out = run("demo", "--list")
    models, machines = out.split("\nmachines")
    assert code == 0 and "fourbar" in models.split() and "excavator_machine" not in models
    assert "excavator_machine" in machines.split()
    code, out = run("demo", "--model", "excavator_machine", "--out-dir", str(tmp_path / "d"))
    assert code == 2 and "not a built-in model" in out and not (tmp_path / "d").exists()


def test_unknown_names_of_a_result_suggest_the_close_ones() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    res = mech.solve({"crank": np.radians([0.0, 90.0])})
    with pytest.raises(UnknownNameError, match="did you mean 'rocker'"):
        res.body("rockr")
    with pytest.raises(KeyError, match="did you mean 'rocker.omega'"):
        res.column("rocker.omga")
    with pytest.raises(UnknownNameError, match="did you mean 'crank'"):
        res.driver("crnk")
    assert res.body("rocker")[0].shape == (2,)


def test_results_read_well_in_a_notebook() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    res = mech.solve({"crank": np.linspace(0.0, 2 * np.pi, 361)})
    forces = mech.forces(res)
    for obj, limit in ((res, 400), (forces, 600), (res.status, 100), (mech, 200)):
        assert len(repr(obj)) < limit, type(obj).__name__
    assert repr(res).startswith("KinematicResult(361 samples: ok 361; 37 columns")
    assert "bodies crank, coupler, rocker" in repr(res)
    html = res._repr_html_()
    assert "<table>" in html and "rocker" in html and len(html) < 5000
    assert "<svg" in mech._repr_html_() and "dyad" in mech._repr_html_()
    assert "<table>" in forces._repr_html_() and "<table>" in res.status._repr_html_()


def test_failures_are_named_by_their_input_values() -> None:
    from tests.models import double_rocker

    res = double_rocker().solve({"crank": np.radians(np.arange(0.0, 360.0, 10.0))})
    text = res.summary(limit=2)
    assert "samples 0 (crank = 0°), 1 (crank = 10°)" in text


def test_inverse_takes_a_single_pose_and_machine_results_print_short() -> None:
    from excavkin.excavator.machine import forward, inverse
    from excavkin.excavator.machine_file import load_machine

    machine = load_machine(excavkin.example_path("excavator_machine"))
    pose = forward(machine, machine.lengths_min[None, :])
    one = inverse(machine, pose.tip[0], pose.bucket_angle[0])
    many = inverse(machine, pose.tip, pose.bucket_angle)
    np.testing.assert_array_equal(one.lengths, many.lengths)
    assert len(repr(machine)) < 200


def test_tables_use_shortest_floats_plain_names_and_carry_units(tmp_path) -> None:
    import pandas as pd
    import pyarrow.parquet as pq

    code, _ = run(
        "solve",
        "fourbar",
        "--sweep",
        "crank=0deg:360deg:5",
        "-q",
        "-o",
        str(tmp_path / "a.csv"),
        "--units-row",
    )
    assert code == 0
    lines = (tmp_path / "a.csv").read_text().splitlines()
    assert lines[1].startswith("m,m,m/s,m/s,m/s^2,m/s^2") and "0.040000000000000001" not in lines[2]
    back = pd.read_csv(tmp_path / "a.csv", skiprows=[1])
    mech = excavkin.load(excavkin.example_path("fourbar"))
    frame = mech.solve({"crank": np.radians(np.linspace(0, 360, 5))}).to_frame()
    np.testing.assert_array_equal(back["B.vx"].to_numpy(), frame["B.vx"].to_numpy())
    code, _ = run(
        "solve",
        "fourbar",
        "--sweep",
        "crank=0deg:360deg:5",
        "-q",
        "-o",
        str(tmp_path / "a.parquet"),
    )
    meta = pq.read_schema(tmp_path / "a.parquet").metadata
    assert b'"rocker.omega": "rad/s"' in meta[b"excavkin.units"]
    assert meta[b"excavkin.model"] == b"crank-rocker four-bar"
    assert frame.attrs["excavkin.kinds"]["crank.value"] == "angle"
    code, _ = run("excavator", "forces", "excavator_machine", "-o", str(tmp_path / "f.csv"))
    assert code == 0 and {"force", "own_limit", "x", "y"} <= set(pd.read_csv(tmp_path / "f.csv"))


def test_the_report_says_how_its_rates_were_made(tmp_path) -> None:
    from excavkin.outputs.report import build_report

    mech = excavkin.load(excavkin.example_path("fourbar"))
    q = np.radians(np.linspace(0, 360, 13))
    assert "transfer functions" in build_report(mech, mech.solve({"crank": q}))
    given = build_report(mech, mech.solve({"crank": q}, rates={"crank": 31.4}))
    assert "transfer functions" not in given and "input rates and accelerations given" in given


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (["solv"], "did you mean 'solve'"),
        (["solve"], "Missing argument 'MODEL'"),
        (["solve", "fourbar", "--bogus"], "No such option '--bogus'"),
        (["check", "nosuchmodel"], "no built-in example"),
    ],
)
def test_one_error_style_for_every_mistake(args, expected) -> None:
    code, out = run(*args)
    assert code == 2
    assert out.startswith("excavkin: error:") and expected in out and "Usage:" not in out


def test_the_excavator_default_sweep_stays_within_the_strokes() -> None:
    from excavkin.outputs.report import default_sweep

    mech = excavkin.load(excavkin.example_path("excavator"))
    sweep = default_sweep(mech)
    for d in mech.model.linear:
        assert d.stroke is not None
        lo, hi = d.stroke
        assert lo - 1e-12 <= sweep[d.name].min() and sweep[d.name].max() <= hi + 1e-12, d.name


def test_model_files_suggest_the_names_they_meant(tmp_path) -> None:
    text = excavkin.example_path("fourbar").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace('body = "crank"', 'body = "crnk"'))
    code, out = run("check", str(bad))
    assert code == 2 and "did you mean 'crank'" in out and "drivers.crank" in out
    bad.write_text(text.replace('pivot = "O2"', 'pivot = "O2"\nrefrence = "ground"'))
    code, out = run("check", str(bad))
    assert code == 2 and "did you mean 'reference'" in out
    bad.write_text(
        text.replace(
            "[drivers.crank]",
            '[drivers.rod]\ntype = "linear"\nbetween = ["A", "O4"]\nmode = "free"\n'
            "stroke = [90, 50]\n[drivers.crank]",
        )
    )
    code, out = run("check", str(bad))
    assert code == 2 and "0 < shortest < longest" in out
    mech = excavkin.load(excavkin.example_path("fourbar"))
    with pytest.raises(excavkin.InputError, match="did you mean 'crank'"):
        mech.solve({"crnk": 0.0})


def test_excavator_results_read_well_in_a_notebook() -> None:
    from excavkin.excavator.forces import tool_forces
    from excavkin.excavator.machine import forward
    from excavkin.excavator.machine_file import load_machine

    machine = load_machine(excavkin.example_path("excavator_machine"))
    lengths = np.repeat(machine.lengths_min[None, :], 500, axis=0)
    for obj in (forward(machine, lengths), tool_forces(machine, lengths)):
        assert len(repr(obj)) < 400 and "500 samples" in repr(obj)
    html = machine._repr_html_()
    assert "<table>" in html and "boom_cyl" in html and "1990–3325" in html
