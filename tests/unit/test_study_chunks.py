"""A study's chunks: their default size (the fused evaluation's, or the full solve's, the
same on every machine), a resumed run that keeps no part of other chunks, the cores shared
among fewer chunks than cores, and each design's status made from a few texts."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import excavkin
from excavkin.execution import Execution
from excavkin.studies import study as study_module
from excavkin.studies.metrics import Constraint, Metric, Poses, tabulate_sets
from excavkin.studies.study import (
    CHUNK_SAMPLES,
    FUSED_CHUNK_SAMPLES,
    Study,
    chunks,
    default_chunk_samples,
    run_study,
)


def fourbar_study(samples: int, loads: str | None = None, poses: int = 40) -> Study:
    gamma = Metric("g", "B.transmission", "min")
    metric = Metric("t", "crank.torque", "absmax") if loads else gamma
    return Study(
        model=Path(excavkin.example_path("fourbar")),
        bounds={"A-B": (0.10, 0.14), "O4-B": (0.07, 0.11)},
        poses=Poses({"crank": np.linspace(0.0, 2 * np.pi, poses)}, {"crank": 31.4}, {}),
        metrics=(metric, Metric("w", "rocker.omega", "absmax")) if not loads else (metric,),
        samples=samples,
        loads=loads,
    )


def test_a_fused_study_takes_larger_chunks_than_the_full_solve() -> None:
    fused, full = fourbar_study(100_000), fourbar_study(100_000, loads="model")
    assert fused.chunk_samples() == default_chunk_samples(fused) == FUSED_CHUNK_SAMPLES
    assert full.chunk_samples() == default_chunk_samples(full) == CHUNK_SAMPLES
    assert FUSED_CHUNK_SAMPLES > CHUNK_SAMPLES
    # a whole number of designs a chunk, every design once, in order
    for study, size in ((fused, FUSED_CHUNK_SAMPLES), (full, CHUNK_SAMPLES)):
        spans = chunks(study)
        assert spans == chunks(study, size)
        assert spans[0] == (0, size // 40)
        assert [s for s, _ in spans[1:]] == [e for _, e in spans[:-1]]
        assert spans[-1][1] == 100_000
    # the size does not depend on the machine's cores
    assert chunks(fused) == chunks(fused, None)


def test_a_run_with_other_chunks_starts_anew(tmp_path: Path) -> None:
    """The parts of an interrupted run with other chunks overlap this run's designs: they
    are not kept (the table is a fresh run's, every design once)."""
    study = fourbar_study(60)
    target = tmp_path / "out.parquet"
    done: list[int] = []

    def stop(d: int, total: int) -> None:
        done.append(d)
        if len(done) == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_study(study, target, chunk_samples=7 * 40, progress=stop)
    assert len(list((tmp_path / ".out.parquet.parts").glob("part-*.parquet"))) == 2
    got = run_study(study, target, chunk_samples=11 * 40)
    fresh = run_study(study, tmp_path / "fresh.parquet", chunk_samples=11 * 40)
    a, b = pd.read_parquet(got), pd.read_parquet(fresh)
    assert a["design"].tolist() == list(range(60))
    pd.testing.assert_frame_equal(a, b, check_exact=True)


def test_fewer_chunks_than_cores_share_the_cores(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Two chunks on four threads: each chunk's blocks on two of them; the table is the one
    of a single thread, to the bit."""
    study = fourbar_study(300)
    seen: list[int | None] = []
    real = study_module.evaluate_part

    def spy(subject: object, start: int, stop: int, execution: Execution | None = None) -> object:
        seen.append(None if execution is None else execution.workers)
        return real(subject, start, stop, execution)  # type: ignore[arg-type]

    monkeypatch.setattr(study_module, "evaluate_part", spy)
    kw = {"chunk_samples": 150 * 40, "backend": "numba"}
    four = run_study(study, tmp_path / "four.parquet", execution=Execution(workers=4), **kw)
    assert seen == [2, 2]
    one = run_study(study, tmp_path / "one.parquet", execution=Execution(workers=1), **kw)
    pd.testing.assert_frame_equal(pd.read_parquet(four), pd.read_parquet(one), check_exact=True)


def test_each_designs_status_is_its_own_text() -> None:
    """The status column, made from a few texts, against each design's text made alone:
    the first set whose poses fail (their count), else the first constraint not met, else
    ok."""
    rng = np.random.default_rng(4)
    d = 400
    oks = {None: rng.random((d, 6)) > 0.04, "reach": rng.random((d, 5)) > 0.06}
    metrics = [Metric("a", "x", "max"), Metric("b", "y", "min", poses="reach")]
    series = {metrics[0].key: rng.random((d, 6)), metrics[1].key: rng.random((d, 5))}
    constraints = (Constraint("a", 0.5, None), Constraint("b", None, 0.3))
    frame = tabulate_sets({"p": rng.random(d)}, series, oks, metrics, constraints)
    want = []
    for i in range(d):
        miss = {k: int((~ok[i]).sum()) for k, ok in oks.items()}
        a, b = frame["a"][i], frame["b"][i]
        if miss[None]:
            want.append(f"{miss[None]} of 6 poses do not solve")
        elif miss["reach"]:
            want.append(f"{miss['reach']} of 5 poses of set 'reach' do not solve")
        elif not a >= 0.5:
            want.append("constraint on a not met")
        elif not b <= 0.3:
            want.append("constraint on b not met")
        else:
            want.append("ok")
    assert frame["status"].tolist() == want
    assert len(set(want)) > 5
    assert frame["status"].dtype == pd.Series(np.array(["ok"])).dtype
    assert (frame["feasible"] == (frame["status"] == "ok")).all()


def test_a_chunks_arrays_are_kept_for_the_next_and_its_table_is_the_same() -> None:
    """The compiled path's chunk-sized arrays, given back after a chunk's table is made, are
    the next chunk's (written again in place): each chunk's table is the one it has alone,
    to the bit, a chunk of another size and one with pose sets between them."""
    from excavkin.execution import use
    from excavkin.studies import fused
    from excavkin.studies.design_space import sample_designs
    from excavkin.studies.metrics import evaluate

    mech = excavkin.load(excavkin.example_path("fourbar"))
    bounds = {"A-B": (0.0, 0.16), "O4-B": (0.05, 0.12)}
    first, other = (sample_designs(bounds, n, "sobol", seed) for n, seed in ((300, 1), (170, 2)))
    poses = Poses({"crank": np.linspace(0.0, 2 * np.pi, 30)}, {"crank": 5.0}, {})
    sets = {"b": Poses({"crank": np.linspace(0.0, 1.0, 7)}, {}, {})}
    metrics = [Metric("g", "B.transmission", "min"), Metric("w", "rocker.omega", "max")]
    metrics.append(Metric("a", "rocker.angle", "change", poses="b"))
    with use(Execution(backend="numba", workers=1)):
        fused._spare.clear()
        alone = evaluate(mech, first, poses, metrics, pose_sets=sets)
        got = fused.evaluate_fused(mech, first, poses, metrics, pose_sets=sets)
        kept = {id(a) for a in fused._spare}
        assert len(kept) == 9  # two sets: inputs, statuses, oks, and a series per metric
        between = fused.evaluate_fused(mech, other, poses, metrics, pose_sets=sets)
        assert {id(a) for a in fused._spare} == kept  # (170 designs: 300's arrays serve)
        again = fused.evaluate_fused(mech, first, poses, metrics, pose_sets=sets)
        assert {id(a) for a in fused._spare} == kept
        between_alone = evaluate(mech, other, poses, metrics, pose_sets=sets)
    pd.testing.assert_frame_equal(got, alone, check_exact=True)
    pd.testing.assert_frame_equal(again, alone, check_exact=True)
    pd.testing.assert_frame_equal(between, between_alone, check_exact=True)


def test_a_chunks_columns_make_the_part_its_frame_makes() -> None:
    """A chunk's columns (`Study.chunk_columns`) make the frame `Study.evaluate_chunk`
    gives (the designs' table, its ``design`` first) and, under the schema made once,
    the Arrow table its frame makes, metadata included — for the fused evaluation and the
    full solve, chunks with failing poses and NaN metrics among them."""
    import pyarrow as pa

    from excavkin.studies.fused import evaluate_designs
    from excavkin.studies.study import _mechanism, part_table, sample_designs

    for study in (fourbar_study(90, poses=30), fourbar_study(70, loads="model", poses=30)):
        # a coupler of no length or less: designs that build no mechanism, NaN metrics
        wide = dataclass_replace(study, bounds={"A-B": (-0.05, 0.16), "O4-B": (0.05, 0.12)})
        mech = _mechanism(wide.model)
        seen = []
        for start, stop in ((0, 30), (30, 60), (60, wide.designs)):
            columns = wide.chunk_columns(start, stop)
            frame = wide.evaluate_chunk(start, stop)
            part = sample_designs(wide.bounds, wide.samples, wide.method, wide.seed, (start, stop))
            alone = evaluate_designs(
                mech, part, wide.poses, wide.metrics, wide.constraints, wide.loads
            )
            alone.insert(0, "design", np.arange(start, stop))
            pd.testing.assert_frame_equal(frame, alone, check_exact=True)
            pd.testing.assert_frame_equal(pd.DataFrame(columns), frame, check_exact=True)
            want = pa.Table.from_pandas(frame, preserve_index=False)
            assert part_table(columns).equals(want, check_metadata=True)
            assert part_table(frame).equals(want, check_metadata=True)
            seen.append(frame)
        every = pd.concat(seen)
        assert (every["status"] != "ok").any() and every.iloc[:, 3].isna().any()


def dataclass_replace(study: Study, **changes: object) -> Study:
    import dataclasses

    return dataclasses.replace(study, **changes)  # type: ignore[arg-type]


@pytest.mark.filterwarnings("ignore:.*balance properties of Sobol:UserWarning")
def test_a_chunks_sobol_points_from_a_kept_engine_are_a_new_ones() -> None:
    """The Sobol' engine a chunk gives back, taken again where it stopped (skipped on) or
    reset, makes the next chunk's points as a new engine would: every part of the sequence,
    from its start or skipped to, in any order."""
    from scipy.stats import qmc

    from excavkin.studies import design_space
    from excavkin.studies.design_space import sample_designs

    bounds = {"a": (0.0, 1.0), "b": (-2.0, 3.0), "c": (10.0, 11.0)}
    design_space._engines.clear()
    for start, stop in ((0, 100), (100, 333), (0, 7), (5000, 9000), (333, 334), (0, 100)):
        got = sample_designs(bounds, 9000, "sobol", 5, (start, stop))
        engine = qmc.Sobol(3, scramble=True, seed=5)
        if start:
            engine.fast_forward(start)
        want = qmc.scale(engine.random(stop - start), [0.0, -2.0, 10.0], [1.0, 3.0, 11.0])
        for j, name in enumerate(bounds):
            np.testing.assert_array_equal(got[name], want[:, j])
    assert len(design_space._engines[(3, 5)]) == 1  # one engine, taken and given back
    assert design_space._engines[(3, 5)][0].num_generated == 100  # kept where it stopped


def test_a_chunk_in_order_takes_the_sobol_engine_where_the_one_before_stopped(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Chunks drawn in order skip nothing: each takes the engine the chunk before gave back,
    at its first design (skipping from the sequence's start would cost each chunk a step
    for every design before it)."""
    from scipy.stats import qmc

    from excavkin.studies import design_space
    from excavkin.studies.design_space import sample_designs

    bounds = {"a": (0.0, 1.0), "b": (-2.0, 3.0)}
    design_space._engines.clear()
    whole = sample_designs(bounds, 4096, "sobol", 9)
    design_space._engines.clear()
    skipped: list[int] = []
    real = qmc.Sobol.fast_forward

    def counted(self: qmc.Sobol, n: int) -> qmc.Sobol:
        skipped.append(n)
        return real(self, n)

    monkeypatch.setattr(qmc.Sobol, "fast_forward", counted)
    parts = [sample_designs(bounds, 4096, "sobol", 9, (s, s + 512)) for s in range(0, 4096, 512)]
    assert skipped == []
    for name in bounds:
        np.testing.assert_array_equal(np.concatenate([p[name] for p in parts]), whole[name])
