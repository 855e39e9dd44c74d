r"""Hydraulics of an excavator front: its pumps feed the boom, arm and bucket; the
dig–swing–dump cycle time.

The speeds, stroke times, power along a motion and buckling every machine with cylinders
shares live in the
machinery layer (`excavkin.machinery.flows`, `excavkin.machinery.buckling`) and are re-exported
here; the model of each is written there.

**Cycle.** A dig–swing–dump cycle is four phases, each made of full strokes (a conservative
choice: operators use partial strokes) and a swing at constant speed through the dig-to-dump
angle (acceleration and braking left out)::

    dig     arm and bucket in their digging direction        t_dig  = t_arm,dig + t_bkt,dig
    raise   boom up (cylinder extending), swing to dump      t_boom,up,  t_swing = θ / ω
    dump    arm and bucket back                              t_dump = t_arm,back + t_bkt,back
    return  swing back, boom down                            t_swing,  t_boom,down

``sequential`` adds every motion (one at a time, an upper bound); ``overlapped`` lets the swing
overlap the boom in the raise and return phases, ``max(t_boom, t_swing)``, as operators do.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from excavkin.excavator.machine import ROLES, Machine
from excavkin.machinery import pumps
from excavkin.machinery.buckling import Buckling, buckling, pose_buckling, relief_buckling
from excavkin.machinery.flows import (
    Power,
    Stroke,
    cylinder_speed,
    hydraulics_of,
    motion_power,
    power_of,
    strokes,
)
from excavkin.machinery.pumps import ROD_YIELD, STEEL_E, Pump

__all__ = [
    "ROD_YIELD",
    "STEEL_E",
    "Buckling",
    "Cycle",
    "Hydraulics",
    "Power",
    "Pump",
    "Stroke",
    "buckling",
    "cycle_time",
    "cylinder_speed",
    "hydraulics_of",
    "motion_power",
    "pose_buckling",
    "power_of",
    "relief_buckling",
    "strokes",
]


@dataclass(frozen=True, slots=True)
class Hydraulics(pumps.Hydraulics):
    """Pumps, swing and rod material of an excavator (SI): its pumps feed the ``"boom"``,
    ``"arm"`` and ``"bucket"`` functions, and each of them is fed.

    Attributes
    ----------
    pumps, swing_speed, swing_angle, modulus, rod_yield
        As for [`excavkin.machinery.pumps.Hydraulics`][].
    """

    roles: ClassVar[tuple[str, ...]] = ROLES


@dataclass(frozen=True, slots=True)
class Cycle:
    """A dig–swing–dump cycle estimate (s); see the module's docstring for the model.

    Attributes
    ----------
    dig, boom_up, swing, dump, boom_down : float
        Times of the motions: arm and bucket digging, boom raising, one swing (dig to dump),
        arm and bucket back, boom lowering.
    sequential : float
        Every motion one after the other: ``dig + boom_up + swing + dump + swing + boom_down``.
    overlapped : float
        The swing overlapping the boom: ``dig + max(boom_up, swing) + dump + max(swing,
        boom_down)``.
    """

    dig: float
    boom_up: float
    swing: float
    dump: float
    boom_down: float
    sequential: float
    overlapped: float


def cycle_time(machine: Machine, hydraulics: Hydraulics | None = None) -> Cycle:
    """The dig–swing–dump cycle estimate of ``machine`` (full strokes, constant swing speed).

    Parameters
    ----------
    machine : Machine
        The excavator.
    hydraulics : Hydraulics, optional
        Pump flows and swing to use instead of the machine's own ``[hydraulics]``.

    Returns
    -------
    Cycle
        The times of each motion and of the cycle, sequential and overlapped (s).

    Raises
    ------
    InputError
        The machine has no hydraulics.
    """
    h = hydraulics_of(machine, hydraulics)
    s = dict(zip(ROLES, strokes(machine, h), strict=True))
    cyl = dict(zip(ROLES, machine.cylinders, strict=True))

    def digging(role: str, dig: bool) -> float:
        extend = (cyl[role].dig == "extend") == dig
        return s[role].extend_time if extend else s[role].retract_time

    dig = digging("arm", True) + digging("bucket", True)
    dump = digging("arm", False) + digging("bucket", False)
    up, down = s["boom"].extend_time, s["boom"].retract_time
    swing = h.swing_angle / h.swing_speed
    return Cycle(
        dig,
        up,
        swing,
        dump,
        down,
        dig + up + swing + dump + swing + down,
        dig + max(up, swing) + dump + max(swing, down),
    )
