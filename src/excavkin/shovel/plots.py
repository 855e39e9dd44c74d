"""Plots of a rope shovel's analyses: each result's ``plot()`` draws here.

matplotlib is imported inside the functions. Each function takes ``ax=`` (a new figure when
omitted), rejects unknown keyword arguments by signature, and returns a `MachinePlot`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.outputs.machine_plot import MachinePlot, draw_pose, figure_axes
from excavkin.shovel.machine import Shovel

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from excavkin.shovel.dig import Dig
    from excavkin.shovel.envelope import Envelope
    from excavkin.shovel.loads import BoomLoads

GROUND_COLOR = "saddlebrown"
HOIST_COLOR, CROWD_COLOR, ROPE_COLOR = "tab:blue", "tab:green", "0.45"


def draw_front(machine: Shovel, xy: F, ax: Axes, **style: Any) -> list[Any]:
    """Draw the front at one pose: its bodies, the hoist rope (drum → sheave → bail) and the
    suspension ropes as thin lines.

    Parameters
    ----------
    machine : Shovel
    xy : ndarray, shape (n_points, 2)
        The points at the pose, in the plan's order.
    ax : matplotlib Axes
    **style
        The bodies' line style.

    Returns
    -------
    list
        The lines drawn.
    """
    plan = machine.mechanism.plan
    out = draw_pose(machine.mechanism, xy, ax, (), (), **style)
    for rope in machine.mechanism.model.ropes:
        idx = [plan.points.index(p) for p in rope.path]
        out += ax.plot(xy[idx, 0], xy[idx, 1], color=ROPE_COLOR, lw=0.9, ls="-", zorder=2)
    return out


def _ground(ax: Axes, x0: float, x1: float) -> None:
    ax.axhline(0.0, color=GROUND_COLOR, lw=1.2, zorder=1)
    ax.fill_between([x0, x1], [-1.5, -1.5], [0.0, 0.0], color=GROUND_COLOR, alpha=0.12, lw=0)


def _pose(machine: Shovel, length: float, extension: float) -> F:
    res = machine.solve(np.array([length]), np.array([extension]))
    return np.asarray(res.positions[0])


def plot_envelope(machine: Shovel, env: Envelope, *, ax: Axes | None = None) -> MachinePlot:
    """The working-range diagram (see
    [`Envelope.plot`][excavkin.shovel.envelope.Envelope.plot]).

    Parameters
    ----------
    machine : Shovel
    env : Envelope
    ax : matplotlib Axes, optional

    Returns
    -------
    MachinePlot
    """
    fig, ax = figure_axes(ax, (8.0, 6.5))
    teeth = env.grid_teeth
    artists: dict[str, Any] = {}
    artists["reach"] = ax.scatter(
        teeth[..., 0].ravel(), teeth[..., 1].ravel(), s=2, color="tab:orange", alpha=0.35,
        label="tooth tip over the hoist × crowd box",
    )  # fmt: skip
    for k, edge in enumerate((teeth[0], teeth[-1], teeth[:, 0], teeth[:, -1])):
        ax.plot(edge[:, 0], edge[:, 1], color="tab:orange", lw=1.2,
                label="box edges (hoist or crowd at a limit)" if k == 0 else None)  # fmt: skip
    cut = env.figure("cutting height")
    artists["front"] = draw_front(machine, _pose(machine, cut.length, cut.extension), ax)
    dump = env.figure("dump height")
    draw_front(machine, _pose(machine, dump.length, dump.extension), ax, alpha=0.35)
    floor = env.figure("radius at floor level")
    if np.isfinite(floor.value):
        draw_front(machine, _pose(machine, floor.length, floor.extension), ax, alpha=0.35)
    marks = {
        "cutting height": ("^", "tab:red"),
        "cutting radius": (">", "tab:purple"),
        "dump height": ("v", "tab:blue"),
        "radius at floor level": ("o", "tab:brown"),
    }
    for name, (marker, color) in marks.items():
        f = env.figure(name)
        ax.plot([f.x], [f.y], marker=marker, color=color, ms=8, ls="none",
                label=f"{name} {f.value:.2f} m")  # fmt: skip
    d = env.figure("dump radius")
    ax.plot([d.x, d.x], [0.0, d.y], color="tab:blue", lw=0.8, ls="--",
            label=f"dump radius {d.value:.2f} m")  # fmt: skip
    xs = np.nan_to_num(teeth[..., 0], nan=0.0)
    _ground(ax, -6.0, float(xs.max()) + 2.0)
    ax.set_aspect("equal")
    ax.set_xlabel("radius from the slew axis (m)")
    ax.set_ylabel("height above the ground (m)")
    ax.set_title(f"{machine.name}: digging envelope", fontsize=10)
    ax.legend(loc="lower left", fontsize=7)
    ax.grid(alpha=0.3)
    return MachinePlot(fig, ax, artists)


def plot_dig(machine: Shovel, dig: Dig, *, ax: Axes | None = None) -> MachinePlot:
    """The dig: bail pull and crowd force needed against the motors' limits, and the margin,
    over the tooth tip's height (see [`Dig.plot`][excavkin.shovel.dig.Dig.plot]).

    Parameters
    ----------
    machine : Shovel
    dig : Dig
    ax : matplotlib Axes, optional

    Returns
    -------
    MachinePlot
    """
    fig, ax = figure_axes(ax, (8.0, 5.0))
    h = dig.teeth[:, 1]
    artists: dict[str, Any] = {}
    ok = dig.ok
    artists["bail"] = ax.plot(h, dig.bail_pull / 1e3, color=HOIST_COLOR, label="bail pull needed")
    artists["crowd"] = ax.plot(h, dig.crowd_force / 1e3, color=CROWD_COLOR,
                               label="crowd force needed")  # fmt: skip
    ax.axhline(machine.hoist.pull / 1e3, color=HOIST_COLOR, ls="--", lw=0.9,
               label=f"hoist limit {machine.hoist.pull / 1e3:.0f} kN")  # fmt: skip
    ax.axhline(machine.crowd.force / 1e3, color=CROWD_COLOR, ls="--", lw=0.9,
               label=f"crowd limit ±{machine.crowd.force / 1e3:.0f} kN")  # fmt: skip
    ax.axhline(-machine.crowd.force / 1e3, color=CROWD_COLOR, ls="--", lw=0.9)
    if (~ok).any():
        ax.plot(h[~ok], dig.bail_pull[~ok] / 1e3, "x", color="tab:red", label="not ok (status)")
    ax.set_xlabel("tooth tip height (m)")
    ax.set_ylabel("force (kN)")
    ax2 = ax.twinx()
    artists["margin"] = ax2.plot(h, dig.margin, color="tab:red", lw=1.0,
                                 label="margin (× digging resistance)")  # fmt: skip
    ax2.axhline(1.0, color="tab:red", lw=0.6, ls=":")
    ax2.set_ylabel("digging-resistance margin (×)", color="tab:red")
    lines, labels = ax.get_legend_handles_labels()
    l2, lb2 = ax2.get_legend_handles_labels()
    ax.legend(lines + l2, labels + lb2, loc="upper left", fontsize=7)
    ax.set_title(f"{machine.name}: along a dig ({dig.soil})", fontsize=10)
    ax.grid(alpha=0.3)
    return MachinePlot(fig, ax, artists)


def plot_boom_loads(loads: BoomLoads, *, ax: Axes | None = None) -> MachinePlot:
    """The boom's loads over the tooth tip's height (see
    [`BoomLoads.plot`][excavkin.shovel.loads.BoomLoads.plot]).

    Parameters
    ----------
    loads : BoomLoads
    ax : matplotlib Axes, optional

    Returns
    -------
    MachinePlot
    """
    fig, ax = figure_axes(ax, (8.0, 5.0))
    h = loads.teeth[:, 1]
    artists: dict[str, Any] = {}
    for name, mag, color in (
        ("suspension ropes", loads.suspension, "tab:blue"),
        ("boom-foot pin", np.hypot(*loads.boom_foot.T), "tab:red"),
        ("shipper shaft", np.hypot(*loads.shipper_shaft.T), "tab:green"),
        ("boom-point sheave", np.hypot(*loads.sheave.T), "tab:purple"),
    ):
        artists[name] = ax.plot(h, mag / 1e3, color=color, label=name)
    bad = ~loads.ok
    if bad.any():
        ax.plot(h[bad], loads.suspension[bad] / 1e3, "x", color="tab:red", label="not ok (status)")
    ax.set_xlabel("tooth tip height (m)")
    ax.set_ylabel("force on the boom (kN)")
    ax.set_title(f"{loads.machine}: boom loads along the dig", fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return MachinePlot(fig, ax, artists)
