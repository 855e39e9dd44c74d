"""Issue 28: large models on every backend. A chain of 16 four-bars (34 points) compiles (its
vectorised kernel is one block of single assignments; before, numba's SSA pass raised
RecursionError on it) and gives NumPy's kinematics and forces; a 300-point chain solves, with
forces, in NumPy, on the simulated GPU and, its kernels compiled in passes one by one
(minutes: marked slow, run by hand with ``-m slow``), with numba; a plan over
`excavkin.kinematics.compiled.COMPILE_POINTS` points is refused in one message."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from excavkin import Gravity, Mechanism
from excavkin.errors import InputError
from excavkin.kinematics import compiled
from tests.unit.test_large_plan_source import chain

FIELDS = ("positions", "velocities", "accelerations", "body_angle", "body_omega", "body_epsilon")
ROOT = Path(__file__).resolve().parents[2]


def _sweep(mech: Mechanism, n: int) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    q = np.pi / 2 + 0.05 * np.sin(np.linspace(0.0, 6.0, n))
    return {"crank": q}, {"crank": 0.4 + 0.1 * np.cos(np.linspace(0.0, 6.0, n))}


def _gap(a: np.ndarray, b: np.ndarray) -> float:
    scale = np.maximum(np.max(np.abs(b), axis=0), 1e-300)
    return float(np.max(np.abs(a - b) / scale))


def _agree(mech: Mechanism, n: int, backend: str) -> None:
    """The kinematics and the forces of ``backend`` against NumPy's."""
    q, r = _sweep(mech, n)
    ref = mech.solve(q, r, backend="numpy")
    got = mech.solve(q, r, backend=backend)
    assert ref.status.all_ok and got.status.all_ok
    np.testing.assert_array_equal(got.positions, ref.positions)
    for field in FIELDS:  # the compiled arctangent's last bits
        assert _gap(getattr(got, field), getattr(ref, field)) <= 1e-14, field
    f_ref = mech.forces(ref, [Gravity()], backend="numpy")
    f_got = mech.forces(got, [Gravity()], backend=backend)
    for field in ("pin_force", "driver_torque"):
        assert _gap(getattr(f_got, field), getattr(f_ref, field)) <= 1e-12, field


def test_a_34_point_chain_compiles_to_numpys_numbers() -> None:
    mech = Mechanism(chain(16))
    assert len(mech.plan.points) == 34 <= compiled.COMPILE_POINTS
    _agree(mech, 700, "numba")


def test_a_300_point_chain_solves_with_forces_in_numpy() -> None:
    mech = Mechanism(chain(149))
    assert len(mech.plan.points) == 300 <= compiled.COMPILE_POINTS
    q, r = _sweep(mech, 64)
    kin = mech.solve(q, r)  # auto: NumPy (not compiled unasked)
    assert kin.status.all_ok
    forces = mech.forces(kin, [Gravity()])
    assert np.isfinite(forces.pin_force).all() and np.isfinite(forces.driver_torque).all()
    pb = forces.power_balance()  # the crank's power against gravity's and inertia's
    assert np.all(np.abs(pb.load) > 0.0) and np.max(pb.relative) <= 1e-9


@pytest.mark.slow
def test_a_300_point_chain_compiles_to_numpys_numbers(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """Its kinematic and forces kernels, each compiled in passes (minutes the first time)."""
    monkeypatch.setenv("EXCAVKIN_CACHE_DIR", str(tmp_path))
    _agree(Mechanism(chain(149)), 3000, "numba")


SIMULATED = r"""
import json, sys
import numpy as np
from excavkin import Gravity, Mechanism
from tests.unit.test_large_plan_source import chain
mech = Mechanism(chain(149))
q = {"crank": np.pi / 2 + np.array([-0.05, 0.0, 0.04])}
r = {"crank": np.array([0.3, 0.4, 0.5])}
out = {}
for b in ("numpy", "cuda"):
    kin = mech.solve(q, r, backend=b)
    f = mech.forces(kin, [Gravity()], backend=b)
    out[b] = [kin.status.all_ok, kin.positions.tolist(), kin.body_omega.tolist(),
              f.pin_force.tolist(), f.driver_torque.tolist()]
print(json.dumps(out))
"""


def test_a_300_point_chain_solves_with_forces_on_the_simulated_gpu(tmp_path: Path) -> None:
    """numba's CUDA simulator runs the device kernels (the plain loops, one thread a sample),
    a few samples: NumPy's numbers."""
    env = {
        **os.environ,
        "NUMBA_ENABLE_CUDASIM": "1",
        "EXCAVKIN_CACHE_DIR": str(tmp_path / "kernels"),
        "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), str(ROOT)]),
    }
    done = subprocess.run(
        [sys.executable, "-c", SIMULATED], env=env, capture_output=True, text=True, timeout=900
    )
    assert done.returncode == 0, done.stderr[-3000:]
    got = json.loads(done.stdout.strip().splitlines()[-1])
    ref, gpu = got["numpy"], got["cuda"]
    assert ref[0] and gpu[0]
    np.testing.assert_array_equal(gpu[1], ref[1])
    for k in (2, 3, 4):
        assert _gap(np.array(gpu[k]), np.array(ref[k])) <= 1e-12, k


def test_a_plan_over_the_compiled_size_is_refused_in_one_message(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    mech = Mechanism(chain(149))
    monkeypatch.setattr(compiled, "COMPILE_POINTS", 299)
    q, r = _sweep(mech, 8)
    kin = mech.solve(q, r, backend="numpy")
    for run in (lambda b: mech.solve(q, r, backend=b), lambda b: mech.forces(kin, backend=b)):
        with pytest.raises(InputError) as err:
            run("numba")
        text = str(err.value)
        assert "300 points" in text and "NumPy" in text and "\n" not in text, text
