"""The plots of a study's results: an optimisation's convergence, an optimum's variables in
their box, and a study's metric against a design variable (one point per design).

Each takes ``ax=`` and returns the axes or a handle with the figure; matplotlib is imported
only when a plot is made.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.collections import PathCollection
    from matplotlib.figure import Figure


def plot_convergence(
    history: Sequence[float], name: str, *, unit: str = "", ax: Axes | None = None
) -> Axes:
    """The objective ``name`` after each iteration; on a log scale when it is positive and
    spans more than three decades (a converging sum of squares), else plain.

    Parameters
    ----------
    history : sequence of float
        The best objective after each iteration (``Optimum.history``), as given: no unit is
        converted.
    name : str
        The objective's name, for the labels.
    unit : str, default ""
        The unit ``history`` is in, shown on the axis label; none when empty.
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; a new figure is made without one.

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn into.
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 4))
    h = np.asarray(history, dtype=np.float64)
    it = np.arange(1, h.size + 1)
    positive = h.size > 1 and (h > 0).all()
    if positive and h.max() / h.min() > 1e3:
        ax.semilogy(it, h, marker="o", ms=3, color="#1f4e79")
    else:
        ax.plot(it, h, marker="o", ms=3, color="#1f4e79")
    ax.set_xlabel("iteration")
    ax.set_ylabel(f"{name} [{unit}]" if unit else name)
    ax.set_title(f"convergence of {name}")
    ax.grid(True, alpha=0.3)
    return ax


def plot_in_bounds(
    values: Mapping[str, float],
    bounds: Mapping[str, tuple[float, float]],
    *,
    ax: Axes | None = None,
) -> Axes:
    """Each variable's place in its box: 0 at its lower bound, 1 at its upper one.

    Parameters
    ----------
    values : mapping of str to float
    bounds : mapping of str to (float, float)
        Each variable's bounds, in the units of ``values``.
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    import matplotlib.pyplot as plt

    names = list(values)
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 1.2 + 0.4 * len(names)))
    y = np.arange(len(names))
    place = [(values[k] - bounds[k][0]) / (bounds[k][1] - bounds[k][0]) for k in names]
    ax.hlines(y, 0.0, 1.0, color="0.75", lw=6)
    ax.plot(place, y, "o", color="#1f4e79")
    ax.set_yticks(y, names)
    ax.set_xlim(-0.05, 1.05)
    ax.set_xticks([0.0, 0.5, 1.0], ["low", "", "high"])
    ax.invert_yaxis()
    ax.set_title("the optimum in its box")
    return ax


@dataclass
class StudyPlot:
    """The artists of [`plot_study`][excavkin.studies.plots.plot_study].

    Attributes
    ----------
    fig : matplotlib.figure.Figure
    ax : matplotlib.axes.Axes
    feasible, infeasible : PathCollection
        The feasible designs' points and the others'.
    """

    fig: Figure
    ax: Axes
    feasible: PathCollection
    infeasible: PathCollection


def plot_study(
    x: ArrayLike,
    y: ArrayLike,
    feasible: ArrayLike,
    *,
    xlabel: str,
    ylabel: str,
    ax: Axes | None = None,
) -> StudyPlot:
    """One point per design: a metric against a design variable, the infeasible designs grey.

    Parameters
    ----------
    x, y : array_like, shape (n,)
    feasible : array_like of bool, shape (n,)
    xlabel, ylabel : str
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    StudyPlot
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 4.5))
    xs, ys = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    ok = np.asarray(feasible, dtype=bool)
    size = 4.0 if xs.size > 2000 else 12.0
    bad = ax.scatter(xs[~ok], ys[~ok], s=size, color="0.7", label="infeasible", lw=0)
    good = ax.scatter(xs[ok], ys[ok], s=size, color="#1f4e79", label="feasible", lw=0)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", markerscale=2)
    fig = ax.get_figure(root=True)
    assert fig is not None
    return StudyPlot(fig, ax, good, bad)  # type: ignore[arg-type]
