"""Parallel lift: the bucket's angle over the lift with the tilt cylinder held, against the
angle read directly from the solved hinge-pin and cutting-edge points, the held tilt length
against the ground pose's definition, and the two built-in linkages' behaviour (the Z-bar rolls
its bucket back over the lift, the parallel-lift linkage keeps it nearly level)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

from excavkin.cli import main
from excavkin.errors import ModelError
from excavkin.loader.machine import Loader
from excavkin.loader.machine_file import load_machine
from excavkin.loader.parallel_lift import parallel_lift
from tests.conftest import EXAMPLES


@pytest.fixture(scope="module", params=["wheel_loader_machine", "wheel_loader_tp_machine"])
def machine(request) -> Loader:
    return load_machine(EXAMPLES / f"{request.param}.toml")


def _direct_angles(m: Loader, lift: np.ndarray, tilt: float) -> tuple[np.ndarray, np.ndarray]:
    """The floor's angle at each pose, read from the hinge pin and the cutting edge: the edge
    lies at a fixed angle from the floor in the bucket, which the ground pose (floor level)
    fixes; also the hinge pin's height."""
    res = m.solve(np.column_stack([lift, np.full_like(lift, tilt)]))
    assert res.status.ok.all()
    b = res.positions[:, m.index(m.pins.hinge)]
    e = res.positions[:, m.index(m.linkage.edge)]
    h = res.positions[:, m.index(m.linkage.heel)]
    hinge_to_edge = np.arctan2(e[:, 1] - b[:, 1], e[:, 0] - b[:, 0])
    # the floor (heel → edge) against the hinge → edge line, a constant of the rigid bucket,
    # taken from the sketch's points of the model
    pts = m.mechanism.model.points
    sb, se, sh = (
        np.array(pts[k], dtype=float) for k in (m.pins.hinge, m.linkage.edge, m.linkage.heel)
    )
    offset = math.atan2(*(se - sh)[::-1]) - math.atan2(*(se - sb)[::-1])
    floor = np.angle(np.exp(1j * (hinge_to_edge + offset)))
    # and the floor read straight from heel and edge: the two reads agree
    assert_allclose(floor, np.arctan2(e[:, 1] - h[:, 1], e[:, 0] - h[:, 0]), rtol=0, atol=1e-12)
    return floor, b[:, 1] - m.ground_line


def test_the_angle_read_directly_from_the_solved_points(machine) -> None:
    p = parallel_lift(machine, 41)
    assert p.lift[-1] == machine.full_lift()
    # the held tilt levels the floor with the cutting edge on the ground
    floor0, _ = _direct_angles(machine, p.lift[:1], p.tilt)
    assert abs(floor0[0]) < 1e-12
    e0 = machine.solve(np.array([[p.lift[0], p.tilt]])).positions[0, machine.index("W")]
    assert abs(e0[1] - machine.ground_line) < 1e-9
    floor, height = _direct_angles(machine, p.lift, p.tilt)
    assert_allclose(p.angle, floor, rtol=0, atol=1e-12)
    assert_allclose(p.hinge_height, height, rtol=0, atol=1e-12)
    assert p.change == pytest.approx(floor[-1] - floor[0], abs=1e-12)
    k = int(np.argmax(np.abs(floor - floor[0])))
    assert p.deviation == pytest.approx(floor[k] - floor[0], abs=1e-12)
    assert abs(p.deviation) >= abs(p.change)


def test_the_z_bar_rolls_back_and_the_parallel_lift_keeps_level() -> None:
    z = parallel_lift(load_machine(EXAMPLES / "wheel_loader_machine.toml"))
    tp = parallel_lift(load_machine(EXAMPLES / "wheel_loader_tp_machine.toml"))
    # the Z-bar's design brief (docs/loader.md): 26.4° rolled back at worst, from its sketch
    assert z.tilt == pytest.approx(1.6122953, abs=1e-6)
    assert math.degrees(z.deviation) == pytest.approx(26.4, abs=0.1)
    assert 20.0 < math.degrees(z.change) < 30.0
    assert abs(math.degrees(tp.deviation)) < 3.0
    assert abs(math.degrees(tp.change)) < 3.0


def test_table_summary_and_command(tmp_path) -> None:
    p = parallel_lift(load_machine(EXAMPLES / "wheel_loader_tp_machine.toml"), 5)
    frame = p.to_frame()
    assert list(frame.columns) == ["lift_cyl", "tilt_cyl", "hinge_height", "angle"]
    assert frame.attrs["excavkin.units"] == {
        "lift_cyl": "m",
        "tilt_cyl": "m",
        "hinge_height": "m",
        "angle": "rad",
    }
    assert_allclose(frame["angle"], p.angle)
    assert "largest deviation" in p.summary()
    out = tmp_path / "lift.csv"
    r = CliRunner().invoke(main, ["loader", "lift", "wheel_loader_machine", "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert "change, ground to full lift" in r.output and out.exists()
    r = CliRunner().invoke(main, ["loader", "lift", "wheel_loader_machine", "-o", str(out)])
    assert r.exit_code == 2 and "Traceback" not in r.output
    with pytest.raises(ValueError, match="samples"):
        parallel_lift(load_machine(EXAMPLES / "wheel_loader_machine.toml"), 1)


def test_a_lift_that_does_not_assemble_with_the_tilt_held_is_named(tmp_path) -> None:
    """The bucket's tilt pin moved so that the held tilt cylinder cannot follow the arm to the
    top: one message naming the file and the lift length, exit status 2 from the command."""
    model = (EXAMPLES / "wheel_loader_tp.toml").read_text(encoding="utf-8")
    old = "I = [2050.0, 1280.0]"
    assert old in model and "stroke = [2710, 3300]" in model
    model = model.replace(old, "I = [2750.0, 900.0]").replace("[2710, 3300]", "[1500, 4500]")
    (tmp_path / "wheel_loader_tp.toml").write_text(model, encoding="utf-8")
    text = (EXAMPLES / "wheel_loader_tp_machine.toml").read_text(encoding="utf-8")
    for old, new in (
        ("retracted = 2710 ", "retracted = 1500 "),
        ("stroke = 590 ", "stroke = 3000"),
    ):
        assert old in text
        text = text.replace(old, new, 1)
    path = tmp_path / "m.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ModelError, match="does not assemble at lift length") as err:
        parallel_lift(load_machine(path), 11)
    assert str(path) in str(err.value)
    r = CliRunner().invoke(main, ["loader", "lift", str(path)])
    assert r.exit_code == 2 and "does not assemble" in r.output and "Traceback" not in r.output
