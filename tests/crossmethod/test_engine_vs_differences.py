"""Analytic velocities and accelerations against 8th-order central differences of positions,
and the closed-form plan against the Newton–Raphson fallback on the same mechanism."""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from excavkin.mechanism import Mechanism
from tests.conftest import EXAMPLES, assert_rel, fd_derivatives

CASES = {
    "fourbar": {"crank": (np.radians(np.linspace(0, 360, 73)), 3.0, -2.0)},
    "slider_crank": {"crank": (np.radians(np.linspace(0, 360, 73)), -4.0, 1.5)},
}


def _motion(mech: Mechanism, spec: dict[str, tuple[np.ndarray, float, float]]) -> tuple:
    values = {k: v for k, (v, _, _) in spec.items()}
    rates = {k: r for k, (_, r, _) in spec.items()}
    accels = {k: a for k, (_, _, a) in spec.items()}

    base = mech.solve(values).body_angle

    def at(t: float) -> np.ndarray:
        res = mech.solve({k: v + rates[k] * t + 0.5 * accels[k] * t * t for k, v in values.items()})
        # angles wrap at ±π: take them as continuous offsets from the t = 0 solution
        angles = base + np.angle(np.exp(1j * (res.body_angle - base)))
        return np.concatenate(
            [res.positions.reshape(len(res), -1), angles, res.element_length], axis=1
        )

    res = mech.solve(values, rates, accels)
    exact_v = np.concatenate(
        [res.velocities.reshape(len(res), -1), res.body_omega, res.element_rate], axis=1
    )
    exact_a = np.concatenate(
        [res.accelerations.reshape(len(res), -1), res.body_epsilon, res.element_accel], axis=1
    )
    return at, exact_v, exact_a


@pytest.mark.parametrize("name", sorted(CASES))
def test_rates_match_finite_differences(name: str) -> None:
    mech = excavkin.load(EXAMPLES / f"{name}.toml")
    at, exact_v, exact_a = _motion(mech, CASES[name])
    fd_v, fd_a = fd_derivatives(at, 2e-3)
    # body angles wrap at ±π: difference them continuously
    assert_rel(exact_v, fd_v, 1e-9)
    assert_rel(exact_a, fd_a, 1e-8)


@pytest.mark.parametrize("name", sorted(CASES))
def test_newton_fallback_equals_closed_form(name: str) -> None:
    model = excavkin.load(EXAMPLES / f"{name}.toml").model
    closed = Mechanism(model)
    newton = Mechanism(model, method="newton")
    assert not closed.plan.has_newton and newton.plan.has_newton
    spec = CASES[name]
    args = (
        {k: v for k, (v, _, _) in spec.items()},
        {k: r for k, (_, r, _) in spec.items()},
        {k: a for k, (_, _, a) in spec.items()},
    )
    a, b = closed.solve(*args), newton.solve(*args)
    assert a.status.all_ok and b.status.all_ok
    np.testing.assert_allclose(b.positions, a.positions, rtol=0, atol=1e-13)
    assert_rel(b.velocities, a.velocities, 1e-11)
    assert_rel(b.accelerations, a.accelerations, 1e-10)
