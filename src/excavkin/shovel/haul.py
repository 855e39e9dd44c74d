"""A rope backhoe hauled in by its drag winch: the bucket's attitude and the drag rope's pull.

The drag rope's length runs over the machine file's ``[drag] length`` range, hauled in at the
winch's rated speed ([`RopeBackhoe.haul`][excavkin.shovel.machine.RopeBackhoe.haul]); at each
sample the general engine gives the stick's angle and rate, the bucket's attitude to the stick
and to the boom and its rate, and the general kinetostatics the drag rope's tension and the
winch motor's torque holding a force on the bucket (a digging resistance, the bucket's and its
load's weight: the caller's). Where the machine file describes the boom (``[boom]``), the boom's
moment balance about its foot adds the hoist tackle's pull and the foot pin's force
([`RopeBackhoe.hoist`][excavkin.shovel.machine.RopeBackhoe.hoist]).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.kinetostatics import PointForce
from excavkin.shovel.boom import SLACK_DRAG, SLACK_HOIST
from excavkin.shovel.machine import RopeBackhoe, table_attrs

if TYPE_CHECKING:
    import pandas as pd


@dataclass(frozen=True, slots=True)
class Haul:
    """The samples of a haul, SI, shape (n,) each.

    Attributes
    ----------
    machine : str
    length : ndarray
        The drag rope's length, sheave to bucket (m).
    speed : ndarray
        The rope's hauling speed (m/s, > 0 hauls in).
    stick, stick_rate : ndarray
        The stick's angle (rad, the model's frame) and rate (rad/s).
    to_stick, to_boom : ndarray
        The bucket's angle to the stick and to the boom (rad).
    bucket_rate : ndarray
        The bucket's rate relative to the stick (rad/s).
    tension : ndarray
        The drag rope's tension (N), each of its parts.
    torque : ndarray
        The winch motor's torque (N·m, all its motors): tension · parts · R / i.
    status : ndarray of str
    hoist : ndarray or None
        One part of the hoist tackle's tension (N); None without a ``[boom]`` table.
    hoist_parts : int
        The tackle's parts (0 without a boom).
    boom_foot : ndarray, shape (n, 2), or None
        The foot pin's force on the boom (N, the model's frame).
    """

    machine: str
    length: F
    speed: F
    stick: F
    stick_rate: F
    to_stick: F
    to_boom: F
    bucket_rate: F
    tension: F
    torque: F
    status: np.ndarray
    hoist: F | None = None
    hoist_parts: int = 0
    boom_foot: F | None = None

    def summary(self) -> str:
        """The haul's ranges of attitude, rates and pull.

        Returns
        -------
        str
        """
        deg = np.degrees
        # the drag rope's range where it pulls, whether or not the hoist does
        pulls = np.isin(self.status, ("ok", SLACK_HOIST)) & np.isfinite(self.tension)
        lines = [
            f"{self.machine}: hauled in over {self.length[-1]:.3f}..{self.length[0]:.3f} m "
            f"of drag rope at {self.speed[0]:.3f} m/s",
            f"  stick angle      {deg(self.stick[0]):7.2f} .. {deg(self.stick[-1]):7.2f} deg",
            f"  bucket to stick  {deg(self.to_stick[0]):7.2f} .. "
            f"{deg(self.to_stick[-1]):7.2f} deg"
            f" (turns {deg(self.to_stick[-1] - self.to_stick[0]):.1f} deg)",
        ]
        if pulls.any():
            lines.append(
                f"  drag rope        {np.min(self.tension[pulls]) / 1e3:7.2f} .. "
                f"{np.max(self.tension[pulls]) / 1e3:.2f} kN a part where it pulls, motor "
                f"{np.max(self.torque[pulls]) / 1e3:.3f} kN*m at most"
            )
        ok = self.status == "ok"
        if self.hoist is not None and self.boom_foot is not None and ok.any():
            foot = np.hypot(*self.boom_foot[ok].T)
            lines.append(
                f"  hoist rope       {np.min(self.hoist[ok]) / 1e3:7.2f} .. "
                f"{np.max(self.hoist[ok]) / 1e3:.2f} kN a part ({self.hoist_parts} parts), "
                f"boom-foot pin {np.min(foot) / 1e3:.1f} .. {np.max(foot) / 1e3:.1f} kN"
            )
        pushes = int(np.sum(self.status == SLACK_HOIST))
        why = f" (the hoist rope would push in {pushes})" if pushes else ""
        lines.append(f"  not ok           {int(np.sum(~ok))} samples{why}")
        return "\n".join(lines)

    def to_frame(self) -> pd.DataFrame:
        """The samples as a table, SI; ``attrs`` record the machine and the columns' kinds.

        Returns
        -------
        pandas.DataFrame
        """
        import pandas as pd

        cols = {
            "drag_length": (self.length, "length"),
            "drag_speed": (self.speed, "velocity"),
            "stick_angle": (self.stick, "angle"),
            "stick_rate": (self.stick_rate, "angular_velocity"),
            "bucket_to_stick": (self.to_stick, "angle"),
            "bucket_to_boom": (self.to_boom, "angle"),
            "bucket_rate": (self.bucket_rate, "angular_velocity"),
            "drag_tension": (self.tension, "force"),
            "winch_torque": (self.torque, "torque"),
        }
        if self.hoist is not None and self.boom_foot is not None:
            cols["hoist_tension"] = (self.hoist, "force")
            cols["boom_foot_x"] = (self.boom_foot[:, 0], "force")
            cols["boom_foot_y"] = (self.boom_foot[:, 1], "force")
        frame = pd.DataFrame({k: v for k, (v, _) in cols.items()})
        frame["status"] = self.status
        frame.attrs.update(table_attrs(self.machine, {k: kind for k, (_, kind) in cols.items()}))
        return frame


def haul(
    machine: RopeBackhoe,
    *,
    samples: int = 91,
    point: str = "D",
    force: tuple[float, float] = (0.0, 0.0),
) -> Haul:
    """Haul the bucket in over the drag rope's range (module docstring).

    Parameters
    ----------
    machine : RopeBackhoe
        With a ``[drag] length`` range.
    samples : int, default 91
        Samples (≥ 2).
    point : str, default "D"
        The bucket's point the force acts at.
    force : (float, float), default (0, 0)
        The force on the bucket (N, the model's frame).

    Returns
    -------
    Haul

    Raises
    ------
    InputError
        No drag-rope range, too few samples, or a point not of the bucket.
    """
    from excavkin.errors import InputError

    if machine.drag.length is None:
        raise InputError(f"{machine.name}: its [drag] table gives no length range to haul over")
    if not 2 <= samples <= 100_000:
        raise InputError(f"samples must be from 2 to 100000, not {samples}")
    bucket = next(b for b in machine.mechanism.model.bodies if b.name == machine.bucket)
    if point not in bucket.points:
        raise InputError(f"{point!r} is not a point of the bucket ({', '.join(bucket.points)})")
    lo, hi = machine.drag.length
    length = np.linspace(hi, lo, samples)  # hauled in: shortening
    res = machine.haul(length)
    to_stick, to_boom = machine.attitude(res)
    stick, stick_rate, _ = res.body(machine.stick)
    bucket_rate = res.body(machine.bucket)[1] - stick_rate
    load = PointForce("bucket load", machine.bucket, point, tuple(float(f) for f in force))
    static = machine.mechanism.solve({machine.drag.driver: length})
    forces = machine.mechanism.forces(static, [load])
    tension = machine.rope_tension(forces)
    d = machine.drag
    hoist, parts, foot = None, 0, None
    if machine.boom is None:
        labels = forces.status_labels().astype(object)
        labels[(tension < 0.0) & (labels == "ok")] = SLACK_DRAG
        status = np.asarray(labels, dtype=str)
    else:
        held = machine.hoist(forces)
        hoist, parts, foot, status = held.tension, machine.boom.parts, held.foot, held.status
    return Haul(
        machine.name, length, -res.driver(d.driver)[1], stick, stick_rate,
        np.angle(np.exp(1j * to_stick)), np.angle(np.exp(1j * to_boom)), bucket_rate,
        tension, tension * d.parts * d.drum_radius / d.gear_ratio, status, hoist, parts, foot,
    )  # fmt: skip
