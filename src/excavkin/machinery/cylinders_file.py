"""The machine file's ``[circuits]`` and ``[cylinders]`` tables, as every family with hydraulic
cylinders writes them::

    [circuits.NAME]
    working = 28                      # pressure ([units] pressure, or "28 MPa")
    relief = 30                       # port relief
    [cylinders.ROLE]
    driver = "ROLE_cyl"               # the model's linear driver (default ROLE_cyl)
    retracted = 1901                  # pin to pin, fully retracted
    stroke = 1279
    bore = 200
    rod = 110
    circuit = "NAME"                  # default ROLE
    count = 1                         # cylinders acting together
    mass = 0                          # with oil, half at either end pin
    raises = "extend"                 # a family's motion key, where it has one

Every number is range-checked; errors name the file, the table and the entry.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, Literal

from excavkin.machinery.cylinders import Circuit, Cylinder
from excavkin.machinery.file_fields import MachineReader

#: the keys of a ``[cylinders.ROLE]`` table besides a family's motion key
CYLINDER_TABLE_KEYS = frozenset(
    {"driver", "retracted", "stroke", "bore", "rod", "circuit", "count", "mass"}
)


def read_circuits(r: MachineReader, data: dict[str, Any]) -> dict[str, Circuit]:
    """The ``[circuits]`` table: each circuit's working and port relief pressures.

    Parameters
    ----------
    r : MachineReader
        The file's reader (units, messages).
    data : dict
        The file's top-level table.

    Returns
    -------
    dict of str to Circuit
    """
    circuits = {}
    for cname, spec in r.subtable(data, "circuits", "circuits").items():
        table = f"circuits.{cname}"
        if not isinstance(spec, dict):
            raise r.err("must be a table with working and relief pressures", table)
        r.keys(spec, {"working", "relief"}, table)
        circuits[cname] = Circuit(
            cname,
            r.bounded(spec, "working", "pressure", table, 0.0, 2e8, "Pa"),
            r.bounded(spec, "relief", "pressure", table, 0.0, 2e8, "Pa"),
        )
    return circuits


def read_cylinders(
    r: MachineReader,
    data: dict[str, Any],
    roles: Sequence[str],
    machine: str,
    *,
    motions: Mapping[str, str] | None = None,
    max_count: int = 16,
) -> dict[str, Cylinder]:
    """The ``[cylinders]`` table: one cylinder per role, no other.

    Parameters
    ----------
    r : MachineReader
    data : dict
        The file's top-level table.
    roles : sequence of str
        The family's roles, each a ``[cylinders.ROLE]`` table.
    machine : str
        What has those roles, for the message on another one (``"a loader"``).
    motions : mapping of str to str, optional
        Per role, the key that says which motion does the role's work (``"raises"``):
        ``"extend"`` (default) or ``"retract"``.
    max_count : int
        The most cylinders acting together in one role.

    Returns
    -------
    dict of str to Cylinder
        By role.
    """
    cyl_t = r.subtable(data, "cylinders", "cylinders")
    extra = set(cyl_t) - set(roles)
    if extra:
        raise r.err(
            f"unknown cylinder {', '.join(sorted(extra))} ({machine} has {', '.join(roles)})",
            "cylinders",
        )
    return {role: _cylinder(r, cyl_t, role, (motions or {}).get(role), max_count) for role in roles}


def _cylinder(
    r: MachineReader, cyl_t: dict[str, Any], role: str, motion: str | None, max_count: int
) -> Cylinder:
    table = f"cylinders.{role}"
    spec = cyl_t.get(role)
    if not isinstance(spec, dict):
        raise r.err("is missing or not a table", table)
    r.keys(spec, set(CYLINDER_TABLE_KEYS) | ({motion} if motion else set()), table)
    count = spec.get("count", 1)
    if not isinstance(count, int) or isinstance(count, bool) or not 1 <= count <= max_count:
        raise r.err(f"count must be a whole number from 1 to {max_count}", table, "count")
    how: Literal["extend", "retract"] = "extend"
    if motion:
        given = spec.get(motion, "extend")
        if given not in ("extend", "retract"):
            raise r.err(f"{motion} must be 'extend' or 'retract', not {given!r}", table, motion)
        how = "retract" if given == "retract" else "extend"
    return Cylinder(
        role=role,
        driver=r.text(spec, "driver", table, f"{role}_cyl"),
        retracted=r.bounded(spec, "retracted", "length", table, 0.0, 50.0, "m"),
        stroke=r.bounded(spec, "stroke", "length", table, 0.0, 20.0, "m"),
        bore=r.bounded(spec, "bore", "length", table, 0.0, 2.0, "m"),
        rod=r.bounded(spec, "rod", "length", table, 0.0, 2.0, "m"),
        circuit=r.text(spec, "circuit", table, role),
        count=count,
        dig=how,
        mass=r.bounded(spec, "mass", "mass", table, 0.0, 1e6, "kg", default=0.0, open_low=False),
    )
