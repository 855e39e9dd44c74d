"""Maksimov's rope-shovel bucket mechanism: the engine (examples/rope_shovel.toml) against the
paper's own equations (1)-(19), corrected (excavkin.papers.rope_shovel.reference; seeds 000/004,
spec seeds/maksimov-rope-shovel-bucket.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from excavkin.papers import common
from excavkin.papers.rope_shovel import reference as ref
from excavkin.papers.rope_shovel import study as papers
from excavkin.papers.rope_shovel.cli import command
from tests.conftest import assert_rel

GEOM = ref.EO4112_GEOMETRY
PHI1 = np.radians(np.linspace(60.0, 150.0, 181))  # the paper's working range, a quarter turn
ANGLES = {k for k, v in papers.ROPE_SHOVEL_KINDS.items() if v == "angle"}


@pytest.fixture(scope="module")
def mech():  # type: ignore[no-untyped-def]
    return common.load_paper_model("rope_shovel")


@pytest.fixture(scope="module")
def run(mech):  # type: ignore[no-untyped-def]
    return papers.rope_shovel_sweep(PHI1, mech=mech)


def test_model_has_the_reference_dimensions(mech) -> None:  # type: ignore[no-untyped-def]
    sh = mech.plan.shapes
    d = {
        "l1": sh["stick"].distance("O1", "O2"),
        "l2": sh["lever"].distance("O2", "B"),
        "l4": sh["boom"].distance("O1", "A"),
        "l5": sh["lever"].distance("O2", "C"),
        "l6": sh["coupler"].distance("C", "D"),
        "l7": sh["bucket"].distance("E", "D"),
        "l8": sh["stick"].distance("O2", "E"),
        "l9": sh["bucket"].distance("E", "H"),
        "ke": sh["stick"].distance("K", "E"),
        "l13": sh["boom"].distance("O1", "F"),
    }
    for k, v in d.items():
        assert v == pytest.approx(getattr(GEOM, k), rel=1e-13), k
    c2 = next(e for e in mech.plan.elements if e.name == "c2")
    assert c2.mode == "locked" and c2.length == pytest.approx(GEOM.l3, rel=1e-15)
    assert next(e for e in mech.plan.elements if e.name == "c1").mode == "free"
    assert sh["stick"].distance("O1", "E") == pytest.approx(GEOM.o1e_length, rel=1e-13)


def test_winch_is_the_reference_drive() -> None:
    d = ref.EO4112_DRIVE
    v = ref.rope_speed(d.omega_motor, d.r_drum, d.gear_ratio, d.multiplicity)
    assert papers.EO4112_WINCH.rope_speed == pytest.approx(float(v[0]), rel=1e-15)


def test_every_quantity_equals_the_reference(run) -> None:  # type: ignore[no-untyped-def]
    assert run.result.status.all_ok
    st = ref.bucket_mechanism_from_drive(GEOM, ref.EO4112_DRIVE, PHI1)
    compared = 0
    for field in st._fields:
        if field not in run.columns:
            continue
        expected = np.asarray(getattr(st, field))
        got = run[field]
        if field in ANGLES:
            got = expected + common.wrap(got - expected)
        assert_rel(got, expected, 1e-9)
        compared += 1
    # every field of the reference state is compared (the engine reports all of them)
    assert compared == len(st._fields)
    np.testing.assert_allclose(run["phi1"], PHI1, rtol=0, atol=1e-12)


def test_rope_drive_gives_omega1_by_corrected_eq2(run) -> None:  # type: ignore[no-untyped-def]
    w1 = ref.stick_rate_from_rope(GEOM.o1e_length, GEOM.l13, PHI1, run["v_rope"])
    assert_rel(run["omega1"], w1, 1e-9)
    printed = ref.printed_eq2_omega1(GEOM.o1e_length, GEOM.l13, PHI1, run["v_rope"])
    assert np.max(np.abs(printed - run["omega1"])) > 0.1 * np.max(np.abs(run["omega1"]))


def test_printed_eq15_fails_against_the_engine(run) -> None:  # type: ignore[no-untyped-def]
    """(15) as printed (input rate ω2, angle φ7 of (13)) is not the engine's bucket rate."""
    printed = ref.printed_eq15_omega7(
        GEOM.l5, GEOM.l7, run["phi1"], run["phi2"], run["phi6"], run["phi7"], run["omega2"]
    )
    assert np.max(np.abs(printed - run["omega7p"])) > 0.1 * np.max(np.abs(run["omega7p"]))


def _fd(mech, phi1: np.ndarray, key: str, h: float) -> np.ndarray:  # type: ignore[no-untyped-def]
    from tests.conftest import fd_derivatives

    def at(dp: float) -> np.ndarray:
        r = papers.rope_shovel_sweep(phi1 + dp, mech=mech)
        return np.unwrap(r[key]) if key in ANGLES else r[key]

    return fd_derivatives(at, h)[0]


def test_rates_and_accelerations_match_8th_order_differences(mech, run) -> None:  # type: ignore[no-untyped-def]
    """d/dt = ω1·d/dφ1: every rate against differences of its angle or length in φ1, and the
    engine's accelerations (ε1, ε of the bucket, a of Ц1) against differences of the rates."""
    h = 1e-3
    w1 = run["omega1"]
    for angle, rate in (
        ("phi1", "omega1"),
        ("phi2", "omega2"),
        ("phi3", "omega3"),
        ("phi7p", "omega7p"),
        ("phi6", "omega6"),
        ("gamma", "omega10"),
        ("hk", "v_c1"),
        ("bucket_to_horizon", "omega7_abs"),
    ):
        assert_rel(w1 * _fd(mech, PHI1, angle, h), run[rate], 1e-9)
    assert_rel(-w1 * _fd(mech, PHI1, "fe", h), run["v_rope"], 1e-9)
    for rate, acc in (("omega1", "epsilon1"), ("omega7_abs", "epsilon7_abs"), ("v_c1", "a_c1")):
        assert_rel(w1 * _fd(mech, PHI1, rate, h), run[acc], 1e-8)


def test_reproduce_command(tmp_path: Path) -> None:
    out = tmp_path / "out"
    result = CliRunner().invoke(command, ["--out-dir", str(out), "--samples", "61"])
    assert result.exit_code == 0, result.output
    assert "not published" in result.output
    for name in ("rope-shovel-scheme.png", "rope-shovel-angles.png", "rope-shovel-rates.png"):
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
