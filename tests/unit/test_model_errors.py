"""Every bad input gives a clear message that names the file, the table and the entry."""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from excavkin.errors import AssemblyError, InputError, MobilityError, ModelError, UnitError

GOOD = """
schema_version = 1
name = "four-bar"
[units]
length = "mm"
angle = "deg"
[points]
O2 = [0, 0]
A  = [0, 40]
B  = [110, 90]
O4 = [100, 0]
[bodies]
ground  = { points = ["O2", "O4"], ground = true }
crank   = { points = ["O2", "A"] }
coupler = { points = ["A", "B"] }
rocker  = { points = ["O4", "B"] }
[lengths]
"A-B" = 120
[drivers.crank]
type = "rotary"
body = "crank"
pivot = "O2"
reference = "ground"
"""


def load(text: str) -> excavkin.Mechanism:
    return excavkin.loads(text, source="model.toml")


def test_good_model_loads() -> None:
    assert load(GOOD).inputs == ("crank",)


@pytest.mark.parametrize(
    ("old", "new", "error", "words"),
    [
        (
            'rocker  = { points = ["O4", "B"] }',
            'rocker  = { points = ["O4", "Q"] }',
            ModelError,
            ["model.toml", "[bodies]", "'rocker'", "unknown point 'Q'"],
        ),
        (
            'rocker  = { points = ["O4", "B"] }',
            'rocker  = { points = ["O4"] }',
            ModelError,
            ["[bodies]", "'rocker'", "at least 2 points"],
        ),
        ('"A-B" = 120', '"A-B" = -5', ModelError, ["[lengths]", "'A-B'", "positive"]),
        ('"A-B" = 120', '"A-B" = 400', AssemblyError, ["cannot be assembled", "dyad B"]),
        ('"A-B" = 120', '"A-B" = "120 deg"', UnitError, ["[lengths]", "'A-B'", "not a length"]),
        ('"A-B" = 120', '"A-B" = "120 parsecz"', UnitError, ["[lengths]", "cannot read"]),
        ('length = "mm"', 'length = "kg"', UnitError, ["[units]", "'length'", "not a unit of"]),
        ('length = "mm"\n', "", UnitError, ["[points]", "needs a unit"]),
        ("schema_version = 1", "schema_version = 7", ModelError, ["schema_version = 7"]),
        ("schema_version = 1", "", ModelError, ["schema_version is missing"]),
        (
            'name = "four-bar"',
            'name = "four-bar"\ncolour = "red"',
            ModelError,
            ["unknown top-level key colour"],
        ),
        ('body = "crank"', 'body = "crnk"', ModelError, ["[drivers.crank]", "unknown body 'crnk'"]),
        ('type = "rotary"', 'type = "spinning"', ModelError, ["type must be 'rotary' or 'linear'"]),
        ('pivot = "O2"', 'pivot = "O4"', ModelError, ["pivot 'O4' is not a point of body"]),
        (
            'ground  = { points = ["O2", "O4"], ground = true }',
            'ground  = { points = ["O2", "O4"] }',
            ModelError,
            ["exactly one body", "found none"],
        ),
        (
            'crank   = { points = ["O2", "A"] }',
            'crank   = { points = ["O2", "A"], mass = -1 }',
            UnitError,
            ["[bodies]", "'crank'", "needs a unit"],
        ),
        (
            'crank   = { points = ["O2", "A"] }',
            'crank   = { points = ["O2", "A"], mass = "-1 kg" }',
            ModelError,
            ["'crank'", "mass must be positive"],
        ),
        (
            'crank   = { points = ["O2", "A"] }',
            'crank   = { points = ["O2", "A"], colour = 1 }',
            ModelError,
            ["'crank'", "unknown key colour"],
        ),
        (
            "[drivers.crank]",
            '[drivers.crank2]\ntype = "rotary"\nbody = "rocker"\npivot = "O4"\n[drivers.crank]',
            MobilityError,
            ["mobility 1", "2 drivers", "1 is redundant"],
        ),
        (
            "B  = [110, 90]",
            "B  = [110, 90]\nZ = [5, 5]",
            ModelError,
            ["[points]", "Z: point belongs to no body"],
        ),
        ("B  = [110, 90]", "B  = [110, 90]\nB = [1, 1]", ModelError, ["not valid TOML"]),
        ("B  = [110, 90]", "B  = [50, 20]", AssemblyError, ["'B'", "lies on the line through"]),
    ],
)
def test_error_messages(old: str, new: str, error: type, words: list[str]) -> None:
    assert old in GOOD
    with pytest.raises(error) as info:
        load(GOOD.replace(old, new, 1))
    text = str(info.value)
    for w in words:
        assert w in text, f"{w!r} not in {text!r}"


