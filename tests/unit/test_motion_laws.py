"""Unit tests of excavkin.motion: motion laws, profiles, registry and drives.

Cross-checks: analytic v, a, j against 8th-order central finite differences of s, v, a;
s, v, a against quadrature (scipy.integrate.quad) of v, a, j; the cubic law against
Pasika & Koruniak Eqs. (4)-(6); peak coefficients against their closed forms and the usual
textbook values (Chen, Norton).
"""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal
from scipy.integrate import quad

from excavkin.motion import (
    LAW_NAMES,
    ConstantSpeedCrank,
    CubicLaw,
    CycloidalLaw,
    HarmonicLaw,
    ModifiedSineLaw,
    ModifiedTrapezoidLaw,
    MotionLaw,
    Poly345Law,
    Poly4567Law,
    Profile,
    RopeWinch,
    SCurveLaw,
    Segment,
    TrapezoidalLaw,
    dwell,
    get_law,
    rope_speed,
)

H, T, T0 = -0.37, 1.7, 0.3  # a return stroke, non-unit duration, shifted start

EXPECTED_CLASS = {
    "cubic": CubicLaw,
    "345": Poly345Law,
    "4567": Poly4567Law,
    "cycloidal": CycloidalLaw,
    "harmonic": HarmonicLaw,
    "modified-trapezoid": ModifiedTrapezoidLaw,
    "modified-sine": ModifiedSineLaw,
    "trapezoidal": TrapezoidalLaw,
    "s-curve": SCurveLaw,
}
SOFT_SHOCK = {"cubic", "harmonic", "trapezoidal"}
SHOCK_FREE = set(LAW_NAMES) - SOFT_SHOCK


def make_laws(stroke: float = H, duration: float = T, start: float = T0) -> list[MotionLaw]:
    """Every law, with non-default shape parameters for the parametrised ones."""
    laws = [get_law(n, stroke, duration, start=start) for n in LAW_NAMES]
    laws.append(TrapezoidalLaw(stroke, duration, start=start, accel_fraction=0.2))
    laws.append(TrapezoidalLaw(stroke, duration, start=start, accel_fraction=0.5))
    laws.append(SCurveLaw(stroke, duration, start=start, accel_fraction=0.3, jerk_fraction=0.2))
    laws.append(SCurveLaw(stroke, duration, start=start, accel_fraction=0.5, jerk_fraction=0.5))
    return laws


ALL_LAWS = make_laws()
LAW_IDS = [f"{law.name}-{i}" if i >= len(LAW_NAMES) else law.name for i, law in enumerate(ALL_LAWS)]


def interior_times(law: MotionLaw, margin: float, n: int = 41) -> np.ndarray:
    """Times inside (t0, t0 + T) at least ``margin`` [s] from every breakpoint."""
    t = law.start + law.duration * np.linspace(0.0, 1.0, n + 2)[1:-1]
    t = np.concatenate([t, law.start + law.duration * np.array([0.137, 0.5, 0.61, 0.93])])
    bps = law.start + law.duration * np.asarray(law.breakpoints)
    keep = np.min(np.abs(t[:, None] - bps[None, :]), axis=1) > margin
    return t[keep]


_FD8 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])


def central_diff(fun, t: np.ndarray, h: float) -> np.ndarray:
    """8th-order central difference of ``fun`` at ``t`` (shape (n,))."""
    offs = np.arange(-4, 5) * h
    vals = fun((t[:, None] + offs[None, :]).ravel()).reshape(t.size, 9)
    return vals @ _FD8 / h


# ------------------------------------------------------------------------------------------
# Boundary values and held values outside [t0, t0 + T]
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("law", ALL_LAWS, ids=LAW_IDS)
def test_boundary_values(law: MotionLaw) -> None:
    st = law.evaluate(np.array([law.start, law.end]))
    assert_allclose(st.s, [0.0, law.stroke], rtol=1e-14, atol=1e-15)
    assert_allclose(st.v, [0.0, 0.0], rtol=0, atol=1e-13 * abs(law.stroke) / law.duration)


