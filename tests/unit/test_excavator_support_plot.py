"""The support as the stability plots draw it (from the model's contact elements, no second
geometry) and the stability summary's line of least margin."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

from excavkin.excavator.machine import Machine
from excavkin.excavator.machine_file import load_machine
from excavkin.excavator.stability_plots import draw_support_side, plot_support
from excavkin.excavator.stability_survey import stability_survey
from tests.unit.test_excavator_base import MACHINE, TRACKS, _text

matplotlib.use("Agg")

#: an oscillating front axle, a rigid rear one, a blade ahead and two outrigger pads behind
WHEELED = (
    "[base.undercarriage.front_axle]\nposition = 1250\ntread = 2400\noscillating = true\n"
    "[base.undercarriage.rear_axle]\nposition = -1250\ntread = 2400\n"
)
EXTRA = (
    "\n[base.blade]\nposition = 2300\nwidth = 2500\n"
    "\n[base.outriggers]\npoints = [[-1800, 2000], [-1800, -2000]]\n"
)


def _wheeled(tmp_path: Path) -> Machine:
    path = tmp_path / "wheeled.toml"
    path.write_text(_text(EXTRA, **{TRACKS: WHEELED}), encoding="utf-8")
    return load_machine(path)


def _machines(tmp_path: Path) -> list[Machine]:
    return [load_machine(MACHINE), _wheeled(tmp_path)]


@pytest.mark.parametrize("swing", [0.0, 0.5, 0.5 * np.pi])
def test_the_plan_draws_the_models_support(tmp_path: Path, swing: float) -> None:
    import matplotlib.pyplot as plt

    for m in _machines(tmp_path):
        assert m.base is not None
        support = m.base.support
        h = plot_support(m, swing=swing)
        a = h.artists
        pts, _ = support.contact_points(m.swing_axis, swing)
        drawn = np.column_stack([a["points"].get_xdata(), a["points"].get_ydata()])
        np.testing.assert_allclose(drawn, pts, rtol=0, atol=1e-12)
        poly, _ = support.support_polygon(m.swing_axis, swing)
        np.testing.assert_allclose(a["polygon"].get_xy()[: len(poly)], poly, rtol=0, atol=1e-12)
        lines = support.tipping_lines(m.swing_axis, swing)
        assert list(a["lines"]) == [ln.name for ln in lines]
        assert [t.get_text() for t in a["lines"].values()] == [ln.name for ln in lines]
        assert list(a["contacts"]) == [c.name for c in support.contacts]
        plt.close(h.figure)


def test_each_contact_element_is_drawn_where_its_points_lie(tmp_path: Path) -> None:
    import matplotlib.pyplot as plt

    m = _wheeled(tmp_path)
    h = plot_support(m)
    c = h.artists["contacts"]
    assert set(c) == {"front axle pivot", "rear axle", "blade", "outriggers"}
    xy = {k: np.column_stack([v.get_xdata(), v.get_ydata()]) for k, v in c.items()}
    # the model's frame about the swing axis (at 0 here): as the machine file gives them
    np.testing.assert_allclose(xy["front axle pivot"], [[1.25, 0.0]], atol=1e-12)
    np.testing.assert_allclose(xy["rear axle"], [[-1.25, 1.2], [-1.25, -1.2]], atol=1e-12)
    np.testing.assert_allclose(xy["blade"], [[2.3, -1.25], [2.3, 1.25]], atol=1e-12)
    np.testing.assert_allclose(xy["outriggers"], [[-1.8, 2.0], [-1.8, -2.0]], atol=1e-12)
    assert c["front axle pivot"].get_marker() == "^" and c["rear axle"].get_marker() == "o"
    plt.close(h.figure)
    crawler = load_machine(MACHINE)
    h = plot_support(crawler)
    for name, v in (("left track", 1.19), ("right track", -1.19)):
        corners = h.artists["contacts"][name].get_xy()[:4]
        np.testing.assert_allclose(np.sort(np.unique(corners[:, 0])), [-1.825, 1.825], atol=1e-12)
        np.testing.assert_allclose(
            np.sort(np.unique(corners[:, 1])), [v - 0.3, v + 0.3], atol=1e-12
        )
    plt.close(h.figure)


def test_the_side_view_draws_the_contacts_abscissae(tmp_path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    crawler = load_machine(MACHINE)
    (box,) = draw_support_side(crawler, ax)  # two tracks side by side: one box
    assert (box.get_x(), box.get_width(), box.get_height()) == pytest.approx(
        (-1.825, 3.65, 0.9), abs=1e-12
    )
    fig2, ax2 = plt.subplots()
    drawn = draw_support_side(_wheeled(tmp_path), ax2)
    us = [sorted(set(np.asarray(a.get_xdata(), dtype=float).round(12))) for a in drawn]
    assert us == [[1.25], [-1.25], [2.3], [-1.8]]
    plt.close(fig)
    plt.close(fig2)


def test_the_summary_names_the_line_of_least_margin(tmp_path: Path) -> None:
    """Swung over the side, the centre of mass moves to the left: with the blade's and the
    pads' slanted edges it lies nearest the front-left edge; on tracks, the left side."""
    for m, expect in zip(
        _machines(tmp_path), ("left side", "front-left (blade) (outriggers)"), strict=True
    ):
        s = stability_survey(m, 2)
        text = s.summary().splitlines()
        for over, st in s.tipping.items():
            j = int(np.argmin(st.margin))
            # independently: the least distance of the unloaded centre of mass inside a line
            d = [ln.offset - np.dot(ln.normal, st.com[j, :2]) for ln in st.lines]
            k = int(np.argmin(d))
            assert d[k] == pytest.approx(st.margin[j], abs=1e-12)
            at = next(i for i, t in enumerate(text) if t.startswith(f"  over the {over}:"))
            assert text[at + 1] == f"    line of least margin: {st.lines[k].name}"
        side = next(i for i, t in enumerate(text) if t.startswith("  over the side:"))
        assert text[side + 1] == f"    line of least margin: {expect}"
