"""``excavkin excavator ranges|forces|ik|stability|lift|pins|cycle|dig MACHINE.toml``: an
excavator's spec sheet; ``excavkin excavator optimize STUDY.toml``: the best design of a
machine study.

The wing's entry point: ``excavkin --help`` imports this module, so the heavy modules (NumPy,
the machine, pint) are imported inside the commands.
"""

from __future__ import annotations

import math
import sys
from typing import TYPE_CHECKING, Any

import click

from excavkin.cli.common import (
    EXIT_SAMPLES,
    check_count,
    handle_errors,
    is_number,
    model_path,
    si_value,
)
from excavkin.cli.machine_report import machine_report_options
from excavkin.cli.study_options import machine_optimize_options, study_options

if TYPE_CHECKING:
    from excavkin.excavator.machine import Machine

#: the most grid points per stroke of a sweep (101³ ≈ 10⁶ poses, about a minute and a half here)
MAX_GRID = 101
#: the most points along a dig (about ten seconds here)
MAX_DIG_POINTS = 100_000


def _machine(path: str) -> Machine:
    from excavkin.excavator.machine_file import load_machine

    return load_machine(model_path(path, "machine"))


def _save_png(fig, path: str, force: bool) -> None:  # type: ignore[no-untyped-def]
    import matplotlib.pyplot as plt

    from excavkin.outputs.tables import check_target, write_atomic

    target = check_target(path, force=force, suffixes=(".png", ".svg", ".pdf"))
    try:
        write_atomic(target, lambda tmp: fig.savefig(tmp, dpi=100, format=target.suffix[1:]))
    finally:
        plt.close(fig)  # (a command's figures are its own: none left open in the process)
    click.echo(f"wrote {target}")


@click.group("excavator", context_settings={"help_option_names": ["-h", "--help"]})
def command() -> None:
    """Working ranges, tool forces, stability, lift capacity, pin loads, cycle time, digging
    resistance and IK of an excavator MACHINE."""


@command.command("ranges")
@click.argument("machine", type=click.Path(dir_okay=False))
@click.option("--plot", "plot", type=click.Path(dir_okay=False), help="Working-range PNG.")
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    help="The figures as a table (.csv or .parquet).",
)
@click.option(
    "--envelope",
    type=click.Path(dir_okay=False),
    help="The envelope polygon as a table (x_m, y_m).",
)
@click.option("--force", is_flag=True, help="Replace output files that exist.")
@click.option("-q", "--quiet", is_flag=True, help="No progress.")
@handle_errors
def ranges(
    machine: str,
    plot: str | None,
    output: str | None,
    envelope: str | None,
    force: bool,
    quiet: bool,
) -> None:
    """Print the working-range figures (mm) and the cylinder lengths where they occur."""

    from excavkin.cli.progress import staged
    from excavkin.excavator.ranges import working_ranges
    from excavkin.outputs.tables import check_target, write_table

    for p in (output, envelope):
        if p:
            check_target(p, force=force, suffixes=(".csv", ".parquet"))
    m = _machine(machine)
    with staged("working ranges", 1, quiet=quiet) as next_stage:
        wr = working_ranges(m, progress=next_stage())
    click.echo(wr.summary())
    if output:
        click.echo(f"wrote {write_table(wr.to_frame(), output, force=force)}")
    if envelope:
        click.echo(f"wrote {write_table(wr.envelope_frame(), envelope, force=force)}")
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        from excavkin.excavator.plots import plot_working_range

        _save_png(plot_working_range(m, wr).figure, plot, force)


