"""Regression tests for the findings of the first critical review (issues 2, 3, 6): each one
reproduces a case that used to give a wrong number, a silent NaN or a traceback."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import excavkin
from excavkin.errors import AssemblyError, InputError, ModelError
from excavkin.mechanism import Mechanism
from tests.conftest import EXAMPLES
from tests.property.test_random_linkages import TRIAD, triad

FOURBAR = (EXAMPLES / "fourbar.toml").read_text()


def test_negative_driven_length_is_refused_per_sample() -> None:
    """A negative cylinder length used to be solved as the mirror-image pose, marked ok."""
    mech = excavkin.load(EXAMPLES / "pasika_module.toml")
    res = mech.solve({"cyl": np.array([-1.0, 0.0, 1.0])})
    assert res.status.message(0) == "a driven length is zero or negative"
    assert res.status.message(1) == "a driven length is zero or negative"
    assert res.status.code[2] == 0
    assert np.isnan(res.positions[:2]).any(axis=(1, 2)).all()
    np.testing.assert_array_equal(res.driver("cyl")[0], [-1.0, 0.0, 1.0])  # the input is kept


def test_dyad_whose_partners_coincide_is_flagged_not_nan_ok() -> None:
    """Crank pin A passes through the rocker pivot O4: the dyad B has no base there."""
    text = (
        FOURBAR.replace("O4 = [100, 0]", "O4 = [40, 0]")
        .replace('"O4-B" = 90', '"O4-B" = 90\n"O2-A" = 40')
        .replace("B  = [110, 90]", "B  = [60, 120]")
    )
    mech = excavkin.loads(text)
    res = mech.solve({"crank": np.array([0.0, 1.5])})
    assert res.status.code[0] != 0, "a NaN sample must carry a reason"
    assert "dyad B" in res.status.message(0)
    assert np.isfinite(res.positions[1]).all() and res.status.code[1] == 0


def test_duplicate_length_in_both_orders_is_an_error() -> None:
    with pytest.raises(ModelError, match=r"\[lengths\] 'B-A': the distance B-A is given twice"):
        excavkin.loads(FOURBAR.replace('"A-B"  = 120', '"A-B"  = 120\n"B-A"  = 121'))


def test_slide_through_coincident_points_is_an_error() -> None:
    text = (EXAMPLES / "slider_crank.toml").read_text().replace("G2 = [100, 20]", "G2 = [0, 20]")
    with pytest.raises(ModelError, match="line's points G1 and G2 coincide"):
        excavkin.loads(text)


def test_sketch_at_a_dead_position_is_refused() -> None:
    """Lengths that put the re-assembled sketch at a dead position (coupler and rocker
    collinear: |A − O4| = 140 mm = 50 + 90) leave the branch undetermined."""
    text = FOURBAR.replace("A  = [0, 40]", "A  = [-40, 0]").replace(
        "B  = [110, 90]", "B  = [10, 5]"
    )
    text = text.replace('"A-B"  = 120', '"A-B"  = 50')
    with pytest.raises(AssemblyError, match="dead position of dyad B"):
        excavkin.loads(text)


def test_newton_group_takes_the_shorter_way_round() -> None:
    """q and q + 2π are one pose: the continuation from the sketch must not depend on how the
    angle is written."""
    mech = Mechanism(triad(TRIAD))
    q0 = mech.sketch_values()["crank"]
    res = mech.solve({"crank": np.array([q0 - 0.4, q0 - 0.4 + 2 * np.pi, q0 - 0.4 - 4 * np.pi])})
    assert res.status.all_ok, res.status.summary()
    np.testing.assert_allclose(res.positions[1], res.positions[0], atol=1e-12)
    np.testing.assert_allclose(res.positions[2], res.positions[0], atol=1e-12)


def test_linear_input_value_survives_a_failed_sample() -> None:
    mech = excavkin.load(EXAMPLES / "excavator.toml")
    lengths = np.linspace(0.5, 6.0, 12)
    res = mech.solve({"boom_cyl": lengths})
    assert (~res.status.ok).any()
    np.testing.assert_array_equal(res.driver("boom_cyl")[0], lengths)
    np.testing.assert_array_equal(res.to_frame()["boom_cyl.value"], lengths)


def test_locked_driver_is_named_as_locked() -> None:
    mech = excavkin.load(EXAMPLES / "rope_shovel.toml")
    with pytest.raises(InputError, match="driver 'c2' is locked, not an input"):
        mech.solve({"c2": 1.0})


def test_ground_points_keep_their_sketch_coordinates_exactly() -> None:
    mech = excavkin.load(EXAMPLES / "fourbar.toml")
    pos = mech.solve({"crank": np.array([0.3])}).point("O4")[0]
    assert pos.tolist() == [[0.1, 0.0]]


@pytest.mark.parametrize(
    "args",
    [
        ["--sweep", "crank=0:1:3", "--sweep", "crank=0:2:3"],
        ["--set", "crank=nan"],
        ["--sweep", "crank=0:inf:3"],
    ],
)
def test_cli_refuses_repeated_and_non_finite_values(tmp_path: Path, args: list[str]) -> None:
    out = tmp_path / "x.csv"
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "excavkin",
            "solve",
            str(EXAMPLES / "fourbar.toml"),
            *args,
            "-o",
            str(out),
        ],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert not out.exists()


def test_machine_whose_stroke_never_assembles_names_the_cylinder(tmp_path: Path) -> None:
    from excavkin.excavator.machine_file import load_machine

    bad = tmp_path / "machine.toml"
    text = (EXAMPLES / "excavator_machine.toml").read_text()
    text = text.replace('model = "excavator.toml"', f'model = "{EXAMPLES / "excavator.toml"}"')
    bad.write_text(text.replace("retracted = 2170", "retracted = 100"))
    with pytest.raises(ModelError, match=r"\[cylinders.arm\].*cylinder 'arm_cyl'"):
        load_machine(bad)
