"""Studies with several pose sets and clearance metrics (the reader's tests are in
tests/unit/test_study_sets_reader.py): a two-set study against one-set studies, static and
dynamic forces per set, clearances against shapely, resumption, the optimisers, and the
optimum written back as a model file."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import shapely
from click.testing import CliRunner
from numpy.testing import assert_allclose

import excavkin
from excavkin.cli import main
from excavkin.studies.design_space import sample_designs
from excavkin.studies.metrics import Metric, Poses, clearance_metric, evaluate
from excavkin.studies.optimize import _MechanismProblem, optimize_study
from excavkin.studies.study import chunks, run_study
from excavkin.studies.study_file import load_study

STUDY = """
[study]
model = "fourbar"
method = "sobol"
samples = 48
seed = 2
loads = "model"

[units]
length = "mm"

[parameters]
"A-B" = [110, 130]
"O4.x" = [90, 110]

[poses]
crank = "0 deg:360 deg:25"
[poses.rates]
crank = "300 rpm"

[pose_sets.low]
crank = "-30 deg:30 deg:7"

[pose_sets.high]
crank = "150 deg:210 deg:9"
[pose_sets.high.rates]
crank = "60 rpm"

[pose_sets.held]
crank = "100 deg:120 deg:5"

[metrics]
gamma_min = { column = "B.transmission", reduce = "min" }
torque_turn = { column = "crank.torque", reduce = "absmax" }
torque_high = { column = "crank.torque", reduce = "absmax", poses = "high" }
torque_held = { column = "crank.torque", reduce = "absmax", poses = "held" }
rocker_low = { column = "rocker.angle", reduce = "first", poses = "low" }
gap = { clearance = ["O2-A", "O4-B"], poses = "high" }
gap_last = { clearance = ["A-B", "O2-O4"], reduce = "last", poses = "low" }

