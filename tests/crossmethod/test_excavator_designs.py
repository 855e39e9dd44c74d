"""A family of machine designs in one batch against each design built as its own machine; the
bucket-linkage study's optimum against a brute-force grid and the working ranges."""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from excavkin.errors import ExcavkinError
from excavkin.excavator.designs import (
    design_machine,
    design_tool_forces,
    machine_parameters,
)
from excavkin.excavator.forces import tool_forces
from excavkin.excavator.machine_file import load_machine
from excavkin.excavator.study import (
    evaluate_machine,
    load_machine_study,
    machine_columns,
    optimize_machine,
)
from excavkin.studies.metrics import Metric

STUDY = "excavator_bucket_linkage"


@pytest.fixture(scope="module")
def machine():  # type: ignore[no-untyped-def]
    return load_machine(excavkin.example_path("excavator_machine"))


@pytest.fixture(scope="module")
def study():  # type: ignore[no-untyped-def]
    return load_machine_study(excavkin.example_path(STUDY))


@pytest.fixture(scope="module")
def optimum(study):  # type: ignore[no-untyped-def]
    return optimize_machine(study, method="slsqp")


def test_parameters_are_the_mechanisms_and_the_machine_files(machine) -> None:  # type: ignore[no-untyped-def]
    p = machine_parameters(machine)
    assert {k: p[k] for k in machine.mechanism.parameters} == machine.mechanism.parameters
    assert p["cylinders.boom.bore"] == pytest.approx(0.120, rel=1e-15)
    assert p["cylinders.arm.rod"] == pytest.approx(0.095, rel=1e-15)
    assert p["cylinders.bucket.retracted"] == pytest.approx(1.645, rel=1e-15)
    assert p["cylinders.bucket.stroke"] == pytest.approx(1.120, rel=1e-15)
    assert p["circuits.bucket.working"] == pytest.approx(34.3e6, rel=1e-15)
    assert p["circuits.arm.relief"] == pytest.approx(39.2e6, rel=1e-15)
    assert machine.parameters == p


def _random_designs(machine, rng, d):  # type: ignore[no-untyped-def]
    p = machine_parameters(machine)
    pins = ["H.x", "H.y", "N.x", "N.y", "K.x", "K.y", "L.x", "L.y", "G.x", "D.y"]
    out = {k: p[k] + rng.uniform(-0.03, 0.03, d) for k in pins}
    for k in (
        "bucket.mass",
        "stick.mass",
        "cylinders.bucket.bore",
        "cylinders.arm.rod",
        "cylinders.boom.bore",
        "circuits.bucket.working",
        "circuits.arm.working",
    ):
        out[k] = p[k] * rng.uniform(0.9, 1.1, d)
    out["bucket.center_of_mass.x"] = p["bucket.center_of_mass.x"] + rng.uniform(-0.05, 0.05, d)
    out["h_link.center_of_mass.y"] = p["h_link.center_of_mass.y"] + rng.uniform(-0.05, 0.05, d)
    # reliefs at least the working pressures
    for c in ("bucket", "arm", "boom"):
        out[f"circuits.{c}.relief"] = np.maximum(
            p[f"circuits.{c}.relief"] * rng.uniform(0.95, 1.1, d),
            out.get(f"circuits.{c}.working", p[f"circuits.{c}.working"]),
        )
    return out


@pytest.mark.parametrize("working", ["bucket", "arm"])
@pytest.mark.parametrize("gravity", [True, False])
@pytest.mark.parametrize("at", ["lip", "tip"])
def test_design_forces_equal_each_design_as_its_own_machine(machine, working, gravity, at) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(15)
    d, p = 5, 7
    designs = _random_designs(machine, rng, d)
    lengths = np.column_stack([
        np.full(p, 2.768), np.linspace(2.4, 3.4, p), np.linspace(1.7, 2.7, p)
    ])  # fmt: skip
    params = {k: np.repeat(v, p) for k, v in designs.items()}
    batch = design_tool_forces(
        machine, np.tile(lengths, (d, 1)), params, working, at=at, gravity=gravity
    )
    force = batch.force.reshape(d, p)
    cyl = batch.cylinder_force.reshape(d, p, 3)
    for i in range(d):
        one = design_machine(machine, {k: float(v[i]) for k, v in designs.items()})
        ref = tool_forces(one, lengths, working, at=at, gravity=gravity)
        assert np.all(np.isfinite(ref.force)) and np.all(ref.force > 0.0)
        np.testing.assert_allclose(force[i], ref.force, rtol=1e-12, atol=0.0)
        np.testing.assert_allclose(cyl[i], ref.cylinder_force, rtol=1e-12, atol=1e-6)
        np.testing.assert_array_equal(batch.limiting.reshape(d, p)[i], ref.limiting)


