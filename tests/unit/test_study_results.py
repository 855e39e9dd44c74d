"""A study's and an optimisation's results as a user meets them: the table a study writes is a
result object (path-like, a frame with units, a summary, HTML, a plot); an optimum shows itself
in the study file's own units; a model study optimises in one call, as a machine study does."""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib
import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

import excavkin
from excavkin.cli import main
from excavkin.errors import InputError
from excavkin.studies.optimize import Optimum, optimize, optimize_study
from excavkin.studies.study import StudyResult, run_study
from excavkin.studies.study_file import load_optimization, load_study

matplotlib.use("Agg")

STUDY = """
[study]
model = "fourbar"
samples = 32
seed = 3
loads = "model"

[units]
length = "mm"

[parameters]
"A-B" = [110, 130]
"O4.x" = ["0.09 m", "0.11 m"]

[poses]
crank = "0 deg:360 deg:37"
[poses.rates]
crank = "10 rad/s"

[metrics]
gamma_min = { column = "B.transmission", reduce = "min" }
torque_peak = { column = "crank.torque", reduce = "absmax" }
omega_max = { column = "rocker.omega", reduce = "max" }

[constraints]
gamma_min = { min = "0.5 rad" }

[optimize]
objective = "gamma_min"
sense = "max"
"""


@pytest.fixture
def study_path(tmp_path: Path) -> Path:
    path = tmp_path / "study.toml"
    path.write_text(STUDY, encoding="utf-8")
    return path


def test_a_study_file_keeps_the_units_it_writes_in(study_path: Path) -> None:
    study = load_study(study_path)
    assert study.units == {
        "design.A-B": "mm",  # a bare number: the [units] table's
        "design.O4.x": "m",  # written with its unit
        "gamma_min": "rad",  # its constraint's unit
        "torque_peak": "N*m",  # none given: SI
        "omega_max": "rad/s",
    }
    assert study.optimize["objective"] == "gamma_min"


@pytest.fixture
def result(study_path: Path, tmp_path: Path) -> StudyResult:
    return run_study(load_study(study_path), tmp_path / "out.parquet")


def test_run_study_returns_a_path_like_result(result: StudyResult, tmp_path: Path) -> None:
    assert isinstance(result, StudyResult)
    assert os.fspath(result) == str(tmp_path / "out.parquet") == str(result.path)
    assert_allclose(pd.read_parquet(result)["gamma_min"], result.to_frame()["gamma_min"], rtol=0)


def test_the_frame_has_its_units_and_kinds_in_attrs(result: StudyResult) -> None:
    frame = result.to_frame()
    assert frame.attrs["excavkin.model"] == excavkin.load(excavkin.example_path("fourbar")).name
    kinds = frame.attrs["excavkin.kinds"]
    assert kinds["design.A-B"] == "length" and kinds["gamma_min"] == "angle"
    assert kinds["torque_peak"] == "torque"
    units = frame.attrs["excavkin.units"]
    assert (units["design.A-B"], units["gamma_min"], units["torque_peak"]) == ("m", "rad", "N*m")
    # SI values: the box is 110–130 mm
    assert frame["design.A-B"].min() >= 0.11 and frame["design.A-B"].max() <= 0.13


def test_the_summary_gives_each_metrics_range_in_the_studys_units(result: StudyResult) -> None:
    frame = result.to_frame()
    ok = frame["feasible"].to_numpy()
    text = result.summary()
    assert f"32 designs, {int(ok.sum())} feasible" in text
    line = next(s for s in text.splitlines() if s.strip().startswith("torque_peak"))
    v = frame["torque_peak"].to_numpy()[ok]
    lo, hi = frame["design"].to_numpy()[ok][[np.argmin(v), np.argmax(v)]]
    assert f"{v.min():.6g} … {v.max():.6g} N*m" in line
    assert f"least: design {lo}, greatest: design {hi}" in line
    assert "<table>" in result._repr_html_() and "32 designs" in result._repr_html_()


def test_the_plot_is_a_metric_against_a_variable_in_the_studys_units(result: StudyResult) -> None:
    frame = result.to_frame()
    ok = frame["feasible"].to_numpy()
    plot = result.plot("torque_peak", "A-B")
    assert plot.fig is plot.ax.get_figure(root=True)
    xy = plot.feasible.get_offsets()
    assert_allclose(xy[:, 0], 1000.0 * frame["design.A-B"].to_numpy()[ok], rtol=1e-12)
    assert_allclose(xy[:, 1], frame["torque_peak"].to_numpy()[ok], rtol=1e-12)
    assert len(plot.infeasible.get_offsets()) == (~ok).sum()
    assert plot.ax.get_xlabel() == "A-B [mm]"
    with pytest.raises(InputError, match="metric"):
        result.plot("nope")
    with pytest.raises(InputError, match="design parameter"):
        result.plot("torque_peak", "nope")


