"""Typed columns: every result says what each of its table's columns is.

A [`Column`][excavkin.kinematics.columns.Column] names its owner (a point, body, driver, pin, slider
or the time axis), the
quantity and the physical kind (length, velocity, angle, force, ...). Outputs read these
descriptions instead of parsing column names; a table read back from a file, which has only
names, gets them from [`columns_from_names`][excavkin.kinematics.columns.columns_from_names], the
one place that parses names.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

if TYPE_CHECKING:
    import pandas as pd

OwnerKind = Literal["time", "point", "body", "driver", "pin", "slider", "other"]

#: kinds of a driver's value, rate and acceleration, by the kind of its value
DRIVER_KINDS: dict[str, tuple[str, str, str]] = {
    "angle": ("angle", "angular_velocity", "angular_acceleration"),
    "length": ("length", "velocity", "acceleration"),
}

#: a winch rope's blocks' distance, its rate and acceleration (its ``.value`` is its motor's
#: angle, the input)
WINCH_LENGTH = ("length", "length_rate", "length_accel")

#: (owner kind, kind) of each quantity, where the quantity alone tells them
QUANTITIES: dict[str, tuple[OwnerKind, str]] = {
    "x": ("point", "length"),
    "y": ("point", "length"),
    "vx": ("point", "velocity"),
    "vy": ("point", "velocity"),
    "ax": ("point", "acceleration"),
    "ay": ("point", "acceleration"),
    "angle": ("body", "angle"),
    "omega": ("body", "angular_velocity"),
    "epsilon": ("body", "angular_acceleration"),
    "transmission": ("point", "angle"),
    "Fx": ("pin", "force"),
    "Fy": ("pin", "force"),
    "F": ("pin", "force"),
    "Rx": ("body", "force"),
    "Ry": ("body", "force"),
    "force": ("driver", "force"),
    "torque": ("driver", "torque"),
    "normal": ("slider", "force"),
    "tooth": ("other", "force"),
    "guide": ("other", "force"),
    "contact": ("other", "force"),
    "couple": ("other", "torque"),
    "tension": ("driver", "force"),
    "length": ("driver", "length"),
    "length_rate": ("driver", "velocity"),
    "length_accel": ("driver", "acceleration"),
    "power": ("driver", "power"),
    "pressure": ("driver", "pressure"),
}


#: the SI unit of each kind, as tables record it
SI_UNITS: dict[str, str] = {
    "time": "s",
    "length": "m",
    "velocity": "m/s",
    "acceleration": "m/s^2",
    "angle": "rad",
    "angular_velocity": "rad/s",
    "angular_acceleration": "rad/s^2",
    "force": "N",
    "torque": "N*m",
    "moment": "N*m",
    "pressure": "Pa",
    "power": "W",
    "energy": "J",
    "volume_flow": "m^3/s",
    "mass": "kg",
    "inertia": "kg*m^2",
    "dimensionless": "",
}


def si_unit(kind: str) -> str:
    """The SI unit of a kind, also of a derivative's ``"<kind> per <kind>"``."""
    top, per, bottom = kind.partition(" per ")
    if per:
        return f"({SI_UNITS.get(top, '')})/({SI_UNITS.get(bottom, '')})"
    return SI_UNITS.get(kind, "")


def design_column(name: str, kind: str) -> Column:
    """A design parameter's column in a table of a family of designs: ``design.<name>``."""
    return Column(f"design.{name}", name, "other", "design", kind)


def derivative_column(of: Column, parameter: str, kind: str) -> Column:
    """d(column)/d(parameter): ``d(<column>)/d(<parameter>)``."""
    return Column(
        f"d({of.name})/d({parameter})",
        of.owner,
        of.owner_kind,
        of.quantity,
        f"{of.kind} per {kind}",
    )


@dataclass(frozen=True, slots=True)
class Column:
    """What one column of a result table holds.

    Attributes
    ----------
    name : str
        The column's name in the table, ``<owner>.<quantity>`` (``t`` for time).
    owner : str
        The point, body, driver, pin (``"<point>.<body>"``) or slider it belongs to.
    owner_kind : {"time", "point", "body", "driver", "pin", "slider", "other"}
    quantity : str
        ``x``, ``vx``, ``angle``, ``omega``, ``value``, ``rate``, ``Fx``, ``force``, ...
    kind : str
        The physical kind, SI in the table: ``length``, ``velocity``, ``acceleration``,
        ``angle``, ``angular_velocity``, ``angular_acceleration``, ``force``, ``torque``,
        ``time``, ... (``unknown`` where a name read back from a file does not tell).
    """

    name: str
    owner: str
    owner_kind: OwnerKind
    quantity: str
    kind: str


