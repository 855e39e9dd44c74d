"""Curves of a result: any column against the input, time or another column, in display units.

Thin matplotlib functions (``ax`` in, a handle out, unknown keywords rejected) that take any
[`KinematicResult`][excavkin.kinematics.KinematicResult], any result with ``to_frame()``
(kinetostatic
results: ``<point>.<body>.Fx``, ``<driver>.force``, ``<driver>.torque``) or a DataFrame with such
columns. matplotlib is imported inside the functions only.

>>> import numpy as np, excavkin
>>> from excavkin.outputs.plots import plot_columns
>>> res = excavkin.load(excavkin.example_path("fourbar")).solve(
...     {"crank": np.radians(np.arange(0, 361, 5))})
>>> handle = plot_columns(res, y=["rocker.angle"])
>>> handle.ax.get_xlabel(), handle.ax.get_ylabel()
('crank [°]', 'rocker.angle [°]')

The mechanism itself is drawn by `excavkin.outputs.drawing`
([`draw_mechanism`][excavkin.outputs.plots.draw_mechanism],
[`trace_paths`][excavkin.outputs.plots.trace_paths], re-exported here).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.outputs.display_units import KIND_NAMES, Display, DisplayUnits, pretty_unit
from excavkin.outputs.drawing import (
    MechanismDrawing,
    TracedPaths,
    draw_mechanism,
    trace_paths,
)
from excavkin.outputs.events import Table, as_table, dead_samples, failed_runs, varies
from excavkin.outputs.style import DEAD_COLOR, FAIL_COLOR, check_line_style

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    from excavkin.outputs.protocols import TableData

__all__ = [
    "ColumnsPlot",
    "CurvesPlot",
    "MechanismDrawing",
    "TracedPaths",
    "check_line_style",
    "default_x",
    "draw_mechanism",
    "main_columns",
    "plot_columns",
    "plot_curves",
    "trace_paths",
]


def default_x(table: Table) -> str:
    """The column to plot against: ``t`` if present, else the first input that varies, else
    ``"sample"`` (the row number)."""
    frame = table.frame
    if "t" in frame:
        return "t"
    if table.plan is not None:
        candidates = [f"{name}.value" for name in table.plan.inputs]
    else:
        candidates = table.of_quantity("value", "driver")
    for c in candidates:
        if c in frame and varies(frame[c]):
            return c
    return "sample"


def _values(table: Table, column: str) -> np.ndarray:
    if column == "sample":
        return np.arange(len(table.frame), dtype=np.float64)
    if column not in table.frame:
        cols = [str(c) for c in table.frame.columns if c != "status"]
        near = [c for c in cols if c.split(".")[0] == column.split(".")[0]]
        hint = f"; columns of {column.split('.')[0]!r}: {', '.join(near)}" if near else ""
        raise KeyError(f"no column {column!r} in the result{hint}")
    return np.asarray(table.frame[column], dtype=np.float64)


def _x_label(d: Display) -> str:
    if d.column == "t":
        return f"Time [{pretty_unit(d.unit)}]"
    if d.column == "sample":
        return "Sample"
    if d.quantity == "value":
        name = d.owner
        return f"{name} [{pretty_unit(d.unit)}]" if d.unit else name
    return d.label


@dataclass
class ColumnsPlot:
    """The artists of [`plot_columns`][excavkin.outputs.plots.plot_columns].

    Attributes
    ----------
    ax : matplotlib.axes.Axes
    lines : dict of str to Line2D
        One line per y column; ``get_data()`` are the plotted values in display units.
    x : Display
        The x column and its display unit.
    y : list of Display
    failures : list
        Shaded spans over samples that do not close.
    dead : list of Line2D
        Vertical lines at dead positions.
    """

    ax: Axes
    lines: dict[str, Line2D]
    x: Display
    y: list[Display]
    failures: list[Any] = field(default_factory=list)
    dead: list[Line2D] = field(default_factory=list)


def _mark(ax: Axes, table: Table, xv: np.ndarray, out: ColumnsPlot) -> None:
    finite = np.isfinite(xv)
    if finite.sum() < 1:
        return
    step = float(np.nanmedian(np.abs(np.diff(xv)))) if xv.size > 1 else 0.0
    for k, (a, b, _) in enumerate(failed_runs(table)):
        seg = xv[a : b + 1]
        lo, hi = float(np.nanmin(seg)) - step / 2, float(np.nanmax(seg)) + step / 2
        out.failures.append(
            ax.axvspan(
                lo,
                hi,
                color=FAIL_COLOR,
                alpha=0.12,
                lw=0,
                label="does not close" if k == 0 else None,
            )
        )
    for k, i in enumerate(dead_samples(table)):
        if np.isfinite(xv[i]):
            out.dead.append(
                ax.axvline(
                    float(xv[i]),
                    color=DEAD_COLOR,
                    ls="--",
                    lw=1.2,
                    label="dead position" if k == 0 else None,
                )
            )


def plot_columns(
    data: TableData,
    y: str | Sequence[str],
    x: str | None = None,
    *,
    units: Mapping[str, str] | None = None,
    ax: Axes | None = None,
    mark: bool = True,
    legend: bool | None = None,
    title: str | None = None,
    **style: Any,
) -> ColumnsPlot:
    """Plot result columns of one kind of quantity against the input, time or any column.

    Parameters
    ----------
    data : KinematicResult, a result with ``to_frame()``, or pandas.DataFrame
        Columns in SI, named as in
        [`KinematicResult.to_frame`][excavkin.kinematics.result.KinematicResult.to_frame] (and force
        columns
        ``<point>.<body>.Fx``, ``<driver>.force``, ``<driver>.torque``).
    y : str or sequence of str
        Column(s) to plot; all of one kind (lengths, angles, forces, ...).
    x : str, optional
        ``"t"``, ``"sample"`` (row number) or any column. Default: ``t`` if the result is in
        time, otherwise the first input that varies.
    units : mapping of str to str, optional
        Display units by kind or by column, e.g. ``{"angle": "rad", "force": "N",
        "boom_cyl.value": "m"}``. Defaults: mm, deg, m/s, kN, kN·m, s, ...
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; a new figure is made without one.
    mark : bool
        Shade the samples that do not close and draw a line at each dead position.
    legend : bool, optional
        Default: a legend when there are several lines or marks.
    title : str, optional
        Axes title.
    **style
        matplotlib ``Line2D`` properties for every line (``color``, ``lw``, ``ls``, ``marker``,
        ``alpha``, ``label`` ...).

    Returns
    -------
    ColumnsPlot

    Raises
    ------
    TypeError
        On a keyword that is not a ``Line2D`` property.
    KeyError
        On an unknown column.
    ValueError
        If the y columns are of different kinds (plot them on separate axes, or use
        [`plot_curves`][excavkin.outputs.plots.plot_curves]).
    """
    style = check_line_style(style)
    table = as_table(data)
    cols = [y] if isinstance(y, str) else list(y)
    if not cols:
        raise ValueError("y: give at least one column")
    disp = DisplayUnits(units, table.kinds)
    x = x or default_x(table)
    xd = disp(x)
    xv = xd.convert(_values(table, x))
    yds = disp.all(cols)
    kinds = {d.kind for d in yds}
    units_used = {d.unit for d in yds}
    if len(kinds) > 1 or len(units_used) > 1:
        listing = ", ".join(f"{d.column} ({d.kind})" for d in yds)
        raise ValueError(
            f"y columns of different kinds or units: {listing}; plot them on "
            "separate axes or use plot_curves"
        )
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(7, 4), layout="constrained")
    lines: dict[str, Line2D] = {}
    for d in yds:
        kw = {"linewidth": 1.8, "label": d.column, **style}
        (lines[d.column],) = ax.plot(xv, d.values(_values(table, d.column)), **kw)
    out = ColumnsPlot(ax, lines, xd, yds)
    if mark:
        _mark(ax, table, xv, out)
    ax.set_xlabel(_x_label(xd))
    first = yds[0]
    if len(yds) == 1:
        ax.set_ylabel(first.label)
    else:
        name = KIND_NAMES.get(first.kind, "Value")
        ax.set_ylabel(f"{name} [{pretty_unit(first.unit)}]" if first.unit else name)
    ax.grid(True, color="#e0e0e0", lw=0.8)
    if title:
        ax.set_title(title)
    if legend or (legend is None and (len(yds) > 1 or out.failures or out.dead)):
        ax.legend(fontsize="small", loc="best")
    return out


def main_columns(data: Any) -> list[str]:
    """The columns an engineer looks at first, in order.

    Linear-element lengths, moving-body angles, transmission angles, body angular velocities and
    accelerations, then driver forces and torques if present; the plotted input excluded.
    """
    table = as_table(data)
    x = default_x(table)
    order = ("value", "angle", "transmission", "omega", "epsilon", "force", "torque")
    out: list[str] = []
    elements = {e.name for e in table.plan.elements} if table.plan is not None else set()
    inputs = set(table.plan.inputs) if table.plan is not None else set()
    driven = (
        {d.body for d in table.plan.model.rotary if d.reference == table.plan.model.ground.name}
        if table.plan is not None
        else set()
    )
    for quantity in order:
        for c in table.of_quantity(quantity):
            if c == x or c in out:
                continue
            owner = table.columns[c].owner
            if quantity in ("angle", "omega", "epsilon") and owner in elements | driven:
                continue  # a cylinder's line (its length says more) or a body the input turns
            if quantity == "value" and table.plan is not None and owner not in elements | inputs:
                continue
            v = np.asarray(table.frame[c], dtype=np.float64)
            if v.size and not np.isfinite(v).any():
                continue
            if quantity == "value" and not varies(v):
                continue  # a locked element or a held input
            out.append(c)
    return out


@dataclass
class CurvesPlot:
    """The artists of [`plot_curves`][excavkin.outputs.plots.plot_curves].

    Attributes
    ----------
    fig : matplotlib.figure.Figure
    panels : list of ColumnsPlot
        One per kind of quantity, top to bottom.
    """

    fig: Figure
    panels: list[ColumnsPlot]

    @property
    def axes(self) -> list[Axes]:
        """The axes of the panels."""
        return [p.ax for p in self.panels]


def plot_curves(
    data: TableData,
    y: Sequence[str] | None = None,
    x: str | None = None,
    *,
    units: Mapping[str, str] | None = None,
    fig: Figure | None = None,
    mark: bool = True,
    title: str | None = None,
    **style: Any,
) -> CurvesPlot:
    """Plot columns of several kinds, one panel per kind, sharing the x axis.

    Parameters
    ----------
    data : KinematicResult, a result with ``to_frame()``, or pandas.DataFrame
    y : sequence of str, optional
        Columns; default `main_columns`.
    x : str, optional
        As in [`plot_columns`][excavkin.outputs.plots.plot_columns].
    units : mapping of str to str, optional
        As in [`plot_columns`][excavkin.outputs.plots.plot_columns].
    fig : matplotlib.figure.Figure, optional
        An empty figure to draw into; a new one without it.
    mark : bool
        Mark non-closure and dead positions on every panel.
    title : str, optional
        Figure title.
    **style
        matplotlib ``Line2D`` properties for every line.

    Returns
    -------
    CurvesPlot

    Raises
    ------
    TypeError
        On a keyword that is not a ``Line2D`` property.
    """
    style = check_line_style(style)
    table = as_table(data)
    cols = list(y) if y is not None else main_columns(table)
    if not cols:
        raise ValueError("y: no columns to plot")
    disp = DisplayUnits(units, table.kinds)
    groups: dict[tuple[str, str], list[str]] = {}
    for d in disp.all(cols):
        groups.setdefault((d.kind, d.unit), []).append(d.column)
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(7.5, 1.2 + 2.2 * len(groups)), layout="constrained")
    axes = fig.subplots(len(groups), 1, sharex=True, squeeze=False)[:, 0]
    panels = []
    for k, (a, group) in enumerate(zip(axes, groups.values(), strict=True)):
        p = plot_columns(
            table,
            group,
            x,
            units=units,
            ax=a,
            mark=mark,
            legend=True if len(group) > 1 else None,
            **style,
        )
        if k < len(axes) - 1:
            a.set_xlabel("")
        panels.append(p)
    if title:
        fig.suptitle(title)
    return CurvesPlot(fig, panels)