@command.command("forces")
@click.argument("machine", type=click.Path(dir_okay=False))
@click.option(
    "--samples", default=31, show_default=True, help="Grid points per stroke of the sweep."
)
@click.option("--no-gravity", is_flag=True, help="Leave the weight of the front out of the sweep.")
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    help="The rated forces and the sweep's maxima as a table (.csv or .parquet).",
)
@click.option(
    "--map",
    "map_prefix",
    type=click.Path(dir_okay=False),
    help="Write force-map PNGs PREFIX-arm.png and PREFIX-bucket.png.",
)
@click.option("--force", is_flag=True, help="Replace output files that exist.")
@click.option("-q", "--quiet", is_flag=True, help="No progress.")
@handle_errors
def forces(
    machine: str,
    samples: int,
    no_gravity: bool,
    output: str | None,
    map_prefix: str | None,
    force: bool,
    quiet: bool,
) -> None:
    """Print the rated ISO 6015 (lip) and SAE J1179 (tooth tip) tool forces, and the largest
    over a sweep of the strokes."""
    from excavkin.cli.progress import staged
    from excavkin.excavator.force_survey import STANDARDS, WORKING, tool_force_survey
    from excavkin.outputs.tables import check_target, write_table

    check_count(samples, "--samples", least=2, most=MAX_GRID, samples=samples**3,
                bytes_per_sample=8_000, what="poses of the stroke sweep")  # fmt: skip
    if output:
        check_target(output, force=force, suffixes=(".csv", ".parquet"))
    if map_prefix:
        for working in WORKING:
            check_target(f"{map_prefix}-{working}.png", force=force, suffixes=(".png",))
    m = _machine(machine)
    with staged("rated forces", len(STANDARDS) * len(WORKING), quiet=quiet) as next_stage:
        survey = tool_force_survey(m, samples, gravity=not no_gravity, stages=next_stage)
    click.echo(survey.summary())
    if output:
        click.echo(f"wrote {write_table(survey.to_frame(), output, force=force)}")
    if map_prefix:
        import matplotlib

        matplotlib.use("Agg")
        for name, handle in survey.plot_maps().items():
            _save_png(handle.figure, f"{map_prefix}-{name}.png", force)


@command.command("ik")
@click.argument("machine", type=click.Path(dir_okay=False))
@click.option("--x", "x", required=True, help="Tip reach from the swing axis, e.g. 7m.")
@click.option("--y", "y", required=True, help="Tip height above the ground line, e.g. -1.5m.")
@click.option(
    "--angle",
    "angle",
    default="-90deg",
    show_default=True,
    help="Bucket angle: direction of bucket pin → tip, CCW from +x.",
)
@handle_errors
def ik(machine: str, x: str, y: str, angle: str) -> None:
    """Cylinder lengths that put the tooth tip at (X, Y) with the given bucket angle (exit
    status 3 when no branch reaches it within the strokes)."""
    from excavkin.excavator.ik import tip_target

    m = _machine(machine)
    reach, height = si_value(x, "length", "--x"), si_value(y, "length", "--y")
    target = tip_target(m, reach, height, si_value(angle, "angle", "--angle"))
    click.echo(target.summary())
    if not target.valid:
        sys.exit(EXIT_SAMPLES)  # as a sample that does not solve


def _swing_option(text: str) -> float | str:
    """``front``, ``side`` or an angle such as ``30deg``."""
    if text in ("front", "side"):
        return text
    return si_value(text, "angle", "--swing")


@command.command("stability")
@click.argument("machine", type=click.Path(dir_okay=False))
@click.option(
    "--samples", default=31, show_default=True, help="Grid points per stroke of the sweep."
)
@click.option(
    "--swing",
    default="front",
    show_default=True,
    help="Where the front points: front (along the tracks), side, or an angle such as 30deg.",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    help="The capped rated forces as a table (.csv or .parquet).",
)
@click.option(
    "--map",
    "map_prefix",
    type=click.Path(dir_okay=False),
    help="Write PREFIX-tipping-front.png, PREFIX-tipping-side.png (tipping load at the bucket "
    "pin), PREFIX-limits-arm.png, PREFIX-limits-bucket.png (which limit binds) and "
    "PREFIX-support.png (the support in plan and its tipping lines).",
)
@click.option("--force", is_flag=True, help="Replace output files that exist.")
@click.option("-q", "--quiet", is_flag=True, help="No progress.")
@handle_errors
def stability(
    machine: str,
    samples: int,
    swing: str,
    output: str | None,
    map_prefix: str | None,
    force: bool,
    quiet: bool,
) -> None:
    """Print tipping lines, the rated tool forces capped by tipping and slipping (ISO 6015
    §4.5), and the stability over a sweep of the strokes."""
    from excavkin.cli.progress import staged
    from excavkin.excavator.stability_survey import MAPS, pin_grid, stability_survey
    from excavkin.outputs.tables import check_target, write_table

    check_count(samples, "--samples", least=2, most=MAX_GRID,
                samples=samples**3 + math.prod(pin_grid(samples)), bytes_per_sample=10_000,
                what="poses of the stroke sweeps")  # fmt: skip
    sw = _swing_option(swing)
    if output:
        check_target(output, force=force, suffixes=(".csv", ".parquet"))
    if map_prefix:
        for name in MAPS:
            check_target(f"{map_prefix}-{name}.png", force=force, suffixes=(".png",))
    m = _machine(machine)
    with staged("rated forces", 4, quiet=quiet) as next_stage:
        survey = stability_survey(m, samples, swing=sw, stages=next_stage)  # type: ignore[arg-type]
    click.echo(survey.summary())
    if output:
        click.echo(f"wrote {write_table(survey.to_frame(), output, force=force)}")
    if map_prefix:
        import matplotlib

        matplotlib.use("Agg")
        for name, handle in survey.plot_maps().items():
            _save_png(handle.figure, f"{map_prefix}-{name}.png", force)


