"""A mechanism as a small SVG drawing: the notebook display of [`Mechanism`][excavkin.Mechanism].

The third renderer of a `Scene`, beside matplotlib
(`drawing`) and plotly (`report`): it writes the
scene's primitives of one sample — ground symbols, slider guides and blocks, bodies, cylinders
as barrel and rod, pins and point names — as SVG text, in the colours of
`style`. It needs neither matplotlib nor plotly, so a notebook shows a
mechanism without a plotting library.

``Mechanism._repr_html_`` and ``Mechanism.sketch_svg`` import this module when they are called
(the one import from the core up into ``outputs``, named in the layer contract), as the results'
displays delegate to the outputs they draw with.
"""

from __future__ import annotations

import html

import numpy as np

from excavkin.outputs.protocols import MechanismLike
from excavkin.outputs.scene import Scene, scene_of
from excavkin.outputs.style import CYLINDER_COLOR, GROUND_COLOR, ROD_COLOR, SLIDER_FILL

__all__ = ["mechanism_html", "scene_svg", "sketch_svg"]


def scene_svg(scene: Scene, sample: int = 0, *, size: int = 240, labels: bool = True) -> str:
    """One sample of a scene as an SVG drawing of ``size`` × ``size`` pixels.

    Parameters
    ----------
    scene : Scene
        The geometry to draw.
    sample : int
        Which sample of the scene.
    size : int
        Width and height of the drawing, pixels; the scene is scaled to fit, its aspect kept.
    labels : bool
        Whether to write each point's name beside it.

    Returns
    -------
    str
        An ``<svg>`` element.
    """
    xy = scene.xy[sample]
    tri, hatch = scene.ground_symbols() if scene.ground_pivots or scene.sliders else (None, None)
    extents = [xy] + [a for a in (tri, hatch) if a is not None and a.size]
    every = np.vstack(extents)
    every = every[np.isfinite(every).all(axis=1)]
    lo, hi = (every.min(axis=0), every.max(axis=0)) if every.size else (np.zeros(2), np.ones(2))
    span = float(max(hi[0] - lo[0], hi[1] - lo[1], 1e-12))
    pad = 0.08 * span
    scale = size / (span + 2 * pad)

    def at(p: np.ndarray) -> tuple[float, float]:
        return (p[0] - lo[0] + pad) * scale, size - (p[1] - lo[1] + pad) * scale

    def points(path: np.ndarray) -> str:
        return " ".join("{:.1f},{:.1f}".format(*at(p)) for p in path)

    def polylines(path: np.ndarray, style: str) -> list[str]:
        """A NaN-separated path as one polyline per piece."""
        out = []
        breaks = np.flatnonzero(~np.isfinite(path).all(axis=1))
        for piece in np.split(path, breaks):
            piece = piece[np.isfinite(piece).all(axis=1)]
            if len(piece) >= 2:
                out.append(f"<polyline points='{points(piece)}' fill='none' {style}/>")
        return out

    parts: list[str] = []
    if tri is not None and hatch is not None:
        parts += polylines(tri, f"stroke='{GROUND_COLOR}' stroke-width='1.3'")
        parts += polylines(hatch, f"stroke='{GROUND_COLOR}' stroke-width='1'")
    for sl in scene.sliders:
        parts += polylines(
            scene.slider_guide(sl, sample),
            f"stroke='{GROUND_COLOR}' stroke-width='1.2' stroke-dasharray='4 3'",
        )
    for body in scene.bodies:
        path = scene.body_path(body, sample)
        if body.closed:
            parts.append(
                f"<polygon points='{points(path[:-1])}' fill='{body.color}' fill-opacity='0.35' "
                f"stroke='{body.color}' stroke-width='2.5'/>"
            )
        else:
            parts += polylines(
                path,
                f"stroke='{body.color}' stroke-width='5' stroke-linecap='round'",
            )
    for el in scene.elements:
        barrel, rod = scene.element_segments(el, sample)
        if el.style == "line":
            parts += polylines(barrel, f"stroke='{CYLINDER_COLOR}' stroke-width='1.5'")
            continue
        parts += polylines(rod, f"stroke='{ROD_COLOR}' stroke-width='3.5'")
        parts += polylines(barrel, f"stroke='{CYLINDER_COLOR}' stroke-width='9'")
    for rope in scene.rope_paths:
        parts += polylines(
            scene.rope_line(rope, sample), f"stroke='{CYLINDER_COLOR}' stroke-width='1.5'"
        )
    for sl in scene.sliders:
        block = scene.slider_block(sl, sample)
        if np.isfinite(block).all():
            parts.append(
                f"<polygon points='{points(block)}' fill='{SLIDER_FILL}' "
                f"stroke='{GROUND_COLOR}' stroke-width='1.3'/>"
            )
    for i in scene.pins:
        if np.isfinite(xy[i]).all():
            x, y = at(xy[i])
            parts.append(
                f"<circle cx='{x:.1f}' cy='{y:.1f}' r='3.5' fill='white' stroke='black' "
                "stroke-width='1.5'/>"
            )
    for i in scene.dots:
        if np.isfinite(xy[i]).all():
            x, y = at(xy[i])
            parts.append(f"<circle cx='{x:.1f}' cy='{y:.1f}' r='2' fill='black'/>")
    if labels:
        for i, name in enumerate(scene.plan.points):
            if np.isfinite(xy[i]).all():
                x, y = at(xy[i])
                parts.append(
                    f"<text x='{x + 5:.1f}' y='{y - 5:.1f}' font-size='11'>"
                    f"{html.escape(name)}</text>"
                )
    return (
        f"<svg xmlns='http://www.w3.org/2000/svg' width='{size}' height='{size}' "
        f"viewBox='0 0 {size} {size}'>{''.join(parts)}</svg>"
    )


def sketch_svg(mechanism: MechanismLike, size: int = 240) -> str:
    """The mechanism assembled at its sketch, as an SVG drawing.

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism to draw.
    size : int
        Width and height of the drawing, pixels.

    Returns
    -------
    str
        An ``<svg>`` element.
    """
    scene, _ = scene_of(mechanism, (), "m")
    return scene_svg(scene, 0, size=size)


def mechanism_html(mechanism: MechanismLike) -> str:
    """The mechanism's notebook display: its sketch beside its description and solve plan.

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism to show.

    Returns
    -------
    str
        An HTML fragment.
    """
    # the drawing keeps its size (a flex item shrinks to nothing beside long lines); the text
    # scrolls instead
    return (
        "<div style='display:flex;gap:1em;align-items:flex-start'>"
        f"<div style='flex:none'>{sketch_svg(mechanism)}</div>"
        "<pre style='margin:0;min-width:0;overflow-x:auto'>"
        f"{html.escape(mechanism.describe())}</pre></div>"
    )
