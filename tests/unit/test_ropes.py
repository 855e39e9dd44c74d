"""Ropes in the model and its file: a rope is the linear element of its name between its blocks
(driven by its winch motor's angle, or locked), and every bad entry is one message naming it."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from excavkin import Mechanism, Model, Rope
from excavkin.errors import ModelError
from excavkin.io.toml_model import loads_model
from excavkin.model.entities import Body, LinearDriver

BOOM = """
schema_version = 1
name = "boom on a hoist rope"
[units]
length = "m"
[points]
O = [0.0, 0.0]
A = [-1.0, 3.0]
B = [1.5, 2.0]
[bodies]
ground = { points = ["O", "A"], ground = true }
boom = { points = ["O", "B"] }
"""

WINCH = """
[ropes.hoist]
path = ["A", "B"]
parts = 2
mode = "winch"
drum_radius = "250 mm"
gear_ratio = 20
"""


def test_winch_rope_from_the_file() -> None:
    model = loads_model(BOOM + WINCH, "boom.toml")
    (rope,) = model.ropes
    assert rope == Rope("hoist", ("A", "B"), 2, "winch", 0.25, 20.0)
    assert rope.ratio == 0.25 / (20.0 * 2)
    # the rope is the model's linear element of its name, driven: its motor's angle the input
    assert model.linear == (LinearDriver("hoist", ("A", "B"), "driven"),)
    assert model.inputs == ("hoist",)
    plan = Mechanism(model).plan
    assert plan.input_kinds == ("angle",)
    # the sketch's motor angle puts the blocks at their sketch distance
    assert plan.input_sketch[0] * rope.ratio == pytest.approx(np.hypot(2.5, 1.0), rel=1e-15)


def test_locked_rope_holds_its_length() -> None:
    text = BOOM.replace("B = [1.5, 2.0]", "B = [1.5, 2.0]\nC = [2.0, 0.0]").replace(
        'boom = { points = ["O", "B"] }',
        'boom = { points = ["O", "B"] }\nlink = { points = ["B", "C"] }',
    )
    text += '[ropes.pendant]\npath = ["A", "B"]\n'
    text += '[drivers.crank]\ntype = "linear"\nbetween = ["O", "C"]\n'
    model = loads_model(text, "pendant.toml")
    assert model.ropes[0].mode == "locked" and model.ropes[0].parts == 1
    assert LinearDriver("pendant", ("A", "B"), "locked") in model.linear
    assert model.inputs == ("crank",)


def test_python_api_adds_the_element_once() -> None:
    model = loads_model(BOOM + WINCH)
    again = dataclasses.replace(model, name="again")
    assert again.linear == model.linear
    bare = Model(
        "boom",
        dict(model.points),
        (Body("ground", ("O", "A"), ground=True), Body("boom", ("O", "B"))),
        ropes=(Rope("hoist", ("A", "B"), 2, "winch", 0.25, 20.0),),
    )
    assert bare.linear == model.linear
    assert hash(bare) == hash(dataclasses.replace(bare))


@pytest.mark.parametrize(
    ("entry", "expect"),
    [
        ("parts = 0", "[ropes.hoist] 'parts': parts must be a whole number ≥ 1, not 0"),
        ("parts = 2.5", "parts must be a whole number ≥ 1, not 2.5"),
        ('mode = "free"', "mode must be 'winch' or 'locked', not 'free'"),
        ('mode = "winch"', "a winch needs its drum_radius"),
        ('drum_radius = "0.2 m"', "drum_radius belong to a winch; a locked rope has none"),
        ('path = ["A"]', "path must list the rope's two blocks (got 1 points)"),
        ('path = ["A", "O", "B"]', "radii must give one value per sheave (1: the inner points"),
        ('path = ["A", "O", "B"]\nradii = ["1 m"]', "wraps must give one value per sheave"),
        ('path = ["A", "O", "B"]\nradii = ["0 m"]\nwraps = ["cw"]', "sheave O: its radius must"),
        ('path = ["A", "O", "B"]\nradii = ["1 m"]\nwraps = ["up"]', "wrap must be 'ccw' or 'cw'"),
        ('path = ["A", "O", "O", "B"]', "point O follows itself in the path"),
        ('path = ["A", "O", "B"]\nradii = ["1 m"]\nwraps = ["cw"]\nparts = 2', "has one part"),
        ('radii = ["1 m"]', "radii and wraps belong to sheaves"),
        ('wraps = "cw"', 'wraps must list "ccw" or "cw"'),
        ('path = ["A", "Z"]', "Z"),
        ('path = ["A", "A"]', "its two blocks are the same point"),
        ('path = ["O", "A"]', "are both points of body 'ground'"),
        ("path = []", "path must list the point names of the rope's blocks"),
        ('colour = "red"', "unknown key colour"),
        ('mode = "winch"\ndrum_radius = "3 kg"', "[ropes.hoist] 'drum_radius'"),
        ('mode = "winch"\ndrum_radius = "-1 m"', "a winch needs a finite drum_radius > 0"),
        ('mode = "winch"\ndrum_radius = "1 m"\ngear_ratio = 0', "finite gear_ratio > 0"),
    ],
)
def test_bad_rope_entries_are_named(entry: str, expect: str) -> None:
    lines = ["[ropes.hoist]"]
    if not entry.startswith("path"):
        lines.append('path = ["A", "B"]')
    lines.append(entry)
    with pytest.raises(ModelError) as info:
        loads_model(BOOM + "\n".join(lines) + "\n", "boom.toml")
    message = str(info.value)
    assert expect in message
    assert "boom.toml" in message


def test_a_driver_of_the_rope_s_name_elsewhere_is_refused() -> None:
    text = BOOM + WINCH + '[drivers.hoist]\ntype = "linear"\nbetween = ["O", "B"]\n'
    with pytest.raises(ModelError, match="a driver is also called 'hoist'"):
        loads_model(text, "boom.toml")


def test_winch_solves_the_same_in_numpy_compiled_and_newton() -> None:
    model = loads_model(BOOM + WINCH)
    mech = Mechanism(model)
    ratio = model.ropes[0].ratio
    theta = mech.plan.input_sketch[0] + np.linspace(-60.0, 60.0, 7)
    runs = [
        mech.solve({"hoist": theta}, {"hoist": 3.0}, {"hoist": 0.5}, backend=c)
        for c in ("numpy", "numba")
    ]
    runs.append(
        Mechanism(model, method="newton").solve({"hoist": theta}, {"hoist": 3.0}, {"hoist": 0.5})
    )
    for r in runs:
        assert r.status.all_ok
        # the blocks' distance, its rate and its acceleration: ratio times the motor's
        np.testing.assert_allclose(r.element_length[:, 0], ratio * theta, rtol=1e-15)
        np.testing.assert_allclose(r.element_rate[:, 0], ratio * 3.0, rtol=1e-15)
        np.testing.assert_allclose(r.element_accel[:, 0], ratio * 0.5, rtol=1e-15)
        d = np.linalg.norm(r.positions[:, 2] - r.positions[:, 1], axis=1)
        np.testing.assert_allclose(d, ratio * theta, rtol=1e-14)
    for r in runs[1:]:
        np.testing.assert_allclose(r.positions, runs[0].positions, rtol=0, atol=1e-13)
        np.testing.assert_allclose(r.velocities, runs[0].velocities, rtol=0, atol=1e-13)
        np.testing.assert_allclose(r.accelerations, runs[0].accelerations, rtol=0, atol=1e-13)


def test_command_line_refuses_a_slack_rope_unless_keep_going(tmp_path: Path) -> None:
    """The boom's tip passes over its pivot at the motor angle sqrt(1.25)/ratio = 178.9 rad:
    beyond it the rope would have to push."""
    model = tmp_path / "boom.toml"
    model.write_text(
        BOOM
        + WINCH
        + '[loads.hook]\ntype = "force"\nbody = "boom"\npoint = "B"\nvalue = ["0 N", "-1 kN"]\n'
    )
    out = tmp_path / "boom.csv"
    sweep = ["--sweep", "hoist=150rad:250rad:11", "--forces", "-o", str(out)]
    r = subprocess.run(
        [sys.executable, "-m", "excavkin", "solve", str(model), *sweep],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 3, r.stderr
    assert "3 samples have a slack rope ('hoist'" in r.stderr and "samples 0, 1, 2" in r.stderr
    assert "Traceback" not in r.stderr and not out.exists()
    r = subprocess.run(
        [sys.executable, "-m", "excavkin", "solve", str(model), *sweep, "--keep-going"],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    frame = pd.read_csv(out)
    assert list(frame["status"] == "ok") == [False] * 3 + [True] * 8
    assert (frame["hoist.tension"][:3] < 0).all() and (frame["hoist.tension"][3:] > 0).all()
    np.testing.assert_allclose(frame["hoist.value"], np.linspace(150, 250, 11))


def test_a_rope_is_drawn_as_a_line() -> None:
    import matplotlib

    matplotlib.use("Agg")
    from excavkin.outputs.drawing import draw_mechanism

    mech = Mechanism(loads_model(BOOM + WINCH))
    res = mech.solve({"hoist": mech.plan.input_sketch[0] + np.linspace(-20.0, 20.0, 3)})
    barrel, rod = draw_mechanism(res).cylinders["hoist"]
    assert barrel is rod  # one line from block to block, no barrel and rod
    np.testing.assert_allclose(
        np.column_stack([barrel.get_xdata(), barrel.get_ydata()]),
        res.positions[0, [1, 2]] * 1000.0,
        atol=1e-9,
    )


def test_default_sweep_of_a_winch_spans_its_blocks_distance() -> None:
    from excavkin.default_sweep import default_sweep

    mech = Mechanism(loads_model(BOOM + WINCH))
    theta = default_sweep(mech)["hoist"]
    ratio = mech.model.ropes[0].ratio
    d0 = np.hypot(2.5, 1.0)
    # 0.8 to 1.25 times the sketch's distance (the boom reaches all of it)
    assert theta[0] * ratio == pytest.approx(0.8 * d0, rel=1e-12)
    assert theta[-1] * ratio == pytest.approx(1.25 * d0, rel=1e-12)
    assert mech.solve({"hoist": theta}).status.all_ok


def test_check_lists_the_rope() -> None:
    text = Mechanism(loads_model(BOOM + WINCH)).describe()
    assert "  rope    : hoist winch, 2 parts A–B, drum R 0.25 m, i = 20" in text.splitlines()


def test_simulate_drives_a_winch_by_its_motor() -> None:
    from excavkin.errors import InputError
    from excavkin.motion.drives import ConstantSpeedCrank, RopeWinch
    from excavkin.simulation.timeline import simulate

    mech = Mechanism(loads_model(BOOM + WINCH))
    frame = simulate(mech, {"hoist": ConstantSpeedCrank(-10.0)}, duration=2.0, samples=5).to_frame()
    np.testing.assert_allclose(frame["hoist.rate"], -10.0)
    # the blocks close at ω·R/(i·parts)
    np.testing.assert_allclose(frame["hoist.length_rate"], -10.0 * 0.25 / (20 * 2), rtol=1e-15)
    with pytest.raises(InputError, match="is a winch rope of the model"):
        simulate(mech, {"hoist": RopeWinch(10.0, 0.25, 20.0, 2.0)}, duration=1.0)


def test_a_study_counts_a_slack_rope_as_a_failed_pose() -> None:
    from excavkin.studies.metrics import Poses, solve_set

    text = BOOM + WINCH
    text += '[loads.hook]\ntype = "force"\nbody = "boom"\npoint = "B"\nvalue = ["0 N", "-1 kN"]\n'
    mech = Mechanism(loads_model(text))
    poses = Poses({"hoist": np.array([170.0, 190.0])}, {}, {})  # either side of 178.9 rad
    _, ok = solve_set(mech, {"B.x": np.array([1.5, 1.4])}, poses, 2, "model")
    assert ok.tolist() == [[False, True], [False, True]]


def test_a_winch_written_back_with_new_drum_and_gear(tmp_path: Path) -> None:
    from excavkin.io.model_write import model_text_with

    src = tmp_path / "boom.toml"
    src.write_text(BOOM + WINCH.replace("gear_ratio = 20\n", ""))
    text = model_text_with(src, {"hoist.drum_radius": 0.3125, "hoist.gear_ratio": 25.5})
    (rope,) = loads_model(text).ropes
    assert (rope.drum_radius, rope.gear_ratio) == (0.3125, 25.5)
    assert 'drum_radius = "312.5 mm"' in text
