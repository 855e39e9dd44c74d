"""An excavator's hydraulics as its spec sheet gives them (``excavkin excavator cycle``): each
cylinder's no-load speeds and stroke times at the pumps' full flow
([`strokes`][excavkin.machinery.flows.strokes]), the dig–swing–dump cycle
([`cycle_time`][excavkin.excavator.hydraulics.cycle_time]), the hydraulic power along it
([`cycle_power`][excavkin.excavator.cycle_power.cycle_power]), and the buckling check of each
cylinder at its relief fully extended and at the ISO 6015 rated poses of the arm and the
bucket cylinder (tool force at the lip, no gravity).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from excavkin.excavator.cycle_power import CyclePower
from excavkin.excavator.forces import Working
from excavkin.excavator.hydraulics import Buckling, Cycle, Stroke
from excavkin.excavator.machine import Machine, mm_field

if TYPE_CHECKING:
    import pandas as pd

    from excavkin.excavator.plots import ExcavatorPlot

#: how the buckling check chooses its formula
BUCKLING_NOTE = "Euler above L/r = √(2π²E/σy), Johnson below"
#: the kinds of `CycleSheet.to_frame`'s columns
FRAME_KINDS: dict[str, str] = {
    "force": "force",
    "length": "length",
    "critical": "force",
    "flow": "volume_flow",
    "extend_speed": "velocity",
    "retract_speed": "velocity",
    "extend_time": "time",
    "retract_time": "time",
    "time": "time",
    "peak_power": "power",
    "peak_pressure": "pressure",
    "work": "energy",
}


@dataclass(frozen=True)
class CycleSheet:
    """Strokes, cycle, power and buckling checks of an excavator (`hydraulic_cycle`).

    Attributes
    ----------
    machine : Machine
    strokes : tuple of Stroke
        One per cylinder role.
    cycle : Cycle
        The dig–swing–dump cycle's phases (s).
    power : CyclePower
        The power along the cycle, one motion at a time.
    buckling : tuple of (str, tuple of Buckling)
        Each case (``"relief, fully extended"``, ``"ISO 6015 arm force"``,
        ``"ISO 6015 bucket force"``) and its check of every cylinder.
    """

    machine: Machine
    strokes: tuple[Stroke, ...]
    cycle: Cycle
    power: CyclePower
    buckling: tuple[tuple[str, tuple[Buckling, ...]], ...]

    def _phases(self) -> tuple[tuple[str, float], ...]:
        cy = self.cycle
        return (
            ("dig (arm + bucket in)", cy.dig),
            ("boom up", cy.boom_up),
            ("swing (one way)", cy.swing),
            ("dump (arm + bucket out)", cy.dump),
            ("boom down", cy.boom_down),
            ("cycle, one motion at a time", cy.sequential),
            ("cycle, swing overlapping boom", cy.overlapped),
        )

    def to_frame(self) -> pd.DataFrame:
        """The strokes, the cycle's phases, the power of each phase and the buckling checks,
        one row each (its ``section``), SI.

        Returns
        -------
        pandas.DataFrame
            ``section`` (``stroke``, ``cycle``, ``power``, ``buckling``) and each section's
            columns; its ``attrs`` name the machine and each column's kind.
        """

        from excavkin.kinematics.columns import kinds_frame

        rows: list[dict[str, Any]] = [
            {
                "section": "stroke",
                "cylinder": s.role,
                "flow": s.flow,
                "extend_speed": s.extend_speed,
                "retract_speed": s.retract_speed,
                "extend_time": s.extend_time,
                "retract_time": s.retract_time,
            }
            for s in self.strokes
        ]
        rows += [{"section": "cycle", "phase": n, "time": v} for n, v in self._phases()]
        rows += [
            {
                "section": "power",
                "phase": ph.name,
                "cylinder": ph.role,
                "time": ph.duration,
                "peak_power": ph.peak,
                "peak_pressure": ph.peak_pressure,
                "over_pressure": ph.over_pressure,
                "work": ph.work,
            }
            for ph in self.power.phases
            if ph.role is not None
        ]
        rows += [
            {
                "section": "buckling",
                "case": case,
                "cylinder": b.role,
                "length": float(b.length[0]),
                "force": float(b.force[0]),
                "slenderness": float(b.slenderness[0]),
                "critical": float(b.critical[0]),
                "formula": str(b.formula[0]),
                "safety": float(b.safety[0]),
            }
            for case, checks in self.buckling
            for b in checks
        ]
        return kinds_frame(rows, FRAME_KINDS, self.machine.name)

    def sections(self) -> dict[str, str]:
        """The printout of ``excavkin excavator cycle``, section by section.

        Returns
        -------
        dict of str to str
            ``"strokes"``, ``"cycle"``, ``"power"`` and ``"buckling"`` → its lines.
        """
        m = self.machine
        h = m.hydraulics
        assert h is not None  # strokes() refuses a machine without hydraulics
        strokes = [
            f"{m.name} — hydraulics (no-load, full-flow speeds; flows of the feeding pumps add)",
            f"{'cylinder':<8} {'count':>5} {'flow L/min':>10} {'ext m/s':>8} {'ret m/s':>8} "
            f"{'ext s':>6} {'ret s':>6}",
        ]
        strokes += [
            f"{s.role:<8} {c.count:>5} {s.flow * 6e4:10.0f} {s.extend_speed:8.3f} "
            f"{s.retract_speed:8.3f} {s.extend_time:6.2f} {s.retract_time:6.2f}"
            for c, s in zip(m.cylinders, self.strokes, strict=True)
        ]
        cycle = [
            f"Cycle (full strokes; swing {math.degrees(h.swing_angle):.0f}° at "
            f"{h.swing_speed * 30 / math.pi:.1f} rpm, constant speed), s",
            *(f"  {name:<30} {value:6.2f}" for name, value in self._phases()),
        ]
        cp = self.power
        power = [
            "Power along the cycle, one motion at a time (weight and inertia, no soil; "
            f"pumps: {cp.supply / 1e3:.0f} kW at full flow and working pressure)",
            f"  {'phase':<14} {'peak kW':>8} {'peak bar':>9} {'work kJ':>8}",
        ]
        for ph in cp.phases:
            if ph.role is None:
                continue
            warn = (
                f"  beyond the working pressure ({ph.working_pressure / 1e5:.0f} bar) over "
                f"{ph.over_pressure:.0%} of the stroke: cannot run at full flow there"
                if ph.over_pressure > 0.0
                else ""
            )
            power.append(
                f"  {ph.name:<14} {ph.peak / 1e3:8.1f} {ph.peak_pressure / 1e5:9.0f} "
                f"{ph.work / 1e3:8.1f}{warn}"
            )
        buckling = [
            f"Buckling (one cylinder; rod alone over the pin-to-pin length, pinned-pinned; "
            f"E = {h.modulus / 1e9:.0f} GPa, yield {h.rod_yield / 1e6:.0f} MPa)",
            f"{'case':<26} {'cylinder':<8} {'length':>8} {'push kN':>8} {'L/r':>6} "
            f"{'P_cr kN':>8} {'formula':<8} {'safety':>6}",
        ]
        for case, checks in self.buckling:
            for b in checks:
                safety = float(b.safety[0])
                buckling.append(
                    f"{case:<26} {b.role:<8} {mm_field(float(b.length[0]))} "
                    f"{float(b.force[0]) / 1e3:8.1f} {float(b.slenderness[0]):6.1f} "
                    f"{float(b.critical[0]) / 1e3:8.1f} {str(b.formula[0]):<8} "
                    + (f"{safety:6.2f}" if math.isfinite(safety) else f"{'pulls':>6}")
                )
        buckling.append(
            f"(ISO 6015: rated poses, tool force at the lip, no gravity; {BUCKLING_NOTE})"
        )
        parts = {"strokes": strokes, "cycle": cycle, "power": power, "buckling": buckling}
        return {k: "\n".join(v) for k, v in parts.items()}

    def summary(self) -> str:
        """The whole printout of ``excavkin excavator cycle``.

        Returns
        -------
        str
        """
        return "\n".join(self.sections().values())

    def plot(self) -> ExcavatorPlot:
        """The power and the inlet pressure along the cycle
        ([`plot_cycle_power`][excavkin.excavator.cycle_plots.plot_cycle_power]).

        Returns
        -------
        ExcavatorPlot
        """
        from excavkin.excavator.cycle_plots import plot_cycle_power

        return plot_cycle_power(self.power, title=f"{self.machine.name} — power along the cycle")


def hydraulic_cycle(
    machine: Machine,
    *,
    stages: Callable[[], Callable[[int, int], None] | None] | None = None,
) -> CycleSheet:
    """The strokes, the cycle, its power and the buckling checks of an excavator (module
    docstring).

    Parameters
    ----------
    machine : Machine
        With ``[hydraulics]``.
    stages : callable, optional
        ``stages()`` → the next rated force's ``progress(done, total)`` (a staged progress
        bar over the arm's and the bucket's rated-force searches).

    Returns
    -------
    CycleSheet

    Raises
    ------
    InputError
        The machine has no hydraulics.
    """
    from excavkin.excavator.cycle_power import cycle_power
    from excavkin.excavator.forces import rated_force, tool_forces
    from excavkin.excavator.hydraulics import (
        cycle_time,
        pose_buckling,
        relief_buckling,
        strokes,
    )

    st = strokes(machine)
    cy = cycle_time(machine)
    cp = cycle_power(machine)
    checks: list[tuple[str, tuple[Buckling, ...]]] = [
        ("relief, fully extended", relief_buckling(machine))
    ]
    working: tuple[Working, ...] = ("arm", "bucket")
    rated = {
        w: rated_force(machine, w, progress=None if stages is None else stages()) for w in working
    }
    for w, r in rated.items():
        tf = tool_forces(machine, r.lengths[None, :], w, gravity=False)
        checks.append(
            (
                f"ISO 6015 {w} force",
                pose_buckling(machine, r.lengths[None, :], tf.cylinder_force),
            )
        )
    return CycleSheet(machine, tuple(st), cy, cp, tuple(checks))
