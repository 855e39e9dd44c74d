"""The MO-100 hammer's kinetostatics: the general engine (``examples/mo100_hammer.toml``,
``loads=[]``: inertia only, crank and coupler massless) against the paper's own formulas
(``excavkin.papers.mo100.reference``) with the crank at ω1 = 31.416 s⁻¹, over φ ∈ [0.5°, 359.5°].

Compared, to 1e-9 of the largest value:

* the rocker's d'Alembert force −m3·a_S and couple −J·ε3, projected as the paper defines
  eq. (1): P_u^n along D→S, P_u^τ = −(component along the CCW normal of D→S) (signed like ε3),
  M_u = −(couple) = J·ε3 (J about S: the reference's "centroid" reading);
* the resultant of the pin forces *on the housing* with ``housing_force`` (Rx, Ry), after
  rotating the frame axes (x′ along A→D) into the housing axes (x along D→S at impact) by
  +α = +50°: S lies on the clockwise side of D→C in the model file, so the housing x axis
  is at −50° in frame axes;
* the crank torque with power balance, T·ω1 = dT/dt = I_D·ω3·ε3 = I_D·ω1³·u31·u31′
  (I_D = J + m3·lS², the rocker about its pivot; crank and coupler store no energy);
* the printed chain ``group_reactions`` (eqs. 9–11, Fig. 4 angle sense) with the engine's
  pins, sign corrections as ``docs/papers/mo100.md`` lists them: the printed R03^n and R03^τ
  are the components along D→C and along its CCW normal of *minus* the engine's force of pin
  D on the rocker (the printed chain returns the reactions with the opposite sign, like its
  Rx, Ry = −housing force); the printed R12 (eq. 11) is the engine's force of pin B on the
  coupler along B→C, and ``r12_from_eq6_7`` (the value eqs. 6–7 define) is its negative.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import excavkin
from excavkin.kinetostatics import inertia_loads
from excavkin.papers.mo100 import reference as mo100
from excavkin.papers.mo100 import study as app
from tests.conftest import EXAMPLES, assert_rel

OMEGA1 = 31.416


@pytest.fixture(scope="module")
def mech() -> excavkin.Mechanism:
    return excavkin.load(EXAMPLES / "mo100_hammer.toml")


@pytest.fixture(scope="module")
def phi() -> np.ndarray:
    return np.radians(np.linspace(0.5, 359.5, 1437))


@pytest.fixture(scope="module")
def solved(mech: excavkin.Mechanism, phi: np.ndarray) -> excavkin.kinetostatics.ForceResult:
    n = phi.size
    fr = mech.solve({"crank": phi}, {"crank": np.full(n, OMEGA1)}, {"crank": np.zeros(n)}, loads=[])
    assert fr.ok.all()
    return fr


def _unit(angle: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    u = np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    return u, np.stack([-u[:, 1], u[:, 0]], axis=-1)


def test_model_file_is_the_papers_data(mech: excavkin.Mechanism) -> None:
    data = app.reference_data(mech, OMEGA1)
    ref = mo100.MO100_PAPER
    for name in ("l1", "l2", "l3", "l0", "l_s", "alpha", "m3", "inertia", "omega1"):
        assert getattr(data, name) == pytest.approx(getattr(ref, name), rel=1e-9), name
    assert math.degrees(app.housing_axes_angle(mech)) == pytest.approx(-50.0, abs=1e-7)


def test_inertia_force_and_torque_match_eq1(
    solved: excavkin.kinetostatics.ForceResult, phi: np.ndarray
) -> None:
    kin = solved.kinematics
    j = solved.system.bodies.index("rocker")
    force, couple = inertia_loads(kin, solved.mass)
    psi = kin.body("rocker")[0]
    alpha = mo100.MO100_PAPER.alpha
    u, n = _unit(psi - alpha)  # D->S: alpha clockwise of D->C
    loads = mo100.inertia_loads(phi)
    assert_rel(np.sum(force[:, j] * u, axis=1), loads.p_n, 1e-9)
    assert_rel(-np.sum(force[:, j] * n, axis=1), loads.p_tau, 1e-9)
    assert_rel(-couple[:, j], loads.m_u, 1e-9)
    # the same through the application layer
    run = app.mo100_run(phi, omega1=OMEGA1)
    assert_rel(run.p_n, loads.p_n, 1e-9)
    assert_rel(run.p_tau, loads.p_tau, 1e-9)
    assert_rel(run.m_u, loads.m_u, 1e-9)


def test_housing_resultant_matches_housing_force(
    solved: excavkin.kinetostatics.ForceResult, phi: np.ndarray
) -> None:
    on_housing = solved.resultant("housing")
    # the same as the sum of the pin forces on the ground body
    np.testing.assert_array_equal(
        on_housing, solved.pin("A", "housing") + solved.pin("D", "housing")
    )
    # force on the housing = the rocker's d'Alembert force (crank, coupler massless)
    j = solved.system.bodies.index("rocker")
    f, _ = inertia_loads(solved.kinematics, solved.mass)
    assert_rel(on_housing, f[:, j], 1e-12)
    a = mo100.MO100_PAPER.alpha  # frame -> housing axes: rotate by +alpha
    rx = math.cos(a) * on_housing[:, 0] - math.sin(a) * on_housing[:, 1]
    ry = math.sin(a) * on_housing[:, 0] + math.cos(a) * on_housing[:, 1]
    rx_ref, ry_ref = mo100.housing_force(phi)
    assert_rel(rx, rx_ref, 1e-9)
    assert_rel(ry, ry_ref, 1e-9)
    run = app.mo100_run(phi, omega1=OMEGA1)
    assert_rel(run.rx, rx_ref, 1e-9)
    assert_rel(run.ry, ry_ref, 1e-9)


def test_crank_torque_is_power_balance(
    solved: excavkin.kinetostatics.ForceResult, phi: np.ndarray
) -> None:
    data = mo100.MO100_PAPER
    tf = mo100.transfer_functions(phi)
    expected = data.i_pivot * OMEGA1**2 * tf.u31 * tf.u31p  # T w1 = I_D w3 eps3
    torque = solved.torque("crank")
    assert_rel(torque, expected, 1e-9)
    assert solved.power_balance().relative.max() < 1e-12


def test_printed_chain_matches_engine_pins(
    solved: excavkin.kinetostatics.ForceResult, phi: np.ndarray
) -> None:
    kin = solved.kinematics
    e3, n3 = _unit(kin.body("rocker")[0])
    e2, _ = _unit(kin.body("coupler")[0])
    on_rocker_at_d = solved.pin("D", "rocker")
    on_coupler_at_b = solved.pin("B", "coupler")
    g = mo100.group_reactions(phi)
    assert_rel(-np.sum(on_rocker_at_d * n3, axis=1), g.r03_tau, 1e-9)
    # R03^n and R12 are the 0/0 forms (10)-(11) of the singular group: 1e-9 from 1 deg on
    # (at 0.5 deg the Cartesian engine's 1e-16/phi^3 conditioning gives 2e-9)
    away = (phi > np.radians(1.0)) & (phi < np.radians(359.0))
    r03_n = -np.sum(on_rocker_at_d * e3, axis=1)
    r12 = np.sum(on_coupler_at_b * e2, axis=1)
    assert_rel(r03_n[away], g.r03_n[away], 1e-9)
    assert_rel(r12[away], g.r12[away], 1e-9)
    assert_rel(-r12[away], g.r12_from_eq6_7[away], 1e-9)
    assert_rel(r03_n, g.r03_n, 5e-9)
    assert_rel(r12, g.r12, 5e-9)
    # the massless coupler is a two-force member: pin B on it is along B->C
    assert_rel(on_coupler_at_b, r12[:, None] * e2, 1e-12)


def test_change_point_is_a_dead_position_and_one_sided_values_agree(
    mech: excavkin.Mechanism,
) -> None:
    """At φ = 0 (and 2π) the engine flags a dead position of dyad C and gives no forces. Near
    it the Cartesian engine loses about 1e-16/φ² of relative precision (the kinematics test),
    so at 1 mrad its forces agree with the reference's half-angle forms to 1e-8, and its
    one-sided limits (cubic extrapolation from 1–4 mrad) with the reference's exact limits to
    1e-7 of the largest force (the torque's limit, 0, to 1e-6 of the largest torque)."""
    fr = mech.solve({"crank": np.array([0.0, 2 * np.pi])}, {"crank": OMEGA1}, loads=[])
    for i in (0, 1):
        assert fr.kinematics.status.message(i) == "dead position at dyad C (from B and D)"
    assert np.isnan(fr.resultant("housing")).all()
    assert np.isnan(fr.torque("crank")).all()

    near = np.array([2 * np.pi - 1e-2, 2 * np.pi - 1e-3, 1e-3, 1e-2])
    run = app.mo100_run(near, mech, OMEGA1)
    rx_ref, ry_ref = mo100.housing_force(near)
    scale = 55_449.0
    np.testing.assert_allclose(run.rx, rx_ref, rtol=0, atol=1e-8 * scale)
    np.testing.assert_allclose(run.ry, ry_ref, rtol=0, atol=1e-8 * scale)

    lim = app.one_sided_limits(mech, OMEGA1)
    two_pi = np.array([2 * np.pi])
    for side, phi0, got in (("before", two_pi, lim.before), ("after", np.zeros(1), lim.after)):
        rx0, ry0 = mo100.housing_force(phi0, impact_side=side)  # type: ignore[arg-type]
        assert got["rx"] == pytest.approx(rx0[0], abs=1e-7 * scale)
        assert got["ry"] == pytest.approx(ry0[0], abs=1e-7 * scale)
        assert got["torque"] == pytest.approx(0.0, abs=1e-6 * 18_846.0)  # 0; max |T| 18.8 kN m
    before, after = mo100.impact_limits()
    assert lim.before["u31"] == pytest.approx(before, rel=1e-8)
    assert lim.after["u31"] == pytest.approx(after, rel=1e-8)


def test_cycle_impulses_match_the_momentum_theorem(mech: excavkin.Mechanism) -> None:
    """Net x-impulse over the open cycle 0+…2π− is exactly 0, the y-impulse the blow's
    momentum m3·lS·ω1·(u31(0+) − u31(2π−)) = 534.6 N·s (reference ``cycle_impulse``)."""
    imp = app.rx_impulses(mech=mech, omega1=OMEGA1)
    sx, sy = mo100.cycle_impulse()
    assert abs(imp.net - sx) < 1e-9 * imp.positive
    assert imp.sy == pytest.approx(sy, rel=1e-7)
    pos, neg, _ = mo100.rx_lobe_impulses()
    assert imp.positive == pytest.approx(pos, rel=1e-7)
    assert imp.negative == pytest.approx(neg, rel=1e-7)
    assert [round(math.degrees(lo.stop), 1) for lo in imp.lobes] == [109.2, 344.0, 360.0]


def test_reproduction_table_engine_equals_reference(mech: excavkin.Mechanism) -> None:
    rows = app.reproduction_table(mech, OMEGA1)
    by = {r.quantity: r for r in rows}
    for r in rows:
        assert r.engine == pytest.approx(r.reference, rel=1e-7, abs=1e-6), r.quantity
    assert by["H = max Ry, 10° grid"].engine == pytest.approx(39_899.7, abs=0.1)
    assert by["mu = 2H/S (H 10° grid, S main lobe)"].engine == pytest.approx(165.14, abs=0.01)


def test_reproduce_command(tmp_path: Path) -> None:
    from excavkin.papers.cli import command

    out = tmp_path / "figs"
    result = CliRunner().invoke(command, ["mo100", "--out-dir", str(out), "--samples", "720"])
    assert result.exit_code == 0, result.output
    assert "H = max Ry, 10° grid" in result.output
    assert "39 899.7" in result.output and "39 895.0" in result.output
    assert "dead position at dyad C" in result.output
    for name in ("mo100-fig3.png", "mo100-fig5.png"):
        png = out / name
        assert png.stat().st_size > 10_000
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
