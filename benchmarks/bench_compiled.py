"""The compiled plan against a hand-written numba kernel and against the NumPy engine.

Run: ``python benchmarks/bench_compiled.py [N]``.
Prints, in one run:

- the four-bar's full kinematic state at N samples: excavkin's compiled plan (``mech.solve``,
  all it does included) against a hand-written numba kernel of the textbook arccos/atan2 form on
  a thread per core, computing the same quantities — target ≥ 1.3× its throughput;
- the excavator model: the compiled plan against the NumPy path (today's engine) — target ≥ 2×;
- the excavator's forces (inertia, gravity, a load at the bucket tip): the compiled
  kinetostatic back-substitution against the NumPy one.

The programs run in turn, ``repeat`` rounds, so that a change in the machine's load falls on
all alike; each ratio is printed as the ratio of the best times and the median of the rounds'
ratios.

Not a test: machines differ; the ratios are what is tracked.
"""

from __future__ import annotations

import sys
from collections.abc import Callable

import numba
import numpy as np
from bench_kinematics import A, B, C, D, hand_numpy
from timing import times_in_turn

import excavkin
from excavkin.kinetostatics import Gravity, PointForce


@numba.njit(parallel=True, cache=True)
def _textbook(th: np.ndarray, w: float, al: float, out: np.ndarray) -> None:  # pragma: no cover
    """The crank-rocker by the law of cosines, angles first (the textbook form)."""
    for i in numba.prange(th.size):
        t2 = th[i]
        c2, s2 = np.cos(t2), np.sin(t2)
        ax, ay = A * c2, A * s2
        fx, fy = D - ax, -ay
        f = np.sqrt(fx * fx + fy * fy)
        beta = np.arccos((B * B + f * f - C * C) / (2.0 * B * f))
        t3 = np.arctan2(fy, fx) + beta
        c3, s3 = np.cos(t3), np.sin(t3)
        bx, by = ax + B * c3, ay + B * s3
        t4 = np.arctan2(by, bx - D)
        c4, s4 = np.cos(t4), np.sin(t4)
        s34 = np.sin(t3 - t4)
        w3 = A * w * np.sin(t4 - t2) / (B * s34)
        w4 = A * w * np.sin(t3 - t2) / (C * s34)
        # accelerations from the loop equation's second derivative
        rhs_x = -A * (al * -s2 - w * w * c2) + B * w3 * w3 * c3 - C * w4 * w4 * c4
        rhs_y = -A * (al * c2 - w * w * s2) + B * w3 * w3 * s3 - C * w4 * w4 * s4
        a3 = (rhs_x * c4 + rhs_y * s4) / (B * (-s3 * c4 + c3 * s4))
        a4 = (-B * s3 * rhs_y - B * c3 * rhs_x) / (B * C * (s3 * c4 - c3 * s4))
        vax, vay = -A * w * s2, A * w * c2
        aax = -A * (al * s2 + w * w * c2)
        aay = A * (al * c2 - w * w * s2)
        out[0, i], out[1, i], out[2, i], out[3, i] = ax, ay, vax, vay
        out[4, i], out[5, i] = aax, aay
        out[6, i], out[7, i] = bx, by
        out[8, i], out[9, i] = -C * w4 * s4, C * w4 * c4
        out[10, i] = -C * (a4 * s4 + w4 * w4 * c4)
        out[11, i] = C * (a4 * c4 - w4 * w4 * s4)
        mu = abs(t3 - t4) % (2 * np.pi)
        out[12, i] = min(mu, 2 * np.pi - mu)
        out[13, i], out[14, i], out[15, i] = np.arctan2(s2, c2), w, al
        out[16, i], out[17, i], out[18, i] = np.arctan2(s3, c3), w3, a3
        out[19, i], out[20, i], out[21, i] = t4, w4, a4


def textbook(th: np.ndarray, w: float, al: float) -> np.ndarray:
    out = np.empty((22, th.size))
    _textbook(th, w, al, out)
    return out


