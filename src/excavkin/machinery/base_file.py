"""The machine file's base-machine table (optional)::

    [base]
    friction = 0.5                      # ground friction coefficient (slipping limit)
    [base.upper]                        # upper structure without front and counterweight
    mass = 5900                         # kg ([units] mass, or "5.9 t")
    center_of_mass = [-350, 1600]       # model coordinates at swing 0 (x forward, y up)
    [base.counterweight]
    mass = 3800
    center_of_mass = [-2350, 1650]
    [base.undercarriage]
    mass = 7200
    center_of_mass = [0, 500]
    track_length = 3650                 # idler to sprocket axes
    gauge = 2380                        # track centre to track centre
    shoe_width = 600
    track_centre = 0                    # x of the idler–sprocket midpoint (default: swing axis)
    [base.blade]                        # optional: a lowered blade's ground edge
    position = 2600                     # x
    width = 2500
    [base.outriggers]                   # optional: outrigger pads
    points = [[-2000, 1800], [-2000, -1800]]   # x, lateral (left +)

A wheeled undercarriage gives its two axles instead of the track keys::

    [base.undercarriage]
    mass = 6500
    center_of_mass = [0, 700]
    [base.undercarriage.front_axle]
    position = 1250                     # x of the axle
    tread = 1950                        # tyre centre to tyre centre
    oscillating = true                  # optional (default false): swings about a pin
    [base.undercarriage.rear_axle]
    position = -1250
    tread = 1950

Every number is range-checked; errors name the file, the table and the entry; a support that
spans no area (both axles oscillating, with no pads or blade) is refused.
"""

from __future__ import annotations

from typing import Any

from excavkin.errors import ModelError
from excavkin.machinery.base import BaseMachine, Contact, Mass, axle
from excavkin.machinery.file_fields import MachineReader, within

_BASE = {"friction", "upper", "counterweight", "undercarriage", "blade", "outriggers"}
_MASS = {"mass", "center_of_mass"}
_TRACKS = {"track_length", "gauge", "shoe_width", "track_centre"}
_AXLES = ("front_axle", "rear_axle")
_UNDER = _MASS | _TRACKS | set(_AXLES)
#: the most outrigger pads
MAX_PADS = 16
#: largest mass of one part (kg), coordinate (m) and size (m) accepted
_MAX_MASS, _MAX_X, _MAX_SIZE = 1e7, 1e3, 100.0


def read_base(r: MachineReader, data: dict[str, Any], swing_axis: float) -> BaseMachine | None:
    """The ``[base]`` table of a machine file.

    Parameters
    ----------
    r : MachineReader
        The file's reader (units, messages).
    data : dict
        The file's top-level table.
    swing_axis : float
        Abscissa of the swing axis (m): the default track centre.

    Returns
    -------
    BaseMachine or None
        None where the file has no ``[base]`` table.
    """
    if "base" not in data:
        return None
    t = r.subtable(data, "base", "base")
    r.keys(t, _BASE, "base")
    for part in ("upper", "counterweight", "undercarriage"):
        if part not in t:
            raise r.err(
                f"[base.{part}] is missing (the base machine needs all three parts)", "base"
            )
    upper = _mass(r, t, "upper", positive=True)
    counterweight = _mass(r, t, "counterweight", positive=False)
    undercarriage = _mass(r, t, "undercarriage", positive=True, allowed=_UNDER)
    under_t = t["undercarriage"]
    table = "base.undercarriage"

    def size(key: str, high: float = _MAX_SIZE) -> float:
        return r.bounded(under_t, key, "length", table, 0.0, high, "m")

    axles = _axles(r, under_t)
    if axles:
        track_length = gauge = shoe = 0.0
        centre = swing_axis
    else:
        track_length = size("track_length")
        gauge = size("gauge")
        shoe = size("shoe_width", 10.0)
        if shoe > gauge:
            raise r.err(
                f"the shoes ({shoe * 1e3:.0f} mm) are wider than the gauge "
                f"({gauge * 1e3:.0f} mm): the tracks would overlap",
                table,
                "shoe_width",
            )
        centre = _coordinate(
            r,
            r.field_qty(under_t, "track_centre", "length", table, swing_axis),
            table,
            "track_centre",
        )
    friction = r.bounded(t, "friction", "dimensionless", "base", 0.0, 5.0, "")
    blade = None
    if "blade" in t:
        bt = r.subtable(t, "blade", "base.blade")
        r.keys(bt, {"position", "width"}, "base.blade")
        blade = (
            _coordinate(
                r, r.field_qty(bt, "position", "length", "base.blade"), "base.blade", "position"
            ),
            r.bounded(bt, "width", "length", "base.blade", 0.0, _MAX_SIZE, "m"),
        )
    pads: list[tuple[float, float]] = []
    if "outriggers" in t:
        ot = r.subtable(t, "outriggers", "base.outriggers")
        r.keys(ot, {"points"}, "base.outriggers")
        pts = ot.get("points")
        if not isinstance(pts, list) or not 1 <= len(pts) <= MAX_PADS:
            raise r.err(
                f"points must be a list of 1 to {MAX_PADS} pads [x, lateral]",
                "base.outriggers",
                "points",
            )
        for p in pts:
            x, v = r.xy(p, "base.outriggers", "points")
            pads.append(
                (
                    _coordinate(r, x, "base.outriggers", "points"),
                    _coordinate(r, v, "base.outriggers", "points"),
                )
            )
    base = BaseMachine(
        upper=upper,
        counterweight=counterweight,
        undercarriage=undercarriage,
        track_length=track_length,
        gauge=gauge,
        shoe_width=shoe,
        track_centre=centre,
        friction=friction,
        blade=blade,
        outriggers=tuple(pads),
        axles=axles,
    )
    try:
        base.support_polygon(swing_axis)
    except ModelError as exc:
        raise r.err(exc.problem, "base") from None
    return base


