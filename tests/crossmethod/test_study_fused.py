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
from excavkin import backends
from excavkin.errors import InputError
from excavkin.execution import Execution, use
from excavkin.kinematics import precision
from excavkin.kinematics.solve import BLOCK
from excavkin.studies import fused as fused_module
from excavkin.studies.design_space import sample_designs
from excavkin.studies.fused import evaluate_designs, evaluate_fused, fusable
from excavkin.studies.metrics import (
    REDUCTIONS,
    Constraint,
    Metric,
    Poses,
    clearance_metric,
    evaluate,
    tabulate,
)
from excavkin.studies.reductions import CODES, reduce_designs
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


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_fused_equals_the_full_solve_with_pose_sets_and_held_drivers(backend: str) -> None:
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
    with use(Execution(backend=backend)):
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


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_a_study_on_threads_equals_one_on_a_single_thread(tmp_path: Path, backend: str) -> None:
    study = Study(
        model=excavkin.example_path("fourbar"),
        bounds={"A-B": (0.10, 0.14), "O4-B": (0.07, 0.11)},
        poses=Poses({"crank": np.linspace(0.0, 2 * np.pi, 50)}, {"crank": 31.4}, {}),
        metrics=tuple(every_kind(50)),
        samples=700,
    )
    kw = {"chunk_samples": 5000, "backend": backend}
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


class Spy:
    """Counts the calls of a module's function, and keeps their arguments."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch, module: object, name: str) -> None:
        self.calls: list[tuple[tuple[object, ...], dict[str, object]]] = []
        real = getattr(module, name)

        def spy(*args: object, **kwargs: object) -> object:
            self.calls.append((args, kwargs))
            return real(*args, **kwargs)

        monkeypatch.setattr(module, name, spy)


def test_the_compiled_study_checks_every_blocks_dead_positions_together(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Where numba solves, the study's kernel runs (each design's constants a column read by
    its poses), and the samples near a dead position of every block are checked in one
    precision check, each against its own block's scales: the table is the full solve's,
    to the bit, with poses that do not close, designs near dead centres and designs that
    build no mechanism."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    compiled = Spy(monkeypatch, fused_module, "_solve_set_compiled")
    checked = Spy(monkeypatch, precision, "check_picked")
    p = 61
    d = 3 * BLOCK // p + 50  # three blocks and a bit
    bounds = {"A-B": (-0.01, 0.16), "O4-B": (0.05, 0.12), "O4.x": (0.08, 0.13)}
    designs = sample_designs(bounds, d, "sobol", 7)
    poses = Poses({"crank": np.linspace(0.0, 2 * np.pi, p)}, {"crank": 5.0}, {})
    metrics = every_kind(p)
    with use(Execution(backend="numba", workers=2)):
        full = evaluate(mech, designs, poses, metrics)
        got = evaluate_fused(mech, designs, poses, metrics)
    pd.testing.assert_frame_equal(got, full, check_exact=True)
    assert len(compiled.calls) == 1
    assert len(checked.calls) == 1
    blocks = checked.calls[0][0][-1]
    assert isinstance(blocks, list) and len(blocks) == 4  # each block had samples near one
    assert full["status"].str.contains("do not solve").any()
    assert ((full["poses_failed"] > 0) & (full["poses_failed"] < p)).any()


@pytest.mark.parametrize("backend", ["numpy", "auto"])
def test_numpy_or_no_numba_takes_the_blocks_solve(
    backend: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``backend="numpy"`` never takes the compiled study, nor does ``"auto"`` where numba
    cannot be imported: the blocks are solved as a solve solves them, the same table."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    if backend == "auto":
        monkeypatch.setattr(backends.REGISTRY["numba"], "unavailable", lambda: "no numba here")
    compiled = Spy(monkeypatch, fused_module, "_solve_set_compiled")
    designs = sample_designs({"A-B": (0.08, 0.14), "O4-B": (0.07, 0.11)}, 400, "halton", 3)
    poses = Poses({"crank": np.linspace(0.0, 2 * np.pi, 40)}, {"crank": 3.0}, {})
    metrics = every_kind(40)
    with use(Execution(backend=backend)):
        full = evaluate(mech, designs, poses, metrics)
        got = evaluate_fused(mech, designs, poses, metrics)
    pd.testing.assert_frame_equal(got, full, check_exact=True)
    assert compiled.calls == []


@pytest.mark.parametrize("how", sorted(CODES))
def test_the_compiled_reductions_are_numpys_to_the_bit(how: str) -> None:
    """Each design's reduction in the compiled pass against the study table's NumPy one,
    for rows of every length up to past NumPy's pairwise blocks (its sums' order), values
    of many magnitudes, poses that did not solve, a design none of whose poses solved and
    NaN values at poses that did."""
    rng = np.random.default_rng(11)
    for p in [*range(1, 140), 255, 256, 257, 1000, 4099]:
        d = 6
        series = rng.standard_normal((d, p)) * 10.0 ** rng.uniform(-6, 6, (d, p))
        ok = rng.random((d, p)) > 0.3
        ok[0] = False  # no pose solved
        ok[1] = True
        series[2, rng.integers(0, p)] = np.nan  # a value NaN at a pose that solved
        target = tuple(rng.standard_normal(p)) if how in ("sumsq", "absmax") else None
        m = Metric("m", "c", how, target)  # type: ignore[arg-type]
        want = tabulate({"x": np.arange(d, dtype=float)}, {"c": series}, ok, [m])["m"]
        got = reduce_designs(series, ok, m)
        np.testing.assert_array_equal(got, want.to_numpy(), err_msg=f"{how}, {p} poses")


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
