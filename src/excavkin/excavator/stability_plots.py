"""Plots of an excavator's stability: the lift chart (ISO 10567) and maps over the working range.

matplotlib is imported inside the functions. Each function takes ``ax=`` (a new figure when
omitted), rejects unknown keyword arguments by signature, and returns a handle.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.excavator.lift import LiftTable, lift_poses
from excavkin.excavator.machine import Machine
from excavkin.excavator.plots import ExcavatorPlot, draw_front
from excavkin.outputs.machine_plot import figure_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

#: colours of the limits on the limit maps
LIMIT_COLOURS = {
    "boom": "tab:blue",
    "arm": "tab:green",
    "bucket": "tab:olive",
    "tipping": "tab:red",
    "slipping": "tab:purple",
}


def _kg(v: float) -> str:
    return f"{v:,.0f}".replace(",", " ")


def plot_lift_chart(machine: Machine, table: LiftTable, *, ax: Axes | None = None) -> ExcavatorPlot:
    """A spec sheet's lift chart: rated loads (kg) at each load-point radius and height.

    Each reachable grid point shows the rated load over the front (upper) and over the side
    (lower); ``*`` marks a value the hydraulic capacity limits. The load point's reachable
    region (bucket curled) is shaded, each row's largest reach marked with its loads, and the
    front drawn at the posture of the largest reach at the ground line.

    Parameters
    ----------
    machine : Machine
    table : LiftTable
        From [`lift_table`][excavkin.excavator.lift.lift_table].
    ax : matplotlib Axes, optional

    Returns
    -------
    ExcavatorPlot
    """
    fig, ax = figure_axes(ax, (10.0, 8.0))
    g = machine.gravity
    x0, y0 = machine.swing_axis, machine.ground_line
    R, H = table.radii, table.heights
    reach = table.max_reach
    r_hi = float(np.nanmax(np.r_[reach, R])) + 0.5
    column = r_hi + 2.0  # the "at max reach" column, right-aligned there
    h_lo, h_hi = float(H.min()) - 1.0, float(H.max()) + 1.5
    # the load point's reachable region, on a fine grid
    rg = np.linspace(0.0, r_hi, 161)
    hg = np.linspace(h_lo, h_hi, 141)
    rr, hh = np.meshgrid(rg, hg)
    _, ok = lift_poses(machine, np.column_stack([x0 + rr.ravel(), y0 + hh.ravel()]))
    region = ax.contourf(
        rg, hg, ok.reshape(rr.shape).astype(float), levels=[0.5, 1.5], colors=["#dcebf7"]
    )
    ax.axhline(0.0, color="saddlebrown", lw=1.2)
    ax.axvline(0.0, color="0.5", lw=0.8, ls="-.")
    _draw_base(machine, ax)
    k0 = int(np.argmin(np.abs(H)))
    if np.isfinite(reach[k0]):
        pose = table.max_reach_lengths[k0]
        lines = draw_front(machine, pose, ax, alpha=0.2)
        for ln in lines:  # to the chart's frame (radius, height)
            ln.set_xdata(np.asarray(ln.get_xdata()) - x0)
            ln.set_ydata(np.asarray(ln.get_ydata()) - y0)
    for r in R:
        ax.axvline(r, color="0.8", lw=0.6, zorder=0)
    for h in H:
        ax.axhline(h, color="0.8", lw=0.6, zorder=0)
    texts = []
    front, side = table.rated("front") / g, table.rated("side") / g
    star_f, star_s = table.hydraulic_limited("front"), table.hydraulic_limited("side")
    for i, h in enumerate(H):
        for j, r in enumerate(R):
            if not table.reachable[i, j]:
                continue
            ax.plot(r, h, "o", color="tab:blue", ms=3, zorder=4)
            txt = (
                f"{_kg(front[i, j])}{'*' if star_f[i, j] else ''}\n"
                f"{_kg(side[i, j])}{'*' if star_s[i, j] else ''}"
            )
            texts.append(
                ax.text(r + 0.08, h + 0.08, txt, fontsize=7.5, va="bottom", family="monospace")
            )
        if np.isfinite(reach[i]):
            cap = table.at_max_reach
            f_, s_ = cap.rated["front"][i] / g, cap.rated["side"][i] / g
            sf = "*" if cap.hydraulic_limited["front"][i] else ""
            ss = "*" if cap.hydraulic_limited["side"][i] else ""
            ax.plot(reach[i], h, "D", color="tab:red", ms=4, zorder=4)
            texts.append(
                ax.text(
                    column,
                    h + 0.08,
                    f"{reach[i]:.2f} m\n{_kg(f_)}{sf}\n{_kg(s_)}{ss}",
                    fontsize=7,
                    va="bottom",
                    ha="right",
                    family="monospace",
                    color="tab:red",
                )
            )
    ax.text(column, h_hi - 0.1, "at max reach", ha="right", va="top", fontsize=8, color="tab:red")
    left = -3.2 if machine.base is not None else -1.0
    ax.set_xlim(left, column + 0.1)
    ax.set_ylim(h_lo, h_hi)
    ax.set_aspect("equal")
    ax.set_xlabel("load radius from the swing axis (m)")
    ax.set_ylabel("load-point height above the ground line (m)")
    ax.set_title(f"{machine.name}: lift capacity (ISO 10567), load point {table.point}")
    ax.text(
        0.01,
        0.01,
        "kg, upper: over the front, lower: over the side\n"
        "* limited by hydraulic capacity (87 %), else by tipping (75 %)\n"
        "red: at the largest reach of each height; bucket curled",
        transform=ax.transAxes,
        fontsize=7.5,
        va="bottom",
        bbox={"boxstyle": "round", "fc": "white", "ec": "0.7", "alpha": 0.9},
    )
    return ExcavatorPlot(fig, ax, {"region": region, "texts": texts})


def _draw_base(machine: Machine, ax: Axes) -> None:
    """The support's contact elements over the front (swing 0), seen from the side, and the
    counterweight, schematically, in the chart's frame."""
    from matplotlib.patches import Rectangle

    base = machine.base
    if base is None:
        return
    draw_support_side(machine, ax)
    x0 = machine.swing_axis
    cw = base.counterweight
    ax.add_patch(
        Rectangle((cw.x - x0 - 0.45, 1.0), 0.9, 1.3, fc="0.75", ec="0.5", lw=0.8, zorder=1)
    )


