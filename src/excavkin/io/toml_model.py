"""Read a mechanism from TOML (``schema_version = 1``) into an SI [`Model`][excavkin.Model].

Every number may carry its own unit (``"48 mm"``, ``"50 deg"``); a bare number takes the
file's ``[units]`` default for its kind, and is an error without one.
"""

from __future__ import annotations

import math
import re
import tomllib
from pathlib import Path
from typing import Any

from excavkin.errors import ModelError, UnitError, did_you_mean
from excavkin.model.entities import (
    STANDARD_GRAVITY,
    Body,
    CamFollower,
    DesignVariable,
    GearPair,
    Gravity,
    LinearDriver,
    Model,
    PointForce,
    RackPinion,
    Rope,
    RotaryDriver,
    Slider,
    Torque,
)
from excavkin.model.validate import validate
from excavkin.units import KINDS, check_unit, to_si

SCHEMA_VERSION = 1
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_TOP = {
    "schema_version",
    "name",
    "description",
    "units",
    "points",
    "bodies",
    "lengths",
    "drivers",
    "sliders",
    "loads",
    "gravity",
    "design",
    "gears",
    "racks",
    "cams",
    "ropes",
}


class TomlReader:
    """Reads values of one TOML file: units from its ``[units]`` table, errors naming the file,
    the table and the entry. Shared by the model and machine readers."""

    def __init__(self, data: dict[str, Any], source: str | None) -> None:
        self.data = data
        self.source = source
        units = data.get("units", {})
        if not isinstance(units, dict):
            raise self.err("must be a table of unit names", "units")
        self.units: dict[str, str] = {}
        for kind, unit in units.items():
            if kind not in KINDS or kind == "dimensionless":
                known = ", ".join(k for k in KINDS if k != "dimensionless")
                raise self.err(f"unknown quantity kind (known: {known})", "units", kind)
            if not isinstance(unit, str):
                raise self.err('the unit must be a string such as "mm"', "units", kind)
            try:
                check_unit(unit, kind)
            except UnitError as exc:
                raise UnitError(exc.problem, table="units", entry=kind, source=source) from None
            self.units[kind] = unit
        #: design variables: name → (value, kind); and the entries that refer to each
        self.variables: dict[str, tuple[float, str]] = {}
        self.references: dict[str, list[str]] = {}

    def err(self, problem: str, table: str | None = None, entry: str | None = None) -> ModelError:
        return ModelError(problem, table=table, entry=entry, source=self.source)

    def qty(self, value: Any, kind: str, table: str, entry: str, param: str | None = None) -> float:
        """A quantity in SI; where ``param`` names the parameter this entry is, the value may
        also be the name of a design variable of the file (a reference, nothing evaluated)."""
        if param is not None and isinstance(value, str) and value in self.variables:
            nominal, var_kind = self.variables[value]
            if var_kind != kind:
                raise self.err(
                    f"design variable {value!r} is a {var_kind}, but this entry is a {kind}",
                    table,
                    entry,
                )
            self.references.setdefault(value, []).append(param)
            return nominal
        try:
            return to_si(value, kind, self.units.get(kind))
        except UnitError as exc:
            raise UnitError(exc.problem, table=table, entry=entry, source=self.source) from None

    def xy(
        self, value: Any, table: str, entry: str, param: str | None = None
    ) -> tuple[float, float]:
        if not isinstance(value, list) or len(value) != 2:
            raise self.err("expected two coordinates [x, y]", table, entry)
        px, py = (None, None) if param is None else (f"{param}.x", f"{param}.y")
        return (
            self.qty(value[0], "length", table, entry, px),
            self.qty(value[1], "length", table, entry, py),
        )

    def design_variables(self) -> None:
        """Read ``[design.NAME]`` tables: ``value``, optional ``bounds = [low, high]`` and
        ``kind`` (length, the default; mass; inertia)."""
        for name, spec in self.table("design").items():
            self.name(name, "design")
            table = f"design.{name}"
            if not isinstance(spec, dict):
                raise self.err('must be a table such as { value = "120 mm" }', table)
            self.keys(spec, {"value", "bounds", "kind"}, "design", name)
            kind = spec.get("kind", "length")
            if kind not in ("length", "mass", "inertia"):
                raise self.err(
                    f"kind must be 'length', 'mass' or 'inertia', not {kind!r}", table, "kind"
                )
            if "value" not in spec:
                raise self.err("a design variable needs its nominal value", table, "value")
            value = self.qty(spec["value"], kind, table, "value")
            self.variables[name] = (value, kind)

    def design_bounds(self, name: str) -> tuple[float, float] | None:
        spec = self.table("design")[name]
        if "bounds" not in spec:
            return None
        table = f"design.{name}"
        given = spec["bounds"]
        if not isinstance(given, list) or len(given) != 2:
            raise self.err("bounds must be [low, high]", table, "bounds")
        kind = self.variables[name][1]
        lo, hi = (self.qty(v, kind, table, "bounds") for v in given)
        value = self.variables[name][0]
        if not lo <= value <= hi:
            raise self.err(
                f"bounds must hold the nominal value: {lo:.6g} ≤ {value:.6g} ≤ {hi:.6g} fails",
                table,
                "bounds",
            )
        return lo, hi

    def name(self, value: Any, table: str, entry: str | None = None) -> str:
        if not isinstance(value, str) or not _NAME.match(value):
            raise self.err(
                f"{value!r} is not a valid name (letters, digits and _, not starting with a digit)",
                table,
                entry,
            )
        return value

    def table(self, key: str, required: bool = False) -> dict[str, Any]:
        t = self.data.get(key, {})
        if not isinstance(t, dict):
            raise self.err("must be a table", key)
        if required and not t:
            raise self.err("is missing or empty", key)
        return t

    def keys(
        self, entry: dict[str, Any], allowed: set[str], table: str, name: str | None = None
    ) -> None:
        extra = set(entry) - allowed
        if extra:
            hints = "".join(did_you_mean(k, allowed) for k in sorted(extra))
            raise self.err(
                f"unknown key{'s' if len(extra) > 1 else ''} "
                f"{', '.join(sorted(extra))}{hints} (allowed: {', '.join(sorted(allowed))})",
                table,
                name,
            )


