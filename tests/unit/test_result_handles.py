"""The first hour's small things: a force result's summary (its statuses and extreme forces,
with units and where they occur) and a mechanism drawing's figure."""

from __future__ import annotations

import re

import matplotlib
import numpy as np
import pytest

import excavkin
from excavkin import Gravity
from excavkin.outputs.drawing import draw_mechanism

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def forces():  # type: ignore[no-untyped-def]
    mech = excavkin.load(excavkin.example_path("fourbar"))
    crank = np.radians(np.arange(0.0, 360.0, 10.0))
    return mech.solve({"crank": crank}, {"crank": 10.0}, loads="model")


def test_force_summary_is_text_like_the_kinematic_one(forces) -> None:  # type: ignore[no-untyped-def]
    text = forces.summary()
    assert isinstance(text, str) and isinstance(forces.kinematics.summary(), str)
    assert text.splitlines()[0] == forces.kinematics.summary() == "all samples solved"


def test_force_summary_gives_each_drivers_extreme_with_unit_and_sample(forces) -> None:  # type: ignore[no-untyped-def]
    frame = forces.to_frame()
    torque = frame["crank.torque"].to_numpy()
    i = int(np.argmax(np.abs(torque)))
    line = next(s for s in forces.summary().splitlines() if s.strip().startswith("crank.torque"))
    crank = np.degrees(frame["crank.value"][i])
    assert f"{torque[i]:.4g} N·m at sample {i} (crank = {crank:.0f}°)" in line


def test_force_summary_gives_the_largest_pin_forces(forces) -> None:  # type: ignore[no-untyped-def]
    frame = forces.to_frame()
    cols = [c[:-3] for c in frame.columns if c.endswith(".Fx") and c.count(".") == 2]
    peak = {c: np.hypot(frame[c + ".Fx"], frame[c + ".Fy"]).max() for c in cols}
    text = forces.summary(limit=3)
    listed = re.findall(r"^  (\S+) on (\S+)\s+\|F\| ([\d.]+) N at sample (\d+)", text, re.M)
    assert len(listed) == 3 and "(3 of 8 pins)" in text
    assert [float(v) for *_, v, _ in listed] == sorted((float(f"{v:.4g}") for v in peak.values()),
                                                       reverse=True)[:3]  # fmt: skip
    for p, b, v, i in listed:
        assert float(v) == float(f"{peak[f'{p}.{b}']:.4g}")
        assert np.hypot(frame[f"{p}.{b}.Fx"], frame[f"{p}.{b}.Fy"])[int(i)] == peak[f"{p}.{b}"]


def test_force_summary_lists_failing_samples_and_kilonewtons() -> None:
    mech = excavkin.load(excavkin.example_path("excavator"))
    res = mech.solve(
        {"boom_cyl": [2.768, 99.0], "arm_cyl": 2.972, "bucket_cyl": 2.2}, loads=[Gravity()]
    )
    text = res.summary()
    assert text.startswith("1 of 2 samples failed — ") and "sample 1 (" in text
    assert re.search(r"boom_cyl\.force\s+-?[\d.]+ kN at sample 0", text), text


def test_a_mechanism_drawing_has_its_figure() -> None:
    import matplotlib.pyplot as plt

    mech = excavkin.load(excavkin.example_path("fourbar"))
    drawing = draw_mechanism(mech.solve({"crank": [0.0, 1.0]}), sample=1)
    assert drawing.fig is drawing.ax.get_figure(root=True)
    fig, ax = plt.subplots()
    assert draw_mechanism(mech, ax=ax).fig is fig
    plt.close("all")