def draw_support_side(machine: Machine, ax: Axes) -> list[Any]:
    """The support's contact elements over the front (swing 0), seen from the side, in a lift
    chart's frame (radius from the swing axis, height above the ground line).

    Tracks are drawn as their length on the ground (one box for tracks side by side), tyres
    as circles and an oscillating axle's pivot as a triangle on the ground, a blade as its
    edge and outrigger pads as squares, all at the abscissae of the support's contact points
    (`Support.contact_points`).

    Parameters
    ----------
    machine : Machine
        With a ``[base]``.
    ax : matplotlib Axes

    Returns
    -------
    list
        The artists drawn, one per contact element (a track hidden behind another's box
        draws none).
    """
    from excavkin.excavator.stability import need_base

    support = need_base(machine).support
    pts, owners = support.contact_points(machine.swing_axis, 0.0)
    artists: list[Any] = []
    spans: set[tuple[float, float]] = set()
    for e, ct in enumerate(support.contacts):
        u = pts[[k for k, (o, _) in enumerate(owners) if o == e], 0]
        artist = _side_artist(ax, ct.kind, u, spans)
        if artist is not None:
            artists.append(artist)
    return artists


def _side_artist(ax: Axes, kind: str, u: F, spans: set[tuple[float, float]]) -> Any:
    from matplotlib.patches import Rectangle

    if kind == "track":
        span = (float(u.min()), float(u.max()))
        if span in spans:
            return None
        spans.add(span)
        return ax.add_patch(
            Rectangle((span[0], 0.0), span[1] - span[0], 0.9, fc="0.85", ec="0.5", lw=0.8, zorder=1)
        )
    if kind == "blade":
        return ax.plot([u[0], u[0]], [0.0, 0.6], color="0.35", lw=3.0, zorder=2)[0]
    marker, size = {"tyres": ("o", 14), "pivot": ("^", 9), "outriggers": ("s", 7)}.get(
        kind, ("x", 7)
    )
    return ax.plot(u, 0.0 * u, marker, ms=size, mfc="0.75", mec="0.35", ls="", zorder=2)[0]


