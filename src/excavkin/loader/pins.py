r"""Pin loads and cylinder forces of a wheel loader over its lift, in three load cases.

At lift lengths from the ground pose's (the floor level, the edge on the ground,
[`ground_pose`][excavkin.loader.poses.ground_pose]) to full lift, the machine at rest with both
cylinders holding, the linkage's weight ([`weight_loads`][excavkin.machinery.cylinder_machine.
CylinderMachine.weight_loads]) and one external load on the bucket:

- **breakout**: the tilt circuit's SAE J732 breakout force
  ([`breakout`][excavkin.loader.breakout.breakout]) held vertically downward 100 mm behind the
  cutting edge, the bucket's floor level (the restraint of the breakout test, carried over the
  lift with the lift cylinders holding instead of a block under the hinge pin);
- **rated load**: the rated operating capacity (SAE J818) at the rated load's centre of
  gravity, the bucket at full rollback;
- **tipping**: the straight machine's static tipping load there
  ([`static_tipping`][excavkin.loader.tipping.static_tipping]), the bucket at full rollback.

A load at a point X of the bucket acts on the general kinetostatics as the same force at the
hinge pin B and the couple ``(X − B) × P``. Each pin's load and each cylinder's force come from
[`pin_forces`][excavkin.machinery.pin_loads.pin_forces]: the largest force the pin passes to
any one of its members.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import BoolArray as B
from excavkin.arrays import FloatArray as F
from excavkin.loader.machine import Loader, bucket_frame_point, floor_angle, table_attrs
from excavkin.machinery.cylinders import Cylinder
from excavkin.machinery.pin_loads import first_largest, pin_forces

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.kinetostatics import ForceResult
    from excavkin.loader.plots import LoaderPlot

#: the load cases, in order
CASES = ("breakout", "rated load", "tipping")


@dataclass(frozen=True, slots=True)
class PinCase:
    """Pin loads and cylinder forces of one load case at n lift lengths (SI).

    Attributes
    ----------
    name : {"breakout", "rated load", "tipping"}
    force : ndarray, shape (n, 2)
        The external load on the bucket (N).
    point : ndarray, shape (n, 2)
        Where it acts (m).
    lengths : ndarray, shape (n, 2)
        Lift and tilt lengths (m).
    hinge_height : ndarray, shape (n,)
        The hinge pin above the ground (m).
    pins : tuple of str
        The pins' point names, in the engine's order.
    members : tuple of tuple of str
        Per pin, its members (`PinForces`).
    load : ndarray, shape (n, n_pins)
        Each pin's load (N); NaN where the pose does not assemble.
    cylinder_force : ndarray, shape (n, 2)
        Lift and tilt cylinder forces (N, > 0 pushing), all ``count`` cylinders together.
    ok : ndarray of bool, shape (n,)
    forces : ForceResult
        The kinetostatics the loads come from.
    """

    name: str
    force: F
    point: F
    lengths: F
    hinge_height: F
    pins: tuple[str, ...]
    members: tuple[tuple[str, ...], ...]
    load: F
    cylinder_force: F
    ok: B
    forces: ForceResult


@dataclass(frozen=True, slots=True)
class LoaderPins:
    """Pin loads over the lift in the breakout, rated-load and tipping cases.

    Attributes
    ----------
    machine : str
    labels : dict of str to str
        A pin's name in the summary (``"lift-arm pin"``, ``"hinge pin"``); others by point.
    cases : tuple of PinCase
    cylinders : tuple of Cylinder
        Lift and tilt, for their areas.
    relief : tuple of float
        Their circuits' port relief pressures (Pa).
    """

    machine: str
    labels: dict[str, str]
    cases: tuple[PinCase, ...]
    cylinders: tuple[Cylinder, ...]
    relief: tuple[float, ...]

    def __getitem__(self, name: str) -> PinCase:
        for c in self.cases:
            if c.name == name:
                return c
        from excavkin.errors import unknown_name

        raise unknown_name("load case", name, [c.name for c in self.cases])

    def largest(self) -> list[tuple[str, float, str, float]]:
        """Each pin's largest load over every case and height.

        Returns
        -------
        list of (pin, load, case, hinge height)
            The pin's point name, the load (N), the case and the hinge pin's height (m).
        """
        out = []
        for j, pin in enumerate(self.cases[0].pins):
            best = (pin, -np.inf, "", np.nan)
            for c in self.cases:
                col = np.where(c.ok, c.load[:, j], -np.inf)
                k = first_largest(col)
                if col[k] > best[1]:
                    best = (pin, float(col[k]), c.name, float(c.hinge_height[k]))
            out.append(best)
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per case and lift length, SI: the pose, the load, both cylinder forces and
        one column ``pin.<name>`` per pin.

        Returns
        -------
        pandas.DataFrame
            ``attrs`` record the machine and the columns' kinds and units.
        """
        import pandas as pd

        parts = []
        for c in self.cases:
            cols: dict[str, object] = {
                "case": c.name,
                "lift_cyl": c.lengths[:, 0],
                "tilt_cyl": c.lengths[:, 1],
                "hinge_height": c.hinge_height,
                "load_x": c.point[:, 0],
                "load_y": c.point[:, 1],
                "force_x": c.force[:, 0],
                "force_y": c.force[:, 1],
                "lift_cyl_force": np.where(c.ok, c.cylinder_force[:, 0], np.nan),
                "tilt_cyl_force": np.where(c.ok, c.cylinder_force[:, 1], np.nan),
            }
            for j, p in enumerate(c.pins):
                cols[f"pin.{p}"] = c.load[:, j]
            parts.append(pd.DataFrame(cols))
        frame = pd.concat(parts, ignore_index=True)
        forces = ["force_x", "force_y", "lift_cyl_force", "tilt_cyl_force"]
        forces += [f"pin.{p}" for p in self.cases[0].pins]
        kinds = {
            **dict.fromkeys(("lift_cyl", "tilt_cyl", "hinge_height", "load_x", "load_y"), "length"),
            **dict.fromkeys(forces, "force"),
        }
        frame.attrs.update(table_attrs(self.machine, kinds))
        return frame

    def plot(self, *, ax: Axes | None = None) -> LoaderPlot:
        """Each pin's largest load over the lift in each load case.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Drawn on; a new figure when omitted.

        Returns
        -------
        LoaderPlot
        """
        from excavkin.loader.plots import plot_pins

        return plot_pins(self, ax=ax)

    def summary(self) -> str:
        """Each pin's largest load with its case and height, and each cylinder's largest push
        and pull with its pressure, named where beyond the circuit's port relief.

        Returns
        -------
        str
        """
        lines = [f"{self.machine}: pin loads over the lift (breakout, rated load, tipping)"]
        for pin, load, case, h in self.largest():
            name = self.labels.get(pin, pin)
            lines.append(
                f"  pin {name:<14} {load / 1e3:8.1f} kN  ({case}, hinge at {h * 1e3:.0f} mm)"
            )
        for w, role in enumerate(("lift", "tilt")):
            for word, pick in (("push", np.argmax), ("pull", np.argmin)):
                best: tuple[float, str, float] = (0.0, "", np.nan)
                for c in self.cases:
                    f = np.where(c.ok, c.cylinder_force[:, w], np.nan)
                    if np.isnan(f).all():
                        continue
                    k = int(pick(np.where(np.isnan(f), 0.0, f)))
                    if abs(f[k]) > abs(best[0]):
                        best = (float(f[k]), c.name, float(c.hinge_height[k]))
                if (word == "push") == (best[0] > 0.0):
                    cyl = self.cylinders[w]
                    p = abs(best[0]) / (cyl.bore_area if word == "push" else cyl.annulus_area)
                    note = (
                        ""
                        if p <= self.relief[w]
                        else (f", beyond the port relief {self.relief[w] / 1e6:.1f} MPa")
                    )
                    lines.append(
                        f"  {role} cylinders {word:<5} {abs(best[0]) / 1e3:8.1f} kN  "
                        f"{p / 1e6:5.1f} MPa  ({best[1]}, hinge at {best[2] * 1e3:.0f} mm{note})"
                    )
        return "\n".join(lines)