@command.command("lift")
@click.argument("machine", type=click.Path(dir_okay=False))
@click.option(
    "--step", default="1.5m", show_default=True, help="Grid step of load radius and height."
)
@click.option(
    "--pressure",
    type=click.Choice(["working", "relief"]),
    default="working",
    show_default=True,
    help="The lifting (boom) cylinder's pressure for the hydraulic capacity.",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    help="The table, one row per height, radius and side (.csv or .parquet).",
)
@click.option("--plot", "plot", type=click.Path(dir_okay=False), help="Lift-chart PNG.")
@click.option("--force", is_flag=True, help="Replace output files that exist.")
@handle_errors
def lift(
    machine: str, step: str, pressure: str, output: str | None, plot: str | None, force: bool
) -> None:
    """Print the rated lift capacity (ISO 10567, kg) over load radius × height, over the front
    and over the side."""
    from excavkin.excavator.lift import lift_table
    from excavkin.outputs.tables import check_target, write_table

    dr = si_value(step, "length", "--step")
    if not 0.1 <= dr <= 10.0:
        raise click.BadParameter("between 0.1 m and 10 m", param_hint="--step")
    if output:
        check_target(output, force=force, suffixes=(".csv", ".parquet"))
    if plot:
        check_target(plot, force=force, suffixes=(".png", ".svg", ".pdf"))
    m = _machine(machine)
    t = lift_table(m, step=dr, pressure=pressure)  # type: ignore[arg-type]
    click.echo(t.summary())
    if output:
        click.echo(f"wrote {write_table(t.to_frame(), output, force=force)}")
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        from excavkin.excavator.stability_plots import plot_lift_chart

        _save_png(plot_lift_chart(m, t).figure, plot, force)