[constraints]
gamma_min = { min = "25 deg" }
gap = { min = "20 mm" }
"""


def write(folder: Path, text: str = STUDY, name: str = "study.toml") -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def test_a_two_set_study_equals_one_set_studies(tmp_path: Path) -> None:
    """Each metric of a study with several sets equals the same metric of a study with its set
    alone as the default set: forces dynamic where the set has rates, static where not."""
    study = load_study(write(tmp_path))
    mech = excavkin.load(study.model)
    designs = sample_designs(study.bounds, study.samples, study.method, study.seed)
    whole = evaluate(mech, designs, study.poses, study.metrics, study.constraints, study.loads,
                     study.pose_sets)  # fmt: skip
    for name, poses in study.sets.items():
        own = [replace(m, poses=None) for m in study.metrics if m.poses == name]
        alone = evaluate(mech, designs, poses, own, (), study.loads)
        for m in own:
            assert_allclose(whole[m.name], alone[m.name], rtol=1e-13, atol=1e-15)
    # the held set is static: its torque is that of the poses solved without rates, and not
    # that with the default set's rate
    held = study.pose_sets["held"]
    at_rest = evaluate(mech, designs, held, [Metric("t", "crank.torque", "absmax")], (), "model")
    moving = Poses(held.values, {"crank": 10 * np.pi}, {})
    spun = evaluate(mech, designs, moving, [Metric("t", "crank.torque", "absmax")], (), "model")
    assert_allclose(whole["torque_held"], at_rest["t"], rtol=1e-13)
    assert np.abs(whole["torque_held"] - spun["t"]).max() > 1e-3
    # feasibility over every set
    ok = (whole["gamma_min"] >= np.radians(25)) & (whole["gap"] >= 0.02)
    assert (whole["feasible"] == (ok & (whole["poses_failed"] == 0))).all()
    assert 0 < whole["feasible"].sum() < len(whole)


def test_a_clearance_is_the_least_over_the_poses_of_shapelys_distance(tmp_path: Path) -> None:
    study = load_study(write(tmp_path))
    mech = excavkin.load(study.model)
    designs = sample_designs(study.bounds, 6, "sobol", 9)
    table = evaluate(mech, designs, study.poses, study.metrics, (), study.loads, study.pose_sets)
    crank = study.pose_sets["high"].values["crank"]
    for i in range(6):
        params = {k: float(v[i]) for k, v in designs.items()}
        res = mech.solve({"crank": crank}, params=params)

        xy = {
            p: np.stack([res.column(f"{p}.x"), res.column(f"{p}.y")], -1)
            for p in ["O2", "A", "O4", "B"]
        }
        gaps = [
            shapely.LineString([xy["O2"][k], xy["A"][k]]).distance(
                shapely.LineString([xy["O4"][k], xy["B"][k]])
            )
            for k in range(crank.size)
        ]
        assert_allclose(table["gap"][i], min(gaps), rtol=1e-12)


def test_a_resumed_study_with_sets_equals_an_uninterrupted_one(tmp_path: Path) -> None:
    study = load_study(write(tmp_path))
    whole = run_study(study, tmp_path / "whole.parquet", chunk_samples=300)
    assert len(chunks(study, 300)) > 4  # 46 poses a design over every set
    target = tmp_path / "resumed.parquet"
    seen: list[int] = []

    def stop(done: int, total: int) -> None:
        seen.append(done)
        if len(seen) == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_study(study, target, chunk_samples=300, progress=stop)
    counts: list[int] = []
    run_study(study, target, chunk_samples=300, progress=lambda d, t: counts.append(d))
    assert counts[0] == seen[-1] > 0
    assert pd.read_parquet(whole).equals(pd.read_parquet(target))
    described = whole.metadata()["pose_sets"]
    assert described["sets"] == {"": 25, "low": 7, "high": 9, "held": 5}
    assert described["metrics"]["gap"] == "high" and described["metrics"]["gamma_min"] == ""
    assert "set 'held': static forces" in whole.metadata()["motion"]
    # another set's poses are another study: its parts are not resumed into it
    other = load_study(write(tmp_path, STUDY.replace("150 deg:210 deg:9", "150 deg:200 deg:9")))
    assert other.fingerprint() != study.fingerprint()
    moved = load_study(write(tmp_path, STUDY.replace('poses = "high" }\ntorque_held',
                                                     'poses = "low" }\ntorque_held')))  # fmt: skip
    assert moved.fingerprint() != study.fingerprint()


def test_a_study_without_sets_keeps_its_fingerprint(tmp_path: Path) -> None:
    """Parts written before pose sets existed still resume: the fingerprint of a study
    without sets or clearances hashes what it hashed then."""
    import hashlib
    import json

    plain = STUDY.split("[pose_sets.low]")[0] + (
        '[metrics]\ngamma_min = { column = "B.transmission", reduce = "min" }\n'
    )
    study = load_study(write(tmp_path, plain))
    text = json.dumps(
        {
            "model": study.model.read_text(encoding="utf-8"),
            "bounds": study.bounds,
            "poses": [
                {k: np.asarray(v).tolist() for k, v in part.items()}
                for part in (study.poses.values, study.poses.rates, study.poses.accels)
            ],
            "metrics": [(m.name, m.column, m.reduce, m.target) for m in study.metrics],
            "constraints": [(c.metric, c.low, c.high) for c in study.constraints],
            "sampling": (study.method, study.samples, study.seed),
            "loads": study.loads,
        },
        sort_keys=True,
    )
    assert study.fingerprint() == hashlib.sha256(text.encode()).hexdigest()[:16]


@pytest.mark.parametrize("loads", ["model", None])
def test_the_clearance_gradient_of_the_optimiser_equals_differences(
    tmp_path: Path, loads: str | None
) -> None:
    """With loads every column is differentiated; without, only the metrics' columns and the
    clearances' points."""
    study = load_study(write(tmp_path))
    mech = excavkin.load(study.model)
    kinematic = [m for m in study.metrics if m.clearance or m.column != "crank.torque"]
    metrics = study.metrics if loads else kinematic
    by = {m.name: m for m in metrics}
    problem = _MechanismProblem(
        mech, study.bounds, study.poses, by["gamma_min"], "max",
        [m for m in metrics if m.name != "gamma_min"], study.constraints, loads,
        study.pose_sets,
    )  # fmt: skip
    u = np.array([0.37, 0.61])
    names = ["gap", "gap_last", "rocker_low", "gamma_min"] + (["torque_high"] if loads else [])
    for name in names:
        m = by[name]
        value, grad = problem.column(m, u)
        h = 1e-6
        fd = np.stack(
            [
                (problem.column(m, u + h * e)[0] - problem.column(m, u - h * e)[0]) / (2 * h)
                for e in np.eye(2)
            ],
            axis=-1,
        )
        assert_allclose(grad, fd, rtol=1e-5, atol=1e-7 * max(1.0, np.abs(value).max()))


