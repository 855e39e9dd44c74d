"""Property tests of excavkin.motion (hypothesis, derandomised)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from excavkin.motion import LAW_NAMES, Profile, SCurveLaw, dwell, get_law

pos = st.floats(min_value=1e-2, max_value=1e2, allow_nan=False, allow_infinity=False)
stroke = st.floats(min_value=1e-3, max_value=1e1).flatmap(lambda x: st.sampled_from([x, -x]))


@settings(max_examples=200, derandomize=True, deadline=None, database=None)
@given(h=stroke, v_max=pos, a_max=pos, j_max=pos)
def test_s_curve_from_limits_respects_limits(h, v_max, a_max, j_max) -> None:
    """Time-optimal S-curve: ends at rest at H, never exceeds a limit, attains j_max and
    the binding one of v_max / a_max (or the peak speed that covers H)."""
    law = SCurveLaw.from_limits(h, v_max, a_max, j_max)
    assert_allclose(sum(law.phase_durations), law.duration, rtol=1e-12)
    assert all(d >= 0.0 for d in law.phase_durations)
    t = np.linspace(law.start, law.end, 2001)
    s = law.evaluate(t)
    assert_allclose([s.s[0], s.s[-1]], [0.0, h], rtol=1e-14, atol=1e-15)
    assert_allclose([s.v[0], s.v[-1]], [0.0, 0.0], atol=1e-12 * v_max)
    assert law.peak_velocity <= v_max * (1 + 1e-9)
    assert law.peak_acceleration <= a_max * (1 + 1e-9)
    assert_allclose(law.peak_jerk, j_max, rtol=1e-9)
    tj, tc, _, tv, *_ = law.phase_durations
    if tv > 1e-12 * law.duration:
        assert_allclose(law.peak_velocity, v_max, rtol=1e-9)
    if tc > 1e-12 * law.duration:
        assert_allclose(law.peak_acceleration, a_max, rtol=1e-9)


@settings(max_examples=100, derandomize=True, deadline=None, database=None)
@given(
    name=st.sampled_from(LAW_NAMES),
    h=stroke,
    dur=pos,
    t0=st.floats(min_value=-10.0, max_value=10.0),
)
def test_rise_dwell_return_comes_back(name, h, dur, t0) -> None:
    """Any law as rise and return: the profile is continuous and returns to its start."""
    rise = get_law(name, h, dur)
    back = get_law(name, -h, dur)
    p = Profile.from_laws([rise, dwell(0.5 * dur), back], s0=1.0, t0=t0)
    st_ = p.evaluate(np.array([t0 - 1.0, t0 + dur, t0 + 1.5 * dur, p.end, p.end + 1.0]))
    assert_allclose(st_.s, [1.0, 1.0 + h, 1.0 + h, 1.0, 1.0], rtol=1e-12, atol=1e-12 * abs(h))
