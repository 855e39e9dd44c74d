"""Reference tests: cylinder-rocker module with an internal driving link (Pasika & Koruniak).

Paper: V. Pasika, P. Koruniak, "Kinematic analysis of a lever mechanism with an internal
driving link" (seed 003). Specification: ``seeds/pasika-internal-driving-link.md``
("spec §x" below). Reference table: ``tests/reference/data/pasika_table_4_3.csv``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from excavkin.papers.errors import ReferenceAssemblyError, ReferenceSingularityError
from excavkin.papers.pasika import reference as p

D = p.PASIKA_PAPER
DATA = Path(__file__).parent / "data" / "pasika_table_4_3.csv"

_C1 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
_C2 = np.array([-1 / 560, 8 / 315, -1 / 5, 8 / 5, -205 / 72, 8 / 5, -1 / 5, 8 / 315, -1 / 560])
_K = np.arange(-4, 5)


def _fd(f, x, h, order):
    """8th-order central finite difference of f (vectorised) at x, shape (n,)."""
    c = _C1 if order == 1 else _C2
    vals = np.stack([f(x + k * h) for k in _K])
    return np.tensordot(c, vals, axes=1) / h**order


def _smooth_law(t):
    """A non-polynomial rod law used to show the formulas accept any (s, v21, a21)."""
    s = 0.25 * (1.0 - np.cos(0.6 * t)) + 0.01 * t
    v = 0.15 * np.sin(0.6 * t) + 0.01
    a = 0.09 * np.cos(0.6 * t)
    return s, v, a


def test_data_reading_and_assembly():
    """Spec §4.1: literal data order (l_OA0 = 0.45, l_AB = 0.9, a = 0.8, b = 1.2) cannot be
    assembled (0.45 + 0.9 < 1.442); the adopted reading can. l_OB = 1.00623, gamma2 = 26.565."""
    assert_allclose(D.l_ob, 1.00623, atol=5e-6)
    assert_allclose(math.degrees(D.gamma2), 26.565, atol=5e-4)
    literal = p.PasikaData(a=0.8, b=1.2, l_oa0=0.45, l_ab=0.9)
    with pytest.raises(ReferenceAssemblyError):
        p.positions(np.array([0.0, 0.25, 0.5]), literal)
    res = p.positions(np.array([0.0]), literal, on_failure="nan")
    assert res.status[0] == p.STATUS_NOT_ASSEMBLABLE
    assert np.isnan(res.phi1[0])


def test_reference_table_4_3():
    """Spec §4.3 table, every column, to the printed digits (half a unit of the last digit)."""
    tab = np.loadtxt(DATA, delimiter=",", skiprows=1)
    t = tab[:, 0]
    s, v, a = p.cubic_law(t, D)
    k = p.kinematics(s, v, a, D)
    digits = [4, 4, 4, 4, 5, 5, 4, 5, 5]  # decimals printed per column after t
    ours = [
        s,
        v,
        a,
        np.rad2deg(k.positions.phi1),
        k.velocities.omega1,
        k.accelerations.eps1,
        np.rad2deg(k.positions.phi3),
        k.velocities.omega3,
        k.accelerations.eps3,
    ]
    for col, (val, dg) in enumerate(zip(ours, digits, strict=True), start=1):
        assert_allclose(val, tab[:, col], rtol=0, atol=0.5 * 10.0**-dg + 1e-12, err_msg=f"{col}")


def test_loop_closure():
    """Spec §3.2: O + l_OA e^{i phi1} = B + l_AB e^{i phi3}, B = (-a, b), to 1e-12 m."""
    s = np.linspace(-0.2, 0.6, 801)
    pos = p.positions(s, D)
    lhs = pos.l_oa * np.exp(1j * pos.phi1)
    rhs = complex(-D.a, D.b) + D.l_ab * np.exp(1j * pos.phi3)
    assert_allclose(np.abs(lhs - rhs), 0.0, atol=1e-12)


def test_motion_law_eq4_6():
    """Eqs (4)-(6), spec §3.1/§4.2: boundary conditions (5); v21 max 1.5 H/T = 0.15 m/s at
    T/2; a21 from +0.12 to -0.12 m/s^2; v21, a21 are derivatives of s (8th-order FD)."""
    s, v, a = p.cubic_law(np.array([0.0, D.duration / 2, D.duration]), D)
    assert_allclose(s, [0.0, 0.25, 0.5], atol=1e-15)
    assert_allclose(v, [0.0, 0.15, 0.0], atol=1e-15)
    assert_allclose(a, [0.12, 0.0, -0.12], atol=1e-15)
    t = np.linspace(0.5, 4.5, 41)
    assert_allclose(
        p.cubic_law(t, D)[1], _fd(lambda x: p.cubic_law(x, D)[0], t, 1e-2, 1), rtol=1e-10
    )
    assert_allclose(
        p.cubic_law(t, D)[2],
        _fd(lambda x: p.cubic_law(x, D)[1], t, 1e-2, 1),
        rtol=1e-9,
        atol=1e-12,
    )


@pytest.mark.parametrize("law", ["cubic", "smooth"])
def test_derivatives_vs_finite_differences(law):
    """Eqs (8), (9), (11), (12), spec §3.3-3.4: omega1, omega3, eps1, eps3 against 8th-order
    central differences in time of phi1(s(t)), phi3(s(t)), <= 1e-8 relative, for the paper's
    cubic law and for an arbitrary smooth law (the formulas accept any s, v21, a21)."""
    if law == "cubic":

        def f(t):
            return p.cubic_law(t, D)

        t = np.linspace(0.3, 4.7, 45)
    else:
        f = _smooth_law
        t = np.linspace(0.0, 6.0, 61)
    s, v, a = f(t)
    k = p.kinematics(s, v, a, D)

    def phi1(x):
        return p.positions(f(x)[0], D).phi1

    def phi3(x):
        return p.positions(f(x)[0], D).phi3

    h = 2e-2
    scale_w, scale_e = 0.2, 0.2
    assert_allclose(k.velocities.omega1, _fd(phi1, t, h, 1), rtol=1e-8, atol=1e-10 * scale_w)
    assert_allclose(k.velocities.omega3, _fd(phi3, t, h, 1), rtol=1e-8, atol=1e-10 * scale_w)
    assert_allclose(k.accelerations.eps1, _fd(phi1, t, h, 2), rtol=1e-8, atol=1e-10 * scale_e)
    assert_allclose(k.accelerations.eps3, _fd(phi3, t, h, 2), rtol=1e-8, atol=1e-10 * scale_e)


def _eps1_printed_coriolis(k, v):
    """Eq (11) with the extracted Coriolis term 2 omega3 v21 (misprint, spec §5 item 1)."""
    dphi = k.positions.phi1 - k.positions.phi3
    w3, e3 = k.velocities.omega3, k.accelerations.eps3
    num = D.l_ab * (e3 * np.cos(dphi) + w3**2 * np.sin(dphi)) - 2.0 * w3 * v
    return num / k.positions.l_oa


def test_coriolis_misprint():
    """Spec §5 item 1: with the printed Coriolis 2 omega3 v21, eps1 is off by up to 13.8 % of
    max |eps1| against finite differences, incompatible with the paper's own 0.2 % claim;
    with 2 omega1 v21 the error is < 1e-8. eps3 (12) does not contain the Coriolis term."""
    t = np.linspace(0.1, 4.9, 481)  # FD stencil (+-0.08 s) stays inside the stroke
    s, v, a = p.cubic_law(t, D)
    k = p.kinematics(s, v, a, D)
    fd = _fd(lambda x: p.positions(p.cubic_law(x, D)[0], D).phi1, t, 2e-2, 2)
    rng = np.max(np.abs(fd))  # 0.10034 rad/s^2 at t = 0
    err_printed = np.max(np.abs(_eps1_printed_coriolis(k, v) - fd)) / rng
    err_ours = np.max(np.abs(k.accelerations.eps1 - fd)) / rng
    assert 0.13 < err_printed < 0.145  # 13.8 %
    assert err_ours < 1e-8
    assert_allclose(k.accelerations.coriolis, 2.0 * k.velocities.omega1 * v, rtol=1e-15)


def test_velocity_components_eq7():
    """Eq (7), spec §3.3: v_A = v_A^e + v_A^r; v_A is perpendicular to BA, v_A^e to OA,
    v_A^r along OA; v_A equals the time derivative of A's position (8th-order FD)."""
    t = np.linspace(0.3, 4.7, 23)
    s, v, a = p.cubic_law(t, D)
    vel = p.velocities(s, v, D)
    pos = p.positions(s, D)
    assert_allclose(vel.v_a, vel.v_a_e + vel.v_a_r, atol=1e-14)
    e3 = np.stack([np.cos(pos.phi3), np.sin(pos.phi3)], axis=-1)
    e1 = np.stack([np.cos(pos.phi1), np.sin(pos.phi1)], axis=-1)
    assert_allclose(np.sum(vel.v_a * e3, axis=1), 0.0, atol=1e-15)
    assert_allclose(np.sum(vel.v_a_e * e1, axis=1), 0.0, atol=1e-15)
    assert_allclose(np.sum(vel.v_a_r * e1, axis=1), v, atol=1e-15)

    def ax(x):
        q = p.positions(p.cubic_law(x, D)[0], D)
        return q.l_oa * np.cos(q.phi1)

    def ay(x):
        q = p.positions(p.cubic_law(x, D)[0], D)
        return q.l_oa * np.sin(q.phi1)

    assert_allclose(vel.v_a[:, 0], _fd(ax, t, 2e-2, 1), rtol=1e-8, atol=1e-12)
    assert_allclose(vel.v_a[:, 1], _fd(ay, t, 2e-2, 1), rtol=1e-8, atol=1e-12)
    acc = p.accelerations(s, v, a, D)
    n1 = np.stack([-np.sin(pos.phi1), np.cos(pos.phi1)], axis=-1)
    assert_allclose(acc.a_coriolis, (2 * vel.omega1 * v)[:, None] * n1, atol=1e-15)


