"""The pin loads over the working range as a library result (what ``excavkin excavator pins``
prints and writes): its maxima are those of each case's pin loads over the command's grids,
its table and summary hold them, and its arguments are checked."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin.errors import InputError
from excavkin.excavator.machine_file import load_machine
from excavkin.excavator.pin_loads import (
    lift_grid,
    pin_loads,
    working_range_pin_loads,
)
from excavkin.excavator.ranges import stroke_grid


@pytest.fixture(scope="module")
def machine():  # type: ignore[no-untyped-def]
    return load_machine(excavkin.example_path("excavator_machine"))


def test_the_maxima_are_each_cases_own_over_its_grid(machine) -> None:  # type: ignore[no-untyped-def]
    survey = working_range_pin_loads(machine, ("lift", "bucket"), samples=4, mass=1500.0)
    assert survey.cases == ("bucket", "lift")
    assert lift_grid(4) == (7, 7, 3) and lift_grid(31) == (61, 61, 8)
    bucket = pin_loads(machine, stroke_grid(machine, 4), "bucket")
    lift = pin_loads(machine, stroke_grid(machine, (7, 7, 3)), "lift", load=1500.0 * 9.80665)
    frame = survey.to_frame()
    pins = frame[frame["kind"] == "pin"]
    for j, name in enumerate(bucket.pins):
        row = pins[pins["name"] == name].iloc[0]
        by_case = [np.nanmax(np.where(r.held, r.load[:, j], np.nan)) for r in (bucket, lift)]
        assert_allclose([row["max_bucket"], row["max_lift"]], by_case, rtol=1e-15)
        assert_allclose(row["load"], max(by_case), rtol=1e-15)
        assert row["case"] == ("bucket", "lift")[int(np.argmax(by_case))]
    assert frame.attrs["excavkin.kinds"]["max_lift"] == "force"
    text = survey.summary()
    assert "1500 kg hanging at" in text and "4³ stroke sweep, 7 × 7 × 3 for the lift load" in text
    assert len(text.splitlines()) == 4 + len(frame) + 1


def test_its_arguments_are_checked(machine) -> None:  # type: ignore[no-untyped-def]
    for kwargs, words in (
        ({"cases": ("arm",), "mass": 100.0}, "lift case only"),
        ({"cases": ("lift",), "mass": -1.0}, "0 kg or more"),
        ({"cases": ("shovel",)}, "shovel"),
        ({"cases": ()}, "no load case"),
        ({"samples": 1}, "at least 2"),
    ):
        with pytest.raises(InputError, match=words):
            working_range_pin_loads(machine, **kwargs)  # type: ignore[arg-type]
