"""Issue 12: a change point between samples is said, and the user chooses how to go on."""

from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

import excavkin
from excavkin import Mechanism
from excavkin.cli import main
from excavkin.kinematics.kernels import Code
from excavkin.outputs.events import find_events
from tests.models import parallelogram

SQUARE = parallelogram()


def coupler_offset(res: excavkin.KinematicResult) -> np.ndarray:
    """|B − A − (O4 − O2)| per sample: zero while the linkage is a parallelogram."""
    return np.hypot(*(res.point("B")[0] - res.point("A")[0] - np.array([0.1, 0.0])).T)


@pytest.mark.parametrize("degrees", [np.linspace(-30, 30, 61), np.linspace(30, -30, 60)])
def test_the_parallelogram_through_its_change_point(degrees) -> None:
    mech = Mechanism(SQUARE)
    q = np.radians(degrees)
    side = mech.solve({"crank": q})
    (cp,) = side.change_points
    assert cp.point == "B" and cp.partners == ("A", "O4") and cp.continued == "side"
    crossing = np.flatnonzero(np.diff(np.sign(degrees)))[0]
    assert cp.before <= crossing + 1 <= cp.after
    # the sketch's side is kept: past the change point the linkage is folded, 200 mm off
    off = coupler_offset(side)
    assert np.nanmax(off) == pytest.approx(0.2, rel=1e-3) and np.nanmin(off) < 1e-12
    smooth = mech.solve({"crank": q}, continuation="smooth")
    assert [c.continued for c in smooth.change_points] == ["smooth"]
    ok = smooth.status.ok
    assert np.nanmax(coupler_offset(smooth)[ok]) < 1e-12
    # exactly at crank 0 the crank's end sits on the rocker's pivot: B is undetermined
    if 0.0 in degrees:
        zero = int(np.flatnonzero(degrees == 0.0)[0])
        assert smooth.status.labels()[zero].startswith("undetermined")


def test_change_points_are_warned_of_in_the_report_and_on_the_command_line(tmp_path) -> None:
    mech = Mechanism(SQUARE)
    res = mech.solve({"crank": np.radians(np.linspace(-20, 20, 41))})
    events = [e for e in find_events(res) if e.kind == "change point"]
    assert len(events) == 1 and "between samples 19 and 21" in events[0].message
    model = tmp_path / "square.toml"
    model.write_text(
        """schema_version = 1
name = "parallelogram"
[units]
length = "mm"
[points]
O2 = [0, 0]
A = [0, 100]
B = [100, 100]
O4 = [100, 0]
[bodies]
ground = { points = ["O2", "O4"], ground = true }
crank = { points = ["O2", "A"] }
coupler = { points = ["A", "B"] }
rocker = { points = ["O4", "B"] }
[drivers.crank]
type = "rotary"
body = "crank"
pivot = "O2"
reference = "ground"
"""
    )
    r = CliRunner().invoke(
        main,
        [
            "solve",
            str(model),
            "--sweep",
            "crank=-21deg:19deg:21",
            "--continuation",
            "smooth",
            "-q",
            "-o",
            str(tmp_path / "s.csv"),
        ],
    )
    assert r.exit_code == 0 and "change point of dyad B" in r.output and "other side" in r.output


def test_no_change_point_is_seen_where_there_is_none() -> None:
    for name in ("fourbar", "slider_crank", "excavator", "rope_shovel", "pasika_module"):
        mech = excavkin.load(excavkin.example_path(name))
        for n in (3, 4, 5, 9, 361):
            values = {
                k: v + np.linspace(0, 2 * np.pi, n)
                if mech.input_kind(k) == "angle"
                else v * np.linspace(0.9, 1.1, n)
                for k, v in mech.sketch_values().items()
            }
            assert mech.solve(values).change_points == (), (name, n)