def column(owner: str, owner_kind: OwnerKind, quantity: str, kind: str) -> Column:
    """A column named ``<owner>.<quantity>``."""
    return Column(f"{owner}.{quantity}", owner, owner_kind, quantity, kind)


TIME = Column("t", "", "time", "t", "time")


def driver_columns(name: str, value_kind: str) -> list[Column]:
    """A driver's ``.value .rate .accel`` columns, of the kinds its value's kind implies."""
    kinds = DRIVER_KINDS[value_kind]
    return [
        column(name, "driver", qty, kind)
        for qty, kind in zip(("value", "rate", "accel"), kinds, strict=True)
    ]


def columns_from_names(
    names: Iterable[str], known: Mapping[str, str] | None = None
) -> list[Column]:
    """Describe columns from their names alone: for tables read back from files.

    Parameters
    ----------
    names : iterable of str
    known : mapping of str to str, optional
        Kinds already known by column name (for example kept in a file's metadata), which win.

    Returns
    -------
    list of Column
        One per name; a driver's ``.value`` without a known kind, or a name excavkin does not
        make, has kind ``"unknown"``.
    """
    out = []
    for name in names:
        name = str(name)
        if name == "t":
            out.append(TIME)
            continue
        owner, _, qty = name.rpartition(".")
        owner_kind, kind = QUANTITIES.get(qty, ("other", "unknown"))
        if qty in ("value", "rate", "accel"):
            owner_kind = "driver"
        if owner.count(".") == 1 and qty in ("Fx", "Fy", "F"):
            owner_kind = "pin"
        if known and name in known:
            kind = known[name]
        out.append(Column(name, owner, owner_kind, qty, kind))
    return out


def table_attrs(model: str, columns: Iterable[Column]) -> dict[str, object]:
    """What a result's table keeps in ``frame.attrs``: the model's name and every kind."""
    return {"excavkin.model": model, "excavkin.kinds": {c.name: c.kind for c in columns}}


def kinds_attrs(model: str, kinds: Mapping[str, str]) -> dict[str, object]:
    """``frame.attrs`` for a table whose columns' kinds are given by name."""
    return {"excavkin.model": model, "excavkin.kinds": dict(kinds)}


def kinds_frame(
    rows: Iterable[Mapping[str, object]], kinds: Mapping[str, str], model: str
) -> pd.DataFrame:
    """A table of ``rows`` whose ``frame.attrs`` keep the model's name and the kinds of the
    columns of ``kinds`` it has (`kinds_attrs`).

    Parameters
    ----------
    rows : iterable of mapping
        One mapping a row, column → value.
    kinds : mapping of str to str
        Column → its kind; columns the table lacks are left out.
    model : str
        The model's (machine's) name.

    Returns
    -------
    pandas.DataFrame
    """
    import pandas as pd

    frame = pd.DataFrame(list(rows))
    frame.attrs.update(kinds_attrs(model, {c: k for c, k in kinds.items() if c in frame}))
    return frame


#: columns a selection keeps whatever it asks: each row's status
ALWAYS_KEPT = ("status",)


def select_columns(names: Sequence[str], asked: Iterable[str]) -> list[str]:
    """The names of a table that a selection asks for, in the table's order.

    Parameters
    ----------
    names : sequence of str
        The table's columns, in order.
    asked : iterable of str
        Column names or glob patterns (``"B.*"``, ``"*.x"``, ``"crank.*"``): a name of the
        table is taken as itself, anything else as a pattern (``*``, ``?``, ``[...]``).
        ``status`` is kept whether asked or not.

    Returns
    -------
    list of str
        The columns asked, each once, in the order of ``names``.

    Raises
    ------
    UnknownNameError
        A name or pattern that matches no column, with the nearest column's name.
    """
    from fnmatch import fnmatchcase

    from excavkin.errors import InputError, unknown_name

    present = set(names)
    wanted: set[str] = {n for n in ALWAYS_KEPT if n in present}
    given = [asked] if isinstance(asked, str) else list(asked)
    if not given:
        raise InputError("columns: name at least one column")
    for pattern in given:
        pattern = str(pattern).strip()
        if pattern in present:
            wanted.add(pattern)
            continue
        matched = [n for n in names if fnmatchcase(n, pattern)]
        if not matched:
            raise unknown_name("column", pattern, [n for n in names if n not in ALWAYS_KEPT])
        wanted.update(matched)
    return [n for n in names if n in wanted]
