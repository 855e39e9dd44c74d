"""The single unit registry: quantities at the edges, SI floats inside.

Only the file and command-line boundaries (``excavkin.io``, ``excavkin.cli``, ``excavkin.outputs``)
import this module. Kernels receive plain floats in SI units: m, rad, s, kg, N, N·m, Pa.

pint is imported and the registry built on first use (together about half a second), not when
this module is imported: a command that reads no quantity, such as ``excavkin --help``, does not
pay for them. ``from excavkin.units import ureg`` builds it.
"""

from __future__ import annotations

import math
import re
from functools import cache
from typing import TYPE_CHECKING, Any

from excavkin.errors import UnitError

if TYPE_CHECKING:
    import pint

    #: the registry, `registry` (built when first imported from this module)
    ureg: pint.UnitRegistry[Any]


@cache
def registry() -> pint.UnitRegistry[Any]:
    """The one unit registry, built on the first call."""
    import pint

    return pint.UnitRegistry(autoconvert_offset_to_baseunit=True)


def __getattr__(name: str) -> Any:
    if name == "ureg":
        return registry()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


#: Each kind of quantity: its SI unit (what kernels use) and a human name.
KINDS: dict[str, str] = {
    "length": "m",
    "angle": "rad",
    "mass": "kg",
    "inertia": "kg*m^2",
    "time": "s",
    "force": "N",
    "torque": "N*m",
    "pressure": "Pa",
    "velocity": "m/s",
    "acceleration": "m/s^2",
    "angular_velocity": "rad/s",
    "angular_acceleration": "rad/s^2",
    "jerk": "m/s^3",
    "angular_jerk": "rad/s^3",
    "area": "m^2",
    "volume": "m^3",
    "frequency": "1/s",
    "volume_flow": "m^3/s",
    "density": "kg/m^3",
    "dimensionless": "",
}


@cache
def _si_unit(kind: str) -> Any:
    ureg = registry()
    return ureg.Unit(KINDS[kind]) if KINDS[kind] else ureg.dimensionless


@cache
def _bare_factor(unit: str, kind: str) -> float | None:
    """The factor pint multiplies a bare number in ``unit`` by to convert it to the SI unit of
    ``kind`` (its conversion of a float is exactly ``value * factor`` for a multiplicative
    unit), or None where the unit is not a plain multiple of it (an offset or logarithmic unit,
    a wrong dimension, an unreadable name): those take pint's own path and its messages."""
    import pint

    ureg = registry()
    try:
        unit_q = ureg.Quantity(1.0, unit)
        factor = float(unit_q.to(_si_unit(kind)).magnitude)
        multiplicative = all(
            ureg.Quantity(v, unit).to(_si_unit(kind)).magnitude == v * factor
            for v in (0.0, -3.5, 1e6)
        )
    except (pint.errors.PintError, ValueError, TypeError, AttributeError, KeyError):
        return None
    return factor if multiplicative and math.isfinite(factor) else None


def to_si(value: Any, kind: str, default_unit: str | None = None, *, where: str = "") -> float:
    """Convert ``value`` to a float in the SI unit of ``kind``.

    Parameters
    ----------
    value : float, int or str
        A bare number or a string such as ``"48 mm"``, ``"50 deg"``, ``"250 bar"``.
    kind : str
        One of `KINDS` (``"length"``, ``"angle"``, ...).
    default_unit : str, optional
        The unit of a bare number. Without it a bare number is an error (angles included):
        a dimensional input is never given a silent default.
    where : str
        Used in the error message.

    Raises
    ------
    UnitError
        On an unparseable string, an unknown unit, a unit of the wrong dimension or a bare number
        with no default unit.
    """
    if kind not in KINDS:
        raise ValueError(f"unknown quantity kind {kind!r}")
    import pint

    ureg = registry()
    target = _si_unit(kind)
    if isinstance(value, bool):
        raise UnitError(f"{where}expected {_article(kind)} {kind}, got a boolean {value!r}")
    if isinstance(value, int | float):
        if kind == "dimensionless":
            return float(value)
        if default_unit is None:
            raise UnitError(
                f"{where}the bare number {value!r} needs a unit (write it as a string such as "
                f'"{value} {_example_unit(kind)}", or declare a default in the file\'s [units])'
            )
        factor = _bare_factor(default_unit, kind)
        if factor is not None:  # what pint's conversion computes, without parsing each time
            out = float(value) * factor
            if not math.isfinite(out):
                raise UnitError(f"{where}{value!r} is not a finite number")
            return out
        q = ureg.Quantity(float(value), default_unit)
    elif isinstance(value, str):
        check_grammar(value, where=where)
        try:
            q = ureg.Quantity(value.strip())
        except Exception as exc:  # pint raises several unrelated types on bad input
            raise UnitError(
                f"{where}cannot read {value!r} as {_article(kind)} {kind}: {exc}"
            ) from None
        if not isinstance(q, pint.Quantity) or q.unitless:  # a bare number in a string: "48"
            return to_si(float(getattr(q, "magnitude", q)), kind, default_unit, where=where)
    else:
        raise UnitError(f"{where}expected a number or a string with a unit, got {value!r}")
    try:
        out = float(q.to(target).magnitude)
    except pint.DimensionalityError:
        raise UnitError(
            f"{where}{value!r} is not {_article(kind)} {kind} "
            f"(expected units like {_example_unit(kind)})"
        ) from None
    if not math.isfinite(out):
        raise UnitError(f"{where}{value!r} is not a finite number")
    return out