def test_further_reference_values():
    """Spec §4.3 further values: omega1 max 0.10952 at t = 2.347 s, omega3 max 0.15766 at
    2.619 s; eps1 = 0 at 2.347 s, eps3 = 0 at 2.619 s; phi1 - phi3 from 56.22 to 47.26 deg;
    monotonic angles."""
    t = np.linspace(0.0, D.duration, 500_001)
    s, v, a = p.cubic_law(t, D)
    k = p.kinematics(s, v, a, D)
    w1, w3 = k.velocities.omega1, k.velocities.omega3
    assert_allclose(w1.max(), 0.10952, atol=5e-6)
    assert_allclose(t[np.argmax(w1)], 2.347, atol=5e-4)
    assert_allclose(w3.max(), 0.15766, atol=5e-6)
    assert_allclose(t[np.argmax(w3)], 2.619, atol=5e-4)
    for eps, t0 in ((k.accelerations.eps1, 2.347), (k.accelerations.eps3, 2.619)):
        i = np.flatnonzero(np.sign(eps[:-1]) != np.sign(eps[1:]))
        assert i.size == 1
        assert_allclose(t[i[0]], t0, atol=5e-4)
    dphi = np.rad2deg(k.positions.phi1 - k.positions.phi3)
    assert_allclose([dphi[0], dphi[-1]], [56.22, 47.26], atol=5e-3)
    assert np.all(np.diff(dphi) < 0)
    assert np.all(np.diff(k.positions.phi1) > 0)
    assert np.all(np.diff(k.positions.phi3) > 0)


