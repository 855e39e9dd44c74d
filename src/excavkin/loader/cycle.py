r"""Hydraulic cycle times of a wheel loader per SAE J732: raise, lower empty, dump.

Each phase moves one function alone at the flow of every pump that feeds it (the pumps'
confluence, `excavkin.machinery.flows`): its time is the swept volume over the flow,
``A·ΔL / Q`` with ``A`` the inlet area of all ``count`` cylinders (the bore extending, the
annulus retracting) and ``ΔL`` the length the phase sweeps:

- **raise**: the lift cylinders from the ground pose (the floor level, the cutting edge on the
  ground, [`ground_pose`][excavkin.loader.poses.ground_pose]) to full lift, the bucket at full
  rollback carrying the rated load (the rated operating capacity, SAE J818, at the rated load's
  centre of gravity);
- **lower empty**: full lift back to the ground pose's lift length, the bucket empty at full
  rollback. No float or regeneration is modelled: the pump fills the inlet side (the rod side
  for a lift cylinder that extends to raise) at its full flow, so the lower time is the plain
  rod-side fill;
- **dump**: the tilt cylinder from full rollback to full dump at full lift, the bucket empty
  (the load leaves it).

Leakage, valve losses, pump regulation and cushioning are left out, as in
`excavkin.machinery.flows`: the times are a spec sheet's no-load, full-flow figures.

**Pressure and power.** At rest at each of the phase's poses the moving cylinder carries the
static force of virtual power, ``f_c = W·∂y_P/∂L_c + G_c`` (the load W at its centre of
gravity P, G the linkage's weight terms, [`gravity_terms`][excavkin.machinery.capped_force.
gravity_terms]); its inlet pressure and hydraulic power ``p·Q`` are those of
[`power_of`][excavkin.machinery.flows.power_of]. A phase's figure is its largest pressure over
the stroke and the power at it; a negative pressure is an overrunning load (the weight drives
the cylinder, the outlet throttle holds it back); a pressure above the circuit's working
pressure is named.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np

from excavkin.loader.machine import Loader, bucket_frame_point, floor_angle_rate, table_attrs
from excavkin.loader.machine import transfer as transfer_functions
from excavkin.machinery.capped_force import gravity_terms
from excavkin.machinery.flows import cylinder_speed, hydraulics_of, power_of

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.loader.plots import LoaderPlot

#: poses sampled along each phase for its static pressure
SAMPLES = 101


@dataclass(frozen=True, slots=True)
class Phase:
    """One phase of the cycle.

    Attributes
    ----------
    name : {"raise", "lower empty", "dump"}
    role : str
        The moving cylinder's role.
    direction : {"extend", "retract"}
    start, end : float
        Its length at the start and the end of the phase (m).
    flow : float
        The pumps' flow into it (m³/s).
    area : float
        The inlet area of all its cylinders (m²).
    time : float
        ``area·|end − start| / flow`` (s).
    load : float
        The mass carried at the rated load's centre of gravity (kg); 0 empty.
    pressure : float
        The largest static inlet pressure over the stroke (Pa); < 0 overrunning.
    power : float
        ``pressure·flow`` there (W).
    length_at_peak : float
        The moving cylinder's length there (m).
    working : float
        The circuit's working pressure (Pa).
    """

    name: str
    role: str
    direction: str
    start: float
    end: float
    flow: float
    area: float
    time: float
    load: float
    pressure: float
    power: float
    length_at_peak: float
    working: float

    @property
    def over_working(self) -> bool:
        """Whether the phase needs more than its circuit's working pressure."""
        return self.pressure > self.working


