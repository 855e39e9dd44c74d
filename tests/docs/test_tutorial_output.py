"""The first tutorial shows the whole output of ``excavkin check``, not its first line: the
lines shown are what the command prints, every one of them."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from excavkin.cli import main

ROOT = Path(__file__).parents[2]
PAGE = ROOT / "docs" / "tutorials" / "first-mechanism.md"
COMMAND = "$ excavkin check examples/fourbar.toml"


def shown() -> list[str]:
    """The lines the page shows after the command, to the end of its block."""
    text = PAGE.read_text(encoding="utf-8")
    after = text.split(COMMAND + "\n", 1)[1]
    return after.split("```", 1)[0].rstrip("\n").splitlines()


def test_the_first_tutorial_shows_the_whole_check_output(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, COMMAND[2:].split()[1:])
    assert result.exit_code == 0, result.output
    lines = shown()
    assert len(lines) > 10  # the bodies, joints, mobility and plan, not one line
    assert lines == result.output.rstrip("\n").splitlines()
