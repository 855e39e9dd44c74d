"""Reference tests: bucket-turning mechanism of the EO-4112 rope backhoe (Maksimov).

Source: Yu.V. Maksimov, seeds ``000_be9f5f3a43aff791.txt`` / ``004_03940173d6e2ea14.txt``, and
``seeds/maksimov-rope-shovel-bucket.md`` (cited as "spec §x"). The paper has no numbers: the
tests check finite differences, loop closure, the spec's synthetic regression case (§4) and
each printed-formula error (§5).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from numpy.testing import assert_allclose

from excavkin.papers.rope_shovel import reference as mk

G = mk.EO4112_GEOMETRY
H = 2e-3
D1 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
K = np.arange(-4, 5, dtype=float)
PHI1 = np.radians(np.linspace(60.0, 150.0, 91))  # working quarter turn of the stick
OMEGA1 = np.random.default_rng(7).uniform(-0.6, 0.6, PHI1.size)


def _wrap(a: np.ndarray) -> np.ndarray:
    return np.arctan2(np.sin(a), np.cos(a))


def _fd(f: Callable[[float], np.ndarray], angle: bool = False) -> np.ndarray:
    vals = np.stack([f(k * H) for k in K])
    if angle:
        vals = _wrap(vals - vals[4])
    return np.tensordot(D1, vals, axes=1) / H


def _close(actual: np.ndarray, desired: np.ndarray, rtol: float = 1e-8) -> None:
    assert_allclose(actual, desired, rtol=rtol, atol=rtol * float(np.max(np.abs(desired))))


def _state_at(t: float) -> mk.BucketMechanismState:
    return mk.bucket_mechanism(G, PHI1 + OMEGA1 * t, OMEGA1)


S = mk.bucket_mechanism(G, PHI1, OMEGA1)


# --------------------------------------------------------------------------------------
# chosen geometry works over the quarter turn (spec §1, §6 checks)
# --------------------------------------------------------------------------------------


def test_geometry_assembles_over_quarter_turn() -> None:
    """Both four-bars assemble with transmission angles >= 39 deg over phi1 = 60..150 deg, the
    bucket turns ~93 deg relative to the stick, no dead point (sin(phi3 - phi2),
    sin(phi7p - phi6), sin(phi1 + alpha_tk) away from 0)."""
    for arr in S:
        assert np.all(np.isfinite(arr))
    assert np.all(np.abs(np.sin(S.eps)) > np.sin(np.radians(39)))
    assert np.all(np.abs(np.sin(S.eps2)) > np.sin(np.radians(39)))
    assert np.all(np.abs(np.sin(S.phi3 - S.phi2)) > 0.6)
    assert np.all(np.abs(np.sin(S.phi7p - S.phi6)) > 0.6)
    assert np.all(np.sin(S.phi1 + S.alpha_tk) > 0.3)
    turn = np.degrees(S.phi7p[-1] - S.phi7p[0])
    assert 85.0 < turn < 95.0
    assert np.all(np.diff(S.phi7p) > 0)  # monotone bucket turn


def _segments_cross(p1: np.ndarray, p2: np.ndarray, q1: np.ndarray, q2: np.ndarray) -> np.ndarray:
    def side(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
        return np.sign((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

    return (side(p1, p2, q1) * side(p1, p2, q2) < 0) & (side(q1, q2, p1) * side(q1, q2, p2) < 0)


def test_reading_of_crossing_links() -> None:
    """Module docstring / docs: 'projections of links 2 and 3 cross'. In the chosen geometry
    (i) C lies on ray O2B beyond B (theta0 = 0, l5 > l2), so link 3 ends inside lever 2+5;
    (ii) the contour O1ABO2 is self-intersecting: link 3 (AB) crosses the stick O1O2."""
    assert G.theta0 == 0.0 and G.l5 > G.l2
    o1 = np.zeros((2, PHI1.size))
    o2 = G.l1 * np.stack([np.cos(PHI1), np.sin(PHI1)])
    a = np.stack([np.full(PHI1.size, G.l4), np.zeros(PHI1.size)])
    b = a + G.l3 * np.stack([np.cos(S.phi3), np.sin(S.phi3)])
    assert np.all(_segments_cross(o1, o2, a, b))


# --------------------------------------------------------------------------------------
# loop closures (spec §3.3-3.5)
# --------------------------------------------------------------------------------------


def test_loop_closures() -> None:
    """Loop (8), the four-bar-2 loop, triangle (1) and vector eq. (16) close to 1e-12 m."""
    r1 = G.l1 * np.exp(1j * S.phi1) + G.l2 * np.exp(1j * S.phi2) - G.l3 * np.exp(1j * S.phi3) - G.l4
    assert_allclose(np.abs(r1), 0.0, atol=1e-12)
    r2 = (
        G.l5 * np.exp(1j * S.theta)
        + G.l6 * np.exp(1j * S.phi6)
        - G.l8
        - G.l7 * np.exp(1j * S.phi7p)
    )
    assert_allclose(np.abs(r2), 0.0, atol=1e-12)
    o1e = G.o1e_length
    assert_allclose(S.fe * np.cos(S.alpha_tk), G.l13 - o1e * np.cos(S.phi1), atol=1e-12)
    assert_allclose(S.fe * np.sin(S.alpha_tk), o1e * np.sin(S.phi1), atol=1e-12)
    r16 = G.ke + G.l9 * np.exp(1j * S.phi7p) - S.hk * np.exp(1j * S.gamma)
    assert_allclose(np.abs(r16), 0.0, atol=1e-12)
    assert_allclose(_wrap(S.phi7 + S.phi7p - np.pi), 0.0, atol=1e-12)


# --------------------------------------------------------------------------------------
# velocities vs finite differences (spec §3.1, (11), (12), (15), (19), omega10)
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("rate", "pos", "angle"),
    [
        ("omega2", "phi2", True),
        ("omega3", "phi3", True),
        ("omega7p", "phi7p", True),
        ("omega6", "phi6", True),
        ("omega10", "gamma", True),
        ("v_c1", "hk", False),
    ],
)
def test_rates_vs_fd(rate: str, pos: str, angle: bool) -> None:
    """Every angular rate / stroke speed against 8th-order differences, relative 1e-8."""
    d = _fd(lambda t: getattr(_state_at(t), pos), angle=angle)
    _close(getattr(S, rate), d)


def test_absolute_bucket_rate_and_rope_speed_vs_fd() -> None:
    """omega1 + omega7p = d(phi1 + phi7p)/dt; v_rope = -dFE/dt; omega1 from the rope, eq. (2)
    corrected, recovers the imposed omega1 (spec §3.1)."""
    d = _fd(lambda t: _state_at(t).bucket_to_horizon, angle=True)
    _close(S.omega7_abs, d)
    dfe = _fd(lambda t: _state_at(t).fe)
    _close(S.v_rope, -dfe)
    w1 = mk.stick_rate_from_rope(G.o1e_length, G.l13, PHI1, -dfe)
    _close(w1, OMEGA1)


def test_drive_chain() -> None:
    """v_tk = omega_motor R / (i a_p); omega1 < 0 while winding (spec §3.1)."""
    d = mk.EO4112_DRIVE
    v = mk.rope_speed(d.omega_motor, d.r_drum, d.gear_ratio, d.multiplicity)
    assert_allclose(v, 750 * 2 * np.pi / 60 * 0.25 / 40, rtol=1e-15)
    s = mk.bucket_mechanism_from_drive(G, d, PHI1)
    assert np.all(s.omega1 < 0)
    assert_allclose(s.v_rope, v[0], rtol=1e-12)


# --------------------------------------------------------------------------------------
# spec §4 synthetic regression case
# --------------------------------------------------------------------------------------


def test_spec_regression_case() -> None:
    """Spec §4 table (synthetic, ours): four-bar 1, four-bar 2, Ц1 and rope values."""
    fb1 = mk.fourbar1_position(1.0, 0.45, 1.1, 0.9, np.radians(70.0))
    assert_allclose(
        np.degrees([fb1.eps[0], fb1.v[0], fb1.delta[0], fb1.phi3[0], fb1.phi2[0]]),
        [77.271, 120.701, 23.681, 144.382, -138.347],
        atol=6e-4,
    )
    w2, w3 = mk.fourbar1_rates(1.0, 0.45, 1.1, np.radians(70.0), fb1.phi2, fb1.phi3, 1.0)
    assert_allclose([w3[0], w2[0]], [0.44252, 2.19410], atol=6e-6)
    fb2 = mk.fourbar2_position(0.5, 1.2, 0.45, 1.1, np.radians(50.0))
    assert_allclose(
        np.degrees([fb2.eps2[0], fb2.phi7[0], fb2.phi7p[0], fb2.phi6[0]]),
        [34.546, 154.546, 25.454, -9.092],
        atol=6e-4,
    )
    w7, _ = mk.fourbar2_rates(0.5, 1.2, 0.45, np.radians(50.0), fb2.phi6, fb2.phi7p, 1.0)
    assert_allclose(w7, 1.68115, atol=6e-6)
    hk, gamma = mk.cylinder_c1_position(0.8, 0.30, fb2.phi7p)
    v_c1, _ = mk.cylinder_c1_rates(0.8, 0.30, fb2.phi7p, 1.0)
    assert_allclose([hk[0], np.degrees(gamma[0]), v_c1[0]], [1.07861, 6.866, -0.09563], atol=6e-4)
    alpha, fe = mk.rope_triangle(2.3, 1.6, np.radians(100.0))
    assert_allclose([np.degrees(alpha[0]), fe[0]], [48.565, 3.02127], atol=6e-4)
    assert_allclose(2.3 * np.sin(np.radians(100.0) + alpha), 1.19953, atol=6e-6)


# --------------------------------------------------------------------------------------
# misprints (spec §5)
# --------------------------------------------------------------------------------------


def test_misprint_eq2_rope() -> None:
    """Spec §5.1: printed omega1 = v/(O1E sin(phi1 - alpha)) disagrees with -dFE/dt; the
    corrected -v/(O1E sin(phi1 + alpha)) agrees (see also the FD test above)."""
    dfe = _fd(lambda t: _state_at(t).fe)
    printed = mk.printed_eq2_omega1(G.o1e_length, G.l13, PHI1, -dfe)
    corrected = mk.stick_rate_from_rope(G.o1e_length, G.l13, PHI1, -dfe)
    _close(corrected, OMEGA1)
    assert np.max(np.abs(printed - OMEGA1)) > 0.1
    # spec §4 numbers: printed denominator 1.79838 instead of 1.19953
    alpha, _ = mk.rope_triangle(2.3, 1.6, np.radians(100.0))
    assert_allclose(2.3 * np.sin(np.radians(100.0) - alpha), 1.79838, atol=6e-6)


def test_misprint_eq4_quadrant() -> None:
    """Spec §5.2: printed (4) v = arctan(...) loses pi where l1 cos phi1 < l4; loop (8) then
    fails to close, while atan2 closes it."""
    bad = G.l1 * np.cos(PHI1) < G.l4
    assert np.any(bad)
    v_pr = mk.printed_eq4_v(G.l1, G.l4, PHI1)
    phi3_pr = v_pr + G.branch1 * S.delta
    # (8) with the printed phi3: |O2 + l2 e^{i phi2} - A - l3 e^{i phi3}| cannot be 0 for any phi2
    o2 = G.l1 * np.exp(1j * PHI1)
    b_pr = G.l4 + G.l3 * np.exp(1j * phi3_pr)
    assert np.all(np.abs(np.abs(b_pr[bad] - o2[bad]) - G.l2) > 1e-2)
    assert_allclose(_wrap(v_pr[~bad] - S.v[~bad]), 0.0, atol=1e-14)


def test_misprint_eq9_arcsin() -> None:
    """Spec §5.2: printed (9) phi2 = arcsin(...) returns pi - phi2 where
    l4 + l3 cos phi3 - l1 cos phi1 < 0; the first line of (8) then fails."""
    pr = mk.printed_eq9_phi2(G.l1, G.l2, G.l3, PHI1, S.phi3)
    neg = G.l4 + G.l3 * np.cos(S.phi3) - G.l1 * np.cos(PHI1) < 0
    assert np.any(neg)
    res = G.l2 * np.cos(pr) - (G.l4 + G.l3 * np.cos(S.phi3) - G.l1 * np.cos(PHI1))
    assert np.all(np.abs(res[neg]) > 1e-3)
    assert_allclose(res[~neg], 0.0, atol=1e-12)
    # spec §4: printed arcsin gives -41.653 deg instead of -138.347 deg
    fb1 = mk.fourbar1_position(1.0, 0.45, 1.1, 0.9, np.radians(70.0))
    pr = mk.printed_eq9_phi2(1.0, 0.45, 1.1, np.radians(70.0), fb1.phi3)
    assert_allclose(np.degrees(pr), -41.653, atol=6e-4)


def test_misprint_c2_sign() -> None:
    """Spec §5.5: printed c2 with +l8^2 gives cos eps2 = 3.064 (impossible) in the spec case
    and violates closure in the chosen geometry."""
    c2 = mk.printed_c2(0.5, 1.2, 0.45, 1.1)
    assert_allclose(c2 + 0.5 * 1.1 / (1.2 * 0.45) * np.cos(np.radians(50.0)), 3.064, atol=6e-4)
    cos_pr = mk.printed_c2(G.l5, G.l6, G.l7, G.l8) + G.l5 * G.l8 / (G.l6 * G.l7) * np.cos(S.theta)
    assert np.all(np.abs(cos_pr) > 1.0)
    # corrected c2: cos eps2 equals the cosine of the angle at D between DC and DE
    assert_allclose(np.cos(S.eps2), np.cos(S.phi6 - S.phi7p), atol=1e-12)


def test_misprint_eq13_index() -> None:
    """Spec §5.6: (13) with l8 in the denominator gives 106.881 deg instead of 154.546 deg, and
    does not close loop 2 in the chosen geometry."""
    pr = mk.printed_eq13_phi7(0.5, 1.2, 0.45, 1.1, np.radians(50.0))
    assert_allclose(np.degrees(pr), 106.881, atol=6e-4)
    pr = mk.printed_eq13_phi7(G.l5, G.l6, G.l7, G.l8, S.theta)
    d_pr = G.l8 + G.l7 * np.exp(1j * (np.pi - pr))
    c = G.l5 * np.exp(1j * S.theta)
    assert np.all(np.abs(np.abs(d_pr - c) - G.l6) > 1e-2)


def test_misprint_eq15_relative_rate() -> None:
    """Spec §5.7: (15) fed with omega2 instead of omega2 - omega1 disagrees with the
    differences whenever the stick moves; with the relative rate it agrees."""
    d = _fd(lambda t: _state_at(t).phi7p, angle=True)
    wrong = mk.printed_eq15_omega7(G.l5, G.l7, PHI1, S.phi2, S.phi6, S.phi7p, S.omega2)
    right = mk.printed_eq15_omega7(G.l5, G.l7, PHI1, S.phi2, S.phi6, S.phi7p, S.omega2 - S.omega1)
    _close(right, d)
    assert np.max(np.abs(wrong - d) / np.max(np.abs(d))) > 0.1


def test_misprint_eq15_phi7_convention() -> None:
    """Spec §5.8: (15) with phi7 = ∠O2ED of (13) instead of phi7p = pi - phi7 is wrong even
    with the corrected input rate."""
    d = _fd(lambda t: _state_at(t).phi7p, angle=True)
    wrong = mk.printed_eq15_omega7(G.l5, G.l7, PHI1, S.phi2, S.phi6, S.phi7, S.omega2 - S.omega1)
    assert np.max(np.abs(wrong - d) / np.max(np.abs(d))) > 0.1


def test_misprint_eq19_phi7_convention() -> None:
    """Spec §5.8: (16)-(19) with the paper's phi7 of (13) disagree with dHK/dt; with phi7p they
    agree (the FD test above)."""
    dhk = _fd(lambda t: _state_at(t).hk)
    wrong = mk.printed_eq19_v_c1(G.ke, G.l9, S.phi7, S.omega7p)
    assert np.max(np.abs(wrong - dhk) / np.max(np.abs(dhk))) > 0.1
    v_c1, _ = mk.cylinder_c1_rates(G.ke, G.l9, S.phi7p, S.omega7p)
    _close(v_c1, dhk)


def test_misprint_eq17_quadrant() -> None:
    """Spec §5.2: printed (17) gamma = arctan(...) loses pi when KE + EH cos phi7p < 0 (possible
    when KE < EH; not in the default geometry, shown on a synthetic Ц1); (16) then fails."""
    ke, eh, p7 = 0.3, 0.5, np.radians([150.0, 40.0])
    hk, gamma = mk.cylinder_c1_position(ke, eh, p7)
    pr = mk.printed_eq17_gamma(ke, eh, p7)
    res = ke + eh * np.cos(p7) - hk * np.cos(pr)
    assert abs(res[0]) > 0.1
    assert abs(res[1]) < 1e-12
    assert_allclose(ke + eh * np.cos(p7) - hk * np.cos(gamma), 0.0, atol=1e-15)


def test_misprint_vector_loop_before_eq7() -> None:
    """Docs correction 11 (issue 12): the vector loop printed above (7), l1 + l2 + l3 = l4, and
    its projections (7), which carry -l3 cos phi3, -l3 sin phi3. phi3 of (6) is the angle of
    A->B (B - A = l3 e^{i phi3} to 1e-12 m), so with every vector l_i = l_i e^{i phi_i} the
    loop O1 -> O2 -> B -> A = O1 -> A reads l1 + l2 - l3 = l4: it closes to 1e-12 m, while the
    printed line leaves 2 l3 (1.96 m here, 2.2 m in the spec §4 case). The projections (7) and
    everything after them are right as printed (test_loop_closures)."""
    o2 = G.l1 * np.exp(1j * S.phi1)
    b = o2 + G.l2 * np.exp(1j * S.phi2)
    assert_allclose(np.abs(b - G.l4 - G.l3 * np.exp(1j * S.phi3)), 0.0, atol=1e-12)
    l1, l2, l3 = (
        G.l1 * np.exp(1j * S.phi1),
        G.l2 * np.exp(1j * S.phi2),
        G.l3 * np.exp(1j * S.phi3),
    )
    assert_allclose(np.abs(l1 + l2 - l3 - G.l4), 0.0, atol=1e-12)
    printed = np.abs(l1 + l2 + l3 - G.l4)
    assert_allclose(printed, 2 * G.l3, rtol=1e-12)
    # (7) as printed (its two projections, phi4 = 0) closes
    assert_allclose(l1.real + l2.real - G.l3 * np.cos(S.phi3), G.l4, atol=1e-12)
    assert_allclose(l1.imag + l2.imag - G.l3 * np.sin(S.phi3), 0.0, atol=1e-12)
    fb1 = mk.fourbar1_position(1.0, 0.45, 1.1, 0.9, np.radians(70.0))
    z1, z2, z3 = (
        np.exp(1j * np.radians(70.0)),
        0.45 * np.exp(1j * fb1.phi2),
        1.1 * np.exp(1j * fb1.phi3),
    )
    assert_allclose(np.abs(z1 + z2 - z3 - 0.9), 0.0, atol=1e-12)
    assert_allclose(np.abs(z1 + z2 + z3 - 0.9), 2.2, rtol=1e-12)


def test_branch_flags_validated() -> None:
    """Branch flags accept only +1/-1 (spec §5.11)."""
    with pytest.raises(ValueError, match="branch"):
        mk.fourbar1_position(1.0, 0.45, 1.1, 0.9, 1.0, branch=0)
    other = mk.fourbar1_position(1.0, 0.45, 1.1, 0.9, np.radians(70.0), branch=-1)
    fb1 = mk.fourbar1_position(1.0, 0.45, 1.1, 0.9, np.radians(70.0))
    assert_allclose(other.phi3 - other.v, -(fb1.phi3 - fb1.v), atol=1e-14)