#: the largest model or machine file read (a real one is a few kB)
MAX_FILE_BYTES = 2_000_000
#: the most points a model may have
MAX_POINTS = 10_000
#: the deepest nesting of arrays and tables in a file (a model needs 3)
MAX_DEPTH = 8


def read_toml(text: str, source: str | None = None) -> dict[str, Any]:
    """Parse TOML text; a syntax error, an oversized or too deeply nested file becomes a
    [`ModelError`][excavkin.ModelError] naming the file."""
    if len(text) > MAX_FILE_BYTES:
        raise ModelError(
            f"the file is {len(text):,} characters long; a model or machine file is at most "
            f"{MAX_FILE_BYTES:,}",
            source=source,
        )
    if _nesting(text) > MAX_DEPTH:
        raise ModelError(
            f"arrays or tables are nested more than {MAX_DEPTH} deep; a model needs 3",
            source=source,
        )
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ModelError(f"not valid TOML: {exc}", source=source) from None
    except RecursionError:  # a guard for nesting that _nesting could not see
        raise ModelError("arrays or tables are nested too deeply", source=source) from None


def _nesting(text: str) -> int:
    """The deepest run of open brackets and braces outside strings and comments (an upper
    bound of TOML's nesting, found in one pass without parsing)."""
    depth = deepest = 0
    quote = ""
    comment = False
    for ch in text:
        if comment:
            comment = ch != "\n"
        elif quote:
            if ch == quote:
                quote = ""
        elif ch in "\"'":
            quote = ch
        elif ch == "#":
            comment = True
        elif ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in "]}":
            depth = max(depth - 1, 0)
    return deepest


