"""The MO-100 hammer as a model file, solved by the general engine, against the paper's own
formulas (``excavkin.papers.mo100.reference``): position functions ψ, β (eqs 2–3) and the transfer
functions u31, u21, u31′, u21′ (the paper's lost eqs 4–5), to 1e-9 relative over the cycle."""

from __future__ import annotations

import numpy as np

import excavkin
from excavkin.papers.mo100 import reference as mo100
from tests.conftest import EXAMPLES, assert_rel


def _wrap(x: np.ndarray) -> np.ndarray:
    return np.angle(np.exp(1j * x))


def test_positions_and_transfer_functions_match_the_paper() -> None:
    mech = excavkin.load(EXAMPLES / "mo100_hammer.toml")
    # away from the change point (the reference interpolates within 1 mrad of it)
    phi = np.radians(np.linspace(0.5, 359.5, 1437))
    res = mech.solve({"crank": phi})  # unit rate: velocities are transfer functions
    assert res.status.all_ok, res.status.summary()
    psi, beta = mo100.position_functions(phi)
    tf = mo100.transfer_functions(phi)
    assert np.max(np.abs(_wrap(res.body("rocker")[0] - psi))) < 1e-12
    assert np.max(np.abs(_wrap(res.body("coupler")[0] - beta))) < 1e-12
    assert_rel(res.body("rocker")[1], tf.u31, 1e-9)
    assert_rel(res.body("coupler")[1], tf.u21, 1e-9)
    assert_rel(res.body("rocker")[2], tf.u31p, 1e-9)
    assert_rel(res.body("coupler")[2], tf.u21p, 1e-9)


def test_change_point_is_a_dead_position_and_its_neighbourhood_is_exact() -> None:
    """At φ = 0 the four joints are collinear: the engine flags the sample as a dead position
    of dyad C (its position is exact, its rates undefined). Near it the triangle B-C-D
    collapses: |BD| − (l2 − l3) ≈ 24·φ² mm, so Cartesian coordinates lose about
    1e-16/φ² of relative precision in u31 — any formulation on point coordinates does. At
    1 mrad the engine still agrees with the paper's half-angle forms to 1e-8, and u31 tends to
    the one-sided limits u31(0∓) = −3.8804 / +0.6804 (impact from above, rebound)."""
    mech = excavkin.load(EXAMPLES / "mo100_hammer.toml")
    res = mech.solve({"crank": np.array([0.0, 2 * np.pi])})
    assert all(res.status.message(i) == "dead position at dyad C (from B and D)" for i in (0, 1))
    np.testing.assert_allclose(res.point("C")[0], [[0.198, 0.0]] * 2, atol=1e-9)
    near = np.array([2 * np.pi - 1e-2, 2 * np.pi - 1e-3, 1e-3, 1e-2])
    side = mech.solve({"crank": near})
    assert side.status.all_ok
    tf = mo100.transfer_functions(near)
    np.testing.assert_allclose(side.body("rocker")[1], tf.u31, rtol=1e-8)
    before, after = mo100.impact_limits()
    np.testing.assert_allclose(side.body("rocker")[1][[1, 2]], [before, after], rtol=2e-3)
