"""Tolerance and clearance bands: the linear worst case against every corner of the tolerance
box, the Monte Carlo spread against the linear theory, pin clearances against link lengths,
and the command line."""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

import excavkin
from excavkin import Gravity
from excavkin.cli import main
from excavkin.errors import InputError
from excavkin.studies.tolerance import parse_tolerance, tolerance_bands

TOLS = {"A-B": 1e-4, "O4.x": 2e-4, "O4-B": 5e-5}


@pytest.fixture(scope="module")
def fourbar() -> excavkin.Mechanism:
    return excavkin.load(excavkin.example_path("fourbar"))


@pytest.fixture(scope="module")
def sweep() -> dict[str, np.ndarray]:
    return {"crank": np.radians(np.linspace(0, 350, 15))}


def test_worst_case_is_the_worst_corner(fourbar, sweep) -> None:  # type: ignore[no-untyped-def]
    """For small tolerances the linear worst case equals the largest deviation over the 2³
    corners of the tolerance box, solved as designs (to second order: 5e-4 relative at these
    1 µm tolerances, about 1e-2 at a hundred times them)."""
    tols = {k: v / 100 for k, v in TOLS.items()}
    bands = tolerance_bands(fourbar, sweep, tolerances=tols, draws=0)
    n = len(sweep["crank"])
    corners = list(itertools.product((-1.0, 1.0), repeat=len(tols)))
    params = {
        name: np.repeat([fourbar.parameters[name] + s[k] * tol for s in corners], n)
        for k, (name, tol) in enumerate(tols.items())
    }
    res = fourbar.solve({"crank": np.tile(sweep["crank"], len(corners))}, params=params)
    for col in ("B.x", "B.y", "rocker.angle", "rocker.omega", "B.transmission"):
        j = bands.index(col)
        dev = np.abs(res.column(col).reshape(len(corners), n) - bands.nominal[:, j]).max(axis=0)
        np.testing.assert_allclose(dev, bands.worst[:, j], rtol=5e-4, atol=1e-14)
        assert np.all(bands.rss[:, j] <= bands.worst[:, j] + 1e-15)


@pytest.mark.parametrize("distribution", ["normal", "uniform"])
def test_monte_carlo_converges_to_the_linear_theory(fourbar, sweep, distribution) -> None:  # type: ignore[no-untyped-def]
    """With 40 000 draws the Monte Carlo standard deviation equals the linear prediction
    √(Σ (∂c/∂p)²σ_p² + Σ |∇_j c|²c²/4) to 2 %, and its range lies within the worst case."""
    c = 3e-5
    bands = tolerance_bands(
        fourbar, sweep, tolerances=TOLS, clearance=c, draws=40_000, distribution=distribution
    )
    names = list(TOLS)
    offsets = [k for k in fourbar_offsets(fourbar)]
    res = fourbar.solve(sweep, sensitivities=names + offsets)
    # σ of the drawn distribution: uniform tol/√3; normal σ = tol/3 cut at ±3σ
    factor = 1 / np.sqrt(3) if distribution == "uniform" else 0.986579 / 3
    for col in ("B.x", "B.y", "rocker.angle", "rocker.epsilon"):
        j = bands.index(col)
        var = sum((res.sensitivity(col, p) * TOLS[p] * factor) ** 2 for p in names)
        var = var + sum(res.sensitivity(col, p) ** 2 * c * c / 4 for p in offsets)
        np.testing.assert_allclose(bands.mc_std[:, j], np.sqrt(var), rtol=0.02)
        reach = np.maximum(
            bands.mc_max[:, j] - bands.nominal[:, j], bands.nominal[:, j] - bands.mc_min[:, j]
        )
        assert np.all(reach <= bands.worst[:, j] * (1 + 1e-3))
        assert np.all(reach >= 0.5 * bands.rss[:, j])
    assert bands.failed.sum() == 0


def fourbar_offsets(mech: excavkin.Mechanism) -> list[str]:
    from excavkin.structure.design import joint_offsets

    return list(joint_offsets(mech.model))


def test_a_pin_offset_along_its_link_is_a_change_of_length(fourbar) -> None:  # type: ignore[no-untyped-def]
    """The rocker's pin at B moved along the rocker (its frame's x) changes the rocker's
    length: the sensitivities agree to round-off; across the rocker it changes nothing to
    first order."""
    res = fourbar.solve(
        {"crank": np.radians([10.0, 100.0, 250.0])},
        sensitivities=["B@rocker.x", "B@rocker.y", "O4-B"],
    )
    for col in ("B.x", "rocker.omega", "coupler.epsilon"):
        np.testing.assert_allclose(
            res.sensitivity(col, "B@rocker.x"), res.sensitivity(col, "O4-B"), rtol=1e-12
        )
        assert np.abs(res.sensitivity(col, "B@rocker.y")).max() < 1e-9


def test_the_same_seed_gives_the_same_bands(fourbar, sweep) -> None:  # type: ignore[no-untyped-def]
    a = tolerance_bands(fourbar, sweep, tolerances=TOLS, draws=3000, seed=4)
    b = tolerance_bands(fourbar, sweep, tolerances=TOLS, draws=3000, seed=4)
    np.testing.assert_array_equal(a.mc_max, b.mc_max)
    np.testing.assert_array_equal(a.mc_std, b.mc_std)
    assert a.ranking("B.x")[0][0] in TOLS


