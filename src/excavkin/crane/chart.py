"""A crane's load chart: radius × boom configuration × slew sector, each cell the least of its
limits (`excavkin.crane.limits`) with the one that binds named.

The boom configurations are lengths of the second cylinder (the knuckle or the telescoping
cylinder), each shown as the knuckle angle or the boom length it gives."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.crane.limits import (
    STABILITY_SHARE,
    Sector,
    cylinder_limit,
    force_terms,
    hoist_limit,
    rope_limit,
    sector_candidates,
    sectors,
    stability_criterion,
    stability_limits,
    support_kind,
)
from excavkin.crane.machine import Crane, StabilityFactors
from excavkin.errors import InputError

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.outputs.machine_plot import MachinePlot


def limit_names(crane: Crane) -> tuple[str, ...]:
    """The names of a crane's limits, in the order of `LoadChart.limits`: the two cylinders,
    the hoist, stability, then each rope of its booms (``"rope 'sync' slack"``).

    Parameters
    ----------
    crane : Crane

    Returns
    -------
    tuple of str
    """
    ropes = tuple(f"rope {r.name!r} slack" for r in crane.mechanism.model.ropes)
    return ("luffing cylinder", f"{crane.second.role} cylinder", "hoist", "stability", *ropes)


@dataclass(frozen=True, slots=True)
class LoadChart:
    """The load chart (SI; loads in kg of hook load, hook block included).

    Attributes
    ----------
    machine : str
    radius : ndarray, shape (r,)
        Hook radii (m).
    second : ndarray, shape (k,)
        The second cylinder's lengths (m): the boom configurations.
    config : ndarray, shape (k,)
        What each gives: the knuckle angle (rad) or the boom length (m).
    config_name : str
        ``"knuckle angle"`` or ``"boom length"``.
    sectors : tuple of Sector
    limit_names : tuple of str
        The limits' names (`limit_names`): the cylinders, the hoist, stability (index 3), the
        booms' ropes.
    limits : ndarray, shape (m, r, k, s)
        Each limit (kg); NaN where the radius is out of reach.
    capacity : ndarray, shape (r, k, s)
        The least of them (kg).
    binding : ndarray of str, shape (r, k, s)
        The limit that binds: ``"luffing cylinder"``, ``"knuckle cylinder"`` or
        ``"telescope cylinder"``, ``"hoist"``, ``"stability (CRITERION), LINE"`` (the
        criterion, e.g. ``"85 % of tipping"`` or ``"factors 1.3, 0.2"``, and the tipping line),
        ``"rope 'NAME' slack"`` (a rope of the booms would have to push); ``"out of reach"``
        where NaN.
    slew : ndarray, shape (r, k, s)
        The slew angle of the sector's least stability limit (rad).
    share : float or None
        The share of the tipping load the stability limit is (0.85 or 0.75); None where
        factored loads rate it.
    factors : StabilityFactors or None
        The factors of the criterion by factored loads that rates stability
        (`excavkin.crane.limits`); None where the share of the tipping load does.
    hook_mass : float
        The hook block's mass (kg), part of every capacity.
    """

    machine: str
    radius: F
    second: F
    config: F
    config_name: str
    sectors: tuple[Sector, ...]
    limit_names: tuple[str, ...]
    limits: F
    capacity: F
    binding: NDArray[np.str_]
    slew: F
    share: float | None
    factors: StabilityFactors | None
    hook_mass: float

    def to_frame(self) -> pd.DataFrame:
        """One row per cell, SI (kg, m, rad).

        Returns
        -------
        pandas.DataFrame
        """
        import pandas as pd

        r, k, s = self.capacity.shape
        ir, ik, is_ = np.meshgrid(np.arange(r), np.arange(k), np.arange(s), indexing="ij")
        cols: dict[str, object] = {
            "radius": self.radius[ir].ravel(),
            "second_cylinder": self.second[ik].ravel(),
            self.config_name.replace(" ", "_"): self.config[ik].ravel(),
            "sector": np.array([x.name for x in self.sectors])[is_].ravel(),
            "capacity": self.capacity.ravel(),
            "net": (self.capacity - self.hook_mass).ravel(),
            "binding": self.binding.ravel(),
        }
        for name, lim in zip(self.limit_names, self.limits, strict=True):
            cols[name.replace(" ", "_")] = lim.ravel()
        cols["slew"] = self.slew.ravel()
        frame = pd.DataFrame(cols)
        frame.attrs["machine"] = self.machine
        return frame

    def summary(self) -> str:
        """The chart as text: capacity (t) per radius, one block per configuration, one
        column per sector, and the limit that binds.

        Returns
        -------
        str
        """
        head = [
            f"{self.machine}: load chart (t at the hook, hook block of {self.hook_mass:g} kg "
            f"included); stability {self.criterion_text}",
        ]
        for j in range(self.second.size):
            head.append(f"  {self.config_label(j)}")
            head.append("    radius m  " + "".join(f"{s.name:>32}" for s in self.sectors))
            for i, r in enumerate(self.radius):
                cells = []
                for k in range(len(self.sectors)):
                    c = self.capacity[i, j, k]
                    b = str(self.binding[i, j, k]).replace(" (outriggers)", "")
                    b = b.replace(f" ({self.criterion})", "")  # the header says it
                    cells.append(
                        f"{'—':>8}{'':24}" if np.isnan(c) else f"{c / 1000:8.2f} {b[:23]:<23}"
                    )
                head.append(f"    {r:8.2f}  " + "".join(cells))
        return "\n".join(head)

    @property
    def criterion(self) -> str:
        """What rates stability, as the binding limit names it: ``"85 % of tipping"`` or
        ``"factors 1.3, 0.2"``."""
        if self.factors is not None:
            return self.factors.label
        return f"{self.share:.0%} of tipping".replace("%", " %")

    @property
    def criterion_text(self) -> str:
        """The stability criterion in words: ``"85 % of tipping (ASME B30.5 5-1.1.1)"`` or
        ``"by factored loads 1.3·P + 0.2·F (P the hook load, F the booms' weight reduced to
        the tip; the form of ISO 4305 and EN 13000, the user's factors)"``."""
        f = self.factors
        if f is None:
            return f"{self.criterion} (ASME B30.5 5-1.1.1)"
        return (
            f"by factored loads {f.hook:g}·P + {f.jib:g}·F (P the hook load, F the booms' "
            "weight reduced to the tip; the form of ISO 4305 and EN 13000, the user's factors)"
        )

    def config_label(self, j: int) -> str:
        """The ``j``-th configuration as text: ``"knuckle −60.0°"`` or ``"boom 13.50 m"``.

        Parameters
        ----------
        j : int

        Returns
        -------
        str
        """
        if self.config_name == "knuckle angle":
            return f"knuckle {np.degrees(self.config[j]):.1f}°"
        return f"boom {self.config[j]:.2f} m"

    def plot(self, *, ax: Axes | None = None) -> MachinePlot:
        """Capacity over radius: one line per configuration, in its least stable sector.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Drawn on; a new figure when omitted.

        Returns
        -------
        MachinePlot
        """
        from excavkin.outputs.machine_plot import MachinePlot, figure_axes

        fig, ax = figure_axes(ax, (7.0, 4.5))
        least = np.nanmin(np.where(np.isnan(self.capacity), np.inf, self.capacity), axis=2)
        least = np.where(np.isinf(least), np.nan, least)
        lines = {}
        for j in range(self.second.size):
            (lines[f"config {j}"],) = ax.plot(
                self.radius, least[:, j] / 1000, marker="o", label=self.config_label(j)
            )
        ax.set_xlabel("radius (m)")
        ax.set_ylabel("capacity, least over the sectors (t)")
        ax.set_title(f"{self.machine}: stability {self.criterion}")
        ax.grid(True, alpha=0.3)
        ax.legend()
        return MachinePlot(fig, ax, lines)


