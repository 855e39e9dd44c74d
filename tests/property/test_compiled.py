"""The compiled plan (one machine-code loop per plan structure) against the NumPy kernels, the
reference: every column, status, failed step, error estimate and change point, for every
closed-form example, families of designs, failing and near-dead samples, and a smooth
continuation."""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from excavkin import backends
from excavkin.kinematics import compiled
from tests.models import parallelogram
from tests.property.test_designs import random_designs

CLOSED_FORM = ["fourbar", "slider_crank", "excavator", "rope_shovel", "pasika_module", "arm_vector"]


def assert_same(a: excavkin.KinematicResult, b: excavkin.KinematicResult) -> None:
    """Equal to 1e-15 of each column's scale (the two paths differ only where a libm function
    and NumPy's own round differently), statuses and failed steps alike."""
    fa, fb = a.to_frame(), b.to_frame()
    assert list(fa.columns) == list(fb.columns)
    assert (fa["status"] == fb["status"]).all()
    np.testing.assert_array_equal(a.status.code, b.status.code)
    np.testing.assert_array_equal(a.status.step, b.status.step)
    for col in fa.columns:
        if col == "status":
            continue
        x, y = fa[col].to_numpy(), fb[col].to_numpy()
        np.testing.assert_array_equal(np.isnan(x), np.isnan(y), err_msg=col)
        np.testing.assert_array_equal(x[np.isinf(x)], y[np.isinf(x)], err_msg=col)
        finite = np.isfinite(x)
        scale = max(np.max(np.abs(x[finite]), initial=0.0), 1e-300)
        assert np.max(np.abs(x[finite] - y[finite]), initial=0.0) <= 1e-15 * scale, col
    np.testing.assert_array_equal(np.isnan(a.error_estimate), np.isnan(b.error_estimate))
    assert a.change_points == b.change_points


def sweep(mech: excavkin.Mechanism, n: int, reach: float) -> dict[str, np.ndarray]:
    """Every driver swept about its sketch value, far enough (``reach``) that some samples
    cannot close."""
    out = {}
    for k, v in mech.sketch_values().items():
        if mech.input_kind(k) == "angle":
            out[k] = v + np.linspace(-reach, reach, n)
        else:
            out[k] = v * (1 + np.linspace(-reach, reach, n) / 4)
    return out


@pytest.mark.parametrize("name", CLOSED_FORM)
def test_each_example_compiled_equals_numpy(name: str) -> None:
    mech = excavkin.load(excavkin.example_path(name))
    values = sweep(mech, 4001, 1.5)
    rates = {k: 0.7 for k in values}
    accels = {k: -0.3 for k in values}
    # the drivers' middle sample NaN, and one above: inputs that are no numbers
    for v in values.values():
        v[2000] = np.nan
    args = dict(rates=rates, accels=accels, chunk=997)
    fast = mech.solve(values, backend="numba", **args)
    ref = mech.solve(values, backend="numpy", **args)
    assert_same(fast, ref)
    assert fast.status.ok.sum() > 100  # the comparison is not of failures alone


@pytest.mark.parametrize("name", ["fourbar", "excavator", "rope_shovel"])
def test_families_of_designs_compiled_equal_numpy(name: str) -> None:
    mech = excavkin.load(excavkin.example_path(name))
    values, params = random_designs(mech, np.random.default_rng(7), 3000)
    # one design that builds no mechanism: a length that is not positive
    key = next(k for k in params if "-" in k or k.endswith(".x"))
    params[key][5] = -1.0 if "-" in key else np.nan
    args = dict(rates={k: 0.1 for k in values}, params=params, chunk=512)
    assert_same(
        mech.solve(values, backend="numba", **args), mech.solve(values, backend="numpy", **args)
    )


def test_near_dead_samples_are_checked_alike() -> None:
    """The parallelogram swept through its change point: the precision check re-solves the
    same samples, and the change points found (and passed over) are the same."""
    mech = excavkin.Mechanism(parallelogram())
    th = np.pi / 2 - np.linspace(0.0, np.pi, 20001)  # crank from upright to flat, through 0
    fast = mech.solve({"crank": th}, backend="numba", chunk=1000)
    ref = mech.solve({"crank": th}, backend="numpy", chunk=1000)
    assert_same(fast, ref)
    assert np.isfinite(ref.error_estimate).sum() > 10  # some samples were near dead
    assert ref.change_points  # and the fold was found
    smooth = mech.solve({"crank": th}, backend="numba", continuation="smooth")
    assert_same(smooth, mech.solve({"crank": th}, backend="numpy", continuation="smooth"))