@pytest.mark.parametrize("law", ALL_LAWS, ids=LAW_IDS)
def test_holds_end_values_outside(law: MotionLaw) -> None:
    t = np.array([law.start - 5.0, law.start - 1e-9, law.end + 1e-9, law.end + 7.0])
    st = law.evaluate(t)
    assert_array_equal(st.s, [0.0, 0.0, law.stroke, law.stroke])
    for x in (st.v, st.a, st.j):
        assert_array_equal(x, np.zeros(4))


@pytest.mark.parametrize("law", ALL_LAWS, ids=LAW_IDS)
def test_output_shapes(law: MotionLaw) -> None:
    t = np.linspace(law.start - 0.1, law.end + 0.1, 17)
    st = law.evaluate(t)
    for x in st:
        assert x.shape == (17,)
        assert x.dtype == np.float64


# ------------------------------------------------------------------------------------------
# Analytic derivatives vs finite differences; integrals vs quadrature
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("law", ALL_LAWS, ids=LAW_IDS)
def test_derivatives_against_finite_differences(law: MotionLaw) -> None:
    h = 1e-3 * law.duration
    t = interior_times(law, margin=5 * h)
    assert t.size > 20
    st = law.evaluate(t)
    c = law.coefficients
    scale = abs(law.stroke)
    for k, (quantity, analytic, peak) in enumerate(
        [("s", st.v, c.c_v), ("v", st.a, c.c_a), ("a", st.j, max(c.c_j, 1.0))]
    ):
        fd = central_diff(lambda x, q=quantity: getattr(law.evaluate(x), q), t, h)
        tol = 1e-7 * peak * scale / law.duration ** (k + 1)
        assert_allclose(analytic, fd, rtol=1e-7, atol=tol, err_msg=f"d{quantity}/dt")


@pytest.mark.parametrize("law", ALL_LAWS, ids=LAW_IDS)
def test_stroke_is_integral_of_velocity(law: MotionLaw) -> None:
    pts = [law.start + law.duration * u for u in law.breakpoints[1:-1]]

    def v(x: float) -> float:
        return float(law.evaluate(np.array([x])).v[0])

    total, _ = quad(v, law.start, law.end, points=pts or None, epsabs=1e-13, epsrel=1e-12)
    assert_allclose(total, law.stroke, rtol=1e-10)


@pytest.mark.parametrize("law", ALL_LAWS, ids=LAW_IDS)
def test_running_integrals(law: MotionLaw) -> None:
    """s(t) = ∫v, v(t) = ∫a and, where a is continuous inside, a(t) − a(t0+) = ∫j."""

    def comp(q: str):
        return lambda x: float(getattr(law.evaluate(np.array([x])), q)[0])

    interior_jumps = [j for j in law.acceleration_jumps() if j.where not in ("start", "end")]
    st0 = law.evaluate(np.array([law.start]))
    for u in (0.2, 0.45, 0.77, 1.0):
        t = law.start + u * law.duration
        pts = [law.start + law.duration * b for b in law.breakpoints[1:-1] if b < u] or None
        st = law.evaluate(np.array([t]))
        s_int, _ = quad(comp("v"), law.start, t, points=pts, epsabs=1e-13, epsrel=1e-12)
        v_int, _ = quad(comp("a"), law.start, t, points=pts, epsabs=1e-13, epsrel=1e-12)
        scale = abs(law.stroke)
        assert_allclose(s_int, st.s[0], rtol=1e-10, atol=1e-12 * scale)
        assert_allclose(v_int, st.v[0], rtol=1e-10, atol=1e-11 * scale / law.duration)
        if not interior_jumps:
            j_int, _ = quad(comp("j"), law.start, t, points=pts, epsabs=1e-12, epsrel=1e-11)
            assert_allclose(
                j_int, st.a[0] - st0.a[0], rtol=1e-9, atol=1e-10 * scale / law.duration**2
            )


PIECEWISE = [(law, i) for law, i in zip(ALL_LAWS, LAW_IDS, strict=True) if law.breakpoints[1:-1]]


