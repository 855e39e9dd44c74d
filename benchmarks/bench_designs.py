"""Geometry as a batch axis, as ratios measured in one run.

Run: ``python benchmarks/bench_designs.py [N]``. On ``examples/fourbar.toml`` (default N = 10⁶):

* **designs**: N distinct designs (every dimension of the four-bar moved: A-B, O4-B, O4.x,
  O4.y, A.y), one crank angle each, against one design at N crank angles. Target: the
  designs' throughput ≥ 0.5× the poses'.
* **sensitivities**: the full kinematic state with exact derivatives with respect to 10
  parameters, against the kinematics alone, at N/10 samples, both compiled (``backend="numba"``)
  and both in NumPy, the ratios also crossed. Target ≤ 3× the compiled kinematics.

Best of several repeats in the same process. Not a test: machines differ; the ratios are what
is tracked.
"""

from __future__ import annotations

import sys

import numpy as np
from timing import best_of

import excavkin


def main(n: int = 1_000_000) -> tuple[float, float]:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    rng = np.random.default_rng(0)
    theta = rng.uniform(0.0, 2.0 * np.pi, n)
    nominal = mech.parameters
    designs = {
        "A-B": nominal["A-B"] + rng.uniform(-2e-3, 2e-3, n),
        "O4-B": nominal["O4-B"] + rng.uniform(-2e-3, 2e-3, n),
        "O4.x": nominal["O4.x"] + rng.uniform(-2e-3, 2e-3, n),
        "O4.y": nominal["O4.y"] + rng.uniform(-2e-3, 2e-3, n),
        "A.y": nominal["A.y"] + rng.uniform(-1e-3, 1e-3, n),
    }
    ok = mech.solve({"crank": theta}, params=designs).status.ok.mean()
    t_poses = best_of(lambda: mech.solve({"crank": theta}))
    t_designs = best_of(lambda: mech.solve({"crank": theta}, params=designs))
    print(f"four-bar, {n:,} samples ({ok:.1%} of the random designs close)")
    print(f"  one design, {n:,} poses    {n / t_poses:14,.0f} samples/s")
    print(f"  {n:,} designs, one pose each {n / t_designs:14,.0f} samples/s")
    r_designs = t_poses / t_designs
    print(f"  designs / poses throughput: {r_designs:.2f} (target ≥ 0.5)")

    m = max(n // 10, 1)
    names = list(nominal)[:8] + ["A-B", "O4-B"]
    names = list(dict.fromkeys(names))[:10]
    q = theta[:m]
    rates = {"crank": 3.0}
    mech.solve({"crank": q}, rates=rates, backend="numba")  # kernels compiled (or loaded)
    mech.solve({"crank": q}, rates=rates, sensitivities=names, backend="numba")
    t_kin = best_of(lambda: mech.solve({"crank": q}, rates=rates, backend="numba"))
    t_kin_np = best_of(lambda: mech.solve({"crank": q}, rates=rates, backend="numpy"))
    t_sens = best_of(
        lambda: mech.solve({"crank": q}, rates=rates, sensitivities=names, backend="numba"), 3
    )
    t_sens_np = best_of(
        lambda: mech.solve({"crank": q}, rates=rates, sensitivities=names, backend="numpy"), 3
    )
    r_sens = t_sens / t_kin
    print(
        f"  sensitivities to {len(names)} parameters, {m:,} samples, against the compiled "
        f"kinematics: {r_sens:.2f}× by the compiled tangent kernel, {t_sens_np / t_kin:.2f}× by "
        "the NumPy dual path (target ≤ 3)"
    )
    print(
        f"  against the NumPy kinematics: {t_sens / t_kin_np:.2f}× compiled, "
        f"{t_sens_np / t_kin_np:.2f}× NumPy dual path"
    )
    return r_designs, r_sens


if __name__ == "__main__":
    main(int(float(sys.argv[1])) if len(sys.argv) > 1 else 1_000_000)
