"""Plots of a wheel loader's analyses: each result's ``plot()`` draws here.

matplotlib is imported inside the functions. Each function takes ``ax=`` (a new figure when
omitted), rejects unknown keyword arguments by signature, and returns a `LoaderPlot`. Every
title names the standard the figure follows; every limit drawn is named.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.loader.machine import Loader
from excavkin.outputs.machine_plot import MachinePlot, draw_pose, figure_axes, legend_box

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from excavkin.loader.breakout import Breakout
    from excavkin.loader.capacity import Capacity
    from excavkin.loader.cycle import Cycle
    from excavkin.loader.dimensions import Dimensions
    from excavkin.loader.parallel_lift import ParallelLift
    from excavkin.loader.pins import LoaderPins
    from excavkin.loader.tipping import TippingLoad

#: colours of the load cases and limits, the same in every figure
CASE_COLORS = {"breakout": "tab:red", "rated load": "tab:blue", "tipping": "tab:purple"}
LIFT_COLOR, TILT_COLOR = "tab:blue", "tab:green"
GROUND_COLOR = "saddlebrown"


#: what a loader plot function drew (`figure`, `ax`, `artists`)
LoaderPlot = MachinePlot


def draw_linkage(machine: Loader, lengths: Any, ax: Axes, **style: Any) -> list[Any]:
    """Draw the loader's bodies and cylinders at one pose as lines.

    Parameters
    ----------
    machine : Loader
    lengths : array_like, shape (2,)
        Lift and tilt cylinder lengths (m).
    ax : matplotlib Axes
    **style
        Line properties of the bodies (``alpha``, ``color``, ``lw``); the cylinders take
        ``alpha`` alone.

    Returns
    -------
    list
        The lines drawn; none where the pose does not assemble.
    """
    res = machine.solve(np.asarray(lengths, dtype=np.float64).reshape(1, 2))
    if not bool(res.status.ok[0]):
        return []
    ends = machine.pins.cyl_ends
    return draw_pose(
        machine.mechanism, res.positions[0], ax, ends, (LIFT_COLOR, TILT_COLOR),
        cylinder_alpha=style.get("alpha", 1.0), **style,
    )  # fmt: skip


def draw_chassis(machine: Loader, ax: Axes) -> list[Any]:
    """Draw the ground line and both tyres (side view).

    Parameters
    ----------
    machine : Loader
    ax : matplotlib Axes

    Returns
    -------
    list
        The artists drawn.
    """
    from matplotlib.patches import Circle

    ch = machine.chassis
    yg = ch.ground_line
    out: list[Any] = [ax.axhline(yg, color=GROUND_COLOR, lw=1.2, zorder=1)]
    for x in (ch.front_axle[0], ch.rear_axle):
        circle = Circle((x, ch.front_axle[1]), ch.tyre_radius, fill=False, color="0.45", lw=1.2)
        out.append(ax.add_patch(circle))
    out += ax.plot(
        [ch.rear_axle, ch.front_axle[0]], [ch.front_axle[1]] * 2, color="0.6", lw=1.0, ls="--"
    )
    return out


def plot_dimensions(machine: Loader, dims: Dimensions, *, ax: Axes | None = None) -> LoaderPlot:
    """Side view of the SAE J732 / ISO 7131 dimensions at the poses they are taken at.

    Parameters
    ----------
    machine : Loader
        The machine ``dims`` is of.
    dims : Dimensions
        From [`dimensions`][excavkin.loader.dimensions.dimensions].
    ax : matplotlib Axes, optional
        Where to draw; a new figure when omitted.

    Returns
    -------
    LoaderPlot
    """
    fig, ax = figure_axes(ax, (10.0, 5.6))
    art: dict[str, Any] = {"chassis": draw_chassis(machine, ax)}
    by = {f.name: f for f in dims.figures}
    yg = machine.ground_line
    poses = (
        ("hinge-pin height at full lift", 0.25),
        ("digging depth", 0.45),
        ("dump clearance at 45 deg", 1.0),
    )
    for name, alpha in poses:
        f = by[name]
        if np.all(np.isfinite(f.lengths)):
            art[name] = draw_linkage(machine, f.lengths, ax, alpha=alpha)
    front = machine.chassis.front_most
    hinge = by["hinge-pin height at full lift"]
    dump = by["dump clearance at 45 deg"]
    reach = by["dump reach at 45 deg"]
    digging = by["digging depth"]

    def vertical(x: float, y0: float, y1: float, text: str, color: str, ha: str) -> None:
        ax.annotate(
            "",
            (x, y1),
            (x, y0),
            arrowprops={"arrowstyle": "<->", "color": color, "lw": 1.2},
        )
        ax.text(
            x,
            0.5 * (y0 + y1),
            f" {text} " if ha == "left" else f"{text} ",
            color=color,
            fontsize=9,
            va="center",
            ha=ha,
            bbox={"boxstyle": "round,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.85},
        )

    res = machine.solve(np.vstack([hinge.lengths, dump.lengths]))
    pos = res.positions
    ib, ie = machine.index(machine.pins.hinge), machine.index(machine.linkage.edge)
    if math.isfinite(hinge.value):
        x = float(pos[0, ib, 0]) + 0.35
        vertical(
            x, yg, yg + hinge.value, f"hinge pin {hinge.value * 1e3:.0f} mm", "tab:blue", "right"
        )
    if math.isfinite(dump.value):
        xe = float(pos[1, ie, 0])
        vertical(
            xe, yg, yg + dump.value, f"dump clearance {dump.value * 1e3:.0f} mm", "tab:red", "left"
        )
    if math.isfinite(reach.value):
        ye = yg + dump.value - 0.25
        ax.annotate(
            "",
            (front + reach.value, ye),
            (front, ye),
            arrowprops={"arrowstyle": "<->", "color": "tab:green", "lw": 1.2},
        )
        ax.text(
            front + 0.5 * reach.value,
            ye - 0.08,
            f"dump reach {reach.value * 1e3:.0f} mm",
            color="tab:green",
            fontsize=9,
            ha="center",
            va="top",
        )
    ax.axvline(front, color="0.6", lw=0.8, ls=":")
    lines = [
        f"{f.name}: {_shown(f.value, f.unit)}"
        for f in dims.figures
        if f.unit == "rad" or f.name == "digging depth"
    ]
    legend_box(ax, "\n".join(lines), fontsize=8, box={"ec": "0.8"})
    if math.isfinite(digging.value):
        art["depth"] = ax.axhline(yg - digging.value, color="0.5", lw=0.8, ls="--")
    ax.set_aspect("equal")
    ch = machine.chassis
    ax.set_xlim(ch.rear_axle - ch.tyre_radius - 0.3, ax.get_xlim()[1] + 1.6)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    _title(ax, dims.machine, "dimensions (SAE J732 / ISO 7131)")
    ax.grid(True, alpha=0.3)
    return LoaderPlot(fig, ax, art)


def _title(ax: Axes, machine: str, what: str) -> None:
    ax.set_title(f"{machine}\n{what}", fontsize=11)


def _shown(value: float, unit: str) -> str:
    return f"{math.degrees(value):.1f}°" if unit == "rad" else f"{value * 1e3:.0f} mm"


def _bar_label(ax: Axes, x: float, y: float, text: str, **kw: Any) -> None:
    ax.text(x, y, f" {text}", va="center", fontsize=8, **kw)


def plot_breakout(bo: Breakout, *, ax: Axes | None = None) -> LoaderPlot:
    """The breakout force of each circuit with every limit that caps it (SAE J732).

    Parameters
    ----------
    bo : Breakout
        From [`breakout`][excavkin.loader.breakout.breakout].
    ax : matplotlib Axes, optional

    Returns
    -------
    LoaderPlot
        ``artists["bars"]`` maps ``(circuit, limit)`` to its bar.
    """
    fig, ax = figure_axes(ax, (8.0, 4.2))
    art: dict[str, Any] = {"bars": {}}
    limits = (
        ("working", "working cylinder at working pressure", "0.75"),
        ("hydraulic", "holding cylinder within its relief", "tab:orange"),
        ("tipping", "tipping of the machine", "tab:purple"),
    )
    rows = (bo.tilt, bo.lift)
    y = 0.0
    ticks, labels = [], []
    for r in rows:
        for k, (attr, label, color) in enumerate(limits):
            v = float(getattr(r, attr)) / 1e3
            yy = y + 0.27 * (k - 1)
            bar = ax.barh(yy, v, height=0.25, color=color, label=label if r is bo.tilt else None)
            art["bars"][r.circuit, attr] = bar
            _bar_label(ax, v, yy, f"{v:.1f} kN")
        ax.plot([r.force / 1e3] * 2, [y - 0.45, y + 0.45], color="k", lw=2.0)
        ax.text(
            r.force / 1e3,
            y + 0.47,
            f"breakout {r.force / 1e3:.1f} kN, limited by {r.limiting}",
            fontsize=8,
            ha="center",
            va="bottom",
        )
        ticks.append(y)
        labels.append(f"{r.circuit} circuit\nabout the {r.pivot}")
        y += 1.5
    ax.set_yticks(ticks, labels)
    ax.set_xlabel("force at 100 mm behind the cutting edge (kN)")
    top = max(float(getattr(r, a)) for r in rows for a, _, _ in limits) / 1e3
    ax.set_xlim(0, 1.3 * top if top > 0 else 1.0)
    ax.set_ylim(-0.6, y - 0.7)
    ax.legend(loc="lower right", fontsize=8)
    _title(ax, bo.machine, "breakout force (SAE J732 / ISO 14397-2)")
    ax.grid(True, axis="x", alpha=0.3)
    return LoaderPlot(fig, ax, art)


def plot_tipping(tl: TippingLoad, *, ax: Axes | None = None) -> LoaderPlot:
    """The static tipping loads straight and at full turn, and the rated operating capacity.

    Parameters
    ----------
    tl : TippingLoad
        From [`static_tipping`][excavkin.loader.tipping.static_tipping].
    ax : matplotlib Axes, optional

    Returns
    -------
    LoaderPlot
        ``artists["bars"]`` the two cases' bars, ``artists["roc"]`` the ROC line.
    """
    fig, ax = figure_axes(ax, (7.0, 4.2))
    cases = (tl.straight, tl.full_turn)
    names = [
        "straight",
        f"full turn ({math.degrees(tl.full_turn.articulation):.0f}°)",
    ]
    loads = [c.load / 1e3 for c in cases]
    bars = ax.bar(names, loads, color=["tab:purple", "tab:red"], width=0.5)
    for b, c in zip(bars, cases, strict=True):
        ax.text(
            b.get_x() + b.get_width() / 2,
            b.get_height(),
            f"{c.load:,.0f} kg\nabout the {c.line}".replace(",", " "),
            ha="center",
            va="bottom",
            fontsize=8,
        )
    roc = tl.rated_operating_capacity / 1e3
    line = ax.axhline(roc, color="tab:blue", lw=1.5, ls="--")
    ax.text(
        0.5,
        roc,
        f"rated operating capacity {tl.rated_operating_capacity:,.0f} kg\n".replace(",", " ")
        + "(50 % of the full-turn tipping load, SAE J818)",
        color="tab:blue",
        fontsize=8,
        ha="center",
        va="bottom",
        bbox={"boxstyle": "round", "fc": "white", "ec": "none", "alpha": 0.9},
    )
    ax.set_ylim(0, 1.3 * max(loads))
    ax.set_ylabel("static tipping load (t)")
    _title(ax, tl.machine, "static tipping load (SAE J732 / ISO 14397-1)")
    ax.grid(True, axis="y", alpha=0.3)
    return LoaderPlot(fig, ax, {"bars": bars, "roc": line})


def plot_capacity(cap: Capacity, *, ax: Axes | None = None) -> LoaderPlot:
    """Lift and rollback capacity and the tipping load over the lift (ISO 14397-2).

    Parameters
    ----------
    cap : Capacity
        From [`capacity`][excavkin.loader.capacity.capacity].
    ax : matplotlib Axes, optional

    Returns
    -------
    LoaderPlot
        ``artists`` the ``"lift"``, ``"rollback"`` and ``"tipping"`` curves.
    """
    fig, ax = figure_axes(ax, (8.0, 5.0))
    h = cap.hinge_height * 1e3
    art: dict[str, Any] = {}
    (art["tipping"],) = ax.plot(
        h, cap.tipping / 1e3, color="tab:purple", lw=1.4, ls="--", label="tipping load, straight"
    )
    (art["lift"],) = ax.plot(h, cap.lift / 1e3, color=LIFT_COLOR, lw=2.0, label="lift capacity")
    (art["rollback"],) = ax.plot(
        h, cap.rollback / 1e3, color=TILT_COLOR, lw=2.0, label="rollback capacity"
    )
    if np.isfinite(cap.lift).any():
        k = int(np.nanargmin(cap.lift))
        ax.plot(h[k], cap.lift[k] / 1e3, "o", color=LIFT_COLOR)
        ax.annotate(
            f"to full height {cap.lift[k]:,.0f} kg\n(limited by {cap.lift_limit[k]})".replace(
                ",", " "
            ),
            (h[k], cap.lift[k] / 1e3),
            (-8, -30),
            textcoords="offset points",
            fontsize=8,
            color=LIFT_COLOR,
            ha="right",
        )
    # where the binding limit changes along each curve
    lift_lim = np.asarray(cap.lift_limit).astype(str)
    for values, limits, color, va in (
        (cap.lift, cap.lift_limit, LIFT_COLOR, "top"),
        (cap.rollback, cap.rollback_limit, TILT_COLOR, "bottom"),
    ):
        lim = np.asarray(limits).astype(str)
        change = np.flatnonzero(lim[1:] != lim[:-1]) + 1
        for i in change:
            if np.isfinite(values[i]):
                ax.plot(h[i], values[i] / 1e3, "|", color=color, ms=12)
        starts = np.r_[0, change]
        for s in starts:
            same = values is cap.rollback and lim[s] == lift_lim[s] and cap.lift[s] == values[s]
            if lim[s] and np.isfinite(values[s]) and not same:
                ax.text(h[s], values[s] / 1e3, f" {lim[s]}", fontsize=7, color=color, va=va)
    ax.set_xlabel("hinge-pin height above the ground (mm)")
    ax.set_ylabel("load at the rated load's centre of gravity (t)")
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=8, loc="upper right")
    _title(ax, cap.machine, "lift and rollback capacity, bucket rolled back (ISO 14397-2)")
    ax.grid(True, alpha=0.3)
    return LoaderPlot(fig, ax, art)


def plot_parallel_lift(pl: ParallelLift, *, ax: Axes | None = None) -> LoaderPlot:
    """The bucket's angle over the lift with the tilt cylinder held.

    Parameters
    ----------
    pl : ParallelLift
        From [`parallel_lift`][excavkin.loader.parallel_lift.parallel_lift].
    ax : matplotlib Axes, optional

    Returns
    -------
    LoaderPlot
        ``artists["angle"]`` the curve.
    """
    fig, ax = figure_axes(ax, (7.0, 4.5))
    deg = np.degrees(pl.angle)
    h = pl.hinge_height * 1e3
    (curve,) = ax.plot(h, deg, color=TILT_COLOR, lw=2.0, label="bucket floor angle")
    ax.axhline(deg[0], color="0.5", lw=0.8, ls="--", label="angle on the ground")
    k = int(np.argmax(np.abs(deg - deg[0])))
    ax.plot(h[k], deg[k], "o", color=TILT_COLOR)
    ax.annotate(
        f"largest deviation {math.degrees(pl.deviation):+.1f}°",
        (h[k], deg[k]),
        (0, -18),
        textcoords="offset points",
        fontsize=8,
        ha="center",
    )
    ax.set_xlabel("hinge-pin height above the ground (mm)")
    ax.set_ylabel("floor angle (deg; > 0 rolled back)")
    _title(
        ax,
        pl.machine,
        f"parallel lift, tilt held at {pl.tilt * 1e3:.0f} mm "
        f"(change {math.degrees(pl.change):+.1f}°)",
    )
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return LoaderPlot(fig, ax, {"angle": curve})


def plot_cycle(cy: Cycle, *, ax: Axes | None = None) -> LoaderPlot:
    """The SAE J732 phases' times, each with its peak pressure against its working pressure.

    Parameters
    ----------
    cy : Cycle
        From [`cycle`][excavkin.loader.cycle.cycle].
    ax : matplotlib Axes, optional

    Returns
    -------
    LoaderPlot
        ``artists["bars"]`` the phases' bars.
    """
    fig, ax = figure_axes(ax, (8.0, 3.6))
    names = [p.name for p in cy.phases]
    times = [p.time for p in cy.phases]
    colors = [LIFT_COLOR if p.role == "lift" else TILT_COLOR for p in cy.phases]
    bars = ax.barh(names, times, color=colors, height=0.55)
    for b, p in zip(bars, cy.phases, strict=True):
        if p.pressure < 0.0:
            note = "overrunning"
        elif p.over_working:
            note = f"above the working pressure {p.working / 1e6:.1f} MPa"
        else:
            note = f"of {p.working / 1e6:.1f} MPa working"
        _bar_label(
            ax,
            b.get_width(),
            b.get_y() + b.get_height() / 2,
            f"{p.time:.2f} s · {p.pressure / 1e6:.1f} MPa {note} · {p.power / 1e3:.0f} kW",
            color="tab:red" if p.over_working else "k",
        )
    ax.invert_yaxis()
    ax.set_xlim(0, 2.2 * max(times))
    ax.set_xlabel("time at the pumps' full flow (s)")
    _title(ax, cy.machine, f"hydraulic cycle (SAE J732), total {cy.total:.2f} s")
    ax.grid(True, axis="x", alpha=0.3)
    return LoaderPlot(fig, ax, {"bars": bars})


def plot_pins(pins: LoaderPins, *, ax: Axes | None = None) -> LoaderPlot:
    """Each pin's largest load over the lift in each load case, as grouped bars.

    Parameters
    ----------
    pins : LoaderPins
        From [`pin_loads`][excavkin.loader.pins.pin_loads].
    ax : matplotlib Axes, optional

    Returns
    -------
    LoaderPlot
        ``artists["bars"]`` maps each case to its bars.
    """
    names = pins.cases[0].pins
    fig, ax = figure_axes(ax, (8.5, 1.2 + 0.55 * len(names)))
    y = np.arange(len(names), dtype=np.float64)
    width = 0.8 / len(pins.cases)
    art: dict[str, Any] = {"bars": {}}
    top = 0.0
    for k, c in enumerate(pins.cases):
        best = np.nanmax(np.where(c.ok[:, None], c.load, np.nan), axis=0) / 1e3
        top = max(top, float(np.nanmax(best)))
        art["bars"][c.name] = ax.barh(
            y + (k - (len(pins.cases) - 1) / 2) * width,
            best,
            height=width,
            color=CASE_COLORS.get(c.name, f"C{k}"),
            label=c.name,
        )
    ax.set_yticks(y, [pins.labels.get(p, p) for p in names])
    ax.invert_yaxis()
    ax.set_xlim(0, 1.1 * top if top > 0 else 1.0)
    ax.set_xlabel("largest pin load over the lift (kN)")
    ax.legend(fontsize=8, loc="lower right")
    _title(ax, pins.machine, "pin loads over the lift (SAE J732 breakout, SAE J818 load)")
    ax.grid(True, axis="x", alpha=0.3)
    return LoaderPlot(fig, ax, art)
