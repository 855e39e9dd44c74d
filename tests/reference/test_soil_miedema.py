"""McKyes's model against a source's worked example, and Balovnev's A(x) where its branches
meet. NumPy and SciPy only.

Miedema S. A., *The Delft Sand, Clay and Rock Cutting Model* (open access), exercise 16.8.5:
rock cutting with a blade, no gravity, no adhesion —

    inputs : compressive strength 60 MPa, φ = 20°, δ = 13.33°, blade angle 60°, blade height
             and layer thickness 0.1 m, width 1 m
    printed: shear angle 43.33°, cohesion 21 MPa, normal stress on the shear plane 12.9 MPa,
             shear stress on it 25.7 MPa

McKyes's equation with only its cohesion term (γ = 0, c_a = 0, q = 0) is that model's
cohesive (shear-type) cut: P = c·d·w·N_c at the shear angle that minimises it. The checks
below rebuild every printed figure independently: the cohesion from the uniaxial test's Mohr
circle, the shear angle by minimising the wedge's cutting force (its own 2 × 2 equilibrium,
not McKyes's N factors) with SciPy, and the stresses from that equilibrium.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import brentq, minimize_scalar

from excavkin.errors import InputError
from excavkin.excavator.soil import (
    Soil,
    Tool,
    balovnev_a,
    cohesion_from_ucs,
    mckyes,
    mckyes_shear_plane,
)

DEG = np.pi / 180.0
UCS, PHI, DELTA, ALPHA, H, W = 60e6, 20 * DEG, 13.33 * DEG, 60 * DEG, 0.1, 1.0


def printed(value: float, shown: float, decimals: int) -> bool:
    """``value`` is ``shown`` to the printed precision (within half its last digit)."""
    return abs(value - shown) <= 0.5 * 10.0**-decimals * (1 + 1e-9)


def mohr_cohesion(ucs: float, phi: float) -> float:
    """The c whose line τ = c + σ·tan φ touches the uniaxial test's Mohr circle, found as a
    root: the distance from the circle's centre (ucs/2, 0) to the line equals its radius."""

    def gap(c: float) -> float:
        # the line tan φ·σ − τ + c = 0; distance of (ucs/2, 0) to it
        return abs(np.tan(phi) * 0.5 * ucs + c) / np.hypot(np.tan(phi), 1.0) - 0.5 * ucs

    return float(brentq(gap, 0.0, ucs, xtol=1e-6, rtol=1e-15))


def test_the_cohesion_follows_from_the_compressive_strength() -> None:
    c = cohesion_from_ucs(UCS, PHI)
    assert printed(c / 1e6, 21.0, 0)
    assert_allclose(c, mohr_cohesion(UCS, PHI), rtol=1e-13)
    assert_allclose(c / 1e6, 21.006226146, rtol=1e-10)  # 60·(1 − sin 20°)/(2·cos 20°) MPa
    with pytest.raises(InputError, match="compressive strength"):
        cohesion_from_ucs(-1.0, PHI)


def wedge(beta: float, c: float) -> tuple[float, float, float]:
    """The wedge's equilibrium without weight or adhesion, solved as a linear system: the
    blade's normal force N₂ (with friction N₂·tan δ down the blade) and the shear plane's
    normal force N₁ (with N₁·tan φ + c·A along it, A = h·w/sin β). Returns the horizontal
    cutting force and σ, τ on the plane."""
    a, b = ALPHA, beta
    cohesive = c * H * W / np.sin(b)
    # x (motion) and y (up): N₂(sin α, cos α) + N₂ tan δ (cos α, −sin α)
    #                        + N₁(−sin β, cos β) − (N₁ tan φ + C)(cos β, sin β) = 0
    m = np.array(
        [
            [np.sin(a) + np.tan(DELTA) * np.cos(a), -np.sin(b) - np.tan(PHI) * np.cos(b)],
            [np.cos(a) - np.tan(DELTA) * np.sin(a), np.cos(b) - np.tan(PHI) * np.sin(b)],
        ]
    )
    n2, n1 = np.linalg.solve(m, [cohesive * np.cos(b), cohesive * np.sin(b)])
    horizontal = n2 * (np.sin(a) + np.tan(DELTA) * np.cos(a))
    area = H * W / np.sin(b)
    return float(horizontal), float(n1 / area), float((n1 * np.tan(PHI) + cohesive) / area)


@pytest.fixture(scope="module")
def rock() -> Soil:
    # the exercise has no gravity: its weight is switched off by g = 0 in every call (a soil
    # has a density and a blow count > 0; the blows are Zelenin's and unused here)
    return Soil("rock", 2650.0, PHI, cohesion_from_ucs(UCS, PHI), DELTA, 0.0, 1.0)


