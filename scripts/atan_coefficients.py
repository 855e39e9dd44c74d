"""The coefficients of the compiled kernels' arctangent (excavkin.kinematics.fast_atan2).

atan(u) = u + u·s·g(s), s = u², on |u| ≤ 1/2; g is fitted by Remez's exchange to the least
maximum relative error of atan(u)/u, in 60-digit arithmetic (mpmath). Run:
``python scripts/atan_coefficients.py`` (prints the degree, the error and the coefficients).
"""

from __future__ import annotations

import mpmath as mp

mp.mp.dps = 60
DEGREE = 11
S_MAX = mp.mpf(1) / 4  # |u| ≤ 1/2


def g(s: mp.mpf) -> mp.mpf:
    if s == 0:
        return mp.mpf(-1) / 3
    r = mp.sqrt(s)
    return (mp.atan(r) - r) / (s * r)


def weight(s: mp.mpf) -> mp.mpf:
    """The relative error of atan(u) from an error of g at s."""
    return s / (1 + s * g(s))


def remez(degree: int, grid: int = 4000, rounds: int = 30) -> tuple[list[mp.mpf], mp.mpf]:
    m = degree + 2
    xs = [S_MAX * (1 - mp.cos(mp.pi * k / (m - 1))) / 2 for k in range(m)]
    coef: list[mp.mpf] = []
    level = mp.mpf(0)
    for _ in range(rounds):
        a = mp.matrix(m, m)
        b = mp.matrix(m, 1)
        for i, x in enumerate(xs):
            for j in range(degree + 1):
                a[i, j] = x**j
            a[i, degree + 1] = (-1) ** i / (weight(x) if x else mp.mpf("1e-40"))
            b[i] = g(x)
        sol = mp.lu_solve(a, b)
        coef, level = [sol[j] for j in range(degree + 1)], sol[degree + 1]
        pts = [S_MAX * k / grid for k in range(grid + 1)]
        err = [weight(s) * (mp.polyval(coef[::-1], s) - g(s)) for s in pts]
        ext: list[int] = []  # alternating extrema, the larger of each run of one sign
        for k in range(grid + 1):
            interior = 0 < k < grid and (err[k] - err[k - 1]) * (err[k + 1] - err[k]) > 0
            if interior:
                continue
            if ext and mp.sign(err[ext[-1]]) == mp.sign(err[k]):
                if abs(err[k]) > abs(err[ext[-1]]):
                    ext[-1] = k
            else:
                ext.append(k)
        while len(ext) > m:
            ext = ext[1:] if abs(err[ext[0]]) < abs(err[ext[-1]]) else ext[:-1]
        if len(ext) < m:
            break
        xs = [pts[k] for k in ext]
    return coef, abs(level)


if __name__ == "__main__":
    c, e = remez(DEGREE)
    print(f"degree {DEGREE}, largest relative error of atan(u)/u: {mp.nstr(e, 3)}")
    print(", ".join(repr(float(x)) for x in c))
