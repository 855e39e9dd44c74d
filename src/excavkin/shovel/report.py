"""A rope shovel's machine report: the sections the core's report lays out.

Each section runs one of the wing's analyses and turns its result into tables (every number a
[`Value`][excavkin.outputs.machine_report.content.Value] keyed for reading back), the limits
that bind it, named, and its ``plot()``:

* **digging envelope** ([`envelope`][excavkin.shovel.envelope.envelope]);
* **along a dig**: bail pull, crowd force, motor power and the digging-resistance margin
  ([`dig`][excavkin.shovel.dig.dig], with its defaults);
* **boom loads** along the dig ([`boom_loads`][excavkin.shovel.loads.boom_loads]);
* **the moving front** along the dig, as an interactive figure.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from excavkin.outputs.machine_report import collect, kg_value, kn_value
from excavkin.outputs.machine_report.content import (
    Chart,
    MachineReport,
    Section,
    SectionSource,
    Table,
    Value,
)
from excavkin.shovel.machine import Shovel

if TYPE_CHECKING:
    from excavkin.outputs.machine_report import Cell, Progress
    from excavkin.shovel.dig import Dig

__all__ = ["FAMILY", "machine_report", "report_sections"]

#: the family's name in the report
FAMILY = "rope shovel"

#: grid poses a side of the envelope, and rows of the dig, unless asked otherwise
SAMPLES = 41


def _m(v: float, key: str) -> Value:
    return Value(v, "", "m", 2, key)


def identity(machine: Shovel) -> tuple[tuple[str, Cell], ...]:
    """What the machine is: its drives, dipper and masses.

    Parameters
    ----------
    machine : Shovel

    Returns
    -------
    tuple of (str, Cell)
        Each figure's name and value, in the order the report lists them.
    """
    h, c, d = machine.hoist, machine.crowd, machine.dipper
    rows: list[tuple[str, Cell]] = [
        ("front (boom, saddle, handle, dipper)", kg_value(machine.front_mass, "mass.front")),
        ("rated payload", kg_value(d.payload, "dipper.payload")),
        ("dipper rated capacity", Value(d.capacity, "", "m^3", 1, "dipper.capacity")),
        ("hoist: motors", f"{h.motor.count} × {h.motor.torque / 1e3:.1f} kN·m"),
        ("hoist: bail pull at rated torque", kn_value(h.pull, "hoist.pull")),
        ("hoist: rope speed at rated speed", Value(h.speed, "velocity", "m/s", 2, "hoist.speed")),
        ("hoist: gear ratio, drum radius", f"{h.gear_ratio:g}, {h.drum_radius:g} m"),
        ("crowd: force at rated torque", kn_value(c.force, "crowd.force")),
        ("crowd: speed at rated speed", Value(c.speed, "velocity", "m/s", 2, "crowd.speed")),
        ("crowd: gear ratio, pinion radius", f"{c.gear_ratio:g}, {c.pinion_radius:g} m"),
    ]
    if machine.base is not None:
        rows.append(
            ("base (upper, counterweight, crawlers)", kg_value(machine.base.mass, "mass.base"))
        )
    return tuple(rows)


def _envelope(machine: Shovel, samples: int) -> Section:
    from excavkin.shovel.envelope import envelope

    env = envelope(machine, samples)
    rows = tuple(
        (
            f.name,
            _m(f.value, f"envelope.{f.name}"),
            _m(f.length, f"envelope.{f.name}.hoist"),
            _m(f.extension, f"envelope.{f.name}.crowd"),
            f.definition,
        )
        for f in env.figures
    )
    return Section(
        "dimensions",
        "Digging envelope",
        "",
        "Each figure is the greatest over the box of the hoist rope's lengths and the crowd's "
        "extensions, solved by the engine: a grid, then windows about the best pose down to "
        "1 µm.",
        (
            Table(
                "Digging envelope",
                ("figure", "value (m)", "hoist rope (m)", "crowd (m)", "definition"),
                rows,
                note=f"{samples} × {samples} grid poses over the box.",
            ),
        ),
        (
            Chart(
                "Working range: the tooth tip over the box",
                "engine kinematics",
                env.plot(machine).figure,
                "envelope-chart",
            ),
        ),  # fmt: skip
    )


def _dig(machine: Shovel, d: Dig) -> Section:
    ok = d.ok
    rows: list[tuple[Cell, ...]] = []
    if ok.any():
        rows = [
            ("largest bail pull", kn_value(float(np.max(d.bail_pull[ok])), "dig.bail_pull")),
            ("crowd force, most out", kn_value(float(np.max(d.crowd_force[ok])), "dig.crowd_out")),
            ("crowd force, most in", kn_value(float(np.min(d.crowd_force[ok])), "dig.crowd_in")),
            ("largest hoist power",
             Value(float(np.max(d.hoist_power[ok])), "power", "kW", 0, "dig.hoist_power")),
            ("least digging-resistance margin",
             Value(float(np.min(d.margin[ok])), "", "×", 2, "dig.margin")),
        ]  # fmt: skip
    bad = np.flatnonzero(~ok)
    limits = tuple(
        f"{int(np.sum(d.status == s))} rows: {s}" for s in dict.fromkeys(d.status[bad].tolist())
    )
    return Section(
        "forces",
        "Along a dig",
        "",
        f"From the floor, the hoist hauling in at its rated speed and the crowd at a tenth of "
        f"its: the general kinetostatics holds the front, its payload and the digging "
        f"resistance ({d.soil}). The margin is the largest multiple of the resistance the "
        "motors overcome at their rated torque. A rope never pushes: a row where the hoist "
        "would have to is a status, never ok.",
        (
            Table(
                "Along a dig",
                (
                    "figure",
                    "value",
                ),
                tuple((r[0], r[1]) for r in rows),
                note=f"{d.time.size} rows over {d.time[-1]:.2f} s.",
            ),
        ),  # fmt: skip
        (
            Chart(
                "Bail pull, crowd force and margin over the tooth's height",
                "engine kinetostatics",
                d.plot(machine).figure,
                "dig-chart",
            ),
        ),  # fmt: skip
        limits,
    )


def _loads(machine: Shovel, d: Dig) -> Section:
    from excavkin.shovel.loads import boom_loads

    lb = boom_loads(machine, d)
    ok = lb.ok
    rows: list[tuple[Cell, ...]] = []
    if ok.any():
        for name, mag, key in (
            ("suspension ropes", lb.suspension, "suspension"),
            ("boom-foot pin", np.hypot(*lb.boom_foot.T), "boom_foot"),
            ("shipper shaft", np.hypot(*lb.shipper_shaft.T), "shipper_shaft"),
            ("boom-point sheave", np.hypot(*lb.sheave.T), "sheave"),
        ):
            k = int(np.flatnonzero(ok)[np.argmax(mag[ok])])
            rows.append((name, kn_value(float(mag[k]), f"loads.{key}"),
                         _m(float(lb.teeth[k, 1]), f"loads.{key}.height")))  # fmt: skip
    return Section(
        "pins",
        "Boom loads",
        "",
        "The boom's equilibrium under the saddle at the shipper shaft and the hoist rope's wrap "
        "on the boom-point sheave, along the dig.",
        (
            Table(
                "Largest boom loads along the dig",
                ("load", "largest (kN)", "tooth height (m)"),
                tuple(rows),
            ),
        ),  # fmt: skip
        (
            Chart(
                "The boom's loads over the tooth's height",
                "engine kinetostatics",
                lb.plot().figure,
                "loads-chart",
            ),
        ),  # fmt: skip
    )


def _front(machine: Shovel, d: Dig) -> Section:
    from excavkin.outputs.machine_report.parts import moving_front_section

    res = d.forces.kinematics
    return moving_front_section(
        res,
        "The front along the dig: the teeth from the floor up through the bank.",
        caption="Along the dig",
        standard="engine kinematics",
    )


def report_sections(machine: Shovel, *, samples: int = SAMPLES) -> tuple[SectionSource, ...]:
    """The shovel's sections, still to compute, in the report's order.

    Parameters
    ----------
    machine : Shovel
    samples : int
        Grid poses a side of the envelope, and rows of the dig (at least 3).

    Returns
    -------
    tuple of SectionSource
    """
    from excavkin.shovel.dig import dig

    if samples < 3:
        from excavkin.errors import InputError

        raise InputError(f"samples must be at least 3, not {samples}")
    cache: dict[str, Dig] = {}

    def dug() -> Dig:
        if "dig" not in cache:
            cache["dig"] = dig(machine, samples=samples)
        return cache["dig"]

    return (
        SectionSource("dimensions", "digging envelope", lambda: _envelope(machine, samples)),
        SectionSource("forces", "along a dig", lambda: _dig(machine, dug())),
        SectionSource("pins", "boom loads", lambda: _loads(machine, dug())),
        SectionSource("front", "moving front", lambda: _front(machine, dug())),
    )


def machine_report(
    machine: Shovel, *, samples: int = SAMPLES, command: str = "", progress: Progress | None = None
) -> MachineReport:
    """The shovel's spec sheet, computed (module docstring).

    Parameters
    ----------
    machine : Shovel
    samples : int
        Grid poses a side of the envelope, and rows of the dig (at least 3).
    command : str
        The command line that made it, for the record.
    progress : callable, optional
        ``progress(done, total)`` after each section.

    Returns
    -------
    MachineReport
    """
    return MachineReport(
        machine.name,
        FAMILY,
        str(machine.source or ""),
        identity(machine),
        collect(report_sections(machine, samples=samples), progress),
        command,
        ("Every figure of the built-in machine is an estimate (see its machine file).",),
    )
