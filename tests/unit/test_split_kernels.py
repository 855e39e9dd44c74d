"""Issue 28: a large model's kernels in passes compiled one by one. Cut small here (a pass of a
few statements), the forces kernel of a chain of four-bars (`excavkin.kinematics.split`) and
a study's kinematic kernel (`excavkin.kinematics.vectorise`, its designs' constants a column
each) give the whole kernel's numbers to the bit, flags included; the split sources are kept
on disk as any kernel is."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from excavkin import Gravity, Mechanism, backends, example_path, load
from excavkin.execution import Execution, use
from excavkin.kinematics import split, vectorise
from excavkin.kinetostatics import compiled as forces_kernel
from excavkin.studies import fused
from excavkin.studies.design_space import sample_designs
from excavkin.studies.fused import evaluate_fused
from excavkin.studies.metrics import Metric, Poses, evaluate
from tests.unit.test_large_plan_source import chain


def _forces(mech: Mechanism, n: int) -> list[np.ndarray]:
    t = np.sin(np.linspace(0.0, 6.0, n))
    q = {k: v + 0.3 * t for k, v in mech.sketch_values().items()}
    r = {k: np.full(n, 0.7) for k in q}
    kin = mech.solve(q, r, {k: np.full(n, 2.0) for k in q}, backend="numpy")
    f = mech.forces(kin, [Gravity()], backend="numba")
    return [kin.status.code, f.pin_force, f.driver_torque, f.singular]


@pytest.mark.parametrize("model", ["chain", "crank_rocker_dead_centres"])
def test_a_forces_kernel_cut_in_passes_gives_the_same_numbers(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, model: str
) -> None:
    """A chain of four-bars, and a model whose forces solve a dense block (its pivots' row
    swaps and its scale a branch each, names assigned again and again)."""
    monkeypatch.setenv("EXCAVKIN_CACHE_DIR", str(tmp_path))
    mech = Mechanism(chain(3)) if model == "chain" else load(example_path(model))
    whole = _forces(mech, 5000)  # more samples than a split kernel's scratch holds at a time
    texts: list[str] = []
    source = forces_kernel.source

    def spy(*args: object, **kw: object) -> tuple[str, list[object]]:
        out = source(*args, **kw)  # type: ignore[arg-type]
        texts.append(out[0])
        return out  # type: ignore[return-value]

    monkeypatch.setattr(forces_kernel, "source", spy)
    monkeypatch.setattr(split, "PASS", 40)
    split.split.cache_clear()
    cut = _forces(mech, 5000)
    text = split.split(texts[-1])
    tree = ast.parse(text)
    passes = [f.name for f in tree.body if isinstance(f, ast.FunctionDef)]
    assert len(passes) > 5 and passes[-1] == "kernel"  # passes, and the one that runs them
    assert "SB_[r_, 0] = sg" in text and "SF_[r_," in text  # a flag carried, and floats
    assert ("scale = 0.0" in text) == (model != "chain")
    assert split.split(text) == text  # (a kernel split is split no further)
    assert backends.is_cached(text)  # kept on disk: a later process loads it
    for a, b in zip(whole, cut, strict=True):
        np.testing.assert_array_equal(a, b)
    split.split.cache_clear()


def test_a_study_kernel_cut_in_passes_gives_the_same_table(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setenv("EXCAVKIN_CACHE_DIR", str(tmp_path))
    mech = load(example_path("fourbar"))
    p = 40
    bounds = {"A-B": (-0.01, 0.16), "O4-B": (0.05, 0.12)}
    designs = sample_designs(bounds, 300, "sobol", 1)  # some fail, some build nothing
    poses = Poses({"crank": np.linspace(0.0, 2 * np.pi, p)}, {"crank": 12.0}, {"crank": 3.0})
    metrics = [
        Metric("g_min", "B.transmission", "min"),
        Metric("swing", "rocker.angle", "change"),
        Metric("vy", "B.vy", "absmax"),
    ]
    texts: list[str] = []
    rows = fused.written_rows

    def spy(text: str) -> tuple[dict[tuple[str, tuple[int, ...]], int], int]:
        texts.append(text)
        return rows(text)

    monkeypatch.setattr(fused, "written_rows", spy)
    with use(Execution(backend="numba")):
        whole = evaluate_fused(mech, designs, poses, metrics, [])
        monkeypatch.setattr(vectorise, "PASS", 23)
        vectorise.vectorised.cache_clear()
        again = load(example_path("fourbar"))  # (a plan's kernel source is kept)
        cut = evaluate_fused(again, designs, poses, metrics, [])
        full = evaluate(mech, designs, poses, metrics, [])
    vectorise.vectorised.cache_clear()
    assert "def pass" not in texts[0] and "def pass5_(" in texts[-1]
    assert rows(texts[0])[0] == rows(texts[-1])[0]  # the same rows, kept or not
    pd.testing.assert_frame_equal(cut, whole, check_exact=True)
    pd.testing.assert_frame_equal(cut, full, check_exact=True)
    assert (whole["status"] != "ok").any()
