"""A crane's machine report: the sections the core's report lays out.

Each section runs one of the wing's analyses and turns its result into tables (every number a
[`Value`][excavkin.outputs.machine_report.content.Value] keyed for reading back), the limits
that bind it, named, and its ``plot()``:

* **working range** ([`reach`][excavkin.crane.reach.reach]);
* **load chart** per ASME B30.5 para. 5-1.1.1 ([`load_chart`][excavkin.crane.chart.load_chart]),
  or with stability by the crane's factored loads, one table per boom configuration, each cell
  with the limit that binds it;
* **support reactions** over a 360° slew with the rated load at the middle radius of the
  longest configuration ([`support_reactions`][excavkin.crane.supports.support_reactions]);
* **the moving booms**: luffed up with the jib folded or retracted, the jib opened or pushed
  out, luffed down, as an interactive figure.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from excavkin.crane.machine import Crane
from excavkin.outputs.machine_report import family_report, kg_value, kn_value, mm_value
from excavkin.outputs.machine_report.content import Chart, Section, SectionSource, Table, Value

if TYPE_CHECKING:
    from excavkin.crane.chart import LoadChart
    from excavkin.outputs.machine_report import Cell, MachineReport, Progress

__all__ = ["FAMILY", "machine_report", "report_sections"]

#: the family's name in the report
FAMILY = "crane"
#: radii of the load chart unless asked otherwise
SAMPLES = 15
#: poses of each stage of the moving booms
FRONT_STEPS = 20


def identity(machine: Crane) -> tuple[tuple[str, Cell], ...]:
    """What the crane is: masses, hoist, support.

    Parameters
    ----------
    machine : Crane

    Returns
    -------
    tuple of (str, Cell)
        Each figure's name and value, in the order the report lists them.
    """
    sup, h = machine.support, machine.hoist
    rows: list[tuple[str, Cell]] = [
        ("kind", f"{machine.kind} crane"),
        ("mass without a load", kg_value(machine.mass, "mass.crane")),
        (
            "booms (bodies and cylinders)",
            kg_value(float(machine.mass_points.mass.sum()), "mass.booms"),
        ),
    ]
    rows += [(f"{m.name} (slews)", kg_value(m.mass, f"mass.turning.{m.name}")) for m in sup.turning]
    rows += [(f"{m.name} (carrier)", kg_value(m.mass, f"mass.fixed.{m.name}")) for m in sup.fixed]
    rows += [
        ("hoist line pull", kn_value(h.line_pull, "hoist.line_pull")),
        ("parts of line", Value(float(h.parts), key="hoist.parts")),
        ("hook block", kg_value(h.hook_mass, "hoist.hook_mass")),
        ("support", machine.mounting),
    ]
    return tuple(rows)


def _radii(machine: Crane, samples: int) -> np.ndarray:
    """About ``samples`` radii over the working range, at a step of whole half metres."""
    from excavkin.crane.reach import reach

    x = reach(machine, 21).tip[..., 0]
    lo, hi = max(float(x.min()), 0.0), float(x.max())
    step = max(0.5, 0.5 * round((hi - lo) / (samples - 1) / 0.5))
    return np.arange(np.ceil(lo / step) * step, hi + 1e-9, step)


def _range(machine: Crane) -> Section:
    from excavkin.crane.reach import reach

    rg = reach(machine, 41)
    x, y = rg.tip[..., 0], rg.tip[..., 1]
    knuckle = rg.config_name == "knuckle angle"
    kind, unit, digits = ("angle", "deg", 1) if knuckle else ("length", "mm", 0)

    def row(name: str, key: str, v: np.ndarray, k: str, u: str, d: int) -> tuple[Cell, ...]:
        lo, hi = float(v.min()), float(v.max())
        return (
            name,
            Value(lo, k, u, d, f"range.{key}.min"),
            Value(hi, k, u, d, f"range.{key}.max"),
            u,
        )

    rows = (
        row("boom angle", "boom_angle", rg.boom_angle, "angle", "deg", 1),
        row(rg.config_name, "config", rg.config, kind, unit, digits),
        row("radius of the tip", "radius", x, "length", "mm", 0),
        row("height of the tip", "height", y, "length", "mm", 0),
    )
    return Section(
        "range",
        "Working range",
        "engine kinematics",
        "The jib's tip over 41 × 41 lengths of both cylinders' strokes; the hook hangs below it.",
        (Table("Working range", ("figure", "least", "largest", "unit"), rows),),
        (Chart("Working-range diagram", "engine kinematics", rg.plot().figure, "range-chart"),),
    )


def _chart_table(chart: LoadChart, j: int) -> Table:
    rows = []
    for i, r in enumerate(chart.radius):
        cells: list[Cell] = [mm_value(float(r), f"chart.{j}.{i}.radius")]
        for k in range(len(chart.sectors)):
            c = float(chart.capacity[i, j, k])
            cells.append(Value(c, "mass", "t", 2, f"chart.{j}.{i}.{k}.capacity"))
            cells.append(str(chart.binding[i, j, k]).replace(" (outriggers)", ""))
        rows.append(tuple(cells))
    cols = ["radius (mm)"]
    for s in chart.sectors:
        cols += [f"{s.name} (t)", f"{s.name}: binds"]
    return Table(
        f"Load chart, {chart.config_label(j)} ({_standard(chart)})",
        tuple(cols),
        tuple(rows),
        note=f"Hook load, hook block of {chart.hook_mass:g} kg included; stability "
        f"{chart.criterion_text}, the least over each sector.",
    )


def _standard(chart: LoadChart) -> str:
    """What the chart is rated by, for the report's captions."""
    if chart.factors is None:
        return "ASME B30.5 para. 5-1.1.1"
    return f"stability by factored loads, {chart.criterion}"


