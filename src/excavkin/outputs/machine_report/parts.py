"""Parts every family's report shares: the cylinders' table and the moving front.

Both read the machinery layer's and the engine's objects only, never a wing's.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from excavkin.machinery.cylinders import Circuit, Cylinder
from excavkin.outputs.machine_report.content import Chart, Table, Value

__all__ = ["cylinder_table", "moving_front_chart"]


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
