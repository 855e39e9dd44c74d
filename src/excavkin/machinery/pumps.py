"""Pumps and the hydraulics of a machine (SI records): which functions each pump feeds, the
swing, and the rods' material.

A family's pumps feed its own roles: it subclasses `Hydraulics` with its ``roles`` (the
excavator's [`Hydraulics`][excavkin.excavator.hydraulics.Hydraulics]), and every pump is
checked to feed only those, and every role to be fed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from excavkin.errors import InputError

#: steel defaults of the buckling check: Young's modulus and the rod's yield stress (Pa), a
#: quenched and tempered C45-class rod steel
STEEL_E, ROD_YIELD = 210e9, 500e6


@dataclass(frozen=True, slots=True)
class Pump:
    """A pump: its flow (m³/s) and the functions (cylinder roles) it feeds.

    Attributes
    ----------
    name : str
        The pump's name in the machine file.
    flow : float
        Its delivery (m³/s).
    feeds : tuple of str
        The cylinder roles it feeds; pumps feeding one role together are in confluence.
    """

    name: str
    flow: float
    feeds: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Hydraulics:
    """Pumps, swing and rod material of a machine (SI).

    Attributes
    ----------
    pumps : tuple of Pump
    swing_speed : float
        Swing speed of the upper structure (rad/s).
    swing_angle : float
        Swing angle from dig to dump (rad).
    modulus, rod_yield : float
        Young's modulus and yield stress of the cylinder rods (Pa), for buckling.
    roles : tuple of str (class attribute)
        The functions the pumps may feed, each of which some pump must feed: a family's
        subclass names its roles; empty here (any names, not checked).
    has_swing : bool (class attribute)
        Whether the family's machines swing (an excavator's upper structure); where not (a
        wheel loader), ``swing_speed`` and ``swing_angle`` are 0 and not checked.
    """

    roles: ClassVar[tuple[str, ...]] = ()
    has_swing: ClassVar[bool] = True

    pumps: tuple[Pump, ...]
    swing_speed: float
    swing_angle: float
    modulus: float = STEEL_E
    rod_yield: float = ROD_YIELD

    def __post_init__(self) -> None:
        swing = (
            (("swing_speed", self.swing_speed), ("swing_angle", self.swing_angle))
            if self.has_swing
            else ()
        )
        for name, value in (
            *swing,
            ("modulus", self.modulus),
            ("rod_yield", self.rod_yield),
        ):
            if not (math.isfinite(value) and value > 0.0):
                raise InputError(f"{name} must be positive and finite, not {value!r}")
        for p in self.pumps:
            if not (math.isfinite(p.flow) and p.flow > 0.0):
                raise InputError(f"pump {p.name!r}: flow must be positive, not {p.flow!r}")
            if not p.feeds or any(f not in self.roles for f in p.feeds if self.roles):
                raise InputError(
                    f"pump {p.name!r} must feed some of {', '.join(self.roles)}, not {p.feeds!r}"
                )
        unfed = [r for r in self.roles if not any(r in p.feeds for p in self.pumps)]
        if unfed:
            raise InputError(f"no pump feeds the {', '.join(unfed)} cylinder(s)")

    def flow(self, role: str) -> float:
        """The flow reaching the function ``role`` moved alone: the sum over its pumps.

        Parameters
        ----------
        role : str
            The function, one of ``roles``.

        Returns
        -------
        float
            The summed flow of every pump that feeds it (m³/s).

        Raises
        ------
        InputError
            Another role.
        """
        if self.roles and role not in self.roles:
            raise InputError(f"role must be one of {', '.join(self.roles)}, not {role!r}")
        return float(sum(p.flow for p in self.pumps if role in p.feeds))
