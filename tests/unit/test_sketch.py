"""The SVG sketch of a mechanism: drawn from its scene, in the colours of outputs.style."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from numpy.testing import assert_allclose

import excavkin
from excavkin.outputs.scene import scene_of
from excavkin.outputs.sketch import scene_svg
from excavkin.outputs.style import BODY_COLORS, CYLINDER_COLOR, GROUND_COLOR, ROD_COLOR

EXAMPLES = Path(__file__).parents[2] / "examples"


def test_every_pin_point_body_and_cylinder_is_drawn_in_the_style_colours() -> None:
    mech = excavkin.load(EXAMPLES / "excavator.toml")
    svg = mech.sketch_svg(size=300)
    scene, _ = scene_of(mech, (), "m")
    assert svg.startswith("<svg") and "width='300'" in svg
    assert svg.count("r='3.5'") == len(scene.pins)
    assert svg.count("<text") == len(mech.plan.points)
    for body in scene.bodies:
        assert f"stroke='{body.color}'" in svg
    assert {b.color for b in scene.bodies} <= set(BODY_COLORS)
    cylinders = sum(e.style == "cylinder" for e in scene.elements)
    assert cylinders > 0
    assert svg.count(f"stroke='{CYLINDER_COLOR}' stroke-width='9'") == cylinders
    assert svg.count(f"stroke='{ROD_COLOR}'") == cylinders
    assert f"stroke='{GROUND_COLOR}'" in svg
    colours = set(re.findall(r"#[0-9a-fA-F]{6}", svg))
    assert colours <= {*BODY_COLORS, CYLINDER_COLOR, ROD_COLOR, GROUND_COLOR}


def test_pins_sit_at_the_assembled_positions_scaled_into_the_box() -> None:
    mech = excavkin.load(EXAMPLES / "fourbar.toml")
    scene, _ = scene_of(mech, (), "m")
    svg = scene_svg(scene, size=200, labels=False)
    assert "<text" not in svg
    drawn = np.array(re.findall(r"<circle cx='([-\d.]+)' cy='([-\d.]+)' r='3.5'", svg), float)
    xy = mech.assembly.positions[scene.pins]
    # the same affine map (uniform scale, y flipped) takes every pin to its drawn place
    k = int(np.argmax(np.abs(xy[:, 0] - xy[0, 0])))
    scale = (drawn[k, 0] - drawn[0, 0]) / (xy[k, 0] - xy[0, 0])
    assert scale > 0
    expected = np.column_stack(
        [drawn[0, 0] + scale * (xy[:, 0] - xy[0, 0]), drawn[0, 1] - scale * (xy[:, 1] - xy[0, 1])]
    )
    assert_allclose(drawn, expected, atol=0.1)
    assert ((drawn >= 0) & (drawn <= 200)).all()


def test_the_notebook_display_shows_the_sketch_and_the_plan() -> None:
    mech = excavkin.load(EXAMPLES / "slider_crank.toml")
    html = mech._repr_html_()
    assert html.count("<svg") == 1 and mech.sketch_svg() in html
    assert "<pre" in html and mech.plan.points[0] in html
    # the drawing does not shrink away beside the description's long lines
    assert f"<div style='flex:none'>{mech.sketch_svg()}</div>" in html