@command.command("pins")
@click.argument("machine", type=click.Path(dir_okay=False))
@click.option(
    "--case",
    "cases",
    type=click.Choice(["bucket", "arm", "lift"]),
    multiple=True,
    help="Load case (repeat for several; default all): the bucket- or arm-cylinder tool force, "
    "or a load hanging at the lift point.",
)
@click.option(
    "--load",
    "load",
    help="Lift load as a mass, e.g. 2t (default: the hydraulic lift capacity at each pose).",
)
@click.option(
    "--at",
    type=click.Choice(["lip", "tip"]),
    default="lip",
    show_default=True,
    help="Tool point: the lip (ISO 6015) or the tooth tip (SAE J1179).",
)
@click.option("--no-gravity", is_flag=True, help="Leave the weight of the front out.")
@click.option(
    "--samples", default=31, show_default=True, help="Grid points per stroke of the sweep."
)
@click.option(
    "--plot", "plot", type=click.Path(dir_okay=False), help="Bar chart PNG of the largest loads."
)
@click.option(
    "--map",
    "map_prefix",
    type=click.Path(dir_okay=False),
    help="Write pin-load heat maps PREFIX-<case>.png, one per case.",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    help="The largest loads as a table (.csv or .parquet).",
)
@click.option("--force", is_flag=True, help="Replace output files that exist.")
@click.option("-q", "--quiet", is_flag=True, help="No progress.")
@handle_errors
def pins(
    machine: str,
    cases: tuple[str, ...],
    load: str | None,
    at: str,
    no_gravity: bool,
    samples: int,
    plot: str | None,
    map_prefix: str | None,
    output: str | None,
    force: bool,
    quiet: bool,
) -> None:
    """Print the largest load on each pin and in each cylinder over the working range, the load
    case and the pose where it occurs."""
    from excavkin.cli.progress import staged
    from excavkin.excavator.pin_loads import CASES, lift_grid, working_range_pin_loads
    from excavkin.outputs.tables import check_target, write_table

    check_count(samples, "--samples", least=2, most=MAX_GRID,
                samples=max(samples**3, math.prod(lift_grid(samples))),
                bytes_per_sample=10_000, what="poses of the stroke sweep")  # fmt: skip
    chosen = [c for c in CASES if c in cases] if cases else list(CASES)
    mass = None
    if load is not None:
        if "lift" not in chosen:
            raise click.BadParameter("applies to the lift case only", param_hint="--load")
        mass = si_value(load, "mass", "--load")
        if not mass >= 0.0:
            raise click.BadParameter(f"{load!r} is negative", param_hint="--load")
    if output:
        check_target(output, force=force, suffixes=(".csv", ".parquet"))
    if plot:
        check_target(plot, force=force, suffixes=(".png", ".svg", ".pdf"))
    if map_prefix:
        for case in chosen:
            check_target(f"{map_prefix}-{case}.png", force=force, suffixes=(".png",))
    m = _machine(machine)
    with staged("pin loads", len(chosen), quiet=quiet) as next_stage:
        result = working_range_pin_loads(
            m, chosen, samples=samples, mass=mass, at=at, gravity=not no_gravity,  # type: ignore[arg-type]
            stages=next_stage,
        )  # fmt: skip
    click.echo(result.summary())
    if output:
        click.echo(f"wrote {write_table(result.to_frame(), output, force=force)}")
    if plot or map_prefix:
        import matplotlib

        matplotlib.use("Agg")
        if plot:
            _save_png(result.plot().figure, plot, force)
        if map_prefix:
            for name, handle in result.plot_maps().items():
                _save_png(handle.figure, f"{map_prefix}-{name}.png", force)


@command.command("cycle")
@click.argument("machine", type=click.Path(dir_okay=False))
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    help="Strokes, cycle and buckling checks as a table (.csv or .parquet).",
)
@click.option(
    "--plot",
    type=click.Path(dir_okay=False),
    help="Power and inlet pressure along the cycle (.png, .svg or .pdf).",
)
@click.option("--force", is_flag=True, help="Replace an output file that exists.")
@click.option("-q", "--quiet", is_flag=True, help="No progress.")
@handle_errors
def cycle(machine: str, output: str | None, plot: str | None, force: bool, quiet: bool) -> None:
    """Print cylinder speeds and stroke times from the pump flows, a dig–swing–dump cycle
    estimate with the hydraulic power of each phase, and the buckling check of each cylinder
    at the rated forces."""
    from excavkin.cli.progress import staged
    from excavkin.excavator.cycle_sheet import hydraulic_cycle
    from excavkin.outputs.tables import check_target, write_table

    if output:
        check_target(output, force=force, suffixes=(".csv", ".parquet"))
    if plot:
        check_target(plot, force=force, suffixes=(".png", ".svg", ".pdf"))
    m = _machine(machine)
    with staged("rated forces", 2, quiet=quiet) as next_stage:
        sheet = hydraulic_cycle(m, stages=next_stage)
    text = sheet.sections()
    click.echo("\n".join(text[k] for k in ("strokes", "cycle", "power")))
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        _save_png(sheet.plot().figure, plot, force)
    click.echo(text["buckling"])
    if output:
        click.echo(f"wrote {write_table(sheet.to_frame(), output, force=force)}")


#: ``--param`` keys of ``excavator dig``: kind of quantity, and whether soil or tool
DIG_PARAMS: dict[str, tuple[str, str]] = {
    "density": ("density", "soil"),
    "friction_angle": ("angle", "soil"),
    "cohesion": ("pressure", "soil"),
    "metal_friction": ("angle", "soil"),
    "adhesion": ("pressure", "soil"),
    "blows": ("dimensionless", "soil"),
    "surcharge": ("pressure", "soil"),
    "teeth": ("dimensionless", "tool"),
    "walls": ("dimensionless", "tool"),
    "normal_ratio": ("dimensionless", "tool"),
    "edge_thickness": ("length", "tool"),
    "edge_angle": ("angle", "tool"),
    "wall_thickness": ("length", "tool"),
    "wall_length": ("length", "tool"),
}


