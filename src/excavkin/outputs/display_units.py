"""Column → quantity kind → display unit, for plots, animations and reports.

Result tables are in SI (m, rad, s, N, N·m). For display each column is given a *kind* from its
name, and each kind a *display unit* (mm, deg, kN, ...), converted with the single registry of
`excavkin.units`:

==========================================  ======================  ===============
column                                      kind                    default unit
==========================================  ======================  ===============
``t``                                       time                    s
``<point>.x`` ``.y``                        length                  mm
``<point>.vx`` ``.vy``                      velocity                m/s
``<point>.ax`` ``.ay``                      acceleration            m/s²
``<body>.angle`` ``<x>.transmission``       angle                   deg
``<body>.omega`` / ``.epsilon``             angular velocity / acc  rad/s, rad/s²
``<driver>.value`` ``.rate`` ``.accel``     the driver's own kind   mm or deg, ...
``<point>.<body>.Fx`` ``.Fy`` ``.F``        force                   kN
``<driver>.force``                          force                   kN
``<driver>.torque``                         torque                  kN·m
``<x>.power``                               power                   kW
==========================================  ======================  ===============

Every result describes its own columns
([`KinematicResult.columns`][excavkin.kinematics.result.KinematicResult.columns]), kinds included: a
driver's ``.value`` is an angle for a rotary driver and a length for a linear one. A table read
back from a file keeps the kinds in its metadata, or has them guessed from the names alone.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from excavkin.kinematics.columns import columns_from_names

#: the display unit of each kind unless the caller chooses another
DEFAULT_UNITS: dict[str, str] = {
    "time": "s",
    "length": "mm",
    "velocity": "m/s",
    "acceleration": "m/s^2",
    "angle": "deg",
    "angular_velocity": "rad/s",
    "angular_acceleration": "rad/s^2",
    "force": "kN",
    "torque": "kN*m",
    "pressure": "bar",
    "power": "kW",
    "volume_flow": "L/min",
    "mass": "kg",
    "dimensionless": "",
}

#: SI units of the kinds `excavkin.units` does not list
_EXTRA_SI = {"power": "W", "energy": "J"}

#: words for axis labels
KIND_NAMES = {
    "time": "Time",
    "length": "Length",
    "velocity": "Velocity",
    "acceleration": "Acceleration",
    "angle": "Angle",
    "angular_velocity": "Angular velocity",
    "angular_acceleration": "Angular acceleration",
    "force": "Force",
    "torque": "Torque",
    "pressure": "Pressure",
    "power": "Power",
    "volume_flow": "Flow",
    "mass": "Mass",
    "dimensionless": "Value",
    "unknown": "Value",
}

_ANGLE_UNITS = {"degree", "radian", "turn", "arcminute", "arcsecond", "gradian"}

_PRETTY = (
    ("**", "^"),
    ("^2", "²"),
    ("^3", "³"),
    ("^-1", "⁻¹"),
    ("*", "·"),
    ("degree", "°"),
    ("deg", "°"),
)


def kind_of(column: str, kinds: Mapping[str, str] | None = None) -> str:
    """The quantity kind of a result column.

    Parameters
    ----------
    column : str
        A column name such as ``"B.vx"`` or ``"boom_cyl.force"``.
    kinds : mapping, optional
        Known kinds by column (a result's own [`Column`][excavkin.kinematics.columns.Column]
        descriptions, through `as_table`), consulted first.

    Returns
    -------
    str
        A kind of `DEFAULT_UNITS`, or ``"unknown"`` (a driver's ``.value`` whose kind is
        not known, or a column excavkin does not name).
    """
    if kinds and column in kinds:
        return kinds[column]
    if column == "sample":
        return "dimensionless"
    return columns_from_names([column])[0].kind


def _si_unit(kind: str) -> str:
    from excavkin.units import KINDS

    return _EXTRA_SI.get(kind) or KINDS.get(kind, "")


def convert(values: npt.ArrayLike, kind: str, unit: str) -> Any:
    """Convert SI ``values`` of ``kind`` to ``unit`` (unchanged for unknown kinds or no unit)."""
    if kind in ("unknown", "dimensionless") or not unit:
        return values
    from excavkin.units import KINDS, from_si, ureg

    if kind in KINDS:
        return from_si(values, kind, unit)
    factor = ureg.Quantity(1.0, _si_unit(kind)).to(unit).magnitude
    return np.asarray(values, dtype=np.float64) * factor


def kind_of_unit(unit: str) -> str | None:
    """The kind whose SI unit has the dimension of ``unit`` (``"mm"`` → ``"length"``), if any.

    Angle units (deg, rad) are dimensionless to pint; they are recognised by name.
    """
    from excavkin.units import ureg

    try:
        u = ureg.Unit(unit)
    except Exception:
        return None
    if u.dimensionless:
        return "angle" if str(u) in _ANGLE_UNITS else None
    for kind in DEFAULT_UNITS:
        si = _si_unit(kind)
        if si and ureg.Unit(si).dimensionality == u.dimensionality:
            return kind
    return None


def pretty_unit(unit: str) -> str:
    """A unit for a label: ``"m/s^2"`` → ``"m/s²"``, ``"kN*m"`` → ``"kN·m"``, ``"deg"`` → °."""
    out = unit
    for a, b in _PRETTY:
        out = out.replace(a, b)
    return out


@dataclass(frozen=True, slots=True)
class Display:
    """How one column is shown.

    Attributes
    ----------
    column : str
    kind : str
    unit : str
        The display unit (``""`` when unknown or dimensionless).
    """

    column: str
    kind: str
    unit: str

    @property
    def owner(self) -> str:
        """The point, body or driver the column belongs to."""
        return columns_from_names([self.column])[0].owner

    @property
    def quantity(self) -> str:
        """The column's quantity (``x``, ``value``, ``transmission``, ...)."""
        return columns_from_names([self.column])[0].quantity

    @property
    def label(self) -> str:
        """``"B.x [mm]"``, or the bare name without a unit."""
        return f"{self.column} [{pretty_unit(self.unit)}]" if self.unit else self.column

    def convert(self, values: npt.ArrayLike) -> Any:
        """SI values → display values."""
        return convert(values, self.kind, self.unit)

    def values(self, values: npt.ArrayLike) -> np.ndarray:
        """SI values → display values for a curve, shape (n,).

        Angles (not transmission angles) are unwrapped first, so a body turning past ±180°
        draws a continuous curve; NaN samples are skipped over.
        """
        a = np.array(values, dtype=np.float64)
        if self.kind == "angle" and self.quantity != "transmission":
            ok = np.isfinite(a)
            if ok.sum() > 1:
                a[ok] = np.unwrap(a[ok])
        return np.asarray(self.convert(a))


