"""Figures of the reproduced and extended seed-paper studies (``excavkin reproduce ...``).

matplotlib is imported inside the functions only. The curves are drawn with
:func:`excavkin.outputs.plots.plot_columns` (display units, axis labels); figures are built
on :class:`matplotlib.figure.Figure` directly, without pyplot, so no GUI backend is touched.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.outputs.plots import plot_columns
from excavkin.outputs.tables import check_target, write_atomic

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    from excavkin.applications.laws_study import LawStudy

__all__ = ["LawComparisonFigure", "law_comparison_figure", "save_png"]

_SHOCK_COLORS = ("#d62728", "#ff7f0e", "#8c564b", "#e377c2")
_FREE_COLORS = ("#1f77b4", "#2ca02c", "#17becf", "#9467bd", "#393b79", "#637939", "#7f7f7f")


@dataclass
class LawComparisonFigure:
    """The artists of :func:`law_comparison_figure`.

    Attributes
    ----------
    figure : matplotlib.figure.Figure
    axes : dict of str to Axes
        ``"rod"``, ``"cylinder"``, ``"rocker"`` (curves against time) and ``"peaks"`` (bars).
    lines : dict of (str, str) to Line2D
        ``(panel, law)`` → the curve.
    """

    figure: Figure
    axes: dict[str, Axes]
    lines: dict[tuple[str, str], Line2D] = field(default_factory=dict)


def _law_styles(study: LawStudy) -> dict[str, dict[str, Any]]:
    styles: dict[str, dict[str, Any]] = {}
    k_shock = k_free = 0
    for r in study.rows:
        if r.shock_free:
            styles[r.law] = {"color": _FREE_COLORS[k_free % len(_FREE_COLORS)], "ls": "-"}
            k_free += 1
        else:
            styles[r.law] = {"color": _SHOCK_COLORS[k_shock % len(_SHOCK_COLORS)], "ls": "--"}
            k_shock += 1
    return styles


def law_comparison_figure(
    study: LawStudy,
    *,
    fig: Figure | None = None,
    title: str | None = None,
) -> LawComparisonFigure:
    """Rod acceleration, cylinder and rocker ε against time for every law, and their peaks.

    Parameters
    ----------
    study : LawStudy
        From :func:`excavkin.applications.laws_study.compare_laws`.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (it is cleared); a new 11 × 8 in figure without one.
    title : str, optional
        Figure title.

    Returns
    -------
    LawComparisonFigure

    Notes
    -----
    Laws with soft shocks are dashed in warm colours, shock-free laws solid in cool ones. The
    curves run from ``−T/10`` to ``1.1·T`` so that the jumps at ``0`` and ``T`` show.
    """
    import pandas as pd
    from matplotlib.figure import Figure

    if fig is None:
        fig = Figure(figsize=(11.0, 8.0), layout="constrained")
    else:
        fig.clear()
    axs = fig.subplots(2, 2)
    axes = {"rod": axs[0, 0], "cylinder": axs[0, 1], "rocker": axs[1, 0], "peaks": axs[1, 1]}
    out = LawComparisonFigure(fig, axes)
    styles = _law_styles(study)
    panels = (
        ("rod", "cyl.accel", "acceleration", "(a) rod relative acceleration $a_{21}$ [m/s²]"),
        (
            "cylinder",
            "cyl.epsilon",
            "angular_acceleration",
            "(b) cylinder angular acceleration $\\varepsilon_1$ [rad/s²]",
        ),
        (
            "rocker",
            "rocker.epsilon",
            "angular_acceleration",
            "(c) rocker angular acceleration $\\varepsilon_3$ [rad/s²]",
        ),
    )
    arrays = {
        "cyl.accel": study.rod_accel,
        "cyl.epsilon": study.cyl_eps,
        "rocker.epsilon": study.rocker_eps,
    }
    for k, r in enumerate(study.rows):
        frame = pd.DataFrame({"t": study.t, **{c: arrays[c][k] for c in arrays}})
        frame.attrs["excavkin.kinds"] = {"cyl.accel": "acceleration"}
        for panel, col, _, _ in panels:
            handle = plot_columns(
                frame,
                y=col,
                x="t",
                ax=axes[panel],
                mark=False,
                legend=False,
                label=r.law,
                lw=1.4,
                **styles[r.law],
            )
            out.lines[(panel, r.law)] = handle.lines[col]
    for panel, _, _, label in panels:
        ax = axes[panel]
        ax.set_title(label, fontsize="medium", loc="left")
        ax.set_ylabel("")
        ax.axhline(0.0, color="#999999", lw=0.6)
        for tb in (0.0, study.duration):
            ax.axvline(tb, color="#bbbbbb", lw=0.6, ls=":")
    axes["rod"].legend(fontsize="small", ncol=2, loc="lower left")

    ax = axes["peaks"]
    x = np.arange(len(study.rows))
    peak3 = np.array([r.rocker_peak for r in study.rows])
    peak1 = np.array([r.cyl_peak for r in study.rows])
    jump3 = np.array([max(abs(r.rocker_start), abs(r.rocker_end)) for r in study.rows])
    colors = [styles[r.law]["color"] for r in study.rows]
    from matplotlib.patches import Patch

    ax.bar(x - 0.2, peak1, 0.4, color=colors, alpha=0.45)
    ax.bar(x + 0.2, peak3, 0.4, color=colors)
    has_jump = jump3 > 0.0
    ax.bar(
        x[has_jump] + 0.2, jump3[has_jump], 0.4, fill=False, hatch="///", edgecolor="black", lw=0.8
    )
    ax.set_xticks(x, [r.law for r in study.rows], rotation=35, ha="right", fontsize="small")
    ax.set_title("(d) peaks and soft shocks [rad/s²]", fontsize="medium", loc="left")
    ax.grid(True, axis="y", color="#e0e0e0", lw=0.8)
    ax.set_axisbelow(True)
    ax.set_ylim(0.0, 1.4 * float(max(peak1.max(), peak3.max())))
    proxies = [
        Patch(facecolor="#888888", alpha=0.45, label="max |ε1| (cylinder)"),
        Patch(facecolor="#444444", label="max |ε3| (rocker)"),
        Patch(
            facecolor="white", edgecolor="black", hatch="///", label="soft shock |Δε3| at an end"
        ),
    ]
    ax.legend(handles=proxies, fontsize="small", loc="upper center", ncol=2)
    if title:
        fig.suptitle(title)
    return out


def save_png(fig: Figure, path: str | Path, *, force: bool = False, dpi: int = 100) -> Path:
    """Write a figure as PNG, atomically; refuse to replace a file unless ``force``."""
    p = check_target(path, force=force, suffixes=(".png",))
    return write_atomic(p, lambda tmp: fig.savefig(tmp, dpi=dpi, format="png"))