#: a unit to show in the message for a --param value given without one
_UNIT_EXAMPLE = {"density": "kg/m^3", "angle": "deg", "pressure": "kPa", "length": "m"}


def _lengths_option(text: str, what: str) -> list[float]:
    """``"2639,2170,2205 mm"`` or ``"2.6 m,2.2 m,2.2 m"`` → three lengths (m)."""
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != 3:
        raise click.BadParameter(
            f"three cylinder lengths (boom, arm, bucket) separated by commas, not {text!r}",
            param_hint=what,
        )
    unit = ""
    head = parts[-1].split()
    if len(head) == 2:  # one unit after the last number applies to all three
        unit = head[1]
    out = []
    for p in parts:
        q = p if len(p.split()) == 2 else f"{p} {unit}".strip()
        if not unit and len(p.split()) == 1:
            raise click.BadParameter(
                f"{p!r} has no unit (say '... mm' or '... m')", param_hint=what
            )
        out.append(si_value(q, "length", what, hint=False))
    return out


@command.command("dig")
@click.argument("machine", type=click.Path(dir_okay=False))
@click.option(
    "--model",
    type=click.Choice(["zelenin", "balovnev", "mckyes"]),
    default="balovnev",
    show_default=True,
    help="Soil-cutting model.",
)
@click.option("--soil", "soil_name", default="loam", show_default=True, help="Soil category.")
@click.option(
    "--param",
    "params",
    multiple=True,
    metavar="KEY=VALUE",
    help="Replace a soil or tool property, with its unit: 'cohesion=20 kPa', 'blows=9', "
    "'friction_angle=28 deg', 'wall_length=0.9 m'; teeth and walls are Zelenin's factors "
    "(1 for none), not counts (repeatable).",
)
@click.option("--width", required=True, help="Cutting width of the bucket, e.g. '1.2 m'.")
@click.option("--from", "start", help="Start cylinder lengths: 'boom,arm,bucket mm'.")
@click.option("--to", "end", help="End cylinder lengths: 'boom,arm,bucket mm'.")
@click.option(
    "--depth",
    default="0.5 m",
    show_default=True,
    help="Deepest point of the default dig (without --from/--to).",
)
@click.option("--samples", default=41, show_default=True, help="Points along the dig.")
@click.option("--law", default=None, help="Motion law spacing the points in time (cubic, 345, …).")
@click.option(
    "--at",
    type=click.Choice(["lip", "tip"]),
    default="lip",
    show_default=True,
    help="Tool point: the lip (ISO 6015) or the tooth tip.",
)
@click.option("--swing", default="front", show_default=True, help="front, side or an angle.")
@click.option("--plot", "plot", type=click.Path(dir_okay=False), help="Dig PNG.")
@click.option(
    "-o", "--output", type=click.Path(dir_okay=False), help="The dig as a table (.csv/.parquet)."
)
@click.option("--force", is_flag=True, help="Replace output files that exist.")
@handle_errors
def dig(
    machine: str,
    model: str,
    soil_name: str,
    params: tuple[str, ...],
    width: str,
    start: str | None,
    end: str | None,
    depth: str,
    samples: int,
    law: str | None,
    at: str,
    swing: str,
    plot: str | None,
    output: str | None,
    force: bool,
) -> None:
    """Soil resistance along a dig against the force the machine can exert: margin and the
    point where the dig stalls."""

    from excavkin.errors import InputError
    from excavkin.excavator.dig import default_dig, dig_path
    from excavkin.excavator.dig import dig as run_dig
    from excavkin.excavator.soil import SOILS, Tool, soil
    from excavkin.outputs.tables import check_target, write_table

    check_count(samples, "--samples", least=3, most=MAX_DIG_POINTS, bytes_per_sample=5_000,
                what="points along the dig")  # fmt: skip
    if (start is None) != (end is None):
        raise click.BadParameter("give both --from and --to, or neither", param_hint="--from/--to")
    if soil_name not in SOILS:
        raise click.BadParameter(
            f"unknown soil {soil_name!r}; known: {', '.join(SOILS)}", param_hint="--soil"
        )
    if output:
        check_target(output, force=force, suffixes=(".csv", ".parquet"))
    if plot:
        check_target(plot, force=force, suffixes=(".png", ".svg", ".pdf"))
    soil_kw: dict[str, float] = {}
    tool_kw: dict[str, float] = {}
    for item in params:
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or key not in DIG_PARAMS:
            raise click.BadParameter(
                f"{item!r}: KEY=VALUE with KEY one of {', '.join(DIG_PARAMS)}",
                param_hint="--param",
            )
        kind, target = DIG_PARAMS[key]
        if kind != "dimensionless" and is_number(value):
            raise click.BadParameter(
                f"{key}={value.strip()} has no unit; give it with its unit, e.g. "
                f"'{key}={value.strip()} {_UNIT_EXAMPLE[kind]}'",
                param_hint="--param",
            )
        v = si_value(value, kind, f"--param {key}", hint=kind != "dimensionless")
        (soil_kw if target == "soil" else tool_kw)[key] = v
    tool_width = si_value(width, "length", "--width")
    try:
        s = soil(soil_name, **soil_kw)
        tool = Tool(tool_width, **tool_kw)
    except InputError as exc:
        given = "--param" if soil_kw or tool_kw else "--width"
        raise InputError(f"{given}: {exc}") from None
    sw: float | str = swing if swing in ("front", "side") else si_value(swing, "angle", "--swing")
    m = _machine(machine)
    if law is not None:
        from excavkin.motion import get_law

        try:
            get_law(law, 1.0, 1.0)
        except (ValueError, TypeError) as exc:
            raise InputError(f"--law: {exc}") from None
    if start is not None and end is not None:
        first, last = _lengths_option(start, "--from"), _lengths_option(end, "--to")
        try:
            L = dig_path(m, first, last, samples, law=law)
        except InputError as exc:
            raise InputError(f"--from {start!r} --to {end!r}: {exc}") from None
    else:
        deepest = si_value(depth, "length", "--depth")
        try:
            L = default_dig(m, samples, depth=deepest, law=law)
        except InputError as exc:
            raise InputError(f"--depth {depth!r}: {exc}") from None
    d = run_dig(m, L, s, tool, model, at=at, swing=sw)  # type: ignore[arg-type]
    click.echo(d.summary())
    if output:
        click.echo(f"wrote {write_table(d.to_frame(), output, force=force)}")
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        from excavkin.excavator.dig_plots import plot_dig

        _save_png(plot_dig(m, d).figure, plot, force)


