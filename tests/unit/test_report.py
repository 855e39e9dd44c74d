"""The HTML report, its default sweep, the warnings it lists, ``excavkin report`` and progress."""

from __future__ import annotations

import base64
import io
import re

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

import excavkin
from excavkin.cli import main
from excavkin.cli.progress import enabled, progress, solve_with_progress
from excavkin.outputs.events import find_events
from excavkin.outputs.report import (
    MAX_FRAMES,
    build_report,
    curves_figure,
    default_sweep,
    mechanism_figure,
    write_report,
)
from excavkin.outputs.tables import OutputError
from tests.models import ARM, double_rocker


@pytest.fixture(scope="module")
def fourbar():
    return excavkin.load(excavkin.example_path("fourbar"))


# ------------------------------------------------------------------------------ default sweep
def test_default_sweep_turns_a_crank_fully(fourbar):
    sweep = default_sweep(fourbar)
    assert list(sweep) == ["crank"]
    assert_allclose(sweep["crank"][[0, -1]], [0.0, 2 * np.pi])
    assert sweep["crank"].size == 181
    assert fourbar.solve(sweep).status.all_ok


def test_default_sweep_of_a_rocker_spans_the_range_that_closes():
    mech = double_rocker()
    sweep = default_sweep(mech, n=61)
    res = mech.solve(sweep)
    assert res.status.all_ok
    q0 = mech.sketch_values()["crank"]
    assert sweep["crank"][0] < q0 < sweep["crank"][-1]
    # its ends are near the dead positions: the transmission angle is nearly 0 or 180°
    mu = np.degrees(res.transmission[[0, -1], 0])
    assert np.all(np.minimum(mu, 180.0 - mu) < 10.0)
    # just beyond them the mechanism does not close
    step = 2 * np.pi / 720
    beyond = mech.solve({"crank": [sweep["crank"][0] - step, sweep["crank"][-1] + step]})
    assert not beyond.status.ok.any()


def test_default_sweep_of_cylinders_is_a_stroke_around_the_sketch():
    mech = excavkin.loads(ARM)
    sweep = default_sweep(mech)
    sketch = mech.sketch_values()
    for name in ("boom_cyl", "stick_cyl"):
        assert sweep[name].size == 121
        assert_allclose(sweep[name][[0, -1]], np.array([0.8, 1.25]) * sketch[name], rtol=1e-12)
    assert mech.solve(sweep).status.all_ok


# --------------------------------------------------------------------------------- the report
def test_report_is_self_contained_and_has_every_part(fourbar):
    res = fourbar.solve(default_sweep(fourbar))
    text = build_report(fourbar, res, command="excavkin report fourbar")
    assert text.startswith("<!DOCTYPE html>")
    # nothing is fetched at view time: no external scripts, styles, images or fonts
    assert not re.search(r"<(script|link|img|iframe)[^>]+(src|href)=\"?(https?:)?//", text)
    assert "<script src" not in text and "@import" not in text
    assert "Plotly.newPlot" in text and len(text) > 3_000_000  # plotly.js is embedded
    for part in (
        'id="mechanism"',
        'id="curves"',
        'id="warnings-section"',
        'id="download-table"',
        "Solve plan",
        "rotate   A about O2",
        "crank-rocker four-bar",
        "Extremes",
    ):
        assert part in text
    # the table download is the result's table
    csv = re.search(r'href="data:text/csv;base64,([^"]+)"', text).group(1)
    table = pd.read_csv(io.StringIO(base64.b64decode(csv).decode()))
    assert len(table) == 181
    assert_allclose(table["B.x"], res.to_frame()["B.x"], rtol=1e-9)
    assert "low transmission" in text  # the four-bar's transmission angle drops to 29°