def test_tolerance_texts_and_errors(fourbar, sweep) -> None:  # type: ignore[no-untyped-def]
    assert parse_tolerance("±0.1 mm", "length", "t") == pytest.approx(1e-4)
    assert parse_tolerance("+-0.1mm", "length", "t") == pytest.approx(1e-4)
    assert parse_tolerance("+/- 2 deg", "angle", "t") == pytest.approx(np.radians(2))
    with pytest.raises(InputError, match="half-width"):
        parse_tolerance("-1 mm", "length", "t")
    with pytest.raises(InputError, match="did you mean 'A-B'"):
        tolerance_bands(fourbar, sweep, tolerances={"A-C": 1e-4})
    with pytest.raises(InputError, match="nothing is toleranced"):
        tolerance_bands(fourbar, sweep)
    with pytest.raises(InputError, match="joint"):
        tolerance_bands(fourbar, sweep, clearance={"Q": 1e-5})


def test_the_command_writes_bands_and_a_plot(tmp_path) -> None:  # type: ignore[no-untyped-def]
    out, png = tmp_path / "bands.csv", tmp_path / "bands.png"
    args = [
        "tolerance",
        "fourbar",
        "--sweep",
        "crank=0deg:360deg:13",
        "--tol",
        "A-B=±0.1mm",
        "--tol",
        "O4.x=±0.2mm",
        "--clearance",
        "0.05mm",
        "--clearance",
        "B=0.02mm",
        "--draws",
        "2000",
        "--column",
        "B.y",
        "--column",
        "rocker.angle",
        "-o",
        str(out),
        "--plot",
        str(png),
    ]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    assert "B.y" in r.output and "O4.x" in r.output
    table = pd.read_csv(out)
    assert set(table["column"]) == {"B.y", "rocker.angle"} and len(table) == 26
    assert (table["worst_high"] >= table["mc_max"] - 1e-12).all()
    assert png.stat().st_size > 10_000
    bad = CliRunner().invoke(main, [*args[:4], "--tol", "A-B=±1kg", "--draws", "10"])
    assert bad.exit_code == 2 and "is not a length" in bad.output
    again = CliRunner().invoke(main, args)
    assert again.exit_code == 2 and "exists" in again.output


def test_force_bands_follow_the_linear_theory_too() -> None:
    """The excavator's bucket-cylinder force with its bucket linkage's pins and the bucket's
    mass toleranced, under gravity (static: no rate is given): the Monte Carlo σ equals the
    linear prediction from the exact force sensitivities (to 3 % with 20 000 draws), within the
    worst case."""
    mech = excavkin.load(excavkin.example_path("excavator"))
    sk = mech.sketch_values()
    values = {"bucket_cyl": np.linspace(0.95, 1.05, 5) * sk["bucket_cyl"]}
    tols = {"K.x": 5e-4, "F.y": 5e-4, "bucket.mass": 20.0}
    col = "bucket_cyl.force"
    bands = tolerance_bands(
        mech, values, tolerances=tols, loads=[Gravity()], draws=20_000, columns=[col], seed=3
    )
    res = mech.solve(values, loads=[Gravity()], sensitivities=list(tols))
    sigma = np.sqrt(sum((res.sensitivity(col, p) * t * 0.986579 / 3) ** 2 for p, t in tols.items()))
    np.testing.assert_allclose(bands.mc_std[:, 0], sigma, rtol=0.03)
    reach = np.maximum(bands.mc_max - bands.nominal, bands.nominal - bands.mc_min)[:, 0]
    assert np.all(reach <= bands.worst[:, 0] * (1 + 1e-3))
    assert bands.ranking(col)[0][0] == "bucket.mass"


def test_a_joints_own_clearance_wins_over_the_one_for_all(tmp_path) -> None:  # type: ignore[no-untyped-def]
    base = [
        "tolerance",
        "fourbar",
        "--sweep",
        "crank=0deg:360deg:13",
        "--draws",
        "0",
        "--column",
        "B.x",
    ]
    widths = []
    for order in (["0.01mm", "A=0.05mm"], ["A=0.05mm", "0.01mm"]):
        out = tmp_path / f"{len(widths)}.csv"
        args = [*base, *sum((["--clearance", c] for c in order), []), "-o", str(out)]
        r = CliRunner().invoke(main, args)
        assert r.exit_code == 0, r.output
        widths.append(pd.read_csv(out)["worst_high"].to_numpy())
    np.testing.assert_array_equal(widths[0], widths[1])
    alone = tolerance_bands(
        excavkin.load(excavkin.example_path("fourbar")),
        {"crank": np.radians(np.linspace(0, 360, 13))},
        clearance={"A": 5e-5, "O2": 1e-5, "B": 1e-5, "O4": 1e-5},
        columns=["B.x"],
        draws=0,
    )
    np.testing.assert_allclose(widths[0], (alone.nominal + alone.worst)[:, 0], rtol=1e-12)
    for twice, words in (
        (["--clearance", "0.01mm", "--clearance", "0.02mm"], "more than once"),
        (["--clearance", "A=0.01mm", "--clearance", "A=0.02mm"], "more than once"),
        (["--tol", "A-B=0.1mm", "--tol", "A-B=0.2mm"], "more than once for A-B"),
    ):
        r = CliRunner().invoke(main, [*base, *twice])
        assert r.exit_code == 2 and words in r.output, r.output