def test_overflowing_rates_are_not_finite_alike() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    th = np.linspace(0.0, 2 * np.pi, 300)
    w = np.where(np.arange(300) % 7 == 0, 1e300, 3.0)
    fast = mech.solve({"crank": th}, rates={"crank": w}, backend="numba")
    ref = mech.solve({"crank": th}, rates={"crank": w}, backend="numpy")
    assert_same(fast, ref)
    assert (ref.status.labels() != "ok").sum() >= 43


def test_negative_driven_lengths_alike() -> None:
    mech = excavkin.load(excavkin.example_path("excavator"))
    values = sweep(mech, 500, 1.0)
    name = next(k for k in values if mech.input_kind(k) == "length")
    values[name][::50] = -values[name][::50]
    assert_same(mech.solve(values, backend="numba"), mech.solve(values, backend="numpy"))


def test_kernel_source_depends_on_structure_only() -> None:
    """Two designs of one model share one kernel; the constants table holds their dimensions."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    other = excavkin.load(excavkin.example_path("fourbar"))
    assert compiled.source(mech.plan) == compiled.source(other.plan)
    values = compiled.constants(mech.plan)
    table, stride = compiled.table(values, 10)
    assert stride == 0 and table.shape == (len(values), 1)
    values[0] = np.arange(10.0)
    table, stride = compiled.table(values, 10)
    assert stride == 1 and table.shape == (len(values), 10)
    np.testing.assert_array_equal(table[0], np.arange(10.0))


def test_a_newton_plan_has_kernels_of_its_own() -> None:
    """Not the closed-form kernel's: a plan with a Newton group has its own
    (`excavkin.kinematics.compiled_newton`, held to NumPy in test_compiled_newton.py)."""
    fb = excavkin.load(excavkin.example_path("fourbar"))
    newton = excavkin.Mechanism(fb.model, method="newton")
    assert not compiled.supports(newton.plan)
    with pytest.raises(TypeError, match="cannot be compiled"):
        compiled.source(newton.plan)
    q = {"crank": np.linspace(0.0, 1.0, 7)}
    assert_same(newton.solve(q, backend="numba"), newton.solve(q, backend="numpy"))


def test_a_cache_folder_that_cannot_be_written_compiles_in_memory(
    tmp_path, monkeypatch: pytest.MonkeyPatch
) -> None:  # type: ignore[no-untyped-def]
    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setenv("EXCAVKIN_CACHE_DIR", str(blocker / "kernels"))
    monkeypatch.setattr(backends, "_kernels", {})
    mech = excavkin.load(excavkin.example_path("pasika_module"))
    values = sweep(mech, 50, 0.5)
    assert_same(mech.solve(values, backend="numba"), mech.solve(values, backend="numpy"))
    assert not compiled.is_compiled(mech.plan) or backends._kernels


def test_fixed_points_rows_left_unwritten_only_when_asked() -> None:
    """The solve's kernel leaves a fixed point's velocity and acceleration rows as they come
    (the solve hands them in zeroed: pages never touched); the generator's default writes
    them. Every other value is the same."""
    from excavkin.kinematics.kernels import Chunk
    from excavkin.kinematics.result import Derived
    from excavkin.kinematics.vectorise import vectorised

    mech = excavkin.load(excavkin.example_path("fourbar"))
    plan, n = mech.plan, 200
    fixed = list(plan.steps[0].points)
    outs = []
    for write in (False, True):
        kernel = backends.kernel_of(vectorised(compiled.source(plan, write_at_rest=write), False))
        q = np.linspace(0.0, 6.0, n)[None, :]
        x, v, a = (np.full((len(plan.points), 2, n), 7.0) for _ in range(3))
        c = Chunk(x, v, a, q, np.ones((1, n)), np.zeros((1, n)), np.empty((1, n)),
                  np.zeros(n, np.int8), np.full(n, -1, np.int16), 1e-12, 1e-9, None)  # fmt: skip
        d = Derived.empty(plan, n)
        compiled.run(kernel, plan, c, d.body, d.element, np.empty(n), np.empty(n, np.int16))
        assert (v[fixed] == (0.0 if write else 7.0)).all() and (a[fixed] == v[fixed]).all()
        moving = [p for p in range(len(plan.points)) if p not in fixed]
        outs.append((x, v[moving], a[moving], d.body, c.trans))
    for one, other in zip(*outs, strict=True):
        np.testing.assert_array_equal(one, other)
    assert compiled.source(plan, write_at_rest=False) != compiled.source(plan)


@pytest.mark.parametrize("per_sample", [False, True])
@pytest.mark.parametrize("name", CLOSED_FORM)
def test_the_vectorised_loop_equals_the_scalar_loop_to_the_bit(name: str, per_sample: bool) -> None:
    """The kernel the solve runs (the generated loop rewritten over blocks, branch-free, with
    streaming stores) against the generated scalar loop it is made from: every output to the
    bit, over blocks and a partial one, in two chunks (the second starting mid-block), with
    samples that fail, an input that is no number, and a constant per sample."""
    from excavkin.kinematics.kernels import Chunk
    from excavkin.kinematics.result import Derived
    from excavkin.kinematics.vectorise import WIDTH, vectorised

    mech = excavkin.load(excavkin.example_path(name))
    plan, n = mech.plan, 3 * WIDTH + 17
    values = sweep(mech, n, 1.5)
    q = np.array([values[k] for k in plan.inputs])
    q[0, 5] = np.nan
    rng = np.random.default_rng(3)
    qd, qdd = rng.normal(size=q.shape), rng.normal(size=q.shape)
    k, stride = compiled.table(compiled.constants(plan), 1)
    if per_sample:  # every dimension moved a little, sample by sample (a dyad's side kept)
        k, stride = k * (1 + 1e-3 * rng.uniform(-1, 1, (k.shape[0], n))), 1
    status = np.zeros(n, np.int8)
    status[7] = 5  # a sample refused before the loop keeps its status
    outputs = []
    for vector in (False, True):
        x, v, a = (np.zeros((len(plan.points), 2, n)) for _ in range(3))
        trans = np.zeros((len(plan.transmissions), n))
        d = Derived.empty(plan, n)
        st, failed = status.copy(), np.full(n, -1, np.int16)
        near, near_step = np.zeros(n), np.zeros(n, np.int16)
        out = (x, v, a, trans, d.body, d.element, st, failed, 1e-10, 1e-7, near, near_step)
        text = compiled.source(plan, write_at_rest=False)
        if not vector:
            backends.kernel_of(text)(q, qd, qdd, k, stride, *out)
        else:
            kernel = backends.kernel_of(vectorised(text, per_sample))
            for part in (slice(0, 300), slice(300, n)):
                kk = k[:, part] if stride else k
                c = Chunk(x, v, a, q[:, part], qd[:, part], qdd[:, part], trans, st, failed,
                          1e-10, 1e-7)  # fmt: skip
                compiled.run_table(kernel, (kk, stride), c, d.body, d.element, near, near_step,
                                   part.start)  # fmt: skip
        outputs.append((x, v, a, trans, d.body, d.element, st, failed, near, near_step))
    assert set(np.unique(outputs[0][6])) - {0, 5}, "no sample failed: the test says little"
    for one, other in zip(*outputs, strict=True):
        np.testing.assert_array_equal(one, other)


def test_a_kernel_for_one_design_refuses_a_family() -> None:
    from excavkin.kinematics.kernels import Chunk
    from excavkin.kinematics.result import Derived

    plan, n = excavkin.load(excavkin.example_path("fourbar")).plan, 10
    kernel = compiled.compile_plan(plan, per_sample=False)
    x, v, a = (np.zeros((len(plan.points), 2, n)) for _ in range(3))
    k = np.repeat(compiled.table(compiled.constants(plan), 1)[0], n, axis=1)
    q = np.zeros((1, n))
    c = Chunk(x, v, a, q, q, q, np.zeros((1, n)), np.zeros(n, np.int8),
              np.full(n, -1, np.int16), 1e-10, 1e-7)  # fmt: skip
    d = Derived.empty(plan, n)
    with pytest.raises(ValueError, match="one design"):
        compiled.run_table(kernel, (k, 1), c, d.body, d.element, np.zeros(n),
                           np.zeros(n, np.int16))  # fmt: skip
