"""Loaders on the same footing as excavators, item 2: the built-in wheel loader's figures, as
docs/loader.md states them (a change to the example or the analyses shows here first)."""

from __future__ import annotations

import math

import pytest

from excavkin.loader.breakout import breakout
from excavkin.loader.capacity import capacity
from excavkin.loader.dimensions import dimensions
from excavkin.loader.machine_file import load_machine
from excavkin.loader.tipping import static_tipping
from tests.conftest import EXAMPLES


def test_the_built_in_loaders_figures_are_those_the_docs_state() -> None:
    m = load_machine(EXAMPLES / "wheel_loader_machine.toml")
    d = dimensions(m)
    mm = {k: round(d[k] * 1e3) for k in ("hinge-pin height at full lift", "digging depth")}
    assert mm == {"hinge-pin height at full lift": 4024, "digging depth": 108}
    assert round(d["dump clearance at 45 deg"] * 1e3) == 2680
    assert round(d["dump reach at 45 deg"] * 1e3) == 1610
    deg = {f.name: round(math.degrees(f.value), 1) for f in d.figures if f.unit == "rad"}
    assert deg == {
        "rollback at ground": 43.9,
        "rollback at carry": 46.8,
        "rollback at full lift": 59.1,
        "dump angle at full lift": 47.0,
    }
    b = breakout(m)
    assert (round(b.tilt.force / 1e2) / 10, b.tilt.limiting) == (142.6, "tilt")
    assert (round(b.lift.force / 1e2) / 10, b.lift.limiting) == (91.4, "tipping (front axle)")
    t = static_tipping(m)
    assert round(t.straight.load) == pytest.approx(10919, abs=1)
    assert round(t.full_turn.load) == pytest.approx(9291, abs=1)
    assert round(t.rated_operating_capacity) == pytest.approx(4646, abs=1)
    c = capacity(m)
    assert (round(c.to_full_height), c.lift_limit[-1]) == (9475, "lift")
