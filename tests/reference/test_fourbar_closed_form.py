"""The engine against the textbook closed form of the four-bar.

Reference: R. L. Norton, *Design of Machinery*, 5th ed., McGraw-Hill 2012:
eqs. (4.10a–b) and (4.13) for θ4 and θ3 (Freudenstein half-angle form), eqs. (6.18a–b) for ω3, ω4
and eqs. (7.12a–b) for α3, α4. Link lengths a (crank), b (coupler), c (rocker), d (ground).
"""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from tests.conftest import EXAMPLES, assert_rel

A, B, C, D = 0.040, 0.120, 0.090, 0.100  # examples/fourbar.toml, with its [lengths]


def norton_fourbar(t2: np.ndarray, w2: float, al2: float, sign: float) -> dict[str, np.ndarray]:
    k1, k2, k3 = D / A, D / C, (A * A - B * B + C * C + D * D) / (2 * A * C)
    k4, k5 = D / B, (C * C - D * D - A * A - B * B) / (2 * A * B)
    aa = np.cos(t2) - k1 - k2 * np.cos(t2) + k3
    bb = -2 * np.sin(t2)
    cc = k1 - (k2 + 1) * np.cos(t2) + k3
    t4 = 2 * np.arctan2(-bb + sign * np.sqrt(bb * bb - 4 * aa * cc), 2 * aa)
    dd = np.cos(t2) - k1 + k4 * np.cos(t2) + k5
    ee = -2 * np.sin(t2)
    ff = k1 + (k4 - 1) * np.cos(t2) + k5
    t3 = 2 * np.arctan2(-ee + sign * np.sqrt(ee * ee - 4 * dd * ff), 2 * dd)
    w3 = A * w2 / B * np.sin(t4 - t2) / np.sin(t3 - t4)
    w4 = A * w2 / C * np.sin(t2 - t3) / np.sin(t4 - t3)
    pa, pb = C * np.sin(t4), B * np.sin(t3)
    pc = (
        A * al2 * np.sin(t2)
        + A * w2**2 * np.cos(t2)
        + B * w3**2 * np.cos(t3)
        - C * w4**2 * np.cos(t4)
    )
    pd, pe = C * np.cos(t4), B * np.cos(t3)
    pf = (
        A * al2 * np.cos(t2)
        - A * w2**2 * np.sin(t2)
        - B * w3**2 * np.sin(t3)
        + C * w4**2 * np.sin(t4)
    )
    al3 = (pc * pd - pa * pf) / (pa * pe - pb * pd)
    al4 = (pc * pe - pb * pf) / (pa * pe - pb * pd)
    return {"t3": t3, "t4": t4, "w3": w3, "w4": w4, "al3": al3, "al4": al4}


@pytest.mark.parametrize(("w2", "al2"), [(1.0, 0.0), (31.416, 0.0), (-7.0, 55.0)])
def test_fourbar_matches_norton(w2: float, al2: float) -> None:
    mech = excavkin.load(EXAMPLES / "fourbar.toml")
    t2 = np.radians(np.linspace(0.0, 360.0, 721))
    res = mech.solve({"crank": t2}, rates={"crank": w2}, accels={"crank": al2})
    assert res.status.all_ok
    # the sketch's branch: pick Norton's sign that reproduces the sketch, then keep it
    ref = {s: norton_fourbar(t2, w2, al2, s) for s in (1.0, -1.0)}
    t4 = res.body("rocker")[0]
    sign = min(ref, key=lambda s: float(np.abs(np.angle(np.exp(1j * (ref[s]["t4"] - t4)))).max()))
    r = ref[sign]
    wrap = lambda x: np.angle(np.exp(1j * x))  # noqa: E731
    assert np.max(np.abs(wrap(res.body("coupler")[0] - r["t3"]))) < 1e-12
    assert np.max(np.abs(wrap(t4 - r["t4"]))) < 1e-12
    assert_rel(res.body("coupler")[1], r["w3"], 1e-12)
    assert_rel(res.body("rocker")[1], r["w4"], 1e-12)
    assert_rel(res.body("coupler")[2], r["al3"], 1e-11)
    assert_rel(res.body("rocker")[2], r["al4"], 1e-11)
    # the point B from the rocker angle
    bx = D + C * np.cos(r["t4"])
    by = C * np.sin(r["t4"])
    np.testing.assert_allclose(res.point("B")[0], np.c_[bx, by], rtol=0, atol=1e-15)


def test_fourbar_lengths_override_the_sketch() -> None:
    """The sketch's A–B is 120.4 mm and O4–B 90.55 mm; [lengths] makes them exact."""
    mech = excavkin.load(EXAMPLES / "fourbar.toml")
    res = mech.solve({"crank": np.linspace(0, 6.28, 50)})
    a, b, o4 = (res.point(p)[0] for p in ("A", "B", "O4"))
    np.testing.assert_allclose(np.hypot(*(b - a).T), 0.120, rtol=1e-14)
    np.testing.assert_allclose(np.hypot(*(b - o4).T), 0.090, rtol=1e-14)
    np.testing.assert_allclose(np.hypot(*a.T), 0.040, rtol=1e-14)


def test_slider_crank_matches_closed_form() -> None:
    """Offset slider-crank, x_B = a·cos θ + sqrt(b² − (a·sin θ − e)²) (Norton eq. 4.17)."""
    a, b, e = 0.05, 0.15, 0.02
    mech = excavkin.load(EXAMPLES / "slider_crank.toml")
    th = np.radians(np.linspace(0.0, 360.0, 361))
    w, al = 25.0, -40.0
    res = mech.solve({"crank": th}, rates={"crank": w}, accels={"crank": al})
    assert res.status.all_ok
    s = a * np.sin(th) - e
    sp, spp = a * np.cos(th), -a * np.sin(th)
    root = np.sqrt(b * b - s * s)
    x = a * np.cos(th) + root
    x1 = -a * np.sin(th) - s * sp / root
    x2 = -a * np.cos(th) - (sp * sp + s * spp) / root - s * s * sp * sp / root**3
    pos, vel, acc = res.point("B")
    np.testing.assert_allclose(pos[:, 0], x, rtol=0, atol=1e-16)
    np.testing.assert_allclose(pos[:, 1], e, rtol=0, atol=1e-16)
    assert_rel(vel[:, 0], x1 * w, 1e-12)
    assert_rel(acc[:, 0], x2 * w * w + x1 * al, 1e-12)
    np.testing.assert_allclose(vel[:, 1], 0.0, atol=1e-15)
    # connecting-rod angle, A→B
    np.testing.assert_allclose(res.body("rod")[0], np.arctan2(-s, root), rtol=0, atol=1e-13)
    # the piston translates: C − B is constant, angle 0
    np.testing.assert_allclose(
        res.point("C")[0] - pos, np.tile([0.04, 0.0], (len(th), 1)), rtol=0, atol=1e-15
    )
    np.testing.assert_allclose(res.body("piston")[1], 0.0, atol=1e-12)