def plot_support(machine: Machine, *, swing: float = 0.0, ax: Axes | None = None) -> ExcavatorPlot:
    """The support in plan about the swing axis with the upper structure swung ``swing``:
    each contact element as the model has it (`Support.contacts`: tracks' footprints, tyres,
    an oscillating axle's pivot, a blade's edge, outrigger pads), the support polygon and
    its tipping lines named as the model names them, and the front's direction.

    Parameters
    ----------
    machine : Machine
        With a ``[base]``.
    swing : float, default 0
        The upper structure's swing (rad; 0 over the front of the undercarriage).
    ax : matplotlib Axes, optional

    Returns
    -------
    ExcavatorPlot
        Its ``artists``: ``"contacts"`` (contact name → artist), ``"points"`` (every contact
        point, `Support.contact_points`' order), ``"polygon"`` (the support polygon's patch),
        ``"lines"`` (tipping-line name → its label).
    """
    from matplotlib.patches import Polygon

    from excavkin.excavator.stability import need_base

    fig, ax = figure_axes(ax, (7.0, 6.5))
    support = need_base(machine).support
    axis = machine.swing_axis
    pts, owners = support.contact_points(axis, swing)
    contacts: dict[str, Any] = {}
    for e, ct in enumerate(support.contacts):
        p = pts[[k for k, (o, _) in enumerate(owners) if o == e]]
        contacts[ct.name] = _plan_artist(ax, ct.kind, p)
    (points,) = ax.plot(pts[:, 0], pts[:, 1], ".", color="k", ms=3, zorder=4)
    vertices, _ = support.support_polygon(axis, swing)
    polygon = ax.add_patch(
        Polygon(vertices, closed=True, fill=False, ec="tab:red", lw=1.2, ls="--", zorder=3)
    )
    labels = {}
    for ln in support.tipping_lines(axis, swing):
        mid = ln.ends.mean(axis=0) + 0.25 * np.asarray(ln.normal)
        labels[ln.name] = ax.text(
            mid[0], mid[1], ln.name, color="tab:red", fontsize=8, ha="center", va="center"
        )
    reach = float(np.abs(pts).max()) + 0.8
    head = 0.7 * reach * np.array([np.cos(swing), np.sin(swing)])
    ax.annotate(
        "", xy=tuple(head), xytext=(0.0, 0.0), arrowprops={"arrowstyle": "->", "color": "0.4"}
    )
    tx, ty = 0.5 * head + 0.15 * np.array([-np.sin(swing), np.cos(swing)])
    ax.text(tx, ty, "the front", color="0.4", fontsize=8, ha="center", va="center")
    ax.plot(0.0, 0.0, "+", color="0.4", ms=10)
    ax.set_xlim(-reach, reach)
    ax.set_ylim(-reach, reach)
    ax.set_aspect("equal")
    ax.set_xlabel("along the undercarriage from the swing axis u (m)")
    ax.set_ylabel("to the left v (m)")
    ax.set_title(f"{machine.name}: support and tipping lines, swung {np.degrees(swing):.0f}°")
    return ExcavatorPlot(
        fig, ax, {"contacts": contacts, "points": points, "polygon": polygon, "lines": labels}
    )


def _plan_artist(ax: Axes, kind: str, p: F) -> Any:
    from matplotlib.patches import Polygon

    if kind == "track":
        hull = p[[0, 2, 3, 1]]  # rear-right, front-right, front-left, rear-left
        return ax.add_patch(Polygon(hull, closed=True, fc="0.85", ec="0.5", lw=0.8, zorder=1))
    if kind == "blade":
        return ax.plot(p[:, 0], p[:, 1], color="0.35", lw=4.0, zorder=2)[0]
    marker, size = {"tyres": ("o", 14), "pivot": ("^", 9), "outriggers": ("s", 8)}.get(
        kind, ("x", 7)
    )
    return ax.plot(p[:, 0], p[:, 1], marker, ms=size, mfc="0.75", mec="0.35", ls="", zorder=2)[0]


def map_cells(points: F, cell: float) -> tuple[F, F, Any, Any, int, int]:
    """Cell edges and each point's cell index for a map of ``cell``-sized squares.

    Parameters
    ----------
    points : ndarray, shape (n, 2)
        The mapped points.
    cell : float
        The square's side.

    Returns
    -------
    (x_edges, y_edges, ix, iy, nx, ny)
        Edges, shape (nx + 1,) and (ny + 1,); each point's column and row, shape (n,); the
        number of columns and rows.
    """
    x0, y0 = points.min(axis=0) - cell
    nx = int(np.ceil((points[:, 0].max() - x0) / cell)) + 2
    ny = int(np.ceil((points[:, 1].max() - y0) / cell)) + 2
    ix = ((points[:, 0] - x0) / cell).astype(int)
    iy = ((points[:, 1] - y0) / cell).astype(int)
    return x0 + cell * np.arange(nx + 1), y0 + cell * np.arange(ny + 1), ix, iy, nx, ny


