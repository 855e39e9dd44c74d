"""Geometry as a batch axis: each sample solved with its own dimensions equals that design
solved as its own model, kinematics and forces, for every example model."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pint
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import excavkin
from excavkin.errors import InputError, UnitError
from excavkin.kinematics.kernels import Code


def as_own_model(model: excavkin.Model, params: dict[str, float]) -> excavkin.Model:
    """The model with the parameters set, built the plain way (one design)."""
    pts, lengths, bodies = dict(model.points), dict(model.lengths), list(model.bodies)
    gears = {g.name: g for g in model.gears}
    racks = {r.name: r for r in model.racks}
    names = [b.name for b in bodies]
    for key, v in params.items():
        head, _, tail = key.rpartition(".")
        if tail == "ratio" and head in gears:
            gears[head] = dataclasses.replace(gears[head], ratio=v)
        elif tail == "radius" and head in racks:
            racks[head] = dataclasses.replace(racks[head], radius=v)
        elif ".center_of_mass." in key:
            body, _, axis = key.split(".")
            j = names.index(body)
            com = list(bodies[j].center_of_mass or (0.0, 0.0))
            com["xy".index(axis)] = v
            bodies[j] = dataclasses.replace(bodies[j], center_of_mass=(com[0], com[1]))
        elif tail in ("mass", "inertia"):
            j = names.index(head)
            bodies[j] = dataclasses.replace(bodies[j], **{tail: v})
        elif tail in ("x", "y"):
            xy = list(pts[head])
            xy["xy".index(tail)] = v
            pts[head] = (xy[0], xy[1])
        else:
            p, q = key.split("-")
            lengths[(p, q)] = v
    return dataclasses.replace(
        model,
        points=pts,
        lengths=lengths,
        bodies=tuple(bodies),
        gears=tuple(gears.values()),
        racks=tuple(racks.values()),
    )


def compare_with_own_models(
    mech: excavkin.Mechanism, values: dict, params: dict, n: int, chunk: int
) -> float:
    """The largest difference, relative to max(1, |value|), between the batch over designs and
    each design solved alone (kinematics and forces)."""
    rates = {k: 0.1 for k in values}
    batch = mech.solve(values, rates=rates, params=params, loads="model", chunk=chunk)
    table = batch.to_frame()
    worst = 0.0
    for i in range(n):
        own = excavkin.Mechanism(
            as_own_model(mech.model, {k: float(v[i]) for k, v in params.items()}),
            method=mech.plan.method,
        )
        alone = own.solve({k: v[i : i + 1] for k, v in values.items()}, rates=rates, loads="model")
        ref = alone.to_frame()
        assert table["status"].iloc[i] == ref["status"].iloc[0]
        for col in ref.columns:
            if ref[col].dtype.kind == "f" and np.isfinite(ref[col].iloc[0]):
                d = abs(table[col].iloc[i] - ref[col].iloc[0]) / max(1.0, abs(ref[col].iloc[0]))
                worst = max(worst, d)
    return worst


def random_designs(mech: excavkin.Mechanism, rng: np.random.Generator, n: int) -> tuple:
    """Inputs near the sketch and every third parameter moved a little, per sample."""
    values = {
        k: v + rng.uniform(-0.2, 0.2, n)
        if mech.input_kind(k) == "angle"
        else v * (1 + rng.uniform(-0.02, 0.02, n))
        for k, v in mech.sketch_values().items()
    }
    params = {}
    # a slider's point and its line stay as drawn: a design that moves one off the other is no
    # model of its own (the builder refuses a point drawn off its line), so it has none to match
    on_slides = {p for sl in mech.model.sliders for p in (sl.point, *sl.along)}
    for k, v in list(mech.parameters.items())[::3]:
        if k.rpartition(".")[0] in on_slides:
            continue
        if k.endswith((".mass", ".inertia")):
            params[k] = v * (1 + rng.uniform(-0.2, 0.2, n))
        else:
            params[k] = v + 0.002 * mech.plan.scale * rng.uniform(-1, 1, n)
    return values, params


@pytest.mark.parametrize(
    "name",
    ["fourbar", "slider_crank", "excavator", "rope_shovel", "pasika_module", "arm_vector"],
)
def test_each_example_as_a_family_of_designs(name: str) -> None:
    mech = excavkin.load(excavkin.example_path(name))
    rng = np.random.default_rng(len(name))
    n = 24
    values, params = random_designs(mech, rng, n)
    assert compare_with_own_models(mech, values, params, n, chunk=5) <= 1e-12


def test_gear_ratios_as_a_family_of_designs() -> None:
    """A planetary train's two ratios per design (the train's coefficients and the pitch
    points of its tooth forces) equal each design solved as its own model."""
    path = Path(__file__).parents[1] / "reference" / "data" / "planetary_21_43_108.toml"
    text = path.read_text() + '[loads.out]\ntype = "torque"\nbody = "carrier"\n'
    mech = excavkin.loads(text + 'value = "-20 N*m"\n[gravity]\n', "planetary.toml")
    rng = np.random.default_rng(7)
    n = 9
    values = {"input": rng.uniform(-8.0, 8.0, n)}
    params = {
        "sun_planet.ratio": 43 / 21 * (1 + rng.uniform(-0.1, 0.1, n)),
        "planet_ring.ratio": 108 / 43 * (1 + rng.uniform(-0.1, 0.1, n)),
        "planet.mass": 0.9 * (1 + rng.uniform(-0.2, 0.2, n)),
    }
    assert compare_with_own_models(mech, values, params, n, chunk=4) <= 1e-12


def test_the_generic_solver_takes_designs_too() -> None:
    fb = excavkin.load(excavkin.example_path("fourbar"))
    mech = excavkin.Mechanism(fb.model, method="newton")
    rng = np.random.default_rng(3)
    n = 12
    values = {"crank": rng.uniform(0.0, 1.0, n)}
    params = {"A-B": 0.12 + rng.uniform(-3e-3, 3e-3, n), "O4.x": 0.1 + rng.uniform(-3e-3, 3e-3, n)}
    assert compare_with_own_models(mech, values, params, n, chunk=5) <= 1e-12


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    ab=st.floats(0.105, 0.135),
    o4b=st.floats(0.08, 0.10),
    o4=st.tuples(st.floats(0.09, 0.11), st.floats(-0.01, 0.01)),
    mass=st.floats(0.1, 5.0),
    crank=st.floats(0.0, 2 * np.pi),
)
def test_random_four_bar_designs(ab, o4b, o4, mass, crank) -> None:  # type: ignore[no-untyped-def]
    """One hypothesis design beside the nominal: the pair solved in one batch equals each
    alone (so a design never leaks into its neighbour's sample)."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    nominal = mech.parameters
    params = {
        "A-B": np.array([nominal["A-B"], ab]),
        "O4-B": np.array([nominal["O4-B"], o4b]),
        "O4.x": np.array([nominal["O4.x"], o4[0]]),
        "O4.y": np.array([nominal["O4.y"], o4[1]]),
        "rocker.mass": np.array([nominal["rocker.mass"], mass]),
    }
    values = {"crank": np.array([crank, crank])}
    assert compare_with_own_models(mech, values, params, 2, chunk=1) <= 1e-12


def test_a_design_that_builds_no_mechanism_is_a_status() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    # the ground's two points coincide in the second design; the third cannot close
    res = mech.solve(
        {"crank": np.zeros(3)},
        params={"O4.x": np.array([0.1, 0.0, 0.1]), "A-B": np.array([0.12, 0.12, 0.01])},
    )
    assert res.status.code.tolist() == [Code.OK, Code.BAD_DESIGN, Code.NO_CLOSURE]
    assert res.status.message(1) == "the design's dimensions build no mechanism"
    moving = res.point("B")[0]
    assert np.isnan(moving[1]).all() and np.isfinite(moving[0]).all()


def test_parameters_carry_units_and_are_checked() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    u = pint.UnitRegistry()
    a = mech.solve({"crank": [0.1, 0.2]}, params={"A-B": np.array([118.0, 125.0]) * u.mm})
    b = mech.solve({"crank": [0.1, 0.2]}, params={"A-B": np.array([0.118, 0.125])})
    np.testing.assert_allclose(a.positions, b.positions, rtol=1e-15, atol=1e-17)
    c = mech.solve({"crank": [0.1, 0.2]}, params={"A-B": "125 mm"})
    assert c.parameters is not None and c.parameters["A-B"] == pytest.approx(0.125)
    with pytest.raises(InputError, match="did you mean 'A-B'"):
        mech.solve({"crank": [0.1]}, params={"A-C": 0.1})
    with pytest.raises(UnitError, match="parameter 'A-B'"):
        mech.solve({"crank": [0.1]}, params={"A-B": "3 kg"})
    with pytest.raises(InputError, match="different lengths"):
        mech.solve({"crank": [0.1, 0.2]}, params={"A-B": [0.1, 0.11, 0.12]})


def test_a_held_driver_keeps_its_own_designs_sketch_value() -> None:
    """The excavator's arm cylinder held (not given): its length is each design's own sketch
    distance, as when the design is loaded alone."""
    mech = excavkin.load(excavkin.example_path("excavator"))
    n = 3
    values = {"boom_cyl": np.full(n, mech.sketch_values()["boom_cyl"])}
    moved = mech.parameters["E.x"] + np.array([0.0, 0.02, -0.02])
    res = mech.solve(values, params={"E.x": moved})
    arm = res.driver("arm_cyl")[0]
    for i in range(n):
        own = excavkin.Mechanism(as_own_model(mech.model, {"E.x": float(moved[i])}))
        assert arm[i] == own.sketch_values()["arm_cyl"]
    assert arm[1] != arm[0]


def test_the_command_line_sweeps_a_parameter_and_adds_its_derivatives(tmp_path) -> None:  # type: ignore[no-untyped-def]
    import pandas as pd
    from click.testing import CliRunner

    from excavkin.cli import main

    out = tmp_path / "designs.csv"
    args = ["solve", "fourbar", "--sweep", "crank=30deg:30deg:5", "--param", "A-B=110mm:130mm:5"]
    r = CliRunner().invoke(main, [*args, "--sensitivity", "A-B", "-o", str(out)])
    assert r.exit_code == 0, r.output
    table = pd.read_csv(out)
    mech = excavkin.load(excavkin.example_path("fourbar"))
    ab = np.linspace(0.110, 0.130, 5)
    res = mech.solve(
        {"crank": np.full(5, np.radians(30.0))}, params={"A-B": ab}, sensitivities=["A-B"]
    )
    np.testing.assert_array_equal(table["design.A-B"], ab)
    np.testing.assert_array_equal(table["B.x"], res.column("B.x"))
    np.testing.assert_array_equal(table["d(B.x)/d(A-B)"], res.sensitivity("B.x", "A-B"))
    for bad, words in [
        (["--param", "A-C=1:2:5"], "did you mean 'A-B'"),
        (["--param", "A-B=1kg:2kg:5"], "is not a length"),
        (["--param", "A-B=0.1:0.2:4"], "same number of samples"),
        (["--sensitivity", "O4"], "no parameter 'O4'"),
    ]:
        r = CliRunner().invoke(main, [*args[:4], *bad, "-o", str(tmp_path / "x.csv")])
        assert r.exit_code == 2 and words in r.output, r.output


def test_derivative_columns_count_in_the_disk_check(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """Each --sensitivity adds a derivative of every column: a table that fits on the disk
    without them is refused with them, before anything is solved (memory is bounded by a
    part of the stream; the disk is not)."""
    import shutil
    from collections import namedtuple

    from click.testing import CliRunner

    from excavkin.cli import main
    from excavkin.cli.commands.solve import _columns_per_sample, check_disk

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda path: usage(2**40, 0, 20 * 2**30))
    names = ["A-B", "O4-B", "O4.x", "O4.y", "A.x", "A.y", "B.x", "B.y", "O2.x", "O2.y"]
    out = tmp_path / "o.csv"
    args = ["solve", "fourbar", "-q", "--sweep", "crank=0:1:5000000", "-o", str(out)]
    columns = _columns_per_sample(excavkin.load(excavkin.example_path("fourbar")), False)
    check_disk(out, 5_000_000, columns)  # fits without them
    for name in names:
        args += ["--sensitivity", name]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 2 and "GiB on disk" in r.output, r.output
    assert "5,000,000 samples" in r.output and not out.exists()


def test_values_no_design_can_have_are_a_status_or_an_error() -> None:
    """A length or mass not positive, a negative inertia, a value not finite: the design
    builds no mechanism (as the plain model refuses them); a value that is not a number at all
    is an error naming the parameter."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    q = {"crank": np.radians([10.0, 20.0, 30.0, 40.0, 50.0])}
    res = mech.solve(
        q,
        params={
            "A-B": np.array([0.12, -0.12, 0.12, np.nan, 0.12]),
            "rocker.mass": np.array([0.6, 0.6, -1.0, 0.6, 0.6]),
            "rocker.inertia": np.array([0.0, 1e-4, 1e-4, 1e-4, -1e-4]),
            "B@rocker.x": np.array([-1e-5, 0.0, 0.0, 0.0, 0.0]),  # an offset may be negative
        },
        loads="model",
    )
    assert res.kinematics.status.code.tolist() == [Code.OK] + [Code.BAD_DESIGN] * 4
    assert np.isnan(res.torque("crank")[1:]).all() and np.isfinite(res.torque("crank")[0])
    for bad in (None, True, 0.12 + 1j, "twelve"):
        with pytest.raises((InputError, UnitError), match="parameter 'A-B'"):
            mech.solve(q, params={"A-B": bad})
    one = mech.solve(q, sensitivities="A-B")  # one name, not its letters
    assert np.isfinite(one.sensitivity("B.x", "A-B")).all()
