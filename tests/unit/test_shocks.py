"""Shock report: exact velocity and acceleration jumps at the laws' breakpoints, and peaks.

The acceptance case of the issue: on the Pasika & Koruniak module (seed 003, spec §4.3) the
cubic law has soft shocks at both ends — of the rod's acceleration, of the cylinder's ε1 and
of the rocker's ε3 — and the 3-4-5, 4-5-6-7 and cycloidal laws have none.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin.errors import InputError
from excavkin.motion import ConstantSpeedCrank, Profile, dwell, get_law
from excavkin.simulation.shocks import shock_report, tracked_columns
from excavkin.simulation.timeline import Drive, simulate


@pytest.fixture(scope="module")
def module() -> excavkin.Mechanism:
    return excavkin.load(excavkin.example_path("pasika_module"))


def _cubic(module):
    return shock_report(module, {"cyl": get_law("cubic", 0.5, 5.0)}, samples=201)


def test_cubic_soft_shocks_at_both_ends(module):
    rep = _cubic(module)
    assert rep.hard == ()
    assert_allclose(rep.times, [0.0, 5.0])
    got = {(s.time, s.column): s.jump for s in rep.soft}
    assert set(got) == {
        (t, c) for t in (0.0, 5.0) for c in ("cyl.accel", "cyl.epsilon", "rocker.epsilon")
    }
    # spec §4.3: Δa21 = +6H/T² = 0.12 at both ends; Δε1 = +0.1003, +0.0853; Δε3 = +0.1203,
    # +0.1362 rad/s² (printed digits)
    assert_allclose([got[(0.0, "cyl.accel")], got[(5.0, "cyl.accel")]], [0.12, 0.12], rtol=1e-12)
    assert_allclose(
        [got[(0.0, "cyl.epsilon")], got[(5.0, "cyl.epsilon")]], [0.10034, 0.08530], atol=5e-6
    )
    assert_allclose(
        [got[(0.0, "rocker.epsilon")], got[(5.0, "rocker.epsilon")]], [0.12031, 0.13616], atol=5e-6
    )
    for s in rep.soft:
        assert s.causes == (("cyl: start of cubic",) if s.time == 0.0 else ("cyl: end of cubic",))
    # before the start and after the end the module is at rest
    assert rep.limit("rocker.epsilon", 0.0, "left") == 0.0
    assert rep.limit("rocker.epsilon", 5.0, "right") == 0.0


def test_cubic_jumps_match_the_reference_closed_form(module):
    from excavkin.papers.pasika import reference as pasika

    ref = pasika.soft_shock_jumps()
    rep = _cubic(module)
    got = {(s.time, s.column): s.jump for s in rep.soft}
    assert_allclose(got[(0.0, "cyl.epsilon")], ref["eps1_start"], rtol=1e-12)
    assert_allclose(got[(5.0, "cyl.epsilon")], ref["eps1_end"], rtol=1e-12)
    assert_allclose(got[(0.0, "rocker.epsilon")], ref["eps3_start"], rtol=1e-12)
    assert_allclose(got[(5.0, "rocker.epsilon")], ref["eps3_end"], rtol=1e-12)


@pytest.mark.parametrize(
    "law", ["345", "4567", "cycloidal", "modified-sine", "modified-trapezoid", "s-curve"]
)
def test_shock_free_laws(module, law):
    rep = shock_report(module, {"cyl": get_law(law, 0.5, 5.0)}, samples=101)
    assert rep.shocks == ()
    assert rep.times.size >= 2  # the ends were examined
    assert_allclose(rep.limit("rocker.epsilon", 0.0, "right"), 0.0, atol=1e-15)
    assert_allclose(rep.limit("cyl.epsilon", 5.0, "left"), 0.0, atol=1e-15)


@pytest.mark.parametrize(("law", "n_breakpoints"), [("harmonic", 2), ("trapezoidal", 4)])
def test_laws_with_soft_shocks(module, law, n_breakpoints):
    rep = shock_report(module, {"cyl": get_law(law, 0.5, 5.0)}, samples=101)
    assert rep.hard == ()
    assert len(rep.of("cyl", "soft")) == 2 * n_breakpoints  # accel of the rod and ε1
    assert len(rep.of("rocker", "soft")) == n_breakpoints
    assert {s.time for s in rep.soft} == set(rep.times.tolist())


def test_jump_at_rest_is_geometric_gain_times_rod_jump(module):
    """At rest ε = u'(q)·q'' exactly, so Δε = u'·Δa21 at both ends of any law."""
    rep = shock_report(module, {"cyl": get_law("harmonic", 0.5, 5.0)}, samples=51)
    unit = module.solve({"cyl": np.array([0.8, 1.3])}, {"cyl": np.ones(2)})
    gain = unit.column("rocker.omega")
    da = {s.time: s.jump for s in rep.of("cyl", "soft") if s.quantity == "accel"}
    de = {s.time: s.jump for s in rep.of("rocker", "soft")}
    assert_allclose([de[0.0], de[5.0]], [gain[0] * da[0.0], gain[1] * da[5.0]], rtol=1e-12)


def test_interior_breakpoint_with_motion(module):
    """A jump while moving (trapezoid corner): Δε = u'·Δa21 still, because v is continuous."""
    law = get_law("trapezoidal", 0.5, 5.0)
    rep = shock_report(module, {"cyl": law}, samples=51)
    tb = rep.times[1]
    q = 0.8 + law.evaluate([tb]).s
    gain = module.solve({"cyl": q}, {"cyl": np.ones(1)}).column("rocker.omega")[0]
    s = next(x for x in rep.of("rocker", "soft") if x.time == tb)
    a = next(x for x in rep.of("cyl", "soft") if x.time == tb and x.quantity == "accel")
    assert_allclose(s.jump, gain * a.jump, rtol=1e-10)
    assert rep.limit("rocker.omega", tb, "left") == pytest.approx(
        rep.limit("rocker.omega", tb, "right"), rel=1e-14
    )


