"""``excavkin optimize``: the best design of a study file's box under its constraints."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

import click

from excavkin.cli.common import handle_errors

if TYPE_CHECKING:
    from excavkin.studies.machine_study import MachineStudy
    from excavkin.studies.optimize import Optimum


@click.command("optimize")
@click.argument("spec", metavar="STUDY")
@click.option(
    "--plot",
    default=None,
    metavar="FILE.png|FILE.svg",
    help="Draw the convergence: the objective after each iteration.",
)
@click.option(
    "-o",
    "--out",
    default=None,
    metavar="FILE.csv|FILE.parquet",
    help="Write the optimum (parameters, metrics, feasibility) as a one-row table.",
)
@click.option(
    "--write-model",
    "model_out",
    default=None,
    metavar="FILE.toml",
    help="Write the optimum as a model file: the study's model with the design parameters' "
    "values replaced, each in the file's own unit.",
)
@click.option("--force", is_flag=True, help="Replace the output files if they exist.")
@click.option("-q", "--quiet", is_flag=True, help="No progress.")
@handle_errors
def command(
    spec: str, plot: str | None, out: str | None, model_out: str | None, force: bool, quiet: bool
) -> None:
    """Find the design in STUDY.toml's parameter box that minimises or maximises its
    [optimize] objective (a metric) under its constraints: SLSQP with exact sensitivities, or
    differential evolution over whole populations solved as one batch; print the optimum and
    the constraints that bind.
    """
    from excavkin.cli.common import model_path
    from excavkin.io.files import check_target
    from excavkin.studies.optimize import optimize_study
    from excavkin.studies.study_file import load_optimization

    study, _ = load_optimization(model_path(spec, "study"))
    if plot is not None:
        check_target(plot, force=force, suffixes=(".png", ".svg", ".pdf"))
    if out is not None:
        check_target(out, force=force, suffixes=(".csv", ".parquet"))
    if model_out is not None:
        from excavkin.io.files import OutputError

        target = check_target(model_out, force=force, suffixes=(".toml",))
        if target.exists() and target.resolve() == study.model.resolve():
            raise OutputError(f"{target} is the study's model file; write the design elsewhere")
    with optimizer_progress(quiet) as report:
        best = optimize_study(study, progress=report)
    report_optimum(best, out, plot, force)
    if model_out is not None:
        best.write_model(model_out, force=force)
        click.echo(f"wrote the optimal design as a model to {model_out}")


@contextmanager
def optimizer_progress(quiet: bool) -> Iterator[Callable[[int, int], None]]:
    """A spinner with the optimiser's iteration count (its ``progress`` callback), on a
    terminal and without ``--quiet``."""
    from excavkin.cli.progress import progress

    with progress("optimising", quiet=quiet, count="iterations") as advance:
        yield lambda done, most: advance(1)


def report_optimum(best: Optimum, out: str | None, plot: str | None, force: bool) -> None:
    """Print an optimum (its parameters and metrics in the study's units, the constraints that
    bind and the parameters at the box's bounds), and write it as a one-row table (SI, with
    its units) and its convergence plot if asked."""
    lines = best.summary().splitlines()
    if not best.success:  # the optimiser's doubt goes to stderr as a warning
        lines = lines[:-1]
    click.echo("\n".join(lines))
    if not best.success:
        click.echo(f"excavkin: warning: the optimiser says: {best.message}", err=True)
    if out is not None:
        from excavkin.outputs.tables import write_table

        write_table(best.to_frame("si"), out, force=force)
        click.echo(f"wrote the optimum to {out}")
    if plot is not None:
        from pathlib import Path

        import matplotlib

        matplotlib.use("Agg")
        from excavkin.io.files import write_atomic

        fig = best.plot().get_figure(root=True)
        assert fig is not None
        fig.tight_layout()
        import matplotlib.pyplot as plt

        try:
            write_atomic(plot, lambda tmp: fig.savefig(tmp, dpi=110, format=Path(plot).suffix[1:]))
        finally:
            plt.close(fig)
        click.echo(f"wrote {plot}")


def optimize_machine_study(
    spec: MachineStudy,
    method: str | None,
    output: str | None,
    plot: str | None,
    machine_out: str | None,
    force: bool,
    quiet: bool,
) -> None:
    """Optimise a machine study (any family's) and report it: the outputs checked before any
    work, the optimum printed and written as a table, a convergence plot and a machine file
    as asked."""
    from excavkin.io.files import check_target
    from excavkin.studies.machine_study import (
        check_machine_target,
        optimize_machine,
        write_machine,
    )

    if output is not None:
        check_target(output, force=force, suffixes=(".csv", ".parquet"))
    if plot is not None:
        check_target(plot, force=force, suffixes=(".png", ".svg", ".pdf"))
    if machine_out is not None:
        check_machine_target(spec, machine_out, force=force)
    with optimizer_progress(quiet) as report:
        best = optimize_machine(spec, method=method, progress=report)
    report_optimum(best, output, plot, force)
    if machine_out is not None:
        what = f"{best.sense}imum of {best.objective}" if best.sense else "the optimum"
        write_machine(spec, best.params, machine_out, force=force, note=f"design at the {what}")
        click.echo(f"wrote the optimal design as a machine file to {machine_out}")
