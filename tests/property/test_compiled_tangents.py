"""The compiled design sensitivities (the compiled plan differentiated forward) against the NumPy
dual-number path, the reference: every derivative column of every closed-form example, at the
nominal design and in families of designs, failing and near-dead samples alike (NaN where the
NumPy path has NaN); and against 8th-order central differences of whole compiled solves."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import excavkin
from excavkin.kinematics import compiled_tangents
from excavkin.structure.design import joint_offsets
from tests.models import parallelogram
from tests.property.test_compiled import CLOSED_FORM, sweep
from tests.property.test_designs import random_designs
from tests.property.test_sensitivities import WEIGHTS

#: derivatives held to this fraction of their kind's scale (seen: 3e-14 at most) …
TOL = 1e-13
#: … where every dyad and slider is further than this (sin γ) from its dead position; nearer,
#: round-off grows as the derivatives do, as 1/sin²γ: NEAR_TOL·(NEAR/sin γ)² (seen: 6e-13)
NEAR = 0.05
NEAR_TOL = 1e-12
#: columns of one kind share a scale (a y beside its x)
_GROUP = {"y": "x", "vy": "vx", "ay": "ax"}


def dimensions(mech: excavkin.Mechanism, rng: np.random.Generator, k: int = 10) -> list[str]:
    """``k`` parameters the kinematics depend on (coordinates, lengths, design variables, pin
    offsets), drawn at random, and one mass (whose kinematic derivatives are 0)."""
    kinematic = [p for p in mech.parameters if not p.endswith((".mass", ".inertia", ".Fx", ".Fy"))]
    kinematic = [p for p in kinematic if not p.endswith((".torque", ".center_of_mass.x"))]
    kinematic = [p for p in kinematic if not p.endswith(".center_of_mass.y")]
    pool = kinematic + list(joint_offsets(mech.model))
    names = list(rng.choice(pool, size=min(k - 1, len(pool)), replace=False))
    masses = [p for p in mech.parameters if p.endswith(".mass")]
    return names + masses[:1]


def _kind(col: str) -> str:
    """What a column measures, by its last part (``B.y`` and ``B.x`` alike); of a derivative
    column, what its column measures."""
    if col.startswith("d("):
        col = col[2 : col.index(")/d(")]
    kind = col.rsplit(".", 1)[-1]
    return _GROUP.get(kind, kind)


def _scales(mech: excavkin.Mechanism, table: Any, away: np.ndarray) -> dict[str, float]:
    """Each kind's scale of derivatives: the largest derivative of that kind away from dead
    positions, and no less than the kind's largest value over the plan's length scale."""
    values: dict[str, float] = {}
    derivs: dict[str, float] = {}
    for col in table.columns:
        if table[col].dtype.kind != "f":
            continue
        y = table[col].to_numpy()
        y = y[away & np.isfinite(y)] if col.startswith("d(") else y[np.isfinite(y)]
        top = float(np.max(np.abs(y), initial=0.0))
        own = derivs if col.startswith("d(") else values
        own[_kind(col)] = max(own.get(_kind(col), 0.0), top)
    return {k: max(v, values[k] / mech.plan.scale, 1e-300) for k, v in derivs.items()}


def assert_tangents_same(
    mech: excavkin.Mechanism, a: excavkin.KinematicResult, b: excavkin.KinematicResult
) -> int:
    """Every derivative column of ``a`` equals ``b``'s to :data:`TOL` of its kind's scale
    (:data:`NEAR_TOL`·(NEAR/sin γ)² near a dead position), with NaN and infinities where ``b``
    has them. Returns the number of finite derivatives compared."""
    fa, fb = a.to_frame(), b.to_frame()
    assert list(fa.columns) == list(fb.columns)
    # sin γ of the dyad or slider nearest its dead position, per sample
    trans = [c for c in fb.columns if c.endswith(".transmission") and not c.startswith("d(")]
    near = np.min([np.abs(np.sin(fb[c].to_numpy())) for c in trans], axis=0)
    near = np.nan_to_num(near, nan=1.0)  # a row not solved: its derivatives are NaN
    scales = _scales(mech, fb, near > NEAR)
    compared = 0
    for col in (c for c in fb.columns if c.startswith("d(")):
        x, y = fa[col].to_numpy(), fb[col].to_numpy()
        np.testing.assert_array_equal(np.isnan(x), np.isnan(y), err_msg=col)
        np.testing.assert_array_equal(x[np.isinf(y)], y[np.isinf(y)], err_msg=col)
        finite = np.isfinite(y)
        err = np.abs(x - y)[finite] / scales[_kind(col)]
        grow = np.maximum(NEAR / near[finite], 1.0) ** 2
        assert np.all(err <= np.where(grow > 1.0, NEAR_TOL * grow, TOL)), col
        compared += int(finite.sum())
    return compared


@pytest.mark.parametrize("name", CLOSED_FORM)
def test_each_example_compiled_tangents_equal_numpy(name: str) -> None:
    """Swept far enough that some samples cannot close, with one input that is no number."""
    mech = excavkin.load(excavkin.example_path(name))
    names = dimensions(mech, np.random.default_rng(len(name)))
    values = sweep(mech, 3001, 1.5)
    for v in values.values():
        v[1500] = np.nan
    args = dict(
        rates={k: 0.7 for k in values},
        accels={k: -0.3 for k in values},
        sensitivities=names,
        chunk=997,
    )
    fast = mech.solve(values, backend="numba", **args)
    ref = mech.solve(values, backend="numpy", **args)
    assert assert_tangents_same(mech, fast, ref) > 100 * len(names)
    assert fast.status.ok.sum() > 100 and not fast.status.all_ok  # failures compared too
    assert np.isnan(fast.sensitivity(fast.to_frame().columns[0], names[0])[1500])


@pytest.mark.parametrize("name", ["fourbar", "excavator", "rope_shovel", "arm_vector"])
def test_families_of_designs_compiled_tangents_equal_numpy(name: str) -> None:
    """Every third parameter given per sample; the derivatives by given and by nominal
    parameters; one design that builds no mechanism."""
    mech = excavkin.load(excavkin.example_path(name))
    rng = np.random.default_rng(11)
    values, params = random_designs(mech, rng, 2500)
    key = next(k for k in params if "-" in k or k.endswith(".x"))
    params[key][5] = -1.0 if "-" in key else np.nan
    names = dimensions(mech, rng, 6) + list(params)[:4]
    names = list(dict.fromkeys(names))
    args = dict(rates={k: 0.1 for k in values}, params=params, sensitivities=names)
    fast = mech.solve(values, backend="numba", **args)
    ref = mech.solve(values, backend="numpy", **args)
    assert assert_tangents_same(mech, fast, ref) > 1000 * len(names)
    assert np.isnan(fast.sensitivity(fast.to_frame().columns[0], names[0])[5])


def test_near_dead_and_smooth_continuation_alike() -> None:
    """The parallelogram through its change point: derivatives blow up alike near it, and a
    smooth continuation's per-sample branch signs are read alike."""
    mech = excavkin.Mechanism(parallelogram())
    th = np.pi / 2 - np.linspace(0.0, np.pi, 20001)
    names = [p for p in mech.parameters if not p.endswith((".mass", ".inertia"))][:6]
    for continuation in ("side", "smooth"):
        args = dict(sensitivities=names, continuation=continuation, chunk=1000)
        fast = mech.solve({"crank": th}, backend="numba", **args)  # type: ignore[arg-type]
        ref = mech.solve({"crank": th}, backend="numpy", **args)  # type: ignore[arg-type]
        assert assert_tangents_same(mech, fast, ref) > 1000


