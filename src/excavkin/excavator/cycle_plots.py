"""Plot of the hydraulic power along the dig–swing–dump cycle.

matplotlib is imported inside the function, which returns a handle.
"""

from __future__ import annotations

from excavkin.excavator.cycle_power import CyclePower
from excavkin.excavator.machine import ROLES
from excavkin.excavator.plots import ExcavatorPlot

#: a colour per function, as on the limit maps
ROLE_COLOURS = {"boom": "tab:blue", "arm": "tab:green", "bucket": "tab:olive"}


def plot_cycle_power(cycle: CyclePower, *, title: str = "") -> ExcavatorPlot:
    """Power of each cylinder along the cycle (upper) and the moving cylinder's inlet pressure
    against its working pressure (lower); phases shaded and named, samples beyond the working
    pressure marked.

    Parameters
    ----------
    cycle : CyclePower
        From [`cycle_power`][excavkin.excavator.cycle_power.cycle_power].
    title : str, default ""
        Figure title; none when empty.

    Returns
    -------
    ExcavatorPlot
        Its ``ax`` is the power axes; ``artists["pressure_ax"]`` the pressure axes.
    """
    import matplotlib.pyplot as plt

    fig, (ax, axp) = plt.subplots(
        2, 1, figsize=(11.0, 7.0), sharex=True, layout="constrained", height_ratios=(3, 2)
    )
    t = cycle.time
    power = cycle.power.power / 1e3
    lines = {}
    for i, role in enumerate(ROLES):
        lines[role] = ax.plot(t, power[:, i], color=ROLE_COLOURS[role], lw=1.8, label=role)[0]
    ax.axhline(0.0, color="0.3", lw=0.8)
    supply = f"pumps at full flow and working pressure ({cycle.supply / 1e3:.0f} kW)"
    ax.axhline(cycle.supply / 1e3, color="tab:red", ls="--", lw=1.2, label=supply)
    start = 0.0
    for k, ph in enumerate(cycle.phases):
        end = start + ph.duration
        for a in (ax, axp):
            a.axvspan(start, end, color="0.93" if k % 2 else "white", zorder=0)
        ax.annotate(ph.name, ((start + end) / 2, 1.0), xycoords=("data", "axes fraction"),
                    ha="center", va="bottom", fontsize=8, rotation=30)  # fmt: skip
        if ph.role is not None:
            i = ROLES.index(ph.role)
            sl = (t >= start) & (t <= end) & (cycle.rates[:, i] != 0.0)
            bar = cycle.power.pressure[sl, i] / 1e5
            axp.plot(t[sl], bar, color=ROLE_COLOURS[ph.role], lw=1.8)
            axp.hlines(ph.working_pressure / 1e5, start, end, color="tab:red", ls="--", lw=1.2)
            beyond = bar > ph.working_pressure / 1e5
            if beyond.any():
                axp.fill_between(t[sl], ph.working_pressure / 1e5, bar, where=beyond,
                                 color="tab:red", alpha=0.3, lw=0)  # fmt: skip
        start = end
    ax.set_ylabel("cylinder power, kW (< 0: the load overruns)")
    ax.legend(loc="upper left", fontsize=8, ncols=2)
    ax.grid(alpha=0.3)
    axp.axhline(0.0, color="0.3", lw=0.8)
    axp.set_ylabel("inlet pressure, bar")
    axp.set_xlabel("time from the start of the cycle, s")
    axp.grid(alpha=0.3)
    axp.plot([], [], color="tab:red", ls="--", lw=1.2, label="working pressure")
    beyond_label = "beyond it: cannot run at full flow"
    axp.fill_between([], [], [], color="tab:red", alpha=0.3, label=beyond_label)
    axp.legend(loc="upper left", fontsize=8)
    ax.set_xlim(0.0, float(t[-1]))
    if title:
        fig.suptitle(title)
    return ExcavatorPlot(fig, ax, {"lines": lines, "pressure_ax": axp})