def _chart(machine: Crane, samples: int) -> Section:
    from excavkin.crane.chart import load_chart

    chart = load_chart(machine, _radii(machine, samples))
    binding = sorted({str(b) for b in chart.binding.ravel() if b != "out of reach"})
    return Section(
        "chart",
        "Load chart",
        _standard(chart),
        "Each cell is the least of the cylinders at their port relief (the general "
        "kinetostatics), the hoist's line pull × parts and stability (the whole-machine "
        "equilibrium), with the limit that binds named; '—' where the radius is out of reach.",
        tuple(_chart_table(chart, j) for j in range(chart.second.size)),
        (
            Chart(
                "Capacity over radius, least over the sectors",
                _standard(chart),
                chart.plot().figure,
                "chart-chart",
            ),
        ),  # fmt: skip
        tuple(f"binds somewhere in the chart: {b}" for b in binding),
    )


def _supports(machine: Crane, samples: int) -> Section:
    from excavkin.crane.chart import load_chart
    from excavkin.crane.supports import support_reactions

    second = machine.second.extended
    radii = _radii(machine, samples)
    chart = load_chart(machine, radii, np.array([second]))
    least = np.nanmin(np.where(np.isnan(chart.capacity), np.inf, chart.capacity), axis=2)[:, 0]
    good = np.nonzero(np.isfinite(least))[0]
    i = int(good[len(good) // 2])
    radius, load = float(radii[i]), float(least[i])
    rs = support_reactions(machine, radius, second, load)

    def row(j: int, name: str) -> tuple[Cell, ...]:
        r = rs.reaction[:, j]
        hi, lo = int(np.nanargmax(r)), int(np.nanargmin(r))
        return (
            name,
            kn_value(float(r[hi]), f"supports.{j}.max"),
            Value(float(rs.slew[hi]), "angle", "deg", 0, f"supports.{j}.max_slew"),
            kn_value(float(r[lo]), f"supports.{j}.min"),
            Value(float(rs.slew[lo]), "angle", "deg", 0, f"supports.{j}.min_slew"),
        )

    rows = tuple(row(j, name) for j, name in enumerate(rs.labels))
    return Section(
        "stability",
        "Support reactions",
        "whole-machine equilibrium",
        f"The rated load at {radius:.2f} m with the jib at the end of its stroke "
        f"({load / 1000:.2f} t), slewed through 360°: each contact point's reaction, the "
        "carrier rigid on equal springs that push but never pull.",
        (
            Table(
                "Reactions over a 360° slew",
                ("contact", "largest (kN)", "at slew (deg)", "least (kN)", "at slew (deg)"),
                rows,
                note=f"Total {rs.weight / 1000:.1f} kN: the crane and its load.",
            ),
        ),
        (
            Chart(
                "Reactions over the slew",
                "whole-machine equilibrium",
                rs.plot().figure,
                "supports-chart",
            ),
        ),  # fmt: skip
    )


def front_lengths(machine: Crane, steps: int = FRONT_STEPS) -> np.ndarray:
    """Cylinder lengths of the moving booms: luffed up with the second cylinder retracted, the
    second cylinder extended, luffed down, the second cylinder retracted.

    Parameters
    ----------
    machine : Crane
    steps : int
        Poses per stage.

    Returns
    -------
    ndarray, shape (4·steps, 2)
    """
    luff, second = machine.cylinders
    t = np.linspace(0.0, 1.0, steps)
    up = luff.retracted + (luff.extended - luff.retracted) * t
    out = second.retracted + (second.extended - second.retracted) * t
    return np.vstack(
        [
            np.column_stack([up, np.full(steps, second.retracted)]),
            np.column_stack([np.full(steps, luff.extended), out]),
            np.column_stack([up[::-1], np.full(steps, second.extended)]),
            np.column_stack([np.full(steps, luff.retracted), out[::-1]]),
        ]
    )


def _front(machine: Crane) -> Section:
    from excavkin.outputs.machine_report.parts import moving_front_section

    text = (
        "The booms over their range: luffed up with the jib folded in, the jib opened or "
        "pushed out, luffed down, the jib brought back."
    )
    res = machine.solve(front_lengths(machine))
    return moving_front_section(
        res, text, caption="Luff, open, lower, close", standard="engine kinematics"
    )


def machine_report(
    machine: Crane, *, samples: int = SAMPLES, command: str = "", progress: Progress | None = None
) -> MachineReport:
    """The crane's spec sheet, computed (module docstring): `report_sections` through
    [`family_report`][excavkin.outputs.machine_report.parts.family_report].

    Parameters
    ----------
    machine : Crane
    samples : int
        Radii of the load chart (at least 2).
    command, progress
        As [`family_report`][excavkin.outputs.machine_report.parts.family_report]'s: the
        command line that made it; ``progress(done, total)`` after each section.

    Returns
    -------
    MachineReport
    """
    notes = ("Static: no wind, no dynamic effect of hoisting or slewing.",)
    return family_report(
        machine, machine.name, FAMILY, identity(machine),
        report_sections(machine, samples=samples), notes, command=command, progress=progress,
    )  # fmt: skip


def report_sections(machine: Crane, *, samples: int = SAMPLES) -> tuple[SectionSource, ...]:
    """The crane's sections, still to compute, in the report's order.

    Parameters
    ----------
    machine : Crane
    samples : int
        Radii of the load chart (at least 2).

    Returns
    -------
    tuple of SectionSource
    """
    if samples < 2:
        from excavkin.errors import InputError

        raise InputError(f"samples must be at least 2, not {samples}")
    return (
        SectionSource("range", "working range", lambda: _range(machine)),
        SectionSource("chart", "load chart", lambda: _chart(machine, samples)),
        SectionSource("stability", "support reactions", lambda: _supports(machine, samples)),
        SectionSource("front", "moving booms", lambda: _front(machine)),
    )