@pytest.mark.parametrize("continuation", ["side", "smooth"])
def test_the_generic_solver_goes_through_the_change_point_as_the_closed_form(continuation) -> None:
    """A plan with a Newton group follows either continuation (smooth was once refused for it):
    the same change points, statuses and values as the closed form's — but at the sample on
    the change point itself, where the crank's end sits on the rocker's pivot: the closed form
    finds B undetermined, and Newton, whose Jacobian is singular there, does not converge."""
    q = np.radians(np.linspace(-30, 30, 61))
    closed = Mechanism(SQUARE).solve({"crank": q}, continuation=continuation)
    newton = Mechanism(SQUARE, method="newton").solve({"crank": q}, continuation=continuation)
    assert newton.change_points == closed.change_points
    assert [cp.continued for cp in newton.change_points] == [continuation]
    codes = closed.status.code.copy()
    codes[30] = Code.NO_CONVERGENCE  # crank 0°
    np.testing.assert_array_equal(newton.status.code, codes)
    ok = closed.status.ok
    np.testing.assert_allclose(newton.positions[ok], closed.positions[ok], rtol=0, atol=1e-14)
    np.testing.assert_allclose(newton.velocities[ok], closed.velocities[ok], rtol=0, atol=1e-13)
    np.testing.assert_allclose(newton.accelerations[ok], closed.accelerations[ok], atol=1e-12)
    off = coupler_offset(newton)[ok]
    assert np.nanmax(off) < 1e-12 if continuation == "smooth" else np.nanmax(off) > 0.19


@pytest.mark.parametrize("degrees", [np.linspace(90, 270, 181), np.linspace(270, 90, 180)])
def test_a_fold_that_passes_flat_is_a_bend(degrees) -> None:
    """At 180° the parallelogram lies flat along its long diagonal (A, B, O4 collinear, base
    200 mm): the side rule bends B's path back rather than jumping it. It is named, and the
    smooth continuation keeps the parallelogram through it."""
    mech = Mechanism(SQUARE)
    q = np.radians(degrees)
    side = mech.solve({"crank": q})
    (cp,) = side.change_points
    assert (cp.point, cp.partners, cp.shape, cp.continued) == ("B", ("A", "O4"), "bend", "side")
    crossing = int(np.argmin(np.abs(degrees - 180)))
    assert cp.before < crossing < cp.after or crossing in (cp.before, cp.after)
    assert "its path bends back" in cp.describe()
    ok = side.status.ok
    # positions stay continuous (no jump) but leave the parallelogram: a bend, not a jump
    step = np.hypot(*np.diff(side.point("B")[0][ok], axis=0).T)
    assert step.max() < 0.01
    assert np.nanmax(coupler_offset(side)[ok]) > 0.05
    smooth = mech.solve({"crank": q}, continuation="smooth")
    assert [(c.shape, c.continued) for c in smooth.change_points] == [("bend", "smooth")]
    assert np.nanmax(coupler_offset(smooth)[smooth.status.ok]) < 1e-12


def test_the_mo100_blow_is_a_bend() -> None:
    mech = excavkin.load(excavkin.example_path("mo100_hammer"))
    res = mech.solve({"crank": np.radians(np.linspace(-20, 20, 41))})
    (cp,) = res.change_points
    assert (cp.point, cp.shape, cp.before, cp.after) == ("C", "bend", 19, 21)
    # a turn that ends either side of the blow passes none
    turn = mech.solve({"crank": np.radians(np.linspace(0.5, 359.5, 359))})
    assert turn.change_points == ()


def test_no_bend_is_seen_on_random_crank_rockers() -> None:
    """200 random Grashof crank-rockers through a turn of 361 samples, at rates 1 and 7 rad/s:
    the dyad never folds, and no change point is reported."""
    from tests.models import fourbar_model

    rng = np.random.default_rng(12)
    seen = 0
    while seen < 200:
        r, b, c = rng.uniform(0.05, 1.0, 3)
        g = 1.0
        short, long_ = min(r, b, c, g), max(r, b, c, g)
        if short != r or short + long_ >= r + b + c + g - short - long_:
            continue  # not a crank-rocker
        ax, ay = 0.0, r
        ex, ey = g - ax, -ay
        l2 = ex * ex + ey * ey
        kk = (b * b - c * c + l2) / (2 * l2)
        h = np.sqrt(b * b / l2 - kk * kk)
        b_pos = (ax + kk * ex - h * ey, ay + kk * ey + h * ex)
        model = fourbar_model(
            {"O2": (0.0, 0.0), "A": (ax, ay), "B": b_pos, "O4": (g, 0.0)}, "crank-rocker"
        )
        res = Mechanism(model).solve(
            {"crank": np.linspace(0, 2 * np.pi, 361)}, rates={"crank": 1.0 + 6.0 * (seen % 2)}
        )
        assert res.status.all_ok
        assert res.change_points == (), seen
        seen += 1
