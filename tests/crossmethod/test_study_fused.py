"""A study's fused evaluation (each design's constants made once, metrics taken block by
block, no full state kept) against the full solve of every design at every pose: the same
table, to the bit, for every kind of metric a study file can name, across block boundaries,
with failing poses, designs that build no mechanism, pose sets, held drivers and either
backend."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import excavkin
from excavkin.errors import InputError
from excavkin.execution import Execution, use
from excavkin.kinematics.solve import BLOCK
from excavkin.studies.design_space import sample_designs
from excavkin.studies.fused import evaluate_designs, evaluate_fused, fusable
from excavkin.studies.metrics import (
    REDUCTIONS,
    Constraint,
    Metric,
    Poses,
    clearance_metric,
    evaluate,
)
from excavkin.studies.study import Study, run_study


def every_kind(p: int) -> list[Metric]:
    """One metric of each reduction (targets for sumsq and absmax), a change of an angle
    and of a length, and a clearance."""
    target = tuple(np.linspace(0.9, 1.1, p))
    out = [Metric(f"g_{how}", "B.transmission", how) for how in REDUCTIONS if how != "sumsq"]
    out += [
        Metric("swing", "rocker.angle", "change"),
        Metric("dx", "B.x", "change"),
        Metric("fit", "B.transmission", "sumsq", target),
        Metric("off", "rocker.omega", "absmax", (0.5,)),
        Metric("vy", "B.vy", "mean"),
        clearance_metric("gap", ("A", "B"), ("O2", "O4")),
    ]
    return out


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_fused_equals_the_full_solve_for_every_metric_kind(backend: str) -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    assert fusable(mech)
    p = 97  # designs straddle the blocks
    d = BLOCK // p + 40  # more than one block
    # wide bounds: some poses fail (a crank that cannot turn), some designs near dead centres,
    # some build no mechanism (a coupler of no length)
    bounds = {"A-B": (-0.01, 0.16), "O4-B": (0.05, 0.12), "O4.x": (0.08, 0.13)}
    designs = sample_designs(bounds, d, "sobol", 1)
    poses = Poses({"crank": np.linspace(0.0, 2 * np.pi, p)}, {"crank": 12.0}, {"crank": 3.0})
    metrics = every_kind(p)
    constraints = [Constraint("g_min", low=0.4), Constraint("swing", high=2.0)]
    with use(Execution(backend=backend)):
        full = evaluate(mech, designs, poses, metrics, constraints)
        fused = evaluate_fused(mech, designs, poses, metrics, constraints)
    pd.testing.assert_frame_equal(fused, full, check_exact=True)
    status = full["status"]
    assert (status == "ok").any() and status.str.contains("do not solve").any()
    assert (status == "constraint on g_min not met").any()
    assert (full.loc[designs["A-B"] <= 0, "poses_failed"] == p).all()


def test_fused_equals_the_full_solve_with_pose_sets_and_held_drivers() -> None:
    mech = excavkin.load(excavkin.example_path("wheel_loader"))
    sketch = mech.sketch_values()
    # G is the tilt cylinder's pin: the held driver's value is each design's own
    par = mech.parameters
    bounds = {"G.x": (par["G.x"] - 0.05, par["G.x"] + 0.05), "G.y": (par["G.y"] - 0.1, par["G.y"])}
    designs = sample_designs(bounds, 300, "halton", 2)
    lift = sketch["lift_cyl"] + np.linspace(-0.5, 1.0, 40)
    poses = Poses({"lift_cyl": lift}, {}, {})
    tilt = Poses(
        {
            "tilt_cyl": sketch["tilt_cyl"] + np.linspace(-0.2, 0.2, 9),
            "lift_cyl": sketch["lift_cyl"],
        },
        {"tilt_cyl": 0.05},
        {},
    )
    metrics = [
        Metric("reach", "W.x", "max"),
        Metric("tilt_at_top", "bucket.angle", "last"),
        Metric("bucket_swing", "bucket.angle", "change", poses="tilt"),
        Metric("w_rate", "W.vy", "absmax", poses="tilt"),
    ]
    full = evaluate(mech, designs, poses, metrics, pose_sets={"tilt": tilt})
    fused = evaluate_fused(mech, designs, poses, metrics, pose_sets={"tilt": tilt})
    pd.testing.assert_frame_equal(fused, full, check_exact=True)
    assert full["status"].str.contains("do not solve").any()
    assert full["feasible"].any()


def test_a_plan_with_a_newton_group_or_loads_takes_the_full_solve() -> None:
    newton = excavkin.load(excavkin.example_path("crank_rocker_dead_centres"))
    fourbar = excavkin.load(excavkin.example_path("fourbar"))
    assert not fusable(newton) and not fusable(fourbar, "model") and fusable(fourbar)
    with pytest.raises(ValueError, match="Newton"):
        evaluate_fused(newton, {"A-B": np.array([0.1])}, Poses({}, {}, {}), [])
    designs = sample_designs({"A-B": (0.11, 0.13)}, 8, "halton", 0)
    poses = Poses({"crank": np.linspace(0, 6, 7)}, {"crank": 10.0}, {})
    metrics = [Metric("t", "crank.torque", "absmax")]
    got = evaluate_designs(fourbar, designs, poses, metrics, loads="model")
    want = evaluate(fourbar, designs, poses, metrics, loads="model")
    pd.testing.assert_frame_equal(got, want, check_exact=True)


def test_a_study_on_threads_equals_one_on_a_single_thread(tmp_path: Path) -> None:
    study = Study(
        model=excavkin.example_path("fourbar"),
        bounds={"A-B": (0.10, 0.14), "O4-B": (0.07, 0.11)},
        poses=Poses({"crank": np.linspace(0.0, 2 * np.pi, 50)}, {"crank": 31.4}, {}),
        metrics=tuple(every_kind(50)),
        samples=700,
    )
    kw = {"chunk_samples": 5000, "backend": "numpy"}
    one = run_study(study, tmp_path / "one.parquet", execution=Execution(workers=1), **kw)
    two = run_study(study, tmp_path / "two.parquet", execution=Execution(workers=2), **kw)
    pd.testing.assert_frame_equal(pd.read_parquet(two), pd.read_parquet(one), check_exact=True)


MODELS = [
    "arm_vector", "excavator", "mo100_hammer", "pasika_module", "rope_shovel", "slider_crank",
    "wheel_loader_tp",
]  # fmt: skip


@pytest.mark.parametrize("name", MODELS)
def test_fused_equals_the_full_solve_on_every_closed_form_example(name: str) -> None:
    mech = excavkin.load(excavkin.example_path(name))
    assert fusable(mech)
    par = mech.parameters
    # three dimensions, each ±3 % about its own value: some designs of some models build
    # no mechanism
    keys = [k for k in par if k.endswith(".x") or "-" in k][:3]
    bounds = {
        k: (par[k] - 0.03 * abs(par[k]) - 0.01, par[k] + 0.03 * abs(par[k]) + 0.01) for k in keys
    }
    designs = sample_designs(bounds, 50, "halton", 1)
    first = mech.inputs[0]
    at = mech.sketch_values()[first]
    poses = Poses({first: at + np.linspace(-0.2, 0.2, 30) * (abs(at) + 0.1)}, {first: 0.3}, {})
    columns = [c.name for c in mech.solve({}).columns][::7]
    ways = [how for how in REDUCTIONS if how != "sumsq"] * 5
    metrics = [
        Metric(f"m{i}", c, how) for i, (c, how) in enumerate(zip(columns, ways, strict=False))
    ]
    for backend in ("numpy", "numba"):
        with use(Execution(backend=backend)):
            full = evaluate(mech, designs, poses, metrics)
            fused = evaluate_fused(mech, designs, poses, metrics)
        pd.testing.assert_frame_equal(fused, full, check_exact=True)


@pytest.mark.parametrize(
    ("poses", "message"),
    [
        (Poses({"crankk": np.linspace(0.0, 1.0, 5)}, {}, {}), "unknown driver 'crankk'"),
        (Poses({"crank": np.linspace(0.0, 1.0, 5)}, {"crank": np.ones(4)}, {}), r"shape \(4,\)"),
        (Poses({"crank": np.ones((5, 2))}, {}, {}), r"shape \(5, 2\)"),
        (Poses({"crank": "30 deg"}, {}, {}), "numbers"),
    ],
)
def test_a_bad_pose_set_is_refused_naming_the_driver(poses: Poses, message: str) -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    metrics = [Metric("g", "B.transmission", "min")]
    with pytest.raises(InputError, match=message):
        evaluate_fused(mech, {"A-B": np.array([0.12, 0.125])}, poses, metrics)


@pytest.mark.parametrize(
    ("designs", "message"),
    [
        ({"A-X": np.array([0.12])}, "no parameter 'A-X'"),
        ({"A-B": np.array([0.12, 0.13]), "O4.x": np.array([0.1])}, "different lengths"),
        ({"A-B": np.ones((2, 2))}, "one number"),
        ({}, "different lengths"),
    ],
)
def test_bad_designs_are_refused_naming_the_parameter(designs: dict, message: str) -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    poses = Poses({"crank": np.linspace(0.0, 1.0, 5)}, {}, {})
    with pytest.raises(InputError, match=message):
        evaluate_fused(mech, designs, poses, [Metric("g", "B.transmission", "min")])
