"""``excavkin crane chart|range|supports MACHINE``: a crane's load chart, working range and
support reactions.

The wing's entry point: ``excavkin --help`` imports this module, so the heavy modules (NumPy,
the machine, pint) are imported inside the commands. Each command parses, calls the library
and writes: the result's ``summary()`` on the terminal, its ``to_frame()`` to a table.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

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
    from excavkin.crane.machine import Crane, StabilityFactors
    from excavkin.outputs.machine_report import MachineReport


def _machine(path: str, factors: tuple[str, str] | None = None) -> Crane:
    """The machine file's crane; rated by ``--stability-factors`` where given."""
    from excavkin.crane.machine_file import load_machine

    crane = load_machine(model_path(path, "machine"))
    return crane if factors is None else crane.with_stability(_factors(factors))


def _factors(text: tuple[str, str]) -> StabilityFactors:
    """``--stability-factors GAMMA_P GAMMA_F``, or one message naming the option."""
    from excavkin.crane.machine import StabilityFactors
    from excavkin.errors import InputError

    values = []
    for t in text:
        try:
            values.append(float(t))
        except ValueError:
            raise InputError(f"--stability-factors: {t[:40]!r} is not a number") from None
    try:
        return StabilityFactors(*values)
    except InputError as exc:
        raise InputError(f"--stability-factors: {exc}") from None


#: ``--stability-factors`` of the commands that rate a load chart
FACTORS_OPTION = click.option(
    "--stability-factors",
    "stability_factors",
    nargs=2,
    type=str,
    default=None,
    metavar="GAMMA_P GAMMA_F",
    help="Rate stability by factored loads instead of 85 % (75 % on crawlers) of tipping: "
    "the crane stands under GAMMA_P × the hook load + GAMMA_F × the booms' weight reduced to "
    "the tip (the form of ISO 4305 and EN 13000; take the factors from the standard's clause). "
    "Overrides the machine file's [stability].",
)


@click.group("crane", context_settings={"help_option_names": ["-h", "--help"]})
def command() -> None:
    """Load chart, working range and outrigger reactions of a crane MACHINE, its spec sheet;
    studies and optimisation of its design."""


@command.command("chart")
@MACHINE_ARGUMENT
@click.option("--step", default="1m", show_default=True, help="Radius step of the chart.")
@click.option(
    "--second",
    multiple=True,
    help="A length of the knuckle or telescoping cylinder (a boom configuration), e.g. "
    "1800mm; repeat for more; default its two ends and its middle.",
)
@click.option(
    "--sectors",
    default=4,
    show_default=True,
    type=click.IntRange(min=1, max=36),
    help="Equal slew sectors over 360° (4: front, left, rear, right).",
)
@FACTORS_OPTION
@OUTPUT_OPTION
@FORCE_OPTION
@handle_errors
def chart(
    machine: str,
    step: str,
    second: tuple[str, ...],
    sectors: int,
    stability_factors: tuple[str, str] | None,
    output: str | None,
    force: bool,
) -> None:
    """Print the load chart (t at the hook) over radius × boom configuration × slew sector:
    the least of the cylinders at relief, the hoist and stability (85 % of tipping on
    outriggers, 75 % on crawlers, ASME B30.5 5-1.1.1, or factored loads), with the limit that
    binds."""
    import numpy as np

    from excavkin.cli.common import si_value
    from excavkin.crane.chart import load_chart
    from excavkin.crane.reach import reach

    dr = si_value(step, "length", "--step")
    if not 0.1 <= dr <= 10.0:
        raise click.BadParameter("between 0.1 m and 10 m", param_hint="--step")
    lengths = [si_value(k, "length", "--second") for k in second]
    check_output(output, force)
    crane = _machine(machine, stability_factors)
    x = reach(crane).tip[..., 0]
    radii = np.arange(np.ceil(x.min() / dr) * dr, x.max() + 1e-9, dr)
    if radii.size == 0:
        radii = np.array([x.min()])
    result = load_chart(crane, radii, np.array(lengths) if lengths else None, sectors)
    if np.isnan(result.capacity).all():
        from excavkin.errors import InputError

        shown = ", ".join(result.config_label(j) for j in range(result.second.size))
        raise InputError(
            f"no radius is in reach at {shown}; `excavkin crane range` gives the radius range"
        )
    print_result(result, output, force)


