"""The wheel loader's design brief (docs/loader.md, "A design brief"): the built-in study
`wheel_loader_level_dump` finds a Z-bar linkage that keeps its bucket nearer level over the lift,
still dumps 45° at full lift and keeps its bell crank off the bucket's back; the model file it
writes back reproduces the optimum. Its figures are checked against the floor's angle and the
clearance computed here from the solved points (shapely for the distance), and the dump angle
against the loader wing's SAE J732 dimension of the written linkage."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from numpy.testing import assert_allclose

import excavkin
from excavkin.loader.dimensions import dimensions
from excavkin.loader.machine_file import load_machine
from excavkin.studies.metrics import evaluate
from excavkin.studies.optimize import optimize_study
from excavkin.studies.study_file import load_study

NAME = "wheel_loader_level_dump"
LIFT = {"lift_cyl": np.linspace(1.7811, 2.753, 25), "tilt_cyl": np.full(25, 1.6123)}
DUMP = {"lift_cyl": np.full(26, 2.753), "tilt_cyl": np.linspace(1.293, 1.793, 26)}
# the bucket's first two points B -> I stand this far ahead of its floor K -> W
OFFSET = np.arctan2(0.709 - 0.480, 1.998 - 2.050)


def point(res: Any, name: str) -> np.ndarray:
    return np.stack([res.column(f"{name}.x"), res.column(f"{name}.y")], axis=-1)


def floor_angle(res: Any) -> np.ndarray:
    """The floor's (heel K -> cutting edge W) angle to the horizontal at each pose."""
    k, w = point(res, "K"), point(res, "W")
    return np.asarray(np.arctan2(w[:, 1] - k[:, 1], w[:, 0] - k[:, 0]))


def figures(
    mech: excavkin.Mechanism, params: dict[str, float] | None = None
) -> tuple[float, float, float]:
    """(the floor's largest tilt from level over the lift, the largest dump angle at full lift,
    the least distance of the bell crank's lower leg E–H from the bucket's back B–K over the
    dump), from the points of two plain solves."""
    lift, dump = mech.solve(LIFT, params=params), mech.solve(DUMP, params=params)
    assert lift.status.ok.all() and dump.status.ok.all()
    e, h, b, k = (point(dump, n) for n in "EHBK")
    gap = min(
        shapely.LineString([e[i], h[i]]).distance(shapely.LineString([b[i], k[i]]))
        for i in range(len(e))
    )
    return (float(np.abs(floor_angle(lift)).max()), float(-floor_angle(dump).min()), gap)


def test_the_design_brief_finds_a_level_loader_that_dumps_45_degrees(tmp_path: Path) -> None:
    study = load_study(excavkin.example_path(NAME))
    assert set(study.sets) == {"lift", "dump"}
    mech = excavkin.load(study.model)
    at = {k: np.array([mech.parameters[k]]) for k in study.bounds}
    nominal = evaluate(mech, at, study.poses, study.metrics, study.constraints, None,
                       study.pose_sets)  # fmt: skip
    # the nominal linkage rolls back 26.4° over the lift, dumps 47.0° (docs/loader.md's
    # dimensions) and its bell crank comes within 25 mm of the bucket's back: infeasible
    level, dump, gap = figures(mech)
    assert_allclose([np.degrees(level), np.degrees(dump), gap], [26.39, 46.98, 0.0247],
                    atol=0.005)  # fmt: skip
    assert_allclose(nominal["level"][0], level, atol=1e-6)  # the target is OFFSET to 1e-6°
    assert_allclose(OFFSET - nominal["full_dump"][0], dump, rtol=1e-12)
    assert_allclose(nominal["crank_to_bucket"][0], gap, rtol=1e-9)
    assert not nominal["feasible"][0]
    assert nominal["status"][0] == "constraint on crank_to_bucket not met"

    best = optimize_study(NAME)
    assert best.feasible and best.objective == "level" and best.sense == "min"
    level_b, dump_b, gap_b = figures(mech, best.params)
    assert_allclose(best.metrics["level"], level_b, atol=1e-6)
    assert_allclose(best.metrics["crank_to_bucket"], gap_b, rtol=1e-9)
    assert dump_b >= np.radians(45.0) and gap_b >= 0.05
    assert level_b < level - np.radians(20.0)  # 26.39° -> 5.46°
    assert_allclose(np.degrees(best.value), 5.4588, atol=5e-4)
    for k, v in best.params.items():
        low, high = study.bounds[k]
        assert low <= v <= high

    out = best.write_model(tmp_path / "level.toml")
    written = excavkin.load(out)
    for k, v in best.params.items():
        assert_allclose(written.parameters[k], v, rtol=1e-15)
    own = replace(study, model=out)
    row = evaluate(written, {k: np.array([written.parameters[k]]) for k in study.bounds},
                   own.poses, own.metrics, own.constraints, own.loads, own.pose_sets)  # fmt: skip
    assert row["feasible"][0]
    for k, v in best.metrics.items():
        assert_allclose(row[k][0], v, rtol=1e-9)
    assert_allclose(figures(written), (level_b, dump_b, gap_b), rtol=1e-9)

    # the loader wing rates the written linkage: its SAE J732 dump angle at full lift is the
    # study's largest dump angle
    machine = tmp_path / "machine.toml"
    text = excavkin.example_path("wheel_loader_machine").read_text(encoding="utf-8")
    assert 'model = "wheel_loader.toml"' in text
    machine.write_text(text.replace('model = "wheel_loader.toml"', 'model = "level.toml"'),
                       encoding="utf-8")  # fmt: skip
    dims = dimensions(load_machine(machine))
    assert_allclose(dims["dump angle at full lift"], dump_b, rtol=1e-9)