def test_design_machine_of_no_change_is_the_machine(machine) -> None:  # type: ignore[no-untyped-def]
    L = np.array([[2.768, 2.972, 2.2]])
    same = design_machine(machine, {})
    for g in (True, False):
        a = tool_forces(machine, L, "bucket", gravity=g).force
        assert tool_forces(same, L, "bucket", gravity=g).force[0] == pytest.approx(a[0], rel=1e-15)


def test_pose_outside_a_designs_stroke_fails(machine) -> None:  # type: ignore[no-untyped-def]
    L = np.array([[2.768, 2.972, 2.70], [2.768, 2.972, 2.70]])
    params = {"cylinders.bucket.stroke": np.array([1.12, 1.0])}  # extended 2.765, 2.645 m
    _, ok = machine_columns(machine, L, params, ["rated.bucket"])
    assert ok.tolist() == [True, False]
    bad = {"cylinders.bucket.rod": np.array([0.085, 0.2])}  # a rod wider than the bore
    _, ok = machine_columns(machine, L, bad, ["rated.bucket"])
    assert ok.tolist() == [True, False]


def test_study_of_the_nominal_design_is_the_machines_own(machine, study) -> None:  # type: ignore[no-untyped-def]
    assert STUDY in excavkin.examples("study")
    nominal = {k: np.array([machine.mechanism.parameters[k]]) for k in study.bounds}
    row = study.evaluate(nominal)
    f = tool_forces(machine, study.lengths, "bucket", gravity=False).force
    assert row["force_min"][0] == pytest.approx(f.min(), rel=1e-14)
    assert bool(row["feasible"][0])


def test_unknown_names_are_refused(machine, tmp_path) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ExcavkinError, match="parameter"):
        evaluate_machine(
            machine, {"cylinders.bucket.bores": np.array([0.1])},
            np.array([[2.768, 2.972, 2.2]]), [Metric("f", "rated.bucket", "min")],
        )  # fmt: skip
    text = excavkin.example_path(STUDY).read_text(encoding="utf-8")
    bad = tmp_path / "s.toml"
    bad.write_text(text.replace('"rated.bucket"', '"rated.buckets"'), encoding="utf-8")
    with pytest.raises(ExcavkinError, match=r"s\.toml.*metrics.*rated\.bucket"):
        load_machine_study(bad)
    bad.write_text(text.replace('"excavator_machine"', '"nowhere"'), encoding="utf-8")
    with pytest.raises(ExcavkinError, match="nowhere"):
        load_machine_study(bad)
    from excavkin.studies.study_file import load_study

    with pytest.raises(ExcavkinError, match="excavator optimize"):
        load_study(excavkin.example_path(STUDY))


def test_bucket_linkage_optimum_beats_no_point_of_a_grid(study, optimum) -> None:  # type: ignore[no-untyped-def]
    """Brute force on the slice of the two parameters not at a bound, the others at the
    optimum: the whole box coarsely, and 8 mm around the optimum finely (0.1 mm)."""
    nominal = study.evaluate(
        {
            k: np.array([v])
            for k, v in machine_parameters(study.machine).items()
            if k in study.bounds
        }
    )
    assert optimum.feasible and optimum.success
    assert optimum.value > 1.3 * nominal["force_min"][0]  # the gain the docs report: ~40 %
    free = [k for k in study.bounds if k not in optimum.at_bounds]
    assert len(free) == 2
    a, b = free
    for (alo, ahi), (blo, bhi), n in (
        (study.bounds[a], study.bounds[b], 41),
        ((optimum.params[a] - 0.004, optimum.params[a] + 0.004),
         (optimum.params[b] - 0.004, optimum.params[b] + 0.004), 81),
    ):  # fmt: skip
        A, B = np.meshgrid(np.linspace(alo, ahi, n), np.linspace(blo, bhi, n), indexing="ij")
        designs = {k: np.full(A.size, v) for k, v in optimum.params.items()}
        designs[a], designs[b] = A.ravel(), B.ravel()
        table = study.evaluate(designs)
        feasible = table["feasible"].to_numpy()
        best = table["force_min"].to_numpy()[feasible].max(initial=-np.inf)
        assert best <= optimum.value * (1.0 + 1e-9)
    assert feasible.sum() > 100  # the fine grid sees the feasible region
    assert best >= optimum.value * (1.0 - 2e-3)  # and comes within its resolution


