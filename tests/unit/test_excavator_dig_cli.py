"""``excavkin excavator dig``: the table, the files it writes, and errors that name the entry
and the value, with a non-zero exit and no traceback."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from excavkin.cli import main
from tests.conftest import EXAMPLES
from tests.unit.test_excavator_base import _drop, _text

MACHINE = str(EXAMPLES / "excavator_machine.toml")


def test_cli_dig_table_plot_and_file(tmp_path: Path) -> None:
    out, png = tmp_path / "dig.csv", tmp_path / "dig.png"
    args = ["excavator", "dig", MACHINE, "--width", "1.2 m", "--soil", "clay", "--samples", "21"]
    r = CliRunner().invoke(main, [*args, "-o", str(out), "--plot", str(png)])
    assert r.exit_code == 0, r.output
    assert "balovnev resistance along a dig in clay, 1200 mm wide" in r.output
    assert "the dig stalls at point" in r.output and "← stalls" in r.output
    assert png.is_file() and png.stat().st_size > 10_000
    table = pd.read_csv(out)
    assert len(table) == 21
    np.testing.assert_allclose(
        table["margin"], table["available"] - table["required"], rtol=1e-9, atol=1e-9
    )
    k = int(np.flatnonzero((table["depth"] > 0) & (table["margin"] < 0))[0])
    assert f"the dig stalls at point {k} " in r.output
    again = CliRunner().invoke(main, [*args, "-o", str(out)])
    assert again.exit_code == 2 and "--force" in again.output


def test_cli_dig_between_poses_with_params() -> None:
    r = CliRunner().invoke(
        main,
        [
            "excavator",
            "dig",
            MACHINE,
            "--model",
            "mckyes",
            "--soil",
            "sand",
            "--param",
            "cohesion=5 kPa",
            "--param",
            "friction_angle=30 deg",
            "--width",
            "1100 mm",
            "--from",
            "2700,2170,2205 mm",
            "--to",
            "2.9 m,3.4 m,2.6 m",
            "--samples",
            "9",
            "--law",
            "345",
        ],
    )
    assert r.exit_code == 0, r.output
    assert "soil sand: ρ 1600 kg/m³, φ 30°, c 5 kPa" in r.output
    rows = [ln for ln in r.output.splitlines() if re.match(r"^ *\d+ +\d+ +-?\d+ ", ln)]
    assert [int(ln.split()[0]) for ln in rows] == list(range(9))


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--param", "colour=red"], "--param"),
        (["--param", "cohesion=20 deg"], "--param cohesion"),
        (["--from", "2700,2170,2205"], "--from/--to"),
        (["--from", "2700,2170,2205", "--to", "2900,3400,2600"], "has no unit"),
        (["--from", "2700,2170 mm", "--to", "2900,3400,2600 mm"], "three cylinder lengths"),
        (["--from", "100,2170,2205 mm", "--to", "2900,3400,2600 mm"], "strokes at sample 0"),
        (["--soil", "peat"], "unknown soil 'peat'"),
        (["--depth", "-1 m"], "depth must be > 0"),
        (["--law", "wobble"], "unknown motion law 'wobble'"),
        (["--param", "friction_angle=10 deg"], "δ ≤ φ"),
    ],
)
def test_cli_dig_errors_name_the_entry(extra: list[str], needle: str) -> None:
    r = CliRunner().invoke(main, ["excavator", "dig", MACHINE, "--width", "1.2 m", *extra])
    assert r.exit_code != 0
    assert needle in r.output, r.output
    assert "Traceback" not in r.output


def test_cli_dig_without_base_uses_the_cylinders_alone(tmp_path: Path) -> None:
    bare = tmp_path / "bare.toml"
    bare.write_text(_drop(_text(), "base"), encoding="utf-8")
    r = CliRunner().invoke(
        main, ["excavator", "dig", str(bare), "--width", "1.2 m", "--samples", "11"]
    )
    assert r.exit_code == 0, r.output
    assert "tipping" not in r.output and "slipping" not in r.output