def test_peaks_and_inertia_torque(module):
    rep = _cubic(module)
    p3 = rep.peak("rocker.epsilon")
    assert p3.time == 5.0 and p3.side == "left"
    assert_allclose(p3.magnitude, 0.13616, atol=5e-6)
    assert_allclose(p3.inertia_torque, 120.0 * p3.magnitude, rtol=1e-15)  # J = 1000·1.2²/12
    assert rep.peak("cyl.epsilon").inertia_torque is None
    s = next(x for x in rep.of("rocker", "soft") if x.time == 0.0)
    assert_allclose(s.inertia_torque_jump, 120.0 * s.jump)
    # an interior peak (3-4-5) is refined to the true maximum
    law = get_law("345", 0.5, 5.0)
    rep = shock_report(module, {"cyl": law}, samples=21)
    p = rep.peak("rocker.epsilon")
    dense = simulate(module, {"cyl": law}, t=np.linspace(0.0, 5.0, 200001))
    eps = np.abs(dense.column("rocker.epsilon"))
    assert p.side == "sample"
    assert_allclose(p.magnitude, eps.max(), rtol=1e-9)
    assert p.magnitude >= eps.max() * (1.0 - 1e-12)  # never below the dense grid's max
    assert rep.peak("cyl.accel").magnitude == pytest.approx(law.peak_acceleration, rel=1e-9)


def test_profile_joins_and_coincident_drivers(module):
    p = Profile.from_laws([get_law("cubic", 0.3, 2.0), dwell(1.0), get_law("345", -0.3, 2.0)])
    rep = shock_report(module, {"cyl": Drive(p, initial=0.9)}, samples=101)
    assert_allclose(rep.times, [0.0, 2.0, 3.0, 5.0])
    assert {s.time for s in rep.soft} == {0.0, 2.0}
    assert "join 1" in rep.causes[1][0]


