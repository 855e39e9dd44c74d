"""Full kinematic state of the crank-rocker at 10⁶ crank angles: excavkin vs hand-written NumPy.

Run: ``python benchmarks/bench_kinematics.py [N]``. Prints samples/s of ``Mechanism.solve`` and of
a hand-written NumPy closed form computing the same quantities (positions, velocities and
accelerations of every point, angle/ω/ε of every body, the driver columns and the transmission
angle), and their ratio — the target is ≤ 1.5. When pylinkage is installed (``pip install
'excavkin[bench]'``) its fastest path for the same linkage at the same N, its compiled stepping
loop, is timed for positions and for positions with velocities and accelerations (what it
offers), after its numbers are checked against the closed form; see ``pylinkage_rates``.
Not a test: machines differ; the ratio is what is tracked.
"""

from __future__ import annotations

import sys

import numpy as np
from timing import best_of

import excavkin

A, B, C, D = 0.040, 0.120, 0.090, 0.100


def hand_numpy(th: np.ndarray, w: float, al: float) -> dict[str, np.ndarray]:
    """The four-bar state by hand: A from the crank, B from the dyad A–B / O4–B."""
    cs, sn = np.cos(th), np.sin(th)
    ax, ay = A * cs, A * sn
    vax, vay = -A * w * sn, A * w * cs
    aax = -A * (al * sn + w * w * cs)
    aay = A * (al * cs - w * w * sn)
    ex, ey = D - ax, -ay
    l2 = ex * ex + ey * ey
    k = (B * B - C * C + l2) / (2 * l2)
    h = np.sqrt(B * B / l2 - k * k)
    bx = ax + k * ex - h * ey
    by = ay + k * ey + h * ex
    r1x, r1y, r2x, r2y = bx - ax, by - ay, bx - D, by
    det = r1x * r2y - r1y * r2x
    f1 = r1x * vax + r1y * vay
    vbx = f1 * r2y / det
    vby = -r2x * f1 / det
    wx, wy = vbx - vax, vby - vay
    g1 = r1x * aax + r1y * aay - (wx * wx + wy * wy)
    g2 = -(vbx * vbx + vby * vby)
    abx = (g1 * r2y - g2 * r1y) / det
    aby = (r1x * g2 - r2x * g1) / det
    out = {
        "ax": ax,
        "ay": ay,
        "vax": vax,
        "vay": vay,
        "aax": aax,
        "aay": aay,
        "bx": bx,
        "by": by,
        "vbx": vbx,
        "vby": vby,
        "abx": abx,
        "aby": aby,
        "mu": np.arctan2(np.abs(det), r1x * r2x + r1y * r2y),
    }
    for name, (rx, ry, vx, vy, ax_, ay_) in {
        "crank": (ax, ay, vax, vay, aax, aay),
        "coupler": (r1x, r1y, wx, wy, abx - aax, aby - aay),
        "rocker": (r2x, r2y, vbx, vby, abx, aby),
    }.items():
        r2 = rx * rx + ry * ry
        out[name + ".angle"] = np.arctan2(ry, rx)
        out[name + ".omega"] = (rx * vy - ry * vx) / r2
        out[name + ".epsilon"] = (rx * ay_ - ry * ax_) / r2
    return out