def read_text_file(path: str | Path) -> str:
    """A model, machine or study file as text: read only if it is a regular file of at most
    `MAX_FILE_BYTES`; size, kind, encoding and file-system errors as one
    [`ModelError`][excavkin.ModelError] naming the file."""
    from excavkin.io.files import ReadError, read_limited

    try:
        data = read_limited(path, MAX_FILE_BYTES, "a model, machine or study file")
        return data.decode("utf-8")
    except ReadError as exc:
        raise ModelError(exc.problem, source=str(path)) from None
    except UnicodeDecodeError as exc:
        raise ModelError(
            f"the file is not UTF-8 text (byte {exc.start} is {exc.object[exc.start]:#04x})",
            source=str(path),
        ) from None


def loads_model(text: str, source: str | None = None) -> Model:
    """Parse a mechanism from TOML text; see `load_model`."""
    return build_model(read_toml(text, source), source)


def load_model(path: str | Path) -> Model:
    """Read and validate a mechanism file.

    Raises
    ------
    ModelError
        Naming the file, the table and the entry of the first problem found.
    """
    return loads_model(read_text_file(path), str(path))


#: the sketch's size must lie between these (m): below, coordinates are round-off
#: (1e-290 m underflows a squared distance); above, the model is not a machine
MIN_EXTENT, MAX_EXTENT = 1e-6, 1e6


def _check_extent(points: dict[str, tuple[float, float]], r: TomlReader) -> None:
    xs = [x for x, _ in points.values()]
    ys = [y for _, y in points.values()]
    extent = max(max(xs) - min(xs), max(ys) - min(ys)) if points else 0.0
    far = max((max(abs(x), abs(y)) for x, y in points.values()), default=0.0)
    if len(points) > 1 and not extent >= MIN_EXTENT:
        raise r.err(
            f"the sketch spans {extent:.3g} m; points closer than {MIN_EXTENT:g} m cannot be "
            "told apart in double precision (check the [units] length)",
            "points",
        )
    if far > MAX_EXTENT:
        raise r.err(
            f"a point lies {far:.3g} m from the origin; coordinates are at most "
            f"{MAX_EXTENT:g} m (check the [units] length)",
            "points",
        )


def build_model(data: dict[str, Any], source: str | None = None) -> Model:
    """Build and validate a model from parsed TOML tables (``schema_version = 1``): one reader
    per table, in the order the file's checks have always run, then the model's
    cross-references (`validate`)."""
    r = TomlReader(data, source)
    name = _header(r, data, source)
    r.design_variables()
    points = _points(r)
    bodies = _bodies(r)
    rotary, linear = _drivers(r, bodies)
    sliders = _sliders(r)
    lengths = _lengths(r)
    loads = _loads(r, {b.name for b in bodies}, {b.name: b.points for b in bodies})
    gravity = _gravity(r)
    gears = _gears(r, bodies)
    racks = _racks(r, bodies)
    cams = _cams(r, bodies)
    ropes = _ropes(r)

    model = Model(
        str(name),
        points,
        tuple(bodies),
        tuple(rotary),
        tuple(linear),
        tuple(sliders),
        lengths,
        source,
        loads,
        gravity,
        _design(r),
        gears,
        racks,
        cams,
        ropes=ropes,
    )
    validate(model)
    return model


def _header(r: TomlReader, data: dict[str, Any], source: str | None) -> str:
    """The file's version, its top-level keys, and its name (checked; the description too)."""
    ver = data.get("schema_version")
    if ver is None:
        raise r.err(
            f"schema_version is missing (this version of excavkin reads "
            f"schema_version = {SCHEMA_VERSION})"
        )
    if type(ver) is not int or ver != SCHEMA_VERSION:
        raise r.err(
            f"schema_version = {ver!r} is not supported (this version of excavkin "
            f"reads {SCHEMA_VERSION})"
        )
    unknown = set(data) - _TOP
    if unknown and {"cylinders", "model"} & unknown:
        raise r.err(
            "this looks like an excavator machine file (it has [cylinders] or model = ...), "
            "not a mechanism model: use it with `excavkin excavator ranges|forces|ik`"
        )
    if unknown:
        raise r.err(
            f"unknown top-level key{'s' if len(unknown) > 1 else ''} "
            f"{', '.join(sorted(unknown))}"
            f"{''.join(did_you_mean(k, _TOP) for k in sorted(unknown))} "
            f"(allowed: {', '.join(sorted(_TOP))})"
        )
    name = data.get("name", Path(source).stem if source else "mechanism")
    if not isinstance(name, str):
        raise r.err(f"name must be a string, got {name!r}"[:120], "name")
    description = data.get("description", "")
    if not isinstance(description, str):
        raise r.err(
            f"description must be a string, got {type(description).__name__} {description!r}"[:160],
            entry="description",
        )
    return name


