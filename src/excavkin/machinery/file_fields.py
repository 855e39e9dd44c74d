"""Field lookups of machine files, shared by every family's readers (units, ranges, errors
naming the file, the table and the entry)."""

from __future__ import annotations

from typing import Any

from excavkin.errors import UnitError
from excavkin.io.toml_model import TomlReader
from excavkin.units import to_si


class MachineReader(TomlReader):
    """The model reader's units and errors, plus the machine file's field lookups."""

    def subtable(self, data: dict[str, Any], key: str, where: str) -> dict[str, Any]:
        t = data.get(key)
        if not isinstance(t, dict):
            raise self.err("is missing or not a table", where)
        return t

    def field_qty(
        self, t: dict[str, Any], key: str, kind: str, table: str, default: float | None = None
    ) -> float:
        if key not in t:
            if default is None:
                raise self.err(f"{key!r} is missing", table)
            return default
        try:
            return to_si(t[key], kind, self.units.get(kind))
        except UnitError as exc:
            raise UnitError(exc.problem, table=table, entry=key, source=self.source) from None

    def bounded(
        self,
        t: dict[str, Any],
        key: str,
        kind: str,
        table: str,
        low: float,
        high: float,
        unit: str,
        *,
        default: float | None = None,
        open_low: bool = True,
    ) -> float:
        """A quantity in SI within its range: `field_qty` checked by
        [`within`][excavkin.machinery.file_fields.within].

        Parameters
        ----------
        t : dict
            The table holding the entry.
        key : str
            The entry.
        kind : str
            Its kind of quantity (``"length"``, ``"pressure"``, …).
        table : str
            The table's name, for messages.
        low, high : float
            The range (SI): more than ``low`` (at least, with ``open_low=False``), at most
            ``high``.
        unit : str
            The SI unit the message writes.
        default : float, optional
            Where the entry is missing; without it, a missing entry is an error.
        open_low : bool
            Whether ``low`` itself is refused.

        Returns
        -------
        float
        """
        value = self.field_qty(t, key, kind, table, default)
        return within(self, value, table, key, low, high, unit, open_low=open_low)

    def text(self, t: dict[str, Any], key: str, table: str, default: str | None = None) -> str:
        v = t.get(key, default)
        if not isinstance(v, str):
            raise self.err(
                f"{key!r} must be a string" if key in t else f"{key!r} is missing",
                table,
                key if key in t else None,
            )
        return v


def within(
    r: MachineReader,
    value: float,
    table: str,
    key: str,
    low: float,
    high: float,
    unit: str,
    *,
    open_low: bool = True,
) -> float:
    """``value`` if ``low < value ≤ high`` (``low ≤`` with ``open_low=False``), else an error
    naming the file, the table and the entry."""
    ok = (value > low if open_low else value >= low) and value <= high
    if not ok:
        side = "more than" if open_low else "at least"
        raise r.err(
            f"{key} = {value:.6g} {unit} must be {side} {low:g} and at most {high:g} {unit}",
            table,
            key,
        )
    return value
