"""The report draws what it is given: building it never solves, and the names it used to hold
for the default sweep are the library's."""

from __future__ import annotations

from typing import Any

import pytest

import excavkin
import excavkin.default_sweep as sweep_module
import excavkin.outputs.report as report
from excavkin.default_sweep import default_sweep


class NoSolving:
    """A mechanism that refuses to solve, and is otherwise the one it wraps."""

    def __init__(self, mech: Any) -> None:
        self._mech = mech

    def __getattr__(self, name: str) -> Any:
        return getattr(self._mech, name)

    def solve(self, *args: Any, **kwargs: Any) -> Any:
        raise AssertionError("the report solved")

    solve_stream = solve


def test_building_a_report_never_solves() -> None:
    mech = excavkin.load(excavkin.example_path("slider_crank"))
    result = mech.solve(default_sweep(mech, n=9))
    text = report.build_report(NoSolving(mech), result, title="no solving")
    assert text.startswith("<!DOCTYPE html>") and "no solving" in text
    with pytest.raises(AssertionError, match="the report solved"):
        NoSolving(mech).solve({})


def test_the_default_sweep_names_are_still_found_on_the_report() -> None:
    for name in ("default_sweep", "solve_default", "N_ROTARY", "N_LINEAR", "STROKE"):
        assert getattr(report, name) is getattr(sweep_module, name)
