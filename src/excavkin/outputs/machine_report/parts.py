"""Parts every family's report shares: values in the sheet's units, the names of binding
limits, the cylinders' table, the moving front and the report itself.

Both read the machinery layer's and the engine's objects only, never a wing's.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from excavkin.machinery.cylinders import Circuit, Cylinder
from excavkin.outputs.machine_report.content import (
    Cell,
    Chart,
    MachineReport,
    Progress,
    Section,
    SectionSource,
    Table,
    Value,
    collect,
)

if TYPE_CHECKING:
    from excavkin.machinery.cylinder_machine import CylinderMachine

__all__ = [
    "cylinder_table",
    "family_report",
    "kg_value",
    "kn_value",
    "limit_name",
    "mm_value",
    "moving_front_chart",
    "moving_front_section",
]


def mm_value(v: float, key: str) -> Value:
    """A length shown in mm.

    Parameters
    ----------
    v : float
        SI (m).
    key : str
        The value's key.

    Returns
    -------
    Value
    """
    return Value(float(v), "length", "mm", key=key)


def kn_value(v: float, key: str) -> Value:
    """A force shown in kN, one decimal.

    Parameters
    ----------
    v : float
        SI (N).
    key : str
        The value's key.

    Returns
    -------
    Value
    """
    return Value(float(v), "force", "kN", 1, key=key)


def kg_value(v: float, key: str) -> Value:
    """A mass shown in kg.

    Parameters
    ----------
    v : float
        SI (kg).
    key : str
        The value's key.

    Returns
    -------
    Value
    """
    return Value(float(v), "mass", "kg", key=key)


def limit_name(cylinders: Sequence[Cylinder], limiting: str) -> str:
    """A binding limit as the report names it: a cylinder's role becomes ``"boom cylinder"``.

    Parameters
    ----------
    cylinders : sequence of Cylinder
        The machine's.
    limiting : str
        As an analysis names it (a role, ``"tipping (LINE)"``, ``"slipping"``, several joined
        by ``+``).

    Returns
    -------
    str
    """
    roles = {c.role for c in cylinders}
    return " + ".join(
        f"{p} cylinder" if p in roles else p for p in (x.strip() for x in limiting.split("+"))
    )


def family_report(
    machine: CylinderMachine,
    title: str,
    family: str,
    identity: Sequence[tuple[str, Cell]],
    sources: Sequence[SectionSource],
    notes: Sequence[str],
    *,
    command: str = "",
    progress: Progress | None = None,
) -> MachineReport:
    """A family's spec sheet: its sections computed one after another, with its identity,
    its notes and its cylinders' table.

    Parameters
    ----------
    machine : CylinderMachine
        The machine (its source, cylinders and circuits).
    title : str
        The machine's name.
    family : str
        The family's name in the report (``"wheel loader"``).
    identity : sequence of (str, Cell)
        What the machine is (masses, base, tool …).
    sources : sequence of SectionSource
        The wing's sections, still to compute, in the report's order.
    notes : sequence of str
        What the report leaves out, and why.
    command : str
        The command line that made it, for the record.
    progress : callable, optional
        ``progress(done, total)`` after each section.

    Returns
    -------
    MachineReport
    """
    return MachineReport(
        title,
        family,
        str(machine.source or ""),
        tuple(identity),
        collect(tuple(sources), progress),
        command,
        tuple(notes),
        (cylinder_table(machine.cylinders, machine.circuits),),
    )


def cylinder_table(
    cylinders: Sequence[Cylinder], circuits: Mapping[str, Circuit], *, key: str = "cylinder"
) -> Table:
    """The cylinders with their circuits' pressures, one row each.

    Parameters
    ----------
    cylinders : sequence of Cylinder
    circuits : mapping of str to Circuit
        By name; each cylinder's ``circuit`` names one.
    key : str
        Prefix of the values' keys (``cylinder.lift.bore``).

    Returns
    -------
    Table
    """
    rows = []
    for c in cylinders:
        k = f"{key}.{c.role}"
        circ = circuits[c.circuit]
        rows.append(
            (
                c.role,
                Value(float(c.count), key=f"{k}.count"),
                Value(c.bore, "length", "mm", key=f"{k}.bore"),
                Value(c.rod, "length", "mm", key=f"{k}.rod"),
                Value(c.retracted, "length", "mm", key=f"{k}.retracted"),
                Value(c.stroke, "length", "mm", key=f"{k}.stroke"),
                Value(circ.working, "pressure", "MPa", 1, key=f"{k}.working"),
                Value(circ.relief, "pressure", "MPa", 1, key=f"{k}.relief"),
            )
        )
    return Table(
        "Cylinders and circuits",
        (
            "cylinder",
            "count",
            "bore (mm)",
            "rod (mm)",
            "retracted (mm)",
            "stroke (mm)",
            "working (MPa)",
            "relief (MPa)",
        ),
        tuple(rows),
        note="Working pressure drives the working cylinder; a holding cylinder may reach its "
        "port relief.",
    )


def moving_front_chart(
    result: Any,
    *,
    caption: str,
    standard: str,
    key: str = "front",
    show: Sequence[str] | None = None,
    max_frames: int = 121,
) -> Chart:
    """The linkage moving along ``result``'s samples, as an interactive Plotly figure.

    Parameters
    ----------
    result : KinematicResult
        The engine's solution along the motion shown.
    caption : str
    standard : str
        What the motion follows.
    key : str
        The figure's id on the page.
    show : sequence of str, optional
        Columns whose current value the view shows; default the cylinder lengths.
    max_frames : int
        Most slider positions.

    Returns
    -------
    Chart
    """
    from excavkin.outputs.report import mechanism_figure

    fig = mechanism_figure(result, show=show, max_frames=max_frames)
    fig.layout.height = 640
    return Chart(caption, standard, fig, key)


def moving_front_section(result: Any, text: str, *, caption: str, standard: str) -> Section:
    """The report's last section: the linkage moving along ``result``'s samples
    (`moving_front_chart`).

    Parameters
    ----------
    result : KinematicResult
        The engine's solution along the motion shown.
    text : str
        What the motion is; the section adds how to play it.
    caption : str
    standard : str
        What the motion follows.

    Returns
    -------
    Section
    """
    return Section(
        "front",
        "Moving front",
        "",
        f"{text} Drag the slider or press Play; the box shows the cylinder lengths.",
        charts=(moving_front_chart(result, caption=caption, standard=standard),),
    )
