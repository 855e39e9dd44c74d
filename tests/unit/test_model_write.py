"""A model file written back with new values of its dimensions: every entry in the file's own
unit, loading to exactly those values; the TOML writer reads back to the same tables."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

import excavkin
from excavkin.errors import ModelError
from excavkin.io.files import OutputError
from excavkin.io.model_write import dumps, model_text_with, write_model

MODEL = """# a four-bar with a design variable, units in its entries and a load
schema_version = 1
name = "written back"

[units]
length = "mm"

[design.crank_len]
value = "40 mm"

[design.m_c]
value = "0.3 kg"
kind = "mass"

[points]
O2 = [0, 0]
A  = [0, "crank_len"]
B  = ["110 mm", 90]
O4 = ["0.1 m", 0]

[bodies]
ground  = { points = ["O2", "O4"], ground = true }
crank   = { points = ["O2", "A"] }
coupler = { points = ["A", "B"], mass = "m_c" }

[bodies.rocker]
points = ["O4", "B"]
mass = "600 g"
inertia = "4.5e-4 kg*m^2"
center_of_mass = [105, "45 mm"]

[lengths]
"A-B" = "0.12 m"
"O4-B" = 90

[drivers.crank]
type = "rotary"
body = "crank"
pivot = "O2"

[loads.pull]
type = "force"
body = "rocker"
point = "B"
value = ["1 kN", "0 N"]

[loads.brake]
type = "torque"
body = "rocker"
value = "2 N*m"
"""


@pytest.mark.parametrize("name", excavkin.examples())
def test_the_writer_reads_back_to_the_same_tables(name: str) -> None:
    data = tomllib.loads(excavkin.example_path(name).read_text(encoding="utf-8"))
    assert tomllib.loads(dumps(data)) == data


def test_awkward_strings_and_keys_read_back() -> None:
    data = {
        "a": 'quote " back \\ tab \t nl \n del \x7f é',
        "x.y": {"k k": [1, 2.5, True, -0.0, float("inf")], "t": {"deep": {"er": "v"}}},
        "empty": {},
    }
    assert tomllib.loads(dumps(data)) == data


def test_values_are_written_in_each_entrys_unit_and_load_exactly(tmp_path: Path) -> None:
    src = tmp_path / "model.toml"
    src.write_text(MODEL, encoding="utf-8")
    mech = excavkin.load(src)
    new = {
        "crank_len": 0.04123456789,
        "B.x": 0.1123,
        "B.y": 0.0871,
        "O4.x": 0.0987654321,
        "A-B": 0.1234567,
        "O4-B": 0.091,
        "coupler.mass": 0.31,
        "rocker.mass": 0.65,
        "rocker.inertia": 5e-4,
        "rocker.center_of_mass.x": 0.104,
        "rocker.center_of_mass.y": 0.046,
        "pull.Fx": 1234.5,
        "pull.Fy": -10.0,
        "brake.torque": 2.5,
    }
    assert set(new) <= set(mech.parameters)
    out = write_model(src, new, tmp_path / "new.toml", note="a test")
    text = out.read_text(encoding="utf-8")
    assert text.startswith("# a four-bar with a design variable")
    assert "# a test: crank_len, B.x" in text
    data = tomllib.loads(text)
    # each entry keeps the unit it was written in; bare numbers stay bare (in mm)
    assert data["points"]["B"][0].endswith(" mm") and isinstance(data["points"]["B"][1], float)
    assert data["points"]["O4"][0].endswith(" m")
    assert data["lengths"]["A-B"].endswith(" m") and isinstance(data["lengths"]["O4-B"], float)
    assert data["bodies"]["rocker"]["mass"].endswith(" g")
    assert data["bodies"]["rocker"]["inertia"].endswith(" kg*m^2")
    assert data["loads"]["pull"]["value"][0].endswith(" kN")
    assert data["loads"]["brake"]["value"].endswith(" N*m")
    assert data["design"]["crank_len"]["value"].endswith(" mm")
    assert data["points"]["A"][1] == "crank_len"  # still refers to the design variable
    # the coupler's mass referred to a design variable, and the file has no [units] mass: it
    # gets the SI unit, and the variable, now referred to by nothing, goes
    assert data["bodies"]["coupler"]["mass"] == "0.31 kg"
    assert set(data["design"]) == {"crank_len"} and "design variable m_c" in text
    written = excavkin.load(out)
    assert set(written.parameters) == set(mech.parameters) - {"m_c"}
    for k, v in mech.parameters.items():
        expected = new["crank_len"] if k == "A.y" else new.get(k, v)  # A.y is crank_len
        if k != "m_c":  # to the ulp: 0.104 m is no double of mm times 0.001
            assert written.parameters[k] == pytest.approx(expected, rel=3e-16, abs=0), k


def test_a_parameter_set_alone_replaces_its_design_variables_reference(tmp_path: Path) -> None:
    src = tmp_path / "model.toml"
    src.write_text(MODEL, encoding="utf-8")
    text = model_text_with(src, {"A.y": 0.05})
    data = tomllib.loads(text)
    assert data["points"]["A"][1] == 50.0
    # the design variable has no entry referring to it any more: it goes
    assert "crank_len" not in data["design"] and "m_c" in data["design"]
    out = tmp_path / "a.toml"
    out.write_text(text, encoding="utf-8")
    written = excavkin.load(out)
    assert written.parameters["A.y"] == 0.05 and "crank_len" not in written.parameters


def test_refusals(tmp_path: Path) -> None:
    src = tmp_path / "model.toml"
    src.write_text(MODEL, encoding="utf-8")
    with pytest.raises(ModelError, match=r"model.toml.*'Z.x' has no entry"):
        model_text_with(src, {"Z.x": 1.0})
    target = tmp_path / "there.toml"
    target.write_text("mine", encoding="utf-8")
    with pytest.raises(OutputError, match="exists"):
        write_model(src, {"B.x": 0.1}, target)
    assert target.read_text(encoding="utf-8") == "mine"
    with pytest.raises(OutputError, match="model file itself"):
        write_model(src, {"B.x": 0.1}, src, force=True)
    assert src.read_text(encoding="utf-8") == MODEL
    with pytest.raises(OutputError, match=".toml"):
        write_model(src, {"B.x": 0.1}, tmp_path / "x.txt")
    write_model(src, {"B.x": 0.1}, target, force=True)
    assert excavkin.load(target).parameters["B.x"] == 0.1
