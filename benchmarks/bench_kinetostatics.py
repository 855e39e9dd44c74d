"""Kinetostatics of the crank-rocker at 10⁶ crank angles, as a ratio to its kinematics.

Run: ``python benchmarks/bench_kinetostatics.py [N]``. Solves ``examples/fourbar.toml`` over N
crank angles (default 10⁶) at 31.4 rad/s accelerating at 100 rad/s², then its kinetostatics with
gravity and a constant force on the coupler (every pin force, the crank torque; inertia of the
rocker, the model's only massive link) — and prints samples/s of both and the ratio of their
times, best of several repeats in the same run. Target: kinetostatics ≤ 3× kinematics. The
dense per-sample LAPACK solve of the same system is timed on a slice for comparison.
Not a test: machines differ; the ratio is what is tracked.
"""

from __future__ import annotations

import sys

import numpy as np
from timing import best_of

import excavkin
from excavkin.kinetostatics import Gravity, PointForce, solve_forces


def main(n: int = 1_000_000) -> float:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    theta = np.linspace(0.0, 2.0 * np.pi, n)
    rates, accels = {"crank": 31.4}, {"crank": 100.0}
    loads = [Gravity(), PointForce("push", "coupler", "B", (5.0, -2.0))]
    statics = mech.statics  # compiled once per mechanism, as Mechanism.forces does

    kin = mech.solve({"crank": theta}, rates, accels)
    assert kin.status.all_ok
    res = solve_forces(kin, loads, system=statics)
    worst = float(np.max(res.power_balance().relative))

    t_kin = best_of(lambda: mech.solve({"crank": theta}, rates, accels), 7)
    t_force = best_of(lambda: solve_forces(kin, loads, system=statics), 7)
    m = min(n, 20_000)
    part = mech.solve({"crank": theta[:m]}, rates, accels)
    t_dense = best_of(lambda: solve_forces(part, loads, system=statics, method="dense"), 3)

    print(
        f"four-bar, {n:,} samples, structure: {statics.size} unknowns, "
        f"{len(mech.plan.steps)} plan steps"
    )
    print(f"  kinematics     {n / t_kin:14,.0f} samples/s  ({t_kin * 1e3:8.1f} ms)")
    print(f"  kinetostatics  {n / t_force:14,.0f} samples/s  ({t_force * 1e3:8.1f} ms)")
    print(f"  dense LAPACK   {m / t_dense:14,.0f} samples/s  (per-sample np.linalg.solve)")
    print(f"  power balance: worst relative residual {worst:.2e}")
    ratio = t_force / t_kin
    print(f"  ratio kinetostatics / kinematics = {ratio:.2f}  (target ≤ 3)")
    return ratio


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000)
