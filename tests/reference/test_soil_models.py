"""The three soil-cutting models against independent computations.

No source's worked example was at hand for these checks (Zelenin 1968, Balovnev 1981 and
McKyes 1985 were not accessible here), so every check is independent of the implementation:

* McKyes: the closed-form N factors against the wedge's force equilibrium solved as a linear
  system; the least force over the failure angle against mpmath (40 digits) and a dense grid;
  the classical limits it must reproduce — Rankine's (Bell's) passive pressure on a smooth
  vertical face, ½γd²K_p + 2cd√K_p + qdK_p, and Coulomb's passive coefficient of a rough
  vertical face;
* Balovnev: A(x) continuous where its branches meet, A(0) = 1, A(π/2) = K_p for a smooth face;
  the force re-evaluated in 40-digit arithmetic; V/H = cot(α + δ);
* Zelenin: one point evaluated by hand in kgf and cm (mpmath), and the h^1.35 scaling.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from excavkin.errors import InputError
from excavkin.excavator.soil import (
    KGF,
    SOILS,
    Soil,
    Tool,
    balovnev,
    balovnev_a,
    mckyes,
    mckyes_factors,
    mckyes_failure_angle,
    resistance,
    zelenin,
)

mp.mp.dps = 40
DEG = np.pi / 180.0


def _soil(**kw: float) -> Soil:
    base = {
        "density": 1850.0,
        "friction_angle": 30 * DEG,
        "cohesion": 20e3,
        "metal_friction": 18 * DEG,
        "adhesion": 6e3,
        "blows": 8.0,
        "surcharge": 3e3,
    }
    return Soil("test", **(base | kw))  # type: ignore[arg-type]


def _wedge_force(a: float, b: float, d: float, s: Soil) -> float:
    """P per unit width from the wedge's equilibrium: weight, surcharge, cohesion on the
    failure plane, adhesion on the face, and the two unknown resultants P (at δ to the face's
    normal) and R (at φ to the failure plane's normal), solved as a 2×2 linear system."""
    g = s.unit_weight()
    cot = 1.0 / np.tan(a) + 1.0 / np.tan(b)
    known = np.array([0.0, -(0.5 * g * d * d + s.surcharge * d) * cot])
    known += s.cohesion * d / np.sin(b) * np.array([-np.cos(b), -np.sin(b)])
    known += s.adhesion * d / np.sin(a) * np.array([np.cos(a), -np.sin(a)])
    ad, bp = a + s.metal_friction, b + s.friction_angle
    M = np.array([[np.sin(ad), -np.sin(bp)], [np.cos(ad), np.cos(bp)]])
    return float(np.linalg.solve(M, -known)[0])


def test_mckyes_factors_are_the_wedge_equilibrium() -> None:
    rng = np.random.default_rng(7)
    s = _soil()
    for _ in range(40):
        a = rng.uniform(20, 110) * DEG
        top = np.pi - a - s.metal_friction - s.friction_angle
        b = rng.uniform(0.05, 0.95) * top
        d = rng.uniform(0.05, 1.0)
        N = mckyes_factors(a, b, s.friction_angle, s.metal_friction)
        p = s.unit_weight() * d * d * N.gamma + s.cohesion * d * N.c
        p += s.surcharge * d * N.q + s.adhesion * d * N.a
        np.testing.assert_allclose(p, _wedge_force(a, b, d, s), rtol=1e-11)


def _mp_force(a: float, d: float, s: Soil) -> tuple[mp.mpf, mp.mpf]:
    """The least P over β and its β, in 40-digit arithmetic (root of dP/dβ)."""
    phi, delta = mp.mpf(s.friction_angle), mp.mpf(s.metal_friction)
    A, D = mp.mpf(a), mp.mpf(d)
    g = mp.mpf(s.density) * mp.mpf("9.80665")

    def P(b: mp.mpf) -> mp.mpf:
        den = mp.sin(A + delta + b + phi) / mp.sin(b + phi)
        ng = (mp.cot(A) + mp.cot(b)) / (2 * den)
        nc = (1 + mp.cot(b) * mp.cot(b + phi)) / den
        nq = (mp.cot(A) + mp.cot(b)) / den
        na = (1 - mp.cot(A) * mp.cot(b + phi)) / den
        return (
            g * D**2 * ng
            + mp.mpf(s.cohesion) * D * nc
            + mp.mpf(s.surcharge) * D * nq
            + mp.mpf(s.adhesion) * D * na
        )

    top = mp.pi - A - delta - phi
    grid = [top * k / 400 for k in range(1, 400)]
    b0 = min(grid, key=P)
    b = mp.findroot(lambda x: mp.diff(P, x), b0)
    return P(b), b


@pytest.mark.parametrize(
    ("a_deg", "d", "kw"),
    [
        (45.0, 0.3, {}),
        (70.0, 0.6, {"cohesion": 0.0, "adhesion": 0.0}),
        (100.0, 0.2, {"friction_angle": 20 * DEG, "metal_friction": 12 * DEG}),
        (30.0, 1.0, {"surcharge": 0.0, "cohesion": 60e3}),
    ],
)
def test_mckyes_least_force_against_mpmath(a_deg: float, d: float, kw: dict[str, float]) -> None:
    s = _soil(**kw)
    tool = Tool(1.3)
    a = a_deg * DEG
    P, b = _mp_force(a, d, s)
    beta = mckyes_failure_angle([d], [a], s, tool)
    r = mckyes([d], [a], s, tool)
    # P is flat at its least: β to √ε, the force to round-off
    np.testing.assert_allclose(beta[0], float(b), rtol=1e-6)
    along = 1.3 * float(P) * np.sin(a + s.metal_friction) + s.adhesion * d * 1.3 / np.tan(a)
    normal = 1.3 * float(P) * np.cos(a + s.metal_friction) - s.adhesion * d * 1.3
    np.testing.assert_allclose(r.along[0], along, rtol=1e-12)
    np.testing.assert_allclose(r.normal[0], normal, rtol=1e-10, atol=1e-9 * along)
    # and no failure angle of a dense grid gives less
    top = np.pi - a - s.metal_friction - s.friction_angle
    grid = np.linspace(1e-4, top - 1e-4, 20001)
    N = mckyes_factors(a, grid, s.friction_angle, s.metal_friction)
    p = s.unit_weight() * d * d * N.gamma + s.cohesion * d * N.c
    p = p + s.surcharge * d * N.q + s.adhesion * d * N.a
    assert np.min(p[p > 0]) >= float(P) * (1 - 1e-12)


def test_mckyes_smooth_vertical_face_is_rankine_and_bell() -> None:
    """δ = c_a = 0, α = 90°: P = ½γd²K_p + 2cd√K_p + qdK_p, β = 45° − φ/2."""
    for phi_deg in (15.0, 25.0, 35.0):
        phi = phi_deg * DEG
        s = _soil(friction_angle=phi, metal_friction=0.0, adhesion=0.0)
        d, w = 0.7, 1.1
        kp = np.tan(0.25 * np.pi + 0.5 * phi) ** 2
        expect = w * (0.5 * s.unit_weight() * d * d * kp + 2 * s.cohesion * d * np.sqrt(kp))
        expect += w * s.surcharge * d * kp
        r = mckyes([d], [0.5 * np.pi], s, Tool(w))
        np.testing.assert_allclose(r.along[0], expect, rtol=1e-12)
        np.testing.assert_allclose(r.normal[0], 0.0, atol=1e-9 * expect)
        np.testing.assert_allclose(r.failure_angle[0], 0.25 * np.pi - 0.5 * phi, rtol=1e-6)


def test_mckyes_rough_vertical_face_is_coulomb() -> None:
    """c = q = c_a = 0, α = 90°, wall friction δ: Coulomb's passive force
    P = ½γd²·cos²φ / (cos δ·(1 − √(sin(φ+δ)·sin φ / cos δ))²), at δ to the face's normal."""
    for phi_deg, delta_deg in ((30.0, 10.0), (35.0, 20.0), (25.0, 25.0)):
        phi, delta = phi_deg * DEG, delta_deg * DEG
        s = _soil(
            friction_angle=phi, metal_friction=delta, cohesion=0.0, adhesion=0.0, surcharge=0.0
        )
        d = 0.8
        kp = np.cos(phi) ** 2 / (
            np.cos(delta) * (1 - np.sqrt(np.sin(phi + delta) * np.sin(phi) / np.cos(delta))) ** 2
        )
        P = 0.5 * s.unit_weight() * d * d * kp
        r = mckyes([d], [0.5 * np.pi], s, Tool(1.0))
        np.testing.assert_allclose(r.along[0], P * np.cos(delta), rtol=1e-12)
        np.testing.assert_allclose(r.normal[0], -P * np.sin(delta), rtol=1e-11)


def test_balovnev_a_is_continuous_and_has_its_limits() -> None:
    for phi_deg, delta_deg in ((20.0, 10.0), (35.0, 20.0), (40.0, 0.0), (30.0, 30.0)):
        phi, delta = phi_deg * DEG, delta_deg * DEG
        x0 = 0.5 * (np.pi - delta - np.arcsin(np.sin(delta) / np.sin(phi)))
        lo, hi = balovnev_a([x0 - 1e-9, x0 + 1e-9], phi, delta)
        np.testing.assert_allclose(lo, hi, rtol=1e-8)
        # the two branches, in 40 digits, meet exactly at x0
        P, D, X = mp.mpf(phi), mp.mpf(delta), mp.mpf(x0)
        mu = mp.asin(mp.sin(D) / mp.sin(P))
        rankine = (1 - mp.sin(P) * mp.cos(2 * X)) / (1 - mp.sin(P))
        fan = (
            mp.cos(D)
            * (mp.cos(D) + mp.sqrt(mp.sin(P) ** 2 - mp.sin(D) ** 2))
            / (1 - mp.sin(P))
            * mp.exp((2 * X - mp.pi + D + mu) * mp.tan(P))
        )
        assert abs(rankine - fan) < mp.mpf(10) ** -12 * rankine
        np.testing.assert_allclose(balovnev_a(0.0, phi, delta), 1.0, rtol=1e-15)
    kp = np.tan(0.25 * np.pi + 15 * DEG) ** 2
    np.testing.assert_allclose(balovnev_a(0.5 * np.pi, 30 * DEG, 0.0), kp, rtol=1e-14)


def test_balovnev_force_in_forty_digits() -> None:
    s = _soil()
    tool = Tool(1.2, edge_thickness=0.02, edge_angle=70 * DEG, wall_thickness=0.03, wall_length=0.9)
    d, a = 0.35, 40 * DEG
    r = balovnev([d], [a], s, tool)
    P, D, A = mp.mpf(s.friction_angle), mp.mpf(s.metal_friction), mp.mpf(a)
    g = mp.mpf(s.density) * mp.mpf("9.80665")
    mu = mp.asin(mp.sin(D) / mp.sin(P))
    x0 = (mp.pi - D - mu) / 2

    def Af(x: mp.mpf) -> mp.mpf:
        if x <= x0:
            return (1 - mp.sin(P) * mp.cos(2 * x)) / (1 - mp.sin(P))
        return (
            mp.cos(D)
            * (mp.cos(D) + mp.sqrt(mp.sin(P) ** 2 - mp.sin(D) ** 2))
            / (1 - mp.sin(P))
            * mp.exp((2 * x - mp.pi + D + mu) * mp.tan(P))
        )

    dd, w, e, ae = (
        mp.mpf(d),
        mp.mpf(tool.width),
        mp.mpf(tool.edge_thickness),
        mp.mpf(tool.edge_angle),
    )
    base = mp.mpf(s.cohesion) * mp.cot(P) + mp.mpf(s.surcharge)
    ka = (1 - mp.sin(P)) / (1 + mp.sin(P))
    H = w * dd * Af(A) * (1 + mp.cot(A) * mp.tan(D)) * (g * dd / 2 + base)
    H += w * e * Af(ae) * (1 + mp.tan(D) * mp.cot(ae)) * (g * e / 2 + base + g * dd * ka)
    H += (
        dd
        * Af(mp.pi / 2)
        * (2 * mp.mpf(tool.wall_thickness) + 4 * mp.mpf(tool.wall_length) * mp.tan(D))
        * (g * dd / 2 + base)
    )
    np.testing.assert_allclose(r.along[0], float(H), rtol=1e-13)
    np.testing.assert_allclose(r.normal[0], float(H * mp.cot(A + D)), rtol=1e-13)


def test_zelenin_by_hand_and_its_depth_exponent() -> None:
    s = _soil(blows=10.0)
    tool = Tool(1.0, teeth=0.8, walls=1.1, normal_ratio=0.3)
    r = zelenin([0.2, 0.4], [45 * DEG, 45 * DEG], s, tool)
    kgf = mp.mpf(10) * mp.mpf(20) ** mp.mpf("1.35") * mp.mpf("3.6") * mp.mpf("1.3375")
    expect = float(kgf * mp.mpf("0.8") * mp.mpf("1.1") * mp.mpf("9.80665"))
    np.testing.assert_allclose(r.along[0], expect, rtol=1e-13)
    np.testing.assert_allclose(r.along[1] / r.along[0], 2.0**1.35, rtol=1e-13)
    np.testing.assert_allclose(r.normal, 0.3 * r.along, rtol=1e-15)
    assert KGF == 9.80665


@pytest.mark.parametrize("model", ["zelenin", "balovnev", "mckyes"])
def test_out_of_the_soil_nothing_resists(model: str) -> None:
    r = resistance(model, [-0.1, 0.0, 0.2], [0.8, 0.8, 0.8], SOILS["loam"], Tool(1.0))
    np.testing.assert_array_equal(r.along[:2], 0.0)
    np.testing.assert_array_equal(r.normal[:2], 0.0)
    assert r.along[2] > 0.0


def test_bad_inputs_are_refused_by_name() -> None:
    with pytest.raises(InputError, match="δ ≤ φ"):
        balovnev([0.2], [0.8], _soil(metal_friction=35 * DEG), Tool(1.0))
    with pytest.raises(InputError, match="unknown soil model 'coulomb'"):
        resistance("coulomb", [0.2], [0.8], SOILS["sand"], Tool(1.0))
    with pytest.raises(InputError, match="cohesion"):
        _soil(cohesion=-1.0)
    with pytest.raises(InputError, match="width"):
        Tool(0.0)


def test_a_frictionless_soil_is_refused_by_balovnev_before_any_arithmetic() -> None:
    """φ = 0: the clear refusal, with no division-by-zero warning ahead of it."""
    import dataclasses
    import warnings

    from excavkin.excavator.soil import SOILS, Tool, balovnev

    soil = dataclasses.replace(SOILS["clay"], friction_angle=0.0, metal_friction=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(InputError, match="0 < φ < 90°"):
            balovnev(np.array([0.2]), np.array([1.0]), soil, Tool(width=1.2))
