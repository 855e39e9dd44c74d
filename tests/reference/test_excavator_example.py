"""The example excavator model against an independent closed form.

Reference: the triangle (law of cosines) method of the seed paper "Vector model of a crawler
excavator arm" (``seeds/vector-model-excavator-arm.md`` §3.4: cylinder length ↔ link angle),
applied to each cylinder in its parent's frame, plus the bucket's four-bar solved by hand and
the tip by composing rotations. The pin coordinates are read straight from
``examples/excavator.toml`` with ``tomllib``; nothing here uses the engine except the values
compared against.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

import excavkin
from tests.conftest import EXAMPLES

PATH = EXAMPLES / "excavator.toml"
LIMITS = np.array([[1.990, 3.325], [2.170, 3.660], [1.645, 2.765]])  # strokes (machine file)


def _sketch() -> dict[str, np.ndarray]:
    data = tomllib.loads(PATH.read_text(encoding="utf-8"))
    return {k: np.array(v, dtype=float) / 1000.0 for k, v in data["points"].items()}


def _ang(v: np.ndarray) -> np.ndarray:
    return np.arctan2(v[..., 1], v[..., 0])


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _dir(a: np.ndarray) -> np.ndarray:
    return np.stack([np.cos(a), np.sin(a)], axis=-1)


def closed_form(lengths: np.ndarray) -> dict[str, np.ndarray]:
    """All pins of the front for cylinder lengths (n, 3), by the triangle method."""
    s = _sketch()
    d = lambda p, q: float(np.linalg.norm(s[p] - s[q]))  # noqa: E731
    side = lambda a, b, p: float(np.sign(_cross(s[b] - s[a], s[p] - s[a])))  # noqa: E731

    def triangle(
        o: np.ndarray, base: np.ndarray, r_move: float, length: np.ndarray, sgn: float
    ) -> np.ndarray:
        """Angle of o→moving point, from |o base|, |o moving| and the cylinder length."""
        r0 = np.linalg.norm(base - o, axis=-1)
        cos_o = (r0**2 + r_move**2 - length**2) / (2.0 * r0 * r_move)
        return _ang(base - o) + sgn * np.arccos(cos_o)

    lb, la, lk = lengths.T
    out: dict[str, np.ndarray] = {}
    A, C = s["A"], s["C"]
    # boom: triangle A–C–D, sign from the sketch; boom chord A→F at a fixed offset from A→D
    th_d = triangle(A, C, d("A", "D"), lb, side("A", "C", "D"))
    phi1 = th_d + (_ang(s["F"] - A) - _ang(s["D"] - A))
    out["F"] = A + d("A", "F") * _dir(phi1)
    dphi_boom = phi1 - _ang(s["F"] - A)
    out["E"] = A + _rotate(s["E"] - A, dphi_boom)
    # stick: triangle F–E–G about the stick pivot F
    F = out["F"]
    th_g = triangle(F, out["E"], d("F", "G"), la, side("F", "E", "G"))
    dphi_stick = th_g - _ang(s["G"] - s["F"])
    for p in ("Q", "H", "N"):
        out[p] = F + _rotate(s[p] - s["F"], dphi_stick)
    # bucket four-bar: K from N (side link) and H (cylinder), then L from K and Q
    N, H, Q = out["N"], out["H"], out["Q"]
    th_k = triangle(N, H, d("N", "K"), lk, side("N", "H", "K"))
    out["K"] = N + d("N", "K") * _dir(th_k)
    th_l = triangle(Q, out["K"], d("Q", "L"), np.full(len(lk), d("K", "L")), side("Q", "K", "L"))
    out["L"] = Q + d("Q", "L") * _dir(th_l)
    # tip and lip: rotate the bucket's sketch by the turn of Q→L
    dphi_bucket = th_l - _ang(s["L"] - s["Q"])
    for p in ("T", "W"):
        out[p] = Q + _rotate(s[p] - s["Q"], dphi_bucket)
    out["phi_boom"] = phi1
    return out


def _rotate(v: np.ndarray, a: np.ndarray) -> np.ndarray:
    c, s_ = np.cos(a), np.sin(a)
    return np.stack([c * v[..., 0] - s_ * v[..., 1], s_ * v[..., 0] + c * v[..., 1]], axis=-1)


@pytest.fixture(scope="module")
def mech() -> excavkin.Mechanism:
    return excavkin.load(excavkin.example_path("excavator"))


def _random_lengths(n: int, seed: int = 2024) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return LIMITS[:, 0] + rng.random((n, 3)) * (LIMITS[:, 1] - LIMITS[:, 0])


def _solve(mech: excavkin.Mechanism, L: np.ndarray, rates: np.ndarray | None = None):
    names = ("boom_cyl", "arm_cyl", "bucket_cyl")
    r = np.zeros(3) if rates is None else rates
    return mech.solve(
        {n: L[:, i] for i, n in enumerate(names)},
        {n: np.full(len(L), r[i]) for i, n in enumerate(names)},
    )


def test_plan_is_closed_form(mech: excavkin.Mechanism) -> None:
    assert not mech.plan.has_newton
    text = mech.plan.describe()
    assert "newton" not in text
    assert text.count("dyad") == 4 and "attach" in text
    assert set(mech.inputs) == {"boom_cyl", "arm_cyl", "bucket_cyl"}


def test_assembles_over_the_whole_stroke_box(mech: excavkin.Mechanism) -> None:
    axes = [np.linspace(lo, hi, 15) for lo, hi in LIMITS]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    assert _solve(mech, grid).status.all_ok


def test_positions_match_the_triangle_method(mech: excavkin.Mechanism) -> None:
    L = _random_lengths(400)
    res = _solve(mech, L)
    ref = closed_form(L)
    scale = 10.0  # m, the size of the front
    for p in ("F", "E", "Q", "H", "N", "K", "L", "T", "W"):
        np.testing.assert_allclose(res.point(p)[0], ref[p], rtol=0, atol=1e-9 * scale, err_msg=p)
    np.testing.assert_allclose(res.body("boom")[0], ref["phi_boom"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.driver("boom_cyl")[0], L[:, 0], rtol=1e-14)


_D6 = np.array([-1 / 60, 3 / 20, -3 / 4, 0.0, 3 / 4, -3 / 20, 1 / 60])  # 6th-order central


@pytest.mark.parametrize("col", [0, 1, 2])
def test_velocities_match_sixth_order_differences(mech: excavkin.Mechanism, col: int) -> None:
    L = _random_lengths(60, seed=7)
    L[:, col] = np.clip(L[:, col], LIMITS[col, 0] + 0.01, LIMITS[col, 1] - 0.01)
    rates = np.eye(3)[col]
    res = _solve(mech, L, rates)
    h = 5e-4  # truncation ~h⁶·f⁽⁷⁾, rounding ~1e-16·|T|/h: both below 1e-9 here
    stack = []
    for k in range(-3, 4):
        Lk = L.copy()
        Lk[:, col] += k * h
        stack.append(closed_form(Lk)["T"])
    fd = np.tensordot(_D6, np.stack(stack), axes=1) / h
    v = res.point("T")[1]
    np.testing.assert_allclose(v, fd, rtol=0, atol=1e-9 * np.abs(fd).max())
