"""What every family's plot functions share: the handle they return and the axes they draw on.

matplotlib is imported inside `figure_axes`, so that importing a wing's plots costs nothing
until it draws.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.arrays import FloatArray as F

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from excavkin.mechanism import Mechanism

__all__ = ["MachinePlot", "draw_pose", "figure_axes", "legend_box"]


@dataclass(frozen=True, slots=True)
class MachinePlot:
    """What a plot function drew.

    Attributes
    ----------
    figure : matplotlib.figure.Figure
    ax : matplotlib.axes.Axes
    artists : dict of str to object
    """

    figure: Figure
    ax: Axes
    artists: dict[str, Any]


def figure_axes(ax: Axes | None, size: tuple[float, float]) -> tuple[Figure, Axes]:
    """The figure and axes to draw on: ``ax`` and its figure, or a new figure of ``size``
    (inches) when ``ax`` is None.

    Parameters
    ----------
    ax : Axes or None
        The caller's axes.
    size : (float, float)
        Width and height of a new figure, in inches.

    Returns
    -------
    (Figure, Axes)
    """
    import matplotlib.pyplot as plt

    if ax is None:
        fig, ax = plt.subplots(figsize=size, layout="constrained")
        return fig, ax
    return ax.figure, ax  # type: ignore[return-value]


def draw_pose(
    mechanism: Mechanism,
    xy: F,
    ax: Axes,
    cylinders: Sequence[tuple[str, str]],
    colors: Sequence[str],
    *,
    cylinder_alpha: float | None = None,
    **style: Any,
) -> list[Any]:
    """Draw a machine's linkage at one pose as lines: each moving body as the outline of its
    points, each cylinder as a thick line between its end pins.

    Parameters
    ----------
    mechanism : Mechanism
        The machine's mechanism.
    xy : ndarray, shape (n_points, 2)
        Its points at the pose, in the plan's order.
    ax : matplotlib Axes
    cylinders : sequence of (str, str)
        Each cylinder's end pins (base, rod).
    colors : sequence of str
        Each cylinder's colour.
    cylinder_alpha : float, optional
        The cylinders' opacity (matplotlib's default when None).
    **style
        The bodies' line style, over a grey line.

    Returns
    -------
    list
        The lines drawn.
    """
    plan = mechanism.plan
    out: list[Any] = []
    kw: dict[str, Any] = {"color": "0.25", "lw": 1.6, "zorder": 3} | style
    for b in mechanism.model.bodies:
        if b.ground:
            continue
        idx = np.array([plan.points.index(p) for p in b.points])
        if len(idx) > 2:  # outline: the points in order of angle about their centroid
            c = xy[idx].mean(axis=0)
            idx = idx[np.argsort(np.arctan2(xy[idx, 1] - c[1], xy[idx, 0] - c[0]))]
            idx = np.r_[idx, idx[0]]
        out += ax.plot(xy[idx, 0], xy[idx, 1], **kw)
    line: dict[str, Any] = {"lw": 3.0, "zorder": 2, "solid_capstyle": "round"}
    if cylinder_alpha is not None:
        line["alpha"] = cylinder_alpha
    for (base, rod), color in zip(cylinders, colors, strict=True):
        i, j = plan.points.index(base), plan.points.index(rod)
        out += ax.plot(xy[[i, j], 0], xy[[i, j], 1], color=color, **line)
    return out


def legend_box(ax: Axes, text: str, *, fontsize: float, box: dict[str, Any], **style: Any) -> Any:
    """Write a figure's legend text in a box at the top left of the axes, in a monospaced
    font.

    Parameters
    ----------
    ax : matplotlib Axes
    text : str
        The lines, joined.
    fontsize : float
    box : dict
        The box's properties over a round white box (``ec``, ``alpha`` …).
    **style
        Further text properties (``ha`` …).

    Returns
    -------
    matplotlib.text.Text
    """
    return ax.text(
        0.01,
        0.99,
        text,
        transform=ax.transAxes,
        fontsize=fontsize,
        va="top",
        family="monospace",
        bbox={"boxstyle": "round", "fc": "white"} | box,
        **style,
    )
