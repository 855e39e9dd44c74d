"""The excavator machine file: reading, errors that name their place, the CLI."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

import excavkin
from excavkin.cli import main
from excavkin.errors import InputError, ModelError, UnitError
from excavkin.excavator.machine import forward, inverse, transmission_angles
from excavkin.excavator.machine_file import load_machine, loads_machine
from tests.conftest import EXAMPLES

MACHINE = EXAMPLES / "excavator_machine.toml"


def _text(**replace: str) -> str:
    text = MACHINE.read_text(encoding="utf-8").replace(
        'model = "excavator.toml"', f'model = "{(EXAMPLES / "excavator.toml").as_posix()}"'
    )
    for old, new in replace.items():
        assert old in text, old
        text = text.replace(old, new)
    return text


def test_example_machine_reads_in_si() -> None:
    m = load_machine(excavkin.example_path("excavator_machine"))
    boom, arm, bucket = m.cylinders
    assert boom.count == 2 and boom.driver == "boom_cyl"
    np.testing.assert_allclose(m.lengths_min, [1.990, 2.170, 1.645])
    np.testing.assert_allclose(m.lengths_max, [3.325, 3.660, 2.765])
    np.testing.assert_allclose(boom.bore_area, 2 * np.pi / 4 * 0.12**2)
    np.testing.assert_allclose(arm.annulus_area, np.pi / 4 * (0.135**2 - 0.095**2))
    assert m.circuit("bucket").working == pytest.approx(34.3e6)
    assert m.circuit("arm").relief == pytest.approx(39.2e6)
    assert m.pins.foot == "A" and m.pins.junction == "K"
    assert m.tip_radius == pytest.approx(1.5, abs=1e-3)
    assert bucket.dig == "extend"


@pytest.mark.parametrize(
    ("old", "new", "pattern"),
    [
        ('driver = "arm_cyl"', 'driver = "nope"', r"\[cylinders\.arm\] 'driver'.*nope"),
        ("stroke = 1490", 'stroke = "1490 kg"', r"\[cylinders\.arm\] 'stroke'"),
        ("relief = 39.2                     #", "relief = 20 #", r"\[circuits\.boom\].*relief"),
        ('tip = "T"', 'tip = "Q2"', r"\[front\].*'Q2'"),
        ('circuit = "bucket"', 'circuit = "pilot"', r"unknown circuit 'pilot'"),
        (
            'dig = "extend"                    # crowding',
            'dig = "up" #',
            r"dig must be 'extend' or 'retract'",
        ),
        ("[gravity]", "[gravity]\nh = 1", r"\[gravity\].*unknown key h"),
        ('lip = "W"', 'lip = "W"\nfloor = "N"', r"\[front\] 'floor'.*'N' is not a point"),
    ],
)
def test_errors_name_table_and_entry(old: str, new: str, pattern: str) -> None:
    with pytest.raises(ModelError, match=pattern) as info:
        loads_machine(_text(**{old: new}), "m.toml")
    assert str(info.value).startswith("m.toml")


def test_bucket_without_teeth() -> None:
    """A tip that is the lip (ISO 6015 needs only the lip): the machine reads, its tool
    forces at the tip are those at the lip, and the vertical-wall depth needs a floor point."""
    m = loads_machine(_text(**{'tip = "T"': 'tip = "W"'}), "m.toml")
    assert m.front.tip == m.front.lip == "W" and not m.has_cutting_direction
    assert m.tip_radius == m.lip_radius
    with pytest.raises(ModelError, match=r"m.toml \[front\] 'floor'.*cutting direction"):
        _ = m.wall_bucket_angle
    omitted = loads_machine(re.sub(r'\ntip = "T".*\n', "\n", _text()), "m.toml")
    assert omitted.front.tip == "W"
    # floor → lip along pin → lip: the wall angle hangs the bucket straight down
    floor = loads_machine(_text(**{'tip = "T"': 'tip = "W"\nfloor = "Q"'}), "m.toml")
    assert floor.has_cutting_direction
    assert floor.wall_bucket_angle == pytest.approx(-np.pi / 2, abs=1e-15)
    with pytest.raises(ModelError, match=r"\[front\] 'floor'.*coincides with the lip"):
        loads_machine(_text(**{'tip = "T"': 'tip = "W"\nfloor = "W"'}), "m.toml")


def test_bare_numbers_need_units() -> None:
    with pytest.raises(UnitError, match=r"\[cylinders\.boom\] 'retracted'"):
        loads_machine(_text(**{'length = "mm"\n': ""}), "m.toml")


def test_missing_cylinder_and_schema() -> None:
    with pytest.raises(ModelError, match="cylinders.bucket"):
        loads_machine(re.sub(r"\[cylinders\.bucket\][^\[]*", "", _text()), "m.toml")
    with pytest.raises(ModelError, match="schema_version"):
        loads_machine(_text(**{"schema_version = 1": "schema_version = 7"}))


def test_inline_model(tmp_path: Path) -> None:
    model = (EXAMPLES / "excavator.toml").read_text(encoding="utf-8")
    body = model.split("schema_version = 1", 1)[1]
    body = re.sub(r"^\[(?!\[)", "[model.", body, flags=re.M)
    body = re.sub(r"^(name|description) = .*$", "", body, flags=re.M)
    machine = _text(**{'model = "' + (EXAMPLES / "excavator.toml").as_posix() + '"': ""})
    head, rest = machine.split("[units]", 1)
    text = head + "[units]" + rest + "\n" + body
    m = loads_machine(text, str(tmp_path / "inline.toml"))
    ref = load_machine(MACHINE)
    L = np.array([[2.5, 2.9, 2.2]])
    np.testing.assert_allclose(forward(m, L).tip, forward(ref, L).tip, rtol=1e-15)


def test_input_shapes_are_checked() -> None:
    m = load_machine(MACHINE)
    with pytest.raises(InputError, match=r"shape \(n, 3\)"):
        forward(m, np.zeros(3))
    with pytest.raises(InputError, match=r"shape \(n, 2\)"):
        inverse(m, np.zeros((2, 3)), np.zeros(2))


def test_transmission_angles_have_every_key() -> None:
    m = load_machine(MACHINE)
    pose = forward(m, m.lengths_min[None, :])
    ang = transmission_angles(m, pose.result)
    assert set(ang) == {"boom", "arm", "bucket", "bucket_linkage"}
    assert all(0.0 < float(v[0]) < np.pi for v in ang.values())


def test_cli_ranges_ik_and_errors(tmp_path: Path) -> None:
    runner = CliRunner()
    out = tmp_path / "r.csv"
    png = tmp_path / "r.png"
    r = runner.invoke(
        main, ["excavator", "ranges", str(MACHINE), "-o", str(out), "--plot", str(png)]
    )
    assert r.exit_code == 0, r.output
    assert "AC   Maximum digging depth" in r.output
    assert out.is_file() and png.is_file()
    again = runner.invoke(main, ["excavator", "ranges", str(MACHINE), "-o", str(out)])
    assert again.exit_code == 2 and "--force" in again.output
    r = runner.invoke(main, ["excavator", "ik", str(MACHINE), "--x", "7m", "--y", "-1.5m"])
    assert r.exit_code == 0 and "valid" in r.output
    r = runner.invoke(
        main, ["excavator", "ik", str(tmp_path / "none.toml"), "--x", "1m", "--y", "0m"]
    )
    assert r.exit_code == 2 and "none.toml: no such file" in r.output
    assert "Traceback" not in r.output


def test_cli_forces(tmp_path: Path) -> None:
    out = tmp_path / "f.csv"
    args = ["excavator", "forces", str(MACHINE), "--samples", "9", "-o", str(out)]
    r = CliRunner().invoke(main, [*args, "--map", str(tmp_path / "map")])
    assert r.exit_code == 0, r.output
    assert "ISO 6015" in r.output and "SAE J1179" in r.output and "Rated" in r.output
    assert (tmp_path / "map-arm.png").is_file() and (tmp_path / "map-bucket.png").is_file()
    table = pd.read_csv(out)
    assert list(table["kind"]) == ["rated"] * 4 + ["sweep_max"] * 4
    assert (table["force"] <= table["own_limit"] * (1 + 1e-12)).all()
    rated = table[table["kind"] == "rated"]
    assert rated["gravity"].eq(False).all() and rated["moment"].gt(0).all()
    # an existing map is refused before anything is computed or written
    fresh = tmp_path / "g.csv"
    again = CliRunner().invoke(
        main,
        ["excavator", "forces", str(MACHINE), "-o", str(fresh), "--map", str(tmp_path / "map")],
    )
    assert again.exit_code == 2 and "map-arm.png" in again.output and "--force" in again.output
    assert "Rated" not in again.output and not fresh.exists()


def test_cli_pins(tmp_path: Path) -> None:
    out = tmp_path / "pins.csv"
    args = ["excavator", "pins", str(MACHINE), "--samples", "5", "-o", str(out)]
    r = CliRunner().invoke(
        main, [*args, "--plot", str(tmp_path / "bars.png"), "--map", str(tmp_path / "map")]
    )
    assert r.exit_code == 0, r.output
    assert "boom foot" in r.output and "link junction / bucket cylinder rod eye" in r.output
    for name in ("bars.png", "map-bucket.png", "map-arm.png", "map-lift.png"):
        assert (tmp_path / name).is_file(), name
    table = pd.read_csv(out)
    assert list(table["kind"]) == ["pin"] * 11 + ["cylinder"] * 3
    assert set(table["case"]) <= {"bucket", "arm", "lift"}
    per_case = table[["max_bucket", "max_arm", "max_lift"]].max(axis=1)
    np.testing.assert_allclose(table["load"].abs(), per_case, rtol=1e-15)
    # one case with a given lift mass; the table's load is that mass's weight
    lift = tmp_path / "lift.csv"
    r = CliRunner().invoke(
        main,
        ["excavator", "pins", str(MACHINE), "--samples", "5", "--case", "lift", "--load", "2t"]
        + ["-o", str(lift)],
    )
    assert r.exit_code == 0, r.output
    assert "2000 kg hanging at Q" in r.output and "holds the lift load at 100 %" in r.output
    np.testing.assert_allclose(pd.read_csv(lift)["tool_force"], 2000 * 9.80665, rtol=1e-15)
    # errors: name the option, write nothing, keep what exists
    for bad, text in (
        (["--case", "arm", "--load", "2t"], "lift case only"),
        (["--load", "2m"], "not a mass"),
        (["--load", "-1t"], "negative"),
        (["--samples", "1"], "at least 2"),
        (["-o", str(out)], "--force"),
    ):
        before = out.read_bytes()
        r = CliRunner().invoke(main, ["excavator", "pins", str(MACHINE), *bad])
        assert r.exit_code == 2 and text in r.output and "Traceback" not in r.output, bad
        assert "boom foot" not in r.output and out.read_bytes() == before