@pytest.mark.parametrize("law", [p[0] for p in PIECEWISE], ids=[p[1] for p in PIECEWISE])
def test_s_and_v_continuous_at_breakpoints(law: MotionLaw) -> None:
    """One-sided limits of f and f' agree at interior breakpoints (only a may jump)."""
    u = np.asarray(law.breakpoints[1:-1])
    left = law._shape(u, left=True)
    right = law._shape(u, left=False)
    assert_allclose(left[0], right[0], rtol=0, atol=1e-14)
    assert_allclose(left[1], right[1], rtol=0, atol=1e-13)


# ------------------------------------------------------------------------------------------
# Peak coefficients
# ------------------------------------------------------------------------------------------


def test_peak_coefficients_match_literature() -> None:
    def c(name: str):
        return get_law(name, 1.0, 1.0).coefficients

    assert_allclose(c("cycloidal").c_a, 2 * math.pi, rtol=1e-15)
    assert_allclose(c("cycloidal").c_v, 2.0, rtol=1e-15)
    assert_allclose(c("345").c_a, 5.7735, atol=5e-5)
    assert_allclose(c("345").c_a, 10 / math.sqrt(3), rtol=1e-15)
    assert_allclose(c("345").c_v, 1.875, rtol=1e-15)
    assert_allclose(c("345").c_j, 60.0, rtol=1e-15)
    assert_allclose(c("4567").c_v, 2.1875, rtol=1e-15)
    assert_allclose(c("4567").c_a, 7.5132, atol=5e-5)
    assert_allclose(c("4567").c_j, 52.5, rtol=1e-15)
    assert_allclose(c("modified-trapezoid").c_a, 4.888, atol=5e-4)
    assert_allclose(c("modified-trapezoid").c_v, 2.0, rtol=1e-15)
    assert_allclose(c("modified-trapezoid").c_j, 61.43, atol=5e-3)
    assert_allclose(c("modified-sine").c_a, 5.528, atol=5e-4)
    assert_allclose(c("modified-sine").c_v, 1.760, atol=5e-4)
    assert_allclose(c("modified-sine").c_j, 69.47, atol=5e-3)
    assert_allclose(c("harmonic").c_a, math.pi**2 / 2, rtol=1e-15)
    assert_allclose(c("harmonic").c_v, math.pi / 2, rtol=1e-15)
    assert_allclose(c("cubic"), (1.5, 6.0, 12.0), rtol=1e-15)
    assert_allclose(c("trapezoidal"), (1.5, 4.5, 0.0), rtol=1e-15)  # the 1/3-1/3-1/3 law
    assert_allclose(c("s-curve"), (2.0, 16 / 3, 128 / 3), rtol=1e-15)


@pytest.mark.parametrize("law", ALL_LAWS, ids=LAW_IDS)
def test_peak_coefficients_match_sampled_peaks(law: MotionLaw) -> None:
    """The samples never exceed the coefficients and attain them at the known argmax."""
    u_special = [0.0, 0.125, 0.25, 0.5, (3 - math.sqrt(3)) / 6, (5 - math.sqrt(5)) / 10]
    if isinstance(law, SCurveLaw):
        u_special.append(law.accel_fraction / 2)
    u = np.concatenate([np.linspace(0.0, 1.0, 20001), u_special])
    st = law.evaluate(law.start + law.duration * u)
    c = law.coefficients
    for x, ck, k in ((st.v, c.c_v, 1), (st.a, c.c_a, 2), (st.j, c.c_j, 3)):
        peak = ck * abs(law.stroke) / law.duration**k
        assert_allclose(np.max(np.abs(x)), peak, rtol=1e-12, atol=1e-300)
    assert_allclose(law.peak_velocity, c.c_v * abs(law.stroke) / law.duration, rtol=1e-15)
    assert_allclose(law.peak_acceleration, c.c_a * abs(law.stroke) / law.duration**2, rtol=1e-15)
    assert_allclose(law.peak_jerk, c.c_j * abs(law.stroke) / law.duration**3, rtol=1e-15)


# ------------------------------------------------------------------------------------------
# The paper's cubic law (Pasika & Koruniak, Eqs. (4)-(6))
# ------------------------------------------------------------------------------------------


