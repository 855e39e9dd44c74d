"""Read a wheel-loader machine file (TOML, ``schema_version = 1``, ``family = "loader"``).

The file builds on a general mechanism model, referenced (``model = "wheel_loader.toml"``,
relative to the machine file) or inline (a ``[model]`` table)::

    schema_version = 1
    family = "loader"
    model = "wheel_loader.toml"
    [units]                      # defaults for bare numbers in this file
    length = "mm"
    pressure = "MPa"
    mass = "kg"
    [linkage]                    # bodies and points of the model
    lift_arm = "lift_arm"; bucket = "bucket"; edge = "W"; heel = "K"
    carry_height = 400           # hinge-pin height in the carry position
    [cylinders.lift]             # and [cylinders.tilt]
    driver = "lift_cyl"; count = 2; retracted = 1733; stroke = 1020; bore = 140; rod = 80
    circuit = "lift"; mass = 360; raises = "extend"     # tilt: rolls_back = "extend"
    [circuits.lift]
    working = 25; relief = 28
    [bucket]
    capacity = "3.0 m^3"         # rated (heaped), ISO 7546
    width = 2900
    load_cg = [650, 50]          # the rated load's centre of gravity in the bucket frame
    [chassis]
    wheelbase = 3300; front_axle = [0, 800]; tread = 2250; tyre_radius = 800
    articulation = -1650; max_articulation = "40 deg"; rear_axle = "oscillating"
    friction = 0.6               # optional: tyres on the ground (the slipping limit)
    [chassis.front_frame]        # and .rear_frame, .counterweight
    mass = 3800; center_of_mass = [-300, 1000]
    [hydraulics.pumps.P1]        # optional: pumps (no swing)
    flow = "230 L/min"; feeds = ["lift", "tilt"]

Every number is range-checked; an error names the file, the table and the entry.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from excavkin.io.toml_model import read_text_file, read_toml
from excavkin.loader.family import NAME
from excavkin.loader.machine import (
    ROLES,
    Bucket,
    Chassis,
    Linkage,
    Loader,
    LoaderHydraulics,
)
from excavkin.machinery.base import Mass
from excavkin.machinery.cylinders_file import read_circuits, read_cylinders
from excavkin.machinery.file_fields import MachineReader, check_head, read_model
from excavkin.machinery.hydraulics_file import read_hydraulics
from excavkin.mechanism import Mechanism

SCHEMA_VERSION = 1
_TOP = {
    "schema_version",
    "family",
    "name",
    "description",
    "model",
    "units",
    "linkage",
    "cylinders",
    "circuits",
    "bucket",
    "chassis",
    "gravity",
    "hydraulics",
}
_LINKAGE = {"lift_arm", "bucket", "edge", "heel", "carry_height"}
#: per role, the key that says which motion of the cylinder does the role's work
_MOTION = {"lift": "raises", "tilt": "rolls_back"}
_CHASSIS = {
    "wheelbase",
    "front_axle",
    "tread",
    "tyre_radius",
    "articulation",
    "max_articulation",
    "rear_axle",
    "front_frame",
    "rear_frame",
    "counterweight",
    "friction",
}
#: the most cylinders acting together in one role; the largest coordinate (m) and mass (kg)
MAX_COUNT, _MAX_X, _MAX_MASS = 16, 1e3, 1e7


def loads_machine(text: str, source: str | None = None) -> Loader:
    """Parse a loader machine file from TOML text; see
    [`load_machine`][excavkin.loader.machine_file.load_machine].

    Parameters
    ----------
    text : str
        The file's text.
    source : str, optional
        The file, for messages and for a model file named relative to it.

    Returns
    -------
    Loader
    """
    return _machine(read_toml(text, source), source)


def load_machine(path: str | Path) -> Loader:
    """Read a wheel-loader machine file.

    Parameters
    ----------
    path : str or Path
        The file, or the name of a built-in machine (``"wheel_loader_machine"``).

    Returns
    -------
    Loader

    Raises
    ------
    ModelError
        Naming the file, the table and the entry of the first problem found.
    """
    import excavkin

    file = excavkin.source_file(path, "machine")
    return loads_machine(read_text_file(file), str(file))


def _machine(data: dict[str, Any], source: str | None) -> Loader:
    r = MachineReader(data, source)
    if data.get("family") != NAME:  # another family's file: its keys are not the question
        raise r.err(
            f"family = {data.get('family')!r}: this reader reads loader machine files "
            f'(family = "{NAME}")',
            None,
            "family",
        )
    check_head(r, SCHEMA_VERSION, _TOP, "wheel_loader.toml")
    mech = Mechanism(read_model(r, data.get("model"), source, "wheel_loader.toml"))

    lt = r.subtable(data, "linkage", "linkage")
    r.keys(lt, _LINKAGE, "linkage")
    linkage = Linkage(
        lift_arm=r.text(lt, "lift_arm", "linkage", "lift_arm"),
        bucket=r.text(lt, "bucket", "linkage", "bucket"),
        edge=r.text(lt, "edge", "linkage"),
        heel=r.text(lt, "heel", "linkage"),
    )
    carry = r.bounded(lt, "carry_height", "length", "linkage", 0.0, 100.0, "m")

    circuits = read_circuits(r, data)
    cylinders = read_cylinders(r, data, ROLES, "a loader", motions=_MOTION, max_count=MAX_COUNT)

    bt = r.subtable(data, "bucket", "bucket")
    r.keys(bt, {"capacity", "width", "load_cg"}, "bucket")
    if "load_cg" not in bt:
        raise r.err("'load_cg' is missing", "bucket")
    cg = r.xy(bt["load_cg"], "bucket", "load_cg")
    for v in cg:
        if not abs(v) <= 100.0:
            raise r.err(f"load_cg = {v:.6g} m is out of range (±100 m)", "bucket", "load_cg")
    bucket = Bucket(
        capacity=r.bounded(bt, "capacity", "volume", "bucket", 0.0, 1e3, "m^3"),
        width=r.bounded(bt, "width", "length", "bucket", 0.0, 50.0, "m"),
        load_cg=cg,
    )
    chassis = _chassis(r, data)

    grav = data.get("gravity", {})
    if not isinstance(grav, dict):
        raise r.err('must be a table such as { g = "9.81 m/s^2" }', "gravity")
    r.keys(grav, {"g"}, "gravity")
    g = r.bounded(grav, "g", "acceleration", "gravity", 0.0, 100.0, "m/s^2", default=9.80665)
    name = data.get("name", Path(source).stem if source else mech.name)
    if not isinstance(name, str):
        raise r.err(f"name must be a string, got {name!r}"[:120], entry="name")
    return Loader(
        mech,
        linkage,
        cylinders,
        circuits,
        bucket,
        chassis,
        carry_height=carry,
        gravity=g,
        hydraulics=read_hydraulics(r, data, LoaderHydraulics),
        name=name,
        source=source,
    )


def _chassis(r: MachineReader, data: dict[str, Any]) -> Chassis:
    table = "chassis"
    t = r.subtable(data, table, table)
    r.keys(t, _CHASSIS, table)
    if "front_axle" not in t:
        raise r.err("'front_axle' is missing", table)
    fx, fy = r.xy(t["front_axle"], table, "front_axle")
    for v in (fx, fy):
        if not abs(v) <= _MAX_X:
            raise r.err(f"front_axle: {v:.6g} m is out of range (±{_MAX_X:g} m)", table)
    rear = t.get("rear_axle", "oscillating")
    if rear not in ("oscillating", "rigid"):
        raise r.err(f"rear_axle must be 'oscillating' or 'rigid', not {rear!r}", table, "rear_axle")
    wheelbase = r.bounded(t, "wheelbase", "length", table, 0.0, 100.0, "m")
    articulation = r.bounded(
        t, "articulation", "length", table, -_MAX_X, _MAX_X, "m", open_low=False
    )
    if not fx - wheelbase <= articulation <= fx:
        raise r.err(
            "the articulation joint must lie between the rear and the front axle",
            table,
            "articulation",
        )
    tyre = r.bounded(t, "tyre_radius", "length", table, 0.0, 10.0, "m")
    return Chassis(
        wheelbase=wheelbase,
        front_axle=(fx, fy),
        tread=r.bounded(t, "tread", "length", table, 0.0, 50.0, "m"),
        tyre_radius=tyre,
        articulation=articulation,
        max_articulation=r.bounded(
            t, "max_articulation", "angle", table, 0.0, math.radians(60.0), "rad", open_low=False
        ),
        front_frame=_mass(r, t, "front_frame", positive=True),
        rear_frame=_mass(r, t, "rear_frame", positive=True),
        counterweight=_mass(r, t, "counterweight", positive=False),
        oscillating=rear == "oscillating",
        friction=(
            r.bounded(t, "friction", "dimensionless", table, 0.0, 5.0, "")
            if "friction" in t
            else None
        ),
    )


def _mass(r: MachineReader, chassis: dict[str, Any], part: str, *, positive: bool) -> Mass:
    table = f"chassis.{part}"
    t = r.subtable(chassis, part, table)
    r.keys(t, {"mass", "center_of_mass"}, table)
    m = r.bounded(t, "mass", "mass", table, 0.0, _MAX_MASS, "kg", open_low=positive)
    if "center_of_mass" not in t:
        raise r.err("'center_of_mass' is missing", table)
    x, y = r.xy(t["center_of_mass"], table, "center_of_mass")
    for v in (x, y):
        if not abs(v) <= _MAX_X:
            raise r.err(f"{v:.6g} m is out of range (±{_MAX_X:g} m)", table, "center_of_mass")
    return Mass(part, m, x, y)
