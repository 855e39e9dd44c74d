r"""Static tipping load and rated operating capacity of a wheel loader.

**Static tipping load** (SAE J732; ISO 14397-1, "tipping load at maximum reach"): the least
mass at the centre of gravity of the rated load (the centroid of the rated bucket volume,
ISO 7546) that lifts the rear wheels off the ground (tips the machine about its front tipping
line), with the machine stationary on a hard level surface at operating mass, the bucket at
full rollback and the load at its most forward position during the lift — here the lift length
where the tipping load is least, found by a pattern search over the lift stroke
([`maximize_strokes`][excavkin.machinery.search.maximize_strokes]). An articulated loader is
rated twice: **straight** and **at full turn** (the largest articulation angle), where the
support polygon turns with the front frame (`excavkin.loader.stability`).

**Rated operating capacity** (SAE J818; ISO 14397-1 for wheel loaders): 50 % of the full-turn
static tipping load.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.loader.machine import Loader, bucket_frame_point, table_attrs
from excavkin.loader.stability import tipping
from excavkin.machinery.search import maximize_strokes

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.loader.plots import LoaderPlot

#: the rated operating capacity's share of the full-turn static tipping load (wheel loaders)
ROC_FACTOR = 0.5


@dataclass(frozen=True, slots=True)
class TippingCase:
    """The static tipping load at one articulation angle.

    Attributes
    ----------
    name : {"straight", "full turn"}
    articulation : float
        rad.
    load : float
        The static tipping load (kg).
    line : str
        The tipping line.
    lengths : ndarray, shape (2,)
        Lift and tilt lengths of the pose (m).
    point : ndarray, shape (2,)
        The rated load's centre of gravity at that pose (m, model plane).
    """

    name: str
    articulation: float
    load: float
    line: str
    lengths: F
    point: F


@dataclass(frozen=True, slots=True)
class TippingLoad:
    """Static tipping loads and the rated operating capacity.

    Attributes
    ----------
    machine : str
    straight, full_turn : TippingCase
    rated_operating_capacity : float
        50 % of the full-turn static tipping load (kg).
    capacity : float
        The bucket's rated (heaped) capacity (m³).
    """

    machine: str
    straight: TippingCase
    full_turn: TippingCase
    rated_operating_capacity: float
    capacity: float

    @property
    def density(self) -> float:
        """The densest material the rated capacity may hold: ROC / bucket capacity (kg/m³)."""
        return self.rated_operating_capacity / self.capacity

    def to_frame(self) -> pd.DataFrame:
        """The two cases as a table, SI.

        Returns
        -------
        pandas.DataFrame
            One row per case; ``attrs`` record the machine and the columns' kinds and units
            (``excavkin.model``, ``excavkin.kinds``, ``excavkin.units``) and
            ``attrs["excavkin.rated_operating_capacity"]`` holds the ROC (kg).
        """
        import pandas as pd

        cases = (self.straight, self.full_turn)
        frame = pd.DataFrame(
            {
                "case": [c.name for c in cases],
                "articulation": [c.articulation for c in cases],
                "tipping_load": [c.load for c in cases],
                "line": [c.line for c in cases],
                "lift_cyl": [c.lengths[0] for c in cases],
                "tilt_cyl": [c.lengths[1] for c in cases],
                "load_x": [c.point[0] for c in cases],
                "load_y": [c.point[1] for c in cases],
            }
        )
        kinds = {
            "articulation": "angle",
            "tipping_load": "mass",
            **dict.fromkeys(("lift_cyl", "tilt_cyl", "load_x", "load_y"), "length"),
        }
        frame.attrs.update(table_attrs(self.machine, kinds))
        frame.attrs["excavkin.rated_operating_capacity"] = self.rated_operating_capacity
        return frame

    def plot(self, *, ax: Axes | None = None) -> LoaderPlot:
        """The tipping loads and the rated operating capacity (SAE J732, SAE J818).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Drawn on; a new figure when omitted.

        Returns
        -------
        LoaderPlot
        """
        from excavkin.loader.plots import plot_tipping

        return plot_tipping(self, ax=ax)

    def summary(self) -> str:
        """The tipping loads and the rated operating capacity, one line each.

        Returns
        -------
        str
        """
        s, f = self.straight, self.full_turn
        return "\n".join(
            [
                f"{self.machine}: static tipping load (SAE J732 / ISO 14397-1)",
                f"  straight                 {s.load:8.0f} kg  about {s.line}",
                f"  full turn ({math.degrees(f.articulation):.0f} deg)      {f.load:8.0f} kg  "
                f"about {f.line}",
                f"  rated operating capacity {self.rated_operating_capacity:8.0f} kg  "
                f"(50 % of full turn, SAE J818); {self.density:.0f} kg/m^3 in "
                f"{self.capacity:.2f} m^3",
            ]
        )


def tipping_loads(machine: Loader, lift: F, articulation: float) -> tuple[F, F]:
    """The static tipping load (kg) of the rated load at lift lengths, bucket at full rollback.

    Parameters
    ----------
    machine : Loader
    lift : ndarray, shape (n,)
        Lift-cylinder lengths (m).
    articulation : float
        rad.

    Returns
    -------
    load : ndarray, shape (n,)
        kg; NaN where the pose does not assemble.
    point : ndarray, shape (n, 2)
        The rated load's centre of gravity (m).
    """
    L = np.column_stack([lift, np.full_like(lift, machine.full_rollback())])
    res = machine.solve(L)
    pos = np.where(res.status.ok[:, None, None], res.positions, np.nan)
    point = bucket_frame_point(machine, pos, machine.bucket.load_cg)
    tip = tipping(machine, pos, point, articulation)
    return tip.load / machine.gravity, point


def _case(machine: Loader, name: str, articulation: float) -> TippingCase:
    roll = machine.full_rollback()

    def evaluate(L: F) -> tuple[F, F]:
        flat = L.reshape(-1, 2)
        load, _ = tipping_loads(machine, flat[:, 0], articulation)
        obj = np.where(np.isfinite(load), -load, -np.inf)
        full = flat.copy()
        full[:, 1] = roll
        return obj.reshape(L.shape[:2]), full.reshape(L.shape)

    base = np.array([[0.5 * (machine.lengths_min[0] + machine.lengths_max[0]), roll]])
    _, lengths = maximize_strokes(evaluate, machine, (0,), coarse=65, base=base)
    L = lengths[0]
    load, point = tipping_loads(machine, L[:1], articulation)
    res = machine.solve(L[None, :])
    tip = tipping(machine, res.positions, point, articulation)
    return TippingCase(name, articulation, float(load[0]), str(tip.line[0]), L, point[0])


def static_tipping(machine: Loader) -> TippingLoad:
    """Static tipping loads straight and at full turn, and the rated operating capacity.

    Parameters
    ----------
    machine : Loader

    Returns
    -------
    TippingLoad
    """
    straight = _case(machine, "straight", 0.0)
    full = _case(machine, "full turn", machine.chassis.max_articulation)
    return TippingLoad(
        machine.name,
        straight,
        full,
        ROC_FACTOR * full.load,
        machine.bucket.capacity,
    )