@dataclass(frozen=True, slots=True)
class Cycle:
    """SAE J732 hydraulic cycle: raise, lower empty and dump.

    Attributes
    ----------
    machine : str
    phases : tuple of Phase
        Raise, lower empty, dump.
    """

    machine: str
    phases: tuple[Phase, ...]

    def __getitem__(self, name: str) -> Phase:
        for p in self.phases:
            if p.name == name:
                return p
        from excavkin.errors import unknown_name

        raise unknown_name("cycle phase", name, [p.name for p in self.phases])

    @property
    def total(self) -> float:
        """Raise + lower empty + dump (s)."""
        return float(sum(p.time for p in self.phases))

    def to_frame(self) -> pd.DataFrame:
        """One row per phase, SI.

        Returns
        -------
        pandas.DataFrame
            ``attrs`` record the machine and the columns' kinds and units.
        """
        import pandas as pd

        ph = self.phases
        cols = {
            "phase": [p.name for p in ph],
            "cylinder": [p.role for p in ph],
            "direction": [p.direction for p in ph],
            "start": [p.start for p in ph],
            "end": [p.end for p in ph],
            "flow": [p.flow for p in ph],
            "time": [p.time for p in ph],
            "load": [p.load for p in ph],
            "pressure": [p.pressure for p in ph],
            "power": [p.power for p in ph],
            "length_at_peak": [p.length_at_peak for p in ph],
            "working": [p.working for p in ph],
            "over_working": [p.over_working for p in ph],
        }
        frame = pd.DataFrame(cols)
        kinds = {
            **dict.fromkeys(("start", "end", "length_at_peak"), "length"),
            "flow": "volume_flow",
            "time": "time",
            "load": "mass",
            "pressure": "pressure",
            "working": "pressure",
            "power": "power",
        }
        frame.attrs.update(table_attrs(self.machine, kinds))
        return frame

    def plot(self, *, ax: Axes | None = None) -> LoaderPlot:
        """The phases' times with their peak pressures (SAE J732).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Drawn on; a new figure when omitted.

        Returns
        -------
        LoaderPlot
        """
        from excavkin.loader.plots import plot_cycle

        return plot_cycle(self, ax=ax)

    def summary(self) -> str:
        """Each phase's time, pressure and power, and the total.

        Returns
        -------
        str
        """
        lines = [f"{self.machine}: hydraulic cycle (SAE J732), pumps at full flow"]
        for p in self.phases:
            note = ""
            if p.pressure < 0.0:
                note = "  (overrunning: the weight drives it)"
            elif p.over_working:
                note = f"  (above the working pressure {p.working / 1e6:.1f} MPa)"
            lines.append(
                f"  {p.name:<12} {p.time:6.2f} s  {p.role} {p.direction:<7} "
                f"{p.flow * 6e4:5.0f} L/min  {p.pressure / 1e6:6.1f} MPa  "
                f"{p.power / 1e3:6.1f} kW{note}"
            )
        lines.append(f"  total        {self.total:6.2f} s")
        return "\n".join(lines)


def _phase(
    machine: Loader, name: str, w: int, start: float, end: float, held: float, load: float
) -> Phase:
    """One function ``w`` moving from ``start`` to ``end``, the other held at ``held``."""
    c = machine.cylinders[w]
    h = hydraulics_of(machine)
    q = h.flow(c.role)
    direction: Literal["extend", "retract"] = "extend" if end > start else "retract"
    speed = float(cylinder_speed(c, q, direction))
    area = c.bore_area if direction == "extend" else c.annulus_area
    moving = np.linspace(start, end, SAMPLES)
    L = np.empty((SAMPLES, 2))
    L[:, w] = moving
    L[:, 1 - w] = held
    tr = transfer_functions(machine, L)
    force = gravity_terms(machine, tr.d)
    if load > 0.0:
        point = bucket_frame_point(machine, tr.positions, machine.bucket.load_cg)
        hinge, d_hinge = tr.point(machine, machine.pins.hinge)
        rel = point - hinge
        da = floor_angle_rate(machine, tr)
        dy = d_hinge[:, 1, :] + rel[:, 0, None] * da  # ∂y_P/∂L
        force = force + load * machine.gravity * dy
    rates = np.zeros_like(L)
    rates[:, w] = speed if direction == "extend" else -speed
    pw = power_of(machine, force, rates)
    p = np.where(tr.ok, pw.pressure[:, w], np.nan)
    k = int(np.nanargmax(p))
    return Phase(
        name,
        c.role,
        direction,
        start,
        end,
        q,
        area,
        abs(end - start) / speed,
        load,
        float(p[k]),
        float(pw.pump_power[k, w]),
        float(moving[k]),
        machine.circuit(c.role).working,
    )


def cycle(machine: Loader, load: float | None = None) -> Cycle:
    """The SAE J732 raise, lower-empty and dump times, with each phase's pressure and power.

    Parameters
    ----------
    machine : Loader
        With ``[hydraulics]`` pumps feeding its lift and tilt cylinders.
    load : float, optional
        The mass raised (kg); default the rated operating capacity (SAE J818).

    Returns
    -------
    Cycle

    Raises
    ------
    InputError
        The machine has no hydraulics, or ``load`` is negative or not finite.
    ModelError
        No pose within the strokes sets the floor level with the edge on the ground.
    """
    from excavkin.errors import InputError
    from excavkin.loader.poses import ground_pose

    hydraulics_of(machine)
    if load is None:
        from excavkin.loader.tipping import static_tipping

        load = static_tipping(machine).rated_operating_capacity
    if not (np.isfinite(load) and load >= 0.0):
        raise InputError(f"the load must be a finite mass of 0 kg or more, not {load}")
    ground = float(ground_pose(machine)[0])
    top, roll = machine.full_lift(), machine.full_rollback()
    return Cycle(
        machine.name,
        (
            _phase(machine, "raise", 0, ground, top, roll, float(load)),
            _phase(machine, "lower empty", 0, top, ground, roll, 0.0),
            _phase(machine, "dump", 1, roll, machine.full_dump(), top, 0.0),
        ),
    )