def _points(r: TomlReader) -> dict[str, tuple[float, float]]:
    """The ``[points]`` table: each point's sketch coordinates, SI."""
    raw_points = r.table("points", True)
    if len(raw_points) > MAX_POINTS:
        raise r.err(f"has {len(raw_points):,} points; a model has at most {MAX_POINTS:,}", "points")
    points = {r.name(k, "points"): r.xy(v, "points", k, k) for k, v in raw_points.items()}
    _check_extent(points, r)
    return points


def _bodies(r: TomlReader) -> list[Body]:
    """The ``[bodies]`` table."""
    bodies = []
    for bname, spec in r.table("bodies", True).items():
        r.name(bname, "bodies")
        if not isinstance(spec, dict):
            raise r.err('must be a table such as { points = ["A", "B"] }', "bodies", bname)
        r.keys(spec, {"points", "ground", "mass", "inertia", "center_of_mass"}, "bodies", bname)
        pts = spec.get("points")
        if not isinstance(pts, list) or not all(isinstance(p, str) for p in pts):
            raise r.err("points must be a list of point names", "bodies", bname)
        ground = spec.get("ground", False)
        if not isinstance(ground, bool):
            raise r.err("ground must be true or false", "bodies", bname)
        mass = (
            r.qty(spec["mass"], "mass", "bodies", bname, f"{bname}.mass")
            if "mass" in spec
            else None
        )
        inertia = (
            r.qty(spec["inertia"], "inertia", "bodies", bname, f"{bname}.inertia")
            if "inertia" in spec
            else None
        )
        com = (
            r.xy(spec["center_of_mass"], "bodies", bname, f"{bname}.center_of_mass")
            if "center_of_mass" in spec
            else None
        )
        bodies.append(Body(bname, tuple(pts), ground, mass, inertia, com))
    return bodies


def _drivers(r: TomlReader, bodies: list[Body]) -> tuple[list[RotaryDriver], list[LinearDriver]]:
    """The ``[drivers]`` table: rotary and linear drivers (a rotary one's reference defaults to
    the ground body)."""
    rotary, linear = [], []
    for dname, spec in r.table("drivers").items():
        r.name(dname, "drivers")
        table = f"drivers.{dname}"
        if not isinstance(spec, dict):
            raise r.err("must be a table", table)
        kind = spec.get("type")
        if kind == "rotary":
            r.keys(spec, {"type", "body", "pivot", "reference"}, "drivers", dname)
            for key in ("body", "pivot"):
                if key not in spec:
                    raise r.err(f"a rotary driver needs {key!r}", table)
            rotary.append(
                RotaryDriver(
                    dname,
                    str(spec["body"]),
                    str(spec["pivot"]),
                    str(spec.get("reference", _ground_name(bodies))),
                )
            )
        elif kind == "linear":
            r.keys(spec, {"type", "between", "mode", "stroke"}, "drivers", dname)
            between = spec.get("between")
            if not isinstance(between, list) or len(between) != 2:
                raise r.err("between must list two point names", table, "between")
            mode = spec.get("mode", "driven")
            if mode not in ("driven", "locked", "free"):
                raise r.err(
                    f"mode must be 'driven', 'locked' or 'free', not {mode!r}", table, "mode"
                )
            stroke = None
            if "stroke" in spec:
                given = spec["stroke"]
                if not isinstance(given, list) or len(given) != 2:
                    raise r.err("stroke must be [shortest, longest] lengths", table, "stroke")
                lo = r.qty(given[0], "length", table, "stroke")
                hi = r.qty(given[1], "length", table, "stroke")
                if not 0.0 < lo < hi:
                    raise r.err(
                        "stroke must be [shortest, longest] pin-to-pin lengths, "
                        f"0 < shortest < longest (got {lo:.6g} m, {hi:.6g} m)",
                        table,
                        "stroke",
                    )
                stroke = (lo, hi)
            linear.append(LinearDriver(dname, (str(between[0]), str(between[1])), mode, stroke))
        else:
            raise r.err(f"type must be 'rotary' or 'linear', not {kind!r}", table, "type")
    return rotary, linear


