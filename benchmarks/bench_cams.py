"""A disc cam's kinematics and forces compiled against NumPy, as ratios measured in one run.

Run: ``python benchmarks/bench_cams.py [N]`` (default N = 2·10⁵ samples over turns of the
camshaft, with rates and accelerations). The model is the tests' disc cam lifting a roller
follower along its guide by a lift table (``tests/reference/data/disc_cam.toml``). Prints, for
``backend="numpy"`` and ``backend="numba"`` (the kernel compiled before timing): the full
kinematic state and the forces under gravity, ns a sample, best of several repeats, and the
ratios; the two backends' largest difference is checked first.

Not a test: machines differ; the ratios are what is tracked.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from timing import best_of

import excavkin
from excavkin.kinetostatics import Gravity

MODEL = Path(__file__).resolve().parents[1] / "tests" / "reference" / "data" / "disc_cam.toml"


def main(n: int) -> None:
    mech = excavkin.load(MODEL)
    theta = np.linspace(0.0, 40.0 * np.pi, n)  # twenty turns
    values, rates, accels = {"shaft": theta}, {"shaft": np.full(n, 30.0)}, {"shaft": np.ones(n)}
    loads = [*mech.loads] if any(isinstance(x, Gravity) for x in mech.loads) else [Gravity()]
    results = {}
    for backend in ("numpy", "numba"):  # compiled before timing, and checked alike
        kin = mech.solve(values, rates, accels, backend=backend)
        results[backend] = (kin, mech.forces(kin, loads, backend=backend))
    (k0, f0), (k1, f1) = results["numpy"], results["numba"]
    t0, t1 = f0.torque("shaft"), f1.torque("shaft")
    diff = max(
        float(np.max(np.abs(k0.positions - k1.positions))),
        float(np.max(np.abs(t0 - t1)) / np.max(np.abs(t0))),
    )
    print(f"disc cam, {n} samples; numba against NumPy: largest difference {diff:.1e}")
    ns = {}
    for backend in ("numpy", "numba"):
        kin = results[backend][0]
        t_kin = best_of(lambda b=backend: mech.solve(values, rates, accels, backend=b), 3)
        t_for = best_of(lambda b=backend, k=kin: mech.forces(k, loads, backend=b), 3)
        ns[backend] = (1e9 * t_kin / n, 1e9 * t_for / n)
        kin_ns, for_ns = ns[backend]
        print(f"  {backend:6s} kinematics {kin_ns:8.1f} ns/sample   forces {for_ns:8.1f} ns/sample")
    print(
        f"  compiled / NumPy: kinematics {ns['numba'][0] / ns['numpy'][0]:.2f}×, "
        f"forces {ns['numba'][1] / ns['numpy'][1]:.2f}×"
    )


if __name__ == "__main__":
    main(int(float(sys.argv[1])) if len(sys.argv) > 1 else 200_000)