def test_soft_shock_jumps():
    """Spec §3.1, §4.3: soft shocks at the ends: a21 jumps by 6H/T^2 = 0.12; eps1 by +0.1003
    and +0.0853, eps3 by +0.1203 and +0.1362 rad/s^2 at t = 0 and t = T."""
    j = p.soft_shock_jumps(D)
    assert_allclose([j["a21_start"], j["a21_end"]], [0.12, 0.12], rtol=1e-14)
    assert_allclose(
        [j["eps1_start"], j["eps1_end"], j["eps3_start"], j["eps3_end"]],
        [0.1003, 0.0853, 0.1203, 0.1362],
        atol=5e-5,
    )
    # at rest outside [0, T]
    s, v, a = p.cubic_law(np.array([-1.0, 6.0]), D)
    assert_allclose(np.c_[s, v, a], [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]], atol=0)


def test_linearity_of_angular_accelerations():
    """Spec §4.2-4.3: eps(t) "almost linear": the linear-fit residual is 6 % (eps1) and 4 %
    (eps3) of the range."""
    t = np.linspace(0.0, D.duration, 5001)
    s, v, a = p.cubic_law(t, D)
    acc = p.accelerations(s, v, a, D)
    for eps, expected in ((acc.eps1, 0.06), (acc.eps3, 0.04)):
        fit = np.polyval(np.polyfit(t, eps, 1), t)
        resid = np.max(np.abs(eps - fit)) / (eps.max() - eps.min())
        assert_allclose(resid, expected, atol=0.01)


def test_inverse_stroke_relations():
    """Spec §6: stroke <-> phi3 and stroke <-> phi1 round trips, to 1e-12 m."""
    s = np.linspace(0.0, 0.5, 101)
    pos = p.positions(s, D)
    assert_allclose(p.stroke_from_phi3(pos.phi3, D), s, atol=1e-12)
    assert_allclose(p.stroke_from_phi1(pos.phi1, D), s, atol=1e-12)
    assert_allclose(p.phi3_from_stroke(s, D), pos.phi3, rtol=0, atol=0)
    assert_allclose(p.phi1_from_stroke(s, D), pos.phi1, rtol=0, atol=0)
    with pytest.raises(ReferenceAssemblyError):
        p.stroke_from_phi3(np.array([math.radians(200.0)]), D)


def test_singularity_flag():
    """Spec §5-6: the dead point sin(phi1 - phi3) = 0 (l_OA = l_OB + l_AB, cylinder collinear
    with the rocker) raises, or is flagged with status 2 and NaN rates with on_failure="nan"."""
    s_dead = D.l_ob + D.l_ab - D.l_oa0
    with pytest.raises(ReferenceSingularityError):
        p.velocities(np.array([0.1, s_dead]), np.array([0.1, 0.1]), D)
    k = p.kinematics(
        np.array([0.1, s_dead]),
        np.array([0.1, 0.1]),
        np.array([0.0, 0.0]),
        D,
        on_failure="nan",
    )
    assert k.status.tolist() == [p.STATUS_OK, p.STATUS_SINGULAR]
    assert np.isfinite(k.velocities.omega3[0]) and np.isnan(k.velocities.omega3[1])
    assert np.isnan(k.accelerations.eps1[1])
    with pytest.raises(ReferenceAssemblyError):
        p.positions(np.array([s_dead + 0.01]), D)
    with pytest.raises(ValueError):
        p.positions(np.zeros((2, 2)), D)