def test_slsqp_meets_a_clearance_over_a_set(tmp_path: Path) -> None:
    """The least transmission angle over the turn, with a clearance over another set held:
    SLSQP's optimum meets it (active), no design of a grid of the box does better, and the
    table's metrics at the optimum equal the optimum's."""
    text = STUDY.replace('gap = { min = "20 mm" }', 'gap = { min = "80 mm" }') + (
        '\n[optimize]\nobjective = "gamma_min"\nsense = "max"\n'
    )
    study = load_study(write(tmp_path, text))
    best = optimize_study(study)
    assert best.feasible and best.active == ("gap",)
    assert_allclose(best.metrics["gap"], 0.08, rtol=1e-8)
    mech = excavkin.load(study.model)
    row = evaluate(mech, {k: np.array([v]) for k, v in best.params.items()}, study.poses,
                   study.metrics, study.constraints, study.loads, study.pose_sets)  # fmt: skip
    for k, v in best.metrics.items():
        assert_allclose(row[k][0], v, rtol=1e-12)
    grid = np.meshgrid(*(np.linspace(lo, hi, 41) for lo, hi in study.bounds.values()))
    designs = dict(zip(study.bounds, (g.ravel() for g in grid), strict=True))
    table = evaluate(mech, designs, study.poses, study.metrics, study.constraints, study.loads,
                     study.pose_sets)  # fmt: skip
    feasible = table[table["feasible"]]
    assert len(feasible) > 10 and feasible["gamma_min"].max() <= best.value + 1e-12
    assert feasible["gamma_min"].max() > best.value - np.radians(0.5)
    free = optimize_study(
        load_study(write(tmp_path, text.replace('gap = { min = "80 mm" }\n', "")))
    )
    assert free.metrics["gap"] < 0.08 and free.value > best.value + np.radians(1)


