"""The study file's pose sets and clearance metrics: good files read as meant (a file without
sets as before), and every bad one is one message naming the file, the table and the entry."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

import excavkin
from excavkin.cli import main
from excavkin.errors import ExcavkinError
from excavkin.studies.metrics import Metric
from excavkin.studies.study_file import load_study
from tests.property.test_pose_sets import STUDY, write


def test_the_reader_reads_the_sets_and_the_metrics_sets(tmp_path: Path) -> None:
    study = load_study(write(tmp_path))
    assert list(study.sets) == [None, "low", "high", "held"]
    assert study.pose_count == 25 + 7 + 9 + 5
    assert_allclose(study.pose_sets["high"].values["crank"], np.radians(np.linspace(150, 210, 9)))
    assert_allclose(study.pose_sets["high"].rates["crank"], 2 * np.pi)
    assert study.pose_sets["held"].rates == {}
    by = {m.name: m for m in study.metrics}
    assert by["gamma_min"].poses is None and by["torque_high"].poses == "high"
    assert by["gap"].clearance == ("O2", "A", "O4", "B") and by["gap"].reduce == "min"
    assert by["gap_last"].reduce == "last"
    assert study.units["gap"] == "mm"
    note = study.motion_note
    assert note.startswith("forces with the inertia") and "set 'held': static forces" in note
    assert "set 'high': forces with the inertia" in note


def test_a_file_without_sets_reads_as_before(tmp_path: Path) -> None:
    plain = STUDY.split("[pose_sets.low]")[0] + (
        '[metrics]\ngamma_min = { column = "B.transmission", reduce = "min" }\n'
    )
    study = load_study(write(tmp_path, plain))
    assert study.pose_sets == {} and list(study.sets) == [None]
    assert study.metrics == (Metric("gamma_min", "B.transmission", "min"),)


def test_named_sets_alone_need_each_metric_to_name_its_set(tmp_path: Path) -> None:
    text = STUDY.replace(
        '[poses]\ncrank = "0 deg:360 deg:25"\n[poses.rates]\ncrank = "300 rpm"\n', ""
    )
    with pytest.raises(ExcavkinError, match=r"metrics.*gamma_min.*names no pose set.*'low'"):
        load_study(write(tmp_path, text))
    only = text.replace(
        'reduce = "min" }\ntorque_turn', 'reduce = "min", poses = "low" }\ntorque_turn'
    )
    only = only.replace(
        'reduce = "absmax" }\ntorque_high', 'reduce = "absmax", poses = "low" }\ntorque_high'
    )
    study = load_study(write(tmp_path, only))
    assert list(study.sets) == ["low", "high", "held"]


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (('poses = "high" }\ntorque_held', 'poses = "hihg" }\ntorque_held'),
         r"metrics.*torque_high.*no pose set 'hihg'.*high"),
        (('[pose_sets.held]\ncrank = "100 deg:120 deg:5"', '[pose_sets.held]\nbucket = "1 deg"'),
         r"pose_sets\.held.*bucket.*no driver"),
        (('[pose_sets.held]\ncrank = "100 deg:120 deg:5"', '[pose_sets.held]\ncrank = "1 mm"'),
         r"pose_sets\.held.*crank"),
        (('[pose_sets.high.rates]\ncrank = "60 rpm"', '[pose_sets.high.rates]\ncrank = "60 mm"'),
         r"pose_sets\.high\.rates.*crank"),
        (('[pose_sets.held]\ncrank = "100 deg:120 deg:5"', "[pose_sets]\nheld = 3"),
         r"pose_sets.*held.*must be a table"),
        (('clearance = ["O2-A", "O4-B"]', 'clearance = ["O2-A", "O4-X"]'),
         r"metrics.*gap.*no point 'X'"),
        (('clearance = ["O2-A", "O4-B"]', 'clearance = ["O2A", "O4-B"]'),
         r"metrics.*gap.*'O2A'.*two point names"),
        (('clearance = ["O2-A", "O4-B"]', 'clearance = ["O2-O2", "O4-B"]'),
         r"metrics.*gap.*two different points"),
        (('clearance = ["O2-A", "O4-B"]', 'clearance = ["O2-A"]'), r"metrics.*gap.*two segments"),
        (('clearance = ["O2-A", "O4-B"]', 'clearance = ["O2-A", "O4-B"], column = "A.x"'),
         r"metrics.*gap.*no column"),
        (('["O2-A", "O4-B"], poses', '["O2-A", "O4-B"], reduce = "sumsq", poses'),
         r"metrics.*gap.*reduce"),
        (('gap = { min = "20 mm" }', 'gap = { min = "20 deg" }'), r"constraints.*gap"),
        (("[pose_sets.low]", "[poses.low]"), r"\[poses\] 'low'.*\[pose_sets.low\] table"),
        (('poses = "high" }\ntorque_held', 'poses = 3 }\ntorque_held'),
         r"metrics.*torque_high.*pose set"),
    ],
)  # fmt: skip
def test_errors_name_the_file_table_and_entry(
    tmp_path: Path, change: tuple[str, str], message: str
) -> None:
    old, new = change
    assert STUDY.count(old) == 1
    spec = write(tmp_path, STUDY.replace(old, new))
    with pytest.raises(ExcavkinError, match=message):
        load_study(spec)
    result = CliRunner().invoke(main, ["study", str(spec), "-q"])
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert str(spec) in result.output


def test_a_machine_study_has_no_pose_sets_nor_clearances(tmp_path: Path) -> None:
    from excavkin.excavator.study import load_machine_study

    text = excavkin.example_path("excavator_bucket_linkage").read_text(encoding="utf-8")
    with_sets = write(tmp_path, text + '\n[pose_sets.x]\nbucket_cyl = "1.8 m"\n', "a.toml")
    with pytest.raises(ExcavkinError, match=r"a.toml.*pose_sets"):
        load_machine_study(with_sets)
    named = text.replace('reduce = "min" }', 'reduce = "min", poses = "x" }', 1)
    spec = write(tmp_path, named, "b.toml")
    with pytest.raises(ExcavkinError, match=r"b.toml.*\[metrics\].*unknown key poses"):
        load_machine_study(spec)
