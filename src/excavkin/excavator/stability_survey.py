"""An excavator's stability as its spec sheet gives it (``excavkin excavator stability``): the
rated tool forces capped by the cylinders, tipping and slipping (ISO 6015 §4.5) with the front
swung as asked, and over the working range the least tipping load of a load hung at the bucket
pin (over the front and over the side) and which limit binds the lip's tool force of the arm and
the bucket cylinder.

The rated forces are [`base_rated_force`][excavkin.excavator.stability.base_rated_force]'s; the
sweep is a ``samples``³ grid of the strokes for the tool forces
([`capped_tool_forces`][excavkin.excavator.stability.capped_tool_forces], with the front's
weight) and, since the bucket pin moves with the boom and the arm alone, a finer
(4 ``samples`` − 3)² × 5 grid for the tipping load at the pin
([`stability`][excavkin.excavator.stability.stability]).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.excavator.forces import At, Working
from excavkin.excavator.machine import Machine, length_columns
from excavkin.excavator.stability import BaseRatedForce, CappedToolForces, Over
from excavkin.machinery.equilibrium import Stability

if TYPE_CHECKING:
    import pandas as pd

    from excavkin.excavator.plots import ExcavatorPlot

#: the tool points and their standards, in the order of every table
STANDARDS: tuple[tuple[At, str], ...] = (("lip", "ISO 6015"), ("tip", "SAE J1179"))
#: the working cylinders, in the order of every table
WORKING: tuple[Working, ...] = ("arm", "bucket")
#: the maps `StabilitySurvey.plot_maps` draws
MAPS: tuple[str, ...] = (
    "tipping-front",
    "tipping-side",
    "limits-arm",
    "limits-bucket",
    "support",
)
#: the kinds of `StabilitySurvey.to_frame`'s columns
FRAME_KINDS: dict[str, str] = {
    **dict.fromkeys(("x", "y", "boom", "arm", "bucket"), "length"),
    **dict.fromkeys(
        ("force", "hydraulic_force", "tipping_force", "slipping_force", "cylinders_only"), "force"
    ),
}


def pin_grid(samples: int) -> tuple[int, int, int]:
    """The stroke grid of the tipping load at the bucket pin for ``samples`` points per stroke
    of the tool forces' sweep: the pin moves with the boom and the arm alone.

    Parameters
    ----------
    samples : int

    Returns
    -------
    (int, int, int)
        ``4 samples - 3`` boom and arm points, 5 bucket points.
    """
    dense = 4 * samples - 3
    return (dense, dense, 5)


@dataclass(frozen=True)
class StabilitySurvey:
    """Rated forces capped by stability and the stability over the working range
    (`stability_survey`).

    Attributes
    ----------
    machine : Machine
    samples : int
        Grid points per stroke of the tool forces' sweep.
    swing : str or float
        ``"front"``, ``"side"`` or the swing angle (rad) of the rated forces.
    rated : dict of (str, str) to BaseRatedForce
        ``(at, working)`` → the rated force capped by tipping and slipping.
    pin : ndarray, shape (m, 2)
        The bucket pin at the poses of the tipping load's grid that assemble (m).
    tipping : dict of str to Stability
        ``"front"``, ``"side"`` → the stability of a load hung at the bucket pin there.
    capped : dict of str to CappedToolForces
        ``"arm"``, ``"bucket"`` → the lip's tool force capped by every limit over the sweep.
    """

    machine: Machine
    samples: int
    swing: float | Over
    rated: dict[tuple[str, str], BaseRatedForce]
    pin: F
    tipping: dict[str, Stability]
    capped: dict[str, CappedToolForces]

    def to_frame(self) -> pd.DataFrame:
        """The rated forces capped by stability, one row each, SI.

        Returns
        -------
        pandas.DataFrame
            ``standard``, ``cylinder``, ``force``, ``hydraulic_force``, ``tipping_force``,
            ``tipping_line``, ``slipping_force``, ``cylinders_only`` (N), the tool point ``x``,
            ``y`` and the cylinder lengths ``boom``, ``arm``, ``bucket`` (m), ``limited_by``;
            its ``attrs`` name the machine and each column's kind.
        """

        from excavkin.kinematics.columns import kinds_frame

        rows = []
        for at, std in STANDARDS:
            for working in WORKING:
                r = self.rated[at, working]
                rf = r.rated
                rows.append(
                    {
                        "standard": std,
                        "cylinder": working,
                        "force": rf.force,
                        "hydraulic_force": r.hydraulic,
                        "tipping_force": r.tipping,
                        "tipping_line": r.tipping_line,
                        "slipping_force": r.slipping,
                        "cylinders_only": r.cylinders_only.force,
                        "x": rf.point[0],
                        "y": rf.point[1],
                        **length_columns(rf.lengths),
                        "limited_by": rf.limiting,
                    }
                )
        return kinds_frame(rows, FRAME_KINDS, self.machine.name)

    def summary(self) -> str:
        """The stability as ``excavkin excavator stability`` prints it (forces kN, lengths
        mm).

        Returns
        -------
        str
        """
        from excavkin.excavator.stability import need_base

        m, sw = self.machine, self.swing
        base = need_base(m)
        g = m.gravity
        total = m.front_mass + base.mass
        where = sw if isinstance(sw, str) else f"swung {math.degrees(sw):.1f}°"
        lines = [
            f"{m.name} — stability (forces kN, lengths mm)",
            f"masses kg: front {m.front_mass:.0f} (bodies and cylinders), upper structure "
            f"{base.upper.mass:.0f}, counterweight {base.counterweight.mass:.0f}, undercarriage "
            f"{base.undercarriage.mass:.0f}; whole machine {total:.0f}; ground friction "
            f"{base.friction:.2f}",
            "tipping lines (distance from the swing axis): "
            + ", ".join(
                f"{ln.name} {ln.offset * 1e3:.0f}" for ln in base.tipping_lines(m.swing_axis)
            ),  # fmt: skip
            f"Rated tool forces over the {where}" if isinstance(sw, str) else f"Rated, {where}",
            "(capped by the cylinders, tipping and slipping: ISO 6015 §3.17–3.19, §4.5; the "
            "front's weight counts for tipping and slipping only)",
            f"{'standard':<10} {'cylinder':<8} {'force':>7} {'cyl.':>7} {'tipping':>8} "
            f"{'(line)':<12} {'slip':>7}  {'boom':>6} {'arm':>6} {'bucket':>6}  limited by",
        ]
        for at, std in STANDARDS:
            for working in WORKING:
                r = self.rated[at, working]
                rf = r.rated
                lines.append(
                    f"{std:<10} {working:<8} {rf.force / 1e3:7.1f} {r.hydraulic / 1e3:7.1f} "
                    f"{r.tipping / 1e3:8.1f} {'(' + r.tipping_line + ')':<12} "
                    f"{r.slipping / 1e3:7.1f}  {rf.lengths[0] * 1e3:6.0f} "
                    f"{rf.lengths[1] * 1e3:6.0f} {rf.lengths[2] * 1e3:6.0f}  {rf.limiting}"
                )
        dense = pin_grid(self.samples)[0]
        lines += [
            "cyl.: the cylinders' limit at that pose; slip: where the machine slides",
            f"Over the working range ({self.samples}³ stroke sweep; {dense}² × 5 for the bucket "
            "pin; the front's weight at each pose)",
        ]
        pin = self.pin
        for over, st in self.tipping.items():
            k = int(np.argmin(st.tipping_load))
            j = int(np.argmin(st.margin))
            lines.append(
                f"  over the {over}: least tipping load of a load hung at the bucket pin "
                f"{st.tipping_load[k] / 1e3:.1f} kN ({st.tipping_load[k] / g:.0f} kg) at x "
                f"{pin[k, 0] * 1e3:.0f}, y {pin[k, 1] * 1e3:.0f}; unloaded, the centre of mass "
                f"stays {st.margin[j] * 1e3:.0f} or more inside the support"
            )
            lines.append(f"    line of least margin: {st.margin_line[j]}")
        for cylinder, c in self.capped.items():
            kinds = np.array([s.split(" ")[0] for s in c.limiting.astype(str)])
            share = ", ".join(
                f"{k} {100 * np.mean(kinds == k):.0f} %" for k in dict.fromkeys(sorted(kinds)) if k
            )
            k = int(np.nanargmax(c.force))
            lines.append(
                f"  {cylinder}-cylinder tool force (lip, with gravity): largest "
                f"{c.force[k] / 1e3:.1f} ({c.limiting[k]}); limited by {share}"
            )
        return "\n".join(lines)

    def plot_maps(self) -> dict[str, ExcavatorPlot]:
        """The tipping load at the bucket pin over the front and over the side, and the
        binding limit of the lip's tool force of each working cylinder, as maps, and the
        support in plan with its tipping lines, swung as the rated forces are.

        Returns
        -------
        dict of str to ExcavatorPlot
            `MAPS` → its figure.
        """
        from excavkin.excavator.stability import SWING
        from excavkin.excavator.stability_plots import (
            plot_limit_map,
            plot_support,
            plot_value_map,
        )

        m = self.machine
        out = {}
        for over, st in self.tipping.items():
            out[f"tipping-{over}"] = plot_value_map(
                m,
                self.pin,
                st.tipping_load / m.gravity / 1e3,
                label="tipping load (t)",
                title=f"tipping load of a load at the bucket pin, over the {over}",
                log=True,
            )
        for working, c in self.capped.items():
            out[f"limits-{working}"] = plot_limit_map(
                m,
                c.hydraulic.pose.lip,
                c.force,
                c.limiting,
                title=f"{working}-cylinder tool force (ISO 6015, lip): the binding limit",
            )
        sw = self.swing
        out["support"] = plot_support(m, swing=SWING[sw] if isinstance(sw, str) else sw)
        return out


def stability_survey(
    machine: Machine,
    samples: int = 31,
    *,
    swing: float | Over = "front",
    stages: Callable[[], Callable[[int, int], None] | None] | None = None,
) -> StabilitySurvey:
    """The rated forces capped by stability and the stability over the working range (module
    docstring).

    Parameters
    ----------
    machine : Machine
        With a ``[base]``.
    samples : int, default 31
        Grid points per stroke of the tool forces' sweep (at least 2).
    swing : {"front", "side"} or float, default "front"
        Where the front points for the rated forces, or its swing angle (rad).
    stages : callable, optional
        ``stages()`` → the next rated force's ``progress(done, total)`` (a staged progress
        bar over the four searches).

    Returns
    -------
    StabilitySurvey

    Raises
    ------
    InputError
        Fewer than 2 samples, or a machine without a base.
    """
    from excavkin.excavator.ranges import sweep
    from excavkin.excavator.stability import (
        base_rated_force,
        capped_tool_forces,
        need_base,
        stability,
    )

    if int(samples) < 2:
        raise InputError(f"samples must be at least 2, not {samples}")
    samples = int(samples)
    need_base(machine)
    rated: dict[tuple[str, str], BaseRatedForce] = {
        (at, working): base_rated_force(
            machine, working, at=at, swing=swing, progress=None if stages is None else stages()
        )
        for at, _ in STANDARDS
        for working in WORKING
    }
    pose = sweep(machine, samples)
    L = pose.lengths[pose.ok & pose.within_stroke]
    pin_pose = sweep(machine, pin_grid(samples))
    pin_ok = pin_pose.ok & pin_pose.within_stroke
    pin = pin_pose.result.point(machine.pins.bucket_pin)[0][pin_ok]
    sides: tuple[Over, ...] = ("front", "side")
    tipping: dict[str, Stability] = {
        over: stability(machine, pin_pose.lengths[pin_ok], machine.pins.bucket_pin, swing=over)
        for over in sides
    }
    capped: dict[str, CappedToolForces] = {
        working: capped_tool_forces(machine, L, working, at="lip", gravity=True, swing=swing)
        for working in WORKING
    }
    return StabilitySurvey(machine, samples, swing, rated, pin, tipping, capped)