def _ratios(slow: list[float], fast: list[float]) -> tuple[float, float]:
    """The ratio of the best times, and the median of the rounds' ratios (runs in turn)."""
    per_round = sorted(a / b for a, b in zip(slow, fast, strict=True))
    return min(slow) / min(fast), per_round[len(per_round) // 2]


def main(n: int = 1_000_000, repeat: int = 7) -> tuple[float, float, float]:
    fourbar = excavkin.load(excavkin.example_path("fourbar"))
    th = np.linspace(0.0, 2 * np.pi, n)
    w, al = 31.416, 2.5
    hand = textbook(th, w, al)
    ref = hand_numpy(th, w, al)
    checked = {6: "bx", 7: "by", 10: "abx", 12: "mu", 18: "coupler.epsilon", 21: "rocker.epsilon"}
    for row, key in checked.items():
        assert np.allclose(hand[row], ref[key], rtol=1e-9, atol=1e-9 * np.abs(ref[key]).max())

    def fb(backend: str) -> Callable[[], object]:
        return lambda: fourbar.solve(
            {"crank": th}, rates={"crank": w}, accels={"crank": al}, backend=backend
        )

    fourbar.solve({"crank": th[:1000]}, backend="numba")  # compile (or load the kernel made before)
    t_hand, t_ours, t_numpy = times_in_turn(
        [lambda: textbook(th, w, al), fb("numba"), fb("numpy")], repeat
    )
    print(f"four-bar, full kinematic state, N = {n:,}, {numba.get_num_threads()} threads, "
          f"{repeat} rounds (best, median)")  # fmt: skip
    rows = [("hand-written numba, textbook form", t_hand), ("excavkin, NumPy path", t_numpy),
            ("excavkin, compiled plan", t_ours)]  # fmt: skip
    for label, t in rows:
        print(f"  {label:37s}: {n / min(t) / 1e6:6.2f}, {n / np.median(t) / 1e6:6.2f} M samples/s")
    r_fourbar, m_fourbar = _ratios(t_hand, t_ours)
    print(f"  compiled / hand-written numba        : {r_fourbar:6.2f}×, {m_fourbar:.2f}×"
          "  (target ≥ 1.3)")  # fmt: skip

    exc = excavkin.load(excavkin.example_path("excavator"))
    values = {}
    for k, v in exc.sketch_values().items():
        span = 0.3 if exc.input_kind(k) == "angle" else 0.03 * v
        values[k] = v + span * np.sin(np.linspace(0.0, 7.0, n) + len(k))
    rates = {k: 0.5 for k in values}

    def ex(backend: str) -> Callable[[], object]:
        return lambda: exc.solve(values, rates=rates, backend=backend)

    exc.solve({k: v[:1000] for k, v in values.items()}, backend="numba")
    t_fast, t_slow = times_in_turn([ex("numba"), ex("numpy")], repeat)
    r_exc, m_exc = _ratios(t_slow, t_fast)
    print(f"excavator, full kinematic state, N = {n:,}")
    print(f"  excavkin, NumPy path                 : {n / min(t_slow) / 1e6:6.2f} M samples/s")
    print(f"  excavkin, compiled plan              : {n / min(t_fast) / 1e6:6.2f} M samples/s")
    print(f"  compiled / NumPy                     : {r_exc:6.2f}×, {m_exc:.2f}×  (target ≥ 2)")

    kin = exc.solve(values, rates=rates, backend="numba")
    loads = [Gravity(), PointForce("dig", "bucket", "W", (-20e3, 5e3))]
    exc.forces(kin, loads, backend="numba")
    fast, slow = (lambda b=b: exc.forces(kin, loads, backend=b) for b in ("numba", "numpy"))
    t_fast, t_slow = times_in_turn([fast, slow], repeat)
    r_forces, m_forces = _ratios(t_slow, t_fast)
    print(f"excavator, forces (inertia, gravity, a load at the tip), N = {n:,}")
    print(f"  excavkin, NumPy forces               : {n / min(t_slow) / 1e6:6.2f} M samples/s")
    print(f"  excavkin, compiled elimination       : {n / min(t_fast) / 1e6:6.2f} M samples/s")
    print(f"  compiled / NumPy                     : {r_forces:6.2f}×, {m_forces:.2f}×")
    return r_fourbar, r_exc, r_forces


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000)
