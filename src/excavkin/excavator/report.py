"""An excavator's machine report: the sections the core's report lays out.

Each section runs the wing's analyses and turns their results into tables (every number a
[`Value`][excavkin.outputs.machine_report.content.Value] keyed for reading back), the limits
that bind them, named, and the wing's figures:

* **working ranges** per ISO 7135 / SAE J1193
  ([`working_ranges`][excavkin.excavator.ranges.working_ranges]);
* **tool forces** per ISO 6015 (lip) and SAE J1179 (tooth tip)
  ([`rated_force`][excavkin.excavator.forces.rated_force]), with force maps over a stroke sweep;
* **stability**: the rated forces capped by tipping and slipping (ISO 6015 §4.5,
  [`base_rated_force`][excavkin.excavator.stability.base_rated_force]) and the rated lift
  capacity (ISO 10567, [`lift_table`][excavkin.excavator.lift.lift_table]) — where the machine
  file has a base machine;
* **pin loads** over a stroke sweep ([`pin_loads`][excavkin.excavator.pin_loads.pin_loads]);
* **hydraulic cycle**: stroke times, the dig–swing–dump cycle and its power
  ([`cycle_time`][excavkin.excavator.hydraulics.cycle_time],
  [`cycle_power`][excavkin.excavator.cycle_power.cycle_power]) — where it has ``[hydraulics]``;
* **the moving front** through the working-range poses, as an interactive figure.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from excavkin.excavator.machine import Machine
from excavkin.outputs.machine_report import family_report, kg_value, kn_value, limit_name, mm_value
from excavkin.outputs.machine_report.content import Chart, Section, SectionSource, Table, Value

if TYPE_CHECKING:
    from excavkin.outputs.machine_report import Cell, MachineReport, Progress

__all__ = ["FAMILY", "machine_report", "report_sections"]

#: the family's name in the report
FAMILY = "hydraulic excavator"

#: grid points per stroke of the force-map and pin-load sweeps unless asked otherwise
SAMPLES = 21

#: poses between two working-range poses of the moving front
FRONT_STEPS = 16

#: the working-range poses the moving front passes through, in order
FRONT_POSES = (
    "max_reach_ground",
    "max_digging_depth",
    "max_digging_reach",
    "max_cutting_height",
    "max_dumping_height",
    "max_reach_ground",
)

_STANDARDS = (("lip", "ISO 6015"), ("tip", "SAE J1179"))


def identity(machine: Machine) -> tuple[tuple[str, Cell], ...]:
    """What the machine is: masses, the base, the tool.

    Parameters
    ----------
    machine : Machine

    Returns
    -------
    tuple of (str, Cell)
    """
    out: list[tuple[str, Cell]] = [
        ("front (bodies and cylinders)", kg_value(machine.front_mass, "mass.front")),
    ]
    base = machine.base
    if base is not None:
        out += [
            ("upper structure", kg_value(base.upper.mass, "mass.upper")),
            ("counterweight", kg_value(base.counterweight.mass, "mass.counterweight")),
            ("undercarriage", kg_value(base.undercarriage.mass, "mass.undercarriage")),
            ("operating mass", kg_value(machine.front_mass + base.mass, "mass.operating")),
            ("track length", mm_value(base.track_length, "base.track_length")),
            ("track gauge", mm_value(base.gauge, "base.gauge")),
            ("ground friction", Value(base.friction, digits=2, key="base.friction")),
        ]
    out += [
        ("tooth-tip radius", mm_value(machine.tip_radius, "tool.tip_radius")),
        ("lip radius", mm_value(machine.lip_radius, "tool.lip_radius")),
        ("lift point", machine.lift_point),
    ]
    return tuple(out)


def _ranges(machine: Machine) -> tuple[Section, object]:
    from excavkin.excavator.plots import plot_working_range
    from excavkin.excavator.ranges import working_ranges

    wr = working_ranges(machine)
    rows = tuple(
        (
            f.code,
            f.label,
            mm_value(f.value, f"ranges.{f.key}"),
            mm_value(f.tip[0], f"ranges.{f.key}.x"),
            mm_value(f.tip[1], f"ranges.{f.key}.y"),
            mm_value(f.lengths[0], f"ranges.{f.key}.boom"),
            mm_value(f.lengths[1], f"ranges.{f.key}.arm"),
            mm_value(f.lengths[2], f"ranges.{f.key}.bucket"),
        )
        for f in wr.figures
    )
    section = Section(
        "dimensions",
        "Working ranges",
        "ISO 7135 / SAE J1193",
        "The tooth tip's standard figures, each found by a search over the strokes, and the "
        "envelope it sweeps.",
        (
            Table(
                "Working ranges (tooth tip)",
                (
                    "code",
                    "figure",
                    "value (mm)",
                    "x (mm)",
                    "y (mm)",
                    "boom (mm)",
                    "arm (mm)",
                    "bucket (mm)",
                ),
                rows,
                note="x from the swing axis, y from the ground line; boom, arm and bucket: the "
                "cylinder lengths of the pose.",
            ),
        ),
        (
            Chart(
                "Working-range diagram: the tooth-tip envelope with the figures marked",
                "ISO 7135 / SAE J1193",
                plot_working_range(machine, wr).figure,
                "ranges-chart",
            ),
        ),
    )
    return section, wr


def _forces(machine: Machine, samples: int) -> Section:
    from excavkin.excavator.forces import rated_force, tool_forces
    from excavkin.excavator.plots import plot_force_map
    from excavkin.excavator.ranges import sweep

    rows = []
    limits = []
    for at, std in _STANDARDS:
        for working in ("arm", "bucket"):
            r = rated_force(machine, working, at=at)  # type: ignore[arg-type]
            k = f"forces.{at}.{working}"
            rows.append(
                (
                    std,
                    working,
                    kn_value(r.force, f"{k}.force"),
                    kn_value(r.uncapped, f"{k}.own_limit"),
                    Value(r.moment, "torque", "kN*m", 1, f"{k}.moment"),
                    mm_value(r.radius, f"{k}.radius"),
                    r.limiting,
                )
            )
            if r.limiting != r.working:
                limits.append(
                    f"{std} {working} force: limited by the relief of the "
                    f"{limit_name(machine.cylinders, r.limiting)}"
                )
    pose = sweep(machine, samples)
    charts = tuple(
        Chart(
            f"{working}-cylinder tool force at the lip over a {samples}³ stroke sweep, the "
            "front's weight included",
            "ISO 6015",
            plot_force_map(
                machine,
                tool_forces(machine, pose.lengths, working, at="lip"),  # type: ignore[arg-type]
                cell=max(0.25, 8.0 / samples),
            ).figure,
            f"force-map-{working}",
        )
        for working in ("arm", "bucket")
    )
    return Section(
        "forces",
        "Tool forces",
        "ISO 6015 / SAE J1179",
        "Rated digging forces: the bucket at its cylinder's largest moment, the stick at the "
        "arm cylinder's, working pressure in the working cylinder, the holding cylinders within "
        "their relief, no gravity; at the lip (ISO 6015) and at the tooth tip (SAE J1179).",
        (
            Table(
                "Rated tool forces",
                (
                    "standard",
                    "cylinder",
                    "force (kN)",
                    "own limit (kN)",
                    "moment (kN·m)",
                    "radius (mm)",
                    "limited by",
                ),
                tuple(rows),
                note="own limit: the working cylinder's moment over the radius; force: capped "
                "where a holding cylinder reaches its relief.",
            ),
        ),
        charts,
        tuple(limits),
    )


def _stability(machine: Machine, samples: int) -> Section:
    from excavkin.excavator.lift import lift_table
    from excavkin.excavator.stability import base_rated_force
    from excavkin.excavator.stability_plots import plot_lift_chart

    rows = []
    limits = []
    for at, std in _STANDARDS:
        for working in ("arm", "bucket"):
            r = base_rated_force(machine, working, at=at, swing="front")  # type: ignore[arg-type]
            k = f"stability.{at}.{working}"
            rows.append(
                (
                    std,
                    working,
                    kn_value(r.rated.force, f"{k}.force"),
                    kn_value(r.hydraulic, f"{k}.hydraulic"),
                    kn_value(r.tipping, f"{k}.tipping"),
                    r.tipping_line,
                    kn_value(r.slipping, f"{k}.slipping"),
                    r.rated.limiting,
                )
            )
            limits.append(
                f"{std} {working} force over the front: limited by "
                f"{limit_name(machine.cylinders, r.rated.limiting)}"
            )
    t = lift_table(machine)
    g = machine.gravity
    lift_rows = []
    a = t.at_max_reach
    for i, h in enumerate(t.heights):
        if not np.isfinite(t.max_reach[i]):
            continue
        k = f"lift.{h:.2f}"
        lift_rows.append(
            (
                mm_value(float(h), f"{k}.height"),
                mm_value(t.max_reach[i], f"{k}.radius"),
                kg_value(a.rated["front"][i] / g, f"{k}.front"),
                "hydraulic" if a.hydraulic_limited["front"][i] else "tipping",
                kg_value(a.rated["side"][i] / g, f"{k}.side"),
                "hydraulic" if a.hydraulic_limited["side"][i] else "tipping",
            )
        )
    return Section(
        "stability",
        "Stability and lift capacity",
        "ISO 6015 §4.5, ISO 10567",
        "The rated tool forces over the front capped by the cylinders, tipping and slipping of "
        "the whole machine (the front's weight counts for tipping and slipping); the rated lift "
        "capacity: the lesser of 75 % of the tipping load and 87 % of the hydraulic capacity.",
        (
            Table(
                "Rated tool forces capped by the base machine (ISO 6015 §4.5)",
                (
                    "standard",
                    "cylinder",
                    "force (kN)",
                    "cylinders (kN)",
                    "tipping (kN)",
                    "tipping line",
                    "slipping (kN)",
                    "limited by",
                ),
                tuple(rows),
            ),
            Table(
                f"Rated lift capacity at the largest radius (ISO 10567), load at {t.point}",
                (
                    "height (mm)",
                    "radius (mm)",
                    "over the front (kg)",
                    "limit",
                    "over the side (kg)",
                    "limit",
                ),
                tuple(lift_rows),
                note="The chart gives the whole table over load radius and height.",
            ),
        ),
        (
            Chart(
                "Lift chart: rated capacity over load radius and height, front and side",
                "ISO 10567",
                plot_lift_chart(machine, t).figure,
                "lift-chart",
            ),
        ),
        tuple(limits),
    )


def _pins(machine: Machine, samples: int) -> Section:
    from excavkin.excavator.pin_loads import CASES, load_maxima, pin_loads
    from excavkin.excavator.pin_plots import plot_load_maxima
    from excavkin.excavator.ranges import stroke_grid

    grid = stroke_grid(machine, samples)
    results = tuple(pin_loads(machine, grid, case) for case in CASES)
    maxima = load_maxima(results)
    rows = tuple(
        (
            mx.label,
            mx.kind,
            kn_value(mx.value, f"pins.{mx.name}.load"),
            mx.case,
            kn_value(mx.tool_force, f"pins.{mx.name}.tool_force"),
        )
        for mx in maxima
    )
    return Section(
        "pins",
        "Pin loads and cylinder forces",
        "ISO 6015 (lip)",
        "Each pin's largest load and each cylinder's largest force over a stroke sweep, the "
        "front's weight included, in three cases: the bucket- or arm-cylinder tool force at the "
        "lip, or the hydraulic lift capacity hanging at the lift point.",
        (
            Table(
                "Largest loads over the working range",
                ("pin or cylinder", "kind", "load (kN)", "case", "tool force or load (kN)"),
                rows,
                note=f"{samples}³ stroke sweep; a cylinder's force > 0 pushes.",
            ),
        ),
        (
            Chart(
                "Largest load of each pin and cylinder in each load case",
                "ISO 6015 (lip)",
                plot_load_maxima(machine, maxima).figure,
                "pins-chart",
            ),
        ),
    )


def _cycle(machine: Machine) -> Section:
    from excavkin.excavator.cycle_plots import plot_cycle_power
    from excavkin.excavator.cycle_power import cycle_power
    from excavkin.excavator.hydraulics import cycle_time, strokes

    st = strokes(machine)
    cy = cycle_time(machine)
    cp = cycle_power(machine)
    stroke_rows = tuple(
        (
            s.role,
            Value(s.flow, "volume_flow", "L/min", key=f"cycle.{s.role}.flow"),
            Value(s.extend_time, "time", "s", 2, f"cycle.{s.role}.extend_time"),
            Value(s.retract_time, "time", "s", 2, f"cycle.{s.role}.retract_time"),
        )
        for s in st
    )
    phases = (
        ("dig (arm + bucket in)", cy.dig, "dig"),
        ("boom up", cy.boom_up, "boom_up"),
        ("swing (one way)", cy.swing, "swing"),
        ("dump (arm + bucket out)", cy.dump, "dump"),
        ("boom down", cy.boom_down, "boom_down"),
        ("cycle, one motion at a time", cy.sequential, "sequential"),
        ("cycle, swing overlapping boom", cy.overlapped, "overlapped"),
    )
    cycle_rows = tuple((name, Value(v, "time", "s", 2, f"cycle.{key}")) for name, v, key in phases)
    power_rows = []
    limits = []
    for ph in cp.phases:
        if ph.role is None:
            continue
        k = f"cycle.power.{ph.name}"
        power_rows.append(
            (
                ph.name,
                Value(ph.peak, "power", "kW", 1, f"{k}.peak"),
                Value(ph.peak_pressure, "pressure", "MPa", 1, f"{k}.peak_pressure"),
                Value(ph.work, "energy", "kJ", 1, f"{k}.work"),
            )
        )
        if ph.over_pressure > 0.0:
            limits.append(
                f"{ph.name}: beyond the working pressure {ph.working_pressure / 1e6:.1f} MPa "
                f"over {ph.over_pressure:.0%} of the stroke (cannot run at full flow there)"
            )
    return Section(
        "cycle",
        "Hydraulic cycle",
        "",
        "Full-stroke, no-load times at the pumps' full flow, a dig–swing–dump cycle estimate "
        "and the power along it (weight and inertia, no soil).",
        (
            Table(
                "Stroke times",
                ("cylinder", "flow (L/min)", "extend (s)", "retract (s)"),
                stroke_rows,
            ),
            Table("Cycle", ("motion", "time (s)"), cycle_rows),
            Table(
                "Power along the cycle",
                ("phase", "peak power (kW)", "peak pressure (MPa)", "work (kJ)"),
                tuple(power_rows),
                note=f"The pumps deliver at most {cp.supply / 1e3:.0f} kW at full flow and "
                "working pressure.",
            ),
        ),
        (
            Chart(
                "Power and inlet pressure along the cycle",
                "pump flows and the machine's weight and inertia",
                plot_cycle_power(cp, title=f"{machine.name}: power along the cycle").figure,
                "cycle-chart",
            ),
        ),
        tuple(limits),
    )


def front_lengths(machine: Machine, ranges: object, steps: int = FRONT_STEPS) -> np.ndarray:
    """Cylinder lengths of the moving front: through the working-range poses in turn.

    Parameters
    ----------
    machine : Machine
    ranges : WorkingRanges
        Whose figures' poses the front passes through (`FRONT_POSES`).
    steps : int
        Poses from one figure's pose to the next.

    Returns
    -------
    ndarray, shape (n, 3)
        Boom, arm and bucket lengths (m), each straight between two poses.
    """
    known = {f.key: f.lengths for f in ranges.figures}  # type: ignore[attr-defined]
    poses = [np.asarray(known[k], dtype=np.float64) for k in FRONT_POSES if k in known]
    t = np.linspace(0.0, 1.0, steps, endpoint=False)[:, None]
    parts = [a + (b - a) * t for a, b in zip(poses[:-1], poses[1:], strict=True)]
    return np.vstack([*parts, poses[-1][None, :]])


def _front(machine: Machine, ranges: object) -> Section:
    from excavkin.excavator.machine import forward
    from excavkin.outputs.machine_report.parts import moving_front_section

    return moving_front_section(
        forward(machine, front_lengths(machine, ranges)).result,
        "The front over its range, through the poses of the working-range figures: reach at "
        "ground, digging depth, digging reach, cutting height, dumping height.",
        caption="Through the working-range poses",
        standard="ISO 7135 poses, engine kinematics",
    )


def report_sections(machine: Machine, *, samples: int = SAMPLES) -> tuple[SectionSource, ...]:
    """The excavator's sections, still to compute, in the report's order.

    Parameters
    ----------
    machine : Machine
    samples : int
        Grid points per stroke of the force-map and pin-load sweeps (2 to 101).

    Returns
    -------
    tuple of SectionSource
    """
    if not 2 <= samples <= 101:
        from excavkin.errors import InputError

        raise InputError(f"samples must be from 2 to 101, not {samples}")
    found: dict[str, object] = {}

    def ranges() -> Section:
        section, found["ranges"] = _ranges(machine)
        return section

    out = [
        SectionSource("dimensions", "working ranges", ranges),
        SectionSource("forces", "tool forces", lambda: _forces(machine, samples)),
    ]
    if machine.base is not None:
        out.append(SectionSource("stability", "stability", lambda: _stability(machine, samples)))
    out.append(SectionSource("pins", "pin loads", lambda: _pins(machine, samples)))
    if machine.hydraulics is not None:
        out.append(SectionSource("cycle", "hydraulic cycle", lambda: _cycle(machine)))
    out.append(SectionSource("front", "moving front", lambda: _front(machine, found["ranges"])))
    return tuple(out)


def machine_report(
    machine: Machine,
    *,
    samples: int = SAMPLES,
    command: str = "",
    progress: Progress | None = None,
) -> MachineReport:
    """The excavator's spec sheet, computed (module docstring): its `report_sections` laid
    out by [`family_report`][excavkin.outputs.machine_report.parts.family_report], with a note
    for each section the machine file leaves out.

    Parameters
    ----------
    machine : Machine
    samples : int
        Grid points per stroke of the force-map and pin-load sweeps (2 to 101).
    command, progress
        As `family_report`'s: the record of the command line that made it; the callback
        ``progress(done, total)`` after each section.

    Returns
    -------
    MachineReport
    """
    notes = []
    if machine.base is None:
        notes.append("No base machine in the machine file: no stability section.")
    if machine.hydraulics is None:
        notes.append("No [hydraulics]: no cycle section.")
    sources = report_sections(machine, samples=samples)
    return family_report(
        machine, machine.name, FAMILY, identity(machine), sources, notes,
        command=command, progress=progress,
    )  # fmt: skip
