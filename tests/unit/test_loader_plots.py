"""Every loader analysis result draws itself: ``plot()`` draws the result's own numbers, on the
axes given or a new figure, and refuses an unknown keyword."""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest
from numpy.testing import assert_allclose

from excavkin.loader.breakout import breakout
from excavkin.loader.capacity import capacity
from excavkin.loader.cycle import cycle
from excavkin.loader.dimensions import dimensions
from excavkin.loader.machine_file import load_machine
from excavkin.loader.parallel_lift import parallel_lift
from excavkin.loader.pins import pin_loads
from excavkin.loader.plots import LoaderPlot
from excavkin.loader.tipping import static_tipping
from tests.conftest import EXAMPLES

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402


@pytest.fixture(scope="module")
def loader():
    return load_machine(EXAMPLES / "wheel_loader_machine.toml")


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def test_dimensions_plot_draws_the_linkage_at_its_poses(loader) -> None:
    d = dimensions(loader)
    p = d.plot(loader)
    assert isinstance(p, LoaderPlot) and p.figure is p.ax.figure
    assert "SAE J732 / ISO 7131" in p.ax.get_title()
    # the dump pose's bucket edge: a line of the drawing passes through it
    f = next(f for f in d.figures if f.name == "dump clearance at 45 deg")
    res = loader.solve(f.lengths[None, :])
    edge = res.positions[0, loader.index(loader.linkage.edge)]
    pts = np.vstack([np.column_stack(ln.get_data()) for ln in p.artists[f.name]])
    assert np.min(np.hypot(*(pts - edge).T)) < 1e-9
    assert_allclose(edge[1] - loader.ground_line, f.value, rtol=1e-12)
    texts = " ".join(t.get_text() for t in p.ax.texts)
    assert f"dump clearance {f.value * 1e3:.0f} mm" in texts


def test_breakout_plot_bars_are_the_limits(loader) -> None:
    bo = breakout(loader)
    _, ax = plt.subplots()
    p = bo.plot(ax=ax)
    assert p.ax is ax
    for r in (bo.tilt, bo.lift):
        for limit in ("working", "hydraulic", "tipping"):
            (bar,) = p.artists["bars"][r.circuit, limit]
            assert_allclose(bar.get_width(), getattr(r, limit) / 1e3, rtol=1e-12)
    texts = " ".join(t.get_text() for t in ax.texts)
    assert f"limited by {bo.lift.limiting}" in texts


def test_tipping_plot_bars_and_rated_capacity(loader) -> None:
    tl = static_tipping(loader)
    p = tl.plot()
    heights = [b.get_height() for b in p.artists["bars"]]
    assert_allclose(heights, [tl.straight.load / 1e3, tl.full_turn.load / 1e3], rtol=1e-12)
    assert_allclose(p.artists["roc"].get_ydata()[0], tl.rated_operating_capacity / 1e3)
    assert_allclose(tl.rated_operating_capacity, 0.5 * tl.full_turn.load, rtol=1e-12)


def test_capacity_plot_curves_are_the_capacities(loader) -> None:
    cap = capacity(loader, 21)
    p = cap.plot()
    for name, values in (("lift", cap.lift), ("rollback", cap.rollback), ("tipping", cap.tipping)):
        x, y = p.artists[name].get_data()
        assert_allclose(x, cap.hinge_height * 1e3, rtol=1e-12)
        assert_allclose(y, values / 1e3, rtol=1e-12)
    assert "ISO 14397-2" in p.ax.get_title()


def test_parallel_lift_plot_curve_is_the_angle(loader) -> None:
    pl = parallel_lift(loader, 21)
    p = pl.plot()
    x, y = p.artists["angle"].get_data()
    assert_allclose(x, pl.hinge_height * 1e3, rtol=1e-12)
    assert_allclose(y, np.degrees(pl.angle), rtol=1e-12)
    assert f"{math.degrees(pl.change):+.1f}°" in p.ax.get_title()


def test_cycle_plot_bars_are_the_times(loader) -> None:
    cy = cycle(loader)
    p = cy.plot()
    assert_allclose([b.get_width() for b in p.artists["bars"]], [ph.time for ph in cy.phases])
    assert f"total {cy.total:.2f} s" in p.ax.get_title()


def test_pins_plot_bars_are_the_largest_loads(loader) -> None:
    pl = pin_loads(loader, 5)
    p = pl.plot()
    for c in pl.cases:
        widths = [b.get_width() for b in p.artists["bars"][c.name]]
        ref = [np.nanmax(np.where(c.ok, c.load[:, j], np.nan)) / 1e3 for j in range(len(c.pins))]
        assert_allclose(widths, ref, rtol=1e-12)


def test_plot_refuses_an_unknown_keyword(loader) -> None:
    with pytest.raises(TypeError):
        breakout(loader).plot(colour="red")  # type: ignore[call-arg]
