"""An optimisation's convergence: the best objective after each iteration."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes


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
