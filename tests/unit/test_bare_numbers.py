"""A bare number in a file's default unit converts to SI exactly as pint converts it (the
factor is found once per unit, not parsed again for every number)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from excavkin.errors import UnitError
from excavkin.units import registry, to_si

CASES = [
    ("length", "mm"),
    ("length", "in"),
    ("length", "ft"),
    ("length", "m"),
    ("angle", "deg"),
    ("angle", "rad"),
    ("mass", "lb"),
    ("mass", "t"),
    ("inertia", "kg*mm^2"),
    ("force", "kN"),
    ("pressure", "bar"),
    ("velocity", "km/h"),
    ("angular_velocity", "rpm"),
]


@pytest.mark.parametrize(("kind", "unit"), CASES)
def test_bare_numbers_equal_pints_conversion_to_the_bit(kind: str, unit: str) -> None:
    from excavkin.units import KINDS

    ureg = registry()
    rng = np.random.default_rng(17)
    values = [0.0, -0.0, 1.0, 3, -250, 1e-300, 1.7e300, *rng.normal(0, 1e3, 200).tolist()]
    for v in values:
        want = ureg.Quantity(float(v), unit).to(KINDS[kind]).magnitude
        got = to_si(v, kind, unit)
        assert math.copysign(1.0, got) == math.copysign(1.0, want)
        assert got == want, (v, unit)


def test_a_bare_number_out_of_range_is_refused() -> None:
    with pytest.raises(UnitError, match="not a finite number"):
        to_si(1e308, "length", "km")
    with pytest.raises(UnitError, match="not a finite number"):
        to_si(float("nan"), "length", "mm")
