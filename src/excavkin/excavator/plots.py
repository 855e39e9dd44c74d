"""Plots of an excavator front: the working-range diagram and tool-force maps.

matplotlib is imported inside the functions. Each function takes ``ax=`` (a new figure when
omitted), rejects unknown keyword arguments by signature, and returns a handle.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.excavator.forces import ToolForces
from excavkin.excavator.machine import Machine, forward
from excavkin.excavator.ranges import WorkingRanges
from excavkin.outputs.machine_plot import MachinePlot, draw_pose, figure_axes, legend_box

if TYPE_CHECKING:
    from matplotlib.axes import Axes


#: what an excavator plot function drew
ExcavatorPlot = MachinePlot


def draw_front(machine: Machine, lengths: np.ndarray, ax: Axes, **style: Any) -> list[Any]:
    """Draw the bodies and cylinders at one set of lengths (shape (3,)) as lines."""
    pose = forward(machine, np.asarray(lengths, dtype=np.float64).reshape(1, 3))
    ends = machine.pins.cyl_ends
    colors = ["tab:orange"] * len(ends)
    return draw_pose(machine.mechanism, pose.result.positions[0], ax, ends, colors, **style)


def plot_working_range(
    machine: Machine,
    ranges: WorkingRanges,
    *,
    ax: Axes | None = None,
    show_front: bool = True,
) -> ExcavatorPlot:
    """Side-view working-range diagram: the tip envelope with the standard figures marked.

    Parameters
    ----------
    machine : Machine
    ranges : WorkingRanges
        From [`working_ranges`][excavkin.excavator.ranges.working_ranges].
    ax : matplotlib Axes, optional
    show_front : bool
        Also draw the front at the maximum-reach pose, faintly.

    Returns
    -------
    ExcavatorPlot
    """
    fig, ax = figure_axes(ax, (8.5, 8.0))
    env = np.vstack([ranges.envelope, ranges.envelope[:1]])
    art: dict[str, Any] = {}
    art["envelope"] = ax.fill(env[:, 0], env[:, 1], color="tab:blue", alpha=0.12, lw=0)
    ax.plot(env[:, 0], env[:, 1], color="tab:blue", lw=1.5, label="tooth-tip envelope")
    g0, x0 = machine.ground_line, machine.swing_axis
    xmin, xmax = float(env[:, 0].min()), float(env[:, 0].max())
    ax.axhline(g0, color="saddlebrown", lw=1.2)
    ax.axvline(x0, color="0.5", lw=0.8, ls="-.")
    ax.text(x0, g0 - 0.15, " swing axis", fontsize=8, va="top", color="0.4")
    if show_front:
        draw_front(machine, ranges.figure("max_digging_reach").lengths, ax, alpha=0.35)
    marks = [
        ("max_digging_reach", "A", "h"),
        ("max_reach_ground", "B", "h"),
        ("max_digging_depth", "C", "v"),
        ("max_vertical_wall_depth", "D", "v"),
        ("max_cutting_height", "E", "v"),
        ("max_dumping_height", "F", "v"),
        ("min_dumping_height", "G", "v"),
        ("level_bottom_depth", "H", "v"),
    ]
    legend = []
    right = xmax + 0.4
    known = {f.key for f in ranges.figures}
    for n, (key, tag, kind) in enumerate(marks):
        if key not in known:  # AF of a bucket without teeth or floor point
            continue
        f = ranges.figure(key)
        tx, ty = float(f.tip[0]), float(f.tip[1])
        ax.plot(tx, ty, "o", color="tab:red", ms=4, zorder=5)
        if key == "max_vertical_wall_depth":  # the wall the vertical teeth shave
            ax.plot([tx, tx], [g0, ty], color="saddlebrown", lw=0.9, ls="--")
        if kind == "h":
            ax.annotate(
                "", (tx, ty), (x0, ty), arrowprops={"arrowstyle": "<->", "color": "0.3", "lw": 0.8}
            )
            ax.text(0.5 * (x0 + tx), ty + 0.1, tag, ha="center", fontsize=9, weight="bold")
        else:
            xa = right + 0.35 * (n - 2)
            ax.plot([tx, xa], [ty, ty], color="0.6", lw=0.5, ls=":")
            ax.annotate(
                "", (xa, ty), (xa, g0), arrowprops={"arrowstyle": "<->", "color": "0.3", "lw": 0.8}
            )
            ax.text(xa + 0.05, 0.5 * (g0 + ty), tag, fontsize=9, weight="bold", va="center")
        code = f" ({f.code})" if f.code else ""
        legend.append(f"{tag}  {f.label}{code}: {f.value:.2f} m")
    lb = ranges.extra["level_bottom"]
    ax.plot(lb[:, 0], lb[:, 1], color="tab:green", lw=2.5, zorder=4)
    legend_box(ax, "\n".join(legend), fontsize=7.5, box={"ec": "0.7", "alpha": 0.9}, ha="left")
    ax.set_xlim(min(xmin, x0) - 0.8, right + 0.35 * len(marks) + 0.3)
    ymax = float(env[:, 1].max())
    ax.set_ylim(float(env[:, 1].min()) - 0.5, ymax + 0.35 * (ymax - g0))
    ax.set_aspect("equal")
    ax.grid(True, lw=0.3, alpha=0.6)
    ax.set_xlabel("reach from swing axis x (m)")
    ax.set_ylabel("height above ground line y (m)")
    ax.set_title(f"{machine.name}: working range")
    art["legend"] = legend
    return ExcavatorPlot(fig, ax, art)


def plot_force_map(
    machine: Machine,
    forces: ToolForces,
    *,
    ranges: WorkingRanges | None = None,
    cell: float = 0.25,
    ax: Axes | None = None,
) -> ExcavatorPlot:
    """Heat map of a tool force over the working range (largest value per cell).

    Parameters
    ----------
    machine : Machine
    forces : ToolForces
        Over a dense sweep (`sweep`).
    ranges : WorkingRanges, optional
        Overlays the envelope.
    cell : float
        Cell size (m).
    ax : matplotlib Axes, optional

    Returns
    -------
    ExcavatorPlot
    """
    fig, ax = figure_axes(ax, (7.5, 6.5))
    pts = forces.pose.lip if forces.at == "lip" else forces.pose.tip
    f = forces.force
    good = np.isfinite(f) & np.all(np.isfinite(pts), axis=1)
    pts, f = pts[good], f[good] / 1e3
    x0, y0 = pts.min(axis=0) - cell
    nx = int(np.ceil((pts[:, 0].max() - x0) / cell)) + 2
    ny = int(np.ceil((pts[:, 1].max() - y0) / cell)) + 2
    ix = ((pts[:, 0] - x0) / cell).astype(int)
    iy = ((pts[:, 1] - y0) / cell).astype(int)
    grid = np.full((ny, nx), -np.inf)
    np.maximum.at(grid, (iy, ix), f)
    grid[~np.isfinite(grid)] = np.nan
    mesh = ax.pcolormesh(
        x0 + cell * np.arange(nx + 1),
        y0 + cell * np.arange(ny + 1),
        grid,
        cmap="viridis",
        shading="flat",
    )
    cb = fig.colorbar(mesh, ax=ax, shrink=0.8)
    cb.set_label("tool force (kN)")
    if ranges is not None:
        env = np.vstack([ranges.envelope, ranges.envelope[:1]])
        ax.plot(env[:, 0], env[:, 1], color="k", lw=0.8)
    ax.axhline(machine.ground_line, color="saddlebrown", lw=1.2)
    k = int(np.nanargmax(f))
    ax.plot(pts[k, 0], pts[k, 1], "r*", ms=12, label=f"max {f[k]:.0f} kN")
    ax.legend(loc="upper right", fontsize=8)
    std = "ISO 6015" if forces.at == "lip" else "SAE J1179"
    ax.set_title(
        f"{forces.working} cylinder tool force ({std}, "
        f"{'with' if forces.gravity else 'without'} gravity)"
    )
    ax.set_aspect("equal")
    ax.set_xlabel("reach from swing axis x (m)")
    ax.set_ylabel("height above ground line y (m)")
    return ExcavatorPlot(fig, ax, {"mesh": mesh, "colorbar": cb})
