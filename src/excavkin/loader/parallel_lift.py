"""Parallel lift: the bucket's angle over the lift with the tilt cylinder held.

A loader's front linkage should keep its bucket level while the arm rises with the tilt
cylinder held, so that the load stays in it without the operator's help. The tilt cylinder is
held at the length that levels the bucket on the ground (the ground pose: floor level, cutting
edge on the ground, [`ground_pose`][excavkin.loader.poses.ground_pose]) and the lift cylinders
run from that pose to full lift; the bucket's angle is its floor's (heel → edge), 0 level,
> 0 rolled back.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import ModelError
from excavkin.loader.machine import Loader, floor_angle, table_attrs
from excavkin.loader.poses import ground_pose

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.loader.plots import LoaderPlot


@dataclass(frozen=True, slots=True)
class ParallelLift:
    """The bucket's angle over the lift, the tilt cylinder held.

    Attributes
    ----------
    machine : str
        Its name.
    tilt : float
        The held tilt-cylinder length (m): the one that levels the floor on the ground.
    lift : ndarray, shape (n,)
        Lift-cylinder lengths, from the ground pose to full lift (m).
    hinge_height : ndarray, shape (n,)
        The hinge pin above the ground (m).
    angle : ndarray, shape (n,)
        The floor's angle (rad; 0 level, > 0 rolled back).
    """

    machine: str
    tilt: float
    lift: F
    hinge_height: F
    angle: F

    @property
    def change(self) -> float:
        """The angle at full lift less the angle on the ground (rad; > 0 rolls back).

        Returns
        -------
        float
        """
        return float(self.angle[-1] - self.angle[0])

    @property
    def deviation(self) -> float:
        """The largest departure from the angle on the ground over the lift, signed (rad).

        Returns
        -------
        float
        """
        d = self.angle - self.angle[0]
        return float(d[int(np.argmax(np.abs(d)))])

    def to_frame(self) -> pd.DataFrame:
        """The lift, one row per pose, SI.

        Returns
        -------
        pandas.DataFrame
            Columns ``lift_cyl``, ``tilt_cyl``, ``hinge_height`` (m) and ``angle`` (rad);
            ``attrs`` record the machine and the columns' kinds and units.
        """
        import pandas as pd

        frame = pd.DataFrame(
            {
                "lift_cyl": self.lift,
                "tilt_cyl": np.full_like(self.lift, self.tilt),
                "hinge_height": self.hinge_height,
                "angle": self.angle,
            }
        )
        kinds = {"lift_cyl": "length", "tilt_cyl": "length", "hinge_height": "length"}
        frame.attrs.update(table_attrs(self.machine, {**kinds, "angle": "angle"}))
        return frame

    def plot(self, *, ax: Axes | None = None) -> LoaderPlot:
        """The bucket's angle over the lift, the tilt cylinder held.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Drawn on; a new figure when omitted.

        Returns
        -------
        LoaderPlot
        """
        from excavkin.loader.plots import plot_parallel_lift

        return plot_parallel_lift(self, ax=ax)

    def summary(self) -> str:
        """The held tilt length, the total change and the largest deviation.

        Returns
        -------
        str
        """
        k = int(np.argmax(np.abs(self.angle - self.angle[0])))
        return "\n".join(
            [
                f"{self.machine}: parallel lift, the tilt cylinder held",
                f"  tilt cylinder held at              {self.tilt * 1e3:9.1f} mm",
                f"  lift cylinder, ground to full lift {self.lift[0] * 1e3:9.1f} to "
                f"{self.lift[-1] * 1e3:.1f} mm ({len(self.lift)} poses)",
                f"  hinge pin, ground to full lift     {self.hinge_height[0] * 1e3:9.0f} to "
                f"{self.hinge_height[-1] * 1e3:.0f} mm",
                f"  change, ground to full lift        {math.degrees(self.change):9.2f} deg "
                "(> 0 rolls back)",
                f"  largest deviation                  {math.degrees(self.deviation):9.2f} deg "
                f"(hinge pin at {self.hinge_height[k] * 1e3:.0f} mm)",
            ]
        )


def parallel_lift(machine: Loader, samples: int = 101) -> ParallelLift:
    """The bucket's angle over the lift with the tilt cylinder held (module docstring).

    Parameters
    ----------
    machine : Loader
    samples : int
        Lift lengths, evenly spaced from the ground pose to full lift (at least 2).

    Returns
    -------
    ParallelLift

    Raises
    ------
    ValueError
        Where ``samples`` is under 2.
    ModelError
        Naming the machine file, where a pose of the lift does not assemble with the tilt held.
    """
    if samples < 2:
        raise ValueError(f"samples must be at least 2, not {samples}")
    lift0, tilt = ground_pose(machine)
    lift = np.linspace(lift0, machine.full_lift(), samples)
    res = machine.solve(np.column_stack([lift, np.full_like(lift, tilt)]))
    if not res.status.ok.all():
        bad = float(lift[np.flatnonzero(~res.status.ok)[0]])
        raise ModelError(
            f"the linkage does not assemble at lift length {bad * 1e3:.1f} mm with the tilt "
            f"cylinder held at {tilt * 1e3:.1f} mm (the length that levels the bucket on the "
            "ground)",
            table="cylinders",
            source=machine.source,
        )
    pos = res.positions
    height = pos[:, machine.index(machine.pins.hinge), 1] - machine.ground_line
    return ParallelLift(machine.name, float(tilt), lift, height, floor_angle(machine, pos))
