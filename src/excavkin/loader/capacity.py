r"""Lift and rollback capacity of a wheel loader over its lift (ISO 14397-2).

At each lift length, the bucket at full rollback, a load of weight W hangs at the rated load's
centre of gravity P (the bucket frame's ``load_cg``). Virtual power over a motion of cylinder c
alone gives the force it must carry (> 0 pushing)::

    f_c = W·∂y_P/∂L_c + G_c         (∂P/∂L from the engine's transfer functions, G_c gravity)

with ∂P/∂L = ∂B/∂L + ∂a/∂L·perp(P − B), B the hinge pin and a the floor angle. The **lift
capacity** is the largest W the lift cylinders raise at their circuit's working pressure, the
tilt cylinder holding within its port relief; the **rollback capacity** the largest W the tilt
cylinder rolls back at working pressure, the lift cylinders holding within theirs
([`capped_force`][excavkin.machinery.capped_force.capped_force] on the vertical row of ∂P/∂L,
the binding cylinder named). Each is also capped by the straight machine's tipping load at that
pose ([`cap_by`][excavkin.machinery.capped_force.cap_by]), named ``"tipping (LINE)"``.

ISO 14397-2's **lift capacity to maximum height** is the least lift capacity over the lift: the
mass the lift cylinders can raise from the ground to full height.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.loader.machine import (
    Loader,
    bucket_frame_point,
    floor_angle_rate,
    table_attrs,
    transfer,
)
from excavkin.loader.stability import tipping
from excavkin.machinery.capped_force import cap_by, capped_force, gravity_terms, pressure_limits

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.loader.plots import LoaderPlot


@dataclass(frozen=True, slots=True)
class Capacity:
    """Lift and rollback capacity at n lift lengths, bucket at full rollback.

    Attributes
    ----------
    machine : str
    lengths : ndarray, shape (n, 2)
        Lift and tilt lengths (m).
    hinge_height : ndarray, shape (n,)
        The hinge pin above the ground (m).
    point : ndarray, shape (n, 2)
        The rated load's centre of gravity (m).
    lift, rollback : ndarray, shape (n,)
        The capacities (kg); NaN where the pose does not assemble, 0 where the cylinders
        cannot even hold the linkage's weight or their motion does not raise the load.
    lift_limit, rollback_limit : ndarray of str, shape (n,)
        What binds each.
    tipping : ndarray, shape (n,)
        The straight machine's tipping load at the pose (kg).
    """

    machine: str
    lengths: F
    hinge_height: F
    point: F
    lift: F
    lift_limit: NDArray[np.str_]
    rollback: F
    rollback_limit: NDArray[np.str_]
    tipping: F

    @property
    def to_full_height(self) -> float:
        """ISO 14397-2 lift capacity to maximum height: the least lift capacity (kg)."""
        return float(np.nanmin(self.lift))

    def to_frame(self) -> pd.DataFrame:
        """One row per lift length, SI.

        Returns
        -------
        pandas.DataFrame
            ``attrs`` record the machine and the columns' kinds and units.
        """
        import pandas as pd

        frame = pd.DataFrame(
            {
                "lift_cyl": self.lengths[:, 0],
                "tilt_cyl": self.lengths[:, 1],
                "hinge_height": self.hinge_height,
                "load_x": self.point[:, 0],
                "load_y": self.point[:, 1],
                "lift_capacity": self.lift,
                "lift_limit": self.lift_limit,
                "rollback_capacity": self.rollback,
                "rollback_limit": self.rollback_limit,
                "tipping_load": self.tipping,
            }
        )
        kinds = {
            **dict.fromkeys(("lift_cyl", "tilt_cyl", "hinge_height", "load_x", "load_y"), "length"),
            **dict.fromkeys(("lift_capacity", "rollback_capacity", "tipping_load"), "mass"),
        }
        frame.attrs.update(table_attrs(self.machine, kinds))
        return frame

    def plot(self, *, ax: Axes | None = None) -> LoaderPlot:
        """Lift and rollback capacity and the tipping load over the lift (ISO 14397-2).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Drawn on; a new figure when omitted.

        Returns
        -------
        LoaderPlot
        """
        from excavkin.loader.plots import plot_capacity

        return plot_capacity(self, ax=ax)

    def summary(self) -> str:
        """The lift capacity to full height and the least rollback capacity.

        Returns
        -------
        str
        """
        k = int(np.nanargmin(self.lift))
        j = int(np.nanargmin(self.rollback))
        return "\n".join(
            [
                f"{self.machine}: lift and rollback capacity (ISO 14397-2), bucket rolled back",
                f"  lift capacity to full height {self.lift[k]:8.0f} kg  (least at hinge "
                f"height {self.hinge_height[k] * 1e3:.0f} mm, limited by {self.lift_limit[k]})",
                f"  least rollback capacity      {self.rollback[j]:8.0f} kg  (at hinge height "
                f"{self.hinge_height[j] * 1e3:.0f} mm, limited by {self.rollback_limit[j]})",
            ]
        )


def capacity(machine: Loader, samples: int = 101) -> Capacity:
    """Lift and rollback capacity over the lift stroke (module docstring).

    Parameters
    ----------
    machine : Loader
    samples : int
        Lift lengths, evenly over the stroke (at least 2).

    Returns
    -------
    Capacity
    """
    if samples < 2:
        from excavkin.errors import InputError

        raise InputError(f"samples must be at least 2, not {samples}")
    lift = np.linspace(machine.lengths_min[0], machine.lengths_max[0], samples)
    L = np.column_stack([lift, np.full(samples, machine.full_rollback())])
    tr = transfer(machine, L)
    ok = tr.ok
    pos = np.where(ok[:, None, None], tr.positions, np.nan)
    point = bucket_frame_point(machine, pos, machine.bucket.load_cg)
    hinge, d_hinge = tr.point(machine, machine.pins.hinge)
    rel = point - hinge
    da = floor_angle_rate(machine, tr)  # (n, 2)
    perp = np.column_stack([-rel[:, 1], rel[:, 0]])
    J = d_hinge + perp[:, :, None] * da[:, None, :]  # ∂P/∂L, (n, 2, 2)
    Jy = np.zeros_like(J)
    Jy[:, 1, :] = J[:, 1, :]
    G = gravity_terms(machine, tr.d)
    tip = tipping(machine, pos, point, 0.0)
    tip_name = np.char.add(np.char.add("tipping (", tip.line.astype(str)), ")")
    g = machine.gravity
    out = []
    for w, sign in ((0, machine.raise_sign()), (1, machine.rollback_sign())):
        limits = pressure_limits(machine.cylinders, machine.circuits, w)
        force, _, limiting, _, direction = capped_force(Jy, G, w, sign, limits, machine.roles)
        up = direction[:, 1] > 0.0
        force = np.where(up, force, 0.0)
        limiting = np.where(up, limiting, "")
        force, limiting = cap_by(force, limiting, [(tip_name, tip.load)])
        out.append((np.where(ok, force / g, np.nan), np.where(ok, limiting, "")))
    return Capacity(
        machine.name,
        L,
        hinge[:, 1] - machine.ground_line,
        point,
        out[0][0],
        out[0][1],
        out[1][0],
        out[1][1],
        tip.load / g,
    )