def _axles(r: MachineReader, under: dict[str, Any]) -> tuple[Contact, ...]:
    """A wheeled undercarriage's two axles, or () for tracks (never both)."""
    given = [a for a in _AXLES if a in under]
    if not given:
        return ()
    table = "base.undercarriage"
    tracks = sorted(_TRACKS & set(under))
    if tracks:
        raise r.err(
            f"an undercarriage runs on tracks or on axles, not both: drop {tracks[0]!r} "
            "or the axles",
            table,
            tracks[0],
        )
    if len(given) == 1:
        missing = next(a for a in _AXLES if a not in under)
        raise r.err(
            f"[{table}.{missing}] is missing (a wheeled undercarriage has two axles)", table
        )
    out = []
    for key in _AXLES:
        t_name = f"{table}.{key}"
        t = r.subtable(under, key, t_name)
        r.keys(t, {"position", "tread", "oscillating"}, t_name)
        x = _coordinate(r, r.field_qty(t, "position", "length", t_name), t_name, "position")
        tread = r.bounded(t, "tread", "length", t_name, 0.0, _MAX_SIZE, "m")
        oscillating = t.get("oscillating", False)
        if not isinstance(oscillating, bool):
            raise r.err(f"must be true or false, not {oscillating!r}", t_name, "oscillating")
        out.append(axle(key.removesuffix("_axle"), x, tread, oscillating=oscillating))
    if out[0].x <= out[1].x:
        raise r.err("the front axle must lie ahead of the rear axle", f"{table}.front_axle")
    return tuple(out)


def _coordinate(r: MachineReader, value: float, table: str, key: str) -> float:
    return within(r, value, table, key, -_MAX_X, _MAX_X, "m", open_low=False)


def _mass(
    r: MachineReader,
    base: dict[str, Any],
    part: str,
    *,
    positive: bool,
    allowed: set[str] = _MASS,
) -> Mass:
    table = f"base.{part}"
    t = r.subtable(base, part, table)
    r.keys(t, allowed, table)
    m = r.bounded(t, "mass", "mass", table, 0.0, _MAX_MASS, "kg", open_low=positive)
    if "center_of_mass" not in t:
        raise r.err("'center_of_mass' is missing", table)
    x, y = r.xy(t["center_of_mass"], table, "center_of_mass")
    return Mass(
        part,
        m,
        _coordinate(r, x, table, "center_of_mass"),
        _coordinate(r, y, table, "center_of_mass"),
    )
