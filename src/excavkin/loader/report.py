"""A wheel loader's machine report: the sections the core's report lays out.

Each section runs one of the wing's analyses and turns its result into tables (every number a
[`Value`][excavkin.outputs.machine_report.content.Value] keyed for reading back), the limits
that bind it, named, and its ``plot()``:

* **dimensions** per SAE J732 / ISO 7131 ([`dimensions`][excavkin.loader.dimensions.dimensions]);
* **parallel lift** ([`parallel_lift`][excavkin.loader.parallel_lift.parallel_lift]);
* **breakout force** per SAE J732 / ISO 14397-2 ([`breakout`][excavkin.loader.breakout.breakout]);
* **stability**: static tipping loads and the rated operating capacity per SAE J732 /
  ISO 14397-1 / SAE J818 ([`static_tipping`][excavkin.loader.tipping.static_tipping]), lift and
  rollback capacity per ISO 14397-2 ([`capacity`][excavkin.loader.capacity.capacity]);
* **hydraulic cycle** per SAE J732 ([`cycle`][excavkin.loader.cycle.cycle]);
* **pin loads** over the lift ([`pin_loads`][excavkin.loader.pins.pin_loads]);
* **the moving front**: the linkage raising the rolled-back bucket from the ground pose to
  full lift, dumping, rolling back and lowering, as an interactive figure.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from excavkin.loader.machine import Loader
from excavkin.outputs.machine_report import family_report, kg_value, kn_value, limit_name, mm_value
from excavkin.outputs.machine_report.content import Chart, Section, SectionSource, Table, Value

if TYPE_CHECKING:
    from excavkin.outputs.machine_report import Cell, MachineReport, Progress

__all__ = ["FAMILY", "machine_report", "report_sections"]

#: the family's name in the report
FAMILY = "wheel loader"

#: lift lengths of the capacity, parallel-lift and pin-load sweeps unless asked otherwise
SAMPLES = 41

#: poses of each stage of the moving front (raise, dump, roll back, lower)
FRONT_STEPS = 20


def identity(machine: Loader) -> tuple[tuple[str, Cell], ...]:
    """What the machine is: masses, bucket, chassis.

    Parameters
    ----------
    machine : Loader
        The loader whose masses, bucket and chassis are listed.

    Returns
    -------
    tuple of (str, Cell)
        Each figure's name and value, in the order the report lists them.
    """
    ch, b = machine.chassis, machine.bucket
    return (
        ("operating mass", kg_value(machine.mass, "mass.operating")),
        ("linkage (bodies and cylinders)", kg_value(machine.linkage_mass, "mass.linkage")),
        ("front frame", kg_value(ch.front_frame.mass, "mass.front_frame")),
        ("rear frame", kg_value(ch.rear_frame.mass, "mass.rear_frame")),
        ("counterweight", kg_value(ch.counterweight.mass, "mass.counterweight")),
        ("bucket rated capacity (ISO 7546)", Value(b.capacity, "", "m^3", 2, "bucket.capacity")),
        ("bucket width", mm_value(b.width, "bucket.width")),
        ("wheelbase", mm_value(ch.wheelbase, "chassis.wheelbase")),
        ("tread", mm_value(ch.tread, "chassis.tread")),
        ("tyre static loaded radius", mm_value(ch.tyre_radius, "chassis.tyre_radius")),
        (
            "largest articulation",
            Value(ch.max_articulation, "angle", "deg", 1, "chassis.max_articulation"),
        ),
        ("rear axle", "oscillating" if ch.oscillating else "rigid"),
        ("carry height (hinge pin)", mm_value(machine.carry_height, "carry_height")),
    )


def _dimensions(machine: Loader) -> Section:
    from excavkin.loader.dimensions import dimensions

    d = dimensions(machine)
    rows = []
    for f in d.figures:
        v = (
            Value(f.value, "angle", "deg", 1, key=f"dimensions.{f.name}")
            if f.unit == "rad"
            else mm_value(f.value, f"dimensions.{f.name}")
        )
        rows.append(
            (
                f.name,
                v,
                "deg" if f.unit == "rad" else "mm",
                mm_value(f.lengths[0], f"dimensions.{f.name}.lift_cyl"),
                mm_value(f.lengths[1], f"dimensions.{f.name}.tilt_cyl"),
                f.definition,
            )
        )
    missing = [f.name for f in d.figures if not math.isfinite(f.value)]
    return Section(
        "dimensions",
        "Dimensions",
        "SAE J732 / ISO 7131",
        "Each figure is measured at the pose the standards define, solved by the engine; "
        "angles are the bucket floor's (heel to cutting edge) to the horizontal.",
        (
            Table(
                "Dimensions (SAE J732 / ISO 7131)",
                ("figure", "value", "unit", "lift cyl. (mm)", "tilt cyl. (mm)", "definition"),
                tuple(rows),
            ),
        ),
        (
            Chart(
                "Side view at the poses of the hinge-pin height, the dump clearance and reach "
                "at 45° and the digging depth",
                "SAE J732 / ISO 7131",
                d.plot(machine).figure,
                "dimensions-chart",
            ),
        ),
        tuple(f"{n}: its pose is not reached within the strokes" for n in missing),
    )


def _parallel_lift(machine: Loader, samples: int) -> Section:
    from excavkin.loader.parallel_lift import parallel_lift

    p = parallel_lift(machine, samples)
    k = int(np.argmax(np.abs(p.angle - p.angle[0])))
    table = Table(
        "Bucket angle over the lift, tilt cylinder held",
        ("figure", "value", "unit"),
        (
            ("tilt cylinder held at", mm_value(p.tilt, "parallel_lift.tilt"), "mm"),
            (
                "change, ground to full lift (> 0 rolls back)",
                Value(p.change, "angle", "deg", 2, "parallel_lift.change"),
                "deg",
            ),
            (
                "largest deviation",
                Value(p.deviation, "angle", "deg", 2, "parallel_lift.deviation"),
                "deg",
            ),
            (
                "hinge-pin height at the largest deviation",
                mm_value(p.hinge_height[k], "parallel_lift.deviation_height"),
                "mm",
            ),
        ),
        note=f"{len(p.lift)} lift lengths from the ground pose to full lift.",
    )
    return Section(
        "parallel-lift",
        "Parallel lift",
        "",
        "The tilt cylinder held at the length that levels the bucket on the ground, the lift "
        "cylinders run to full lift: a parallel-lift front keeps the bucket's angle.",
        (table,),
        (
            Chart(
                "Bucket floor angle over the hinge-pin height, tilt held",
                "engine kinematics",
                p.plot().figure,
                "parallel-lift-chart",
            ),
        ),
    )


def _breakout(machine: Loader) -> Section:
    from excavkin.loader.breakout import breakout

    bo = breakout(machine)
    rows = []
    limits = []
    for r in (bo.tilt, bo.lift):
        k = f"breakout.{r.circuit}"
        rows.append(
            (
                r.circuit,
                r.pivot,
                kn_value(r.force, f"{k}.force"),
                kn_value(r.working, f"{k}.working"),
                kn_value(r.hydraulic, f"{k}.hydraulic"),
                kn_value(r.tipping, f"{k}.tipping"),
                r.limiting,
            )
        )
        limits.append(
            f"breakout through the {r.circuit} circuit: limited by "
            f"{limit_name(machine.cylinders, r.limiting)}"
        )
    return Section(
        "forces",
        "Breakout force",
        "SAE J732 / ISO 14397-2",
        "The largest sustained vertical force 100 mm behind the cutting edge, the floor level "
        "on the ground, through the tilt circuit (about the bucket hinge pin, the arm blocked) "
        "and the lift circuit (about the lift-arm pin): the working cylinder at its circuit's "
        "working pressure, the holding cylinder within its port relief, the machine not tipping.",
        (
            Table(
                "Breakout force (SAE J732 / ISO 14397-2)",
                (
                    "circuit",
                    "pivot",
                    "breakout (kN)",
                    "working cyl. (kN)",
                    "with holding cyl. (kN)",
                    "tipping (kN)",
                    "limited by",
                ),
                tuple(rows),
            ),
        ),
        (
            Chart(
                "Each circuit's breakout force and the limits that cap it",
                "SAE J732 / ISO 14397-2",
                bo.plot().figure,
                "breakout-chart",
            ),
        ),
        tuple(limits),
    )


def _stability(machine: Loader, samples: int) -> Section:
    from excavkin.loader.capacity import capacity
    from excavkin.loader.tipping import static_tipping

    tl = static_tipping(machine)
    cap = capacity(machine, samples)
    rows: list[tuple[Cell, ...]] = []
    for c in (tl.straight, tl.full_turn):
        name = f"tipping.{c.name}"
        rows.append(
            (
                c.name,
                Value(c.articulation, "angle", "deg", 1, f"{name}.articulation"),
                kg_value(c.load, f"{name}.load"),
                c.line,
                mm_value(c.lengths[0], f"{name}.lift_cyl"),
            )
        )
    rows.append(
        (
            "rated operating capacity (50 % of full turn, SAE J818)",
            "",
            kg_value(tl.rated_operating_capacity, "tipping.rated_operating_capacity"),
            "",
            "",
        )
    )
    k = int(np.nanargmin(cap.lift))
    j = int(np.nanargmin(cap.rollback))
    cap_rows = (
        (
            "lift capacity to full height",
            kg_value(cap.to_full_height, "capacity.to_full_height"),
            mm_value(cap.hinge_height[k], "capacity.to_full_height.hinge_height"),
            str(cap.lift_limit[k]),
        ),
        (
            "least rollback capacity",
            kg_value(cap.rollback[j], "capacity.least_rollback"),
            mm_value(cap.hinge_height[j], "capacity.least_rollback.hinge_height"),
            str(cap.rollback_limit[j]),
        ),
    )
    return Section(
        "stability",
        "Stability and rated operating capacity",
        "SAE J732 / ISO 14397-1, SAE J818, ISO 14397-2",
        "Static tipping load: the least mass at the rated load's centre of gravity that lifts "
        "the rear wheels, bucket rolled back, over the lift, straight and at full turn. The "
        "rated operating capacity is half the full-turn tipping load. Lift and rollback "
        "capacity: what each circuit raises at working pressure, capped by tipping.",
        (
            Table(
                "Static tipping load (SAE J732 / ISO 14397-1)",
                ("case", "articulation (deg)", "load (kg)", "tipping line", "lift cyl. (mm)"),
                tuple(rows),
                note=f"The densest material the rated capacity may hold: {tl.density:.0f} "
                f"kg/m³ in {tl.capacity:.2f} m³.",
            ),
            Table(
                "Lift and rollback capacity (ISO 14397-2), bucket rolled back",
                ("figure", "load (kg)", "at hinge height (mm)", "limited by"),
                cap_rows,
                note=f"{samples} lift lengths over the stroke.",
            ),
        ),
        (
            Chart(
                "Static tipping loads and the rated operating capacity",
                "SAE J732 / ISO 14397-1, SAE J818",
                tl.plot().figure,
                "tipping-chart",
            ),
            Chart(
                "Lift and rollback capacity and the tipping load over the hinge-pin height",
                "ISO 14397-2",
                cap.plot().figure,
                "capacity-chart",
            ),
        ),
        (
            f"rated operating capacity: 50 % of the full-turn tipping load, about the "
            f"{tl.full_turn.line}",
            "lift capacity to full height: limited by "
            + limit_name(machine.cylinders, cap.lift_limit[k]),
            "least rollback capacity: limited by "
            + limit_name(machine.cylinders, cap.rollback_limit[j]),
        ),
    )


def _cycle(machine: Loader) -> Section:
    from excavkin.loader.cycle import cycle

    cy = cycle(machine)
    rows: list[tuple[Cell, ...]] = []
    limits = []
    for p in cy.phases:
        k = f"cycle.{p.name}"
        rows.append(
            (
                p.name,
                f"{p.role} {p.direction}",
                Value(p.flow, "volume_flow", "L/min", key=f"{k}.flow"),
                Value(p.time, "time", "s", 2, f"{k}.time"),
                kg_value(p.load, f"{k}.load"),
                Value(p.pressure, "pressure", "MPa", 1, f"{k}.pressure"),
                Value(p.power, "power", "kW", 1, f"{k}.power"),
            )
        )
        if p.over_working:
            limits.append(
                f"{p.name}: needs {p.pressure / 1e6:.1f} MPa, above the working pressure "
                f"{p.working / 1e6:.1f} MPa"
            )
        elif p.pressure < 0.0:
            limits.append(f"{p.name}: overrunning (the weight drives the cylinder)")
    rows.append(("total", "", "", Value(cy.total, "time", "s", 2, "cycle.total"), "", "", ""))
    return Section(
        "cycle",
        "Hydraulic cycle",
        "SAE J732",
        "Raise (rated load, bucket rolled back), lower empty and dump, each function alone at "
        "the full flow of the pumps that feed it; no leakage, valve losses or cushioning.",
        (
            Table(
                "Hydraulic cycle times (SAE J732)",
                (
                    "phase",
                    "cylinder",
                    "flow (L/min)",
                    "time (s)",
                    "load (kg)",
                    "peak pressure (MPa)",
                    "power (kW)",
                ),
                tuple(rows),
            ),
        ),
        (
            Chart(
                "Phase times with each phase's peak static pressure",
                "SAE J732",
                cy.plot().figure,
                "cycle-chart",
            ),
        ),
        tuple(limits),
    )


def _pins(machine: Loader, samples: int) -> Section:
    from excavkin.loader.pins import pin_loads

    pl = pin_loads(machine, samples)
    rows = tuple(
        (
            pl.labels.get(pin, pin),
            kn_value(load, f"pins.{pin}.load"),
            case,
            mm_value(h, f"pins.{pin}.hinge_height"),
        )
        for pin, load, case, h in pl.largest()
    )
    return Section(
        "pins",
        "Pin loads",
        "SAE J732 breakout, SAE J818 rated load",
        "Each pin's largest load over the lift, both cylinders holding, with the linkage's "
        "weight and one load on the bucket: the tilt circuit's breakout force, the rated "
        "operating capacity, or the straight tipping load.",
        (
            Table(
                "Largest pin loads over the lift",
                ("pin", "load (kN)", "case", "hinge height (mm)"),
                rows,
                note=f"{samples} lift lengths from the ground pose to full lift.",
            ),
        ),
        (
            Chart(
                "Each pin's largest load in each load case",
                "SAE J732 breakout, SAE J818 rated load",
                pl.plot().figure,
                "pins-chart",
            ),
        ),
    )


def front_lengths(machine: Loader, steps: int = FRONT_STEPS) -> np.ndarray:
    """Lift and tilt lengths of the moving front: raise, dump, roll back, lower.

    Parameters
    ----------
    machine : Loader
    steps : int
        Poses of each stage.

    Returns
    -------
    ndarray, shape (4·steps, 2)
        The bucket rolled back raised from the ground pose to full lift, dumped, rolled back
        and lowered (m).
    """
    from excavkin.loader.poses import ground_pose

    low = float(ground_pose(machine)[0])
    top, roll, dump = machine.full_lift(), machine.full_rollback(), machine.full_dump()
    t = np.linspace(0.0, 1.0, steps)
    up = np.column_stack([low + (top - low) * t, np.full(steps, roll)])
    tip = np.column_stack([np.full(steps, top), roll + (dump - roll) * t])
    return np.vstack([up, tip, tip[::-1], up[::-1]])


def _front(machine: Loader) -> Section:
    from excavkin.outputs.machine_report.parts import moving_front_section

    text = (
        "The linkage over its range: the rolled-back bucket raised from the ground pose to "
        "full lift, dumped, rolled back and lowered."
    )
    res = machine.solve(front_lengths(machine))
    return moving_front_section(
        res, text, caption="Raise, dump, roll back, lower", standard="engine kinematics"
    )


def machine_report(
    machine: Loader, *, samples: int = SAMPLES, command: str = "", progress: Progress | None = None
) -> MachineReport:
    """The loader's spec sheet, computed (module docstring): `report_sections` through
    [`family_report`][excavkin.outputs.machine_report.parts.family_report].

    Parameters
    ----------
    machine : Loader
    samples : int
        Lift lengths of the capacity, parallel-lift and pin-load sweeps (at least 2).
    command, progress
        As [`family_report`][excavkin.outputs.machine_report.parts.family_report]'s: the
        command line that made it; ``progress(done, total)`` after each section.

    Returns
    -------
    MachineReport
    """
    notes = () if machine.hydraulics is not None else ("No [hydraulics]: no cycle section.",)
    return family_report(
        machine, machine.name, FAMILY, identity(machine),
        report_sections(machine, samples=samples), notes, command=command, progress=progress,
    )  # fmt: skip


def report_sections(machine: Loader, *, samples: int = SAMPLES) -> tuple[SectionSource, ...]:
    """The loader's sections, still to compute, in the report's order.

    Parameters
    ----------
    machine : Loader
    samples : int
        Lift lengths of the capacity, parallel-lift and pin-load sweeps (at least 2).

    Returns
    -------
    tuple of SectionSource
    """
    if samples < 2:
        from excavkin.errors import InputError

        raise InputError(f"samples must be at least 2, not {samples}")
    out = [
        SectionSource("dimensions", "dimensions", lambda: _dimensions(machine)),
        SectionSource("parallel-lift", "parallel lift", lambda: _parallel_lift(machine, samples)),
        SectionSource("forces", "breakout force", lambda: _breakout(machine)),
        SectionSource("stability", "tipping and capacity", lambda: _stability(machine, samples)),
    ]
    if machine.hydraulics is not None:
        out.append(SectionSource("cycle", "hydraulic cycle", lambda: _cycle(machine)))
    out += [
        SectionSource("pins", "pin loads", lambda: _pins(machine, samples)),
        SectionSource("front", "moving front", lambda: _front(machine)),
    ]
    return tuple(out)
