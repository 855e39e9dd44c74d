"""Design studies: the metrics of each design equal that design solved alone at every pose;
a resumed study equals an uninterrupted one; a Dask run equals a local one to the bit; the
study file's errors name the file, table and entry."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

import excavkin
from excavkin.cli import main
from excavkin.errors import ExcavkinError, InputError
from excavkin.studies.design_space import sample_designs
from excavkin.studies.metrics import Constraint, Metric, Poses, evaluate
from excavkin.studies.study import Study, chunks, run_study
from excavkin.studies.study_file import load_study
from tests.property.test_designs import as_own_model

STUDY = """
[study]
model = "fourbar"
method = "sobol"
samples = 64
seed = 3
loads = "model"

[units]
length = "mm"

[parameters]
"A-B" = [110, 130]
"O4.x" = [90, 110]

[poses]
crank = "0 deg:360 deg:37"
[poses.rates]
crank = "10 rad/s"

[metrics]
gamma_min = { column = "B.transmission", reduce = "min" }
torque_peak = { column = "crank.torque", reduce = "absmax" }
worst = { column = "B.transmission", reduce = "argmin" }
omega_max = { column = "rocker.omega", reduce = "max" }

[constraints]
gamma_min = { min = "25 deg" }
"""


def write_study(folder: Path, text: str = STUDY) -> Path:
    path = folder / "study.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_each_designs_metrics_equal_that_design_solved_alone() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    designs = sample_designs({"A-B": (0.11, 0.13), "O4.x": (0.09, 0.11)}, 16, "halton", 5)
    crank = np.linspace(0.0, 2 * np.pi, 25)
    poses = Poses({"crank": crank}, {"crank": 10.0}, {})
    metrics = [
        Metric("g", "B.transmission", "min"),
        Metric("t", "crank.torque", "absmax"),
        Metric("w", "rocker.omega", "argmax"),
        Metric("m", "B.y", "mean"),
    ]
    table = evaluate(mech, designs, poses, metrics, [Constraint("g", low=0.4)], loads="model")
    for i in range(16):
        own = excavkin.Mechanism(
            as_own_model(mech.model, {k: float(v[i]) for k, v in designs.items()})
        )
        res = own.solve({"crank": crank}, {"crank": 10.0}, loads="model")
        g = res.kinematics.column("B.transmission")
        assert table["g"][i] == pytest.approx(g.min(), rel=1e-12)
        assert table["t"][i] == pytest.approx(np.abs(res.column("crank.torque")).max(), rel=1e-12)
        assert table["w"][i] == np.argmax(res.kinematics.column("rocker.omega"))
        assert table["m"][i] == pytest.approx(res.kinematics.column("B.y").mean(), rel=1e-12)
        assert table["feasible"][i] == (g.min() >= 0.4)
    assert 0 < table["feasible"].sum() < 16  # the constraint binds on some designs only


def test_failed_poses_make_a_design_infeasible_and_metrics_skip_them() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    # a coupler too short for a full turn: some crank angles do not close
    designs = {"A-B": np.array([0.12, 0.02])}
    poses = Poses({"crank": np.linspace(0.0, 2 * np.pi, 13)}, {}, {})
    table = evaluate(mech, designs, poses, [Metric("g", "B.transmission", "min")])
    assert table["poses_failed"].tolist()[0] == 0 and table["poses_failed"][1] > 0
    assert table["feasible"].tolist() == [True, False]
    assert "poses do not solve" in table["status"][1]
    assert np.isfinite(table["g"]).all()


def test_sampling_methods_are_seeded_and_parts_equal_the_whole() -> None:
    bounds = {"a": (0.0, 1.0), "b": (2.0, 3.0), "c": (-1.0, 1.0)}
    for method, n in (("sobol", 64), ("halton", 50), ("lhs", 40), ("grid", 4)):
        whole = sample_designs(bounds, n, method, 11)
        again = sample_designs(bounds, n, method, 11)
        total = len(whole["a"])
        part = sample_designs(bounds, n, method, 11, (7, total - 3))
        for k, (lo, hi) in bounds.items():
            np.testing.assert_array_equal(whole[k], again[k])
            np.testing.assert_array_equal(whole[k][7 : total - 3], part[k])
            assert lo <= whole[k].min() and whole[k].max() <= hi
    grid = sample_designs({"a": (0.0, 1.0), "b": (2.0, 3.0)}, 3, "grid")
    pairs = set(zip(grid["a"].tolist(), grid["b"].tolist(), strict=True))
    assert pairs == {(a, b) for a in (0.0, 0.5, 1.0) for b in (2.0, 2.5, 3.0)}
    lhs = sample_designs({"a": (0.0, 1.0)}, 40, "lhs", 2)["a"]
    assert sorted(np.floor(lhs * 40).astype(int).tolist()) == list(range(40))  # one per stratum
    with pytest.raises(InputError, match="low < high"):
        sample_designs({"a": (1.0, 1.0)}, 4)


def test_a_resumed_study_equals_an_uninterrupted_one(tmp_path: Path) -> None:
    study = load_study(write_study(tmp_path))
    whole = run_study(study, tmp_path / "whole.parquet", chunk_samples=500)
    assert len(chunks(study, 500)) > 4
    target = tmp_path / "resumed.parquet"
    seen: list[int] = []

    def stop_after_three(done: int, total: int) -> None:
        seen.append(done)
        if len(seen) == 4:  # the first call reports what was done before
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_study(study, target, chunk_samples=500, progress=stop_after_three)
    assert not target.exists()  # never half-written
    parts = tmp_path / ".resumed.parquet.parts"
    assert len(list(parts.glob("part-*.parquet"))) == 3
    counts: list[int] = []
    run_study(study, target, chunk_samples=500, progress=lambda d, t: counts.append(d))
    assert counts[0] == seen[-1]  # finished designs were skipped
    assert not parts.exists()
    a, b = pd.read_parquet(whole), pd.read_parquet(target)
    assert a.equals(b) and len(a) == 64


def test_parts_of_another_study_are_not_mixed_in(tmp_path: Path) -> None:
    study = load_study(write_study(tmp_path))
    target = tmp_path / "out.parquet"
    parts = tmp_path / ".out.parquet.parts"
    with pytest.raises(KeyboardInterrupt):
        run_study(study, target, chunk_samples=500, progress=_stop_at(3))
    other = load_study(write_study(tmp_path, STUDY.replace("seed = 3", "seed = 4")))
    run_study(other, target, chunk_samples=500)
    fresh = run_study(other, tmp_path / "fresh.parquet", chunk_samples=500)
    assert pd.read_parquet(target).equals(pd.read_parquet(fresh))
    assert not parts.exists()


def _stop_at(k: int):  # type: ignore[no-untyped-def]
    calls = []

    def progress(done: int, total: int) -> None:
        calls.append(done)
        if len(calls) == k:
            raise KeyboardInterrupt

    return progress


def test_the_table_carries_units_and_kinds(tmp_path: Path) -> None:
    import json

    import pyarrow.parquet as pq

    study = load_study(write_study(tmp_path))
    out = run_study(study, tmp_path / "t.parquet")
    meta = pq.read_schema(out).metadata
    units = json.loads(meta[b"excavkin.units"])
    assert units["design.A-B"] == "m" and units["gamma_min"] == "rad"
    assert units["torque_peak"] == "N*m" and units["worst"] == ""
    table = pd.read_parquet(out)
    assert list(table["design"]) == list(range(64))
    assert set(table.columns) >= {"design.A-B", "design.O4.x", "feasible", "status"}


def test_dask_equals_local_to_the_bit(tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    study = load_study(write_study(tmp_path))
    # 3-design chunks: 22 tasks, more than the window in flight, so the window refills
    local = run_study(study, tmp_path / "local.parquet", chunk_samples=3 * 37)
    dask = run_study(study, tmp_path / "dask.parquet", chunk_samples=3 * 37, scheduler="dask")
    assert pd.read_parquet(local).equals(pd.read_parquet(dask))


def test_the_command_writes_the_table_and_refuses_to_overwrite(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    spec = write_study(tmp_path)
    monkeypatch.chdir(tmp_path)  # the table goes to the current folder
    runner = CliRunner()
    first = runner.invoke(main, ["study", str(spec), "-q"])
    assert first.exit_code == 0, first.output
    assert "64 designs" in first.output and (tmp_path / "study.parquet").exists()
    again = runner.invoke(main, ["study", str(spec), "-q"])
    assert again.exit_code != 0 and "exists" in again.output


def test_the_built_in_study_runs_by_name(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    assert "crank_rocker" in excavkin.examples("study")
    assert "crank_rocker" not in excavkin.examples("model")
    study = load_study(excavkin.example_path("crank_rocker"))
    assert study.designs == 4096 and study.poses.count == 181
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, ["study", "crank_rock", "-q"])
    assert result.exit_code != 0 and "crank_rocker" in result.output  # did you mean


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (('"A-B" = [110, 130]', '"A-X" = [110, 130]'), "parameters.*A-X.*no parameter"),
        (('"A-B" = [110, 130]', '"A-B" = [130, 110]'), "parameters.*A-B.*low < high"),
        (('"A-B" = [110, 130]', '"A-B" = ["110 s", 130]'), "parameters.*A-B"),
        (('crank = "0 deg:360 deg:37"', 'crank = "0 deg:360 deg:x"'), "poses.*crank.*whole"),
        (('crank = "0 deg:360 deg:37"', 'bucket = "0 deg"'), "poses.*bucket.*no driver"),
        (('reduce = "min" }', 'reduce = "least" }'), "metrics.*gamma_min.*reduce"),
        (
            ('column = "B.transmission", reduce = "min"', 'column = "B.trans", reduce = "min"'),
            "metrics.*B.trans",
        ),
        (("gamma_min = { min", "gamma_max = { min"), "constraints.*gamma_max.*no metric"),
        (('{ min = "25 deg" }', '{ min = "25 mm" }'), "constraints.*gamma_min"),
        (
            ('{ min = "25 deg" }', '{ min = "25 deg", equal = "30 deg" }'),
            "constraints.*gamma_min.*equal",
        ),
        (
            ('reduce = "min" }', 'reduce = "min", target = "90 deg" }'),
            "metrics.*gamma_min.*target",
        ),
        (('method = "sobol"', 'method = "random"'), "study.*method"),
        (("samples = 64", "samples = -1"), "study.*samples"),
        (('model = "fourbar"', 'model = "nowhere"'), "study.*model"),
        (('loads = "model"', 'loads = "all"'), "study.*loads"),
    ],
)
def test_study_file_errors_name_the_entry(
    tmp_path: Path, change: tuple[str, str], message: str
) -> None:
    old, new = change
    assert old in STUDY
    spec = write_study(tmp_path, STUDY.replace(old, new))
    with pytest.raises(ExcavkinError, match=message):
        load_study(spec)
    result = CliRunner().invoke(main, ["study", str(spec), "-q"])
    assert result.exit_code != 0 and "Traceback" not in result.output
    assert str(spec) in result.output


def test_a_force_metric_needs_the_loads(tmp_path: Path) -> None:
    spec = write_study(tmp_path, STUDY.replace('loads = "model"\n', ""))
    study = load_study(spec)
    assert isinstance(study, Study) and study.loads is None
    with pytest.raises(InputError, match="force column"):
        run_study(study, tmp_path / "x.parquet")


OPTIMIZE = """
[optimize]
objective = "gamma_min"
sense = "max"
"""


def test_the_optimize_command_prints_and_writes_the_optimum(tmp_path: Path) -> None:
    spec = write_study(tmp_path, STUDY + OPTIMIZE)
    table, figure = tmp_path / "best.csv", tmp_path / "conv.png"
    result = CliRunner().invoke(
        main, ["optimize", str(spec), "-o", str(table), "--plot", str(figure)]
    )
    assert result.exit_code == 0, result.output
    assert "maximum of gamma_min" in result.output and "feasible" in result.output
    best = pd.read_csv(table)
    # the optimum is no worse than the best of the study's own 64 designs
    study = load_study(spec)
    designs = pd.read_parquet(run_study(study, tmp_path / "s.parquet"))
    assert best["gamma_min"][0] >= designs["gamma_min"].max() - 1e-12
    assert figure.stat().st_size > 1000


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ('sense = "max"', r"\[optimize\] 'objective'.*no metric"),
        ('objective = "gamma"', r"\[optimize\] 'objective'.*gamma_min"),
        ('objective = "gamma_min"\nsense = "up"', r"\[optimize\] 'sense'"),
        ('objective = "gamma_min"\nmethod = "newton"', r"\[optimize\] 'method'"),
        ('objective = "gamma_min"\nmaxiter = 0', r"\[optimize\] 'maxiter'"),
    ],
)
def test_optimize_table_errors_name_the_entry(tmp_path: Path, body: str, message: str) -> None:
    import re

    spec = write_study(tmp_path, STUDY + "\n[optimize]\n" + body + "\n")
    result = CliRunner().invoke(main, ["optimize", str(spec)])
    assert result.exit_code != 0 and "Traceback" not in result.output
    assert str(spec) in result.output and re.search(message, result.output), result.output


def test_first_and_last_are_the_columns_at_the_end_poses() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    crank = np.linspace(0.3, 2.9, 9)
    designs = {"A-B": np.array([0.115, 0.125]), "O4.x": np.array([0.095, 0.105])}
    metrics = [
        Metric("a", "rocker.angle", "first"),
        Metric("b", "rocker.angle", "last"),
    ]
    table = evaluate(mech, designs, Poses({"crank": crank}, {}, {}), metrics)
    for i in range(2):
        res = mech.solve({"crank": crank[[0, -1]]}, params={k: v[i] for k, v in designs.items()})
        ends = np.asarray(res.column("rocker.angle"))
        assert table["a"][i] == ends[0]
        assert table["b"][i] == ends[1]


def test_slsqp_holds_a_last_pose_constraint_with_exact_gradients() -> None:
    """Maximise the least transmission angle with the rocker's angle at the last pose held at
    a value: the constraint is active at the optimum and met to round-off."""
    from excavkin.studies.optimize import optimize

    mech = excavkin.load(excavkin.example_path("fourbar"))
    poses = Poses({"crank": np.linspace(0.0, 2 * np.pi, 37)}, {}, {})
    bounds = {"A-B": (0.11, 0.13), "O4.x": (0.09, 0.11)}
    last = Metric("last", "rocker.angle", "last")
    free = optimize(mech, bounds, poses, Metric("g", "B.transmission", "min"), "max",
                    metrics=[last])  # fmt: skip
    centre = {k: np.array([(a + b) / 2]) for k, (a, b) in bounds.items()}
    target = float(evaluate(mech, centre, poses, [last])["last"][0])  # a feasible value
    assert abs(target - free.metrics["last"]) > 1e-3  # that the free optimum does not meet
    held = optimize(
        mech, bounds, poses, Metric("g", "B.transmission", "min"), "max",
        metrics=[last], constraints=[Constraint("last", target, target)],
    )  # fmt: skip
    assert held.feasible and "last" in held.active
    assert held.metrics["last"] == pytest.approx(target, abs=1e-9)
    assert held.value <= free.value + 1e-9


def test_a_target_is_part_of_the_fingerprint(tmp_path: Path) -> None:
    """Two studies that differ only in a metric's target are two studies: the parts of one
    are never resumed into the other."""
    text = STUDY.replace(
        'torque_peak = { column = "crank.torque", reduce = "absmax" }',
        'torque_peak = { column = "crank.torque", reduce = "absmax", target = "10 N*m" }',
    )
    assert text != STUDY
    a = load_study(write_study(tmp_path, text)).fingerprint()
    b = load_study(write_study(tmp_path, text.replace("10 N*m", "500 N*m"))).fingerprint()
    assert a != b


def test_an_angles_change_is_followed_along_the_poses() -> None:
    """`change` of an angle column passing ±180°: the turn itself (the crank over 0°→210°
    turns 210°), not the wrapped difference (−150°), in the table and in the optimiser's
    value; a length's change is the plain difference."""
    from excavkin.studies.metrics import Metric, Poses, angle_change, evaluate

    mech = excavkin.load(excavkin.example_path("fourbar"))
    poses = Poses({"crank": np.radians(np.linspace(0, 210, 22))}, {}, {})
    metrics = [Metric("turn", "crank.angle", "change"), Metric("dx", "B.x", "change")]
    table = evaluate(mech, {"A-B": np.array([0.12])}, poses, metrics)
    assert table["turn"][0] == pytest.approx(np.radians(210), abs=1e-12)
    res = mech.solve(poses.values)
    assert table["dx"][0] == res.column("B.x")[-1] - res.column("B.x")[0]
    assert angle_change(np.radians([[170.0, -170.0, -150.0]]))[0] == pytest.approx(
        np.radians(40.0), abs=1e-12
    )
