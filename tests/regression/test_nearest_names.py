"""A force result's and a machine's lookups by name say the nearest names, as a kinematic
result's do (they raised a bare KeyError or ValueError); they stay KeyErrors."""

from __future__ import annotations

import pytest

import excavkin
from excavkin import Gravity
from excavkin.errors import UnknownNameError
from excavkin.excavator.machine_file import load_machine


def test_force_lookups_name_the_nearest() -> None:
    res = excavkin.load("fourbar").solve({"crank": [0.1, 0.2]}, loads=[Gravity()])
    with pytest.raises(UnknownNameError, match="did you mean 'B.rocker'"):
        res.pin("B", "rockr")
    with pytest.raises(KeyError, match="did you mean 'crank'"):
        res.torque("crnk")
    with pytest.raises(UnknownNameError, match="did you mean 'ground'"):
        res.resultant("grund")
    with pytest.raises(UnknownNameError, match="no driven or locked linear element"):
        res.force("crank")


def test_a_machine_circuit_by_an_unknown_role() -> None:
    with pytest.raises(UnknownNameError, match=r"no cylinder role 'stick' \(known: boom, arm"):
        load_machine("excavator_machine").circuit("stick")
