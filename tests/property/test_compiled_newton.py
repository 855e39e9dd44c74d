"""Plans with Newton groups compiled (`excavkin.kinematics.compiled_newton`) against their
NumPy path, the reference: every column, status, failed step, error estimate and change point,
for every example solved by ``method="newton"``, a boom whose rope runs over a sheave (out to
where the rope leaves it), and triads drawn by hypothesis, poses out of reach among them."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import excavkin
from excavkin import Mechanism
from excavkin.kinematics import compiled_newton
from excavkin.kinematics.kernels import Code
from tests.crossmethod.test_rope_sheaves import boom
from tests.property.test_random_linkages import TRIAD, triad

EXAMPLES = ["fourbar", "slider_crank", "excavator", "rope_shovel", "pasika_module", "wheel_loader"]


def assert_same(a: excavkin.KinematicResult, b: excavkin.KinematicResult) -> None:
    """Equal to 1e-12 of each column's scale, or 1e-12 in SI units where a column is zero but
    for rounding (the two iterate to the same root from the same start, each to 1e-14 of the
    size), statuses and failed steps alike."""
    np.testing.assert_array_equal(a.status.code, b.status.code)
    np.testing.assert_array_equal(a.status.step, b.status.step)
    fa, fb = a.to_frame(), b.to_frame()
    assert list(fa.columns) == list(fb.columns)
    for col in fa.columns:
        if col == "status":
            continue
        x, y = fa[col].to_numpy(), fb[col].to_numpy()
        np.testing.assert_array_equal(np.isnan(x), np.isnan(y), err_msg=col)
        finite = np.isfinite(x)
        scale = max(np.max(np.abs(x[finite]), initial=0.0), 1.0)
        assert np.max(np.abs(x - y)[finite], initial=0.0) <= 1e-12 * scale, col
    np.testing.assert_array_equal(np.isnan(a.error_estimate), np.isnan(b.error_estimate))
    assert [(c.point, c.sample) for c in a.change_points] == [
        (c.point, c.sample) for c in b.change_points
    ]


def both(mech: Mechanism, q: dict[str, np.ndarray], **kw: object) -> None:
    rates = {k: 0.7 for k in q}
    accels = {k: -0.3 for k in q}
    a = mech.solve(q, rates=rates, accels=accels, backend="numpy", **kw)  # type: ignore[arg-type]
    b = mech.solve(q, rates=rates, accels=accels, backend="numba", **kw)  # type: ignore[arg-type]
    assert_same(a, b)
    return None


def sweep(mech: Mechanism, n: int, reach: float) -> dict[str, np.ndarray]:
    """Each input about its sketch value, far enough (``reach``) that some poses fail."""
    out = {}
    for k, v in mech.sketch_values().items():
        span = reach if mech.input_kind(k) == "angle" else 0.3 * reach * abs(v)
        out[k] = v + span * np.sin(np.linspace(0.0, 6.0, n) + len(k))
    return out


@pytest.mark.parametrize("name", EXAMPLES)
def test_examples_by_newton_compiled_as_in_numpy(name: str) -> None:
    mech = Mechanism(excavkin.load(excavkin.example_path(name)).model, method="newton")
    assert compiled_newton.supports(mech.plan)
    q = sweep(mech, 300, 1.0)
    both(mech, q)


def test_some_examples_fail_as_in_numpy() -> None:
    """The sweeps above reach poses that do not converge and poses out of reach: the test
    compares failures, not only solutions."""
    mech = Mechanism(excavkin.load(excavkin.example_path("excavator")).model, method="newton")
    res = mech.solve(sweep(mech, 300, 1.0), backend="numba")
    codes = set(np.unique(res.status.code))
    assert {Code.OK, Code.NO_CONVERGENCE, Code.OUT_OF_REACH} <= codes


def test_rope_over_a_sheave_compiled_as_in_numpy() -> None:
    """A rope over the boom's tip sheave: its length and its rates by the sheave's tangents;
    paid out far enough that the rope leaves the sheave or the boom cannot follow."""
    mech = Mechanism(boom(mass=False))
    assert mech.plan.has_newton
    theta = mech.plan.input_sketch[0] + np.linspace(-400.0, 400.0, 401)
    res = mech.solve({"hoist": theta}, backend="numba")
    assert res.status.ok.any() and not res.status.ok.all()
    both(mech, {"hoist": theta})


def test_the_triad_over_a_turn_compiled_as_in_numpy() -> None:
    mech = Mechanism(triad(TRIAD))
    q0 = mech.sketch_values()["crank"]
    both(mech, {"crank": q0 - np.pi + np.linspace(0.0, 2.0 * np.pi, 2001)})


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    moves=st.lists(
        st.tuples(st.floats(-0.25, 0.25), st.floats(-0.25, 0.25)), min_size=7, max_size=7
    ),
    angles=st.lists(st.floats(-7.0, 7.0), min_size=1, max_size=40),
)
def test_random_triads_compiled_as_in_numpy(
    moves: list[tuple[float, float]], angles: list[float]
) -> None:
    """Triads of drawn dimensions at drawn crank angles: some poses out of reach, some not
    converging, each with the NumPy path's status and numbers."""
    sketch = {
        k: (x + dx, y + dy) for (k, (x, y)), (dx, dy) in zip(TRIAD.items(), moves, strict=True)
    }
    try:
        mech = Mechanism(triad(sketch))
    except excavkin.errors.ExcavkinError:
        return  # a sketch that does not assemble: no mechanism to solve
    q0 = mech.sketch_values()["crank"]
    both(mech, {"crank": q0 + np.asarray(angles)})


def test_a_large_group_source_grows_linearly_and_parses() -> None:
    """Every moving point of a chain in one group (``method="newton"``): the source is one
    block of lines an equation (the LU a loop beyond `UNROLL` unknowns, no chain of ``and``),
    so it grows linearly with the chain and parses without recursion."""
    import ast

    from excavkin.step_kinds.newton_emit import UNROLL
    from tests.models import fourbar_chain

    sizes = {}
    for stages in (20, 40):
        mech = Mechanism(excavkin.loads(fourbar_chain(stages), "chain").model, method="newton")
        (group,) = [st for st in mech.plan.steps if type(st).__name__ == "NewtonGroup"]
        assert 2 * len(group.points) > UNROLL
        text = compiled_newton.source(mech.plan)
        ast.parse(text)
        assert " and math.isfinite(" not in text
        sizes[stages] = text.count("\n")
    assert sizes[40] < 2.2 * sizes[20]
