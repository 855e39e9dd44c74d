"""The machine file's ``[hydraulics]`` table (optional), here for an excavator::

    [hydraulics]
    swing_speed = "11 rpm"              # swing speed of the upper structure
    swing_angle = "90 deg"              # dig to dump
    rod_modulus = "210 GPa"             # optional (default 210 GPa): buckling
    rod_yield = "500 MPa"               # optional (default 500 MPa): the rods' yield stress
    [hydraulics.pumps.P1]
    flow = "220 L/min"
    feeds = ["boom", "arm", "bucket"]   # functions it feeds (their flows add: confluence)
    [hydraulics.pumps.P2]
    flow = "220 L/min"
    feeds = ["boom", "arm"]

A family whose machines do not swing (its class's ``has_swing`` is False: a wheel loader)
has no ``swing_speed`` and ``swing_angle`` entries.

A single ``flow`` per function is written as one pump per function. Every number is
range-checked, a pump feeds only the roles of the family's
[`Hydraulics`][excavkin.machinery.pumps.Hydraulics] class, and every role must be fed by some
pump; errors name the file, the table and the entry.
"""

from __future__ import annotations

import math
from typing import Any, TypeVar

from excavkin.machinery.file_fields import MachineReader
from excavkin.machinery.pumps import ROD_YIELD, STEEL_E, Hydraulics, Pump

H = TypeVar("H", bound=Hydraulics)

_TOP = {"swing_speed", "swing_angle", "rod_modulus", "rod_yield", "pumps"}
#: the most pumps
MAX_PUMPS = 8
#: largest flow of one pump (m³/s: 60 000 L/min) and swing speed (rad/s: 60 rpm)
_MAX_FLOW, _MAX_SWING = 1.0, 2.0 * math.pi


def read_hydraulics(r: MachineReader, data: dict[str, Any], kind: type[H]) -> H | None:
    """The ``[hydraulics]`` table of a machine file.

    Parameters
    ----------
    r : MachineReader
        The file's reader (units, messages).
    data : dict
        The file's top-level table.
    kind : type
        The family's [`Hydraulics`][excavkin.machinery.pumps.Hydraulics] class: its ``roles``
        are the functions the pumps may feed.

    Returns
    -------
    Hydraulics or None
        An instance of ``kind``, or None where the file has no ``[hydraulics]`` table.

    Raises
    ------
    ModelError
        Naming the file, the table and the entry.
    """
    roles = kind.roles
    if "hydraulics" not in data:
        return None
    table = "hydraulics"
    t = r.subtable(data, table, table)
    if kind.has_swing:
        r.keys(t, _TOP, table)
        speed = r.bounded(t, "swing_speed", "angular_velocity", table, 0.0, _MAX_SWING, "rad/s")
        angle = r.bounded(t, "swing_angle", "angle", table, 0.0, 2 * math.pi, "rad")
    else:  # a family without a swing (a wheel loader)
        r.keys(t, _TOP - {"swing_speed", "swing_angle"}, table)
        speed = angle = 0.0
    modulus = r.bounded(t, "rod_modulus", "pressure", table, 0.0, 1e13, "Pa", default=STEEL_E)
    yield_ = r.bounded(t, "rod_yield", "pressure", table, 0.0, 1e11, "Pa", default=ROD_YIELD)
    pt = r.subtable(t, "pumps", "hydraulics.pumps")
    if not 1 <= len(pt) <= MAX_PUMPS:
        raise r.err(f"must hold 1 to {MAX_PUMPS} pumps", "hydraulics.pumps")
    pumps = []
    for name, spec in pt.items():
        pname = f"hydraulics.pumps.{name}"
        if not isinstance(spec, dict):
            raise r.err("must be a table with flow and feeds", pname)
        r.keys(spec, {"flow", "feeds"}, pname)
        flow = r.bounded(spec, "flow", "volume_flow", pname, 0.0, _MAX_FLOW, "m^3/s")
        feeds = spec.get("feeds")
        if (
            not isinstance(feeds, list)
            or not feeds
            or any(f not in roles for f in feeds)
            or len(set(feeds)) != len(feeds)
        ):
            raise r.err(
                f"feeds must be a list of distinct functions among {', '.join(roles)}, "
                f"got {feeds!r}"[:160],
                pname,
                "feeds",
            )
        pumps.append(Pump(str(name), flow, tuple(feeds)))
    unfed = [role for role in roles if not any(role in p.feeds for p in pumps)]
    if unfed:
        raise r.err(
            f"no pump feeds the {', '.join(unfed)} cylinder{'s' if len(unfed) > 1 else ''}",
            "hydraulics.pumps",
        )
    return kind(tuple(pumps), speed, angle, modulus, yield_)