class DisplayUnits:
    """Choose the display unit of each column.

    Parameters
    ----------
    units : mapping of str to str, optional
        Either a kind (``{"length": "m", "force": "N"}``) or a column (``{"B.x": "cm"}``)
        mapped to a unit; a column's entry wins over its kind's. A unit given for a column of
        unknown kind also sets its kind (``{"boom_cyl.value": "mm"}`` → a length).
    kinds : mapping of str to str, optional
        Known column kinds (``Table.kinds``).

    Raises
    ------
    excavkin.errors.UnitError
        If a unit is unknown or does not fit its kind.
    """

    def __init__(
        self, units: Mapping[str, str] | None = None, kinds: Mapping[str, str] | None = None
    ) -> None:
        from excavkin.errors import UnitError
        from excavkin.units import ureg

        self.kinds = dict(kinds or {})
        self.by_kind = dict(DEFAULT_UNITS)
        self.by_column: dict[str, str] = {}
        for key, unit in (units or {}).items():
            if not isinstance(unit, str):
                raise TypeError(f"units[{key!r}] must be a unit string such as 'mm', got {unit!r}")
            target = self.by_kind if key in DEFAULT_UNITS else self.by_column
            try:
                ureg.Unit(unit) if unit else None
            except Exception:
                raise UnitError(f"units[{key!r}]: unknown unit {unit!r}") from None
            if key in DEFAULT_UNITS:
                kind: str | None = key
            else:
                kind = kind_of(key, self.kinds)
                if kind == "unknown":
                    kind = kind_of_unit(unit)
                    if kind is None:
                        raise UnitError(f"units[{key!r}]: cannot tell what {unit!r} measures")
                    self.kinds[key] = kind
            if unit and kind not in ("unknown", "dimensionless") and kind is not None:
                try:
                    convert(1.0, kind, unit)
                except Exception:
                    raise UnitError(f"units[{key!r}]: {unit!r} is not a unit of {kind}") from None
            target[key] = unit

    def __call__(self, column: str) -> Display:
        """The `Display` of ``column``."""
        kind = kind_of(column, self.kinds)
        if column in self.by_column:
            unit = self.by_column[column]
        elif kind == "unknown":
            unit = ""
        else:
            unit = self.by_kind.get(kind, "")
        return Display(column, kind, unit)

    def all(self, columns: Iterable[str]) -> list[Display]:
        """`Display` of each column."""
        return [self(c) for c in columns]