def test_cubic_equals_paper_law() -> None:
    stroke, dur = 0.8, 2.5
    t = np.linspace(0.0, dur, 101)
    st = CubicLaw(stroke, dur).evaluate(t)
    assert_allclose(st.s, stroke * (3 * t**2 / dur**2 - 2 * t**3 / dur**3), rtol=1e-14, atol=1e-16)
    assert_allclose(st.v, 6 * stroke / dur * (t / dur) * (1 - t / dur), rtol=1e-14, atol=1e-16)
    assert_allclose(st.a, 6 * stroke / dur**2 * (1 - 2 * t / dur), rtol=1e-14, atol=1e-15)
    assert_allclose(st.j, np.full_like(t, -12 * stroke / dur**3), rtol=1e-15)
    assert_allclose(st.a[[0, -1]], [6 * stroke / dur**2, -6 * stroke / dur**2], rtol=1e-15)
    assert_allclose(st.v.max(), 1.5 * stroke / dur, rtol=1e-15)  # at T/2


# ------------------------------------------------------------------------------------------
# Soft shocks
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(SOFT_SHOCK))
def test_soft_shock_laws_have_nonzero_end_acceleration(name: str) -> None:
    law = get_law(name, H, T, start=T0)
    a = law.evaluate(np.array([law.start, law.end])).a
    a_scale = abs(H) / T**2
    assert np.all(np.abs(a) > 1.0 * a_scale)
    jumps = law.acceleration_jumps()
    assert jumps[0].where == "start" and jumps[-1].where == "end"
    assert_allclose([jumps[0].time, jumps[-1].time], [law.start, law.end], rtol=1e-15)
    assert_allclose(jumps[0].jump, a[0], rtol=1e-15)
    assert_allclose(jumps[-1].jump, -a[1], rtol=1e-15)


@pytest.mark.parametrize("name", sorted(SHOCK_FREE))
def test_shock_free_laws_have_zero_end_acceleration(name: str) -> None:
    law = get_law(name, H, T, start=T0)
    a = law.evaluate(np.array([law.start, law.end])).a
    assert_allclose(a, [0.0, 0.0], rtol=0, atol=1e-13 * abs(H) / T**2)
    assert law.acceleration_jumps() == ()


def test_cubic_soft_shocks_are_6H_over_T2() -> None:
    law = CubicLaw(0.8, 2.0)
    jumps = law.acceleration_jumps()
    assert [j.where for j in jumps] == ["start", "end"]
    assert_allclose([j.jump for j in jumps], [6 * 0.8 / 4.0, 6 * 0.8 / 4.0], rtol=1e-15)


def test_trapezoidal_has_four_soft_shocks() -> None:
    law = TrapezoidalLaw(1.0, 2.0, accel_fraction=0.25)
    A = (1 / 0.75) / 0.25 * 1.0 / 2.0**2  # V/τ in H/T²
    jumps = law.acceleration_jumps()
    assert_allclose([j.time for j in jumps], [0.0, 0.5, 1.5, 2.0], rtol=1e-15)
    assert_allclose([j.jump for j in jumps], [A, -A, -A, A], rtol=1e-14)


def test_triangular_velocity_has_three_soft_shocks() -> None:
    law = TrapezoidalLaw(1.0, 2.0, accel_fraction=0.5)
    jumps = law.acceleration_jumps()
    assert_allclose([j.time for j in jumps], [0.0, 1.0, 2.0], rtol=1e-15)
    assert_allclose([j.jump for j in jumps], [1.0, -2.0, 1.0], rtol=1e-14)  # A = 4H/T² = 1


def test_trapezoidal_from_max_velocity() -> None:
    # H/T = 0.5 m/s, v_max = 0.75 m/s  ->  τ = 1 − 0.5/0.75 = 1/3
    law = TrapezoidalLaw.from_max_velocity(1.0, 2.0, 0.75)
    assert_allclose(law.accel_fraction, 1 / 3, rtol=1e-15)
    assert_allclose(law.peak_velocity, 0.75, rtol=1e-15)
    with pytest.raises(ValueError, match="v_max"):
        TrapezoidalLaw.from_max_velocity(1.0, 2.0, 0.5)
    with pytest.raises(ValueError, match="v_max"):
        TrapezoidalLaw.from_max_velocity(1.0, 2.0, 1.01)


