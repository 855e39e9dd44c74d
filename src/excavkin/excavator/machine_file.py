"""Read an excavator machine description (TOML, ``schema_version = 1``) into a Machine.

The file builds on a general mechanism model, either referenced (``model = "front.toml"``,
relative to the machine file) or inline (a ``[model]`` table holding the model's own tables)::

    schema_version = 1
    family = "excavator"    # optional: a file without it is read as an excavator's
    model = "excavator.toml"
    [units]                 # defaults for bare numbers in this file
    length = "mm"
    pressure = "MPa"
    [front]                 # bodies and points of the model
    boom = "boom"; stick = "stick"; bucket = "bucket"; side_link = "side_link"
    h_link = "h_link"; tip = "T"; lip = "W"
    ground_line = 0; swing_axis = 0; level_bottom = 2440
    [cylinders.boom]        # and .arm, .bucket
    driver = "boom_cyl"; retracted = 1990; stroke = 1335; bore = 120; rod = 85
    circuit = "boom"; count = 2; dig = "extend"
    [circuits.boom]
    working = 34.3; relief = 39.2
    [gravity]
    g = "9.80665 m/s^2"

Masses, inertias and centres of mass of the front are the model's (``[bodies]``), plus each
cylinder's optional ``mass``. The optional ``[base]`` (upper structure, counterweight,
undercarriage, ground support) and ``[lift]`` tables are read by
`excavkin.excavator.base_file`, the optional ``[hydraulics]`` (pumps, swing, rod material)
by `excavkin.excavator.hydraulics_file`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from excavkin.excavator.base_file import read_base, read_lift_point
from excavkin.excavator.family import check_family
from excavkin.excavator.hydraulics_file import read_hydraulics
from excavkin.excavator.machine import ROLES, Circuit, Cylinder, Front, Machine
from excavkin.io.toml_model import (
    read_text_file,
    read_toml,
)
from excavkin.machinery.file_fields import MachineReader as _Reader
from excavkin.machinery.file_fields import check_head, read_model
from excavkin.machinery.file_fields import within as _within
from excavkin.mechanism import Mechanism

SCHEMA_VERSION = 1
_TOP = {
    "schema_version",
    "family",
    "name",
    "description",
    "model",
    "units",
    "front",
    "cylinders",
    "circuits",
    "gravity",
    "base",
    "lift",
    "hydraulics",
}
_FRONT = {
    "boom",
    "stick",
    "bucket",
    "side_link",
    "h_link",
    "tip",
    "lip",
    "floor",
    "ground_line",
    "swing_axis",
    "level_bottom",
}
_CYL = {"driver", "retracted", "stroke", "bore", "rod", "circuit", "count", "dig", "mass"}


def loads_machine(text: str, source: str | None = None) -> Machine:
    """Parse a machine description from TOML text; see
    [`load_machine`][excavkin.excavator.machine_file.load_machine]."""
    return _machine(read_toml(text, source), source)


def load_machine(path: str | Path) -> Machine:
    """Read an excavator machine file.

    Parameters
    ----------
    path : str or Path
        The file, or the name of a built-in machine (``"excavator_machine"``;
        ``excavkin.examples("machine")`` lists them).

    Returns
    -------
    Machine

    Raises
    ------
    ModelError
        Naming the file, the table and the entry of the first problem found (in the machine
        file or in the model it refers to).
    """
    import excavkin

    path = excavkin.source_file(path, "machine")
    return loads_machine(read_text_file(path), str(path))


def _machine(data: dict[str, Any], source: str | None) -> Machine:
    r = _Reader(data, source)
    check_head(r, SCHEMA_VERSION, _TOP, "excavator.toml")
    check_family(r, data)
    mech = Mechanism(read_model(r, data.get("model"), source, "front.toml"))

    front_t = r.subtable(data, "front", "front")
    r.keys(front_t, _FRONT, "front")
    lip = r.text(front_t, "lip", "front")
    names = {
        k: r.text(front_t, k, "front", d)
        for k, d in (
            ("boom", "boom"),
            ("stick", "stick"),
            ("bucket", "bucket"),
            ("side_link", "side_link"),
            ("h_link", "h_link"),
            ("tip", lip),  # a bucket without teeth: the tip is the lip
        )
    }
    front = Front(
        **names,
        lip=lip,
        floor=r.text(front_t, "floor", "front") if "floor" in front_t else None,
    )

    circ_t = r.subtable(data, "circuits", "circuits")
    circuits = {}
    for cname, spec in circ_t.items():
        table = f"circuits.{cname}"
        if not isinstance(spec, dict):
            raise r.err("must be a table with working and relief pressures", table)
        r.keys(spec, {"working", "relief"}, table)
        circuits[cname] = Circuit(
            cname,
            _within(
                r, r.field_qty(spec, "working", "pressure", table), table, "working", 0.0, 2e8, "Pa"
            ),
            _within(
                r, r.field_qty(spec, "relief", "pressure", table), table, "relief", 0.0, 2e8, "Pa"
            ),
        )

    cyl_t = r.subtable(data, "cylinders", "cylinders")
    extra = set(cyl_t) - set(ROLES)
    if extra:
        raise r.err(
            f"unknown cylinder {', '.join(sorted(extra))} (a backhoe front has {', '.join(ROLES)})",
            "cylinders",
        )
    cylinders = {}
    for role in ROLES:
        table = f"cylinders.{role}"
        spec = cyl_t.get(role)
        if not isinstance(spec, dict):
            raise r.err("is missing or not a table", table)
        r.keys(spec, _CYL, table)
        count = spec.get("count", 1)
        if not isinstance(count, int) or isinstance(count, bool) or not 1 <= count <= MAX_COUNT:
            raise r.err(f"count must be a whole number from 1 to {MAX_COUNT}", table, "count")
        dig = spec.get("dig", "extend")
        if dig not in ("extend", "retract"):
            raise r.err(f"dig must be 'extend' or 'retract', not {dig!r}", table, "dig")
        cylinders[role] = Cylinder(
            role=role,
            driver=r.text(spec, "driver", table, f"{role}_cyl"),
            retracted=_within(
                r,
                r.field_qty(spec, "retracted", "length", table),
                table,
                "retracted",
                0.0,
                50.0,
                "m",
            ),
            stroke=_within(
                r, r.field_qty(spec, "stroke", "length", table), table, "stroke", 0.0, 20.0, "m"
            ),
            bore=_within(
                r, r.field_qty(spec, "bore", "length", table), table, "bore", 0.0, 2.0, "m"
            ),
            rod=_within(r, r.field_qty(spec, "rod", "length", table), table, "rod", 0.0, 2.0, "m"),
            circuit=r.text(spec, "circuit", table, role),
            count=count,
            dig=dig,
            mass=_within(
                r,
                r.field_qty(spec, "mass", "mass", table, 0.0),
                table,
                "mass",
                0.0,
                1e6,
                "kg",
                open_low=False,
            ),
        )
    grav = data.get("gravity", {})
    if not isinstance(grav, dict):
        raise r.err('must be a table such as { g = "9.81 m/s^2" }', "gravity")
    r.keys(grav, {"g"}, "gravity")
    g = _within(
        r,
        r.field_qty(grav, "g", "acceleration", "gravity", 9.80665),
        "gravity",
        "g",
        0.0,
        100.0,
        "m/s^2",
    )
    name = data.get("name", Path(source).stem if source else mech.name)
    if not isinstance(name, str):
        raise r.err(f"name must be a string, got {name!r}"[:120], "name")
    description = data.get("description", "")
    if not isinstance(description, str):
        raise r.err(
            f"description must be a string, got {type(description).__name__} {description!r}"[:160],
            entry="description",
        )
    swing_axis = _within(
        r,
        r.field_qty(front_t, "swing_axis", "length", "front", 0.0),
        "front",
        "swing_axis",
        -1e3,
        1e3,
        "m",
        open_low=False,
    )
    return Machine(
        mech,
        front,
        cylinders,
        circuits,
        ground_line=_within(
            r,
            r.field_qty(front_t, "ground_line", "length", "front", 0.0),
            "front",
            "ground_line",
            -1e3,
            1e3,
            "m",
            open_low=False,
        ),
        swing_axis=swing_axis,
        level_bottom=_within(
            r,
            r.field_qty(front_t, "level_bottom", "length", "front", 2.44),
            "front",
            "level_bottom",
            0.0,
            100.0,
            "m",
        ),
        gravity=g,
        base=read_base(r, data, swing_axis),
        lift_point=read_lift_point(r, data),
        hydraulics=read_hydraulics(r, data),
        name=str(name),
        source=source,
    )


#: the most cylinders acting together in one role
MAX_COUNT = 16
