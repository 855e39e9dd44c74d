"""A model file with new values of its dimensions: the parameters of a design (points'
coordinates, ``[lengths]``, bodies' masses, inertias and centres of mass, constant loads,
design variables) written into a copy of the file, each in the unit the file writes that entry
in, so that the copy loads as that design.

The copy is the file's tables written anew (TOML has no comments to carry over in a parsed
file): the same tables and entries, the file's leading comment block, and a comment naming the
values that were set. Nothing is written over an existing file unless asked.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from os import PathLike
from pathlib import Path
from typing import Any

from excavkin.errors import ModelError
from excavkin.io.toml_model import read_text_file, read_toml

#: a bare key of TOML
_BARE = re.compile(r"^[A-Za-z0-9_-]+$")
#: a quantity written as text: its number, then its unit
_QUANTITY = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")


def model_text_with(path: str | PathLike[str], values: Mapping[str, float], note: str = "") -> str:
    """The text of the model file ``path`` with the parameters ``values`` (SI) written in.

    Parameters
    ----------
    path : str or Path
        The model file (TOML).
    values : mapping of str to float
        Parameter name (as ``Mechanism.parameters`` names it: ``P.x``, ``"A-B"``,
        ``BODY.mass``, ``BODY.center_of_mass.x``, ``LOAD.Fx``, a design variable's name …) →
        its value, SI.
    note : str
        A comment line saying where the values come from.

    Returns
    -------
    str
        The new file's text: an entry written as ``"90 mm"`` keeps its unit, a bare number
        stays a bare number in the file's ``[units]``; an entry that referred to a design
        variable becomes the value itself.

    Raises
    ------
    ModelError
        A parameter with no entry in the file, naming the file and the parameter.
    """
    source = str(path)
    text = read_text_file(Path(path))
    data = read_toml(text, source)
    dropped = set_model_values(data, values, source)
    head = [line for line in leading_comments(text)]
    if values:
        listed = ", ".join(values)
        head += ["#"] * bool(head) + [f"# {note or 'values set'}: {listed}"]
    if dropped:
        head.append(f"# (no entry refers to design variable {', '.join(dropped)} any more)")
    return "\n".join([*head, dumps(data)]) if head else dumps(data)


def set_model_values(
    data: dict[str, Any],
    values: Mapping[str, float],
    source: str,
    units: Mapping[str, Any] | None = None,
) -> list[str]:
    """Write the parameters ``values`` (SI) into a parsed model ``data`` (in place), as
    [`model_text_with`][excavkin.io.model_write.model_text_with] does.

    Parameters
    ----------
    data : dict
        The model's tables, as ``tomllib`` parses them.
    values : mapping of str to float
        Parameter name → its value, SI.
    source : str
        The model's file, for messages.
    units : mapping of str to str, optional
        The units bare numbers are written in, per kind (default: the model's ``[units]``).

    Returns
    -------
    list of str
        The design variables no entry refers to any more, removed.

    Raises
    ------
    ModelError
        A parameter with no entry in the model, naming the source and the parameter.
    """
    if units is None:
        units = data.get("units", {}) if isinstance(data.get("units"), dict) else {}
    for name, value in values.items():
        holder, key, kind = _entry(data, name, source)
        if kind == "dimensionless":  # a ratio: a plain number
            holder[key] = float(value)
            continue
        holder[key] = written_value(holder[key], float(value), kind, units, data)
        for where, at in _visits(data, name, holder):  # the same value written elsewhere too
            where[at] = holder[key]
    return _drop_orphans(data)


def write_model(
    path: str | PathLike[str],
    values: Mapping[str, float],
    out: str | PathLike[str],
    *,
    force: bool = False,
    note: str = "",
) -> Path:
    """Write the model file ``path`` with the parameters ``values`` (SI) to ``out``, whole or
    not at all ([`model_text_with`][excavkin.io.model_write.model_text_with]).

    Parameters
    ----------
    path : str or Path
        The model file.
    values : mapping of str to float
        Parameter → SI value.
    out : str or Path
        The new file (``.toml``); never the model file itself.
    force : bool
        Whether ``out`` may be replaced.
    note : str
        The comment line at the top: where the values come from.

    Returns
    -------
    Path
        ``out``, written.

    Raises
    ------
    OutputError
        ``out`` exists (without ``force``), is the model file, or is not a ``.toml`` file.
    """
    from excavkin.io.files import write_toml_from

    return write_toml_from(
        path,
        out,
        lambda: model_text_with(path, values, note),
        force=force,
        itself="is the model file itself; write the design to another file",
    )


def _entry(data: dict[str, Any], name: str, source: str) -> tuple[Any, Any, str]:
    """Where parameter ``name`` is written in the parsed file: (the list or table holding it,
    its key or index, its kind)."""

    def table(key: str) -> dict[str, Any]:
        t = data.get(key, {})
        return t if isinstance(t, dict) else {}

    def missing() -> ModelError:
        return ModelError(f"parameter {name!r} has no entry in the file", source=source)

    design = table("design")
    if name in design and isinstance(design[name], dict) and "value" in design[name]:
        return design[name], "value", str(design[name].get("kind", "length"))
    if name in table("lengths"):
        return table("lengths"), name, "length"
    base, _, last = name.rpartition(".")
    points = table("points")
    if last in ("x", "y") and base in points and isinstance(points[base], list):
        return points[base], "xy".index(last), "length"
    bodies = table("bodies")
    if last in ("mass", "inertia") and last in (bodies.get(base) or {}):
        return bodies[base], last, last
    owner, _, com = base.rpartition(".")
    if com == "center_of_mass" and last in ("x", "y") and isinstance(bodies.get(owner), dict):
        given = bodies[owner].get("center_of_mass")
        if isinstance(given, list) and len(given) == 2:
            return given, "xy".index(last), "length"
    loads = table("loads")
    if isinstance(loads.get(base), dict) and "value" in loads[base]:
        value = loads[base]["value"]
        if last in ("Fx", "Fy") and isinstance(value, list) and len(value) == 2:
            return value, ("Fx", "Fy").index(last), "force"
        if last == "torque" and not isinstance(value, list):
            return loads[base], "value", "torque"
    rope = table("ropes").get(base)
    if last in ("drum_radius", "gear_ratio") and isinstance(rope, dict):
        if last == "gear_ratio":
            rope.setdefault("gear_ratio", 1.0)  # (a winch's default, written out)
        if last in rope:
            return rope, last, "length" if last == "drum_radius" else "dimensionless"
    gear = table("gears").get(base)
    if last == "ratio" and isinstance(gear, dict):
        if "ratio" not in gear:  # given by teeth or pitch radii: the ratio written instead
            gear.pop("teeth", None)
            gear.pop("radii", None)
            gear["ratio"] = 1.0
        return gear, "ratio", "dimensionless"
    owner, _, mid = base.rpartition(".")
    sheaved = table("ropes").get(owner)
    if mid == "radius" and isinstance(sheaved, dict):
        path, radii = sheaved.get("path"), sheaved.get("radii")
        if isinstance(path, list) and isinstance(radii, list) and last in path[1:-1]:
            return radii, path[1:-1].index(last), "length"
    cam = table("cams").get(owner)
    if mid == "lift" and isinstance(cam, dict) and isinstance(cam.get("lift"), list):
        rows, k = cam["lift"], int(last) if last.isdigit() else -1
        if 0 <= k < len(rows) - 1 and isinstance(rows[k], list) and len(rows[k]) == 2:
            oscillating = "along" not in cam
            return rows[k], 1, "angle" if oscillating else "length"
    rack = table("racks").get(base)
    if last == "radius" and isinstance(rack, dict) and "radius" in rack:
        return rack, "radius", "length"
    raise missing()


def _visits(data: dict[str, Any], name: str, holder: Any) -> list[tuple[Any, Any]]:
    """Where else the value of parameter ``name`` is written, ``holder`` being the entry
    written: a sheave radius ``ROPE.radius.S``'s later visits of S in its rope's ``radii`` (a
    block reeved over: each of its sheaves has the radius), a cam's ``CAM.lift.0`` its table's
    last row (the same lift, a turn on); none otherwise."""
    base, _, last = name.rpartition(".")
    owner, _, mid = base.rpartition(".")
    cams = data.get("cams")
    cam = cams.get(owner) if isinstance(cams, dict) and mid == "lift" else None
    if isinstance(cam, dict) and last == "0" and isinstance(cam.get("lift"), list):
        rows = cam["lift"]
        return [(rows[-1], 1)] if holder is rows[0] and len(rows) > 1 else []
    ropes = data.get("ropes")
    sheaved = ropes.get(owner) if isinstance(ropes, dict) and mid == "radius" else None
    if not isinstance(sheaved, dict) or sheaved.get("radii") is not holder:
        return []
    path = sheaved.get("path")
    if not isinstance(path, list):
        return []
    inner = path[1:-1]
    return [(holder, k) for k, p in enumerate(inner) if p == last][1:]


def _drop_orphans(data: dict[str, Any]) -> list[str]:
    """Remove the design variables that no entry refers to any more (each of their entries was
    given a value of its own); their names."""
    design = data.get("design")
    if not isinstance(design, dict):
        return []

    def strings(v: Any) -> list[str]:
        if isinstance(v, str):
            return [v]
        if isinstance(v, list):
            return [x for item in v for x in strings(item)]
        if isinstance(v, dict):
            return [x for item in v.values() for x in strings(item)]
        return []

    used = set(strings([data.get(k) for k in ("points", "bodies", "lengths")]))
    dropped = [name for name in design if name not in used]
    for name in dropped:
        del design[name]
    if not design:
        del data["design"]
    return dropped


def written_value(given: Any, value: float, kind: str, units: Mapping[str, Any], data: Any) -> Any:
    """``value`` (SI) as the file writes the entry ``given``: with its unit where it has one,
    else a bare number in the file's ``[units]`` for the kind, else with the SI unit.

    Parameters
    ----------
    given : object
        The entry as the file writes it now (``"90 mm"``, a bare number, a design variable's
        name).
    value : float
        The new value, SI.
    kind : str
        Its physical kind (``"length"``, ``"pressure"`` …).
    units : mapping of str to str
        The file's units of bare numbers, per kind.
    data : mapping
        The whole parsed file (its ``[design]`` variables).

    Returns
    -------
    str or float
        ``"<number> <unit>"`` or a bare number.
    """
    from excavkin.units import KINDS

    if isinstance(given, str):
        design = data.get("design", {})
        match = _QUANTITY.match(given)
        if isinstance(design, dict) and given in design:  # a design variable's name
            match = None
        if match and match.group(2):
            unit = match.group(2)
            return f"{_number(value, kind, unit)!r} {unit}"
    default = units.get(kind)
    if isinstance(default, str):
        return _number(value, kind, default)
    return f"{value!r} {KINDS[kind]}"


def _number(value: float, kind: str, unit: str) -> float:
    """``value`` (SI) in ``unit``: the shortest number that reads back to exactly ``value``,
    else the nearest one that does (a conversion rounds), else the plain conversion."""
    from excavkin.units import from_si, to_si

    plain = float(from_si(value, kind, unit))
    for digits in range(1, 18):
        shorter = float(f"{plain:.{digits}g}")
        if to_si(shorter, kind, unit) == value:
            return shorter
    # the conversion rounds: a neighbour of the plain value may read back exactly
    up = down = plain
    for _ in range(8):
        up, down = math.nextafter(up, math.inf), math.nextafter(down, -math.inf)
        for near in (up, down):
            if to_si(near, kind, unit) == value:
                return near
    return plain


def leading_comments(text: str) -> list[str]:
    """The comment lines at the top of a file (its description).

    Parameters
    ----------
    text : str
        The file's text.

    Returns
    -------
    list of str
    """
    out = []
    for line in text.splitlines():
        if not line.startswith("#"):
            break
        out.append(line)
    return out


# ---- TOML


def dumps(data: Mapping[str, Any]) -> str:
    """TOML text of parsed tables (strings, numbers, booleans, arrays and tables): scalars and
    arrays first, then each table under its header; a table of plain values (no table inside)
    is written inline where it is an entry of another table.

    Parameters
    ----------
    data : mapping
        What ``tomllib`` parses (no dates or times).

    Returns
    -------
    str
        TOML that ``tomllib`` reads back to ``data``.
    """
    lines: list[str] = []
    _table_body(data, [], lines)
    return "\n".join(lines).lstrip("\n") + "\n"


def _table_body(table: Mapping[str, Any], path: list[str], lines: list[str]) -> None:
    headed = [
        (k, v) for k, v in table.items() if _is_table(v) or (isinstance(v, dict) and not path)
    ]
    for k, v in table.items():
        if all(k != h for h, _ in headed):
            lines.append(f"{_key(k)} = {_value(v)}")
    for k, v in headed:
        lines.append("")
        lines.append(f"[{'.'.join(_key(p) for p in [*path, k])}]")
        _table_body(v, [*path, k], lines)


def _is_table(v: Any) -> bool:
    """A table written under its own header (one with a table inside; every table at the
    top of the file is too)."""
    return isinstance(v, dict) and (not v or any(isinstance(x, dict) for x in v.values()))


def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k, ensure_ascii=False)


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):  # JSON's escapes are TOML's; DEL is a control character in TOML
        return json.dumps(v, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + " }"
    raise ModelError(f"a value of type {type(v).__name__} cannot be written back")


__all__ = ["dumps", "model_text_with", "set_model_values", "write_model", "written_value"]