def _ropes(r: TomlReader) -> tuple[Rope, ...]:
    """The ``[ropes]`` table: ``path = [A, B]`` (its two blocks; or ``[A, S1, …, B]`` over
    sheaves centred at S1 …, with ``radii`` and ``wraps = ["ccw" | "cw", …]``, one per
    sheave), ``parts`` (default 1), ``mode = "winch" | "locked"`` (default locked), and for a
    winch ``drum_radius`` (a length) and ``gear_ratio`` (motor turns per drum turn, default
    1)."""
    ropes = []
    for rname, spec in r.table("ropes").items():
        r.name(rname, "ropes")
        table = f"ropes.{rname}"
        if not isinstance(spec, dict):
            raise r.err('must be a table such as { path = ["A", "B"], mode = "locked" }', table)
        allowed = {"path", "parts", "mode", "drum_radius", "gear_ratio", "radii", "wraps"}
        r.keys(spec, allowed, "ropes", rname)
        path = spec.get("path")
        if not isinstance(path, list) or not all(isinstance(p, str) for p in path) or not path:
            raise r.err("path must list the point names of the rope's blocks", table, "path")
        parts = spec.get("parts", 1)
        if isinstance(parts, bool) or not isinstance(parts, int) or parts < 1:
            raise r.err(f"parts must be a whole number ≥ 1, not {parts!r}"[:120], table, "parts")
        mode = spec.get("mode", "locked")
        if mode not in ("winch", "locked"):
            raise r.err(f"mode must be 'winch' or 'locked', not {mode!r}"[:120], table, "mode")
        winch_keys = {"drum_radius", "gear_ratio"} & set(spec)
        if mode == "locked" and winch_keys:
            raise r.err(
                f"{', '.join(sorted(winch_keys))} belong to a winch; a locked rope has none",
                table,
                sorted(winch_keys)[0],
            )
        radius = None
        ratio = 1.0
        if mode == "winch":
            if "drum_radius" not in spec:
                raise r.err("a winch needs its drum_radius", table, "drum_radius")
            radius = r.qty(spec["drum_radius"], "length", table, "drum_radius")
            if "gear_ratio" in spec:
                ratio = r.qty(spec["gear_ratio"], "dimensionless", table, "gear_ratio")
        radii = spec.get("radii", [])
        if not isinstance(radii, list):
            raise r.err("radii must list each sheave's radius", table, "radii")
        wraps = spec.get("wraps", [])
        if not isinstance(wraps, list) or not all(isinstance(w, str) for w in wraps):
            raise r.err('wraps must list "ccw" or "cw" for each sheave', table, "wraps")
        sizes = tuple(r.qty(v, "length", table, "radii") for v in radii)
        ropes.append(
            Rope(rname, tuple(path), parts, mode, radius, ratio, sizes, tuple(wraps))  # type: ignore[arg-type]
        )
    return tuple(ropes)


def _sliders(r: TomlReader) -> list[Slider]:
    """The ``[sliders]`` table."""
    sliders = []
    for sname, spec in r.table("sliders").items():
        r.name(sname, "sliders")
        if not isinstance(spec, dict):
            raise r.err("must be a table", f"sliders.{sname}")
        r.keys(spec, {"point", "along"}, "sliders", sname)
        along = spec.get("along")
        if not isinstance(along, list) or len(along) != 2 or "point" not in spec:
            raise r.err('needs point = "P" and along = ["L1", "L2"]', f"sliders.{sname}")
        sliders.append(Slider(sname, str(spec["point"]), (str(along[0]), str(along[1]))))
    return sliders