def test_miedema_16_8_5_shear_angle(rock: Soil) -> None:
    plane = mckyes_shear_plane(H, ALPHA, rock, Tool(W), g=0.0)
    beta = float(plane.angle[0])
    assert printed(beta / DEG, 43.33, 2)  # (180 − 60 − 13.33 − 20)/2 = 43.335°
    # independent: the least horizontal force of the wedge's own equilibrium
    top = np.pi - ALPHA - DELTA - PHI
    best = minimize_scalar(
        lambda b: wedge(b, rock.cohesion)[0], bounds=(1e-3, top - 1e-3), method="bounded",
        options={"xatol": 1e-12},
    )  # fmt: skip
    assert_allclose(beta, best.x, atol=1e-7)
    # and the closed form of a cohesive cut: N_c = cos φ/(sin β·sin(α + δ + β + φ)) is least
    # at β = (π − α − δ − φ)/2
    assert_allclose(beta, 0.5 * top, atol=1e-7)


def test_miedema_16_8_5_stresses_on_the_shear_plane(rock: Soil) -> None:
    plane = mckyes_shear_plane(H, ALPHA, rock, Tool(W), g=0.0)
    sigma, tau = float(plane.normal_stress[0]), float(plane.shear_stress[0])
    assert printed(sigma / 1e6, 12.9, 1)
    assert printed(tau / 1e6, 25.7, 1)
    horizontal, sigma_ref, tau_ref = wedge(float(plane.angle[0]), rock.cohesion)
    assert_allclose([sigma, tau], [sigma_ref, tau_ref], rtol=1e-12)
    assert_allclose(tau, rock.cohesion + sigma * np.tan(PHI), rtol=1e-13)  # Mohr–Coulomb
    # the cutting force of McKyes's equation is the wedge's
    cut = mckyes(H, ALPHA, rock, Tool(W), g=0.0)
    assert_allclose(cut.along[0], horizontal, rtol=1e-12)


def test_the_plane_is_at_failure_with_weight_surcharge_and_adhesion() -> None:
    rng = np.random.default_rng(5)
    for _ in range(20):
        phi, delta = rng.uniform(10, 40) * DEG, rng.uniform(0, 25) * DEG
        s = Soil("s", rng.uniform(1200, 2200), phi, rng.uniform(0, 5e4), delta,
                 rng.uniform(0, 2e4), 1.0, rng.uniform(0, 1e4))  # fmt: skip
        d, a = rng.uniform(0.05, 1.0, 4), rng.uniform(30, 110, 4) * DEG
        plane = mckyes_shear_plane(d, a, s, Tool(rng.uniform(0.3, 2.0)))
        ok = np.isfinite(plane.angle)
        assert ok.any()
        assert_allclose(
            plane.shear_stress[ok], s.cohesion + plane.normal_stress[ok] * np.tan(phi),
            rtol=1e-9,
        )  # fmt: skip
    with pytest.raises(InputError, match="depth"):
        mckyes_shear_plane(0.0, ALPHA, s, Tool(1.0))


# ------------------------------------------------------------------ Balovnev's A(x) switch
def branches(x: np.ndarray, phi: float, delta: float) -> tuple[np.ndarray, np.ndarray]:
    """A's two branches, each evaluated at x (the Rankine zone and the log-spiral fan)."""
    sp = np.sin(phi)
    mu = np.arcsin(np.sin(delta) / sp)
    rankine = (1.0 - sp * np.cos(2.0 * x)) / (1.0 - sp)
    fan = (
        np.cos(delta) * (np.cos(delta) + np.sqrt(sp**2 - np.sin(delta) ** 2)) / (1.0 - sp)
        * np.exp((2.0 * x - np.pi + delta + mu) * np.tan(phi))
    )  # fmt: skip
    return rankine, fan


def test_balovnev_a_switches_where_its_branches_meet() -> None:
    phi, delta = np.meshgrid(np.linspace(5, 45, 41) * DEG, np.linspace(0, 1, 21))
    delta = delta * phi  # δ ≤ φ
    mu = np.arcsin(np.sin(delta) / np.sin(phi))
    x0 = 0.5 * (np.pi - delta - mu)
    rankine, fan = branches(x0, phi, delta)
    assert_allclose(rankine, fan, rtol=1e-13)  # equal at x₀: the derivation in the docs
    for p, dl, x in zip(phi.ravel(), delta.ravel(), x0.ravel(), strict=True):
        eps = 1e-7
        below, at, above = balovnev_a([x - eps, x, x + eps], p, dl)
        # |dA/dx| is at most 2·sin φ/(1 − sin φ) on the Rankine branch and 2·tan φ·A on the fan
        slope = 2.0 * max(np.sin(p) / (1.0 - np.sin(p)), np.tan(p) * above)
        assert abs(above - below) <= 1.01 * slope * 2 * eps + 1e-13 * at
    # switching elsewhere, as ½·asin(sin δ/sin φ) − δ, leaves a jump there
    p, dl = 30 * DEG, 20 * DEG
    elsewhere = 0.5 * np.arcsin(np.sin(dl) / np.sin(p)) - dl
    r, f = branches(np.array(elsewhere), p, dl)
    assert abs(r - f) > 0.1 * r  # 1.0015 against 0.7797: a 22 % jump