def _case(machine: Loader, name: str, L: F, weight: float) -> PinCase:
    """The linkage's weight and one load on the bucket at lengths ``L``."""
    from excavkin.kinetostatics import PointForce, Torque

    n = len(L)
    ok: B = np.asarray(np.isfinite(L).all(axis=1))
    safe = np.where(ok[:, None], L, np.array([machine.lengths_min[0], machine.full_rollback()]))
    res = machine.solve(safe)  # at rest
    ok = ok & res.status.ok & machine.within_stroke(safe)
    pos = res.positions
    hinge_name = machine.pins.hinge
    hinge = pos[:, machine.index(hinge_name)]
    if name == "breakout":
        edge = pos[:, machine.index(machine.linkage.edge)]
        a = floor_angle(machine, pos)
        from excavkin.loader.breakout import BEHIND_EDGE

        point = edge - BEHIND_EDGE * np.column_stack([np.cos(a), np.sin(a)])
    else:
        point = bucket_frame_point(machine, pos, machine.bucket.load_cg)
    P = np.zeros((n, 2))
    P[:, 1] = -weight
    r = point - hinge
    tau = r[:, 0] * P[:, 1] - r[:, 1] * P[:, 0]
    body = machine.linkage.bucket
    loads = [
        *machine.weight_loads(),
        PointForce(f"{name} load", body, hinge_name, P),
        Torque(f"{name} load moment", body, tau),
    ]
    fr = machine.mechanism.forces(res, loads)
    ok = ok & fr.ok
    pf = pin_forces(fr, machine.cylinders, machine.pins.cyl_ends)
    nan = ~ok
    return PinCase(
        name,
        P,
        np.where(nan[:, None], np.nan, point),
        L,
        np.where(nan, np.nan, hinge[:, 1] - machine.ground_line),
        pf.pins,
        pf.members,
        np.where(nan[:, None], np.nan, pf.load),
        pf.cylinder_force,
        np.asarray(ok),
        fr,
    )