#: a quantity as text: a number, then a unit made of names, ``*``, ``/`` and small powers —
#: checked before pint sees it, so that no text (``"9**9**9 mm"``) can run for long
_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d{1,3})?"
_NAME = r"(?:[A-Za-z_°µΩ][A-Za-z0-9_]*|%)"
_FACTOR = rf"{_NAME}(?:\s*(?:\^|\*\*)\s*[+-]?[1-4])?"
_UNIT = rf"(?:{_FACTOR}|1)(?:\s*(?:\*|/|\s)\s*{_FACTOR})*"
_QUANTITY = re.compile(rf"\s*({_NUMBER})?\s*({_UNIT})?\s*")
_UNIT_ONLY = re.compile(rf"\s*{_UNIT}\s*")
#: longest text read as a quantity
MAX_TEXT = 100


def check_grammar(text: str, *, unit_only: bool = False, where: str = "") -> None:
    """Refuse any text that is not a plain quantity (or unit): a number, unit names, ``*``,
    ``/`` and integer powers up to 4.

    Raises
    ------
    UnitError
        Naming the text and what is allowed.
    """
    shown = text if len(text) <= 40 else text[:37] + "..."
    if len(text) > MAX_TEXT:
        raise UnitError(f"{where}{shown!r} is too long for a quantity ({len(text)} characters)")
    pattern = _UNIT_ONLY if unit_only else _QUANTITY
    if not pattern.fullmatch(text) or not text.strip():
        what = "a unit" if unit_only else "a number with a unit"
        raise UnitError(
            f"{where}cannot read {shown!r} as {what}: write a number and unit names joined by "
            '\'*\', \'/\' and small powers, such as "48 mm", "9.81 m/s^2" or "0.7 kg*m^2"'
        )


def _example_unit(kind: str) -> str:
    return {
        "length": "mm",
        "angle": "deg",
        "mass": "kg",
        "inertia": "kg*m^2",
        "time": "s",
        "force": "kN",
        "torque": "N*m",
        "pressure": "bar",
        "velocity": "m/s",
        "acceleration": "m/s^2",
        "angular_velocity": "rad/s",
        "angular_acceleration": "rad/s^2",
        "jerk": "m/s^3",
        "angular_jerk": "rad/s^3",
        "area": "mm^2",
        "frequency": "1/s",
        "volume_flow": "L/min",
    }.get(kind, KINDS[kind])


def check_unit(unit: str, kind: str, *, where: str = "") -> str:
    """Check that ``unit`` names a unit of ``kind``; return it unchanged."""
    if not isinstance(unit, str):
        raise UnitError(f'{where}a unit must be a string such as "mm", got {unit!r}')
    check_grammar(unit, unit_only=True, where=where)
    try:
        u = registry().Unit(unit)
    except Exception:
        raise UnitError(f"{where}unknown unit {unit!r}") from None
    if u.dimensionality != _si_unit(kind).dimensionality:
        raise UnitError(f"{where}{unit!r} is not a unit of {kind}")
    return unit


def from_si(value: Any, kind: str, unit: str) -> Any:
    """Convert an SI float or array to ``unit`` for display."""
    factor = registry().Quantity(1.0, _si_unit(kind)).to(unit).magnitude
    return value * factor


def _article(word: str) -> str:
    return "an" if word[:1] in "aeiou" else "a"


def quantity_to_si(value: Any, kind: str, *, where: str = "") -> Any:
    """A string with a unit, or a pint quantity of any registry (scalar or array), in the SI
    unit of ``kind``.

    Raises
    ------
    UnitError
        On a wrong dimension or an unreadable string.
    """
    if isinstance(value, str):
        return to_si(value, kind, where=where)
    try:
        out = value.to(KINDS[kind]).magnitude  # the quantity's own registry reads the unit
    except Exception:
        raise UnitError(
            f"{where}{value!s} is not {_article(kind)} {kind} "
            f"(expected units like {_example_unit(kind)})"
        ) from None
    return out


def is_unit_text(text: str) -> bool:
    """Whether ``text`` names a unit (``"m/s^2"``, ``"rad"``; an empty text is
    dimensionless): for telling a table's units row from its first row of numbers."""
    text = text.strip()
    if not text:
        return True
    try:
        check_grammar(text, unit_only=True)
        registry().Unit(text)
    except Exception:
        return False
    return True
