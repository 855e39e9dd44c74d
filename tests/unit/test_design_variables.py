"""Design variables named in a model file: one value that several entries refer to, with a
unit, a nominal value and bounds; a reference only, nothing evaluated."""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from excavkin.errors import InputError, ModelError

TEXT = """
schema_version = 1
name = "four-bar with design variables"
[units]
length = "mm"
angle = "deg"
[design.coupler]
value = "120 mm"
bounds = ["110 mm", "130 mm"]
[design.span]
value = 100
[design.rocker_mass]
kind = "mass"
value = "0.6 kg"
[points]
O2 = [0, 0]
A  = [0, 40]
B  = [110, 90]
O4 = ["span", 0]
[bodies]
ground  = { points = ["O2", "O4"], ground = true }
crank   = { points = ["O2", "A"] }
coupler = { points = ["A", "B"] }
rocker  = { points = ["O4", "B"], mass = "rocker_mass", inertia = "4.5e-4 kg*m^2", \
center_of_mass = [105, 45] }
[lengths]
"A-B" = "coupler"
"O4-B" = 90
[drivers.crank]
type = "rotary"
body = "crank"
pivot = "O2"
reference = "ground"
"""


def test_a_variable_is_a_parameter_that_sets_every_entry_referring_to_it() -> None:
    mech = excavkin.loads(TEXT, "variables.toml")
    plain = excavkin.load(excavkin.example_path("fourbar"))
    assert mech.design_variables["coupler"] == (0.12, (0.11, 0.13), "length")
    assert mech.design_variables["rocker_mass"] == (0.6, None, "mass")
    assert list(mech.parameters)[:3] == ["coupler", "span", "rocker_mass"]
    q = {"crank": np.radians(np.linspace(0, 360, 13))}
    ab = np.linspace(0.11, 0.13, 13)
    a = mech.solve(q, params={"coupler": ab}, sensitivities=["coupler", "span"], loads="model")
    b = plain.solve(q, params={"A-B": ab}, sensitivities=["A-B", "O4.x"], loads="model")
    np.testing.assert_array_equal(a.kinematics.positions, b.kinematics.positions)
    np.testing.assert_array_equal(a.sensitivity("B.x", "coupler"), b.sensitivity("B.x", "A-B"))
    np.testing.assert_array_equal(
        a.sensitivity("crank.torque", "span"), b.sensitivity("crank.torque", "O4.x")
    )
    heavy = mech.solve(q, params={"rocker_mass": "1.2 kg"}, loads="model")
    ref = plain.solve(q, params={"rocker.mass": 1.2}, loads="model")
    np.testing.assert_array_equal(heavy.torque("crank"), ref.torque("crank"))


def test_a_variable_shared_by_two_entries_differentiates_as_their_sum() -> None:
    text = TEXT.replace('"O4-B" = 90', '"O4-B" = "coupler"').replace(
        "B  = [110, 90]", "B  = [115, 95]"
    )
    mech = excavkin.loads(text, "shared.toml")
    q = {"crank": np.radians([20.0, 140.0, 260.0])}
    res = mech.solve(q, sensitivities=["coupler", "A-B", "O4-B"])
    np.testing.assert_allclose(
        res.sensitivity("rocker.angle", "coupler"),
        res.sensitivity("rocker.angle", "A-B") + res.sensitivity("rocker.angle", "O4-B"),
        rtol=1e-13,
    )
    with pytest.raises(InputError, match="both itself and through design variable 'coupler'"):
        mech.solve(q, params={"coupler": 0.12, "A-B": 0.12})


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (('O4 = ["span", 0]', "O4 = [100, 0]"), "[design.span]: no entry refers to"),
        (('mass = "rocker_mass"', 'mass = "coupler"'), "design variable 'coupler' is a length"),
        (('bounds = ["110 mm", "130 mm"]', 'bounds = ["125 mm", "130 mm"]'), "hold the nominal"),
        (('bounds = ["110 mm", "130 mm"]', 'bounds = ["110 mm"]'), "bounds must be [low, high]"),
        (("value = 100", "value = 100\nstep = 1"), "unknown key step"),
        (("[design.span]\nvalue = 100", '[design.span]\nkind = "length"'), "needs its nominal"),
        (('kind = "mass"', 'kind = "force"'), "kind must be"),
        (('O4 = ["span", 0]', 'O4 = ["spam", 0]'), "O4"),
    ],
)
def test_mistakes_name_the_file_table_and_entry(change, words) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ModelError) as info:
        excavkin.loads(TEXT.replace(*change), "variables.toml")
    assert words in str(info.value) and "variables.toml" in str(info.value)
