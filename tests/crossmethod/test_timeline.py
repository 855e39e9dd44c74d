"""Cross-method checks of the time-domain layer.

* velocities and accelerations of a run (exact, from the laws) vs central finite differences
  in time of its positions and velocities;
* the closed-form plan vs the generic Newton–Raphson solver over the same run;
* the one-sided limits used by the shock report vs solves at ``t_b ∓ h`` as ``h → 0``.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin.mechanism import Mechanism
from excavkin.motion import ConstantSpeedCrank, get_law
from excavkin.simulation.shocks import shock_report
from excavkin.simulation.timeline import simulate


@pytest.fixture(scope="module")
def module() -> Mechanism:
    return excavkin.load(excavkin.example_path("pasika_module"))


def _fd(mech, drives, t, column, h):
    """4th-order central difference in time of ``column`` at ``t``, shape (n,)."""
    vals = [np.asarray(simulate(mech, drives, t=t + k * h).column(column)) for k in (-2, -1, 1, 2)]
    return (vals[0] - 8.0 * vals[1] + 8.0 * vals[2] - vals[3]) / (12.0 * h)


@pytest.mark.parametrize("law", ["cycloidal", "4567", "cubic"])
def test_rates_are_time_derivatives(module, law):
    drives = {"cyl": get_law(law, 0.5, 5.0)}
    t = np.linspace(0.2, 4.8, 24)  # inside the motion, away from the breakpoints
    res = simulate(module, drives, t=t)
    h = 1e-3
    pairs = [
        ("A.x", "A.vx"),
        ("A.y", "A.vy"),
        ("A.vx", "A.ax"),
        ("A.vy", "A.ay"),
        ("rocker.omega", "rocker.epsilon"),
        ("cyl.omega", "cyl.epsilon"),
        ("cyl.value", "cyl.rate"),
        ("cyl.rate", "cyl.accel"),
    ]
    for pos, rate in pairs:
        exact = np.asarray(res.column(rate))
        scale = float(np.max(np.abs(exact)))
        assert_allclose(
            _fd(module, drives, t, pos, h),
            exact,
            rtol=0,
            atol=1e-8 * scale,
            err_msg=f"{law}: d({pos})/dt vs {rate}",
        )
    # angles: unwrap-free here (no wrap inside the stroke)
    assert_allclose(
        _fd(module, drives, t, "rocker.angle", h), res.column("rocker.omega"), rtol=0, atol=1e-9
    )


def test_crank_run_rates_are_time_derivatives():
    mech = excavkin.load(excavkin.example_path("fourbar"))
    drives = {"crank": ConstantSpeedCrank(31.416)}
    t = np.linspace(0.0, 0.2, 17)
    res = simulate(mech, drives, t=t)
    h = 1e-5
    for pos, rate in (("B.x", "B.vx"), ("B.vy", "B.ay"), ("rocker.omega", "rocker.epsilon")):
        exact = np.asarray(res.column(rate))
        assert_allclose(
            _fd(mech, drives, t, pos, h),
            exact,
            rtol=0,
            atol=1e-7 * float(np.max(np.abs(exact))),
            err_msg=pos,
        )


def test_closed_form_vs_newton(module):
    newton = Mechanism(module.model, method="newton")
    drives = {"cyl": get_law("modified-sine", 0.5, 5.0, start=0.5)}
    t = np.linspace(0.0, 6.0, 121)
    a, b = simulate(module, drives, t=t), simulate(newton, drives, t=t)
    assert a.status.all_ok and b.status.all_ok
    for col in ("A.x", "A.vy", "A.ax", "rocker.omega", "rocker.epsilon", "cyl.epsilon"):
        assert_allclose(a.column(col), b.column(col), rtol=1e-9, atol=1e-12, err_msg=col)


@pytest.mark.parametrize("law", ["cubic", "trapezoidal", "harmonic"])
def test_one_sided_limits_are_limits(module, law):
    """ε(t_b ∓ h) → the report's left/right limits linearly in h (jerk is finite)."""
    drives = {"cyl": get_law(law, 0.5, 5.0, start=1.0)}
    rep = shock_report(module, drives, samples=51)
    for tb in rep.times:
        for col in ("rocker.epsilon", "cyl.epsilon", "cyl.accel", "rocker.omega"):
            left, right = rep.limit(col, tb, "left"), rep.limit(col, tb, "right")
            errs = []
            for h in (1e-4, 1e-5):
                r = simulate(module, drives, t=[tb - h, tb + h])
                errs.append(abs(r.column(col)[0] - left) + abs(r.column(col)[1] - right))
            assert errs[1] <= max(0.2 * errs[0], 1e-13), (law, tb, col, errs)
