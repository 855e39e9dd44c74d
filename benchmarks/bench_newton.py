"""The generic solver (Newton groups) against the closed form, as ratios measured in one run.

Run: ``python benchmarks/bench_newton.py [N]``. Default N = 10⁶ samples over a full turn of
the crank, full kinematic state (positions, velocities, accelerations, body and driver
columns, the precision and change-point checks), all cores. The baseline is the four-bar's
closed form compiled (``backend="numba"``, the default path at this size); its NumPy path is
printed beside it:

* **triad**: the class-III Assur group of the tests (``triad(TRIAD)`` in
  ``tests/property/test_random_linkages.py``: three points that only Newton closes, a 6×6
  system per sample), against the four-bar's closed form (``examples/fourbar.toml``) at the
  same N. Target: ≤ 10× the closed form's time per sample.
* **four-bar by Newton**: the same four-bar with ``method="newton"`` (a 4×4 system per
  sample) against its closed form.

Both Newton plans are timed compiled (``backend="numba"``: their positions and rates kernels,
`excavkin.kinematics.compiled_newton`) and in NumPy.

The three compiled solves are timed in turn, round after round (a change in the machine's
load falls on all alike), and each ratio is given of the best rounds and of the median ones;
the NumPy paths are the best of three. Not a test: machines differ; the ratios are what is
tracked.
"""

from __future__ import annotations

import sys
from typing import Literal

import numpy as np
from timing import best_of, times_in_turn

import excavkin
from excavkin import Body, Mechanism, Model, RotaryDriver

#: the sketch of the tests' triad
TRIAD = {
    "O1": (0.0, 0.0),
    "A": (0.0, 0.3),
    "O2": (1.6, 0.0),
    "O3": (0.8, -0.9),
    "B": (0.6, 0.9),
    "C": (1.4, 1.0),
    "D": (1.3, 0.3),
}


def triad() -> Mechanism:
    """A crank drives a ternary link held by three binary links: no dyad closes it."""
    model = Model(
        "triad",
        TRIAD,
        (
            Body("ground", ("O1", "O2", "O3"), ground=True),
            Body("crank", ("O1", "A")),
            Body("l1", ("A", "B")),
            Body("l2", ("O2", "C")),
            Body("l3", ("O3", "D")),
            Body("tri", ("B", "C", "D")),
        ),
        rotary=(RotaryDriver("crank", "crank", "O1", "ground"),),
    )
    return Mechanism(model)


def main(n: int = 1_000_000) -> tuple[float, float]:
    closed = excavkin.load(excavkin.example_path("fourbar"))
    newton = Mechanism(closed.model, method="newton")
    group = triad()
    assert group.plan.has_newton and newton.plan.has_newton and not closed.plan.has_newton
    turn = np.linspace(0.0, 2.0 * np.pi, n)
    q_triad = group.sketch_values()["crank"] - np.pi + turn
    rates, accels = {"crank": 31.416}, {"crank": 0.0}

    def solve(
        mech: Mechanism, q: np.ndarray, backend: Literal["auto", "numpy", "numba"] = "auto"
    ) -> excavkin.KinematicResult:
        return mech.solve({"crank": q}, rates=rates, accels=accels, backend=backend)

    # what is timed is right: every sample solved, the generic four-bar equal to the closed one
    a, b, c = solve(closed, turn), solve(newton, turn), solve(group, q_triad)
    assert a.status.all_ok and b.status.all_ok and c.status.all_ok
    np.testing.assert_allclose(b.positions, a.positions, rtol=0, atol=1e-14)
    np.testing.assert_allclose(b.accelerations, a.accelerations, rtol=1e-9, atol=1e-9)

    # each kernel compiled (or loaded) before it is timed; the compiled Newton results are the
    # NumPy path's
    solve(closed, turn, "numba")
    for mech, q, ref in ((newton, turn, b), (group, q_triad, c)):
        got = solve(mech, q, "numba")
        np.testing.assert_array_equal(got.status.code, ref.status.code)
        np.testing.assert_allclose(got.positions, ref.positions, rtol=0, atol=1e-12)
    rounds = 7
    t_closed, t_triad, t_newton = times_in_turn(
        [
            lambda: solve(closed, turn, "numba"),
            lambda: solve(group, q_triad, "numba"),
            lambda: solve(newton, turn, "numba"),
        ],
        rounds,
    )
    t_numpy = best_of(lambda: solve(closed, turn, "numpy"), 3)
    t_triad_np = best_of(lambda: solve(group, q_triad, "numpy"), 3)
    t_newton_np = best_of(lambda: solve(newton, turn, "numpy"), 3)
    best, med = min(t_closed), float(np.median(t_closed))
    r_triad, r_newton = min(t_triad) / best, min(t_newton) / best
    m_triad, m_newton = np.median(t_triad) / med, np.median(t_newton) / med
    print(f"Newton groups against the closed form, full kinematic state, N = {n:,}")
    print(f"  compiled: {rounds} rounds in turn (best, median)")
    for label, t in (
        ("four-bar, closed form", t_closed),
        ("triad (6×6 group)", t_triad),
        ("four-bar, method='newton'", t_newton),
    ):
        print(f"  {label:33s}: {n / min(t) / 1e6:6.3f}, {n / np.median(t) / 1e6:6.3f} M samples/s")
    print("  NumPy: best of 3")
    print(f"  four-bar, closed form            : {n / t_numpy / 1e6:6.3f} M samples/s")
    print(f"  triad (6×6 group)                : {n / t_triad_np / 1e6:6.3f} M samples/s")
    print(f"  four-bar, method='newton'        : {n / t_newton_np / 1e6:6.3f} M samples/s")
    print(f"  triad / closed form, per sample  : {r_triad:6.1f}×, {m_triad:.1f}×  (target ≤ 10)")
    print(f"  four-bar newton / closed form    : {r_newton:6.1f}×, {m_newton:.1f}×")
    print(
        f"  NumPy Newton / closed form       : triad {t_triad_np / best:.1f}×, "
        f"four-bar newton {t_newton_np / best:.1f}×"
    )
    return r_triad, r_newton


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000)
