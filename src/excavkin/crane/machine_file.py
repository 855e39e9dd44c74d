"""Read a crane machine file (TOML, ``schema_version = 1``, ``family = "crane"``).

The booms are a general model (its ``model`` key, a model file relative to this one), in the
slew plane (x the radius from the slew axis, y the height above the ground)::

    schema_version = 1
    family = "crane"
    name = "..."
    model = "knuckle_crane.toml"
    kind = "knuckle"                 # or "telescopic"
    [units]                          # defaults for bare numbers in this file
    length = "mm"; pressure = "MPa"; mass = "kg"; force = "kN"
    [linkage]
    boom = "inner"                   # the body the luffing cylinder raises
    jib = "outer"                    # the outer boom, or a telescopic crane's fly section
    tip = "T"                        # the jib's tip sheave: the hook hangs below it
    lead = "W"                       # optional: where the hoist rope leads off to its winch
    [cylinders.luff]                 # and [cylinders.knuckle] or [cylinders.telescope]
    driver = "luff_cyl"; retracted = 1901; stroke = 1279; bore = 200; rod = 110
    circuit = "crane"; count = 1; mass = 0
    [circuits.crane]
    working = 28; relief = 30
    [hoist]
    line_pull = 25; parts = 2; hook_mass = 60
    [turning.column]                 # masses that slew: at radius x, height y
    mass = 1400; x = -100; y = 1600
    [fixed.truck]                    # masses that do not: at x along the carrier
    mass = 9500; x = -1000; y = 900
    [support]
    kind = "outriggers"              # pads = [[x, v], ...] (v to the left)
    pads = [[2000, 2300], [2000, -2300], [-4000, 2300], [-4000, -2300]]
    # kind = "crawlers": gauge, length, shoe_width, centre (the tracks' midpoint's x)
    # kind = "tyres": axles = [[x, tread], ...] (on its wheels, no outriggers)
    [gravity]
    g = "9.80665 m/s^2"
    [stability]                      # optional: how stability rates the chart
    criterion = "factors"            # default "share": 85 % of tipping (75 % on crawlers)
    hook_load_factor = 1.3           # γ_P on the hook load (> 0), from the standard's clause
    jib_weight_factor = 0.2          # γ_F on the booms' weight reduced to the tip (≥ 0)

Every number is range-checked; an error names the file, the table and the entry.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from excavkin.crane.family import NAME
from excavkin.crane.machine import FACTOR_MAX, SECOND, Crane, Hoist, Linkage, StabilityFactors
from excavkin.io.toml_model import read_text_file, read_toml
from excavkin.machinery.base import Contact, Mass, Support, axle, outriggers, track
from excavkin.machinery.cylinders_file import read_circuits, read_cylinders
from excavkin.machinery.file_fields import MachineReader, check_head, read_model
from excavkin.mechanism import Mechanism

SCHEMA_VERSION = 1
_TOP = {
    "schema_version",
    "family",
    "name",
    "description",
    "model",
    "kind",
    "units",
    "linkage",
    "cylinders",
    "circuits",
    "hoist",
    "turning",
    "fixed",
    "support",
    "gravity",
    "stability",
}
#: the stability criteria a file may name
CRITERIA = ("share", "factors")
#: the most cylinders acting together in one role
MAX_COUNT = 4


def loads_machine(text: str, source: str | None = None) -> Crane:
    """Parse a crane machine file from TOML text; see
    [`load_machine`][excavkin.crane.machine_file.load_machine].

    Parameters
    ----------
    text : str
        The file's text.
    source : str, optional
        The file, for messages and for a model file named relative to it.

    Returns
    -------
    Crane
    """
    return _machine(read_toml(text, source), source)


def load_machine(path: str | Path) -> Crane:
    """Read a crane machine file.

    Parameters
    ----------
    path : str or Path
        The file, or the name of a built-in machine (``"knuckle_crane_machine"``,
        ``"telescopic_crane_machine"``).

    Returns
    -------
    Crane

    Raises
    ------
    ModelError
        Naming the file, the table and the entry of the first problem found.
    """
    import excavkin

    file = excavkin.source_file(path, "machine")
    return loads_machine(read_text_file(file), str(file))


def _machine(data: dict[str, Any], source: str | None) -> Crane:
    r = MachineReader(data, source)
    if data.get("family") != NAME:
        raise r.err(
            f"family = {data.get('family')!r}: this reader reads crane machine files "
            f'(family = "{NAME}")',
            None,
            "family",
        )
    check_head(r, SCHEMA_VERSION, _TOP, "knuckle_crane.toml")
    kind = data.get("kind", "knuckle")
    if kind not in SECOND:
        raise r.err(f"kind must be 'knuckle' or 'telescopic', not {kind!r}"[:120], None, "kind")
    mech = Mechanism(read_model(r, data.get("model"), source, "knuckle_crane.toml"))

    lt = r.subtable(data, "linkage", "linkage")
    r.keys(lt, {"boom", "jib", "tip", "lead"}, "linkage")
    linkage = Linkage(
        boom=r.text(lt, "boom", "linkage"),
        jib=r.text(lt, "jib", "linkage"),
        tip=r.text(lt, "tip", "linkage"),
        lead=r.text(lt, "lead", "linkage") if "lead" in lt else None,
    )

    circuits = read_circuits(r, data)
    roles = ("luff", SECOND[kind])
    cylinders = read_cylinders(r, data, roles, f"a {kind} crane", max_count=MAX_COUNT)

    hoist = r.subtable(data, "hoist", "hoist")
    r.keys(hoist, {"line_pull", "parts", "hook_mass"}, "hoist")
    parts = hoist.get("parts", 1)
    if not isinstance(parts, int) or isinstance(parts, bool) or not 1 <= parts <= 32:
        raise r.err("parts must be a whole number from 1 to 32", "hoist", "parts")

    grav = data.get("gravity", {})
    if not isinstance(grav, dict):
        raise r.err('must be a table such as { g = "9.81 m/s^2" }', "gravity")
    r.keys(grav, {"g"}, "gravity")
    g = r.bounded(grav, "g", "acceleration", "gravity", 0.0, 100.0, "m/s^2", default=9.80665)
    name = data.get("name", Path(source).stem if source else mech.name)
    if not isinstance(name, str):
        raise r.err("must be a string", None, "name")
    return Crane(
        mech,
        kind,
        linkage,
        cylinders,
        circuits,
        Hoist(
            line_pull=r.bounded(hoist, "line_pull", "force", "hoist", 0.0, 1e7, "N"),
            parts=parts,
            hook_mass=r.bounded(
                hoist, "hook_mass", "mass", "hoist", 0.0, 1e5, "kg", default=0.0, open_low=False
            ),
        ),
        Support(_masses(r, data, "turning"), _masses(r, data, "fixed"), _support(r, data)),
        gravity=g,
        name=name,
        source=source,
        stability=_stability(r, data),
    )


def _stability(r: MachineReader, data: dict[str, Any]) -> StabilityFactors | None:
    """``[stability]``: None for the share of the tipping load, or the factors."""
    t = data.get("stability", {})
    if not isinstance(t, dict):
        raise r.err('must be a table such as { criterion = "share" }', "stability")
    factors = {"hook_load_factor", "jib_weight_factor"}
    r.keys(t, {"criterion"} | factors, "stability")
    criterion = r.text(t, "criterion", "stability", default="share")
    if criterion not in CRITERIA:
        raise r.err(
            f"criterion must be 'share' or 'factors', not {criterion!r}"[:120],
            "stability",
            "criterion",
        )
    if criterion == "share":
        given = sorted(factors & set(t))
        if given:
            raise r.err(
                f'{given[0]} needs criterion = "factors" (the share of the tipping load '
                "takes no factors)",
                "stability",
                given[0],
            )
        return None
    return StabilityFactors(
        _factor(r, t, "hook_load_factor", open_low=True),
        _factor(r, t, "jib_weight_factor", open_low=False),
    )


def _factor(r: MachineReader, t: dict[str, Any], key: str, *, open_low: bool) -> float:
    if key not in t:
        raise r.err(f'{key!r} is missing (criterion = "factors" takes both)', "stability")
    v = t[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise r.err(f"{key} must be a plain number, not {v!r}"[:120], "stability", key)
    side = "more than" if open_low else "at least"
    ok = (v > 0.0 if open_low else v >= 0.0) and v <= FACTOR_MAX  # NaN fails both
    if not ok:
        raise r.err(f"{key} = {v} must be {side} 0 and at most {FACTOR_MAX:g}", "stability", key)
    return float(v)


def _xy(r: MachineReader, value: Any, table: str, key: str) -> tuple[float, float]:
    x, y = r.xy(value, table, key)
    if max(abs(x), abs(y)) > 100.0:
        raise r.err(f"{key} lies more than 100 m away", table, key)
    return x, y


def _masses(r: MachineReader, data: dict[str, Any], key: str) -> tuple[Mass, ...]:
    t = data.get(key, {})
    if not isinstance(t, dict):
        raise r.err("must be a table of masses", key)
    out = []
    for name, spec in t.items():
        table = f"{key}.{name}"
        if not isinstance(spec, dict):
            raise r.err("must be a table with mass, x and y", table)
        r.keys(spec, {"mass", "x", "y"}, table)
        out.append(
            Mass(
                name,
                r.bounded(spec, "mass", "mass", table, 0.0, 1e7, "kg"),
                r.bounded(spec, "x", "length", table, -100.0, 100.0, "m", open_low=False),
                r.bounded(
                    spec, "y", "length", table, -100.0, 100.0, "m", default=0.0, open_low=False
                ),
            )
        )
    return tuple(out)


def _support(r: MachineReader, data: dict[str, Any]) -> tuple[Contact, ...]:
    t = r.subtable(data, "support", "support")
    kind = r.text(t, "kind", "support")
    if kind == "outriggers":
        r.keys(t, {"kind", "pads"}, "support")
        pads = t.get("pads")
        if not isinstance(pads, list) or not 3 <= len(pads) <= 16:
            raise r.err("pads must list 3 to 16 [x, v] pad positions", "support", "pads")
        return (outriggers([_xy(r, p, "support", "pads") for p in pads]),)
    if kind == "crawlers":
        keys = {"gauge", "length", "shoe_width", "centre"}
        r.keys(t, keys | {"kind"}, "support")
        gauge = r.bounded(t, "gauge", "length", "support", 0.0, 20.0, "m")
        length = r.bounded(t, "length", "length", "support", 0.0, 30.0, "m")
        width = r.bounded(t, "shoe_width", "length", "support", 0.0, 5.0, "m")
        if width > gauge:
            raise r.err("the shoes are wider than the gauge", "support", "shoe_width")
        centre = r.bounded(
            t, "centre", "length", "support", -50.0, 50.0, "m", default=0.0, open_low=False
        )
        return (
            track("left track", centre, gauge / 2, length, width),
            track("right track", centre, -gauge / 2, length, width),
        )
    if kind == "tyres":
        r.keys(t, {"kind", "axles"}, "support")
        axles = t.get("axles")
        if not isinstance(axles, list) or not 2 <= len(axles) <= 8:
            raise r.err("axles must list 2 to 8 [x, tread] axles", "support", "axles")
        out = []
        for k, spec in enumerate(axles):
            x, tread = _xy(r, spec, "support", "axles")
            if not tread > 0.0:
                raise r.err(f"axle {k + 1}'s tread must be positive", "support", "axles")
            out.append(axle(f"axle {k + 1}", x, tread))
        return tuple(out)
    raise r.err(
        f"kind must be 'outriggers', 'crawlers' or 'tyres', not {kind!r}"[:120], "support", "kind"
    )
