"""The pitch circles of a mechanism's gear pairs and pinions, for its drawings.

Each gear pair's two pitch circles touch at the pitch point ``O1 + λ·(O2 − O1)``
(`excavkin.model.entities.GearPair.pitch_fraction`): their radii are ``|λ|·d`` and
``|1 − λ|·d`` with d the pivots' distance in the drawing's first solved sample; a rack's pinion
is drawn at its pitch radius. The circles turn with nothing but their centres, which move.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.model.gears import gear_pivots, pivot_on
from excavkin.outputs.display_units import convert

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from excavkin.outputs.scene import Scene

__all__ = ["add_pitch_circles", "circle_paths", "move_pitch_circles", "pitch_circles"]


def pitch_circles(scene: Scene) -> list[tuple[int, float]]:
    """(centre point index, radius in the scene's length unit) of every pitch circle.

    Parameters
    ----------
    scene : Scene
        The drawing's geometry.

    Returns
    -------
    list of (int, float)
        Two per gear pair, one per rack's pinion.
    """
    model = scene.plan.model
    index = {p: i for i, p in enumerate(scene.plan.points)}
    ok = np.flatnonzero(np.isfinite(scene.xy).all(axis=(1, 2)))
    xy = scene.xy[ok[0]] if ok.size else None
    out: list[tuple[int, float]] = []
    for g in model.gears:
        p1, p2 = (index[p] for p in gear_pivots(model, g))
        if xy is None:
            continue
        d = float(np.hypot(*(xy[p2] - xy[p1])))
        lam = g.pitch_fraction
        out += [(p1, abs(lam) * d), (p2, abs(1.0 - lam) * d)]
    for rk in model.racks:
        pivot = pivot_on(model, rk.pinion, rk.carrier, f"racks.{rk.name}", "pinion")
        out.append((index[pivot], float(convert(rk.radius, "length", scene.length_unit))))
    return out


def add_pitch_circles(
    ax: Axes, scene: Scene, sample: int, zorder: float, alpha: float
) -> list[tuple[int, Any]]:
    """Draw the pitch circles at ``sample`` (dash-dotted, unfilled).

    Parameters
    ----------
    ax : Axes
        Where.
    scene : Scene
        The drawing's geometry.
    sample : int
        The sample drawn.
    zorder, alpha : float
        As the drawing's.

    Returns
    -------
    list of (int, Circle)
        Each circle with its centre's point index (for `move_pitch_circles`).
    """
    from matplotlib.patches import Circle

    out = []
    for centre, radius in pitch_circles(scene):
        circle = Circle(
            tuple(scene.xy[sample, centre]),
            radius,
            fill=False,
            ls="-.",
            lw=0.9,
            ec="0.35",
            zorder=zorder + 0.4,
            alpha=alpha,
        )
        ax.add_patch(circle)
        out.append((centre, circle))
    return out


def move_pitch_circles(circles: list[tuple[int, Any]], scene: Scene, sample: int) -> list[Any]:
    """Move the pitch circles to ``sample``.

    Parameters
    ----------
    circles : list of (int, Circle)
        From `add_pitch_circles`.
    scene : Scene
        The drawing's geometry.
    sample : int
        The sample shown.

    Returns
    -------
    list of Circle
        The circles moved.
    """
    for centre, circle in circles:
        circle.center = tuple(scene.xy[sample, centre])
        circle.set_visible(bool(np.isfinite(scene.xy[sample, centre]).all()))
    return [c for _, c in circles]


def circle_paths(scene: Scene, sample: int, n: int = 73) -> list[np.ndarray]:
    """Each pitch circle at ``sample`` as a closed polyline (for the HTML report's figure).

    Parameters
    ----------
    scene : Scene
        The drawing's geometry.
    sample : int
        The sample shown.
    n : int
        Points on each circle (the last repeats the first).

    Returns
    -------
    list of ndarray, shape (n, 2)
        One path per circle of `pitch_circles`, in its order.
    """
    t = np.linspace(0.0, 2.0 * np.pi, n)
    ring = np.stack([np.cos(t), np.sin(t)], axis=1)
    return [scene.xy[sample, c] + r * ring for c, r in pitch_circles(scene)]