def _gears(r: TomlReader, bodies: list[Body]) -> tuple[GearPair, ...]:
    """The ``[gears.NAME]`` tables: ``gears = ["B1", "B2"]``, ``carrier`` (default the
    ground), exactly one of ``ratio`` (r2/r1), ``teeth = [z1, z2]`` or ``radii = [r1, r2]``,
    ``internal`` (default false) and ``pressure_angle`` (default 20 deg)."""
    out = []
    for gname, spec in r.table("gears").items():
        r.name(gname, "gears")
        table = f"gears.{gname}"
        if not isinstance(spec, dict):
            raise r.err("must be a table", table)
        r.keys(
            spec,
            {"gears", "carrier", "ratio", "teeth", "radii", "internal", "pressure_angle"},
            "gears",
            gname,
        )
        pair = spec.get("gears")
        if not (
            isinstance(pair, list) and len(pair) == 2 and all(isinstance(b, str) for b in pair)
        ):
            raise r.err('gears must name two bodies, gears = ["B1", "B2"]', table, "gears")
        given = [k for k in ("ratio", "teeth", "radii") if k in spec]
        if len(given) != 1:
            raise r.err(
                "give exactly one of ratio (r2/r1), teeth = [z1, z2] or radii = [r1, r2]"
                + (f" (found {', '.join(given)})" if given else ""),
                table,
            )
        radii = None
        if "ratio" in spec:
            ratio = spec["ratio"]
            if isinstance(ratio, bool) or not isinstance(ratio, int | float):
                raise r.err("ratio must be a number (r2/r1)", table, "ratio")
            ratio = float(ratio)
        elif "teeth" in spec:
            teeth = spec["teeth"]
            if not (
                isinstance(teeth, list)
                and len(teeth) == 2
                and all(type(z) is int and z > 0 for z in teeth)
            ):
                raise r.err("teeth must be two positive whole numbers [z1, z2]", table, "teeth")
            ratio = teeth[1] / teeth[0]
        else:
            given_radii = spec["radii"]
            if not isinstance(given_radii, list) or len(given_radii) != 2:
                raise r.err("radii must be the two pitch radii [r1, r2]", table, "radii")
            r1 = r.qty(given_radii[0], "length", table, "radii")
            r2 = r.qty(given_radii[1], "length", table, "radii")
            if not (r1 > 0 and r2 > 0):
                raise r.err("pitch radii must be positive", table, "radii")
            radii, ratio = (r1, r2), r2 / r1
        internal = spec.get("internal", False)
        if not isinstance(internal, bool):
            raise r.err("internal must be true or false", table, "internal")
        phi = (
            r.qty(spec["pressure_angle"], "angle", table, "pressure_angle")
            if "pressure_angle" in spec
            else math.radians(20.0)
        )
        carrier = spec.get("carrier", _ground_name(bodies))
        if not isinstance(carrier, str):
            raise r.err("carrier must name a body", table, "carrier")
        out.append(GearPair(gname, (pair[0], pair[1]), carrier, ratio, internal, phi, radii))
    return tuple(out)


def _racks(r: TomlReader, bodies: list[Body]) -> tuple[RackPinion, ...]:
    """The ``[racks.NAME]`` tables: ``rack``, ``pinion``, ``carrier`` (default the ground),
    ``along = ["L1", "L2"]``, the pinion's pitch ``radius`` and ``pressure_angle`` (default
    20 deg)."""
    out = []
    for rname, spec in r.table("racks").items():
        r.name(rname, "racks")
        table = f"racks.{rname}"
        if not isinstance(spec, dict):
            raise r.err("must be a table", table)
        r.keys(
            spec,
            {"rack", "pinion", "carrier", "along", "radius", "pressure_angle"},
            "racks",
            rname,
        )
        for key in ("rack", "pinion", "radius", "along"):
            if key not in spec:
                raise r.err(f"a rack and pinion needs {key!r}", table)
        along = spec["along"]
        if not (
            isinstance(along, list) and len(along) == 2 and all(isinstance(p, str) for p in along)
        ):
            raise r.err(
                'along must name two points of the carrier, along = ["L1", "L2"]', table, "along"
            )
        names = {}
        for key in ("rack", "pinion", "carrier"):
            value = spec.get(key, _ground_name(bodies))
            if not isinstance(value, str):
                raise r.err(f"{key} must name a body", table, key)
            names[key] = value
        phi = (
            r.qty(spec["pressure_angle"], "angle", table, "pressure_angle")
            if "pressure_angle" in spec
            else math.radians(20.0)
        )
        out.append(
            RackPinion(
                rname,
                names["rack"],
                names["pinion"],
                names["carrier"],
                (along[0], along[1]),
                r.qty(spec["radius"], "length", table, "radius"),
                phi,
            )
        )
    return tuple(out)