def test_mechanism_figure_has_a_frame_per_sample_and_a_slider(fourbar):
    res = fourbar.solve({"crank": np.radians(np.arange(0.0, 360.0, 15.0))})
    fig = mechanism_figure(res)
    assert len(fig.frames) == len(res) == len(fig.layout.sliders[0].steps)
    assert [b.label for b in fig.layout.updatemenus[0].buttons] == ["▶ Play", "❚❚ Pause"]
    pins = next(k for k, t in enumerate(fig.data) if t.name == "pins")
    for i in (0, 7):
        frame = fig.frames[i]
        idx = list(frame.traces).index(pins)
        xy = np.c_[frame.data[idx].x, frame.data[idx].y]
        assert_allclose(xy, res.positions[i] * 1000.0, atol=1e-5)
        assert frame.name == str(i)
    assert fig.layout.sliders[0].steps[2].label == "crank = 30°"
    assert "crank = 15°" in fig.frames[1].layout.annotations[0].text
    long = fourbar.solve({"crank": np.linspace(0.0, 2 * np.pi, 1000)})
    assert len(mechanism_figure(long).frames) == MAX_FRAMES


def test_report_lists_non_closure_and_dead_positions(tmp_path):
    mech = double_rocker()
    res = mech.solve({"crank": np.radians(np.linspace(0.0, 360.0, 73))})
    events = find_events(res)
    kinds = [e.kind for e in events]
    assert kinds.count("does not close") == 3 and kinds[0] == "does not close"
    assert events[0].severity == "error"
    path = write_report(mech, res, tmp_path / "dr.html")
    text = path.read_text()
    assert "does not close" in text and "cannot close at dyad B" in text
    cfig = curves_figure(res)
    assert len(cfig.layout.shapes) >= 3  # shaded spans where it does not close
    with pytest.raises(OutputError, match="exists"):
        write_report(mech, res, path)
    write_report(mech, res, path, force=True)
    assert not list(tmp_path.glob(".*.tmp*"))  # the temporary file was moved into place
    with pytest.raises(OutputError, match="html"):
        write_report(mech, res, tmp_path / "dr.txt")


def test_no_shock_is_guessed_from_differences_of_samples():
    n = 101
    t = np.linspace(0.0, 1.0, n)
    # a piecewise-constant acceleration: a difference-based guess would call sample 50 a shock
    accel = np.where(t < 0.5, 2.0, -2.0)
    frame = pd.DataFrame(
        {"t": t, "P.ax": accel, "P.vx": np.cumsum(accel) / n, "status": ["ok"] * n}
    )
    assert find_events(frame) == []


def test_a_smooth_sweep_of_the_excavator_reports_no_warning():
    mech = excavkin.load(excavkin.example_path("excavator"))
    events = find_events(mech.solve(default_sweep(mech)))
    assert [e for e in events if e.severity != "note"] == []


def test_exact_shocks_of_a_run_in_time_are_listed(tmp_path):
    from excavkin.motion import get_law
    from excavkin.simulation.shocks import shock_report
    from excavkin.simulation.timeline import Drive, simulate

    mech = excavkin.load(excavkin.example_path("pasika_module"))
    drives = {"cyl": Drive(get_law("cubic", 0.5, 5.0))}
    result = simulate(mech, drives, t=np.linspace(0.0, 5.0, 101))
    report = shock_report(mech, drives, result)
    events = find_events(result, shocks=report.shocks)
    shocks = [e for e in events if e.kind == "shock"]
    assert shocks and all("soft shock" in e.message for e in shocks)
    assert {e.message.rsplit("t = ", 1)[1] for e in shocks} == {"0 s", "5 s"}
    path = tmp_path / "pasika.html"
    write_report(mech, result, path, shocks=report.shocks)
    assert "soft shock" in path.read_text()


def test_a_mechanism_without_moving_inputs_still_reports(fourbar, tmp_path):
    res = fourbar.solve()  # one sample at the sketch
    write_report(fourbar, res, tmp_path / "one.html")
    assert "1 samples" in (tmp_path / "one.html").read_text()


