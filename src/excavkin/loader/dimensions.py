r"""A loader's dimensions per SAE J732 / ISO 7131, from the engine's kinematics.

The definitions follow SAE J732 (JUN92, "Specification definitions — loaders") and ISO 7131
("Loaders — Terminology and commercial specifications"), which name the same figures; each is
computed at a pose the engine solves ([`Loader.solve`][excavkin.loader.machine.Loader.solve]),
found by [`excavkin.loader.poses`]:

* **hinge-pin height at full lift**: the bucket hinge pin above the ground, lift cylinders at
  full lift;
* **dump clearance at full lift and 45° discharge**: the cutting edge above the ground, lift at
  full lift, the bucket floor 45° below the horizontal;
* **dump reach at full lift and 45° discharge**: the cutting edge ahead of the foremost point of
  the machine (the front tyres), same pose;
* **digging depth**: the cutting edge below the ground, lift arm fully lowered, floor level
  (negative where the edge stays above the ground);
* **rollback angle at ground, at carry and at full lift**: the floor above the horizontal with
  the tilt cylinder at full rollback, the lift arm at the ground pose (floor level, edge on the
  ground), at the carry position (the hinge pin at the machine file's ``carry_height``) and at
  full lift;
* **dump angle at full lift**: the floor below the horizontal, tilt at full dump, full lift.

Angles of the bucket are those of its floor, heel → cutting edge.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.loader.machine import Loader, floor_angle, table_attrs
from excavkin.loader.poses import (
    assembling_tilt,
    ground_pose,
    lift_for_hinge_height,
    tilt_for_angle,
)

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.loader.plots import LoaderPlot

#: the discharge angle of dump clearance and reach (SAE J732, ISO 7131): 45° below horizontal
DISCHARGE = math.radians(45.0)


@dataclass(frozen=True, slots=True)
class Figure:
    """One dimension and the pose it is taken at.

    Attributes
    ----------
    name : str
    value : float
        SI (m or rad); NaN where the pose is not reached within the strokes.
    unit : {"m", "rad"}
    lengths : ndarray, shape (2,)
        Lift and tilt lengths of its pose (m).
    definition : str
    """

    name: str
    value: float
    unit: str
    lengths: F
    definition: str


@dataclass(frozen=True, slots=True)
class Dimensions:
    """A loader's SAE J732 / ISO 7131 dimensions.

    Attributes
    ----------
    machine : str
        Its name.
    figures : tuple of Figure
        In the order of the module docstring.
    """

    machine: str
    figures: tuple[Figure, ...]

    def __getitem__(self, name: str) -> float:
        for f in self.figures:
            if f.name == name:
                return f.value
        raise KeyError(f"{name!r} (known: {', '.join(f.name for f in self.figures)})")

    def to_frame(self) -> pd.DataFrame:
        """The figures as a table, SI: one row each, with the lengths of its pose.

        Returns
        -------
        pandas.DataFrame
            Columns ``figure``, ``value`` (SI, its unit in ``unit``: m or rad), ``lift_cyl``,
            ``tilt_cyl`` and ``definition``; ``attrs`` record the machine and the columns'
            kinds and units (``excavkin.model``, ``excavkin.kinds``, ``excavkin.units``).
        """
        import pandas as pd

        frame = pd.DataFrame(
            {
                "figure": [f.name for f in self.figures],
                "value": [f.value for f in self.figures],
                "unit": [f.unit for f in self.figures],
                "lift_cyl": [f.lengths[0] for f in self.figures],
                "tilt_cyl": [f.lengths[1] for f in self.figures],
                "definition": [f.definition for f in self.figures],
            }
        )
        frame.attrs.update(table_attrs(self.machine, {"lift_cyl": "length", "tilt_cyl": "length"}))
        return frame

    def plot(self, machine: Loader, *, ax: Axes | None = None) -> LoaderPlot:
        """Side view of the dimensions at their poses (SAE J732 / ISO 7131).

        Parameters
        ----------
        machine : Loader
            The machine these dimensions are of (its linkage is drawn at their poses).
        ax : matplotlib Axes, optional
            Drawn on; a new figure when omitted.

        Returns
        -------
        LoaderPlot
        """
        from excavkin.loader.plots import plot_dimensions

        return plot_dimensions(machine, self, ax=ax)

    def summary(self) -> str:
        """The figures in mm and degrees, one line each.

        Returns
        -------
        str
        """
        lines = [f"{self.machine}: dimensions (SAE J732 / ISO 7131)"]
        for f in self.figures:
            deg, mm = math.degrees(f.value), f.value * 1e3
            shown = f"{deg:7.1f} deg" if f.unit == "rad" else f"{mm:7.0f} mm"
            lines.append(f"  {f.name:<34} {shown}")
        return "\n".join(lines)


def dimensions(machine: Loader) -> Dimensions:
    """The loader's SAE J732 / ISO 7131 dimensions (module docstring).

    Parameters
    ----------
    machine : Loader

    Returns
    -------
    Dimensions
    """
    up, low = machine.full_lift(), machine.lowest()
    roll, dump = machine.full_rollback(), machine.full_dump()
    ground = ground_pose(machine)
    carry = lift_for_hinge_height(machine, machine.carry_height)
    lifts = np.array([up, low])
    tilts = tilt_for_angle(machine, lifts, np.array([-DISCHARGE, 0.0]))
    poses = np.array(
        [
            [up, assembling_tilt(machine, up)[0]],  # the hinge pin: the lift arm's alone
            [up, tilts[0]],  # 45° discharge
            [low, tilts[1]],  # digging depth
            [ground[0], roll],
            [carry, roll],
            [up, roll],
            [up, dump],
        ]
    )
    good = np.all(np.isfinite(poses), axis=1)
    res = machine.solve(np.where(good[:, None], poses, machine.lengths_min))
    pos = res.positions
    ok = good & res.status.ok
    yg = machine.ground_line
    ib, ie = machine.index(machine.pins.hinge), machine.index(machine.linkage.edge)
    ang = floor_angle(machine, pos)
    values = [
        pos[0, ib, 1] - yg,
        pos[1, ie, 1] - yg,
        pos[1, ie, 0] - machine.chassis.front_most,
        yg - pos[2, ie, 1],
        ang[3],
        ang[4],
        ang[5],
        -ang[6],
    ]
    rows = (
        ("hinge-pin height at full lift", "m", 0, "hinge pin above the ground, full lift"),
        ("dump clearance at 45 deg", "m", 1, "cutting edge above the ground, full lift, 45° dump"),
        (
            "dump reach at 45 deg",
            "m",
            1,
            "cutting edge ahead of the front tyres, full lift, 45° dump",
        ),
        ("digging depth", "m", 2, "cutting edge below the ground, arm lowered, floor level"),
        ("rollback at ground", "rad", 3, "floor above horizontal, full rollback, edge at ground"),
        ("rollback at carry", "rad", 4, "floor above horizontal, full rollback, carry position"),
        ("rollback at full lift", "rad", 5, "floor above horizontal, full rollback, full lift"),
        ("dump angle at full lift", "rad", 6, "floor below horizontal, full dump, full lift"),
    )
    figures = tuple(
        Figure(
            name,
            float(values[i]) if ok[k] else float("nan"),
            unit,
            poses[k].copy(),
            definition,
        )
        for i, (name, unit, k, definition) in enumerate(rows)
    )
    return Dimensions(machine.name, figures)
