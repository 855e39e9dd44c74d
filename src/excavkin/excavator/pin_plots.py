"""Plots of pin loads: heat maps over the working range and a chart of the largest loads.

matplotlib is imported inside the functions. Each function takes ``ax=`` or ``fig=`` (a new
figure when omitted), rejects unknown keyword arguments by signature, and returns a handle.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from excavkin.excavator.machine import Machine
from excavkin.excavator.pin_loads import CASES, LoadMaximum, PinLoads
from excavkin.excavator.plots import ExcavatorPlot
from excavkin.excavator.stability_plots import map_cells
from excavkin.outputs.machine_plot import figure_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: one colour per load case
CASE_COLOURS = {"bucket": "#1f77b4", "arm": "#ff7f0e", "lift": "#2ca02c"}

_CASE_TEXT = {
    "bucket": "bucket-cylinder tool force",
    "arm": "arm-cylinder tool force",
    "lift": "lift load",
}


def plot_pin_maps(
    machine: Machine,
    loads: PinLoads,
    *,
    pins: Sequence[str] | None = None,
    cell: float = 0.3,
    columns: int = 4,
    fig: Figure | None = None,
) -> ExcavatorPlot:
    """Heat maps of pin loads over the working range, one panel per pin.

    Each cell shows the largest load of the pin over the poses that put the load's point (the
    tool point, or the lift point) in it; all panels share one colour scale. A star marks the
    pin's largest load.

    Parameters
    ----------
    machine : Machine
    loads : PinLoads
        Over a stroke grid (`stroke_grid`).
    pins : sequence of str, optional
        Point names of the pins to show (default all).
    cell : float
        Cell size (m).
    columns : int
        Panels per row.
    fig : matplotlib Figure, optional

    Returns
    -------
    ExcavatorPlot
        ``ax`` is the first panel; ``artists["axes"]`` holds them all by pin.
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import Normalize

    names = list(loads.pins if pins is None else pins)
    unknown = [p for p in names if p not in loads.pins]
    if unknown or not names:
        raise ValueError(f"unknown pins {unknown} (pins: {', '.join(loads.pins)})")
    rows = -(-len(names) // columns)
    if fig is None:
        fig = plt.figure(figsize=(3.0 * columns + 1.2, 3.0 * rows + 0.8), layout="constrained")
    axes = fig.subplots(rows, columns, sharex=True, sharey=True, squeeze=False)
    good = loads.held & np.all(np.isfinite(loads.tool_point), axis=1)
    pts = loads.tool_point[good]
    xe, ye, ix, iy, nx, ny = map_cells(pts, cell)
    values = loads.load[good] / 1e3
    cols = [loads.pins.index(p) for p in names]
    norm = Normalize(0.0, float(np.max(values[:, cols])))
    by_pin = {}
    mesh = None
    for k, (name, j) in enumerate(zip(names, cols, strict=True)):
        ax = axes.flat[k]
        grid = np.full((ny, nx), -np.inf)
        np.maximum.at(grid, (iy, ix), values[:, j])
        grid[~np.isfinite(grid)] = np.nan
        mesh = ax.pcolormesh(xe, ye, grid, cmap="viridis", norm=norm, shading="flat")
        ax.axhline(machine.ground_line, color="saddlebrown", lw=1.0)
        ax.axvline(machine.swing_axis, color="0.5", lw=0.7, ls="-.")
        i = int(np.argmax(values[:, j]))
        ax.plot(pts[i, 0], pts[i, 1], "r*", ms=10)
        ax.set_title(f"{name}: {loads.labels[j]}\nmax {values[i, j]:.0f} kN", fontsize=8.5)
        ax.set_aspect("equal")
        ax.tick_params(labelsize=7)
        by_pin[name] = ax
    for ax in axes.flat[len(names) :]:
        ax.set_axis_off()
    for ax in axes[:, 0]:
        ax.set_ylabel("height y (m)", fontsize=8)
    for ax in axes[-1, :]:
        ax.set_xlabel("reach x (m)", fontsize=8)
    assert mesh is not None
    cb = fig.colorbar(mesh, ax=axes, shrink=0.6, aspect=30)
    cb.set_label("pin load (kN): largest per cell")
    where = "lift point" if loads.case == "lift" else "tool point"
    fig.suptitle(
        f"{machine.name}: pin loads under the {_CASE_TEXT[loads.case]} "
        f"({'with' if loads.gravity else 'without'} the front's weight), "
        f"mapped at the {where}",
        fontsize=10,
    )
    return ExcavatorPlot(fig, axes.flat[0], {"axes": by_pin, "colorbar": cb})


def plot_load_maxima(
    machine: Machine, maxima: Sequence[LoadMaximum], *, ax: Axes | None = None
) -> ExcavatorPlot:
    """Bar chart of the largest load of each pin and cylinder in each load case.

    Parameters
    ----------
    machine : Machine
    maxima : sequence of LoadMaximum
        From `load_maxima`.
    ax : matplotlib Axes, optional

    Returns
    -------
    ExcavatorPlot
    """
    fig, ax = figure_axes(ax, (8.0, 0.42 * len(maxima) + 1.6))
    cases: list[str] = [c for c in CASES if any(c in m.by_case for m in maxima)]
    height = 0.8 / len(cases)
    y = np.arange(len(maxima))
    bars = {}
    for k, case in enumerate(cases):
        v = np.array([m.by_case.get(case, np.nan) for m in maxima]) / 1e3
        v = np.where(np.isfinite(v), v, np.nan)
        off = (k - 0.5 * (len(cases) - 1)) * height
        bars[case] = ax.barh(
            y + off, v, height=height, color=CASE_COLOURS[case], label=_CASE_TEXT[case]
        )
    for i, m in enumerate(maxima):  # the largest value, at the end of its case's bar
        off = (cases.index(m.case) - 0.5 * (len(cases) - 1)) * height
        ax.text(abs(m.value) / 1e3, i + off, f" {abs(m.value) / 1e3:.0f}", va="center", fontsize=7)
    pins = sum(m.kind == "pin" for m in maxima)
    if 0 < pins < len(maxima):
        ax.axhline(pins - 0.5, color="0.3", lw=0.8)
    ax.set_yticks(
        y, [f"{m.name}: {m.label}" if m.kind == "pin" else m.label for m in maxima], fontsize=8
    )
    ax.invert_yaxis()
    ax.set_xlabel("largest load over the working range (kN)")
    ax.grid(axis="x", lw=0.5, alpha=0.5)
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title(f"{machine.name}: largest pin loads and cylinder forces", fontsize=10)
    return ExcavatorPlot(fig, ax, {"bars": bars})
