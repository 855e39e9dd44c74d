"""Tolerance bands drawn over a sweep: nominal, worst case, root-sum-square and Monte Carlo."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from excavkin.outputs.display_units import DisplayUnits

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from excavkin.studies.tolerance import ToleranceBands


@dataclass(frozen=True, slots=True)
class BandsPlot:
    """Handles of a bands plot: the axes and its nominal line."""

    ax: Axes
    nominal: Any


def plot_bands(
    bands: ToleranceBands,
    column: str,
    x: npt.ArrayLike | None = None,
    *,
    x_label: str = "sample",
    unit: str | None = None,
    ax: Axes | None = None,
) -> BandsPlot:
    """The bands of one column over the sweep, in a display unit.

    Parameters
    ----------
    bands : ToleranceBands
        The bands of a sweep of n samples.
    column : str
        The column drawn, one of ``bands.columns``.
    x : array_like, shape (n,), optional
        Abscissa (default: the sample number), in the unit ``x_label`` names.
    x_label : str, default "sample"
        Label of the abscissa.
    unit : str, optional
        Display unit of the column (default: its kind's, mm for lengths).
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; a new figure is made without one.

    Returns
    -------
    BandsPlot
        The axes and the nominal line. The bands are drawn as deviations from the nominal;
        the title gives the nominal range and the two largest worst-case contributions.
    """
    import matplotlib.pyplot as plt

    j = bands.index(column)
    show = DisplayUnits({column: unit} if unit else None)(column)
    if ax is None:
        _, ax = plt.subplots(figsize=(8, 4.5))
    n = bands.nominal.shape[0]
    xs = np.arange(n) if x is None else np.asarray(x, dtype=np.float64)
    nom = bands.nominal[:, j]

    def d(values: Any) -> Any:
        return show.convert(values)

    # deviations from the nominal: the bands are small beside the column's own range
    worst, rss = d(bands.worst[:, j]), d(bands.rss[:, j])
    ax.fill_between(xs, -worst, worst, color="#fdd0a2", label="worst case (linear)")
    ax.fill_between(xs, -rss, rss, color="#fd8d3c", alpha=0.8, label="root-sum-square")
    if np.isfinite(bands.mc_min[:, j]).any():
        label = f"Monte Carlo range ({bands.draws:,} draws)"
        ax.plot(xs, d(bands.mc_min[:, j] - nom), color="#7f2704", lw=1, ls="--", label=label)
        ax.plot(xs, d(bands.mc_max[:, j] - nom), color="#7f2704", lw=1, ls="--")
        ax.plot(
            xs, d(3 * bands.mc_std[:, j]), color="#08519c", lw=1, ls=":", label="Monte Carlo ±3σ"
        )
        ax.plot(xs, d(-3 * bands.mc_std[:, j]), color="#08519c", lw=1, ls=":")
    (line,) = ax.plot(xs, np.zeros_like(xs), color="black", lw=1.2, label="nominal")
    ax.set_xlabel(x_label)
    ax.set_ylabel(f"{column} − nominal" + (f" [{show.unit}]" if show.unit else ""))
    top = [(name, v) for name, v in bands.ranking(column)[:2] if v > 0]
    ranked = ", ".join(f"{name} {d(np.asarray(v)):.3g}" for name, v in top)
    lo, hi = np.nanmin(d(nom)), np.nanmax(d(nom))
    ax.set_title(
        f"{column} (nominal {lo:.4g} … {hi:.4g} {show.unit})\n"
        f"largest worst-case contributions: {ranked or 'none'}",
        fontsize=9,
    )
    ax.legend(loc="best", fontsize=8)
    ax.grid(alpha=0.3)
    return BandsPlot(ax, line)
