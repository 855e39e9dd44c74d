"""``excavkin shovel envelope|dig|loads|stability|report|study|haul``: a rope shovel's working
range, dig, loads and spec sheet, and a rope backhoe's haul.

The wing's entry point: ``excavkin --help`` imports this module, so the heavy modules (NumPy,
the machine, pint) are imported inside the commands. Each command parses, calls the library
and writes: the result's ``summary()`` on the terminal, its ``to_frame()`` to a table, its
``plot()`` to an image.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click

from excavkin.cli.common import handle_errors, model_path
from excavkin.cli.machine_report import machine_report_options
from excavkin.cli.result_output import (
    FORCE_OPTION,
    MACHINE_ARGUMENT,
    OUTPUT_OPTION,
    check_output,
    print_result,
)
from excavkin.cli.study_options import study_options

if TYPE_CHECKING:
    from excavkin.shovel.machine import Shovel

_Command = TypeVar("_Command", bound=Callable[..., Any])


def _machine(path: str) -> Shovel:
    from excavkin.errors import InputError
    from excavkin.shovel.machine import Shovel
    from excavkin.shovel.machine_file import load_machine

    machine = load_machine(model_path(path, "machine"))
    if not isinstance(machine, Shovel):
        raise InputError(
            f"{path}: a rope backhoe (its [drag] table); these commands rate a rope shovel "
            "(its [hoist] and [crowd] tables)"
        )
    return machine


def _check(output: str | None, plot: str | None, force: bool) -> None:
    from excavkin.outputs.tables import check_target

    check_output(output, force)
    if plot:
        check_target(plot, force=force, suffixes=(".png", ".svg", ".pdf"))


def _write(result: Any, output: str | None, plot: str | None, force: bool, draw: Any) -> None:
    """Print the result's summary, write its table and its plot."""
    print_result(result, output, force)
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from excavkin.io.files import write_atomic

        handle = draw()
        fig, kind = handle.figure, Path(plot).suffix[1:].lower()
        try:  # (its target checked before the work, `_check`): written whole or not at all
            write_atomic(plot, lambda tmp: fig.savefig(tmp, dpi=120, format=kind))
        finally:
            plt.close(fig)
        click.echo(f"wrote {plot}")


_PLOT = click.option(
    "--plot", type=click.Path(dir_okay=False), help="The figure (.png, .svg or .pdf)."
)


def _dig_options(func: _Command) -> _Command:
    """The dig's options, shared by ``dig`` and ``loads`` (the soil's and the model's names are
    checked by the library: ``--help`` imports no NumPy)."""
    options = [
        click.option(
            "--samples",
            default=101,
            show_default=True,
            type=click.IntRange(min=3, max=100_000),
            help="Rows along the dig.",
        ),
        click.option(
            "--extension",
            type=click.FloatRange(min=0.0, max=1e3),
            default=None,
            help="The crowd's extension at the start (m); default 80 % of its range.",
        ),
        click.option(
            "--crowd-speed",
            type=click.FloatRange(min=-1.0, max=1.0),
            default=0.1,
            show_default=True,
            help="The handle's slide speed, a fraction of the crowd's rated speed "
            "(> 0 crowds out).",
        ),
        click.option(
            "--soil",
            default="loam",
            show_default=True,
            help="The soil: sand, loam, clay or heavy_clay (the machinery layer's categories, "
            "estimates).",
        ),
        click.option(
            "--model",
            "soil_model",
            default="mckyes",
            show_default=True,
            help="The digging-resistance model: zelenin, balovnev or mckyes.",
        ),
        click.option(
            "--depth",
            type=click.FloatRange(min=0.0, max=10.0, min_open=True),
            default=0.8,
            show_default=True,
            help="The cut's thickness (m).",
        ),
        click.option(
            "--rake",
            type=click.FloatRange(min=0.0, max=180.0, min_open=True, max_open=True),
            default=45.0,
            show_default=True,
            help="The teeth's rake to the path (degrees).",
        ),
        click.option(
            "--fill",
            type=click.FloatRange(min=0.0, max=1.0),
            default=None,
            help="A fixed payload fraction; default filling from 0 to 1 over the dig.",
        ),
    ]
    for option in reversed(options):
        func = option(func)
    return func


def _run_dig(machine: Shovel, options: dict[str, Any]) -> Any:
    import math

    from excavkin.shovel.dig import dig

    return dig(
        machine,
        samples=options["samples"],
        extension=options["extension"],
        crowd_speed=options["crowd_speed"],
        soil_name=options["soil"],
        model=options["soil_model"],
        depth=options["depth"],
        rake=math.radians(options["rake"]),
        fill=options["fill"],
    )


@click.group("shovel", context_settings={"help_option_names": ["-h", "--help"]})
def command() -> None:
    """Digging envelope, forces along a dig, boom loads, stability on the crawlers, spec sheet
    and design studies of a rope-shovel MACHINE; a rope backhoe's haul."""