# ------------------------------------------------------------------------------------------
# S-curve from limits (hand-derived phase durations)
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("stroke", "v_max", "a_max", "j_max", "phases", "peaks"),
    [
        # all seven phases: Tj = a/j = 0.2, Tc = v/a − Tj = 0.3, Tv = H/v − (2Tj + Tc) = 1.3
        (2.0, 1.0, 2.0, 10.0, (0.2, 0.3, 0.2, 1.3, 0.2, 0.3, 0.2), (1.0, 2.0, 10.0)),
        # v_max not reached: v = (a/2)(sqrt(a²/j² + 4H/a) − a/j) = sqrt(1.04) − 0.2
        (
            0.5,
            1.0,
            2.0,
            10.0,
            (0.2, math.sqrt(1.04) / 2 - 0.3, 0.2, 0.0, 0.2, math.sqrt(1.04) / 2 - 0.3, 0.2),
            (math.sqrt(1.04) - 0.2, 2.0, 10.0),
        ),
        # neither v_max nor a_max reached (H < 2a³/j² = 0.16): Tj = (H/(2j))^(1/3)
        (
            0.1,
            1.0,
            2.0,
            10.0,
            (0.005 ** (1 / 3), 0.0, 0.005 ** (1 / 3), 0.0, 0.005 ** (1 / 3), 0.0, 0.005 ** (1 / 3)),
            (10.0 * 0.005 ** (2 / 3), 10.0 * 0.005 ** (1 / 3), 10.0),
        ),
        # v_max reached, a_max not (v j < a²): Tj = sqrt(v/j) = sqrt(0.02), Tv = H/v − 2Tj
        (
            -2.0,
            0.2,
            2.0,
            10.0,
            (
                math.sqrt(0.02),
                0.0,
                math.sqrt(0.02),
                10.0 - 2 * math.sqrt(0.02),
                math.sqrt(0.02),
                0.0,
                math.sqrt(0.02),
            ),
            (0.2, 10.0 * math.sqrt(0.02), 10.0),
        ),
    ],
    ids=["all-phases", "v-not-reached", "v-and-a-not-reached", "a-not-reached"],
)
def test_s_curve_from_limits(stroke, v_max, a_max, j_max, phases, peaks) -> None:
    law = SCurveLaw.from_limits(stroke, v_max, a_max, j_max, start=0.4)
    assert_allclose(law.phase_durations, phases, rtol=1e-12, atol=1e-14)
    assert_allclose(law.duration, sum(phases), rtol=1e-14)
    assert_allclose((law.peak_velocity, law.peak_acceleration, law.peak_jerk), peaks, rtol=1e-12)
    t = np.linspace(law.start, law.end, 4001)
    st = law.evaluate(t)
    assert np.all(np.abs(st.v) <= v_max * (1 + 1e-12))
    assert np.all(np.abs(st.a) <= a_max * (1 + 1e-12))
    assert np.all(np.abs(st.j) <= j_max * (1 + 1e-12))
    assert_allclose(st.s[-1], stroke, rtol=1e-15)


def test_s_curve_given_duration() -> None:
    # α = 0.3, β = 0.2: V = 1/0.7, A = V/(0.3·0.8), J = A/0.06 (units H/T^k)
    law = SCurveLaw(2.0, 4.0, accel_fraction=0.3, jerk_fraction=0.2)
    V = 1 / 0.7
    A = V / 0.24
    assert_allclose(law.coefficients, (V, A, A / 0.06), rtol=1e-14)
    assert_allclose(
        law.phase_durations, np.array([0.06, 0.18, 0.06, 0.4, 0.06, 0.18, 0.06]) * 4, rtol=1e-12
    )