@command.command("range")
@MACHINE_ARGUMENT
@click.option(
    "--samples",
    default=21,
    show_default=True,
    type=click.IntRange(min=2, max=1000),
    help="Lengths over each cylinder's stroke.",
)
@OUTPUT_OPTION
@FORCE_OPTION
@handle_errors
def working_range(machine: str, samples: int, output: str | None, force: bool) -> None:
    """Print the working range: the boom's angle and the configuration over the cylinders'
    strokes, the radius range and the highest tip; the table has the tip at every pair of
    lengths."""
    from excavkin.crane.reach import reach

    check_output(output, force)
    print_result(reach(_machine(machine), samples), output, force)


@command.command("supports")
@MACHINE_ARGUMENT
@click.option("--radius", required=True, help="Hook radius, e.g. 6m.")
@click.option(
    "--second",
    default=None,
    help="The knuckle or telescoping cylinder's length, e.g. 1800mm; default mid-stroke.",
)
@click.option("--load", default="0kg", show_default=True, help="Hook load, hook block included.")
@click.option(
    "--samples",
    default=73,
    show_default=True,
    type=click.IntRange(min=2, max=100_000),
    help="Slew angles over 360°.",
)
@OUTPUT_OPTION
@FORCE_OPTION
@handle_errors
def supports(
    machine: str,
    radius: str,
    second: str | None,
    load: str,
    samples: int,
    output: str | None,
    force: bool,
) -> None:
    """Print each outrigger pad's (or track corner's) largest and least ground reaction (kN)
    over a 360° slew; the table has every reaction at every slew angle."""
    from excavkin.cli.common import si_value
    from excavkin.crane.supports import support_reactions

    r = si_value(radius, "length", "--radius")
    m = si_value(load, "mass", "--load")
    if m < 0 or m > 1e6:
        raise click.BadParameter("between 0 and 1000 t", param_hint="--load")
    if not 0 <= r <= 1000:
        raise click.BadParameter("a radius of 0 to 1000 m", param_hint="--radius")
    check_output(output, force)
    crane = _machine(machine)
    cyl = crane.second
    k = 0.5 * (cyl.retracted + cyl.extended)
    if second is not None:
        k = si_value(second, "length", "--second")
        if not cyl.retracted - 1e-9 <= k <= cyl.extended + 1e-9:
            raise click.BadParameter(
                f"within the {cyl.role} cylinder's stroke ({cyl.retracted * 1e3:.0f} to "
                f"{cyl.extended * 1e3:.0f} mm)",
                param_hint="--second",
            )
    print_result(support_reactions(crane, r, k, m, samples), output, force)


@command.command("study")
@click.argument("spec", metavar="STUDY")
@study_options
@handle_errors
def study(spec: str, **options: Any) -> None:
    """A design study of a crane: designs sampled in the box of STUDY.toml's parameter bounds
    (its [study] names a crane machine), each rated by its working range and load chart; one
    row per design."""
    from excavkin.cli.commands.study import run_machine_study
    from excavkin.crane.study import load_crane_study

    run_machine_study(load_crane_study, spec, **options)


@command.command("optimize")
@click.argument("study", type=click.Path(dir_okay=False))
@machine_optimize_options
@handle_errors
def optimize(study: str, **options: Any) -> None:
    """The best design of a crane study (STUDY.toml with a crane machine in its [study]): its
    [optimize] objective over its parameter box under its constraints."""
    from excavkin.cli.commands.optimize import optimize_machine_study
    from excavkin.crane.study import load_crane_study

    optimize_machine_study(load_crane_study(model_path(study, "study")), **options)


@command.command("report")
@machine_report_options(15, 201, "Radii of the load chart.")
@FACTORS_OPTION
@handle_errors
def report(
    machine: str, samples: int, stability_factors: tuple[str, str] | None, **options: Any
) -> None:
    """Write a self-contained HTML spec sheet of MACHINE: working range, load chart with the
    binding limits, support reactions over a slew, their charts and the moving booms."""
    import shlex

    from excavkin.cli.machine_report import run_report
    from excavkin.crane.report import machine_report

    crane = _machine(machine, stability_factors)
    said = (
        ""
        if stability_factors is None
        else " --stability-factors " + " ".join(map(shlex.quote, stability_factors))
    )

    def build(loaded: Crane, *, command: str, **rest: Any) -> MachineReport:
        return machine_report(loaded, command=command + said, **rest)

    run_report("crane", machine, crane, samples, build, **options)