def test_missing_driver_is_named() -> None:
    text = GOOD.split("[drivers.crank]")[0]
    with pytest.raises(MobilityError, match=r"mobility 1 .* but 0 drivers .* 1 driver is missing"):
        load(text)


def test_body_with_one_point() -> None:
    with pytest.raises(ModelError, match="at least 2 points"):
        load(GOOD.replace('coupler = { points = ["A", "B"] }', 'coupler = { points = ["A"] }'))


def test_locally_over_constrained_chain_is_named() -> None:
    """Mobility matches (a redundant strut plus a missing driver) but a sub-chain is rigid."""
    text = GOOD.replace(
        "[drivers.crank]",
        '[drivers.strut]\ntype = "linear"\nbetween = ["A", "O4"]\nmode = "locked"\n[drivers.crank]',
    )
    with pytest.raises(MobilityError):
        load(text)


def test_unknown_driver_and_bad_arrays_in_solve() -> None:
    mech = load(GOOD)
    with pytest.raises(InputError, match="unknown driver 'crnk'.*inputs are crank"):
        mech.solve({"crnk": [0.0]})
    with pytest.raises(InputError, match="different lengths"):
        mech.solve({"crank": [0.0, 1.0]}, rates={"crank": [1.0, 2.0, 3.0]})
    with pytest.raises(InputError, match="1-D"):
        mech.solve({"crank": np.zeros((2, 2))})
    with pytest.raises(TypeError):
        mech.solve({"crank": [0.0]}, colour="red")  # type: ignore[call-arg]


def test_samples_that_cannot_close_are_marked_not_nan_silently() -> None:
    """A non-Grashof four-bar: the crank cannot turn fully; the samples say why."""
    mech = load(GOOD.replace('"A-B" = 120', '"A-B" = 120\n"O2-A" = 95'))
    th = np.radians(np.linspace(0, 360, 361))
    res = mech.solve({"crank": th})
    bad = ~res.status.ok
    assert bad.any() and (~bad).any()
    assert np.isnan(res.positions[bad][:, 2]).all()  # B is NaN where it cannot close...
    assert np.isfinite(res.positions[~bad]).all()  # ...and nowhere else
    assert set(res.status.labels()[bad]) <= {
        "cannot close at dyad B (from A and O4)",
        "dead position at dyad B (from A and O4)",
    }
    assert "samples failed" in res.status.summary()
    with pytest.raises(excavkin.SolveFailure, match="cannot close at dyad B"):
        mech.solve({"crank": th}, strict=True)
    frame = res.to_frame()
    assert (frame["status"] != "ok").sum() == bad.sum()


def test_dead_position_is_reported_with_the_dyad() -> None:
    """At the limit position of the rocker (crank and coupler collinear, sin μ = 0 exactly
    reached in the sweep) the transmission angle is zero: the dyad's matrix is singular."""
    # a change-point four-bar: a + b = c + d, at θ = 0 all four links are collinear
    text = GOOD.replace('"A-B" = 120', '"A-B" = 130\n"O2-A" = 30\n"O4-B" = 60\n"O2-O4" = 100')
    mech = load(text.replace("O4 = [100, 0]", "O4 = [100, 0]"))
    res = mech.solve({"crank": np.array([0.0, 0.5, np.pi])})
    assert res.status.message(0) == "dead position at dyad B (from A and O4)"
    assert np.isfinite(res.positions[0]).all()  # the position is there...
    assert np.isnan(res.velocities[0, 2]).all()  # ...its rates are not, and the status says why
    assert res.status.code[1] == 0