def _cams(r: TomlReader, bodies: list[Body]) -> tuple[CamFollower, ...]:
    """The ``[cams.NAME]`` tables: ``cam``, ``follower``, ``carrier`` (default the ground),
    ``along = ["L1", "L2"]`` (a translating follower's guide; without it the follower
    oscillates about the point it shares with the carrier), ``face`` ("roller", the default, or
    "flat") and ``lift``, rows of [turn, lift] from 0 to 360 deg (the lift an angle for an
    oscillating follower)."""
    out = []
    for cname, spec in r.table("cams").items():
        r.name(cname, "cams")
        table = f"cams.{cname}"
        if not isinstance(spec, dict):
            raise r.err("must be a table", table)
        r.keys(spec, {"cam", "follower", "carrier", "along", "face", "lift"}, "cams", cname)
        for key in ("cam", "follower", "lift"):
            if key not in spec:
                raise r.err(f"a cam and follower needs {key!r}", table)
        along = spec.get("along")
        if along is not None and not (
            isinstance(along, list) and len(along) == 2 and all(isinstance(p, str) for p in along)
        ):
            raise r.err('along must name two points of the carrier, along = ["L1", "L2"]', table)
        names = {}
        for key in ("cam", "follower", "carrier"):
            value = spec.get(key, _ground_name(bodies))
            if not isinstance(value, str):
                raise r.err(f"{key} must name a body", table, key)
            names[key] = value
        rows = spec["lift"]
        if not isinstance(rows, list) or not all(
            isinstance(row, list) and len(row) == 2 for row in rows
        ):
            raise r.err('lift must be rows of [turn, lift], e.g. [["0 deg", "0 mm"], …]', table)
        kind = "length" if along is not None else "angle"
        lift = tuple(
            (r.qty(a, "angle", table, "lift"), r.qty(b, kind, table, "lift")) for a, b in rows
        )
        face = spec.get("face", "roller")
        if face not in ("roller", "flat"):
            raise r.err(f"face must be 'roller' or 'flat', not {face!r}", table, "face")
        out.append(
            CamFollower(
                cname,
                names["cam"],
                names["follower"],
                names["carrier"],
                None if along is None else (along[0], along[1]),
                lift,
                face,
            )
        )
    return tuple(out)


def _lengths(r: TomlReader) -> dict[tuple[str, str], float]:
    """The ``[lengths]`` table: distances that override the sketch's, SI."""
    lengths: dict[tuple[str, str], float] = {}
    for key, value in r.table("lengths").items():
        parts = key.split("-")
        if len(parts) != 2 or not all(parts):
            raise r.err(
                "a length's key is two point names joined by '-', such as \"A-B\"", "lengths", key
            )
        if (parts[1], parts[0]) in lengths or (parts[0], parts[1]) in lengths:
            raise r.err(f"the distance {parts[0]}-{parts[1]} is given twice", "lengths", key)
        lengths[(parts[0], parts[1])] = r.qty(value, "length", "lengths", key, key)
    return lengths


