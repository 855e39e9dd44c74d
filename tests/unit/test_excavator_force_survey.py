"""The tool forces of ``excavkin excavator forces`` as a library result: each row is the
forces module's own answer, and its arguments are checked."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin.errors import InputError
from excavkin.excavator.force_survey import tool_force_survey
from excavkin.excavator.forces import force_maximum, rated_force, tool_forces
from excavkin.excavator.machine_file import load_machine
from excavkin.excavator.ranges import sweep


@pytest.fixture(scope="module")
def machine():  # type: ignore[no-untyped-def]
    return load_machine(excavkin.example_path("excavator_machine"))


def test_each_row_is_the_forces_modules_own(machine) -> None:  # type: ignore[no-untyped-def]
    survey = tool_force_survey(machine, 4, gravity=False)
    frame = survey.to_frame()
    assert list(frame["kind"]) == ["rated"] * 4 + ["sweep_max"] * 4
    assert list(frame["cylinder"]) == ["arm", "bucket"] * 4
    lengths = sweep(machine, 4).lengths
    for i, (at, working) in enumerate([(a, w) for a in ("lip", "tip") for w in ("arm", "bucket")]):
        rated = rated_force(machine, working, at=at)  # type: ignore[arg-type]
        assert_allclose(frame["force"][i], rated.force, rtol=1e-15)
        assert_allclose(frame["moment"][i], rated.moment, rtol=1e-15)
        most = force_maximum(tool_forces(machine, lengths, working, at=at, gravity=False))  # type: ignore[arg-type]
        assert_allclose(frame["force"][4 + i], most.force, rtol=1e-15)
        assert np.isnan(frame["moment"][4 + i]) and not frame["gravity"][4 + i]
    assert set(survey.maps) == {"arm", "bucket"}
    text = survey.summary()
    assert "4³ stroke sweep (without gravity of the front)" in text
    assert len(text.splitlines()) == 3 + 4 + 1 + 4 + 1
    assert frame.attrs["excavkin.kinds"]["moment"] == "torque"


def test_too_few_samples_are_refused(machine) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InputError, match="at least 2"):
        tool_force_survey(machine, 1)


def test_working_ranges_give_their_table_and_summary(machine) -> None:  # type: ignore[no-untyped-def]
    from excavkin.excavator.ranges import working_ranges

    wr = working_ranges(machine)
    frame = wr.to_frame()
    assert list(frame["key"]) == [f.key for f in wr.figures]
    assert_allclose(frame["value"], [f.value for f in wr.figures], rtol=0)
    assert_allclose(frame[["boom", "arm", "bucket"]], [f.lengths for f in wr.figures], rtol=0)
    assert frame.attrs["excavkin.model"] == machine.name
    assert_allclose(wr.envelope_frame()[["x", "y"]], wr.envelope, rtol=0)
    lines = wr.summary().splitlines()
    assert lines[0].startswith(machine.name) and len(lines) == 2 + len(wr.figures)
    depth = wr.figure("max_digging_depth")
    assert f"{round(depth.value * 1000):8d}" in lines[2 + wr.figures.index(depth)]


def test_the_lift_table_gives_its_table_and_summary(machine) -> None:  # type: ignore[no-untyped-def]
    from excavkin.excavator.lift import lift_table

    t = lift_table(machine, step=2.0, pressure="relief")
    frame = t.to_frame()
    cells = int(t.reachable.sum()) + int(np.isfinite(t.max_reach).sum())
    assert len(frame) == 2 * cells and set(frame["over"]) == {"front", "side"}
    inside = frame[~frame["at_max_reach"] & (frame["over"] == "side")]
    rated = t.rated("side")[t.reachable] / machine.gravity
    assert_allclose(inside["rated_load"], rated, rtol=1e-15)
    lines = t.summary().splitlines()
    assert len(lines) == 4 + len(t.heights) and "relief pressure" in lines[1]
    assert frame.attrs["excavkin.kinds"]["rated_load"] == "mass"


def test_the_cycle_sheet_is_the_hydraulics_modules_own(machine) -> None:  # type: ignore[no-untyped-def]
    from excavkin.excavator.cycle_sheet import hydraulic_cycle
    from excavkin.excavator.hydraulics import cycle_time, relief_buckling, strokes

    sheet = hydraulic_cycle(machine)
    frame = sheet.to_frame()
    stroke = frame[frame["section"] == "stroke"]
    assert_allclose(stroke["extend_time"], [s.extend_time for s in strokes(machine)], rtol=0)
    cycle = frame[frame["section"] == "cycle"].set_index("phase")["time"]
    assert cycle["cycle, one motion at a time"] == cycle_time(machine).sequential
    relief = frame[(frame["section"] == "buckling") & (frame["case"] == "relief, fully extended")]
    assert_allclose(relief["critical"], [float(b.critical[0]) for b in relief_buckling(machine)],
                    rtol=0)  # fmt: skip
    assert [c for c, _ in sheet.buckling] == [
        "relief, fully extended", "ISO 6015 arm force", "ISO 6015 bucket force"]  # fmt: skip
    text = sheet.sections()
    assert list(text) == ["strokes", "cycle", "power", "buckling"]
    assert sheet.summary() == "\n".join(text.values())
    assert frame.attrs["excavkin.kinds"]["peak_power"] == "power"


def test_the_stability_survey_is_the_stability_modules_own(machine) -> None:  # type: ignore[no-untyped-def]
    from excavkin.excavator.stability import base_rated_force
    from excavkin.excavator.stability_survey import MAPS, pin_grid, stability_survey

    survey = stability_survey(machine, 3, swing="side")
    frame = survey.to_frame()
    assert list(frame["standard"]) == ["ISO 6015"] * 2 + ["SAE J1179"] * 2
    direct = base_rated_force(machine, "bucket", at="tip", swing="side")
    assert_allclose(frame["force"][3], direct.rated.force, rtol=1e-15)
    assert_allclose(frame["tipping_force"][3], direct.tipping, rtol=1e-15)
    assert pin_grid(3) == (9, 9, 5) and len(survey.pin) == len(survey.tipping["front"].margin)
    text = survey.summary()
    assert "Rated tool forces over the side" in text and "9² × 5 for the bucket pin" in text
    assert tuple(MAPS) == (
        "tipping-front",
        "tipping-side",
        "limits-arm",
        "limits-bucket",
        "support",
    )
    with pytest.raises(InputError, match="at least 2"):
        stability_survey(machine, 1)


def test_a_tip_target_gives_every_branch_and_checks_the_valid_one(machine) -> None:  # type: ignore[no-untyped-def]
    from excavkin.excavator.ik import tip_target
    from excavkin.excavator.machine import forward

    target = tip_target(machine, 7.0, -1.5, np.radians(-90.0))
    assert target.valid and target.check() < 1e-12
    k = int(np.argmax(target.solution.valid[0]))
    fk = forward(machine, target.solution.lengths[0, k][None, :])
    assert_allclose(fk.tip[0], [7.0 + machine.swing_axis, -1.5 + machine.ground_line], atol=1e-12)
    assert target.notes(k) == [] and target.branch_name(k) == "pivot+ link+"
    assert "other assembly branch" in target.notes(2)
    far = tip_target(machine, 20.0, 0.0, np.radians(-90.0))
    assert not far.valid and np.isnan(far.check())
    assert far.summary().endswith("no valid solution: the pose is out of the working range")


def test_a_dig_gives_its_table_and_summary(machine) -> None:  # type: ignore[no-untyped-def]
    from excavkin.excavator.dig import default_dig, dig
    from excavkin.excavator.soil import Tool, soil

    d = dig(machine, default_dig(machine, 9), soil("loam"), Tool(1.2), "balovnev")
    frame = d.to_frame()
    assert list(frame["point"]) == list(range(9))
    assert_allclose(frame["margin"], d.available - d.required, rtol=0)
    assert_allclose(frame[["boom", "arm", "bucket"]], d.lengths, rtol=0)
    assert frame.attrs["excavkin.model"] == machine.name
    lines = d.summary().splitlines()
    assert len(lines) == 2 + 9 + 3 and lines[0].startswith(f"{machine.name} — balovnev")