def test_report_without_breakpoints_and_text(module):
    fourbar = excavkin.load(excavkin.example_path("fourbar"))
    rep = shock_report(fourbar, {"crank": ConstantSpeedCrank(31.416)}, samples=73)
    assert rep.times.size == 0 and rep.shocks == ()
    assert {p.column for p in rep.peaks} >= {"rocker.epsilon", "coupler.epsilon"}
    assert rep.peak("rocker.epsilon").inertia_torque is not None
    text = _cubic(module).format()
    assert "6 soft shock(s)" in text and "t = 5 s (cyl: end of cubic)" in text
    frame = _cubic(module).to_frame()
    assert len(frame) == 6 and set(frame["kind"]) == {"soft"}
    assert _cubic(module).peaks_frame()["column"].tolist() == [
        "cyl.accel",
        "cyl.epsilon",
        "rocker.epsilon",
    ]


def test_errors(module):
    rep = _cubic(module)
    with pytest.raises(KeyError, match="no breakpoint"):
        rep.limit("rocker.epsilon", 2.5, "left")
    with pytest.raises(KeyError, match="no tracked quantity"):
        rep.limit("nothing.epsilon", 0.0, "left")
    with pytest.raises(KeyError, match="no peak"):
        rep.peak("rocker.omega")
    res = module.solve({"cyl": np.array([0.8, 0.9])})
    with pytest.raises(InputError, match="solved in time"):
        shock_report(module, {"cyl": get_law("cubic", 0.5, 5.0)}, res)


def test_tracked_columns(module):
    cols = {c.name: c for c in tracked_columns(module)}
    assert set(cols) == {
        "cyl.rate",
        "cyl.accel",
        "cyl.omega",
        "cyl.epsilon",
        "rocker.omega",
        "rocker.epsilon",
    }
    assert cols["rocker.epsilon"].inertia == pytest.approx(120.0)
    assert cols["cyl.accel"].order == 2 and cols["cyl.omega"].order == 1


def test_hard_shocks_of_a_law_that_starts_moving():
    """A user law with a velocity step (constant-speed ramp, f = u): hard shocks of the rod's
    rate and of every ω at both ends; the rod's acceleration is 0 on both sides, yet the links'
    ε jump by u''·v² (the velocity term) — soft shocks of the links only."""
    from dataclasses import dataclass
    from typing import ClassVar

    from excavkin.motion import MotionLaw, PeakCoefficients

    @dataclass(frozen=True, slots=True)
    class Ramp(MotionLaw):
        name: ClassVar[str] = "ramp"

        def _shape(self, u, left=False):
            return u, np.ones_like(u), np.zeros_like(u), np.zeros_like(u)

        @property
        def coefficients(self):
            return PeakCoefficients(1.0, 0.0, 0.0)

    module = excavkin.load(excavkin.example_path("pasika_module"))
    rep = shock_report(module, {"cyl": Ramp(0.5, 5.0)}, samples=51)
    hard = {(s.time, s.column): s.jump for s in rep.hard}
    assert set(hard) == {
        (t, c) for t in (0.0, 5.0) for c in ("cyl.rate", "cyl.omega", "rocker.omega")
    }
    assert_allclose([hard[(0.0, "cyl.rate")], hard[(5.0, "cyl.rate")]], [0.1, -0.1])
    assert {s.column for s in rep.soft} == {"cyl.epsilon", "rocker.epsilon"}
    q = np.array([0.8, 1.3])
    second = module.solve({"cyl": q}, {"cyl": np.ones(2)}).column("rocker.epsilon")
    de = {s.time: s.jump for s in rep.of("rocker", "soft")}
    assert_allclose([de[0.0], de[5.0]], [second[0] * 0.1**2, -second[1] * 0.1**2], rtol=1e-12)
