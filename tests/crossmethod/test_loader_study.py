"""Studies of a loader's parameters: each design's metrics against the loader's own analyses of
that design written out by hand as machine and model files; the built-in study's optimum
against the study's own designs and its constraints; the optimum written back as a machine
file (for the loader and the excavator) loads and gives the optimum's metrics again."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

import excavkin
from excavkin.cli import main
from excavkin.errors import ExcavkinError
from excavkin.io.files import OutputError
from excavkin.loader.breakout import breakout
from excavkin.loader.cycle import cycle
from excavkin.loader.dimensions import dimensions
from excavkin.loader.machine_file import load_machine
from excavkin.loader.parallel_lift import parallel_lift
from excavkin.loader.study import (
    COLUMNS,
    evaluate_loader,
    load_loader_study,
    loader_columns,
    loader_parameters,
    optimize_loader,
)
from excavkin.loader.tipping import static_tipping
from excavkin.studies.machine_study import write_machine
from excavkin.studies.metrics import Metric

STUDY = "wheel_loader_breakout"


@pytest.fixture(scope="module")
def nominal():  # type: ignore[no-untyped-def]
    return load_machine(excavkin.example_path("wheel_loader_machine"))


@pytest.fixture(scope="module")
def study():  # type: ignore[no-untyped-def]
    return load_loader_study(excavkin.example_path(STUDY))


@pytest.fixture(scope="module")
def optimum(study):  # type: ignore[no-untyped-def]
    return optimize_loader(study)


def _by_hand(tmp_path: Path, bore_mm: float, ey_mm: float, counterweight_kg: float) -> Path:
    """The built-in loader with its tilt bore, bell-crank pivot E.y and counterweight edited
    in its files' own text (independent of the study's design building and write-back)."""
    machine = excavkin.example_path("wheel_loader_machine").read_text()
    model = excavkin.example_path("wheel_loader").read_text()
    edits = (
        (model, "E = [1318.0, 1407.0]", f"E = [1318.0, {ey_mm!r}]"),
        (machine, "bore = 180 ", f"bore = {bore_mm!r} "),
        (machine, "[chassis.counterweight]           # estimate\nmass = 3000",
         f"[chassis.counterweight]           # estimate\nmass = {counterweight_kg!r}"),
    )  # fmt: skip
    texts = {"model": model, "machine": machine}
    for text, old, new in edits:
        key = "model" if text is model else "machine"
        assert texts[key].count(old) == 1, old
        texts[key] = texts[key].replace(old, new)
    (tmp_path / "wheel_loader.toml").write_text(texts["model"])
    path = tmp_path / "edited_machine.toml"
    path.write_text(texts["machine"])
    return path


def _analyses(machine) -> dict[str, float]:  # type: ignore[no-untyped-def]
    """Every column from the wing's analysis functions, called directly."""
    d, b, t = dimensions(machine), breakout(machine), static_tipping(machine)
    lift, c = parallel_lift(machine, 101), cycle(machine)
    return {
        "hinge_pin_height": d["hinge-pin height at full lift"],
        "dump_clearance": d["dump clearance at 45 deg"],
        "dump_reach": d["dump reach at 45 deg"],
        "digging_depth": d["digging depth"],
        "rollback_at_ground": d["rollback at ground"],
        "rollback_at_carry": d["rollback at carry"],
        "rollback_at_full_lift": d["rollback at full lift"],
        "dump_angle": d["dump angle at full lift"],
        "breakout.tilt": b.tilt.force,
        "breakout.lift": b.lift.force,
        "tipping.straight": t.straight.load,
        "tipping.full_turn": t.full_turn.load,
        "rated_operating_capacity": t.rated_operating_capacity,
        "lift.angle_change": lift.change,
        "lift.deviation": lift.deviation,
        "cycle.raise": c["raise"].time,
        "cycle.lower_empty": c["lower empty"].time,
        "cycle.dump": c["dump"].time,
        "cycle.time": c.total,
        "operating_mass": machine.mass,
    }