@pytest.mark.parametrize(
    ("name", "columns", "names"),
    [
        ("fourbar", ["B.vx", "B.transmission", "rocker.epsilon"], ["A-B", "O4.x"]),
        ("excavator", ["W.y", "bucket.epsilon", "K.transmission"], ["F.x", "N.y"]),
        ("rope_shovel", ["bucket.angle", "D.ay"], ["C-D", "D.x"]),
    ],
)
def test_against_central_differences(name: str, columns: list[str], names: list[str]) -> None:
    """8th-order central differences of whole compiled solves, to 1e-8 of each column's
    derivative scale."""
    mech = excavkin.load(excavkin.example_path(name))
    values = sweep(mech, 41, 0.3)
    rates = {k: 0.07 for k in values}
    accels = {k: 0.02 for k in values}
    res = mech.solve(values, rates, accels, sensitivities=names, backend="numba")
    assert res.status.all_ok
    for p in names:
        step = 3e-4 * mech.plan.scale
        solves = []
        for k in range(-4, 5):
            moved = {p: mech.parameters[p] + k * step}
            solves.append(mech.solve(values, rates, accels, params=moved, backend="numba"))
        for col in columns:
            fd = sum(w * s.column(col) for w, s in zip(WEIGHTS, solves, strict=True)) / step
            exact = res.sensitivity(col, p)
            scale = max(np.abs(fd).max(), np.abs(res.column(col)).max() / mech.plan.scale)
            assert np.abs(exact - fd).max() <= 1e-8 * scale, (col, p)


def test_source_depends_on_structure_only() -> None:
    """Two designs of one model share one tangent kernel, for any number of parameters."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    other = excavkin.load(excavkin.example_path("fourbar"))
    text = compiled_tangents.source(mech.plan)
    assert text == compiled_tangents.source(other.plan)
    assert "for p_ in range(m):" in text and "KT[" in text
