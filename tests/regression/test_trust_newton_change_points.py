"""Issue "Trust and the first hour", the generic solver at change points.

A kite (crank = ground = 0.4 m, coupler = rocker = 0.9 m) turned through a full turn of 3,610
samples from its sketch at crank 170.4°: the crank's end passes the rocker's pivot at 360°, a
change point. ``method="newton"`` lost 1,709 of the 3,610 samples (every one past the change
point) to "assembly branch changed", where the closed form goes on, and
``continuation="smooth"`` was refused for any plan with a Newton group. Now the generic solver
keeps the dyad inside its Newton group (B from A and O4) on its sketch side, or flips it at
the change point, as the closed form does: the same statuses, change points and values.
"""

from __future__ import annotations

import numpy as np
import pytest

from excavkin import Mechanism, Model
from excavkin.kinematics.kernels import Code
from tests.models import fourbar_model


def kite(a: float, b: float, degrees: float) -> Model:
    """Crank O2–A = ground O2–O4 = a, coupler A–B = rocker O4–B = b, crank at ``degrees``."""
    th = np.radians(degrees)
    A = a * np.array([np.cos(th), np.sin(th)])
    e = np.array([a, 0.0]) - A
    base = float(np.hypot(*e))
    u = e / base
    B = A + 0.5 * e + np.sqrt(b * b - 0.25 * base * base) * np.array([-u[1], u[0]])
    points = {"O2": (0.0, 0.0), "A": (float(A[0]), float(A[1])), "B": (float(B[0]), float(B[1]))}
    return fourbar_model({**points, "O4": (a, 0.0)}, "kite")


KITE = kite(0.4, 0.9, 170.4)


@pytest.mark.parametrize("continuation", ["side", "smooth"])
def test_a_kite_turned_by_the_generic_solver_loses_no_sample(continuation: str) -> None:
    closed, newton = Mechanism(KITE), Mechanism(KITE, method="newton")
    assert newton.plan.has_newton
    q = closed.sketch_values()["crank"] + np.radians(np.linspace(0.0, 360.0, 3610))
    r1 = closed.solve({"crank": q}, continuation=continuation)
    r2 = newton.solve({"crank": q}, continuation=continuation)
    assert not (r2.status.code == Code.BRANCH_CHANGED).any()
    np.testing.assert_array_equal(r2.status.code, r1.status.code)
    # the sample nearest the fold is marked by both: rates lose precision there
    assert (~r1.status.ok).sum() == 1 and r1.status.code[~r1.status.ok][0] == Code.IMPRECISE
    ((before, after),) = [(cp.before, cp.after) for cp in r1.change_points]
    assert np.degrees(q[before]) % 360 > 359.9 and np.degrees(q[after]) % 360 < 0.1
    want = [("B", ("A", "O4"), before, after, "jump", continuation)]
    got = [(c.point, c.partners, c.before, c.after, c.shape, c.continued) for c in r2.change_points]
    assert got == want
    ok = r1.status.ok
    np.testing.assert_allclose(r2.positions[ok], r1.positions[ok], rtol=0, atol=1e-12 * 0.9)
    # rates: round-off (1e-10 of the scale) plus the two solvers' own error estimates, which
    # bound each row's distance from the exact values near the fold
    est = np.nan_to_num(r1.error_estimate[ok]) + np.nan_to_num(r2.error_estimate[ok])
    for got_, want_ in ((r2.velocities, r1.velocities), (r2.accelerations, r1.accelerations)):
        off = np.max(np.abs(got_[ok] - want_[ok]), axis=(1, 2)) / np.max(np.abs(want_[ok]))
        assert np.all(off <= 1e-10 + est)
    # on the sketch's side B jumps at the change point (to its mirror image in A→O4); the
    # smooth continuation moves it on continuously
    b = r2.point("B")[0]
    jump = np.hypot(*(b[after] - b[before]))
    steps = np.hypot(*np.diff(b[ok], axis=0).T)
    if continuation == "side":
        assert jump > 1.0
    else:
        assert jump < 0.01 and steps.max() < 0.01


@pytest.mark.parametrize("continuation", ["side", "smooth"])
def test_streamed_in_parts_the_generic_solver_gives_the_whole(continuation: str) -> None:
    """Two turns (two change points) in parts of 977 samples: the same to the bit, change
    points included, as the whole sweep solved at once."""
    newton = Mechanism(KITE, method="newton")
    q = newton.sketch_values()["crank"] + np.radians(np.linspace(0.0, 720.0, 7220))
    whole = newton.solve({"crank": q}, continuation=continuation)
    parts = [
        p.result for p in newton.solve_stream({"crank": q}, continuation=continuation, size=977)
    ]
    assert len(parts) > 1
    for name in ("positions", "velocities", "accelerations"):
        joined = np.concatenate([getattr(r, name) for r in parts])
        np.testing.assert_array_equal(joined, getattr(whole, name))
    np.testing.assert_array_equal(np.concatenate([r.status.code for r in parts]), whole.status.code)
    assert [cp for r in parts for cp in r.change_points] == list(whole.change_points)
    assert len(whole.change_points) == 2