def test_s_curve_rejects_bad_limits() -> None:
    with pytest.raises(ValueError, match="a_max"):
        SCurveLaw.from_limits(1.0, 1.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="stroke"):
        SCurveLaw.from_limits(0.0, 1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="jerk_fraction"):
        SCurveLaw(1.0, 1.0, jerk_fraction=0.0)


# ------------------------------------------------------------------------------------------
# Law objects: immutability and validation
# ------------------------------------------------------------------------------------------


def test_laws_are_frozen_and_slotted() -> None:
    law = CycloidalLaw(1.0, 2.0, start=0.5)
    with pytest.raises(dataclasses.FrozenInstanceError):
        law.stroke = 2.0  # type: ignore[misc]
    assert not hasattr(law, "__dict__")


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"stroke": 1.0, "duration": 0.0}, "duration"),
        ({"stroke": 1.0, "duration": -1.0}, "duration"),
        ({"stroke": math.nan, "duration": 1.0}, "stroke"),
        ({"stroke": 1.0, "duration": 1.0, "start": math.inf}, "start"),
    ],
)
def test_invalid_law_parameters(kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        CycloidalLaw(**kwargs)


def test_trapezoidal_fraction_range() -> None:
    with pytest.raises(ValueError, match="accel_fraction"):
        TrapezoidalLaw(1.0, 1.0, accel_fraction=0.6)


def test_unknown_constructor_keyword_raises() -> None:
    with pytest.raises(TypeError):
        CycloidalLaw(1.0, 1.0, t0=0.2)  # type: ignore[call-arg]


# ------------------------------------------------------------------------------------------
# Registry
# ------------------------------------------------------------------------------------------


def test_registry_names_and_classes() -> None:
    assert set(LAW_NAMES) == set(EXPECTED_CLASS)
    for name, cls in EXPECTED_CLASS.items():
        law = get_law(name, 0.5, 2.0, start=1.0)
        assert type(law) is cls
        assert (law.stroke, law.duration, law.start) == (0.5, 2.0, 1.0)
        assert law.name == name


def test_registry_unknown_name_lists_known_ones() -> None:
    with pytest.raises(ValueError, match="unknown motion law 'parabolic'") as exc:
        get_law("parabolic", 1.0, 1.0)
    for name in LAW_NAMES:
        assert name in str(exc.value)


def test_registry_unknown_parameter_raises_type_error() -> None:
    with pytest.raises(TypeError, match="unknown parameter"):
        get_law("cycloidal", 1.0, 1.0, accel_fraction=0.2)
    with pytest.raises(TypeError, match="unknown parameter"):
        get_law("trapezoidal", 1.0, 1.0, a_max=3.0)


def test_registry_parameters() -> None:
    law = get_law("trapezoidal", 1.0, 2.0, v_max=0.75)
    assert isinstance(law, TrapezoidalLaw)
    assert_allclose(law.accel_fraction, 1 / 3, rtol=1e-15)
    assert get_law("trapezoidal", 1.0, 2.0, accel_fraction=0.25).accel_fraction == 0.25
    sc = get_law("s-curve", 2.0, None, v_max=1.0, a_max=2.0, j_max=10.0, start=0.5)
    assert isinstance(sc, SCurveLaw)
    assert_allclose(sc.duration, 2.7, rtol=1e-14)
    assert sc.start == 0.5
    with pytest.raises(ValueError, match="duration=None"):
        get_law("s-curve", 2.0, 3.0, v_max=1.0, a_max=2.0, j_max=10.0)
    with pytest.raises(TypeError, match="needs all"):
        get_law("s-curve", 2.0, None, v_max=1.0, a_max=2.0)
    with pytest.raises(TypeError, match="not both"):
        get_law("trapezoidal", 1.0, 2.0, v_max=0.75, accel_fraction=0.3)
    with pytest.raises(ValueError, match="needs a duration"):
        get_law("cycloidal", 1.0, None)


# ------------------------------------------------------------------------------------------
# Profiles
# ------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True, slots=True)
class _Ramp(MotionLaw):
    """Test-only law with constant velocity H/T (not rest-to-rest: v jumps at the ends)."""

    name: ClassVar[str] = "ramp"

    def _shape(self, u, left=False):
        z = np.zeros_like(u)
        return u.copy(), np.ones_like(u), z, z.copy()


def test_profile_rise_dwell_return() -> None:
    rise = CycloidalLaw(0.5, 2.0)
    ret = Poly345Law(-0.5, 1.5)
    p = Profile.from_laws([rise, dwell(1.0), ret], s0=0.1, t0=1.0)
    assert_allclose(p.joins, [3.0, 4.0], rtol=1e-15)
    assert (p.start, p.end) == (1.0, 5.5)
    t = np.array([0.0, 1.0, 2.0, 3.0, 3.5, 4.0, 4.75, 5.5, 9.0])
    st = p.evaluate(t)
    rise_ref = CycloidalLaw(0.5, 2.0, start=1.0).evaluate(t[:4])
    ret_ref = Poly345Law(-0.5, 1.5, start=4.0).evaluate(t[5:8])
    assert_allclose(st.s[:3], 0.1 + rise_ref.s[:3], rtol=1e-15)
    assert_allclose(st.s[3:5], [0.6, 0.6], rtol=1e-15)
    assert_allclose(st.s[5:8], 0.6 + ret_ref.s, rtol=1e-15)
    assert_allclose(st.s[8], 0.1, rtol=1e-15)
    assert_allclose(st.v[:3], rise_ref.v[:3], rtol=1e-15)
    assert_allclose(st.v[5:8], ret_ref.v, rtol=1e-15, atol=1e-16)
    assert_array_equal(st.v[[0, 3, 4, 8]], np.zeros(4))
    assert p.acceleration_jumps() == ()


def test_profile_continuity_dense() -> None:
    p = Profile.from_laws([ModifiedSineLaw(0.3, 1.0), dwell(0.5), ModifiedSineLaw(-0.3, 1.0)])
    eps = 1e-9
    for tj in p.joins:
        st = p.evaluate(np.array([tj - eps, tj, tj + eps]))
        assert_allclose(np.diff(st.s), 0.0, atol=1e-9)
        assert_allclose(np.diff(st.v), 0.0, atol=1e-7)


def test_profile_lists_acceleration_jumps_at_joins() -> None:
    p = Profile.from_laws([CubicLaw(0.8, 2.0), dwell(1.0), CubicLaw(-0.8, 2.0)])
    jumps = p.acceleration_jumps()
    a0 = 6 * 0.8 / 4.0  # 6H/T²
    assert [j.where for j in jumps] == [
        "start",
        "join 1 (segment 0 'cubic' -> segment 1 'dwell')",
        "join 2 (segment 1 'dwell' -> segment 2 'cubic')",
        "end",
    ]
    assert_allclose([j.time for j in jumps], [0.0, 2.0, 3.0, 5.0], rtol=1e-15)
    assert_allclose([j.a_before for j in jumps], [0.0, -a0, 0.0, a0], rtol=1e-15)
    assert_allclose([j.a_after for j in jumps], [a0, 0.0, -a0, 0.0], rtol=1e-15)
    # cubic rise straight into cubic return: a = −6H/T² on both sides of the join, so the
    # only soft shocks are at the start and the end
    p2 = Profile.from_laws([CubicLaw(0.8, 2.0), CubicLaw(-0.8, 2.0)])
    assert [j.where for j in p2.acceleration_jumps()] == ["start", "end"]


def test_profile_rejects_position_jump() -> None:
    segs = (Segment(CycloidalLaw(0.5, 1.0), 0.0), Segment(CycloidalLaw(0.5, 1.0, start=1.0), 0.4))
    with pytest.raises(ValueError, match=r"join 1 .* displacement s jumps by -0\.1"):
        Profile(segs)


def test_profile_rejects_velocity_jump() -> None:
    with pytest.raises(ValueError, match=r"join 1 .*'cycloidal' -> .*'ramp'.* velocity v jumps"):
        Profile.from_laws([CycloidalLaw(0.5, 1.0), _Ramp(1.0, 2.0)])


def test_profile_rejects_gap_and_overlap() -> None:
    a = Segment(CycloidalLaw(0.5, 1.0), 0.0)
    with pytest.raises(ValueError, match="gap"):
        Profile((a, Segment(CycloidalLaw(0.5, 1.0, start=1.5), 0.5)))
    with pytest.raises(ValueError, match="overlap"):
        Profile((a, Segment(CycloidalLaw(0.5, 1.0, start=0.5), 0.5)))
    with pytest.raises(ValueError, match="at least one"):
        Profile(())


# ------------------------------------------------------------------------------------------
# Drives
# ------------------------------------------------------------------------------------------


def test_crank_constant_speed_hammer() -> None:
    omega, phi0 = 31.416, 0.3  # MO-100 hammer, ω1 = 31.416 s⁻¹
    crank = ConstantSpeedCrank(omega, phi0)
    t = np.linspace(0.0, 0.4, 81)
    st = crank.evaluate(t)
    assert_array_equal(st.s, phi0 + omega * t)
    assert_array_equal(crank.angle(t), phi0 + omega * t)
    assert_array_equal(st.v, np.full(81, omega))
    assert_array_equal(st.a, np.zeros(81))
    assert_array_equal(st.j, np.zeros(81))
    assert_allclose(crank.period, 0.2, rtol=1e-5)  # 2π/31.416 ≈ 0.2 s (5 Hz)
    assert_allclose(crank.period, 2 * math.pi / omega, rtol=1e-15)


def test_rope_speed_formula_by_hand() -> None:
    # ω_motor = 104.72 rad/s (≈ 1000 rpm), R = 0.4 m, i = 20, a_p = 2:
    # v = 104.72 · 0.4 / (20 · 2) = 41.888 / 40 = 1.0472 m/s
    winch = RopeWinch(104.72, 0.4, 20.0, 2.0, initial_length=15.0)
    assert_allclose(winch.rope_speed, 1.0472, rtol=1e-14)
    assert_allclose(winch.ratio, 0.01, rtol=1e-15)
    assert_allclose(
        rope_speed(np.array([104.72, -52.36]), 0.4, 20.0, 2.0), [1.0472, -0.5236], rtol=1e-14
    )
    # hauling in shortens the rope: L(2 s) = 15 − 2 · 1.0472 = 12.9056 m
    assert_allclose(winch.rope_length([0.0, 2.0]), [15.0, 12.9056], rtol=1e-14)
    st = winch.evaluate(np.array([0.0, 2.0]))
    assert_allclose(st.v, [1.0472, 1.0472], rtol=1e-14)
    assert_array_equal(st.a, [0.0, 0.0])


def test_ramped_winch() -> None:
    # motor turns 200 rad in 3 s with a 1/3-1/3-1/3 trapezoidal speed profile:
    # peak motor speed 1.5 · 200/3 = 100 rad/s -> rope 100 · 0.01 = 1 m/s; hauled 2 m.
    motor = TrapezoidalLaw(200.0, 3.0)
    winch = RopeWinch.ramped(motor, 0.4, 20.0, 2.0, initial_length=10.0)
    t = np.linspace(-1.0, 4.0, 501)
    st = winch.evaluate(t)
    assert_allclose(np.max(st.v), 1.0, rtol=1e-14)
    L = winch.rope_length(t)
    assert_allclose([L[0], L[-1]], [10.0, 8.0], rtol=1e-15)
    assert np.all(np.diff(L) <= 0.0)
    with pytest.raises(ValueError, match="ramped"):
        _ = winch.rope_speed


def test_winch_validation() -> None:
    with pytest.raises(ValueError, match="exactly one"):
        RopeWinch(None, 0.4, 20.0, 2.0)
    with pytest.raises(ValueError, match="exactly one"):
        RopeWinch(10.0, 0.4, 20.0, 2.0, motor_law=CycloidalLaw(1.0, 1.0))
    with pytest.raises(ValueError, match="pulley_multiplicity"):
        RopeWinch(10.0, 0.4, 20.0, 0.5)
    with pytest.raises(ValueError, match="drum_radius"):
        RopeWinch(10.0, -0.4, 20.0, 2.0)