def test_differential_evolution_finds_the_same_optimum(study, optimum) -> None:  # type: ignore[no-untyped-def]
    de = optimize_machine(study)  # the study's own method
    assert de.feasible
    assert de.value == pytest.approx(optimum.value, rel=1e-9)
    for k, v in optimum.params.items():
        assert de.params[k] == pytest.approx(v, abs=1e-6)


def test_bucket_linkage_optimum_keeps_the_working_ranges(study, optimum) -> None:  # type: ignore[no-untyped-def]
    from excavkin.excavator.ranges import working_ranges

    before = {f.key: f.value for f in working_ranges(study.machine).figures}
    after = {f.key: f.value for f in
             working_ranges(design_machine(study.machine, optimum.params)).figures}  # fmt: skip
    for key, value in before.items():
        assert after[key] == pytest.approx(value, rel=0.01), key


def test_command_line_optimize_and_the_core_reader_refusing(tmp_path, optimum) -> None:  # type: ignore[no-untyped-def]
    import pandas as pd
    from click.testing import CliRunner

    from excavkin.cli import main

    out = tmp_path / "best.csv"
    r = CliRunner().invoke(
        main, ["excavator", "optimize", STUDY, "--method", "slsqp", "-o", str(out)]
    )
    assert r.exit_code == 0, r.output
    assert "feasible" in r.output and "N.x (low)" in r.output
    row = pd.read_csv(out)
    assert row["force_min"][0] == pytest.approx(optimum.value, rel=1e-12)
    r = CliRunner().invoke(main, ["excavator", "optimize", STUDY, "-o", str(out)])
    assert r.exit_code != 0 and "exists" in r.output  # never overwritten without --force
    r = CliRunner().invoke(main, ["study", STUDY, "-o", str(tmp_path / "t.parquet")])
    assert r.exit_code != 0 and "excavkin excavator optimize" in r.output
    assert "Traceback" not in r.output


def test_a_machine_study_table_is_its_designs_evaluated_and_resumes(tmp_path, study) -> None:  # type: ignore[no-untyped-def]
    """`excavkin excavator study`: the table holds the design of experiments' designs, each
    row equal to evaluating that design directly; an interrupted run resumes to the same
    table; the units are in the metadata."""
    import dataclasses
    import json

    import pandas as pd
    import pyarrow.parquet as pq
    from click.testing import CliRunner

    from excavkin.cli import main
    from excavkin.studies.design_space import sample_designs
    from excavkin.studies.study import run_study

    small = dataclasses.replace(study, samples=48)
    whole = run_study(small, tmp_path / "whole.parquet", chunk_samples=10 * 57)
    table = pd.read_parquet(whole)
    designs = sample_designs(small.bounds, 48, small.method, small.seed, (0, 48))
    direct = small.evaluate(designs)
    assert list(table["design"]) == list(range(48))
    pd.testing.assert_frame_equal(table.drop(columns="design"), direct, check_exact=True)
    units = json.loads(pq.read_schema(whole).metadata[b"excavkin.units"])
    assert units["design.N.x"] == "m" and units["force_min"] == "N"
    # interrupted after two chunks: the rest is computed on resuming, the table is the same
    parts = tmp_path / ".resumed.parquet.parts"
    calls = []

    def stop_after_two(done: int, total: int) -> None:
        calls.append(done)
        if len(calls) == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_study(small, tmp_path / "resumed.parquet", chunk_samples=10 * 57,
                  progress=stop_after_two)  # fmt: skip
    assert len(list(parts.glob("part-*.parquet"))) == 2
    resumed = run_study(small, tmp_path / "resumed.parquet", chunk_samples=10 * 57)
    assert pd.read_parquet(resumed).equals(table)
    # the command line, by the built-in study's name
    out = tmp_path / "linkage.parquet"
    r = CliRunner().invoke(main, ["excavator", "study", STUDY, "-o", str(out), "-q"])
    assert r.exit_code == 0, r.output
    assert "4,096 designs" in r.output and out.stat().st_size > 0
    r = CliRunner().invoke(main, ["excavator", "study", STUDY, "-o", str(out), "-q"])
    assert r.exit_code != 0 and "--force" in r.output and "Traceback" not in r.output
    # a model's study given to the machine command: pointed to the right one
    r = CliRunner().invoke(main, ["excavator", "study", "crank_rocker", "-q"])
    assert r.exit_code == 2 and "`excavkin study`" in r.output and "crank_rocker" in r.output