def pylinkage_rates(n: int) -> tuple[float, float] | None:
    """Samples/s of pylinkage's fastest path for one linkage over many crank angles, on the same
    four-bar at the same N: its numba-compiled stepping loops, ``Linkage.step_fast`` (positions
    of the four joints) and ``Linkage.step_fast_with_kinematics`` (their positions, velocities
    and accelerations). Both run one thread and step the crank by a fixed angle, each step
    solving the dyad from the previous one; they give no body angles, ω, ε or transmission
    angle. Its batched solver (``population.simulate_batch``) runs many designs, not many
    angles of one. Its results are checked against the hand-written closed form first, so the
    figures are of the same numbers."""
    try:
        import pylinkage as pl  # type: ignore[import-not-found]
    except ImportError:
        return None
    try:
        w = 31.416
        g1, g2 = pl.Ground(0.0, 0.0), pl.Ground(D, 0.0)
        crank = pl.Crank(g1, A, angular_velocity=2 * np.pi / n, initial_angle=0.0)
        pin = pl.RRRDyad(crank, g2, B, C, x=0.11, y=0.09)
        linkage = pl.Linkage([g1, g2, crank, pin], order=[g1, g2, crank, pin])
        linkage.set_input_velocity(crank, w)
        start = {j: (j.x, j.y) for j in (crank, pin)}

        def run(kinematics: bool) -> object:
            for j, (x, y) in start.items():  # every run the same turn, from angle 0
                j.x, j.y = x, y
            if kinematics:
                return linkage.step_fast_with_kinematics(iterations=n)
            return linkage.step_fast(iterations=n)

        pos, vel, acc = run(True)  # type: ignore[misc]  # compiles, and is checked
        traj = run(False)
        th = 2 * np.pi / n * np.arange(1, n + 1)  # the angle after each step
        ref = hand_numpy(th, w, 0.0)
        i = [linkage.components.index(j) for j in (crank, pin)]
        for got, names in (
            (traj[:, i[1]], ("bx", "by")),
            (pos[:, i[1]], ("bx", "by")),
            (pos[:, i[0]], ("ax", "ay")),
            (vel[:, i[1]], ("vbx", "vby")),
            (acc[:, i[1]], ("abx", "aby")),
        ):
            want = np.stack([ref[names[0]], ref[names[1]]], axis=1)
            scale = np.abs(want).max()
            assert np.allclose(got, want, rtol=1e-9, atol=1e-9 * scale), names
        t_pos = best_of(lambda: run(False))
        t_kin = best_of(lambda: run(True))
        return n / t_pos, n / t_kin
    except Exception as exc:  # an API change in pylinkage must not break our benchmark
        print(f"  pylinkage: could not run ({type(exc).__name__}: {exc})")
        return None


def main(n: int = 1_000_000) -> float:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    th = np.linspace(0.0, 2 * np.pi, n)
    w, al = 31.416, 0.0
    res = mech.solve({"crank": th}, rates={"crank": w}, accels={"crank": al})
    ref = hand_numpy(th, w, al)
    pos, vel, acc = res.point("B")
    assert np.allclose(pos[:, 0], ref["bx"], atol=1e-14) and np.allclose(
        acc[:, 1], ref["aby"], rtol=1e-9, atol=1e-9
    )

    def ours(workers: int | None) -> float:
        return best_of(
            lambda: mech.solve(
                {"crank": th}, rates={"crank": w}, accels={"crank": al}, workers=workers
            )
        )

    t_ours, t_one = ours(None), ours(1)
    t_hand = best_of(lambda: hand_numpy(th, w, al))
    print(f"four-bar, full kinematic state, N = {n:,}")
    print(f"  hand-written NumPy                   : {n / t_hand / 1e6:6.2f} M samples/s")
    print(f"  excavkin solve, one thread           : {n / t_one / 1e6:6.2f} M samples/s")
    print(f"  excavkin solve, all cores (default)  : {n / t_ours / 1e6:6.2f} M samples/s")
    ratio = t_ours / t_hand
    print(
        f"  ratio excavkin/NumPy                 : {ratio:6.2f}   (target ≤ 1.5; "
        f"one thread: {t_one / t_hand:.2f})"
    )
    pl = pylinkage_rates(n)
    if pl is not None:
        print("  pylinkage 1.3, compiled stepping loop, one thread, same N:")
        print(f"    positions of the joints (step_fast) : {pl[0] / 1e6:6.2f} M samples/s")
        print(f"    + velocities, accelerations         : {pl[1] / 1e6:6.2f} M samples/s")
        print(
            f"    excavkin's full state against pylinkage's positions, vel., accel.: "
            f"{n / t_ours / pl[1]:.1f}× (one thread {n / t_one / pl[1]:.1f}×)"
        )
    return ratio


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000)
