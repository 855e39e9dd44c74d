"""Loads given in Python carry units: quantities of any pint registry and strings, converted by
dimension; a wrong dimension names the load."""

from __future__ import annotations

import numpy as np
import pint
import pytest

import excavkin
from excavkin.errors import UnitError
from excavkin.kinetostatics import Gravity, PointForce, Torque


@pytest.fixture(scope="module")
def solved() -> tuple[excavkin.Mechanism, excavkin.KinematicResult]:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    return mech, mech.solve({"crank": np.radians(np.linspace(0, 360, 7))}, rates={"crank": 3.0})


def test_quantities_and_strings_equal_si_numbers_to_the_bit(solved) -> None:  # type: ignore[no-untyped-def]
    mech, res = solved
    u = pint.UnitRegistry()  # a registry of the user's own, not excavkin's
    with_units = [
        PointForce("push", "rocker", "B", ("1 kN", "-2 kN")),
        Torque("brake", "rocker", 300 * u("N*cm")),
        Gravity(g="9.81 m/s^2"),  # type: ignore[arg-type]
    ]
    plain = [
        PointForce("push", "rocker", "B", (1000.0, -2000.0)),
        Torque("brake", "rocker", 3.0),
        Gravity(g=9.81),
    ]
    a, b = mech.forces(res, with_units), mech.forces(res, plain)
    np.testing.assert_array_equal(a.torque("crank"), b.torque("crank"))
    np.testing.assert_array_equal(a.pin_force, b.pin_force)
    assert np.abs(b.torque("crank")).max() > 10.0  # the loads matter


def test_a_function_may_return_a_quantity_array(solved) -> None:  # type: ignore[no-untyped-def]
    mech, res = solved
    u = pint.UnitRegistry()
    n = len(res)
    per_sample = np.column_stack([np.linspace(0, 1, n), -np.ones(n)])
    a = mech.forces(res, [PointForce("dig", "rocker", "B", lambda r: per_sample * u.kN)])
    b = mech.forces(res, [PointForce("dig", "rocker", "B", per_sample * 1e3)])
    np.testing.assert_array_equal(a.torque("crank"), b.torque("crank"))


def test_solve_with_loads_converts_too(solved) -> None:  # type: ignore[no-untyped-def]
    mech, _ = solved
    q = {"crank": np.radians([10.0, 70.0])}
    a = mech.solve(q, loads=[Torque("brake", "rocker", "0.5 kN*m")])
    b = mech.solve(q, loads=[Torque("brake", "rocker", 500.0)])
    np.testing.assert_array_equal(a.torque("crank"), b.torque("crank"))


@pytest.mark.parametrize(
    ("load", "words"),
    [
        (Torque("brake", "rocker", "3 kN"), "load 'brake': '3 kN' is not a torque"),
        (PointForce("push", "rocker", "B", ("1 m", "0 N")), "load 'push'"),
        (Gravity(g="9.81 m"), "gravity"),  # type: ignore[arg-type]
    ],
)
def test_a_wrong_dimension_names_the_load(solved, load, words) -> None:  # type: ignore[no-untyped-def]
    mech, res = solved
    with pytest.raises(UnitError, match=words):
        mech.forces(res, [load])
