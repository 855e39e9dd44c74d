"""Issue 12: the generic solver holds a full turn.

Over random four-bars — Grashof crank-rockers, double-cranks and double-rockers, and
non-Grashof triple-rockers, either branch; change-point linkages aside —
``method="newton"`` solves every sample that the closed form solves and that the mechanism
can reach from its sketch by moving along the sweep (the closed form's run of solved samples
that holds the sketch, round the turn), on the same branch: positions to 1e-12 of the size,
rates to 1e-9 of their scale.
"""

from __future__ import annotations

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from excavkin import Mechanism, Model
from tests.models import fourbar_model


def fourbar(a: float, b: float, c: float, d: float, up: bool) -> Model | None:
    """Crank a from O2, coupler b, rocker c from O4 = (d, 0); sketched with the crank upright."""
    A = np.array([0.0, a])
    O4 = np.array([d, 0.0])
    e = O4 - A
    base = float(np.hypot(*e))
    k = (b * b - c * c + base * base) / (2 * base)
    h2 = b * b - k * k
    if h2 < (0.05 * min(a, b, c, d)) ** 2:  # the sketch must show a branch clearly
        return None
    u = e / base
    B = A + k * u + (1 if up else -1) * np.sqrt(h2) * np.array([-u[1], u[0]])
    return fourbar_model(
        {"O2": (0.0, 0.0), "A": (0.0, a), "B": (float(B[0]), float(B[1])), "O4": (d, 0.0)},
        "random four-bar",
    )


def sketch_run(ok: np.ndarray) -> np.ndarray:
    """The run of True that holds sample 0, continued round the turn (the last sample is 0)."""
    run = np.zeros_like(ok)
    if not ok[0]:
        return run
    stop = np.argmin(ok) if not ok.all() else len(ok)
    run[:stop] = True
    if not ok.all():
        back = len(ok) - np.argmin(ok[::-1])
        run[back:] = True
    return run


size = st.floats(0.2, 1.5)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(a=size, b=size, c=size, d=size, up=st.booleans())
def test_newton_follows_the_closed_form_round_a_turn(a, b, c, d, up) -> None:
    s, *mid, l = sorted((a, b, c, d))
    # change-point linkages (s + l = p + q: kites, parallelograms) fold at a change point,
    # where the continuation is a choice of its own (tested with the change points)
    assume(abs((s + l) - sum(mid)) > 0.02 * l)
    model = fourbar(a, b, c, d, up)
    assume(model is not None)
    closed, newton = Mechanism(model), Mechanism(model, method="newton")
    q = closed.sketch_values()["crank"] + np.radians(np.linspace(0.0, 360.0, 361))
    r1, r2 = closed.solve({"crank": q}), newton.solve({"crank": q})
    reach = sketch_run(r1.status.ok)
    # away from dead positions, where both solvers agree the rates are well conditioned
    mu = r1.transmission[:, 0]
    clear = reach & (np.minimum(mu, np.pi - mu) > np.radians(2.0))
    assert r2.status.ok[reach].all(), r2.summary()
    scale = max(a, b, c, d)
    np.testing.assert_allclose(r2.positions[reach], r1.positions[reach], rtol=0, atol=1e-12 * scale)
    for got, want in ((r2.velocities, r1.velocities), (r2.accelerations, r1.accelerations)):
        ref = np.max(np.abs(want[clear])) if clear.any() else 1.0
        np.testing.assert_allclose(got[clear], want[clear], rtol=0, atol=1e-9 * ref)
