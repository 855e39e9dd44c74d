"""Plot of a dig: the path on the machine's side view, and resistance against available force.

matplotlib is imported inside the function, which rejects unknown keyword arguments by
signature and returns a handle.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from excavkin.excavator.dig import Dig
from excavkin.excavator.machine import Machine
from excavkin.excavator.plots import ExcavatorPlot, draw_front

MODEL_NAMES = {"zelenin": "Zelenin", "balovnev": "Balovnev", "mckyes": "McKyes"}


def plot_dig(machine: Machine, d: Dig) -> ExcavatorPlot:
    """Two panels: the dig on the side view (front at the start and at the stall or the
    deepest point, the path coloured by its margin), and the resistance, the available force
    and the limit that caps it along the path.

    Parameters
    ----------
    machine : Machine
    d : Dig
        From [`dig`][excavkin.excavator.dig.dig].

    Returns
    -------
    ExcavatorPlot
        ``ax`` is the force panel; ``artists["side"]`` the side view's axes.
    """
    import matplotlib.pyplot as plt

    fig, (side, ax) = plt.subplots(
        1, 2, figsize=(13.0, 5.6), layout="constrained", gridspec_kw={"width_ratios": [1.05, 1]}
    )
    p = d.point
    s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]  # along the path (m)
    inside = d.depth > 0.0
    k_show = d.stall if d.stall >= 0 else int(np.nanargmax(d.depth))
    draw_front(machine, d.lengths[0], side, alpha=0.3)
    draw_front(machine, d.lengths[k_show], side)
    g0 = machine.ground_line
    side.axhline(g0, color="saddlebrown", lw=1.2)
    lo = float(np.nanmin(p[:, 1]))
    side.fill_between([-50.0, 50.0], g0, min(lo, g0) - 2.0, color="saddlebrown", alpha=0.08, lw=0)
    ok = d.margin >= 0.0
    side.plot(p[:, 0], p[:, 1], color="0.55", lw=1.0, zorder=4)
    side.plot(p[ok, 0], p[ok, 1], "o", color="tab:green", ms=3.0, zorder=5, label="margin ≥ 0")
    side.plot(p[~ok, 0], p[~ok, 1], "o", color="tab:red", ms=3.5, zorder=5, label="stalls")
    side.annotate(
        "",
        p[min(2, len(p) - 1)],
        p[0],
        arrowprops={"arrowstyle": "->", "color": "0.2", "lw": 1.2},
        zorder=6,
    )
    if d.stall >= 0:
        side.plot(*p[d.stall], "X", color="k", ms=10, zorder=6, label="first stall")
    pts = d.pose.result.positions[[0, k_show]].reshape(-1, 2)
    xs = np.r_[pts[:, 0], p[:, 0]]
    ys = np.r_[pts[:, 1], p[:, 1]]
    side.set_xlim(float(np.nanmin(xs)) - 0.8, float(np.nanmax(xs)) + 0.8)
    side.set_ylim(min(float(np.nanmin(ys)), g0) - 0.8, float(np.nanmax(ys)) + 0.6)
    side.set_aspect("equal")
    side.grid(True, lw=0.3, alpha=0.6)
    side.set_xlabel("reach from swing axis x (m)")
    side.set_ylabel("height above ground line y (m)")
    where = "stall" if d.stall >= 0 else "deepest point"
    side.set_title(f"the dig (front at its start and at the {where})")
    side.legend(loc="upper right", fontsize=8)

    art: dict[str, Any] = {"side": side}
    art["required"] = ax.plot(s, d.required / 1e3, color="tab:red", lw=2.0, label="resistance |R|")
    art["available"] = ax.plot(
        s, d.available / 1e3, color="tab:blue", lw=2.0, label="available along R"
    )
    top = float(np.nanmax(np.r_[d.required, d.available])) / 1e3
    ax.fill_between(
        s,
        d.required / 1e3,
        d.available / 1e3,
        where=d.available < d.required,
        color="tab:red",
        alpha=0.15,
        lw=0,
        interpolate=True,
    )
    # which limit caps the available force: a band along the top
    names = [str(n) for n in d.limiting]
    colours = ("tab:green", "tab:purple", "tab:orange", "tab:brown", "tab:olive", "tab:cyan")
    palette = dict(zip(dict.fromkeys(names), colours * len(names), strict=False))
    for i in range(len(s) - 1):
        ax.axvspan(s[i], s[i + 1], ymin=0.975, ymax=1.0, color=palette[names[i]], lw=0)
    for name, colour in palette.items():
        ax.plot([], [], color=colour, lw=6, label=f"limit: {name or '—'}")
    depth = ax.twinx()
    depth.fill_between(s, 0.0, np.where(inside, d.depth * 1e3, 0.0), color="0.5", alpha=0.15)
    depth.set_ylabel("depth below ground (mm)", color="0.4")
    depth.set_ylim(0.0, max(float(np.nanmax(d.depth)), 0.0) * 1e3 * 2.5 + 1.0)
    depth.tick_params(axis="y", colors="0.4")
    if d.stall >= 0:
        ax.axvline(s[d.stall], color="k", lw=1.0, ls="--")
        ax.annotate(
            f"stalls: {d.required[d.stall] / 1e3:.0f} kN needed,\n"
            f"{d.available[d.stall] / 1e3:.0f} kN available ({d.limiting[d.stall]})",
            (s[d.stall], d.available[d.stall] / 1e3),
            (12, -40),
            textcoords="offset points",
            fontsize=8,
            arrowprops={"arrowstyle": "->", "lw": 0.8},
        )
    ax.set_xlim(0.0, float(s[-1]))
    ax.set_ylim(0.0, top * 1.3)
    ax.set_zorder(depth.get_zorder() + 1)
    ax.patch.set_visible(False)
    ax.set_xlabel("distance along the lip's path (m)")
    ax.set_ylabel("force (kN)")
    ax.grid(True, lw=0.3, alpha=0.6)
    ax.legend(loc="upper left", bbox_to_anchor=(0.0, 0.97), fontsize=8, ncol=2)
    ax.set_title(
        f"{MODEL_NAMES.get(d.model, d.model)}'s resistance in {d.soil.name}, "
        f"{d.tool.width * 1e3:.0f} mm wide"
    )
    fig.suptitle(f"{machine.name}: digging resistance along a dig", fontsize=11)
    return ExcavatorPlot(fig, ax, art)