def _design(r: TomlReader) -> tuple[DesignVariable, ...]:
    """The design variables, each with the entries that refer to it; one that nothing refers
    to is a mistake worth a message."""
    out = []
    for name, (value, kind) in r.variables.items():
        targets = tuple(r.references.get(name, ()))
        if not targets:
            raise r.err(
                "no entry refers to this design variable (give its name as a value in "
                "[points], [lengths] or [bodies])",
                f"design.{name}",
            )
        out.append(DesignVariable(name, value, kind, r.design_bounds(name), targets))
    return tuple(out)


def _gravity(r: TomlReader) -> Gravity | None:
    """``gravity = true``, ``gravity = "9.81 m/s^2"`` or ``[gravity] g = …, direction = [x, y]``."""
    if "gravity" not in r.data:
        return None
    spec = r.data["gravity"]
    if isinstance(spec, bool):
        return Gravity() if spec else None
    if isinstance(spec, dict):
        r.keys(spec, {"g", "direction"}, "gravity", "g")
        g = r.qty(spec["g"], "acceleration", "gravity", "g") if "g" in spec else STANDARD_GRAVITY
        direction = spec.get("direction", [0, -1])
        if (
            not isinstance(direction, list)
            or len(direction) != 2
            or not all(isinstance(c, int | float) and not isinstance(c, bool) for c in direction)
            or not all(math.isfinite(c) for c in direction)
            or direction[0] == direction[1] == 0
        ):
            raise r.err(
                "direction must be two finite numbers [x, y], not both zero",
                "gravity",
                "direction",
            )
        # a direction only: scale it to a unit vector here, so that no size overflows later
        big = max(abs(float(direction[0])), abs(float(direction[1])))
        dx, dy = float(direction[0]) / big, float(direction[1]) / big
        norm = math.hypot(dx, dy)
        return Gravity(g, (dx / norm, dy / norm))
    return Gravity(r.qty(spec, "acceleration", "gravity", "g"))


def _loads(
    r: TomlReader, bodies: set[str], body_points: dict[str, tuple[str, ...]]
) -> tuple[PointForce | Torque, ...]:
    """``[loads.NAME]`` tables: ``type = "force"`` (body, point, value = [Fx, Fy]) or
    ``type = "torque"`` (body, value, optional reaction)."""
    out: list[PointForce | Torque] = []
    for lname, spec in r.table("loads").items():
        r.name(lname, "loads")
        table = f"loads.{lname}"
        if not isinstance(spec, dict):
            raise r.err("must be a table", table)
        kind = spec.get("type")
        body = spec.get("body")
        if not isinstance(body, str) or body not in bodies:
            raise r.err(
                f"body must name one of the bodies ({', '.join(sorted(bodies))}), not {body!r}",
                table,
                "body",
            )
        if "value" not in spec:
            raise r.err("needs a value", table, "value")
        value = spec["value"]
        if kind == "force":
            r.keys(spec, {"type", "body", "point", "value"}, "loads", lname)
            point = spec.get("point")
            if not isinstance(point, str) or point not in body_points[body]:
                raise r.err(
                    f"point must name one of body {body!r}'s points "
                    f"({', '.join(body_points[body])}), not {point!r}",
                    table,
                    "point",
                )
            if not isinstance(value, list) or len(value) != 2:
                raise r.err(
                    'a force\'s value is two components [Fx, Fy], e.g. ["0 kN", "-5 kN"]',
                    table,
                    "value",
                )
            fx = r.qty(value[0], "force", table, "value")
            fy = r.qty(value[1], "force", table, "value")
            out.append(PointForce(lname, body, point, (fx, fy)))
        elif kind == "torque":
            r.keys(spec, {"type", "body", "value", "reaction"}, "loads", lname)
            reaction = spec.get("reaction")
            if reaction is not None and (
                not isinstance(reaction, str) or reaction not in bodies or reaction == body
            ):
                raise r.err(f"reaction must name another body, not {reaction!r}", table, "reaction")
            out.append(Torque(lname, body, r.qty(value, "torque", table, "value"), reaction))
        else:
            raise r.err(f"type must be 'force' or 'torque', not {kind!r}", table, "type")
    return tuple(out)


def _ground_name(bodies: list[Body]) -> str:
    return next((b.name for b in bodies if b.ground), "ground")
