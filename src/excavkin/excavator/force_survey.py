"""An excavator's tool forces as its spec sheet gives them (``excavkin excavator forces``): the
rated forces of the arm and the bucket cylinder at the lip (ISO 6015) and at the tooth tip
(SAE J1179), and the largest of each over a sweep of the strokes.

The rated forces are [`rated_force`][excavkin.excavator.forces.rated_force]'s (no gravity, by
the standards' definitions); the sweep's are
[`force_maximum`][excavkin.excavator.forces.force_maximum] of
[`tool_forces`][excavkin.excavator.forces.tool_forces] over a ``samples``³ grid of the strokes,
with the front's weight unless asked otherwise.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from excavkin.errors import InputError
from excavkin.excavator.forces import (
    At,
    ForceMaximum,
    RatedForce,
    ToolForces,
    Working,
    force_maximum,
    rated_force,
    tool_forces,
)
from excavkin.excavator.machine import Machine, length_columns

if TYPE_CHECKING:
    import pandas as pd

    from excavkin.excavator.plots import ExcavatorPlot

#: the tool points and their standards, in the order of every table
STANDARDS: tuple[tuple[At, str], ...] = (("lip", "ISO 6015"), ("tip", "SAE J1179"))
#: the working cylinders, in the order of every table
WORKING: tuple[Working, ...] = ("arm", "bucket")
#: the kinds of `ToolForceSurvey.to_frame`'s columns
FRAME_KINDS: dict[str, str] = {
    **dict.fromkeys(("x", "y", "boom", "arm", "bucket", "radius"), "length"),
    **dict.fromkeys(("force", "own_limit"), "force"),
    "moment": "torque",
}


@dataclass(frozen=True)
class ToolForceSurvey:
    """The rated tool forces and the largest over a stroke sweep (`tool_force_survey`).

    Attributes
    ----------
    machine : Machine
    samples : int
        Grid points per stroke of the sweep.
    gravity : bool
        The sweep with the front's weight.
    rated : tuple of (str, RatedForce)
        Each standard with its rated force: arm then bucket, ISO 6015 then SAE J1179.
    maxima : tuple of (str, ForceMaximum)
        The same for the sweep's largest forces.
    maps : dict of str to ToolForces
        The sweep's lip forces of each working cylinder (for the force maps).
    """

    machine: Machine
    samples: int
    gravity: bool
    rated: tuple[tuple[str, RatedForce], ...]
    maxima: tuple[tuple[str, ForceMaximum], ...]
    maps: dict[str, ToolForces]

    def _rows(self) -> list[tuple[str, str, bool, RatedForce | ForceMaximum]]:
        out: list[tuple[str, str, bool, RatedForce | ForceMaximum]] = [
            ("rated", std, False, r) for std, r in self.rated
        ]
        out += [("sweep_max", std, self.gravity, r) for std, r in self.maxima]
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per force: the rated ones, then the sweep's largest, SI.

        Returns
        -------
        pandas.DataFrame
            ``kind`` (``"rated"`` or ``"sweep_max"``), ``standard``, ``cylinder``, ``gravity``,
            ``force`` and ``own_limit`` (N), ``moment`` (N·m) and ``radius`` (m) of a rated
            force (NaN for the sweep's), the tool point ``x``, ``y`` and the cylinder lengths
            ``boom``, ``arm``, ``bucket`` (m), ``limited_by``; its ``attrs`` name the machine
            and each column's kind.
        """

        from excavkin.kinematics.columns import kinds_frame

        rows = []
        for kind, std, gravity, r in self._rows():
            moment, radius = (
                (r.moment, r.radius) if isinstance(r, RatedForce) else (math.nan, math.nan)
            )
            rows.append(
                {
                    "kind": kind,
                    "standard": std,
                    "cylinder": r.working,
                    "gravity": gravity,
                    "force": r.force,
                    "own_limit": r.uncapped,
                    "moment": moment,
                    "radius": radius,
                    "x": r.point[0],
                    "y": r.point[1],
                    **length_columns(r.lengths),
                    "limited_by": r.limiting,
                }
            )
        return kinds_frame(rows, FRAME_KINDS, self.machine.name)

    def summary(self) -> str:
        """The forces as ``excavkin excavator forces`` prints them (kN; positions mm).

        Returns
        -------
        str
        """

        def line(std: str, r: RatedForce | ForceMaximum) -> str:
            lim = r.limiting + (" (working pressure)" if r.limiting == r.working else " (relief)")
            return (
                f"{std:<10} {r.working:<8} {r.force / 1e3:7.1f} {r.uncapped / 1e3:7.1f}  "
                f"{r.point[0] * 1e3:6.0f} {r.point[1] * 1e3:6.0f}  {r.lengths[0] * 1e3:6.0f} "
                f"{r.lengths[1] * 1e3:6.0f} {r.lengths[2] * 1e3:6.0f}  {lim}"
            )

        lines = [
            f"{self.machine.name} — tool forces (kN; positions mm)",
            "Rated: bucket at its cylinder's largest moment, stick at the arm cylinder's "
            "(ISO 6015 §5.2, SAE J1179 §3.3); no gravity",
            f"{'standard':<10} {'cylinder':<8} {'force':>7} {'own':>7}  {'x':>6} {'y':>6}  "
            f"{'boom':>6} {'arm':>6} {'bucket':>6}  limited by",
            *(line(std, r) for std, r in self.rated),
            f"Largest over a {self.samples}³ stroke sweep "
            f"({'with' if self.gravity else 'without'} gravity of the front)",
            *(line(std, r) for std, r in self.maxima),
            "force: capped by the holding cylinders' reliefs; own: the working cylinder's limit",
        ]
        return "\n".join(lines)

    def plot_maps(self) -> dict[str, ExcavatorPlot]:
        """The sweep's lip forces of each working cylinder as a map
        ([`plot_force_map`][excavkin.excavator.plots.plot_force_map]).

        Returns
        -------
        dict of str to ExcavatorPlot
            ``"arm"`` and ``"bucket"`` → its figure.
        """
        from excavkin.excavator.plots import plot_force_map

        return {w: plot_force_map(self.machine, tf) for w, tf in self.maps.items()}