@pytest.fixture
def best(study_path: Path) -> Optimum:
    return optimize_study(study_path)


def test_optimize_study_is_optimize_on_the_studys_settings(study_path: Path, best: Optimum) -> None:
    study, settings = load_optimization(study_path)
    by_name = {m.name: m for m in study.metrics}
    direct = optimize(
        excavkin.load(study.model), study.bounds, study.poses, by_name["gamma_min"], "max",
        metrics=[by_name["torque_peak"], by_name["omega_max"]], constraints=study.constraints,
        loads=study.loads,
    )  # fmt: skip
    assert best.params == direct.params and best.value == direct.value
    assert (best.objective, best.sense, best.method) == ("gamma_min", "max", "slsqp")
    # a loaded study, and arguments that override its table
    assert optimize_study(study).params == best.params
    low = optimize_study(study, "omega_max", "min", maxiter=50)
    assert low.objective == "omega_max" and low.sense == "min"


def test_optimize_study_refuses_a_study_without_an_objective(study_path: Path) -> None:
    text = STUDY.split("[optimize]")[0]
    study_path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError, match="objective"):
        optimize_study(study_path)
    with pytest.raises(InputError, match="nope"):
        optimize_study(study_path, "nope")


def test_the_optimum_shows_itself_in_the_studys_units(best: Optimum) -> None:
    text = best.summary()
    assert text.startswith("maximum of gamma_min (slsqp, ")
    lines = {s.split()[0]: s.split()[1:] for s in text.splitlines()[1:]}
    assert lines["A-B"] == [f"{1000 * best.params['A-B']:.10g}", "mm"]
    assert lines["O4.x"] == [f"{best.params['O4.x']:.10g}", "m"]
    assert lines["gamma_min"] == [f"{best.metrics['gamma_min']:.10g}", "rad"]
    assert f"A-B = {1000 * best.params['A-B']:.6g} mm" in repr(best)
    html = best._repr_html_()
    assert "<table>" in html and "maximum of gamma_min" in html and "mm" in html


def test_the_optimums_frame_in_the_studys_units_and_in_si(best: Optimum, tmp_path: Path) -> None:
    shown = best.to_frame()
    assert_allclose(shown["design.A-B"], 1000 * best.params["A-B"], rtol=1e-15)
    assert shown.attrs["excavkin.units"]["design.A-B"] == "mm"
    assert "excavkin.kinds" not in shown.attrs  # not SI: not a result's table
    si = best.to_frame("si")
    assert si["design.A-B"][0] == best.params["A-B"] and bool(si["feasible"][0]) is best.feasible
    assert si.attrs["excavkin.units"]["design.A-B"] == "m"
    assert si.attrs["excavkin.kinds"]["gamma_min"] == "angle"
    with pytest.raises(InputError, match="units"):
        best.to_frame("mm")  # type: ignore[arg-type]


def test_the_optimums_plot_is_its_convergence_or_its_place_in_the_box(best: Optimum) -> None:
    from dataclasses import replace

    ax = best.plot()
    assert best.history
    assert_allclose(ax.lines[0].get_ydata(), best.history, rtol=1e-15)  # rad: the study's unit
    ax = replace(best, history=()).plot()
    place = ax.lines[0].get_xdata()
    lo, hi = best.bounds["A-B"]
    assert_allclose(place[0], (best.params["A-B"] - lo) / (hi - lo), rtol=1e-12)


def test_the_cli_prints_the_optimum_in_the_studys_units(study_path: Path, best: Optimum) -> None:
    out = CliRunner().invoke(main, ["optimize", str(study_path)])
    assert out.exit_code == 0, out.output
    assert f"A-B                      {1000 * best.params['A-B']:.10g} mm" in out.output


def test_the_optimizers_progress_reports_each_iteration(study_path: Path) -> None:
    calls: list[tuple[int, int]] = []
    best = optimize_study(study_path, progress=lambda done, most: calls.append((done, most)))
    assert calls == [(k + 1, 200) for k in range(len(calls))]
    assert len(calls) >= len(best.history) > 0


def test_a_study_without_a_feasible_design_says_so_and_gives_every_designs_range(
    study_path: Path, tmp_path: Path
) -> None:
    text = STUDY.replace('gamma_min = { min = "0.5 rad" }', 'gamma_min = { min = "3 rad" }')
    study_path.write_text(text, encoding="utf-8")
    result = run_study(load_study(study_path), tmp_path / "none.parquet")
    frame = result.to_frame()
    assert not frame["feasible"].any()
    summary = result.summary()
    assert "0 feasible" in summary and "no design is feasible" in summary
    v = frame["omega_max"].to_numpy()
    assert f"{np.nanmin(v):.6g} … {np.nanmax(v):.6g} rad/s" in summary
