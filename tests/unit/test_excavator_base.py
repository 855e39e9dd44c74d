"""The machine file's base machine: reading in SI, errors naming file, table and entry, the
support polygon and its tipping lines."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from excavkin.cli import main
from excavkin.errors import ModelError, UnitError
from excavkin.excavator.base import convex_hull
from excavkin.excavator.machine_file import loads_machine
from tests.conftest import EXAMPLES

MACHINE = EXAMPLES / "excavator_machine.toml"


def _text(extra: str = "", **replace: str) -> str:
    text = MACHINE.read_text(encoding="utf-8").replace(
        'model = "excavator.toml"', f'model = "{(EXAMPLES / "excavator.toml").as_posix()}"'
    )
    for old, new in replace.items():
        assert old in text, old
        text = text.replace(old, new, 1)
    return text + extra


def _drop(text: str, prefix: str) -> str:
    """The text without the tables whose header starts with ``[prefix``."""
    out, skip = [], False
    for line in text.splitlines(keepends=True):
        if line.startswith("["):
            skip = line.startswith(f"[{prefix}")
        if not skip:
            out.append(line)
    return "".join(out)


def test_example_base_reads_in_si() -> None:
    m = loads_machine(_text(), "m.toml")
    b = m.base
    assert b is not None
    assert (b.upper.mass, b.counterweight.mass, b.undercarriage.mass) == (5900, 3800, 7200)
    assert (b.counterweight.x, b.counterweight.y) == pytest.approx((-2.35, 1.65), abs=1e-15)
    assert (b.track_length, b.gauge, b.shoe_width) == pytest.approx((3.65, 2.38, 0.6), abs=1e-15)
    assert b.friction == 0.5 and b.blade is None and b.outriggers == ()
    assert [c.mass for c in m.cylinders] == [330, 215, 150]
    assert m.front_mass == pytest.approx(3455 + 695, abs=1e-9)
    assert m.lift_point == m.pins.bucket_pin == "Q"
    lines = {ln.name: ln.offset for ln in b.tipping_lines(m.swing_axis)}
    assert lines == pytest.approx(
        {"front": 1.825, "rear": 1.825, "left side": 1.49, "right side": 1.49}, abs=1e-15
    )


def test_without_base_the_machine_still_reads() -> None:
    text = _drop(_text(), "base")
    m = loads_machine(text, "m.toml")
    assert m.base is None and "[base" not in text


@pytest.mark.parametrize(
    ("old", "new", "pattern"),
    [
        ("mass = 5900", "mass = -1", r"\[base\.upper\] 'mass'.*more than 0"),
        ("mass = 5900", 'mass = "5900 mm"', r"\[base\.upper\] 'mass'"),
        ("mass = 3800", "mass = -5", r"\[base\.counterweight\] 'mass'.*at least 0"),
        (
            "gauge = 2380",
            "gauge = 500",
            r"\[base\.undercarriage\] 'shoe_width'.*wider than the gauge",
        ),
        ("track_length = 3650", "track_length = 0", r"\[base\.undercarriage\] 'track_length'"),
        ("track_length = 3650", "track_lenght = 3650", r"unknown key track_lenght.*did you mean"),
        ("friction = 0.5", "friction = 0", r"\[base\] 'friction'.*more than 0"),
        ("friction = 0.5", 'friction = "0.5 m"', r"\[base\] 'friction'"),
        (
            "center_of_mass = [-350, 1600]",
            "center_of_mass = [1]",
            r"\[base\.upper\] 'center_of_mass'",
        ),
        ("center_of_mass = [0, 500]", "center_of_mass = [0, 5e9]", r"'center_of_mass'.*at most"),
        ("mass = 330 ", "mass = -330 ", r"\[cylinders\.boom\] 'mass'.*at least 0"),
        ("[base.counterweight]", "[base.counterweigth]", r"\[base\]: unknown key counterweigth"),
    ],
)
def test_base_errors_name_table_and_entry(old: str, new: str, pattern: str) -> None:
    with pytest.raises(ModelError, match=pattern) as info:
        loads_machine(_text(**{old: new}), "m.toml")
    assert str(info.value).startswith("m.toml")


def test_missing_part_and_units() -> None:
    text = _drop(_text(), "base.counterweight")
    with pytest.raises(ModelError, match=r"m.toml \[base\].*\[base\.counterweight\] is missing"):
        loads_machine(text, "m.toml")
    with pytest.raises(UnitError, match=r"\[cylinders\.boom\] 'mass'.*330 needs a unit"):
        loads_machine(_text(**{'mass = "kg"\n': ""}), "m.toml")
    tonnes = loads_machine(_text(**{"mass = 5900": 'mass = "5.9 t"'}), "m.toml")
    assert tonnes.base is not None and tonnes.base.upper.mass == pytest.approx(5900.0)


@pytest.mark.parametrize(
    ("extra", "pattern"),
    [
        ('\n[lift]\npoint = "A"\n', r"\[lift\] 'point'.*not a point of the stick"),
        ("\n[lift]\nhook = 1\n", r"\[lift\].*unknown key hook"),
        ("\n[base.blade]\nposition = 2600\n", r"\[base\.blade\].*'width' is missing"),
        ("\n[base.blade]\nposition = 4e6\nwidth = 1\n", r"\[base\.blade\] 'position'.*at most"),
        ("\n[base.outriggers]\npoints = []\n", r"\[base\.outriggers\] 'points'"),
        ("\n[base.outriggers]\npoints = [[1, 2, 3]]\n", r"\[base\.outriggers\] 'points'"),
    ],
)
def test_lift_blade_outrigger_errors(extra: str, pattern: str) -> None:
    with pytest.raises(ModelError, match=pattern):
        loads_machine(_text(extra), "m.toml")


def test_a_lowered_blade_moves_the_front_tipping_line() -> None:
    m = loads_machine(_text("\n[base.blade]\nposition = 2600\nwidth = 2500\n"), "m.toml")
    assert m.base is not None
    lines = {ln.name: ln for ln in m.base.tipping_lines(m.swing_axis)}
    front = lines["front (blade)"]
    assert front.offset == pytest.approx(2.6, abs=1e-15)
    np.testing.assert_allclose(sorted(front.ends[:, 1]), [-1.25, 1.25], atol=1e-15)
    # the blade (2.5 m) is narrower than the tracks (2.98 m): slanted lines join them
    assert {"front-left", "front-right"} <= {n.split(" (")[0] for n in lines}
    assert lines["rear"].offset == pytest.approx(1.825, abs=1e-15)


def test_outriggers_widen_the_support() -> None:
    pads = "\n[base.outriggers]\npoints = [[-1825, 2200], [-1825, -2200]]\n"
    m = loads_machine(_text(pads), "m.toml")
    assert m.base is not None
    names = {ln.name: ln for ln in m.base.tipping_lines(m.swing_axis)}
    assert names["rear (outriggers)"].offset == pytest.approx(1.825, abs=1e-15)
    assert names["rear (outriggers)"].ends[:, 1] == pytest.approx([2.2, -2.2], abs=1e-15)
    # from the pads to the tracks' front corners
    assert {"front", "front-left (outriggers)", "front-right (outriggers)"} <= set(names)


def test_convex_hull_drops_inner_and_collinear_points() -> None:
    pts = np.array([[0, 0], [2, 0], [1, 0], [2, 2], [0, 2], [1, 1], [1, 2]], dtype=float)
    hull = convex_hull(pts)
    assert sorted(hull) == [0, 1, 3, 4]
    ring = pts[hull]
    area = 0.5 * np.sum(ring[:, 0] * np.roll(ring[:, 1], -1) - np.roll(ring[:, 0], -1) * ring[:, 1])
    assert area == pytest.approx(4.0)  # counter-clockwise
    with pytest.raises(ModelError, match="no area"):
        convex_hull(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]))


def test_lift_hook_point() -> None:
    m = loads_machine(_text('\n[lift]\npoint = "L"\n'), "m.toml")
    assert m.lift_point == "L"


# ------------------------------------------------------------------ the command line
def test_cli_lift(tmp_path: Path) -> None:
    out, png = tmp_path / "lift.csv", tmp_path / "lift.png"
    args = ["excavator", "lift", str(MACHINE), "-o", str(out), "--plot", str(png)]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    assert "ISO 10567" in r.output and "radius 6.0 m" in r.output and "*" in r.output
    assert png.is_file()
    table = pd.read_csv(out)
    assert set(table["over"]) == {"front", "side"} and set(table["limit"]) == {
        "hydraulic",
        "tipping",
    }
    # each row's rating is the lesser of its two parts
    np.testing.assert_allclose(
        table["rated_load"],
        np.minimum(0.75 * table["tipping_load"], 0.87 * table["hydraulic_load"]),
        rtol=1e-12,
    )
    again = CliRunner().invoke(main, args)
    assert again.exit_code == 2 and "--force" in again.output and "ISO 10567" not in again.output
    r = CliRunner().invoke(main, ["excavator", "lift", str(MACHINE), "--step", "0m"])
    assert r.exit_code == 2 and "--step" in r.output


def test_cli_stability(tmp_path: Path) -> None:
    out = tmp_path / "s.csv"
    args = ["excavator", "stability", str(MACHINE), "--samples", "5", "-o", str(out)]
    r = CliRunner().invoke(main, [*args, "--map", str(tmp_path / "m"), "--swing", "side"])
    assert r.exit_code == 0, r.output
    assert "tipping lines" in r.output and "front 1825" in r.output and "least tipping" in r.output
    for name in ("tipping-front", "tipping-side", "limits-arm", "limits-bucket", "support"):
        assert (tmp_path / f"m-{name}.png").is_file()
    table = pd.read_csv(out)
    assert list(table["cylinder"]) == ["arm", "bucket"] * 2
    lesser = np.minimum(
        np.minimum(table["hydraulic_force"], table["tipping_force"]), table["slipping_force"]
    )
    np.testing.assert_allclose(table["force"], lesser, rtol=1e-9)


def test_cli_without_base_is_one_clear_error(tmp_path: Path) -> None:
    bare = tmp_path / "bare.toml"
    bare.write_text(_drop(_text(), "base"), encoding="utf-8")
    for cmd in (["stability", str(bare), "--samples", "3"], ["lift", str(bare)]):
        r = CliRunner().invoke(main, ["excavator", *cmd])
        assert r.exit_code == 2, r.output
        assert r.output.startswith(f"excavkin: error: {bare} [base]: the machine has no base")
        assert len(r.output.strip().splitlines()) == 1


# ------------------------------------------------------------------ a wheeled undercarriage
TRACKS = (
    "track_length = 3650               # idler to sprocket axes: the front tipping line lies on "
    "the idler axis\ngauge = 2380                      # track centre to track centre\n"
    "shoe_width = 600                  # the side tipping line is the outer edge of the shoes\n"
)
AXLES = (
    "[base.undercarriage.front_axle]\nposition = 1250\ntread = 2400\noscillating = true\n"
    "[base.undercarriage.rear_axle]\nposition = -1250\ntread = 2400\n"
)


def test_a_wheeled_undercarriage_stands_on_its_axles() -> None:
    """An oscillating front axle (its pin at x = 1.25 m) and a rigid rear one (tyres at
    ±1.2 m): the triangle of the pin and the rear tyres, its lines named by direction."""
    m = loads_machine(_text(**{TRACKS: AXLES}), "m.toml")
    b = m.base
    assert b is not None and (b.track_length, b.gauge, b.shoe_width) == (0.0, 0.0, 0.0)
    assert [(a.name, a.kind, a.x) for a in b.axles] == [
        ("front axle pivot", "pivot", 1.25),
        ("rear axle", "tyres", -1.25),
    ]
    poly, kinds = b.support_polygon(m.swing_axis)
    np.testing.assert_allclose(poly, [(-1.25, -1.2), (1.25, 0.0), (-1.25, 1.2)], atol=1e-15)
    assert kinds == ["tyres", "pivot", "tyres"]
    lines = {ln.name: ln for ln in b.tipping_lines(m.swing_axis)}
    assert set(lines) == {"front-right", "front-left", "rear"}
    # the pin (1.25, 0) to the rear-left tyre (−1.25, 1.2): normal (1.2, 2.5)/√(1.2² + 2.5²)
    r = np.hypot(1.2, 2.5)
    np.testing.assert_allclose(lines["front-left"].normal, (1.2 / r, 2.5 / r), atol=1e-15)
    assert lines["front-left"].offset == pytest.approx(1.25 * 1.2 / r, abs=1e-15)


@pytest.mark.parametrize(
    ("old", "new", "pattern"),
    [
        (TRACKS, AXLES.split("[base.undercarriage.rear_axle]")[0], r"rear_axle\] is missing"),
        (TRACKS, AXLES.replace("oscillating = true", 'oscillating = "yes"'), r"'oscillating'"),
        (TRACKS, AXLES.replace("tread = 2400\nosc", "tread = 0\nosc"), r"front_axle\] 'tread'"),
        (TRACKS, AXLES.replace("position = -1250", "position = 1300"), r"ahead of the rear"),
        (
            TRACKS,
            AXLES.replace("tread = 2400\n[", "tread = 2400\noscillating = true\n[").replace(
                "-1250\ntread = 2400\n", "-1250\ntread = 2400\noscillating = true\n"
            ),
            r"m\.toml \[base\].*no area",
        ),
    ],
)
def test_wheeled_errors_name_table_and_entry(old: str, new: str, pattern: str) -> None:
    with pytest.raises(ModelError, match=pattern) as info:
        loads_machine(_text(**{old: new}), "m.toml")
    assert str(info.value).startswith("m.toml")


def test_tracks_and_axles_together_are_refused() -> None:
    with pytest.raises(ModelError, match=r"\[base\.undercarriage\] 'gauge'.*not both"):
        loads_machine(_text("\n" + AXLES), "m.toml")
