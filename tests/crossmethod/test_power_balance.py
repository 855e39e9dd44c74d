"""Power balance of the kinetostatic solution, and the solver against a dense LAPACK solve.

With the d'Alembert inertia included, ideal joints do no work, so at every sample

    Σ driver power = dT/dt − Σ load power,    dT/dt = Σ (m·a_S·v_S + J·ε·ω)

(the driver power is τ·(ω_body − ω_reference) for a rotary driver and f·(rate of length) for
a linear one). This uses the forces only through the drivers' efforts, the motion only through
velocities: an independent check of the whole equilibrium solution. Checked on every example
model with mass properties, at ≤ 1e-9 relative to the sum of the magnitudes of the power terms.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin.kinetostatics import (
    Gravity,
    PointForce,
    Torque,
    kinetic_energy,
    kinetic_energy_rate,
    solve_forces,
)
from excavkin.mechanism import Mechanism
from tests.conftest import EXAMPLES


def _mechanism_examples() -> list[str]:
    """Example files that are mechanism models with at least one body with a mass."""
    out = []
    for path in sorted(EXAMPLES.glob("*.toml")):
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        if "bodies" not in data or "model" in data:  # machine descriptions refer to a model
            continue
        if any(isinstance(b, dict) and "mass" in b for b in data["bodies"].values()):
            out.append(path.stem)
    return out


EXAMPLES_WITH_MASS = _mechanism_examples()


def test_examples_found() -> None:
    assert {"fourbar", "slider_crank"} <= set(EXAMPLES_WITH_MASS)


def _motion(mech: Mechanism, n: int = 241) -> tuple[dict, dict, dict, np.ndarray]:
    """A smooth motion in time around the sketch: every input moves, with rate and accel."""
    t = np.linspace(0.0, 1.0, n)
    values, rates, accels = {}, {}, {}
    for k, (name, q0) in enumerate(mech.sketch_values().items()):
        amp = 0.6 if mech.input_kind(name) == "angle" else 0.02 * mech.plan.scale
        w = 2.0 * np.pi * (0.7 + 0.3 * k)
        values[name] = q0 + amp * np.sin(w * t + 0.3 * k)
        rates[name] = amp * w * np.cos(w * t + 0.3 * k)
        accels[name] = -amp * w * w * np.sin(w * t + 0.3 * k)
    return values, rates, accels, t


def _extra_loads(mech: Mechanism) -> list:
    """A point force at the last point of every moving body and a couple on the first one."""
    out: list = [Gravity(9.81, (0.3, -1.0))]
    moving = [b for b in mech.model.bodies if not b.ground]
    for k, b in enumerate(moving):
        out.append(PointForce(f"f{k}", b.name, b.points[-1], (150.0 * (k + 1), -80.0 * k)))
    out.append(Torque("c0", moving[0].name, 12.5, mech.model.ground.name))
    return out


@pytest.mark.parametrize("name", EXAMPLES_WITH_MASS)
@pytest.mark.parametrize("extra", [False, True], ids=["model-loads", "extra-loads"])
def test_power_balance_examples(name: str, extra: bool) -> None:
    mech = excavkin.load(excavkin.example_path(name))
    values, rates, accels, t = _motion(mech)
    kin = mech.solve(values, rates, accels, time=t)
    assert kin.status.ok.sum() > 0.9 * len(kin)
    loads = _extra_loads(mech) if extra else [*mech.loads, Gravity()]
    res = mech.forces(kin, loads)
    pb = res.power_balance()
    ok = res.ok
    # a rope that would push under this generic motion and these loads is slack, never ok
    # (the synchronised crane's rope about its horizontal sketch); every other sample is
    assert np.array_equal(ok, kin.status.ok & ~res.singular & ~res.slack)
    assert not res.singular.any() and (not mech.model.ropes or ok.sum() > 0)
    assert ok.all() == kin.status.all_ok or (res.slack & kin.status.ok).any()
    assert np.all(pb.relative[ok] <= 1e-9), float(np.max(pb.relative[ok]))
    assert np.all(pb.scale[ok] > 0)


@pytest.mark.parametrize("name", EXAMPLES_WITH_MASS)
def test_kinetic_energy_rate_against_differences(name: str) -> None:
    """dT/dt from a_S·v_S and ε·ω against a central difference of T along the time law."""
    mech = excavkin.load(excavkin.example_path(name))
    values, rates, accels, t = _motion(mech, n=4001)
    kin = mech.solve(values, rates, accels, time=t)
    energy = kinetic_energy(kin)
    rate = kinetic_energy_rate(kin)
    h = t[1] - t[0]
    fd = (energy[2:] - energy[:-2]) / (2 * h)
    ok = kin.status.ok
    both = ok[2:] & ok[1:-1] & ok[:-2]
    assert both.sum() > 0.9 * both.size
    scale = float(np.abs(rate[ok]).max())
    assert_allclose(fd[both], rate[1:-1][both], rtol=0, atol=2e-4 * scale)


@pytest.mark.parametrize("name", EXAMPLES_WITH_MASS)
def test_sparse_elimination_matches_dense_lapack(name: str) -> None:
    """The compiled elimination against the full matrix solved per sample by LAPACK."""
    mech = excavkin.load(excavkin.example_path(name))
    values, rates, accels, t = _motion(mech, n=61)
    kin = mech.solve(values, rates, accels, time=t)
    loads = _extra_loads(mech)
    fast = solve_forces(kin, loads, system=mech.statics)
    dense = solve_forces(kin, loads, method="dense")
    scale = float(np.nanmax(np.abs(fast.pin_force)))
    assert_allclose(fast.pin_force, dense.pin_force, rtol=0, atol=1e-11 * scale)
    assert_allclose(fast.element_force, dense.element_force, rtol=0, atol=1e-11 * scale)
    assert_allclose(fast.slider_force, dense.slider_force, rtol=0, atol=1e-11 * scale)
    tscale = max(float(np.nanmax(np.abs(fast.driver_torque), initial=0.0)), 1e-300)
    assert_allclose(fast.driver_torque, dense.driver_torque, rtol=0, atol=1e-11 * tscale)


def test_power_balance_with_per_sample_and_callable_loads() -> None:
    """A digging-type resistance opposing a point's velocity, and a per-sample couple."""
    mech = excavkin.load(excavkin.example_path("slider_crank"))
    values, rates, accels, t = _motion(mech, n=181)
    kin = mech.solve(values, rates, accels, time=t)

    def resistance(res: excavkin.KinematicResult) -> np.ndarray:
        _, v, _ = res.point("C")
        speed = np.hypot(v[:, 0], v[:, 1])[:, None]
        return -2.0e3 * v / np.where(speed > 0, speed, 1.0)

    loads = [
        Gravity(),
        PointForce("resist", "piston", "C", resistance),
        Torque("var", "rod", 3.0 * np.sin(7 * t)),
    ]
    res = mech.forces(kin, loads)
    pb = res.power_balance()
    assert np.all(pb.relative <= 1e-9)
    # the resistance takes power out of the mechanism wherever the piston moves
    _, v, _ = kin.point("C")
    load_resist = np.sum(resistance(kin) * v, axis=1)
    assert np.all(load_resist <= 0.0)


def test_power_balance_dense_sweep_through_dead_centres() -> None:
    """200 001 crank angles of the crank-rocker, through both of the rocker's dead centres,
    where every net power term passes through zero together while the joint forces stay
    finite: the residual stays at round-off of the joint forces' powers."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    theta = np.linspace(0.0, 2.0 * np.pi, 200_001)
    kin = mech.solve({"crank": theta}, {"crank": 31.4}, {"crank": 100.0})
    res = mech.forces(kin, [Gravity(), PointForce("push", "coupler", "B", (5.0, -2.0))])
    pb = res.power_balance()
    assert res.ok.all()
    assert float(np.max(pb.relative)) <= 1e-12
