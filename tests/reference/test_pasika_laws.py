"""Reference tests: the Pasika & Koruniak module in time, and the follow-up programme on laws.

Paper: V. Pasika, P. Koruniak, "Kinematic analysis of a lever mechanism with an internal
driving link" (seed 003); specification ``seeds/pasika-internal-driving-link.md`` ("spec §x").
Data (spec §4.1): a = 0.45 m, b = 0.9 m, l_OA0 = 0.8 m, l_AB = 1.2 m, H = 0.5 m, T = 5 s.
Reference values: ``tests/reference/data/pasika_table_4_3.csv`` (spec §4.3) and the paper's
own closed-form equations, re-implemented independently in :mod:`excavkin.papers.pasika.reference`.

The engine here is the general one (``examples/pasika_module.toml`` → solve plan → dyad
kernels) fed by the time-domain layer (:func:`excavkin.simulation.timeline.simulate`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

import excavkin
from excavkin.cli import main
from excavkin.motion import LAW_NAMES, get_law
from excavkin.papers.pasika import reference as ref
from excavkin.papers.pasika.laws import compare_laws, end_gains, pasika_module
from excavkin.simulation.timeline import simulate

DATA = Path(__file__).parent / "data" / "pasika_table_4_3.csv"
DOCS = Path(__file__).resolve().parents[2] / "docs"
H, T = 0.5, 5.0
SHOCK_FREE = {"345", "4567", "cycloidal", "modified-trapezoid", "modified-sine", "s-curve"}
WITH_SHOCKS = {"cubic": 2, "harmonic": 2, "trapezoidal": 4}  # soft shocks of the rod


@pytest.fixture(scope="module")
def module() -> excavkin.Mechanism:
    return excavkin.load(excavkin.example_path("pasika_module"))


@pytest.fixture(scope="module")
def study():
    return compare_laws(intervals=1000)


def _engine(mech, law, t):
    res = simulate(mech, {"cyl": law}, t=t)
    assert res.status.all_ok
    return {
        "phi1": res.column("cyl.angle"),
        "omega1": res.column("cyl.omega"),
        "eps1": res.column("cyl.epsilon"),
        "phi3": res.column("rocker.angle"),
        "omega3": res.column("rocker.omega"),
        "eps3": res.column("rocker.epsilon"),
        "l_oa": res.column("cyl.value"),
    }


def _reference(law, t):
    st = law.evaluate(t)
    k = ref.kinematics(st.s, st.v, st.a)
    return {
        "phi1": k.positions.phi1,
        "omega1": k.velocities.omega1,
        "eps1": k.accelerations.eps1,
        "phi3": k.positions.phi3,
        "omega3": k.velocities.omega3,
        "eps3": k.accelerations.eps3,
        "l_oa": k.positions.l_oa,
    }


def test_model_file_is_the_papers_module(module):
    """The TOML model: O at the origin, B = (−a, b), |BA| = 1.2 m, |OA| = 0.8 m at s = 0, the
    rocker's body angle is φ3 (B→A) and the cylinder's line angle is φ1 (spec §4.3, t = 0)."""
    assert module.inputs == ("cyl",)
    assert_allclose(module.sketch_values()["cyl"], 0.8, rtol=1e-15)
    res = module.solve({"cyl": np.array([0.8])})
    assert_allclose(np.degrees(res.column("cyl.angle")), [34.1497], atol=5e-5)
    assert_allclose(np.degrees(res.column("rocker.angle")), [-22.0714], atol=5e-5)
    _, _, b = res.point("B")
    assert_allclose(res.point("B")[0], [[-0.45, 0.9]])
    assert_allclose(np.hypot(*(res.point("A")[0] - res.point("B")[0])[0]), 1.2, rtol=1e-15)
    rocker = module.model.body("rocker")
    assert rocker.mass == 1000.0 and rocker.inertia == pytest.approx(1000.0 * 1.2**2 / 12)


def test_builder_matches_model_file(module):
    t = np.linspace(0.0, T, 51)
    law = get_law("cubic", H, T)
    a, b = _engine(module, law, t), _engine(pasika_module(), law, t)
    for key in a:
        assert_allclose(a[key], b[key], rtol=1e-13, atol=1e-15, err_msg=key)


@pytest.mark.parametrize("name", LAW_NAMES)
def test_engine_matches_papers_closed_form(module, name):
    """Time-domain engine vs the paper's equations (1)–(3), (8), (9), (11), (12), corrected as
    in spec §5, to 1e-9 relative (max over the run, relative to the quantity's range) — for
    the cubic law of the paper and every other law (the formulas accept any s, v21, a21)."""
    t = np.linspace(-0.5, T + 0.5, 1201)
    law = get_law(name, H, T)
    eng, rf = _engine(module, law, t), _reference(law, t)
    for key in eng:
        scale = max(float(np.max(np.abs(rf[key]))), 1e-300)
        assert np.max(np.abs(eng[key] - rf[key])) <= 1e-9 * scale, key


def test_reference_table_in_time(module):
    """Spec §4.3 table (cubic law) from the time-domain run, to the printed digits."""
    tab = np.loadtxt(DATA, delimiter=",", skiprows=1)
    res = simulate(module, {"cyl": get_law("cubic", H, T)}, t=tab[:, 0])
    cols = [
        (res.column("cyl.value") - 0.8, 4),
        (res.column("cyl.rate"), 4),
        (res.column("cyl.accel"), 4),
        (np.degrees(res.column("cyl.angle")), 4),
        (res.column("cyl.omega"), 5),
        (res.column("cyl.epsilon"), 5),
        (np.degrees(res.column("rocker.angle")), 4),
        (res.column("rocker.omega"), 5),
        (res.column("rocker.epsilon"), 5),
    ]
    for k, (val, digits) in enumerate(cols, start=1):
        assert_allclose(val, tab[:, k], rtol=0, atol=0.5 * 10.0**-digits + 1e-12, err_msg=str(k))


def test_almost_linear_cubic(module):
    """Spec §4.3: the cubic law's ε1, ε3 leave a straight-line fit by 6 % and 4 % of their
    ranges ("almost linear")."""
    t = np.linspace(0.0, T, 1001)
    res = simulate(module, {"cyl": get_law("cubic", H, T)}, t=t)
    for col, expected in (("cyl.epsilon", 0.060), ("rocker.epsilon", 0.037)):
        e = res.column(col)
        resid = e - np.polyval(np.polyfit(t, e, 1), t)
        assert_allclose(np.max(np.abs(resid)) / np.ptp(e), expected, atol=0.003)


# ------------------------------------------------------------------------ the programme


def test_table_cubic_row_is_the_papers(study):
    r = study.row("cubic")
    assert_allclose([r.rod_peak, r.rod_start, r.rod_end], [0.12, 0.12, -0.12], rtol=1e-12)
    assert_allclose(
        [r.cyl_start, r.cyl_end, r.rocker_start, r.rocker_end],
        [0.10034, -0.08530, 0.12031, -0.13616],
        atol=5e-6,
    )
    assert_allclose(r.cyl_peak, 0.10034, atol=5e-6)
    assert_allclose(r.rocker_peak, 0.13616, atol=5e-6)
    assert_allclose(r.rocker_torque_peak, 120.0 * r.rocker_peak)


def test_which_laws_remove_the_soft_shocks(study):
    assert {r.law for r in study.rows if r.shock_free} == SHOCK_FREE
    for r in study.rows:
        assert r.hard == 0
        if r.law in WITH_SHOCKS:
            assert r.rod_soft == WITH_SHOCKS[r.law]
            assert r.link_soft == 2 * WITH_SHOCKS[r.law]  # cylinder and rocker, each time
        else:
            assert r.rod_soft == r.link_soft == 0
            assert_allclose(
                [r.rod_start, r.rod_end, r.cyl_start, r.cyl_end, r.rocker_start, r.rocker_end],
                0.0,
                atol=1e-15,
            )


def test_peaks_follow_the_laws_coefficients(study):
    """Rod: max|a21| = C_a·H/T² exactly. Links: the rocker's peak ε ranks the laws nearly as
    C_a does (the cylinder's too), so the 4-5-6-7 law, with the largest C_a, loads the links
    most."""
    ca = np.array([r.c_a for r in study.rows])
    assert_allclose([r.rod_peak for r in study.rows], ca * H / T**2, rtol=1e-9)
    for attr in ("rocker_peak", "cyl_peak"):
        peaks = np.array([getattr(r, attr) for r in study.rows])
        assert study.rows[int(np.argmax(peaks))].law == "4567"
        assert np.corrcoef(ca, peaks)[0, 1] > 0.98


def test_links_copy_the_rods_law(study, module):
    """The paper's claim, quantified for each law: ε1(t), ε3(t) correlate with a21(t) with
    r > 0.995; at the ends ε/a21 is the geometric gain u'(s) (law-independent, exact at rest:
    ε = u'·a21 + u''·v21², v21 = 0); the velocity term u''·v21² stays below 15 % of max|ε|."""
    gains = end_gains(module, "cyl", [0.8, 1.3], ["cyl.omega", "rocker.omega"])
    assert_allclose(gains, study.gains, rtol=1e-12)
    # the gains of spec §4.3: ε/a21 at t = 0 and T for the cubic law
    assert_allclose(gains[:, 0], [0.10034 / 0.12, 0.08530 / 0.12], atol=1e-4)
    assert_allclose(gains[:, 1], [0.12031 / 0.12, 0.13616 / 0.12], atol=1e-4)
    for r in study.rows:
        assert r.corr_cyl > 0.995 and r.corr_rocker > 0.997, r.law
        assert_allclose(r.ratio_cyl, gains[:, 0], rtol=1e-10, err_msg=r.law)
        assert_allclose(r.ratio_rocker, gains[:, 1], rtol=1e-10, err_msg=r.law)
        assert 0.0 < r.v2_share_rocker < r.v2_share_cyl < 0.15, r.law
    # the cubic law has the smallest velocity term (lowest C_v among the polynomial laws)
    assert study.row("cubic").v2_share_rocker == min(r.v2_share_rocker for r in study.rows)


def test_text_and_markdown_tables(study):
    md = study.markdown()
    assert md.count("\n| cubic |") == 2 and "| 6.0000 | 0.1200 | +0.1200 | -0.1200 |" in md
    text = study.text()
    assert "-0.0000" not in text and "-0.00000" not in text
    frame = study.to_frame()
    assert len(frame) == len(LAW_NAMES) and bool(frame["shock_free"].sum() == len(SHOCK_FREE))


def test_reproduce_pasika_laws_cli(tmp_path):
    r = CliRunner().invoke(
        main,
        ["reproduce", "pasika-laws", "--out-dir", str(tmp_path), "--intervals", "200"],
        catch_exceptions=False,
    )
    assert r.exit_code == 0, r.output
    assert (
        "no soft shocks: 345, 4567, cycloidal, modified-trapezoid, modified-sine, s-curve"
        in r.output
    )
    assert "cubic (2 on the rod, 4 on the links)" in r.output
    png = tmp_path / "pasika-laws.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (tmp_path / "pasika-laws.csv").exists() and (tmp_path / "pasika-laws.md").exists()
    r = CliRunner().invoke(main, ["reproduce", "--help"])
    assert "pasika-laws" in r.output


def test_docs_carry_the_table_and_figure():
    page = (DOCS / "time-domain.md").read_text(encoding="utf-8")
    assert "img/pasika-laws.png" in page and "| cubic |" in page
    img = DOCS / "img" / "pasika-laws.png"
    assert img.stat().st_size < 300_000