# ------------------------------------------------------------------------------------ the CLI
def test_cli_report_writes_refuses_to_overwrite_and_takes_sweeps(tmp_path):
    runner = CliRunner()
    out = tmp_path / "r.html"
    r = runner.invoke(main, ["report", str(excavkin.example_path("fourbar")), "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert out.is_file() and "wrote" in r.output and "181 samples" in r.output
    r = runner.invoke(main, ["report", "fourbar", "-o", str(out)])
    assert r.exit_code == 2 and "--force" in r.output
    r = runner.invoke(
        main,
        [
            "report",
            "fourbar",
            "-o",
            str(out),
            "--force",
            "--quiet",
            "--sweep",
            "crank=0deg:90deg:10",
            "--title",
            "Quarter turn",
        ],
    )
    assert r.exit_code == 0 and r.output == ""
    text = out.read_text()
    assert "Quarter turn" in text and "10 samples" in text


def test_cli_report_sets_holds_and_rejects_unknown_inputs(tmp_path):
    model = tmp_path / "arm.toml"
    model.write_text(ARM)
    runner = CliRunner()
    out = tmp_path / "arm.html"
    r = runner.invoke(
        main,
        [
            "report",
            str(model),
            "-o",
            str(out),
            "--sweep",
            "boom_cyl=1.1m:1.6m:20",
            "--set",
            "stick_cyl=600mm",
            "--rope",
            "stick_cyl",
        ],
    )
    assert r.exit_code == 0, r.output
    assert "stick_cyl held at 600 mm" in out.read_text()
    r = runner.invoke(
        main, ["report", str(model), "-o", str(tmp_path / "x.html"), "--sweep", "arm_cyl=1m:2m:3"]
    )
    assert r.exit_code == 2 and "unknown driver 'arm_cyl'" in r.output
    assert not (tmp_path / "x.html").exists()
    r = runner.invoke(
        main, ["report", str(model), "-o", str(tmp_path / "x.html"), "--sweep", "boom_cyl=1m:2m"]
    )
    assert r.exit_code == 2 and "START:STOP:N" in r.output


# ------------------------------------------------------------------------------- progress
def test_progress_is_silent_off_a_terminal_and_chunked_solves_agree(fourbar):
    buf = io.StringIO()
    assert not enabled(stream=buf)
    with progress("x", 10, stream=buf) as advance:
        advance(5)
    assert buf.getvalue() == ""

    class Tty(io.StringIO):
        def isatty(self) -> bool:
            return True

    assert enabled(stream=Tty()) and not enabled(quiet=True, stream=Tty())
    q = np.linspace(0.0, 4 * np.pi, 5000)
    q[1234] = np.nan  # a failed sample keeps its place
    tty = Tty()
    chunked = solve_with_progress(fourbar, {"crank": q}, chunk=700, stream=tty)
    whole = fourbar.solve({"crank": q})
    assert_allclose(chunked.positions, whole.positions, equal_nan=True)
    assert_allclose(chunked.body_epsilon, whole.body_epsilon, equal_nan=True)
    assert (chunked.status.code == whole.status.code).all() and not chunked.status.ok[1234]
    assert len(chunked) == 5000 and "solving" in tty.getvalue()


def test_cli_report_refuses_a_sweep_where_nothing_solves(tmp_path):
    out = tmp_path / "none.html"
    r = CliRunner().invoke(
        main, ["report", "excavator", "-q", "-o", str(out), "--sweep", "boom_cyl=5m:6m:20"]
    )
    assert r.exit_code == 3
    assert "20 of 20 samples failed" in r.output and "nothing was written" in r.output
    assert "Traceback" not in r.output and "RuntimeWarning" not in r.output
    assert not out.exists()


def test_the_excavator_view_names_every_moving_input_and_keeps_its_values_box_aside():
    mech = excavkin.load(excavkin.example_path("excavator"))
    res = mech.solve(default_sweep(mech, n=9))
    fig = mechanism_figure(res)
    label = fig.layout.sliders[0].steps[3].label
    assert all(f"{c} = " in label for c in ("boom_cyl", "arm_cyl", "bucket_cyl")), label
    note = fig.layout.annotations[0]
    # the box is placed in paper coordinates right of the plotting area, never over the axes
    assert note.xref == "paper" and note.x > 1.0 and note.xanchor == "left"
