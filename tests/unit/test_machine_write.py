"""A machine file written back with new values of its parameters: the machine file's entries in
their own units, the model inline with its entries in theirs; the file loads as that design,
stands alone, and is written whole or not at all, never over a file without being asked."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

import excavkin
from excavkin.errors import ModelError
from excavkin.io.files import OutputError
from excavkin.io.machine_write import machine_text_with, write_machine_file
from excavkin.loader.machine_file import load_machine
from excavkin.loader.study import loader_parameter_kind, loader_parameters

SOURCE = excavkin.example_path("wheel_loader_machine")


def _copy(tmp_path: Path) -> Path:
    """The built-in loader's machine and model files, side by side in a scratch folder."""
    (tmp_path / "wheel_loader.toml").write_text(excavkin.example_path("wheel_loader").read_text())
    path = tmp_path / "machine.toml"
    path.write_text(SOURCE.read_text())
    return path


def test_every_value_is_written_in_its_entrys_unit_and_loads_exactly(tmp_path: Path) -> None:
    path = _copy(tmp_path)
    nominal = load_machine(path)
    values = {
        "E.y": 1.4031234567891234,
        "bucket.mass": 1512.5,
        "cylinders.tilt.bore": 0.18028798612430418,
        "circuits.lift.relief": 27.123456e6,
        "chassis.counterweight.mass": 3100.25,
    }
    kinds = {k: loader_parameter_kind(k, nominal) for k in values}
    text = machine_text_with(path, values, kinds, set(nominal.mechanism.parameters), "a note")
    data = tomllib.loads(text)
    assert data["cylinders"]["tilt"]["bore"] == pytest.approx(180.28798612430418, rel=1e-15)
    assert data["circuits"]["lift"]["relief"] == pytest.approx(27.123456, rel=1e-15)  # MPa
    assert data["model"]["points"]["E"][1] == pytest.approx(1403.1234567891234, rel=1e-15)
    assert data["model"]["units"]["length"] == "mm"
    assert "# a note: E.y, bucket.mass" in text and text.startswith("# Machine description")
    out = tmp_path / "written" / "design.toml"
    out.parent.mkdir()
    out.write_text(text)  # elsewhere: nothing refers back to the files it came from
    loaded = loader_parameters(load_machine(out))
    for name, value in values.items():
        assert loaded[name] == value, name
    untouched = loader_parameters(nominal)
    for name in ("E.x", "cylinders.lift.bore", "circuits.tilt.working", "lift_arm.mass"):
        assert loaded[name] == untouched[name], name


def test_a_written_file_written_again_keeps_its_inline_model(tmp_path: Path) -> None:
    path = _copy(tmp_path)
    model = tomllib.loads((tmp_path / "wheel_loader.toml").read_text())
    assert model["units"]["length"] == "mm"
    first = tmp_path / "first.toml"
    nominal = load_machine(path)
    write_machine_file(path, {"E.y": 1.41}, {"E.y": "length"}, {"E.y"}, first)
    # the written file's own model is inline; written again, it stays as it was read
    again = tmp_path / "again.toml"
    write_machine_file(first, {"E.x": 1.32}, {"E.x": "length"}, {"E.x"}, again)
    params = loader_parameters(load_machine(again))
    assert params["E.y"] == 1.41 and params["E.x"] == 1.32
    assert params["G.x"] == loader_parameters(nominal)["G.x"]


def test_what_cannot_be_written_is_refused_and_nothing_is_written(tmp_path: Path) -> None:
    path = _copy(tmp_path)
    out = tmp_path / "out.toml"
    with pytest.raises(ModelError, match="cylinders.tilt.colour"):
        write_machine_file(path, {"cylinders.tilt.colour": 1.0},
                           {"cylinders.tilt.colour": "length"}, set(), out)  # fmt: skip
    with pytest.raises(ModelError, match="Q.x"):
        write_machine_file(path, {"Q.x": 1.0}, {"Q.x": "length"}, {"Q.x"}, out)
    assert not out.exists()
    out.write_text("keep")
    with pytest.raises(OutputError, match="exists"):
        write_machine_file(path, {"E.y": 1.41}, {"E.y": "length"}, {"E.y"}, out)
    with pytest.raises(OutputError, match="machine file itself"):
        write_machine_file(path, {"E.y": 1.41}, {"E.y": "length"}, {"E.y"}, path, force=True)
    with pytest.raises(OutputError, match=".toml"):
        write_machine_file(path, {"E.y": 1.41}, {"E.y": "length"}, {"E.y"}, tmp_path / "o.csv")
    assert out.read_text() == "keep"
    write_machine_file(path, {"E.y": 1.41}, {"E.y": "length"}, {"E.y"}, out, force=True)
    assert load_machine(out).mechanism.model.points["E"][1] == 1.41
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["machine.toml", "wheel_loader.toml", "out.toml"])  # fmt: skip
