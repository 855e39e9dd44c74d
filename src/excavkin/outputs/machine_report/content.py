"""What a machine report holds: values with their units, tables, charts and sections.

A family wing builds these from its analyses; [`build_machine_report`][excavkin.outputs.
machine_report.document.build_machine_report] lays them out. Nothing here knows a family.

A `Value` keeps its SI number with the unit it is shown in: the page shows the converted,
rounded number and carries the SI number too (``data-si``), so that a reader's tool (or a test)
reads back exactly what the analysis returned.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from excavkin.outputs.display_units import convert, pretty_unit

__all__ = [
    "Cell",
    "Chart",
    "MachineReport",
    "Progress",
    "Section",
    "SectionSource",
    "Table",
    "Value",
    "collect",
]

#: ``progress(done, total)``: called as work is done
Progress = Callable[[int, int], None]


@dataclass(frozen=True, slots=True)
class Value:
    """A number of the report: SI inside, shown in ``unit``.

    Attributes
    ----------
    si : float
        The value in SI (m, rad, N, kg, Pa, W, s, m³/s, ...); NaN shows as a dash.
    kind : str
        Its quantity kind (``"length"``, ``"force"``, ``"mass"``, ``"angle"``, ...; see
        `excavkin.outputs.display_units`); ``""`` for a number shown as it is.
    unit : str
        The unit it is shown in (``"mm"``, ``"kN"``); without a kind, the unit of ``si`` as
        it is shown (``"m^3"``); ``""`` for a plain number.
    digits : int
        Decimals shown.
    key : str
        A name that finds it on the page (``data-key``), unique in its report; ``""`` for none.
    """

    si: float
    kind: str = ""
    unit: str = ""
    digits: int = 0
    key: str = ""

    @property
    def shown(self) -> float:
        """The value in ``unit`` (float).

        Returns
        -------
        float
        """
        if not self.kind or not self.unit:
            return float(self.si)
        return float(convert(self.si, self.kind, self.unit))

    def text(self, *, with_unit: bool = False) -> str:
        """The value as shown: rounded to ``digits``, thousands set apart by a thin space.

        Parameters
        ----------
        with_unit : bool
            Append the unit.

        Returns
        -------
        str
            ``"—"`` for a value that is not finite.
        """
        v = self.shown
        if not math.isfinite(v):
            return "—"
        s = f"{v:,.{self.digits}f}".replace(",", "\u2009")
        if s.startswith("-") and float(s.replace("\u2009", "")) == 0.0:
            s = s[1:]
        if with_unit and self.unit:
            s += f"\u00a0{pretty_unit(self.unit)}"
        return s


#: a table cell: a text or a value
Cell = str | Value


@dataclass(frozen=True, slots=True)
class Table:
    """A table of a section.

    Attributes
    ----------
    caption : str
        What it shows, its standard named.
    columns : tuple of str
        Headers; a value column's header should name its unit.
    rows : tuple of tuple of Cell
    note : str
        A line under it (how the figures are defined, what limits them).
    """

    caption: str
    columns: tuple[str, ...]
    rows: tuple[tuple[Cell, ...], ...]
    note: str = ""

    def __post_init__(self) -> None:
        for r in self.rows:
            if len(r) != len(self.columns):
                raise ValueError(
                    f"table {self.caption!r}: a row has {len(r)} cells for "
                    f"{len(self.columns)} columns"
                )


@dataclass(frozen=True, slots=True)
class Chart:
    """A figure of a section.

    Attributes
    ----------
    caption : str
        What it shows.
    standard : str
        The standard it follows (``"SAE J732"``), or what it is computed from when none applies.
    figure : object
        A matplotlib Figure (embedded as a PNG) or a Plotly figure (embedded interactive).
    key : str
        Its id on the page.
    """

    caption: str
    standard: str
    figure: Any
    key: str


@dataclass(frozen=True, slots=True)
class Section:
    """One part of the spec sheet.

    Attributes
    ----------
    key : str
        Its id on the page (``"forces"``).
    title : str
    standard : str
        The standards it follows; ``""`` for none.
    intro : str
        A paragraph on what it shows and how it is computed.
    tables : tuple of Table
    charts : tuple of Chart
    limits : tuple of str
        Each limit that binds a figure of the section, named (``"breakout, lift circuit:
        limited by tipping (front axle)"``).
    """

    key: str
    title: str
    standard: str = ""
    intro: str = ""
    tables: tuple[Table, ...] = ()
    charts: tuple[Chart, ...] = ()
    limits: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class SectionSource:
    """A section still to compute: its title (for progress) and how to build it.

    Attributes
    ----------
    key : str
    title : str
    build : callable
        ``build() -> Section``.
    """

    key: str
    title: str
    build: Callable[[], Section]


@dataclass(frozen=True, slots=True)
class MachineReport:
    """A machine's spec sheet, computed.

    Attributes
    ----------
    title : str
        The machine's name.
    family : str
        What kind of machine (``"wheel loader"``).
    source : str
        Its machine file, or ``""``.
    identity : tuple of (str, Cell)
        What the machine is: masses, cylinders, circuits, ...
    sections : tuple of Section
    command : str
        The command line that made it, for the record; ``""`` for none.
    notes : tuple of str
        Lines under the identity (what the report leaves out, how it was sampled).
    tables : tuple of Table
        Further tables of what the machine is (its cylinders and circuits).
    """

    title: str
    family: str
    source: str
    identity: tuple[tuple[str, Cell], ...]
    sections: tuple[Section, ...]
    command: str = ""
    notes: tuple[str, ...] = ()
    tables: tuple[Table, ...] = ()


def collect(
    sources: tuple[SectionSource, ...] | list[SectionSource], progress: Progress | None = None
) -> tuple[Section, ...]:
    """Build each section in turn, reporting progress after each.

    Parameters
    ----------
    sources : sequence of SectionSource
    progress : callable, optional
        ``progress(done, total)`` after each section.

    Returns
    -------
    tuple of Section
    """
    out = []
    for i, s in enumerate(sources):
        out.append(s.build())
        if progress is not None:
            progress(i + 1, len(sources))
    return tuple(out)
