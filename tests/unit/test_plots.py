"""Plots, mechanism drawings and animations, checked through the artists they return.

Each test reads the drawn geometry back from the handle (line data, patch vertices, labels) and
compares it with the result's numbers, so a plot that looks right is one that *is* right.
"""

from __future__ import annotations

import subprocess
import sys

import matplotlib
import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin.outputs.animation import animate
from excavkin.outputs.plots import (
    draw_mechanism,
    main_columns,
    plot_columns,
    plot_curves,
    trace_paths,
)
from excavkin.outputs.report import default_sweep
from tests.models import ARM, double_rocker  # noqa: E402

matplotlib.use("Agg")


SLIDER_CRANK = """
schema_version = 1
name = "slider-crank"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
A = [30, 40]
B = [150, 0]
G1 = [-60, 0]
G2 = [250, 0]
[bodies]
ground = { points = ["O", "G1", "G2"], ground = true }
crank = { points = ["O", "A"] }
rod = { points = ["A", "B"] }
[drivers.crank]
type = "rotary"
body = "crank"
pivot = "O"
reference = "ground"
[sliders.piston]
point = "B"
along = ["G1", "G2"]
"""


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


@pytest.fixture(scope="module")
def fourbar():
    mech = excavkin.load(excavkin.example_path("fourbar"))
    return mech, mech.solve({"crank": np.radians(np.arange(0.0, 361.0, 10.0))})


