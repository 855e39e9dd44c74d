"""A slider's point drawn off its line is refused with the distance, not moved onto the line
in silence (issue "Ropes over sheaves, pulley blocks, gears, racks and cams", item 6: clear
messages). The assembly tolerance is `ASSEMBLY_TOL` of the sketch's size."""

from __future__ import annotations

import dataclasses
import math

import pytest
from click.testing import CliRunner

import excavkin
from excavkin import Mechanism
from excavkin.cli import main
from excavkin.errors import AssemblyError
from excavkin.structure.builder import ASSEMBLY_TOL

SLIDER_CRANK = excavkin.example_path("slider_crank").read_text(encoding="utf-8")
#: the example's pin B, drawn on the slide y = 20 mm
ON_LINE = "B  = [173.18, 20]"


def _drawn(tmp_path, y: str):  # noqa: ANN001, ANN202
    assert ON_LINE in SLIDER_CRANK
    path = tmp_path / "slider_crank.toml"
    path.write_text(SLIDER_CRANK.replace(ON_LINE, f"B  = [173.18, {y}]"), encoding="utf-8")
    return path


def test_check_names_the_slider_the_point_and_the_distance(tmp_path) -> None:
    path = _drawn(tmp_path, "21.5")
    run = CliRunner().invoke(main, ["check", str(path)])
    assert run.exception is None or isinstance(run.exception, SystemExit)
    assert run.exit_code == 2
    (line,) = [ln for ln in run.output.splitlines() if ln.strip()]
    assert line.startswith(f"excavkin: error: {path} [sliders.pin_on_slide] 'point': ")
    assert "point B is drawn 1.5 mm off the line G1→G2 it slides on" in line
    # the tolerance said in mm: 1e-4 of the sketch's size (O2 at x = 0 to C at x = 213.18 mm)
    assert f"{ASSEMBLY_TOL * 213.18:.2g} mm" in line


def test_the_library_refuses_it_too(tmp_path) -> None:
    with pytest.raises(AssemblyError) as err:
        excavkin.load(_drawn(tmp_path, "19"))
    assert err.value.table == "sliders.pin_on_slide" and err.value.entry == "point"
    assert "1 mm off" in str(err.value)


def test_within_the_tolerance_it_is_accepted(tmp_path) -> None:
    """0.01 mm off, below 1e-4 of 213.18 mm (0.0213 mm): accepted, as before."""
    path = _drawn(tmp_path, "20.01")
    run = CliRunner().invoke(main, ["check", str(path)])
    assert run.exit_code == 0, run.output
    assert "ok: the model is valid and assembles at its sketch" in run.output


def test_a_slider_in_a_newton_group_is_checked_alike() -> None:
    model = excavkin.load("slider_crank").model
    points = dict(model.points)
    points["C"] = (points["C"][0], points["C"][1] - 0.003)  # the piston's second point, 3 mm off
    off = dataclasses.replace(model, points=points)
    for method in ("closed-form", "newton"):
        with pytest.raises(AssemblyError, match=r"point C is drawn 3 mm off the line G1→G2"):
            Mechanism(off, method=method)  # type: ignore[arg-type]


def test_no_built_in_example_has_a_point_off_its_line() -> None:
    """The built-in examples load as before; every slider's point is on its line to the bit."""
    for name in excavkin.examples("model"):
        model = excavkin.load(name).model
        for sl in model.sliders:
            (x1, y1), (x2, y2) = model.points[sl.along[0]], model.points[sl.along[1]]
            px, py = model.points[sl.point]
            cross = (x2 - x1) * (py - y1) - (y2 - y1) * (px - x1)
            assert cross / math.dist((x1, y1), (x2, y2)) == 0.0, (name, sl.name)
