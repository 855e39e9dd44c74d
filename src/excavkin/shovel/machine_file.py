"""Read a rope-shovel machine file (TOML, ``schema_version = 1``, ``family = "shovel"``).

The file builds on a general mechanism model, referenced (``model = "mining_shovel.toml"``,
relative to the machine file) or inline (a ``[model]`` table)::

    schema_version = 1
    family = "shovel"
    model = "mining_shovel.toml"
    [units]
    length = "m"
    mass = "kg"
    torque = "kN*m"
    angular_velocity = "rpm"
    [front]                       # bodies and points of the model
    boom = "boom"; saddle = "saddle"; handle = "handle"; dipper = "dipper"
    boom_foot = "BF"; shipper_shaft = "S"; sheave = "T"; suspension = "suspension"
    teeth = "K"; bail = "BL"; door_hinge = "DH"
    [hoist]
    rope = "hoist"; motors = 2; motor_torque = 16; motor_speed = 750
    gear_ratio = 80; drum_radius = 0.95; ropes = 2; length = [24, 46]
    [crowd]
    driver = "crowd"; motors = 1; motor_torque = 8; motor_speed = 900
    gear_ratio = 60; pinion_radius = 0.6; extension = [5, 10.5]
    [dipper]
    capacity = "56 m^3"; payload = 100000; payload_point = "PC"; door_length = 3.6; width = 4.2
    [base]                        # optional: the machinery layer's base (crawlers)

The hoist's ``gear_ratio`` and ``drum_radius`` replace the model's rope's. A rope backhoe's
file (``examples/eo4112_machine.toml``) has ``[drag]`` and ``[backhoe]`` instead, and may
describe its boom and hoist tackle in ``[boom]`` (`excavkin.shovel.boom`). Every number is
range-checked; an error names the file, the table and the entry.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np

from excavkin.io.toml_model import read_text_file, read_toml
from excavkin.machinery.base_file import read_base
from excavkin.machinery.file_fields import MachineReader, check_head, read_model
from excavkin.mechanism import Mechanism
from excavkin.shovel.boom import Boom
from excavkin.shovel.family import NAME
from excavkin.shovel.machine import (
    Crowd,
    Dipper,
    Drag,
    Front,
    Hoist,
    Motor,
    RopeBackhoe,
    Shovel,
)

SCHEMA_VERSION = 1
_TOP = {
    "schema_version",
    "family",
    "name",
    "description",
    "model",
    "units",
    "front",
    "hoist",
    "crowd",
    "dipper",
    "base",
    "gravity",
    "drag",
    "backhoe",
    "boom",
}
_FRONT_BODIES = ("boom", "saddle", "handle", "dipper")
_FRONT_POINTS = ("boom_foot", "shipper_shaft", "sheave", "teeth", "bail", "door_hinge")
_MOTOR = {"motors", "motor_torque", "motor_speed", "gear_ratio"}
_MAX_COUNT = 16


def loads_machine(text: str, source: str | None = None) -> Shovel | RopeBackhoe:
    """Parse a shovel machine file from TOML text; see
    [`load_machine`][excavkin.shovel.machine_file.load_machine].

    Parameters
    ----------
    text : str
        The file's text.
    source : str, optional
        The file, for messages and for a model file named relative to it.

    Returns
    -------
    Shovel or RopeBackhoe
        A rope backhoe where the file has a ``[drag]`` table.
    """
    return _machine(read_toml(text, source), source)


def load_machine(path: str | Path) -> Shovel | RopeBackhoe:
    """Read a rope-shovel machine file.

    Parameters
    ----------
    path : str or Path
        The file, or the name of a built-in machine (``"mining_shovel_machine"``).

    Returns
    -------
    Shovel or RopeBackhoe
        A rope backhoe where the file has a ``[drag]`` table.

    Raises
    ------
    ModelError
        Naming the file, the table and the entry of the first problem found.
    """
    import excavkin

    file = excavkin.source_file(path, "machine")
    return loads_machine(read_text_file(file), str(file))


def _machine(data: dict[str, Any], source: str | None) -> Shovel | RopeBackhoe:
    r = MachineReader(data, source)
    if data.get("family") != NAME:
        raise r.err(
            f"family = {data.get('family')!r}: this reader reads rope-shovel machine files "
            f'(family = "{NAME}")',
            None,
            "family",
        )
    check_head(r, SCHEMA_VERSION, _TOP, "mining_shovel.toml")
    model = read_model(r, data.get("model"), source, "mining_shovel.toml")
    if "drag" in data:
        return _backhoe(r, data, model, source)

    ft = r.subtable(data, "front", "front")
    r.keys(ft, {*_FRONT_BODIES, *_FRONT_POINTS, "suspension"}, "front")
    bodies = {b.name: b for b in model.bodies}
    names: dict[str, str] = {}
    for key in _FRONT_BODIES:
        names[key] = r.text(ft, key, "front", key)
        if names[key] not in bodies:
            raise r.err(f"{names[key]!r} is not a body of the model", "front", key)
    owner = {"boom_foot": "boom", "shipper_shaft": "boom", "sheave": "boom"}
    for key in _FRONT_POINTS:
        names[key] = r.text(ft, key, "front")
        body = bodies[names[owner.get(key, "dipper")]]
        if names[key] not in body.points:
            raise r.err(f"{names[key]!r} is not a point of the body {body.name!r}", "front", key)
    names["suspension"] = r.text(ft, "suspension", "front", "suspension")
    ropes = {rope.name: rope for rope in model.ropes}
    if names["suspension"] not in ropes or ropes[names["suspension"]].mode != "locked":
        raise r.err(
            f"{names['suspension']!r} is not a locked rope of the model", "front", "suspension"
        )
    front = Front(**names)

    ht = r.subtable(data, "hoist", "hoist")
    r.keys(ht, _MOTOR | {"rope", "drum_radius", "ropes", "length"}, "hoist")
    rope_name = r.text(ht, "rope", "hoist", "hoist")
    if rope_name not in ropes or ropes[rope_name].mode != "winch":
        raise r.err(f"{rope_name!r} is not a winch rope of the model", "hoist", "rope")
    hoist = Hoist(
        rope=rope_name,
        motor=_motor(r, ht, "hoist"),
        gear_ratio=r.bounded(ht, "gear_ratio", "dimensionless", "hoist", 0.0, 1e4, ""),
        drum_radius=r.bounded(ht, "drum_radius", "length", "hoist", 0.0, 20.0, "m"),
        ropes=_count(r, ht, "ropes", "hoist"),
        length=_range(r, ht, "length", "hoist"),
    )
    model = dataclasses.replace(
        model,
        ropes=tuple(
            dataclasses.replace(rp, gear_ratio=hoist.gear_ratio, drum_radius=hoist.drum_radius)
            if rp.name == rope_name
            else rp
            for rp in model.ropes
        ),
    )

    ct = r.subtable(data, "crowd", "crowd")
    r.keys(ct, _MOTOR | {"driver", "pinion_radius", "extension"}, "crowd")
    driver = r.text(ct, "driver", "crowd", "crowd")
    linear = {d.name: d for d in model.linear}
    if driver not in linear or linear[driver].mode != "driven":
        raise r.err(f"{driver!r} is not a driven linear driver of the model", "crowd", "driver")
    radius = r.bounded(ct, "pinion_radius", "length", "crowd", 0.0, 10.0, "m")
    crowd = Crowd(
        driver=driver,
        motor=_motor(r, ct, "crowd"),
        gear_ratio=r.bounded(ct, "gear_ratio", "dimensionless", "crowd", 0.0, 1e4, ""),
        pinion_radius=radius,
        extension=_range(r, ct, "extension", "crowd"),
        sigma=_rack_side(r, model, linear[driver].between, front.shipper_shaft, radius),
    )

    dt = r.subtable(data, "dipper", "dipper")
    r.keys(dt, {"capacity", "payload", "payload_point", "door_length", "width"}, "dipper")
    point = r.text(dt, "payload_point", "dipper")
    if point not in bodies[front.dipper].points:
        raise r.err(f"{point!r} is not a point of the dipper", "dipper", "payload_point")
    dipper = Dipper(
        capacity=r.bounded(dt, "capacity", "volume", "dipper", 0.0, 1e3, "m^3"),
        payload=r.bounded(dt, "payload", "mass", "dipper", 0.0, 1e7, "kg", open_low=False),
        payload_point=point,
        door_length=r.bounded(
            dt, "door_length", "length", "dipper", 0.0, 50.0, "m", open_low=False
        ),
        width=r.bounded(dt, "width", "length", "dipper", 0.0, 50.0, "m"),
    )

    g = _gravity(r, data)
    name = data.get("name", Path(source).stem if source else model.name)
    if not isinstance(name, str):
        raise r.err(f"name must be a string, got {name!r}"[:120], entry="name")
    mech = Mechanism(model)
    return Shovel(
        mech,
        front,
        hoist,
        crowd,
        dipper,
        read_base(r, data, 0.0),
        g,
        name,
        source,
    )


def _count(r: MachineReader, t: dict[str, Any], key: str, table: str) -> int:
    n = t.get(key, 1)
    if not isinstance(n, int) or isinstance(n, bool) or not 1 <= n <= _MAX_COUNT:
        raise r.err(f"{key} must be a whole number from 1 to {_MAX_COUNT}", table, key)
    return n


def _motor(r: MachineReader, t: dict[str, Any], table: str) -> Motor:
    return Motor(
        count=_count(r, t, "motors", table),
        torque=r.bounded(t, "motor_torque", "torque", table, 0.0, 1e8, "N*m"),
        speed=r.bounded(t, "motor_speed", "angular_velocity", table, 0.0, 1e4, "rad/s"),
    )


def _range(r: MachineReader, t: dict[str, Any], key: str, table: str) -> tuple[float, float]:
    if key not in t:
        raise r.err(f"{key!r} is missing", table)
    value = t[key]
    if not isinstance(value, list) or len(value) != 2:
        raise r.err(f"{key} must be [shortest, longest]", table, key)
    lo, hi = (r.bounded({key: v}, key, "length", table, 0.0, 1e3, "m") for v in value)
    if not lo < hi:
        raise r.err(f"{key}: the shortest ({lo:.6g} m) must be below the longest", table, key)
    return lo, hi


def _backhoe(r: MachineReader, data: dict[str, Any], model: Any, source: str | None) -> RopeBackhoe:
    """A rope backhoe: ``[drag]`` (the drag winch) and ``[backhoe]`` (stick and bucket)."""
    for key in ("front", "hoist", "crowd", "dipper"):
        if key in data:
            raise r.err(f"a rope backhoe ([drag]) has no [{key}] table", key)
    dt = r.subtable(data, "drag", "drag")
    r.keys(dt, _MOTOR | {"driver", "drum_radius", "parts", "length"}, "drag")
    driver = r.text(dt, "driver", "drag", "drag")
    linear = {d.name: d for d in model.linear}
    if driver not in linear or linear[driver].mode != "driven":
        raise r.err(f"{driver!r} is not a driven linear driver of the model", "drag", "driver")
    drag = Drag(
        driver=driver,
        motor=_motor(r, dt, "drag"),
        gear_ratio=r.bounded(dt, "gear_ratio", "dimensionless", "drag", 0.0, 1e4, ""),
        drum_radius=r.bounded(dt, "drum_radius", "length", "drag", 0.0, 20.0, "m"),
        parts=_count(r, dt, "parts", "drag"),
        length=_range(r, dt, "length", "drag") if "length" in dt else None,
    )
    bt = r.subtable(data, "backhoe", "backhoe")
    r.keys(bt, {"stick", "bucket"}, "backhoe")
    bodies = {b.name for b in model.bodies}
    names = {}
    for key in ("stick", "bucket"):
        names[key] = r.text(bt, key, "backhoe", key)
        if names[key] not in bodies:
            raise r.err(f"{names[key]!r} is not a body of the model", "backhoe", key)
    boom = _boom(r, data, model, driver) if "boom" in data else None
    if boom is None and "gravity" in data:
        raise r.err("a rope backhoe reads [gravity] only with a [boom] table", "gravity")
    name = data.get("name", Path(source).stem if source else model.name)
    if not isinstance(name, str):
        raise r.err(f"name must be a string, got {name!r}"[:120], entry="name")
    return RopeBackhoe(Mechanism(model), drag, names["stick"], names["bucket"], name, source, boom)


def _gravity(r: MachineReader, data: dict[str, Any]) -> float:
    grav = data.get("gravity", {})
    if not isinstance(grav, dict):
        raise r.err('must be a table such as { g = "9.81 m/s^2" }', "gravity")
    r.keys(grav, {"g"}, "gravity")
    return r.bounded(grav, "g", "acceleration", "gravity", 0.0, 100.0, "m/s^2", default=9.80665)


_BOOM_POINTS = ("foot", "centre", "hoist_block", "gantry", "drag_lead")
_MIN_ARM = 0.05  # m: a tackle's line closer to the foot than this cannot hold a boom


def _point(r: MachineReader, t: dict[str, Any], key: str) -> tuple[float, float]:
    if key not in t:
        raise r.err(f"{key!r} is missing", "boom")
    x, y = r.xy(t[key], "boom", key)
    if not (np.isfinite(x) and np.isfinite(y)) or max(abs(x), abs(y)) > 100.0:
        raise r.err(f"{key} must lie within 100 m of the model's origin", "boom", key)
    return x, y


def _boom(r: MachineReader, data: dict[str, Any], model: Any, driver: str) -> Boom:
    """The ``[boom]`` table: the boom's foot, weight and hoist tackle (`excavkin.shovel.boom`)."""
    bt = r.subtable(data, "boom", "boom")
    r.keys(bt, {*_BOOM_POINTS, "mass", "hoist_parts", "angle"}, "boom")
    for kind in ("sliders", "gears", "racks", "cams"):
        if getattr(model, kind):
            raise r.err(
                f"the boom's balance reads a model of pins, linear drivers and rotary drivers; "
                f"this one has {kind}",
                "boom",
            )
    foot, centre, block, gantry, lead = (_point(r, bt, k) for k in _BOOM_POINTS)
    frame = next(b for b in model.bodies if b.ground)
    ends = [p for p in next(d for d in model.linear if d.name == driver).between]
    on_frame = [p for p in ends if p in frame.points]
    if len(on_frame) != 1:
        raise r.err(
            f"the drag rope {driver!r} must run from one point of the frame {frame.name!r} "
            f"(its sheave on the boom) to the bucket's side, not {' to '.join(ends)}",
            "drag",
            "driver",
        )
    sheave = model.points[on_frame[0]]
    if np.hypot(lead[0] - sheave[0], lead[1] - sheave[1]) < 0.1:
        raise r.err(
            f"the drag rope's lead lies within 0.1 m of its sheave {on_frame[0]!r}",
            "boom",
            "drag_lead",
        )
    if np.hypot(gantry[0] - block[0], gantry[1] - block[1]) < 0.1:
        raise r.err("the gantry's sheave lies within 0.1 m of the hoist block", "boom", "gantry")
    boom = Boom(
        foot=foot,
        mass=r.bounded(bt, "mass", "mass", "boom", 0.0, 1e6, "kg", open_low=False),
        centre=centre,
        block=block,
        gantry=gantry,
        parts=_count(r, bt, "hoist_parts", "boom"),
        angle=r.bounded(bt, "angle", "angle", "boom", -1.5, 1.5, "rad", default=0.0),
        sheave=on_frame[0],
        lead=lead,
        gravity=_gravity(r, data),
    )
    if abs(boom.hoist_arm) < _MIN_ARM:
        raise r.err(
            f"the hoist tackle's line (hoist_block to gantry) passes {abs(boom.hoist_arm):.3g} m "
            f"from the boom foot: it cannot hold the boom (at least {_MIN_ARM} m)",
            "boom",
            "gantry",
        )
    arm = np.subtract(centre, foot)
    held = float(arm[0] * boom.down[1] - arm[1] * boom.down[0]) * boom.mass
    if held * boom.hoist_arm > 0.0:
        raise r.err(
            "the hoist tackle (hoist_block to gantry) turns the boom about its foot the way "
            "its weight does: it would push to hold it",
            "boom",
            "gantry",
        )
    return boom


def _rack_side(
    r: MachineReader, model: Any, between: tuple[str, str], shaft: str, radius: float
) -> float:
    """σ: +1 where the rack's pitch line (the crowd driver's points, from the saddle's pitch
    point to the handle) passes to the left of the shipper shaft, −1 to the right; the line must
    pass the pinion's pitch radius from the shaft."""
    pts = model.points
    p, q, c = (np.asarray(pts[k], dtype=float) for k in (*between, shaft))
    u = (q - p) / np.hypot(*(q - p))
    off = float(u[0] * (p - c)[1] - u[1] * (p - c)[0])  # the pitch point left of u from S
    if not abs(abs(off) - radius) <= 1e-6 * max(1.0, radius):
        raise r.err(
            f"the rack's pitch line ({between[0]} to {between[1]}) passes {abs(off):.6g} m from "
            f"the shipper shaft {shaft!r}, not the pinion's pitch radius {radius:.6g} m",
            "crowd",
            "pinion_radius",
        )
    return 1.0 if off > 0.0 else -1.0