@command.command("envelope")
@MACHINE_ARGUMENT
@click.option(
    "--samples",
    default=41,
    show_default=True,
    type=click.IntRange(min=3, max=301),
    help="Grid poses a side of the hoist × crowd box.",
)
@OUTPUT_OPTION
@_PLOT
@FORCE_OPTION
@handle_errors
def envelope(machine: str, samples: int, output: str | None, plot: str | None, force: bool) -> None:
    """Print the cutting height and radius, dump height and radius and the radius at floor
    level (m), each with its pose."""
    from excavkin.shovel.envelope import envelope as run

    _check(output, plot, force)
    shovel = _machine(machine)
    env = run(shovel, samples)
    _write(env, output, plot, force, lambda: env.plot(shovel))


@command.command("dig")
@MACHINE_ARGUMENT
@_dig_options
@OUTPUT_OPTION
@_PLOT
@FORCE_OPTION
@handle_errors
def dig(machine: str, output: str | None, plot: str | None, force: bool, **options: Any) -> None:
    """Print the bail pull, crowd force, motor power, tooth path and digging-resistance margin
    along a dig at the motors' rated speed; the table has every row."""
    _check(output, plot, force)
    shovel = _machine(machine)
    result = _run_dig(shovel, options)
    _write(result, output, plot, force, lambda: result.plot(shovel))


@command.command("loads")
@MACHINE_ARGUMENT
@_dig_options
@OUTPUT_OPTION
@_PLOT
@FORCE_OPTION
@handle_errors
def loads(machine: str, output: str | None, plot: str | None, force: bool, **options: Any) -> None:
    """Print the suspension-rope tension and the boom-foot, shipper-shaft and sheave loads
    (kN) along a dig; the table has every row."""
    from excavkin.shovel.loads import boom_loads

    _check(output, plot, force)
    shovel = _machine(machine)
    result = boom_loads(shovel, _run_dig(shovel, options))
    _write(result, output, plot, force, lambda: result.plot())


@command.command("study")
@click.argument("spec", metavar="STUDY")
@study_options
@handle_errors
def study(spec: str, **options: Any) -> None:
    """A design study of a rope shovel: designs sampled in the box of STUDY.toml's parameter
    bounds (its [study] names a shovel machine), each rated by the shovel's own analyses; one
    row per design to a Parquet table, streamed and resumable."""
    from excavkin.cli.commands.study import run_machine_study
    from excavkin.shovel.study import load_shovel_study

    run_machine_study(load_shovel_study, spec, **options)


@command.command("report")
@machine_report_options(41, 301, "Grid poses a side of the envelope, and rows of the dig.")
@handle_errors
def report(machine: str, samples: int, **options: Any) -> None:
    """Write a self-contained HTML spec sheet of MACHINE: digging envelope, the forces along a
    dig, the boom's loads, their charts and the moving front."""
    from excavkin.cli.machine_report import run_report
    from excavkin.shovel.report import machine_report

    run_report("shovel", machine, _machine(machine), samples, machine_report, **options)


@command.command("stability")
@MACHINE_ARGUMENT
@_dig_options
@OUTPUT_OPTION
@FORCE_OPTION
@handle_errors
def stability(machine: str, output: str | None, force: bool, **options: Any) -> None:
    """Print the least payload (t) and digging force (kN) that tip the machine on its crawlers
    along a dig, and the centre of mass's margin; the table has every row."""
    from excavkin.errors import InputError
    from excavkin.shovel.stability import stability as run

    _check(output, None, force)
    shovel = _machine(machine)
    if shovel.base is None:
        raise InputError(f"{machine}: no [base] table: the machine stands on nothing to tip")
    result = run(shovel, _run_dig(shovel, options))
    _write(result, output, None, force, None)


@command.command("haul")
@MACHINE_ARGUMENT
@click.option(
    "--samples",
    default=91,
    show_default=True,
    type=click.IntRange(min=2, max=100_000),
    help="Drag-rope lengths over its range.",
)
@click.option("--point", default="D", show_default=True, help="The bucket's point loaded.")
@click.option(
    "--load",
    nargs=2,
    type=click.FloatRange(min=-1e6, max=1e6),
    default=(0.0, 0.0),
    show_default=True,
    help="The force on the bucket, FX FY (kN, the model's frame).",
)
@OUTPUT_OPTION
@FORCE_OPTION
@handle_errors
def haul(
    machine: str,
    samples: int,
    point: str,
    load: tuple[float, float],
    output: str | None,
    force: bool,
) -> None:
    """Print a rope backhoe's bucket attitude, drag-rope pull and boom-hoist tension as its
    winch hauls the bucket in (the EO-4112: eo4112_machine); the table has every sample."""
    from excavkin.errors import InputError
    from excavkin.shovel.haul import haul as run
    from excavkin.shovel.machine import RopeBackhoe
    from excavkin.shovel.machine_file import load_machine

    _check(output, None, force)
    hoe = load_machine(model_path(machine, "machine"))
    if not isinstance(hoe, RopeBackhoe):
        raise InputError(f"{machine}: a rope shovel; haul takes a rope backhoe (its [drag] table)")
    result = run(hoe, samples=samples, point=point, force=(load[0] * 1e3, load[1] * 1e3))
    _write(result, output, None, force, None)
