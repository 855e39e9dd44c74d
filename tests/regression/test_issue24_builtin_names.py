"""Issue 24: built-in examples by name in Python as on the command line, and a missing file
that names the nearest built-in example."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

import excavkin
from excavkin.cli import main
from excavkin.errors import ModelError
from excavkin.excavator.machine_file import load_machine


def test_load_takes_a_builtin_name() -> None:
    assert excavkin.load("fourbar").inputs == ("crank",)
    assert excavkin.load("fourbar").model == excavkin.load(excavkin.example_path("fourbar")).model


def test_load_machine_takes_a_builtin_name() -> None:
    machine = load_machine("excavator_machine")
    assert machine.drivers == ("boom_cyl", "arm_cyl", "bucket_cyl")


def test_a_misspelt_name_names_the_nearest(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ModelError, match=r"fourbr: no such file, .*did you mean 'fourbar'"):
        excavkin.load("fourbr")


def test_a_tutorial_path_outside_the_repository(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(
        ModelError, match=r"examples/fourbar.toml: no such file; the built-in model 'fourbar'"
    ):
        excavkin.load("examples/fourbar.toml")


def test_a_file_here_wins_over_a_builtin(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    text = excavkin.example_path("fourbar").read_text().replace("crank-rocker", "my own")
    Path("fourbar").write_text(text)
    assert excavkin.load("fourbar").name == "my own four-bar"


def test_cli_names_the_nearest(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, ["check", "fourbr"])
    assert result.exit_code == 2
    assert "did you mean 'fourbar'" in result.output
    assert "Traceback" not in result.output
