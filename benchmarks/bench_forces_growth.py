"""Kinematics and forces per sample of ever larger chains: both grow linearly with the model.

Run: ``python benchmarks/bench_forces_growth.py [SIZES...]`` (default 11 101 1001; about a
minute on a 2-core machine: slow). For each size, the chain of crank-rocker four-bars of
``tests/models.py`` made for it, as ``bench_check.py`` makes it (3·stages + 1 points: 10, 100
and 1,000), solved over S samples of the crank (default 16 384) with a rate and an
acceleration, then its forces (a load per sample at every tenth body's last point) along the
solve plan; both on the NumPy path (``backend="numpy"``: the compiled paths stop at a size
limit). It prints the time per sample of each, their ratio, and the growth exponent between
consecutive sizes, log(t₂/t₁) / log(n₂/n₁) (1: linear), and checks the power balance. The
dense per-sample LAPACK solve of the whole system (``method="dense"``) is timed on a few
samples of the two smaller chains, for comparison (0.2 s a sample at 100 points). Best of a
few repeats in the same process. Not a test: machines differ; the ratios and exponents are
what is tracked.
"""

from __future__ import annotations

import math
import sys
import tempfile
from pathlib import Path

import numpy as np
from timing import best_of

import excavkin
from excavkin.kinetostatics import PointForce, solve_forces

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the tests' model generators
from tests.models import fourbar_chain  # noqa: E402


def exponent(t1: float, t2: float, n1: int, n2: int) -> float:
    """The growth exponent between two sizes: t ∝ n^k."""
    return math.log(t2 / t1) / math.log(n2 / n1)


def main(sizes: list[int], samples: int = 16_384) -> list[tuple[int, float, float]]:
    rows: list[tuple[int, float, float]] = []
    rng = np.random.default_rng(1)
    with tempfile.TemporaryDirectory() as tmp:
        for size in sizes:
            path = Path(tmp) / f"chain{size}.toml"
            path.write_text(fourbar_chain((size - 1) // 3))
            mech = excavkin.load(path)
            points = len(mech.model.points)
            crank = mech.plan.inputs[0]
            q = mech.sketch_values()[crank] + np.linspace(-0.02, 0.02, samples)
            args = ({crank: q}, {crank: 1.0}, {crank: 0.5})
            moving = [b for b in mech.model.bodies if not b.ground]
            loads = [
                PointForce(f"f{k}", b.name, b.points[-1], rng.normal(0.0, 100.0, (samples, 2)))
                for k, b in enumerate(moving)
                if k % 10 == 0
            ]
            statics = mech.statics  # (compiled once, as Mechanism.forces does)
            kin = mech.solve(*args, backend="numpy")
            assert kin.status.solved.all()
            forces = mech.forces(kin, loads, backend="numpy")
            worst = float(np.max(forces.power_balance().relative))
            repeat = 3 if points <= 100 else 2
            t_kin = best_of(lambda a=args, m=mech: m.solve(*a, backend="numpy"), repeat) / samples
            t_force = best_of(
                lambda k=kin, ld=loads, s=statics: solve_forces(k, ld, system=s, backend="numpy"),
                repeat,
            )
            t_force /= samples
            rows.append((points, t_kin, t_force))
            line = (
                f"chain {points:5,} points: kinematics {t_kin * 1e6:8.2f} µs, forces "
                f"{t_force * 1e6:8.2f} µs a sample (forces / kinematics {t_force / t_kin:4.2f}); "
                f"power balance {worst:.1e}"
            )
            if points <= 100:  # (a 100-point chain's takes 0.2 s a sample)
                m = 200 if points <= 10 else 5
                part = mech.solve({crank: q[:m]}, {crank: 1.0}, {crank: 0.5}, backend="numpy")
                few = [PointForce(ld.name, ld.body, ld.point, ld.value[:m]) for ld in loads]
                t_dense = best_of(
                    lambda p=part, f=few, s=statics: solve_forces(p, f, system=s, method="dense"),
                    1 if points > 10 else repeat,
                )
                line += f"; dense LAPACK {t_dense / m * 1e6:8.1f} µs a sample"
            print(line, flush=True)
    for (n1, k1, f1), (n2, k2, f2) in zip(rows, rows[1:], strict=False):
        print(
            f"  {n1:,} → {n2:,} points: kinematics ×{k2 / k1:5.1f} (exponent "
            f"{exponent(k1, k2, n1, n2):4.2f}), forces ×{f2 / f1:5.1f} (exponent "
            f"{exponent(f1, f2, n1, n2):4.2f})"
        )
    return rows


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [11, 101, 1001])
