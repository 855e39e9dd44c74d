"""Issue 28: large models on every backend. A chain of 16 four-bars (34 points) compiles (its
vectorised kernel is one block of single assignments; before, numba's SSA pass raised
RecursionError on it) and gives NumPy's kinematics and forces; a 300-point chain solves, with
forces, in NumPy, and a compiled backend asked for it says in one message why it does not
compile it."""

from __future__ import annotations

import numpy as np
import pytest

from excavkin import Gravity, Mechanism
from excavkin.errors import InputError
from excavkin.kinematics import compiled
from tests.unit.test_large_plan_source import chain

FIELDS = ("positions", "velocities", "accelerations", "body_angle", "body_omega", "body_epsilon")


def _sweep(mech: Mechanism, n: int) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    q = np.pi / 2 + 0.05 * np.sin(np.linspace(0.0, 6.0, n))
    return {"crank": q}, {"crank": 0.4 + 0.1 * np.cos(np.linspace(0.0, 6.0, n))}


def _gap(a: np.ndarray, b: np.ndarray) -> float:
    scale = np.maximum(np.max(np.abs(b), axis=0), 1e-300)
    return float(np.max(np.abs(a - b) / scale))


def test_a_34_point_chain_compiles_to_numpys_numbers() -> None:
    mech = Mechanism(chain(16))
    assert len(mech.plan.points) == 34 <= compiled.COMPILE_POINTS
    q, r = _sweep(mech, 700)
    ref = mech.solve(q, r, backend="numpy")
    got = mech.solve(q, r, backend="numba")
    assert ref.status.all_ok and got.status.all_ok
    np.testing.assert_array_equal(got.positions, ref.positions)
    for field in FIELDS:  # the compiled arctangent's last bits
        assert _gap(getattr(got, field), getattr(ref, field)) <= 1e-14, field
    f_ref = mech.forces(ref, [Gravity()], backend="numpy")
    f_got = mech.forces(got, [Gravity()], backend="numba")
    for field in ("pin_force", "driver_torque"):
        assert _gap(getattr(f_got, field), getattr(f_ref, field)) <= 1e-12, field


def test_a_300_point_chain_solves_with_forces_and_compiled_backends_say_why_not() -> None:
    mech = Mechanism(chain(149))
    assert len(mech.plan.points) == 300
    q, r = _sweep(mech, 64)
    kin = mech.solve(q, r)  # auto: NumPy
    assert kin.status.all_ok
    forces = mech.forces(kin, [Gravity()])
    assert np.isfinite(forces.pin_force).all() and np.isfinite(forces.driver_torque).all()
    pb = forces.power_balance()  # the crank's power against gravity's and inertia's
    assert np.all(np.abs(pb.load) > 0.0) and np.max(pb.relative) <= 1e-9
    for run in (lambda b: mech.solve(q, r, backend=b), lambda b: mech.forces(kin, backend=b)):
        with pytest.raises(InputError) as err:
            run("numba")
        text = str(err.value)
        assert "300 points" in text and "NumPy" in text and "\n" not in text, text
        with pytest.raises(InputError) as err:  # no GPU here, or (simulated) its size
            run("cuda")
        assert "\n" not in str(err.value)