@command.command("study")
@click.argument("spec", metavar="STUDY")
@study_options
@handle_errors
def study(spec: str, **options: Any) -> None:
    """A design study of a machine: designs sampled in the box of STUDY.toml's parameter
    bounds (its [study] names a machine), each at every pose (cylinder lengths) in one batch;
    one row per design to a Parquet table, streamed and resumable."""
    from excavkin.cli.commands.study import run_machine_study
    from excavkin.excavator.study import load_machine_study

    run_machine_study(load_machine_study, spec, **options)


@command.command("report")
@machine_report_options(21, 51, "Grid points per stroke of the force-map and pin-load sweeps.")
@handle_errors
def report(machine: str, samples: int, **options: Any) -> None:
    """Write a self-contained HTML spec sheet of MACHINE: working ranges, tool forces,
    stability and lift capacity, pin loads, cycle, their charts and the moving front."""
    from excavkin.cli.machine_report import run_report
    from excavkin.excavator.report import machine_report

    run_report("excavator", machine, _machine(machine), samples, machine_report, **options)


@command.command("optimize")
@click.argument("study", type=click.Path(dir_okay=False))
@machine_optimize_options
@handle_errors
def optimize(study: str, **options: Any) -> None:
    """The best design of a STUDY file that names a machine (``machine = ...`` in [study]):
    its [optimize] objective over its parameter box under its constraints, every population or
    gradient solved as one batch of designs."""
    from excavkin.cli.commands.optimize import optimize_machine_study
    from excavkin.excavator.study import load_machine_study

    optimize_machine_study(load_machine_study(model_path(study, "study")), **options)