def pin_loads(machine: Loader, samples: int = 21) -> LoaderPins:
    """Pin loads and cylinder forces over the lift in the three load cases (module docstring).

    Parameters
    ----------
    machine : Loader
    samples : int
        Lift lengths, evenly from the ground pose to full lift (at least 2).

    Returns
    -------
    LoaderPins

    Raises
    ------
    InputError
        ``samples`` below 2.
    ModelError
        No pose within the strokes sets the floor level with the edge on the ground.
    """
    if samples < 2:
        from excavkin.errors import InputError

        raise InputError(f"samples must be at least 2, not {samples}")
    from excavkin.loader.breakout import breakout
    from excavkin.loader.poses import ground_pose, tilt_for_angle
    from excavkin.loader.tipping import static_tipping

    g = machine.gravity
    lift = np.linspace(float(ground_pose(machine)[0]), machine.full_lift(), samples)
    level = np.column_stack([lift, tilt_for_angle(machine, lift, 0.0)])
    rolled = np.column_stack([lift, np.full(samples, machine.full_rollback())])
    tip = static_tipping(machine)
    cases = (
        _case(machine, "breakout", level, breakout(machine).tilt.force),
        _case(machine, "rated load", rolled, tip.rated_operating_capacity * g),
        _case(machine, "tipping", rolled, tip.straight.load * g),
    )
    labels = {machine.pins.lift_arm_pin: "lift-arm pin", machine.pins.hinge: "hinge pin"}
    relief = tuple(machine.circuit(c.role).relief for c in machine.cylinders)
    return LoaderPins(machine.name, labels, cases, machine.cylinders, relief)
