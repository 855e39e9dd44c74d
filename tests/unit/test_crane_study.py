"""Studies of a crane's design: its parameters, each design a crane of its own, the metrics
against the load chart and working range computed directly, and the optimum written back."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

import excavkin
from excavkin.cli import main
from excavkin.crane.chart import load_chart
from excavkin.crane.machine_file import load_machine
from excavkin.crane.reach import reach
from excavkin.crane.study import (
    CHART_STEP,
    COLUMNS,
    crane_columns,
    crane_figures,
    crane_parameters,
    design_crane,
    load_crane_study,
)
from excavkin.errors import InputError

STUDY = "telescopic_crane_counterweight"


@pytest.fixture(scope="module")
def crane():
    return load_machine("telescopic_crane_machine")


def test_the_parameters_are_the_model_the_cylinders_the_hoist_and_the_masses(crane) -> None:
    p = crane_parameters(crane)
    assert p["turning.counterweight.mass"] == 4500.0
    assert p["fixed.carrier.mass"] == 16000.0
    assert p["hoist.line_pull"] == 40e3
    assert p["cylinders.telescope.stroke"] == pytest.approx(6.5, rel=1e-15)
    assert p["circuits.crane.relief"] == pytest.approx(31e6, rel=1e-15)
    assert p["T.x"] == pytest.approx(14.7, rel=1e-15) and "fly.mass" in p
    with pytest.raises(InputError, match="parameter"):
        design_crane(crane, {"turning.ballast.mass": 1.0})


def test_a_design_is_the_crane_with_its_values(crane) -> None:
    d = design_crane(crane, {"turning.counterweight.mass": 6000.0, "hoist.line_pull": 50e3})
    assert d.mass == pytest.approx(crane.mass + 1500.0, rel=1e-15)
    assert d.hoist.line_pull == 50e3 and crane.hoist.line_pull == 40e3
    r = np.array([12.0])
    s = np.array([crane.second.extended])
    heavier, nominal = load_chart(d, r, s), load_chart(crane, r, s)
    assert np.all(heavier.limits[3] > nominal.limits[3])  # more counterweight, more stable
    assert np.array_equal(heavier.limits[0], nominal.limits[0])  # the cylinders as they were


def test_a_design_keeps_the_stability_criterion_of_its_crane(crane) -> None:
    from excavkin.crane.machine import StabilityFactors

    params = {"turning.counterweight.mass": 6000.0}
    d = design_crane(crane.with_stability(StabilityFactors(1.3, 0.2)), params)
    plain = design_crane(crane, params)
    assert d.stability == StabilityFactors(1.3, 0.2) and plain.stability is None
    r, s = np.array([12.0]), np.array([crane.second.extended])
    chart = load_chart(d, r, s)
    assert chart.factors == d.stability
    assert np.all(chart.limits[3] < load_chart(plain, r, s).limits[3])
    f = crane_figures(d, ["load_moment"])["load_moment"]
    assert f < crane_figures(plain, ["load_moment"])["load_moment"]


def test_the_figures_against_the_chart_and_the_range_directly(crane) -> None:
    f = crane_figures(crane, list(COLUMNS))
    rg = reach(crane, 41)
    assert f["reach"] == rg.tip[..., 0].max() and f["height"] == rg.tip[..., 1].max()
    radius = np.arange(np.ceil(rg.tip[..., 0].min() / CHART_STEP) * CHART_STEP,
                       rg.tip[..., 0].max() + 1e-9, CHART_STEP)  # fmt: skip
    chart = load_chart(crane, radius)
    cells = [
        (chart.capacity[i, j].min(), chart.radius[i])
        for i in range(radius.size)
        for j in range(chart.second.size)
        if np.isfinite(chart.capacity[i, j]).all()
    ]
    assert f["capacity.max"] == max(c for c, _ in cells)
    assert f["load_moment"] == pytest.approx(
        max(crane.gravity * c * r for c, r in cells), rel=1e-15
    )
    assert f["mass"] == crane.mass


def test_each_distinct_design_is_rated_once_and_a_broken_one_is_not_ok(crane) -> None:
    params = {"turning.counterweight.mass": np.array([4000.0, 5000.0, 4000.0]),
              "cylinders.luff.stroke": np.array([1.76, 1.76, 9.0])}  # fmt: skip
    cols, ok = crane_columns(crane, params, ["mass", "load_moment"], 3)
    assert list(ok) == [True, True, False]  # a 9 m stroke does not assemble the boom
    assert cols["mass"][0] == crane.mass - 500.0 and np.isnan(cols["mass"][2])


def test_an_unknown_column_is_an_error_and_no_parameters_the_nominal_crane(crane) -> None:
    """A column that is not one is refused before any design is rated (it was a column of NaN,
    the error swallowed as a design that cannot be rated); no parameters rate the nominal
    crane n times (it raised ValueError)."""
    params = {"turning.counterweight.mass": np.array([4000.0, 5000.0])}
    with pytest.raises(InputError, match="nonsense"):
        crane_columns(crane, params, ["mass", "nonsense"], 2)
    cols, ok = crane_columns(crane, {}, ["mass"], 3)
    assert ok.all() and (cols["mass"] == crane.mass).all()


def test_the_study_runs_and_its_optimum_reloads_with_its_figures(tmp_path) -> None:
    study = load_crane_study(excavkin.example_path(STUDY))
    assert study.family.name == "crane"
    out = tmp_path / "s.parquet"
    run = CliRunner().invoke
    r = run(main, ["crane", "study", STUDY, "-o", str(out), "-q"])
    assert r.exit_code == 0, r.output
    table = pd.read_parquet(out)
    assert len(table) == 8 and table["feasible"].sum() >= 5
    crane = load_machine("telescopic_crane_machine")
    for _, row in table.head(2).iterrows():
        names = ("turning.counterweight.mass", "cylinders.luff.bore")
        one = design_crane(crane, {n: row[f"design.{n}"] for n in names})
        f = crane_figures(one, ["load_moment", "mass"])
        assert row["moment"] == pytest.approx(f["load_moment"], rel=1e-12)
        assert row["mass"] == pytest.approx(f["mass"], rel=1e-12)
    best = tmp_path / "best.toml"
    r = run(main, ["crane", "optimize", STUDY, "--write-machine", str(best)])
    assert r.exit_code == 0, r.output
    assert "feasible" in r.output and best.exists()
    written = load_machine(best)
    f = crane_figures(written, ["load_moment", "mass"])
    assert f["mass"] <= 30e3 * (1 + 1e-9)
    shown = float(r.output.split("N*m")[0].split(":")[-1])
    assert f["load_moment"] == pytest.approx(shown, rel=1e-9)
    assert f["load_moment"] > crane_figures(crane, ["load_moment"])["load_moment"]