def tool_force_survey(
    machine: Machine,
    samples: int = 31,
    *,
    gravity: bool = True,
    stages: Callable[[], Callable[[int, int], None] | None] | None = None,
) -> ToolForceSurvey:
    """The rated tool forces of the arm and the bucket cylinder at the lip and at the tooth
    tip, and the largest of each over a ``samples``³ sweep of the strokes (module docstring).

    Parameters
    ----------
    machine : Machine
    samples : int, default 31
        Grid points per stroke of the sweep (at least 2).
    gravity : bool, default True
        The sweep with the front's weight (the rated forces never have it).
    stages : callable, optional
        ``stages()`` → the next rated force's ``progress(done, total)`` (a staged progress
        bar over the four searches).

    Returns
    -------
    ToolForceSurvey

    Raises
    ------
    InputError
        Fewer than 2 samples.
    """
    from excavkin.excavator.ranges import sweep

    if int(samples) < 2:
        raise InputError(f"samples must be at least 2, not {samples}")
    rated = tuple(
        (std, rated_force(machine, working, at=at, progress=None if stages is None else stages()))
        for at, std in STANDARDS
        for working in WORKING
    )
    pose = sweep(machine, int(samples))
    maxima = []
    maps: dict[str, ToolForces] = {}
    for at, std in STANDARDS:
        for working in WORKING:
            tf = tool_forces(machine, pose.lengths, working, at=at, gravity=gravity)
            maxima.append((std, force_maximum(tf)))
            if at == "lip":
                maps[working] = tf
    return ToolForceSurvey(machine, int(samples), gravity, rated, tuple(maxima), maps)
