"""``excavkin loader ranges|breakout|tipping|capacity|cycle|pins MACHINE``: a loader's spec sheet.

The wing's entry point: ``excavkin --help`` imports this module, so the heavy modules (NumPy,
the machine, pint) are imported inside the commands. Each command parses, calls the library
and writes: the result's ``summary()`` on the terminal, its ``to_frame()`` to a table.
"""

from __future__ import annotations

from collections.abc import Callable
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
from excavkin.cli.study_options import machine_optimize_options, study_options

if TYPE_CHECKING:
    from excavkin.loader.machine import Loader


def _machine(path: str) -> Loader:
    from excavkin.loader.machine_file import load_machine

    return load_machine(model_path(path, "machine"))


_Command = TypeVar("_Command", bound=Callable[..., Any])


def _samples(default: int, what: str) -> Callable[[_Command], _Command]:
    """``--samples``: how many lift lengths a command takes (``what`` they are)."""
    return click.option(
        "--samples",
        default=default,
        show_default=True,
        type=click.IntRange(min=2, max=100_000),
        help=what,
    )


@click.group("loader", context_settings={"help_option_names": ["-h", "--help"]})
def command() -> None:
    """Dimensions, breakout force, static tipping load, lift capacity, parallel lift,
    hydraulic cycle and pin loads of a wheel-loader MACHINE."""


@command.command("ranges")
@MACHINE_ARGUMENT
@OUTPUT_OPTION
@FORCE_OPTION
@handle_errors
def ranges(machine: str, output: str | None, force: bool) -> None:
    """Print the SAE J732 / ISO 7131 dimensions (mm, degrees) and the poses they are taken at."""
    from excavkin.loader.dimensions import dimensions

    check_output(output, force)
    print_result(dimensions(_machine(machine)), output, force)


@command.command("breakout")
@MACHINE_ARGUMENT
@OUTPUT_OPTION
@FORCE_OPTION
@handle_errors
def breakout(machine: str, output: str | None, force: bool) -> None:
    """Print the SAE J732 / ISO 14397-2 breakout forces (kN) and what limits each."""
    from excavkin.loader.breakout import breakout as rate

    check_output(output, force)
    print_result(rate(_machine(machine)), output, force)


@command.command("tipping")
@MACHINE_ARGUMENT
@OUTPUT_OPTION
@FORCE_OPTION
@handle_errors
def tipping(machine: str, output: str | None, force: bool) -> None:
    """Print the static tipping loads, straight and at full turn, and the rated operating
    capacity (kg)."""
    from excavkin.loader.tipping import static_tipping

    check_output(output, force)
    print_result(static_tipping(_machine(machine)), output, force)


@command.command("capacity")
@MACHINE_ARGUMENT
@_samples(101, "Lift lengths over the stroke.")
@OUTPUT_OPTION
@FORCE_OPTION
@handle_errors
def capacity(machine: str, samples: int, output: str | None, force: bool) -> None:
    """Print the lift capacity to full height and the least rollback capacity (kg); the table
    has both at every lift length."""
    from excavkin.loader.capacity import capacity as rate

    check_output(output, force)
    print_result(rate(_machine(machine), samples), output, force)


@command.command("cycle")
@MACHINE_ARGUMENT
@click.option(
    "--load",
    type=click.FloatRange(min=0.0),
    default=None,
    help="The mass raised (kg); default the rated operating capacity.",
)
@OUTPUT_OPTION
@FORCE_OPTION
@handle_errors
def cycle(machine: str, load: float | None, output: str | None, force: bool) -> None:
    """Print the SAE J732 raise, lower-empty and dump times (s) at the pumps' full flow, with
    each phase's static pressure (MPa) and hydraulic power (kW)."""
    from excavkin.loader.cycle import cycle as run

    check_output(output, force)
    print_result(run(_machine(machine), load), output, force)


@command.command("pins")
@MACHINE_ARGUMENT
@_samples(21, "Lift lengths from the ground pose to full lift.")
@OUTPUT_OPTION
@FORCE_OPTION
@handle_errors
def pins(machine: str, samples: int, output: str | None, force: bool) -> None:
    """Print each pin's largest load (kN) over the lift in the breakout, rated-load and tipping
    cases, with its case and height; the table has every pin at every lift length."""
    from excavkin.loader.pins import pin_loads

    check_output(output, force)
    print_result(pin_loads(_machine(machine), samples), output, force)


@command.command("lift")
@MACHINE_ARGUMENT
@_samples(101, "Lift lengths from the ground pose to full lift.")
@OUTPUT_OPTION
@FORCE_OPTION
@handle_errors
def lift(machine: str, samples: int, output: str | None, force: bool) -> None:
    """Print the bucket's angle change over the lift with the tilt cylinder held at the length
    that levels it on the ground (degrees); the table has the angle at every lift length."""
    from excavkin.loader.parallel_lift import parallel_lift

    check_output(output, force)
    print_result(parallel_lift(_machine(machine), samples), output, force)


@command.command("optimize")
@click.argument("study", type=click.Path(dir_okay=False))
@machine_optimize_options
@handle_errors
def optimize(study: str, **options: Any) -> None:
    """The best design of a STUDY file that names a loader machine (``machine = ...`` in
    [study]): its [optimize] objective over its parameter box under its constraints."""
    from excavkin.cli.commands.optimize import optimize_machine_study
    from excavkin.loader.study import load_loader_study

    optimize_machine_study(load_loader_study(model_path(study, "study")), **options)


@command.command("report")
@machine_report_options(
    41, 1001, "Lift lengths of the capacity, parallel-lift and pin-load sweeps."
)
@handle_errors
def report(machine: str, samples: int, **options: Any) -> None:
    """Write a self-contained HTML spec sheet of MACHINE: dimensions, breakout force, tipping
    loads and capacity, cycle, pin loads, their charts and the moving front."""
    from excavkin.cli.machine_report import run_report
    from excavkin.loader.report import machine_report

    run_report("loader", machine, _machine(machine), samples, machine_report, **options)


@command.command("study")
@click.argument("spec", metavar="STUDY")
@study_options
@handle_errors
def study(spec: str, **options: Any) -> None:
    """A design study of a loader: designs sampled in the box of STUDY.toml's parameter bounds
    (its [study] names a loader machine), each rated by the loader's own analyses; one row per
    design to a Parquet table, streamed and resumable."""
    from excavkin.cli.commands.study import run_machine_study
    from excavkin.loader.study import load_loader_study

    run_machine_study(load_loader_study, spec, **options)
