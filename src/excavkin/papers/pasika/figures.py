"""Figures of ``excavkin reproduce pasika`` and ``pasika-laws``: the paper's Fig. 3 and Fig. 5
redrawn, and the comparison of motion laws.

matplotlib is imported inside the functions only; figures are built on
`matplotlib.figure.Figure` without pyplot. Curves go through
[`excavkin.outputs.plots.plot_columns`][] (display units on every axis).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.outputs.plots import plot_columns
from excavkin.papers.figures import PaperFigure, new_figure, panel

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    from excavkin.papers.common import PaperRun
    from excavkin.papers.pasika.laws import LawStudy
# ------------------------------------------------------------------------------------------
# Pasika & Koruniak
# ------------------------------------------------------------------------------------------

_PASIKA_UNITS = {"length": "m", "angle": "deg", "time": "s"}


def pasika_fig3(run: PaperRun) -> PaperFigure:
    """Fig. 3 of the paper: rod displacement s, velocity v21 and acceleration a21 against t.

    Parameters
    ----------
    run : PaperRun
        From [`excavkin.papers.pasika.study.pasika_run`][].

    Returns
    -------
    PaperFigure
        Panels ``"s"``, ``"v"``, ``"a"``.
    """
    fig = new_figure(6.4, 6.4)
    axes = fig.subplots(3, 1, sharex=True)
    out = PaperFigure(fig)
    for ax, key, ylabel in zip(
        axes,
        ("s", "v21", "a21"),
        ("s [m]", "v₂₁ [m/s]", "a₂₁ [m/s²]"),
        strict=True,
    ):
        panel(
            ax,
            run,
            {key: key},
            "t",
            units=_PASIKA_UNITS,
            ylabel=ylabel,
            xlabel="t [s]" if key == "a21" else "",
            styles=[{"color": "#1f77b4"}],
        )
        out.axes[key.rstrip("21") or key] = ax
    axes[2].axhline(0.0, color="0.6", lw=0.8)
    fig.suptitle(
        "Pasika & Koruniak, Fig. 3: cubic law of the rod, H = 0.5 m, T = 5 s", fontsize="medium"
    )
    return out


def pasika_fig5(
    run: PaperRun,
    table: Mapping[str, Sequence[float]] | None = None,
    times: Sequence[float] = (),
) -> PaperFigure:
    """Fig. 5 of the paper: (a) cylinder φ1, ω1, ε1 and (b) rocker φ3, ω3, ε3 against t.

    Parameters
    ----------
    run : PaperRun
        From [`excavkin.papers.pasika.study.pasika_run`][].
    table : mapping, optional
        Points to overlay (spec §4.3: ``phi1`` in degrees, ``omega1``, ``eps1``, ...).
    times : sequence of float
        The times of ``table``'s rows [s].

    Returns
    -------
    PaperFigure
        Panels ``"phi1"``, ``"omega1"``, ``"eps1"``, ``"phi3"``, ``"omega3"``, ``"eps3"``.
    """
    fig = new_figure(9.0, 6.6)
    axes = fig.subplots(3, 2, sharex=True)
    out = PaperFigure(fig)
    rows = (("phi", "φ{} [°]"), ("omega", "ω{} [rad/s]"), ("eps", "ε{} [rad/s²]"))
    for col, (link, title) in enumerate((("1", "(a) cylinder 1"), ("3", "(b) rocker 3"))):
        for row, (q, ylabel) in enumerate(rows):
            ax = axes[row, col]
            key = f"{q}{link}"
            panel(
                ax,
                run,
                {key: f"{key} engine"},
                "t",
                units=_PASIKA_UNITS,
                ylabel=ylabel.format(link),
                xlabel="t [s]" if row == 2 else "",
                title=title if row == 0 else None,
                styles=[{"color": "#1f77b4"}],
            )
            if table is not None and times:
                ax.plot(
                    list(times),
                    list(table[key]),
                    "o",
                    ms=5,
                    mfc="none",
                    color="#d62728",
                    label="spec §4.3",
                )
                ax.legend(["engine", "spec §4.3"], fontsize="small", loc="best")
            if row > 0:
                ax.axhline(0.0, color="0.6", lw=0.8)
            out.axes[key] = ax
    fig.suptitle(
        "Pasika & Koruniak, Fig. 5: cylinder and rocker under the cubic law", fontsize="medium"
    )
    return out


_SHOCK_COLORS = ("#d62728", "#ff7f0e", "#8c564b", "#e377c2")
_FREE_COLORS = ("#1f77b4", "#2ca02c", "#17becf", "#9467bd", "#393b79", "#637939", "#7f7f7f")


@dataclass
class LawComparisonFigure:
    """The artists of `law_comparison_figure`.

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
        From `excavkin.papers.pasika.laws.compare_laws`.
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
        for at, col, _, _ in panels:
            handle = plot_columns(
                frame,
                y=col,
                x="t",
                ax=axes[at],
                mark=False,
                legend=False,
                label=r.law,
                lw=1.4,
                **styles[r.law],
            )
            out.lines[(at, r.law)] = handle.lines[col]
    for at, _, _, label in panels:
        ax = axes[at]
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
