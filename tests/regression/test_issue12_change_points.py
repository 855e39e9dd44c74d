"""Issue 12: a change point between samples is said, and the user chooses how to go on."""

from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

import excavkin
from excavkin import Mechanism
from excavkin.cli import main
from excavkin.errors import InputError
from excavkin.outputs.events import find_events
from tests.models import parallelogram

SQUARE = parallelogram()


def coupler_offset(res: excavkin.KinematicResult) -> np.ndarray:
    """|B − A − (O4 − O2)| per sample: zero while the linkage is a parallelogram."""
    return np.hypot(*(res.point("B")[0] - res.point("A")[0] - np.array([0.1, 0.0])).T)


@pytest.mark.parametrize("degrees", [np.linspace(-30, 30, 61), np.linspace(30, -30, 60)])
def test_the_parallelogram_through_its_change_point(degrees) -> None:
    mech = Mechanism(SQUARE)
    q = np.radians(degrees)
    side = mech.solve({"crank": q})
    (cp,) = side.change_points
    assert cp.point == "B" and cp.partners == ("A", "O4") and cp.continued == "side"
    crossing = np.flatnonzero(np.diff(np.sign(degrees)))[0]
    assert cp.before <= crossing + 1 <= cp.after
    # the sketch's side is kept: past the change point the linkage is folded, 200 mm off
    off = coupler_offset(side)
    assert np.nanmax(off) == pytest.approx(0.2, rel=1e-3) and np.nanmin(off) < 1e-12
    smooth = mech.solve({"crank": q}, continuation="smooth")
    assert [c.continued for c in smooth.change_points] == ["smooth"]
    ok = smooth.status.ok
    assert np.nanmax(coupler_offset(smooth)[ok]) < 1e-12
    # exactly at crank 0 the crank's end sits on the rocker's pivot: B is undetermined
    if 0.0 in degrees:
        zero = int(np.flatnonzero(degrees == 0.0)[0])
        assert smooth.status.labels()[zero].startswith("undetermined")


def test_change_points_are_warned_of_in_the_report_and_on_the_command_line(tmp_path) -> None:
    mech = Mechanism(SQUARE)
    res = mech.solve({"crank": np.radians(np.linspace(-20, 20, 41))})
    events = [e for e in find_events(res) if e.kind == "change point"]
    assert len(events) == 1 and "between samples 19 and 21" in events[0].message
    model = tmp_path / "square.toml"
    model.write_text(
        """schema_version = 1
name = "parallelogram"
[units]
length = "mm"
[points]
O2 = [0, 0]
A = [0, 100]
B = [100, 100]
O4 = [100, 0]
[bodies]
ground = { points = ["O2", "O4"], ground = true }
crank = { points = ["O2", "A"] }
coupler = { points = ["A", "B"] }
rocker = { points = ["O4", "B"] }
[drivers.crank]
type = "rotary"
body = "crank"
pivot = "O2"
reference = "ground"
"""
    )
    r = CliRunner().invoke(
        main,
        [
            "solve",
            str(model),
            "--sweep",
            "crank=-21deg:19deg:21",
            "--continuation",
            "smooth",
            "-q",
            "-o",
            str(tmp_path / "s.csv"),
        ],
    )
    assert r.exit_code == 0 and "change point of dyad B" in r.output and "other side" in r.output


def test_no_change_point_is_seen_where_there_is_none() -> None:
    for name in ("fourbar", "slider_crank", "excavator", "rope_shovel", "pasika_module"):
        mech = excavkin.load(excavkin.example_path(name))
        for n in (3, 4, 5, 9, 361):
            values = {
                k: v + np.linspace(0, 2 * np.pi, n)
                if mech.input_kind(k) == "angle"
                else v * np.linspace(0.9, 1.1, n)
                for k, v in mech.sketch_values().items()
            }
            assert mech.solve(values).change_points == (), (name, n)


def test_smooth_continuation_is_for_closed_form_plans() -> None:
    mech = Mechanism(SQUARE, method="newton")
    with pytest.raises(InputError, match="Newton group"):
        mech.solve({"crank": np.radians([1.0, 2.0])}, continuation="smooth")
