"""What the papers' figures share: the figure record, a blank figure, a run as a table,
a panel of curves, and writing a PNG.

matplotlib is imported inside the functions only; figures are built on
`matplotlib.figure.Figure` without pyplot. Curves go through
[`excavkin.outputs.plots.plot_columns`][] (display units on every axis).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.outputs.plots import plot_columns
from excavkin.outputs.tables import check_target, write_atomic

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from excavkin.papers.common import PaperRun


@dataclass
class PaperFigure:
    """The artists of one reproduced figure.

    Attributes
    ----------
    figure : matplotlib.figure.Figure
    axes : dict of str to Axes
        The panels by name.
    """

    figure: Figure
    axes: dict[str, Axes] = field(default_factory=dict)


def new_figure(width: float, height: float) -> Figure:
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), layout="constrained")


def run_frame(run: PaperRun, names: Mapping[str, str], x: str) -> pd.DataFrame:
    """A DataFrame of ``run``'s columns renamed for display, with their kinds attached."""
    import pandas as pd

    def curve(key: str) -> Any:
        v = run.columns[key]
        ok = np.isfinite(v)
        if run.kinds[key] == "angle" and ok.sum() > 1:  # continuous curves through ±180°
            v = v.copy()
            v[ok] = np.unwrap(v[ok])
        return v

    cols = {x: curve(x), **{label: curve(key) for key, label in names.items()}}
    frame = pd.DataFrame(cols)
    frame.attrs["excavkin.kinds"] = {
        x: run.kinds[x],
        **{label: run.kinds[key] for key, label in names.items()},
    }
    return frame


def panel(
    ax: Axes,
    run: PaperRun,
    names: Mapping[str, str],
    x: str,
    *,
    units: Mapping[str, str],
    ylabel: str,
    xlabel: str,
    title: str | None = None,
    styles: Sequence[Mapping[str, Any]] = (),
) -> None:
    frame = run_frame(run, names, x)
    labels = list(names.values())
    for k, lab in enumerate(labels):
        style = dict(styles[k]) if k < len(styles) else {}
        plot_columns(frame, [lab], x, units=units, ax=ax, mark=False, legend=False, **style)
    ax.set_ylabel(ylabel)
    ax.set_xlabel(xlabel)
    if title:
        ax.set_title(title, fontsize="medium")
    if len(labels) > 1:
        ax.legend(fontsize="small", loc="best")


def save_png(fig: Figure, path: str | Path, *, force: bool = False, dpi: int = 100) -> Path:
    """Write a figure as PNG, atomically; refuse to replace a file unless ``force``."""
    p = check_target(path, force=force, suffixes=(".png",))
    return write_atomic(p, lambda tmp: fig.savefig(tmp, dpi=dpi, format="png"))