def test_design_ranges_equal_each_designs_own_working_ranges(machine) -> None:  # type: ignore[no-untyped-def]
    """The free working-range figures of a family of designs, searched together, equal each
    design's own working_ranges (pins of the bucket linkage and the bucket cylinder's stroke
    changed); a design with an impossible cylinder gives NaN; as machine columns they are the
    design's figure at every pose."""
    from excavkin.excavator.design_ranges import FIGURES, design_ranges
    from excavkin.excavator.designs import design_machine
    from excavkin.excavator.ranges import working_ranges

    rng = np.random.default_rng(5)
    nominal = machine.mechanism.parameters
    # moves that keep the linkage assembling over the whole stroke (working_ranges needs it)
    params = {k: nominal[k] + rng.uniform(-0.02, 0.02, 3) for k in ("N.x", "N.y", "L.x", "L.y")}
    params["cylinders.bucket.stroke"] = np.array([1.10, 1.08, 1.10])
    params["cylinders.bucket.rod"] = np.array([0.085, 0.085, 0.2])  # the third: rod > bore
    got = design_ranges(machine, params)
    for i in range(2):
        own = working_ranges(design_machine(machine, {k: float(v[i]) for k, v in params.items()}))
        for f in FIGURES:
            assert got[f][i] == pytest.approx(own.figure(f).value, abs=1e-9), (i, f)
    assert all(np.isnan(got[f][2]) for f in FIGURES)
    L = np.array([[2.7, 2.9, 2.0], [2.6, 3.0, 1.9]])
    cols, _ = machine_columns(
        machine, np.repeat(L, 2, axis=0), {k: np.tile(v[:2], 2) for k, v in params.items()},
        ["range.max_digging_depth"],
    )  # fmt: skip
    np.testing.assert_array_equal(
        cols["range.max_digging_depth"], np.tile(got["max_digging_depth"][:2], 2)
    )


def test_a_design_that_does_not_assemble_over_its_strokes_has_no_ranges(machine) -> None:  # type: ignore[no-untyped-def]
    """An arm cylinder retracting below where the front assembles: working_ranges refuses
    such a machine, and the family's search gives NaN rather than a figure at the edge of
    assembly."""
    from excavkin.errors import ModelError
    from excavkin.excavator.design_ranges import design_ranges
    from excavkin.excavator.designs import design_machine
    from excavkin.excavator.ranges import working_ranges

    bad = {"cylinders.arm.retracted": 1.80, "cylinders.arm.stroke": 1.76}
    with pytest.raises(ModelError):
        working_ranges(design_machine(machine, bad))
    got = design_ranges(machine, {k: np.array([v]) for k, v in bad.items()})
    assert all(np.isnan(v[0]) for v in got.values())


def test_a_machine_studys_fingerprint_reads_the_model_file_too(tmp_path, machine) -> None:  # type: ignore[no-untyped-def]
    """Editing the model file a machine file names makes another study (its parts are not
    resumed into it)."""
    import shutil

    from excavkin.excavator.study import load_machine_study

    for name in ("excavator_machine", "excavator"):
        shutil.copy(excavkin.example_path(name), tmp_path / f"{name}.toml")
    study = tmp_path / "s.toml"
    text = excavkin.example_path(STUDY).read_text()
    study.write_text(
        text.replace('machine = "excavator_machine"', 'machine = "excavator_machine.toml"')
    )
    assert load_machine_study(study).source.startswith(
        (tmp_path / "excavator_machine.toml").read_text()
    )
    before = load_machine_study(study).fingerprint()
    model = tmp_path / "excavator.toml"
    model.write_text(model.read_text() + "\n# an edit\n")
    assert load_machine_study(study).fingerprint() != before
