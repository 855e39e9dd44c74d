"""Figures of ``excavkin reproduce rope-shovel``: the mechanism's scheme, its angles and rates.

matplotlib is imported inside the functions only; figures are built on
`matplotlib.figure.Figure` without pyplot. Curves go through
[`excavkin.outputs.plots.plot_columns`][] (display units on every axis).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from excavkin.papers.figures import PaperFigure, new_figure, panel

if TYPE_CHECKING:
    from excavkin.papers.common import PaperRun
# ------------------------------------------------------------------------------------------
# Maksimov rope shovel
# ------------------------------------------------------------------------------------------

_ROPE_UNITS = {"angle": "deg", "length": "m", "time": "s"}
_PHI1 = "φ1 stick angle"


def rope_shovel_scheme(run: PaperRun, samples: Sequence[int]) -> PaperFigure:
    """The paper's only figure, «Схема механизма поворота ковша»: the mechanism drawn.

    Parameters
    ----------
    run : PaperRun
        From `excavkin.papers.rope_shovel.study.rope_shovel_sweep`.
    samples : sequence of int
        Samples to draw; the last one in full, the others faded.

    Returns
    -------
    PaperFigure
        Panel ``"scheme"``.
    """
    from excavkin.outputs.drawing import draw_mechanism

    fig = new_figure(7.5, 5.2)
    ax = fig.subplots()
    draw_mechanism(run.result, list(samples), ax=ax, ropes=["drag"], length_unit="m")
    phis = ", ".join(f"{np.degrees(run['phi1'][s]):.0f}°" for s in samples)
    ax.set_title(
        f"EO-4112 bucket-turning mechanism at φ1 = {phis} (last drawn in full)\n"
        "paper's frame: X from the stick pivot O1 towards the boom foot",
        fontsize="medium",
    )
    ax.set_xlabel("X [m]")
    ax.set_ylabel("Y [m]")
    return PaperFigure(fig, {"scheme": ax})


def rope_shovel_angles(run: PaperRun) -> PaperFigure:
    """Angles of the links against the stick angle φ1 (the paper's outputs, §1, §3).

    Parameters
    ----------
    run : PaperRun
        From `excavkin.papers.rope_shovel.study.rope_shovel_sweep`.

    Returns
    -------
    PaperFigure
        Panels ``"absolute"`` (φ2 = φ5, φ3, bucket to the horizon) and ``"stick"``
        (φ6, φ7', γ relative to the stick).
    """
    fig = new_figure(7.0, 6.4)
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    frame_run = _with_phi1(run)
    panel(
        ax1,
        frame_run,
        {
            "phi2": "φ2 = φ5 lever",
            "phi3": "φ3 cylinder Ц2 (locked)",
            "bucket_to_horizon": "bucket to the horizon",
        },
        _PHI1,
        units=_ROPE_UNITS,
        ylabel="absolute angle [°]",
        xlabel="",
        title="absolute angles (paper's frame)",
    )
    panel(
        ax2,
        frame_run,
        {"phi7p": "φ7' bucket to the handle", "phi6": "φ6 coupler", "gamma": "γ cylinder Ц1"},
        _PHI1,
        units=_ROPE_UNITS,
        ylabel="angle to the stick [°]",
        xlabel="φ1 stick angle [°]",
        title="relative to the stick (handle)",
    )
    return PaperFigure(fig, {"absolute": ax1, "stick": ax2})


def rope_shovel_rates(run: PaperRun) -> PaperFigure:
    """Angular velocities, the stroke rate and length of cylinder Ц1 against φ1.

    Parameters
    ----------
    run : PaperRun
        From `excavkin.papers.rope_shovel.study.rope_shovel_sweep` (winch at constant speed).

    Returns
    -------
    PaperFigure
        Panels ``"omega"``, ``"v_c1"``, ``"hk"``.
    """
    fig = new_figure(7.0, 7.6)
    ax1, ax2, ax3 = fig.subplots(3, 1, sharex=True)
    r = _with_phi1(run)
    v = float(np.median(run["v_rope"]))
    panel(
        ax1,
        r,
        {
            "omega1": "ω1 stick",
            "omega2": "ω2 lever",
            "omega3": "ω3 Ц2",
            "omega7p": "ω7 bucket / stick",
            "omega10": "ω10 Ц1 / stick",
        },
        _PHI1,
        units=_ROPE_UNITS,
        ylabel="angular velocity [rad/s]",
        xlabel="",
        title=f"drag rope hauled in at v_тк = {v:.3f} m/s",
    )
    ax1.axhline(0.0, color="0.6", lw=0.8)
    panel(
        ax2,
        r,
        {"v_c1": "v_Ц1"},
        _PHI1,
        units=_ROPE_UNITS,
        ylabel="v_Ц1 = d(HK)/dt [m/s]",
        xlabel="",
        styles=[{"color": "#9467bd"}],
    )
    ax2.axhline(0.0, color="0.6", lw=0.8)
    panel(
        ax3,
        r,
        {"hk": "HK"},
        _PHI1,
        units=_ROPE_UNITS,
        ylabel="HK, length of Ц1 [m]",
        xlabel="φ1 stick angle [°]",
        styles=[{"color": "#8c564b"}],
    )
    return PaperFigure(fig, {"omega": ax1, "v_c1": ax2, "hk": ax3})


def _with_phi1(run: PaperRun) -> PaperRun:
    from excavkin.papers.common import PaperRun

    return PaperRun(
        {**run.columns, _PHI1: run.columns["phi1"]}, {**run.kinds, _PHI1: "angle"}, run.result
    )
