"""The excavator's commands print what they printed before their computations moved out of
the CLI into the wing's results ("A command parses, calls and writes"): the printouts in
``data/excavator_printouts.json`` were written by the commands as they were then, and each
command line must print them again, character for character, with the same exit status."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from excavkin.cli import main

CASES = json.loads((Path(__file__).parent / "data" / "excavator_printouts.json").read_text())


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_command_prints_what_it_printed(name: str) -> None:
    case = CASES[name]
    r = CliRunner().invoke(main, case["args"], env={**os.environ, "COLUMNS": "200"})
    assert r.exit_code == case["exit_code"], r.output
    assert r.output == case["output"]