def plot_value_map(
    machine: Machine,
    points: F,
    values: F,
    *,
    label: str,
    title: str,
    cell: float = 0.25,
    log: bool = False,
    ax: Axes | None = None,
) -> ExcavatorPlot:
    """Heat map of a value over the working range: the least value per cell.

    Parameters
    ----------
    machine : Machine
    points : ndarray, shape (n, 2)
        Where each sample lies (m), e.g. the bucket pin over a stroke sweep.
    values : ndarray, shape (n,)
        Non-finite values are left out.
    label, title : str
    cell : float
        Cell size (m).
    log : bool
        A logarithmic colour scale (values must be positive): tipping loads grow without bound
        towards the tipping line.
    ax : matplotlib Axes, optional

    Returns
    -------
    ExcavatorPlot
    """
    from matplotlib.colors import LogNorm

    fig, ax = figure_axes(ax, (7.5, 6.5))
    good = np.isfinite(values) & np.all(np.isfinite(points), axis=1)
    if log:
        good &= values > 0.0
    pts, v = points[good], values[good]
    xe, ye, ix, iy, nx, ny = map_cells(pts, cell)
    grid = np.full((ny, nx), np.inf)
    np.minimum.at(grid, (iy, ix), v)
    grid[~np.isfinite(grid)] = np.nan
    norm = LogNorm() if log else None
    mesh = ax.pcolormesh(xe, ye, grid, cmap="viridis", shading="flat", norm=norm)
    cb = fig.colorbar(mesh, ax=ax, shrink=0.8)
    cb.set_label(label)
    ax.axhline(machine.ground_line, color="saddlebrown", lw=1.2)
    ax.axvline(machine.swing_axis, color="0.5", lw=0.8, ls="-.")
    k = int(np.argmin(v))
    ax.plot(pts[k, 0], pts[k, 1], "r*", ms=12, label=f"least {v[k]:.3g}")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(title)
    ax.set_aspect("equal")
    ax.set_xlabel("reach from swing axis x (m)")
    ax.set_ylabel("height above ground line y (m)")
    return ExcavatorPlot(fig, ax, {"mesh": mesh, "colorbar": cb})


def plot_limit_map(
    machine: Machine,
    points: F,
    force: F,
    limiting: np.ndarray,
    *,
    title: str,
    cell: float = 0.25,
    ax: Axes | None = None,
) -> ExcavatorPlot:
    """Which limit binds a capped tool force over the working range.

    Each cell shows the limit of its largest force (the sample a force map shows there):
    a cylinder (hydraulic limit), tipping or slipping.

    Parameters
    ----------
    machine : Machine
    points : ndarray, shape (n, 2)
        The tool point of each sample (m).
    force : ndarray, shape (n,)
        The capped force (N).
    limiting : ndarray of str, shape (n,)
        Its limit (`CappedToolForces`).
    title : str
    cell : float
    ax : matplotlib Axes, optional

    Returns
    -------
    ExcavatorPlot
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    fig, ax = figure_axes(ax, (7.5, 6.5))
    good = np.isfinite(force) & np.all(np.isfinite(points), axis=1)
    pts, f = points[good], force[good]
    kinds = list(LIMIT_COLOURS)
    kind = np.array([kinds.index(str(s).split(" ")[0]) for s in limiting[good]])
    xe, ye, ix, iy, nx, ny = map_cells(pts, cell)
    flat = iy * nx + ix
    order = np.lexsort((f, flat))  # per cell, the largest force last
    last = np.r_[flat[order][1:] != flat[order][:-1], True]
    grid = np.full(ny * nx, np.nan)
    grid[flat[order][last]] = kind[order][last]
    cmap = ListedColormap([LIMIT_COLOURS[k] for k in kinds])
    mesh = ax.pcolormesh(
        xe, ye, grid.reshape(ny, nx), cmap=cmap, vmin=-0.5, vmax=len(kinds) - 0.5, shading="flat"
    )
    present = sorted(set(kind.tolist()))
    share = {k: float(np.mean(kind == k)) for k in present}
    ax.legend(
        handles=[
            Patch(color=LIMIT_COLOURS[kinds[k]], label=f"{kinds[k]} ({100 * share[k]:.0f} %)")
            for k in present
        ],
        loc="upper right",
        fontsize=8,
        title="limited by (share of poses)",
        title_fontsize=8,
    )
    ax.axhline(machine.ground_line, color="saddlebrown", lw=1.2)
    ax.set_title(title)
    ax.set_aspect("equal")
    ax.set_xlabel("reach from swing axis x (m)")
    ax.set_ylabel("height above ground line y (m)")
    return ExcavatorPlot(fig, ax, {"mesh": mesh, "share": {kinds[k]: share[k] for k in present}})
