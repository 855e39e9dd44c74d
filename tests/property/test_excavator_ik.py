"""Inverse kinematics of the example excavator: FK∘IK is the identity on reachable poses."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import excavkin
from excavkin.excavator.machine import Machine, forward, inverse
from excavkin.excavator.machine_file import load_machine


@pytest.fixture(scope="module")
def machine() -> Machine:
    return load_machine(excavkin.example_path("excavator_machine"))


def _random(machine: Machine, n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    lo, hi = machine.lengths_min, machine.lengths_max
    return lo + rng.random((n, 3)) * (hi - lo)


def test_fk_of_ik_is_identity_over_random_reachable_poses(machine: Machine) -> None:
    L = _random(machine, 3000, seed=11)
    pose = forward(machine, L)
    assert pose.ok.all()
    sol = inverse(machine, pose.tip, pose.bucket_angle)
    # the generating lengths are always among the valid solutions
    assert (sol.n_valid >= 1).all()
    err = np.abs(sol.lengths - L[:, None, :]).max(axis=2)
    assert np.all(np.min(np.where(sol.valid, err, np.inf), axis=1) <= 1e-9)
    # and every valid solution maps back onto the target
    for k in range(4):
        v = sol.valid[:, k]
        if not v.any():
            continue
        back = forward(machine, sol.lengths[v, k])
        np.testing.assert_allclose(back.tip, pose.tip[v], rtol=0, atol=1e-9)
        dbeta = np.angle(np.exp(1j * (back.bucket_angle - pose.bucket_angle[v])))
        np.testing.assert_allclose(dbeta, 0.0, atol=1e-12)


def test_unreachable_and_stroke_limits_are_reported(machine: Machine) -> None:
    far = inverse(machine, np.array([[25.0, 0.0]]), np.array([0.0]))
    assert not far.reachable.any() and far.n_valid[0] == 0
    assert np.isnan(far.lengths).all()
    # reachable geometrically with all four branches, one of them beyond the bucket stroke
    near = inverse(machine, np.array([[7.0, -1.5]]), np.array([-np.pi / 2]))
    assert near.reachable.all() and near.n_valid[0] == 1
    assert near.reachable.any()
    assert not near.within_stroke[near.reachable].all()


@settings(max_examples=40, deadline=None)
@given(u=st.tuples(*[st.floats(0.0, 1.0)] * 3))
def test_round_trip_hypothesis(u: tuple[float, float, float]) -> None:
    machine = load_machine(excavkin.example_path("excavator_machine"))
    L = machine.lengths_min + np.array(u) * (machine.lengths_max - machine.lengths_min)
    pose = forward(machine, L[None, :])
    sol = inverse(machine, pose.tip, pose.bucket_angle)
    best, has = sol.first_valid()
    assert has[0]
    np.testing.assert_allclose(forward(machine, best).tip, pose.tip, rtol=0, atol=1e-9)
