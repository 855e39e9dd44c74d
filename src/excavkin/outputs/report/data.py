"""What the report is made from: the result's table, its display units and its x axis.

`ReportData` is read by every section; `sweep_text` says in one line what the
samples are; `format_value` and `thin` are the sections' shared formatting.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from excavkin.outputs.display_units import DisplayUnits, pretty_unit
from excavkin.outputs.events import Table, as_table, varies
from excavkin.outputs.protocols import TableData

__all__ = ["ReportData", "format_value", "sweep_text", "thin"]


def format_value(v: float, unit: str) -> str:
    """A value for a reader: four significant digits and its unit (``"35°"``, ``"1.2 kN"``).

    Parameters
    ----------
    v : float
        The value, in ``unit``.
    unit : str
        Its display unit.

    Returns
    -------
    str
        ``"—"`` for a value that is not finite.
    """
    if not np.isfinite(v):
        return "—"
    pu = pretty_unit(unit)
    return f"{v:.4g}{pu}" if pu == "°" else (f"{v:.4g} {pu}" if pu else f"{v:.4g}")


def thin(n: int, most: int) -> np.ndarray:
    """At most ``most`` sample indices out of ``n``, evenly spread, the first and last kept.

    Parameters
    ----------
    n : int
        Samples in the result.
    most : int
        Most samples to keep.

    Returns
    -------
    ndarray of int, shape (min(n, most),)
    """
    if n <= most:
        return np.arange(n)
    return np.unique(np.round(np.linspace(0, n - 1, most)).astype(np.int64))


class ReportData:
    """What the sections of a report read: the result's table, its display units, the x axis.

    Parameters
    ----------
    result : result or DataFrame
        The solved result the report shows.
    units : mapping of str to str or None
        Display units by kind or column.

    Attributes
    ----------
    table : Table
        The result as a table with its columns described.
    units : DisplayUnits
    x : str
        The x column (``"t"``, an input's value column or ``"sample"``); ``xv`` its values in
        display units, ``xd`` its display unit.
    """

    def __init__(self, result: TableData, units: Mapping[str, str] | None) -> None:
        from excavkin.outputs.plots import default_x

        self.result = result
        self.table: Table = as_table(result)
        self.units = DisplayUnits(units, self.table.kinds)
        self.x = default_x(self.table)
        self.xd = self.units(self.x)
        if self.x == "sample":
            self.xv = np.arange(len(self.table.frame), dtype=np.float64)
        else:
            self.xv = np.asarray(
                self.xd.convert(self.table.frame[self.x].to_numpy(dtype=np.float64))
            )

    def x_name(self) -> str:
        """The x axis in words: ``"t"``, ``"sample"`` or the moving input's name."""
        if self.x == "t":
            return "t"
        if self.x == "sample":
            return "sample"
        return self.table.describe(self.x).owner

    def moving_inputs(self) -> list[str]:
        """The value columns of the inputs that vary over the result (the x column first)."""
        frame = self.table.frame
        names = [c for c in self.table.of_quantity("value", "driver") if varies(frame[c])]
        if self.table.plan is not None:
            inputs = {f"{n}.value" for n in self.table.plan.inputs}
            names = [c for c in names if c in inputs]
        return sorted(names, key=lambda c: c != self.x)

    def name(self, i: int) -> str:
        """Sample ``i`` in words, by every input that moves: ``"crank = 35°"``."""
        if self.x == "t":
            return f"t = {format_value(float(self.xv[i]), self.xd.unit)}"
        moving = self.moving_inputs()
        if not moving:
            return f"sample {i}"
        return ", ".join(
            f"{self.table.describe(c).owner} = "
            f"{format_value(self._display(c, i), self.units(c).unit)}"
            for c in moving
        )

    def _display(self, column: str, i: int) -> float:
        d = self.units(column)
        return float(d.convert(self.table.frame[column].to_numpy(dtype=np.float64)[i]))

    def values(self, columns: Iterable[str], i: int) -> str:
        parts = []
        for c in columns:
            described = self.table.describe(c)
            label = described.owner if described.quantity == "value" else c
            parts.append(f"{label} = {format_value(self._display(c, i), self.units(c).unit)}")
        return "<br>".join(parts)


def sweep_text(data: ReportData) -> str:
    """What the samples are, in one line: ``"181 samples: crank from 0° to 360°."``.

    Parameters
    ----------
    data : ReportData

    Returns
    -------
    str
    """
    plan = data.table.plan
    frame = data.table.frame
    n = len(frame)
    if plan is None:
        return f"{n} samples."
    parts = []
    for name in plan.inputs:
        c = f"{name}.value"
        d = data.units(c)
        v = np.asarray(d.convert(frame[c].to_numpy(dtype=np.float64)))
        if varies(v):
            first, last = format_value(float(v[0]), d.unit), format_value(float(v[-1]), d.unit)
            parts.append(f"{name} from {first} to {last}")
        else:
            parts.append(f"{name} held at {format_value(float(v[0]), d.unit)}")
    return f"{n} samples: {'; '.join(parts)}." if parts else f"{n} samples."