def test_the_built_in_study_meets_both_sets_and_its_written_model_reproduces_it(
    tmp_path: Path,
) -> None:
    """The built-in two-set study of the excavator's bucket linkage: its optimum is feasible
    in both sets with the teeth 50 mm from the boom, where the nominal linkage crosses it;
    the model file written back reproduces every metric to 1e-9."""
    name = "bucket_linkage_clearance"
    study = load_study(excavkin.example_path(name))
    assert set(study.sets) == {"curl", "crowd"}
    mech = excavkin.load(study.model)
    at = {k: np.array([mech.parameters[k]]) for k in study.bounds}
    nominal = evaluate(mech, at, study.poses, study.metrics, study.constraints, None,
                       study.pose_sets)  # fmt: skip
    assert nominal["teeth_to_boom"][0] < -0.05 and not nominal["feasible"][0]
    # the nominal column of the table in docs/studies.md
    shown = [np.degrees(nominal[k][0]) for k in ("link", "turn", "open")]
    assert_allclose(shown, [30.53, -187.52, 55.47], atol=0.005)
    assert_allclose(nominal["teeth_to_boom"][0], -0.1135, atol=5e-5)
    best = optimize_study(name)
    assert best.feasible and best.active == ("teeth_to_boom",)
    # the study's own sampling (docs/studies.md): 16 of 1 024 designs meet both sets, none
    # beats the optimum
    designs = sample_designs(study.bounds, study.samples, study.method, study.seed)
    table = evaluate(mech, designs, study.poses, study.metrics, study.constraints, None,
                     study.pose_sets)  # fmt: skip
    sampled = table.loc[table["feasible"], "link"]
    assert len(sampled) == 16 and sampled.max() < best.value
    assert_allclose(np.degrees(sampled.max()), 48.61, atol=0.005)
    assert_allclose(best.metrics["teeth_to_boom"], 0.05, rtol=1e-7)
    assert best.metrics["link"] > nominal["link"][0] + np.radians(15)
    out = best.write_model(tmp_path / "best.toml")
    written = excavkin.load(out)
    for k, v in best.params.items():
        assert_allclose(written.parameters[k], v, rtol=1e-15)
    # the written file solved at its own values: the same metrics
    own = replace(study, model=out)
    row = evaluate(written, {k: np.array([written.parameters[k]]) for k in study.bounds},
                   own.poses, own.metrics, own.constraints, own.loads, own.pose_sets)  # fmt: skip
    assert row["feasible"][0]
    for k, v in best.metrics.items():
        assert_allclose(row[k][0], v, rtol=1e-9)
    # the same with no parameters given at all: the file is the design
    plain = evaluate(written, {"N.x": np.array([written.parameters["N.x"]])}, own.poses,
                     own.metrics, (), None, own.pose_sets)  # fmt: skip
    for k, v in best.metrics.items():
        assert_allclose(plain[k][0], v, rtol=1e-9)
    # and the nominal's other dimensions are kept
    for k, v in mech.parameters.items():
        if k not in study.bounds:
            assert written.parameters[k] == v


def test_the_command_writes_the_model_and_never_over_a_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    text = STUDY + '\n[optimize]\nobjective = "gamma_min"\nsense = "max"\n'
    spec = write(tmp_path, text.replace('model = "fourbar"', 'model = "four.toml"'))
    model = tmp_path / "four.toml"
    model.write_text(excavkin.example_path("fourbar").read_text(), encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "best.toml"
    out.write_text("mine", encoding="utf-8")
    result = CliRunner().invoke(main, ["optimize", str(spec), "-q", "--write-model", str(out)])
    assert result.exit_code == 2 and "exists" in result.output and out.read_text() == "mine"
    result = CliRunner().invoke(main, ["optimize", str(spec), "-q", "--write-model", str(model),
                                       "--force"])  # fmt: skip
    assert result.exit_code == 2 and "model file" in result.output
    assert model.read_text() == excavkin.example_path("fourbar").read_text()
    result = CliRunner().invoke(main, ["optimize", str(spec), "-q", "--write-model", "x.csv"])
    assert result.exit_code == 2 and ".toml" in result.output
    result = CliRunner().invoke(
        main, ["optimize", str(spec), "-q", "--write-model", str(out), "--force"]
    )
    assert result.exit_code == 0, result.output
    assert f"wrote the optimal design as a model to {out}" in result.output
    written = excavkin.load(out)
    best = optimize_study(load_study(spec))
    for k, v in best.params.items():
        assert_allclose(written.parameters[k], v, rtol=1e-15)


def test_a_clearance_metric_in_python() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    crank = Poses({"crank": np.radians(np.arange(0.0, 360.0, 10.0))}, {}, {})
    gap = clearance_metric("gap", ("O2", "A"), ("O4", "B"))
    table = evaluate(mech, {"A-B": np.array([0.12])}, crank, [gap])
    res = mech.solve({"crank": crank.values["crank"]})
    ends = [
        np.stack([res.column(f"{p}.x"), res.column(f"{p}.y")], -1) for p in ("O2", "A", "O4", "B")
    ]
    from excavkin.studies.clearance import segment_clearance

    assert table["gap"][0] == segment_clearance(*ends).min()