def test_each_designs_columns_are_its_own_loaders_figures(nominal, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    designs = [(170.0, 1405.5, 2600.0), (180.0, 1407.0, 3000.0), (192.5, 1411.0, 3400.0)]
    params = {
        "cylinders.tilt.bore": np.array([d[0] / 1e3 for d in designs]),
        "E.y": np.array([d[1] / 1e3 for d in designs]),
        "chassis.counterweight.mass": np.array([d[2] for d in designs]),
    }
    cols, ok = loader_columns(nominal, params, list(COLUMNS), len(designs))
    assert ok.all()
    for i, d in enumerate(designs):
        folder = tmp_path / f"d{i}"
        folder.mkdir()
        expected = _analyses(load_machine(_by_hand(folder, *d)))
        for name in COLUMNS:
            assert_allclose(cols[name][i], expected[name], rtol=1e-12, atol=1e-12, err_msg=name)
    # the designs differ where they should: a wider bore pushes harder and dumps slower
    assert np.all(np.diff(cols["breakout.tilt"]) > 0.0)
    assert np.all(np.diff(cols["cycle.dump"]) > 0.0)
    assert np.all(np.diff(cols["rated_operating_capacity"]) > 0.0)


def test_the_nominal_row_is_the_loaders_own_figures(nominal) -> None:  # type: ignore[no-untyped-def]
    metrics = [Metric(n.replace(".", "_"), n, "first") for n in COLUMNS]
    table = evaluate_loader(nominal, {"E.y": np.array([loader_parameters(nominal)["E.y"]])},
                            metrics)  # fmt: skip
    expected = _analyses(nominal)
    for m in metrics:
        assert_allclose(table[m.name][0], expected[m.column], rtol=1e-12, err_msg=m.column)
    assert bool(table["feasible"][0])


def test_a_design_that_cannot_be_or_has_no_figure_fails_its_one_pose(nominal) -> None:  # type: ignore[no-untyped-def]
    p = loader_parameters(nominal)
    # a rod wider than its bore; a bell crank whose bucket no longer dumps 45°
    params = {"cylinders.tilt.rod": np.array([p["cylinders.tilt.rod"], 0.2, 0.09]),
              "E.y": np.array([p["E.y"], p["E.y"], p["E.y"] - 0.02])}  # fmt: skip
    cols, ok = loader_columns(nominal, params, ["breakout.tilt", "dump_clearance"], 3)
    assert ok.tolist() == [True, False, False]
    assert np.isnan(cols["breakout.tilt"][1]) and np.isnan(cols["dump_clearance"][2])
    assert np.isfinite(cols["breakout.tilt"][2])


def test_the_optimum_meets_its_constraints_and_beats_the_studys_designs(study, optimum) -> None:  # type: ignore[no-untyped-def]
    assert optimum.feasible and optimum.success
    assert optimum.metrics["dump_angle"] >= np.radians(45.0) - 1e-9
    assert optimum.metrics["dump_time"] <= 2.5 + 1e-9
    # the breakout grows with the bore and as E falls; the dump time and dump angle hold both
    assert set(optimum.active) == {"dump_angle", "dump_time"}
    from excavkin.studies.design_space import sample_designs

    table = study.evaluate(sample_designs(study.bounds, 16, "sobol", 3))
    feasible = table[table["feasible"]]
    assert len(feasible) > 0
    assert optimum.value >= feasible["breakout"].max()
    nominal = study.evaluate({k: np.array([v]) for k, v in loader_parameters(
        study.machine).items() if k in study.bounds})  # fmt: skip
    assert optimum.value > nominal["breakout"][0]


def test_the_optimum_written_as_a_machine_file_gives_its_metrics(study, optimum, tmp_path) -> None:  # type: ignore[no-untyped-def]
    out = write_machine(study, optimum.params, tmp_path / "best.toml")
    loaded = load_machine(out)
    assert loaded.cylinders[1].bore == optimum.params["cylinders.tilt.bore"]
    assert loaded.mechanism.model.points["E"][1] == optimum.params["E.y"]
    figures = _analyses(loaded)
    for m in study.metrics:
        assert_allclose(figures[m.column], optimum.metrics[m.name], rtol=1e-12, err_msg=m.name)
    # the file stands alone: the model is inline, nothing refers to the files it came from
    assert "[model]" in out.read_text()
    with pytest.raises(OutputError, match="exists"):
        write_machine(study, optimum.params, out)
    write_machine(study, optimum.params, out, force=True)


def test_the_study_file_refuses_what_a_loader_study_cannot_be(tmp_path: Path) -> None:
    text = excavkin.example_path(STUDY).read_text()
    cases = {
        "poses": (text + '\n[poses]\nlift_cyl = "2000 mm"\n', "has no poses"),
        "column": (text.replace('"breakout.tilt"', '"breakout.bucket"'), "breakout.tilt"),
        "parameter": (text.replace('"E.y" = ', '"E.z" = '), "E.y"),
        "model": (text.replace('machine = "wheel_loader_machine"', 'model = "wheel_loader"'),
                  "excavkin optimize"),
        "excavator": (text.replace('"wheel_loader_machine"', '"excavator_machine"'),
                      "excavkin excavator study"),
    }  # fmt: skip
    for name, (content, words) in cases.items():
        path = tmp_path / f"{name}.toml"
        path.write_text(content)
        with pytest.raises(ExcavkinError, match=words):
            load_loader_study(path)


def test_loader_study_and_optimize_on_the_command_line(tmp_path: Path) -> None:
    small = excavkin.example_path(STUDY).read_text().replace("samples = 64", "samples = 3")
    spec = tmp_path / "small.toml"
    spec.write_text(small)
    r = CliRunner().invoke(main, ["loader", "study", str(spec), "-o", str(tmp_path / "m.parquet"),
                                  "-q"])  # fmt: skip
    assert r.exit_code == 0, r.output
    import pandas as pd

    table = pd.read_parquet(tmp_path / "m.parquet")
    assert len(table) == 3 and {"design.E.y", "breakout", "feasible"} <= set(table.columns)
    assert "wrote 3 designs" in r.output
    # a machine file that exists stops the command before it optimises, and is left as it was
    taken = tmp_path / "taken.toml"
    taken.write_text("keep me")
    r = CliRunner().invoke(main, ["loader", "optimize", str(spec), "--write-machine", str(taken)])
    assert r.exit_code == 2 and "excavkin: error:" in r.output and "taken.toml" in r.output
    assert taken.read_text() == "keep me"
    best = str(tmp_path / "best.toml")
    r = CliRunner().invoke(main, ["loader", "optimize", str(spec), "-o", str(tmp_path / "b.csv"),
                                  "--write-machine", best, "-q"])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "maximum of breakout" in r.output and "feasible" in r.output
    assert "wrote the optimal design as a machine file" in r.output
    assert load_machine(tmp_path / "best.toml").name == load_machine(
        excavkin.example_path("wheel_loader_machine")).name  # fmt: skip


def test_the_excavator_optimum_written_as_a_machine_file_gives_its_metrics(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """The excavator's study (a short run): its optimum as a machine file, loaded and
    evaluated as it is, gives the optimum's metrics; the machine file's own parameters
    (a bore, a pressure) are written into their tables."""
    from excavkin.excavator.designs import machine_parameters
    from excavkin.excavator.machine_file import load_machine as load_excavator
    from excavkin.excavator.study import evaluate_machine, load_machine_study, optimize_machine

    study = load_machine_study(excavkin.example_path("excavator_bucket_linkage"))
    best = optimize_machine(study, method="slsqp", maxiter=3)

    def as_it_is(machine):  # type: ignore[no-untyped-def]
        own = machine_parameters(machine)
        return evaluate_machine(machine, {"L.x": np.array([own["L.x"]])}, study.lengths,
                                study.metrics)  # fmt: skip

    loaded = load_excavator(write_machine(study, best.params, tmp_path / "best.toml"))
    again = as_it_is(loaded)
    for name, value in best.metrics.items():
        assert_allclose(again[name][0], value, rtol=1e-12, err_msg=name)
    params = {**best.params, "cylinders.bucket.bore": 0.125, "circuits.bucket.working": 33e6}
    loaded = load_excavator(write_machine(study, params, tmp_path / "bored.toml"))
    assert loaded.cylinders[2].bore == 0.125 and loaded.circuits["bucket"].working == 33e6
    designed = evaluate_machine(study.machine, {k: np.array([v]) for k, v in params.items()},
                                study.lengths, study.metrics)  # fmt: skip
    again = as_it_is(loaded)
    for m in study.metrics:
        assert_allclose(again[m.name][0], designed[m.name][0], rtol=1e-12, err_msg=m.name)
    assert designed["force_min"][0] != best.metrics["force_min"]