def test_importing_outputs_does_not_import_matplotlib_or_plotly():
    code = (
        "import sys, excavkin, excavkin.outputs.plots, excavkin.outputs.drawing, "
        "excavkin.outputs.animation, excavkin.outputs.report, excavkin.cli.commands.report; "
        "bad = [m for m in ('matplotlib', 'plotly') if m in sys.modules]; "
        "assert not bad, bad"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


# ------------------------------------------------------------------------------ plot_columns
def test_plot_columns_draws_the_column_in_display_units(fourbar):
    _, res = fourbar
    h = plot_columns(res, y=["B.x", "B.y"])
    x, y = h.lines["B.x"].get_data()
    assert_allclose(x, np.arange(0.0, 361.0, 10.0), atol=1e-9)  # the input, in degrees
    assert_allclose(y, res.point("B")[0][:, 0] * 1000.0, rtol=1e-12)  # metres → mm
    assert_allclose(h.lines["B.y"].get_ydata(), res.point("B")[0][:, 1] * 1000.0, rtol=1e-12)
    assert h.ax.get_xlabel() == "crank [°]"
    assert h.ax.get_ylabel() == "Length [mm]"
    assert [t.get_text() for t in h.ax.get_legend().get_texts()] == ["B.x", "B.y"]


def test_plot_columns_units_by_kind_and_by_column(fourbar):
    _, res = fourbar
    h = plot_columns(res, y="rocker.angle", units={"angle": "rad"})
    assert h.ax.get_xlabel() == "crank [rad]"
    assert h.ax.get_ylabel() == "rocker.angle [rad]"
    assert_allclose(h.lines["rocker.angle"].get_ydata(), res.body("rocker")[0])
    h = plot_columns(res, y="B.vx", units={"B.vx": "mm/s"})
    assert h.ax.get_ylabel() == "B.vx [mm/s]"
    assert_allclose(h.lines["B.vx"].get_ydata(), res.point("B")[1][:, 0] * 1000.0)


def test_plot_columns_against_time_and_against_another_column(fourbar):
    mech, _ = fourbar
    t = np.linspace(0.0, 0.2, 21)
    res = mech.solve({"crank": 31.416 * t}, {"crank": np.full(21, 31.416)}, time=t)
    h = plot_columns(res, y="rocker.omega")
    assert h.ax.get_xlabel() == "Time [s]"
    assert_allclose(h.lines["rocker.omega"].get_xdata(), t)
    h = plot_columns(res, y="B.y", x="B.x")
    assert h.ax.get_xlabel() == "B.x [mm]"
    assert_allclose(h.lines["B.y"].get_xdata(), res.point("B")[0][:, 0] * 1000.0)


def test_plot_columns_takes_force_columns_from_a_dataframe(fourbar):
    _, res = fourbar
    frame = res.to_frame()
    frame["B.rocker.Fx"] = np.linspace(-2000.0, 3000.0, len(frame))
    frame["B.rocker.Fy"] = 500.0
    frame["crank.torque"] = np.linspace(0.0, 250.0, len(frame))
    h = plot_columns(
        frame, y=["B.rocker.Fx", "B.rocker.Fy"], x="crank.value", units={"crank.value": "deg"}
    )
    assert h.ax.get_ylabel() == "Force [kN]"
    assert h.ax.get_xlabel() == "crank [°]"
    assert_allclose(h.lines["B.rocker.Fx"].get_ydata(), np.linspace(-2.0, 3.0, len(frame)))
    h = plot_columns(frame, y="crank.torque", x="crank.value", units={"torque": "N*m"})
    assert h.ax.get_ylabel() == "crank.torque [N·m]"
    assert_allclose(h.lines["crank.torque"].get_ydata(), frame["crank.torque"])


def test_plot_columns_style_is_passed_and_unknown_keywords_raise(fourbar):
    _, res = fourbar
    h = plot_columns(res, y="B.x", color="red", lw=3, ls="--")
    line = h.lines["B.x"]
    assert (line.get_color(), line.get_linewidth(), line.get_linestyle()) == ("red", 3, "--")
    with pytest.raises(TypeError, match="colour"):
        plot_columns(res, y="B.x", colour="red")
    with pytest.raises(TypeError, match="xdata"):
        plot_columns(res, y="B.x", xdata=[1, 2])
    with pytest.raises(TypeError):
        draw_mechanism(res, bogus=1)
    with pytest.raises(TypeError, match="bogus"):
        trace_paths(res, ["B"], bogus=1)
    with pytest.raises(TypeError):
        plot_curves(res, ["B.x"], bogus=1)
    with pytest.raises(TypeError):
        animate(res, bogus=1)


def test_plot_columns_refuses_mixed_kinds_and_unknown_columns(fourbar):
    _, res = fourbar
    with pytest.raises(ValueError, match="different kinds"):
        plot_columns(res, y=["B.x", "rocker.angle"])
    with pytest.raises(KeyError, match="B.z"):
        plot_columns(res, y="B.z")
    with pytest.raises(excavkin.UnitError):
        plot_columns(res, y="B.x", units={"length": "deg"})


def test_plot_columns_marks_non_closure_and_dead_positions():
    mech = double_rocker()
    res = mech.solve({"crank": np.radians(np.linspace(0.0, 360.0, 73))})
    bad = ~res.status.ok
    h = plot_columns(res, y="rocker.angle")
    runs = np.flatnonzero(np.diff(np.concatenate([[0], bad.astype(int), [0]])) == 1).size
    assert len(h.failures) == runs == 3  # 0°–10°, the middle, 350°–360°
    span = h.failures[0]  # covers the first failed samples, 0°–10°, half a step either side
    assert_allclose([span.get_x(), span.get_x() + span.get_width()], [-2.5, 12.5])
    labels = [t.get_text() for t in h.ax.get_legend().get_texts()]
    assert "does not close" in labels
    assert np.isnan(h.lines["rocker.angle"].get_ydata()[bad]).all()


def test_dead_position_is_marked_where_the_transmission_angle_vanishes():
    mech = double_rocker()
    sweep = default_sweep(mech, n=41)  # from one dead position to the other
    res = mech.solve(sweep)
    assert res.status.all_ok
    h = plot_columns(res, y="rocker.angle")
    from excavkin.outputs.events import dead_samples

    dead = dead_samples(res, np.radians(5.0))
    assert set(dead.tolist()) <= {0, len(res) - 1} and dead.size >= 1
    del h


def test_plot_curves_one_panel_per_kind(fourbar):
    _, res = fourbar
    cols = main_columns(res)
    assert "crank.angle" not in cols and "crank.value" not in cols  # the input itself
    assert {"rocker.angle", "B.transmission", "rocker.omega", "rocker.epsilon"} <= set(cols)
    c = plot_curves(res, ["rocker.angle", "B.transmission", "rocker.omega", "rocker.epsilon"])
    assert [a.get_ylabel() for a in c.axes] == [
        "Angle [°]",
        "rocker.omega [rad/s]",
        "rocker.epsilon [rad/s²]",
    ]
    assert c.axes[-1].get_xlabel() == "crank [°]" and c.axes[0].get_xlabel() == ""


def test_angles_are_unwrapped_for_display():
    mech = excavkin.loads(SLIDER_CRANK)
    res = mech.solve({"crank": np.radians(np.arange(0.0, 721.0, 10.0))})
    h = plot_columns(res, y="crank.angle")
    y = h.lines["crank.angle"].get_ydata()
    assert_allclose(np.diff(y), 10.0, atol=1e-9)  # no jump at ±180°


# ----------------------------------------------------------------------------- draw_mechanism
def test_draw_mechanism_puts_pins_at_the_solved_points(fourbar):
    _, res = fourbar
    d = draw_mechanism(res, sample=4)
    names = res.plan.points
    x, y = d.pins.get_data()
    assert_allclose(np.c_[x, y], res.positions[4] * 1000.0)  # every point is a joint here
    # each binary body is a line between its points
    for body in ("crank", "coupler", "rocker"):
        pts = excavkin.load(excavkin.example_path("fourbar")).model.body(body).points
        idx = [names.index(p) for p in pts]
        assert_allclose(np.c_[d.bodies[body].get_data()], res.positions[4, idx] * 1000.0)
    assert d.ax.get_xlabel() == "x [mm]" and d.ax.get_ylabel() == "y [mm]"
    assert {t.get_text() for t in d.labels.values()} == set(names)
    # ground hatching under both ground pivots
    tri, hatch = d.ground
    ty = np.asarray(tri.get_ydata(), dtype=float)
    assert np.nanmin(ty) < 0.0 and np.count_nonzero(np.isnan(ty)) == 2
    # set_sample moves the pins
    d.set_sample(9)
    assert_allclose(np.c_[d.pins.get_data()], res.positions[9] * 1000.0)
    with pytest.raises(IndexError):
        d.set_sample(len(res))


def test_draw_mechanism_of_a_mechanism_is_its_sketch_and_ghosts_are_faint(fourbar):
    mech, res = fourbar
    d = draw_mechanism(mech, length_unit="m")
    assert_allclose(np.c_[d.pins.get_data()], mech.assembly.positions)
    assert d.ax.get_xlabel() == "x [m]"
    d = draw_mechanism(res, sample=[0, 5, 10], labels=False)
    assert len(d.ghosts) == 2 and not d.labels
    assert d.ghosts[0].pins.get_alpha() < d.pins.get_alpha() == 1.0


def test_cylinders_are_drawn_as_barrel_and_rod():
    mech = excavkin.loads(ARM)
    res = mech.solve(
        {"boom_cyl": np.linspace(1.1, 1.6, 11), "stick_cyl": np.linspace(0.55, 0.8, 11)}
    )
    assert res.status.all_ok
    d = draw_mechanism(res, sample=0)
    assert set(d.cylinders) == {"boom_cyl", "stick_cyl"}
    barrel_lengths = []
    for i in (0, 10):
        d.set_sample(i)
        barrel, rod = d.cylinders["boom_cyl"]
        c1, d1 = res.point("C1")[0][i] * 1000, res.point("D1")[0][i] * 1000
        b = np.c_[barrel.get_data()]
        r = np.c_[rod.get_data()]
        assert_allclose(b[0], c1, atol=1e-9)  # the barrel starts at the first point
        assert_allclose(r[0], d1, atol=1e-9)  # the rod's eye is at the second
        u = (d1 - c1) / np.linalg.norm(d1 - c1)
        for seg in (b, r):  # both lie on the line C1–D1
            w = seg[1] - c1
            assert abs(u[0] * w[1] - u[1] * w[0]) < 1e-6
        # the rod reaches into the barrel: they overlap along the line
        assert np.dot(r[1] - c1, u) < np.dot(b[1] - c1, u)
        assert barrel.get_linewidth() > rod.get_linewidth()
        barrel_lengths.append(np.linalg.norm(b[1] - b[0]))
    assert_allclose(barrel_lengths[0], barrel_lengths[1])  # a barrel does not stretch
    # the boom (four points) is a filled polygon through its outline
    assert "boom" in d.fills and len(d.fills["boom"].get_xy()) >= 4


def test_ropes_are_lines_and_sliders_have_a_block_on_a_hatched_guide():
    mech = excavkin.loads(ARM)
    res = mech.solve({"boom_cyl": np.linspace(1.1, 1.6, 5)})
    d = draw_mechanism(res, ropes=["stick_cyl"])
    a, b = d.cylinders["stick_cyl"]
    assert a is b
    with pytest.raises(ValueError, match="nothing"):
        draw_mechanism(res, ropes=["nothing"])
    sc = excavkin.loads(SLIDER_CRANK)
    res = sc.solve({"crank": np.radians([30.0, 120.0])})
    d = draw_mechanism(res, sample=1)
    block, guide = d.sliders["piston"]
    centre = np.asarray(block.get_xy())[:4].mean(axis=0)
    assert_allclose(centre, res.point("B")[0][1] * 1000.0, atol=1e-9)
    assert_allclose(guide.get_ydata(), 0.0, atol=1e-12)
    hatch_y = np.asarray(d.ground[1].get_ydata(), dtype=float)
    assert np.nanmax(hatch_y) < 0.0  # hatching lies under the guide and the pivot


def test_trace_paths_follow_the_points_and_mark_the_limits():
    mech = double_rocker()
    res = mech.solve({"crank": np.radians(np.linspace(0.0, 360.0, 73))})
    t = trace_paths(res, ["B"], color="k")
    assert_allclose(t.lines["B"].get_ydata(), res.point("B")[0][:, 1] * 1000.0)
    assert t.lines["B"].get_color() == "k"
    assert t.failures is not None  # the last positions before the runs that do not close
    ok = res.status.ok
    edges = [i for i in range(1, len(res) - 1) if ok[i] and (not ok[i - 1] or not ok[i + 1])]
    assert_allclose(np.sort(t.failures.get_xdata()), np.sort(res.point("B")[0][edges, 0] * 1000.0))
    with pytest.raises(KeyError, match="nowhere"):
        trace_paths(res, ["nowhere"])


# ---------------------------------------------------------------------------------- animation
def test_animation_moves_the_mechanism_and_shows_values(tmp_path, fourbar):
    _, res = fourbar
    a = animate(res, samples=[0, 9, 18], show=["crank.value", "rocker.angle"], trace=["B"])
    assert "crank = 0°" in a.text.get_text()
    a.animation._func(2)  # the frame update, as the writer calls it
    assert_allclose(np.c_[a.drawing.pins.get_data()], res.positions[18] * 1000.0)
    assert "crank = 180°" in a.text.get_text()
    assert f"rocker.angle = {np.degrees(res.body('rocker')[0][18]):.4g}°" in a.text.get_text()
    out = a.save(tmp_path / "fourbar.gif", fps=5, dpi=40)
    from PIL import Image

    with Image.open(out) as im:
        assert im.n_frames == 3
    from excavkin.outputs.tables import OutputError

    with pytest.raises(OutputError, match="exists"):
        a.save(out)
    import shutil

    if shutil.which("ffmpeg") is None:
        with pytest.raises(OutputError, match="ffmpeg"):
            a.save(tmp_path / "fourbar.mp4")
    else:
        assert a.save(tmp_path / "fourbar.mp4", fps=5, dpi=40).stat().st_size > 0


def test_animation_defaults_thin_long_results_and_show_the_input(fourbar):
    mech, _ = fourbar
    res = mech.solve({"crank": np.linspace(0.0, 2 * np.pi, 1001)})
    a = animate(res)
    assert a.samples.size == 180 and a.samples[0] == 0 and a.samples[-1] == 1000
    assert a.text.get_text().startswith("crank = ")
    a.animation._draw_was_started = True  # not rendered on purpose: no warning about it


def test_a_dataframe_without_a_plan_still_plots():
    frame = pd.DataFrame(
        {"t": [0.0, 0.1, 0.2], "cyl.force": [1000.0, 2000.0, 1500.0], "status": ["ok", "ok", "ok"]}
    )
    h = plot_columns(frame, y="cyl.force")
    assert h.ax.get_xlabel() == "Time [s]"
    assert_allclose(h.lines["cyl.force"].get_ydata(), [1.0, 2.0, 1.5])