def load_chart(
    crane: Crane, radius: F, second: F | None = None, sector_count: int = 4
) -> LoadChart:
    """The load chart at hook radii × boom configurations × slew sectors.

    Parameters
    ----------
    crane : Crane
    radius : ndarray
        Hook radii (m).
    second : ndarray, optional
        The second cylinder's lengths (m); default three over its stroke (its ends and its
        middle).
    sector_count : int
        Equal slew sectors over 360° (`excavkin.crane.limits.sectors`).

    Returns
    -------
    LoadChart

    Raises
    ------
    InputError
        An empty or non-finite radius list, a length outside the cylinder's stroke, or fewer
        than one sector.
    """
    radius = np.atleast_1d(np.asarray(radius, dtype=np.float64))
    cyl = crane.second
    if second is None:
        second = np.linspace(cyl.retracted, cyl.extended, 3)
    second = np.atleast_1d(np.asarray(second, dtype=np.float64))
    if radius.size == 0 or not np.all(np.isfinite(radius)) or np.any(radius < 0):
        raise InputError("the radii must be finite and at least 0 m")
    tol = 1e-9
    if (
        second.size == 0
        or not np.all(np.isfinite(second))
        or np.any(second < cyl.retracted - tol)
        or np.any(second > cyl.extended + tol)
    ):
        raise InputError(
            f"the {cyl.role} cylinder's lengths must lie within its stroke "
            f"({cyl.retracted * 1e3:.0f} to {cyl.extended * 1e3:.0f} mm)"
        )
    if sector_count < 1:
        raise InputError("at least one slew sector")
    rr, kk = np.meshgrid(radius, second, indexing="ij")
    pose = crane.pose(rr.ravel(), kk.ravel())
    n = rr.size
    f0, f1, ropes = force_terms(crane, pose)
    luff = cylinder_limit(crane, crane.cylinders[0], f0[:, 0], f1[:, 0])
    other = cylinder_limit(crane, cyl, f0[:, 1], f1[:, 1])
    slack = [rope_limit(*terms) for terms in ropes.values()]
    hoist = np.where(pose.reached, hoist_limit(crane), np.nan)
    criterion = stability_criterion(crane)
    lines = crane.support.tipping_lines(crane.swing_axis, 0.0)
    secs = sectors(sector_count)
    stab = np.empty((n, len(secs)))
    slew = np.empty((n, len(secs)))
    stab_name = np.empty((n, len(secs)), dtype=object)
    rows = np.arange(n)
    for k, sec in enumerate(secs):  # a few sectors; every pose at once
        alpha = sector_candidates(lines, sec.start, sec.end)
        load, line = stability_limits(crane, pose, alpha)
        j = np.argmin(np.where(np.isnan(load), np.inf, load), axis=1)
        stab[:, k] = load[rows, j]
        slew[:, k] = alpha[j]
        stab_name[:, k] = line[rows, j]
    shape = (radius.size, second.size, len(secs))
    per = [np.broadcast_to(x[:, None], (n, len(secs))) for x in (luff, other, hoist)]
    tied = [np.broadcast_to(x[:, None], (n, len(secs))) for x in slack]
    limits = np.stack([*per, stab, *tied]) / crane.gravity
    reach = pose.reached[:, None] & np.ones((1, len(secs)), dtype=bool)
    which = np.argmin(np.where(np.isnan(limits), np.inf, limits), axis=0)
    capacity = np.where(reach, np.min(limits, axis=0), np.nan)
    names_all = limit_names(crane)
    names = np.array(names_all, dtype=object)[which]
    names = np.where(which == 3, f"stability ({criterion}), " + stab_name.astype(str), names)
    binding = np.where(reach, names, "out of reach").astype(str)
    at_config = crane.solve(
        np.column_stack(
            [np.full(second.size, crane.mechanism.sketch_values()[crane.drivers[0]]), second]
        )
    )
    return LoadChart(
        machine=crane.name,
        radius=radius,
        second=second,
        config=crane.configuration(at_config),
        config_name=crane.configuration_name,
        sectors=secs,
        limit_names=names_all,
        limits=limits.reshape(len(names_all), *shape),
        capacity=capacity.reshape(shape),
        binding=binding.reshape(shape),
        slew=slew.reshape(shape),
        share=None if crane.stability is not None else STABILITY_SHARE[support_kind(crane)],
        factors=crane.stability,
        hook_mass=crane.hoist.hook_mass,
    )
