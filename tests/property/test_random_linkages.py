"""Random assemblable linkages: closure and the differentiated constraints hold at every sample.

Any sketch is assemblable by construction (its lengths are read off it), so hypothesis draws
sketches; the sweep then runs the driver around a full turn, and samples that cannot close are
marked — never silently NaN — while every solved sample satisfies the constraints.
"""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from excavkin.mechanism import Mechanism
from excavkin.model import Body, Model, RotaryDriver
from tests.conftest import fd_derivatives
from tests.property.sketches import not_collinear, spread, watt_sketch

coord = st.floats(-1.0, 1.0, allow_nan=False)
point = st.tuples(coord, coord)


def _check_constraints(mech: Mechanism, res, size: float) -> None:  # noqa: ANN001
    ok = res.status.ok
    assert ok.any(), "the sketch's own crank angle must solve"
    names = mech.plan.points
    x, v, a = res.positions[ok], res.velocities[ok], res.accelerations[ok]
    assert np.isfinite(x).all() and np.isfinite(v).all() and np.isfinite(a).all()
    assert (
        np.isnan(res.positions[~ok]).any(axis=(1, 2)).all() | (res.status.code[~ok] == 2).all()
        if (~ok).any()
        else True
    )
    for body in mech.model.bodies:
        shape = mech.plan.shapes[body.name]
        for i, p in enumerate(body.points):
            for q in body.points[i + 1 :]:
                ip, iq = names.index(p), names.index(q)
                r = x[:, ip] - x[:, iq]
                dv = v[:, ip] - v[:, iq]
                da = a[:, ip] - a[:, iq]
                np.testing.assert_allclose(
                    np.hypot(*r.T), shape.distance(p, q), rtol=0, atol=1e-12 * size
                )
                # (P−Q)·(Ṗ−Q̇) = 0 and (P−Q)·(P̈−Q̈) + |Ṗ−Q̇|² = 0 for a rigid pair
                vs = max(float(np.abs(v).max()), 1.0) * size
                np.testing.assert_allclose(np.sum(r * dv, axis=1), 0.0, atol=1e-10 * vs)
                acc_s = max(float(np.abs(a).max()), 1.0) * size
                np.testing.assert_allclose(
                    np.sum(r * da, axis=1) + np.sum(dv * dv, axis=1), 0.0, atol=1e-9 * acc_s
                )


def fourbar(o2, a, b, o4) -> Model:  # noqa: ANN001
    return Model(
        "random four-bar",
        {"O2": o2, "A": a, "B": b, "O4": o4},
        (
            Body("ground", ("O2", "O4"), ground=True),
            Body("crank", ("O2", "A")),
            Body("coupler", ("A", "B")),
            Body("rocker", ("O4", "B")),
        ),
        rotary=(RotaryDriver("crank", "crank", "O2", "ground"),),
    )


@settings(
    max_examples=60,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.filter_too_much],
)
@given(point, point, point, point, st.floats(0.2, 6.0), st.floats(-5, 5))
def test_random_fourbars(o2, a, b, o4, w, al) -> None:  # noqa: ANN001
    pts = [o2, a, b, o4]
    if not (spread(pts) and not_collinear(a, o4, b)):
        return
    mech = Mechanism(fourbar(o2, a, b, o4))
    q0 = mech.sketch_values()["crank"]
    th = q0 + np.linspace(-np.pi, np.pi, 181)
    res = mech.solve({"crank": th}, rates={"crank": w}, accels={"crank": al})
    _check_constraints(mech, res, 2.0)
    # failures are named, never silent: a failed sample has a reason
    for i in np.flatnonzero(~res.status.ok)[:3]:
        assert "dyad B" in res.status.message(int(i))


def watt_sixbar(p: dict[str, tuple[float, float]]) -> Model:
    return Model(
        "Watt II six-bar",
        p,
        (
            Body("ground", ("O2", "O4", "O6"), ground=True),
            Body("crank", ("O2", "A")),
            Body("coupler", ("A", "B")),
            Body("rocker", ("O4", "B", "C")),
            Body("link", ("C", "D")),
            Body("output", ("O6", "D")),
        ),
        rotary=(RotaryDriver("crank", "crank", "O2", "ground"),),
    )


@settings(max_examples=40, deadline=None, derandomize=True)
@given(st.lists(point, min_size=7, max_size=7), st.floats(0.2, 4.0))
def test_random_watt_sixbars(pts, w) -> None:  # noqa: ANN001
    p = watt_sketch(pts)
    if p is None:
        return
    mech = Mechanism(watt_sixbar(p))
    assert not mech.plan.has_newton
    q0 = mech.sketch_values()["crank"]
    res = mech.solve({"crank": q0 + np.linspace(-1.0, 1.0, 101)}, rates={"crank": w})
    _check_constraints(mech, res, 2.0)


def triad(p: dict[str, tuple[float, float]]) -> Model:
    """A class-III Assur group (triad) driven by a crank: no dyad closes it, Newton does."""
    return Model(
        "triad",
        p,
        (
            Body("ground", ("O1", "O2", "O3"), ground=True),
            Body("crank", ("O1", "A")),
            Body("l1", ("A", "B")),
            Body("l2", ("O2", "C")),
            Body("l3", ("O3", "D")),
            Body("tri", ("B", "C", "D")),
        ),
        rotary=(RotaryDriver("crank", "crank", "O1", "ground"),),
    )


TRIAD = {
    "O1": (0.0, 0.0),
    "A": (0.0, 0.3),
    "O2": (1.6, 0.0),
    "O3": (0.8, -0.9),
    "B": (0.6, 0.9),
    "C": (1.4, 1.0),
    "D": (1.3, 0.3),
}


def test_triad_needs_newton_and_is_exact() -> None:
    mech = Mechanism(triad(TRIAD))
    assert mech.plan.has_newton
    assert "newton   B, C, D together" in mech.plan.describe()
    q0 = mech.sketch_values()["crank"]
    th = q0 + np.linspace(-0.6, 0.6, 41)
    res = mech.solve({"crank": th}, rates={"crank": 1.7}, accels={"crank": -0.4})
    assert res.status.all_ok, res.status.summary()
    _check_constraints(mech, res, 2.0)

    base = mech.solve({"crank": th}).positions

    def at(t: float) -> np.ndarray:
        return mech.solve({"crank": th + 1.7 * t - 0.2 * t * t}).positions

    fd_v, fd_a = fd_derivatives(at, 1e-3)
    assert np.allclose(base, res.positions)
    np.testing.assert_allclose(res.velocities, fd_v, rtol=0, atol=1e-9 * np.abs(fd_v).max())
    np.testing.assert_allclose(res.accelerations, fd_a, rtol=0, atol=1e-8 * np.abs(fd_a).max())
