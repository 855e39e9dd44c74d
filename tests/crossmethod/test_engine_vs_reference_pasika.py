"""Pasika & Koruniak: the engine (examples/pasika_module.toml) against the paper's own equations.

Reference: excavkin.papers.pasika.reference (eqs. 1-12, Coriolis term corrected to 2·ω1·v21);
source: V. Pasika, P. Koruniak, seed 003, spec seeds/pasika-internal-driving-link.md.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from excavkin.papers import common
from excavkin.papers.pasika import reference as ref
from excavkin.papers.pasika import study as papers
from excavkin.papers.pasika.cli import command
from tests.conftest import assert_rel, fd_derivatives

T = papers.PASIKA_DURATION


@pytest.fixture(scope="module")
def mech():  # type: ignore[no-untyped-def]
    return common.load_paper_model("pasika_module")


def test_model_is_the_papers_module(mech) -> None:  # type: ignore[no-untyped-def]
    data = ref.PASIKA_PAPER
    plan = mech.plan
    assert plan.shapes["ground"].distance("O", "B") == pytest.approx(data.l_ob, rel=1e-15)
    assert plan.shapes["rocker"].distance("B", "A") == pytest.approx(data.l_ab, rel=1e-15)
    assert mech.sketch_values()["cyl"] == pytest.approx(data.l_oa0, rel=1e-12)


def test_every_quantity_equals_the_reference_over_the_stroke(mech) -> None:  # type: ignore[no-untyped-def]
    t = np.linspace(0.0, T, 1001)
    run = papers.pasika_run(t, mech)
    assert run.result.status.all_ok
    s, v, a = ref.cubic_law(t)
    np.testing.assert_allclose(run["s"], s, rtol=0, atol=1e-15)
    np.testing.assert_allclose(run["v21"], v, rtol=0, atol=1e-15)
    np.testing.assert_allclose(run["a21"], a, rtol=0, atol=1e-15)
    k = ref.kinematics(s, v, a)
    np.testing.assert_allclose(run["l_oa"], k.positions.l_oa, rtol=1e-12)
    for name, expected in (
        ("phi1", k.positions.phi1),
        ("phi3", k.positions.phi3),
        ("omega1", k.velocities.omega1),
        ("omega3", k.velocities.omega3),
        ("eps1", k.accelerations.eps1),
        ("eps3", k.accelerations.eps3),
        ("coriolis", k.accelerations.coriolis),
    ):
        assert_rel(run[name], expected, 1e-9)
    # pointwise, where the rates are not at their zeros
    inner = slice(50, -50)
    for name, expected in (("omega1", k.velocities.omega1), ("omega3", k.velocities.omega3)):
        np.testing.assert_allclose(run[name][inner], expected[inner], rtol=1e-9)
    agree = papers.pasika_reference_agreement(run)
    assert max(agree.values()) < 1e-12


def test_rates_match_8th_order_differences_in_time(mech) -> None:  # type: ignore[no-untyped-def]
    h = 1e-2
    t = np.linspace(4 * h, T - 4 * h, 41)
    run = papers.pasika_run(t, mech)

    def at(dt: float) -> np.ndarray:
        r = papers.pasika_run(t + dt, mech)
        return np.concatenate([r["phi1"], r["phi3"]])

    d1, d2 = fd_derivatives(at, h)
    assert_rel(d1, np.concatenate([run["omega1"], run["omega3"]]), 1e-9)
    assert_rel(d2, np.concatenate([run["eps1"], run["eps3"]]), 1e-8)
    # the paper claims 0.2 %; ours
    assert max(papers.pasika_derivative_agreement(mech).values()) < 1e-8


def test_spec_table_4_3_digits(mech) -> None:  # type: ignore[no-untyped-def]
    run = papers.pasika_run(np.array(papers.PASIKA_TIMES), mech)
    for key, values in papers.PASIKA_SPEC_TABLE.items():
        ours = np.degrees(run[key]) if key.startswith("phi") else run[key]
        digits = 4 if key in ("phi1", "phi3", "s", "v21", "a21") else 5
        np.testing.assert_allclose(ours, values, rtol=0, atol=0.5 * 10.0**-digits)


def test_published_values(mech) -> None:  # type: ignore[no-untyped-def]
    rows = {p.quantity: p for p in papers.pasika_published(mech)}
    assert rows["max v21 and its time (Fig. 3)"].ours == "0.1500 m/s at 2.500 s"
    assert rows["a21 at t = 0 and t = T (Fig. 3)"].ours == "+0.1200 / -0.1200 m/s²"
    assert rows["φ1, φ3 increase monotonically (Fig. 5)"].ours == "yes"


def test_printed_coriolis_term_fails_against_the_engine(mech) -> None:  # type: ignore[no-untyped-def]
    """The print's a_k = 2·ω3·v21 gives ε1 off the engine by far more than the paper's 0.2 %."""
    t = np.linspace(0.0, T, 201)
    run = papers.pasika_run(t, mech)
    w3, v = run["omega3"], run["v21"]
    dphi = run["phi1"] - run["phi3"]
    l_ab, l_oa = ref.PASIKA_PAPER.l_ab, run["l_oa"]
    printed = (l_ab * (run["eps3"] * np.cos(dphi) + w3**2 * np.sin(dphi)) - 2 * w3 * v) / l_oa
    err = np.max(np.abs(printed - run["eps1"])) / np.max(np.abs(run["eps1"]))
    assert err > 0.1


def test_reproduce_command(tmp_path: Path) -> None:
    out = tmp_path / "out"
    result = CliRunner().invoke(command, ["--out-dir", str(out), "--samples", "101"])
    assert result.exit_code == 0, result.output
    assert "0.15 m/s at 2.5 s" in result.output
    assert "≤ 0.2 %" in result.output
    for name in ("pasika-fig3.png", "pasika-fig5.png"):
        png = out / name
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
