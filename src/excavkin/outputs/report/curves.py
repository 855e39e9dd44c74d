"""The report's curves section: result columns over the sweep, one zoomable panel per kind.

Failed runs are shaded and dead positions marked across every panel; `curves_note` says
how to read the rates.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from excavkin.outputs.display_units import KIND_NAMES, pretty_unit
from excavkin.outputs.events import dead_samples, failed_runs
from excavkin.outputs.protocols import Solved
from excavkin.outputs.report.data import ReportData, thin
from excavkin.outputs.style import BODY_COLORS, DEAD_COLOR, FAIL_COLOR

__all__ = ["MAX_CURVE_POINTS", "curves_figure", "curves_note"]

#: most samples per curve; longer results are thinned evenly
MAX_CURVE_POINTS = 5000


def curves_figure(
    result: Solved,
    y: Iterable[str] | None = None,
    *,
    units: Mapping[str, str] | None = None,
    max_points: int = MAX_CURVE_POINTS,
) -> Any:
    """A Plotly figure of result columns, one zoomable panel per kind, sharing the x axis.

    Parameters
    ----------
    result : result or DataFrame
    y : iterable of str, optional
        Default `excavkin.outputs.plots.main_columns`.
    units : mapping of str to str, optional
    max_points : int
        Most samples per curve; longer results are thinned evenly.

    Returns
    -------
    plotly.graph_objects.Figure
    """
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    from excavkin.outputs.plots import main_columns

    data = ReportData(result, units)
    cols = list(y) if y is not None else main_columns(data.table)
    groups: dict[tuple[str, str], list[str]] = {}
    for d in data.units.all(cols):
        groups.setdefault((d.kind, d.unit), []).append(d.column)
    rows = max(len(groups), 1)
    fig = make_subplots(rows=rows, cols=1, shared_xaxes=True, vertical_spacing=0.035)
    keep = thin(len(data.xv), max_points)
    xs = [float(v) if np.isfinite(v) else None for v in data.xv[keep]]
    palette = BODY_COLORS
    for r, ((kind, unit), group) in enumerate(groups.items(), start=1):
        for k, c in enumerate(group):
            d = data.units(c)
            v = d.values(data.table.frame[c].to_numpy(dtype=np.float64))[keep]
            fig.add_trace(
                go.Scatter(
                    x=xs,
                    y=[float(a) if np.isfinite(a) else None for a in v],
                    mode="lines",
                    name=c,
                    line={"width": 2, "color": palette[k % len(palette)]},
                    hovertemplate=f"{c}: %{{y:.4g}}<extra></extra>",
                    legendgroup=str(r),
                ),
                row=r,
                col=1,
            )
        name = KIND_NAMES.get(kind, "Value")
        fig.update_yaxes(title_text=f"{name} [{pretty_unit(unit)}]" if unit else name, row=r, col=1)
    step = float(np.nanmedian(np.abs(np.diff(data.xv)))) if data.xv.size > 1 else 0.0
    first = True
    for a, b, _ in failed_runs(data.table):
        seg = data.xv[a : b + 1]
        fig.add_vrect(
            x0=float(np.nanmin(seg)) - step / 2,
            x1=float(np.nanmax(seg)) + step / 2,
            fillcolor=FAIL_COLOR,
            opacity=0.12,
            line_width=0,
            row="all",
            col=1,
        )
        if first:
            fig.add_trace(
                go.Scatter(
                    x=[None],
                    y=[None],
                    mode="lines",
                    name="does not close",
                    line={"color": FAIL_COLOR, "width": 8},
                    opacity=0.3,
                )
            )
            first = False
    dead = dead_samples(data.table)
    for i in dead:
        fig.add_vline(
            x=float(data.xv[i]),
            line={"color": DEAD_COLOR, "dash": "dash", "width": 1.5},
            row="all",
            col=1,
        )
    if dead.size:
        fig.add_trace(
            go.Scatter(
                x=[None],
                y=[None],
                mode="lines",
                name="dead position",
                line={"color": DEAD_COLOR, "dash": "dash"},
            )
        )
    x_title = (
        "Time [s]"
        if data.x == "t"
        else ("Sample" if data.x == "sample" else f"{data.x_name()} [{pretty_unit(data.xd.unit)}]")
    )
    fig.update_xaxes(title_text=x_title, row=rows, col=1)
    fig.update_xaxes(gridcolor="#ececec", zeroline=False)
    fig.update_yaxes(gridcolor="#ececec", zeroline=False)
    fig.update_layout(
        height=90 + 230 * rows,
        margin={"l": 70, "r": 20, "t": 20, "b": 50},
        plot_bgcolor="white",
        hovermode="x unified",
        legend={"orientation": "v", "x": 1.01, "y": 1.0},
    )
    return fig


def curves_note(result: Solved, in_time: bool) -> str:
    """How to read the rates: real ones, or per unit input rate (transfer functions).

    Parameters
    ----------
    result : result
        The solved result.
    in_time : bool
        Whether the result is a run in time (it has a ``t`` column).

    Returns
    -------
    str
    """
    if in_time:
        return "Velocities and accelerations are in time, from the motion laws' rates."
    kin: Any = getattr(result, "kinematics", result)
    rates = np.asarray(getattr(kin, "input_rates", np.ones((0, 0))))
    accels = np.asarray(getattr(kin, "input_accels", np.zeros((0, 0))))
    unit_rates = rates.size == 0 or bool(np.all((rates == 1.0) | (rates == 0.0)))
    if unit_rates and not np.any(accels):
        return (
            "Velocities and accelerations are per unit input rate (the transfer functions "
            "dφ/dq and d²φ/dq²): no input rate was given."
        )
    return "Velocities and accelerations are for the input rates and accelerations given."
