"""``excavkin report MODEL.toml -o report.html``: one self-contained HTML report of a sweep."""

from __future__ import annotations

from pathlib import Path

import click

from excavkin.cli.commands.solve import build_inputs, with_sweep_options
from excavkin.cli.common import EXIT_SAMPLES, fail, handle_errors, model_path


def _load(model: str):  # type: ignore[no-untyped-def]
    import excavkin

    return excavkin.load(model_path(model))


@click.command(
    "report",
    help="Write a self-contained HTML report of MODEL (a .toml file or the name of a built-in "
    "example): the mechanism moving over a sweep (slider, play/pause), its main curves, the "
    "warnings (dead positions, non-closure, shocks), the model, its solve plan and the table.\n\n"
    "Without --sweep each input gets a default sweep: a full turn for a rotary input that can "
    "turn fully, else the range around the sketch over which the mechanism closes; 0.8 to 1.25 "
    "times the sketch length for a cylinder. Several --sweep options move their inputs together "
    "and need the same N.",
)
@click.argument("model", metavar="MODEL")
@with_sweep_options
@click.option(
    "-o",
    "--out",
    "out",
    default=None,
    metavar="PATH",
    help="The report to write (.html); default MODEL's name + .html here.",
)
@click.option("--title", default=None, help="Title of the report (default: the model's name).")
@click.option(
    "--rope",
    "ropes",
    multiple=True,
    metavar="NAME",
    help="Draw this linear element as a rope (a line), not a cylinder.",
)
@click.option("--force", is_flag=True, help="Replace an existing report.")
@click.option("-q", "--quiet", is_flag=True, help="No progress and no summary line.")
@handle_errors
def command(
    model: str,
    sweeps: tuple[str, ...],
    sets: tuple[str, ...],
    rates: tuple[str, ...],
    accels: tuple[str, ...],
    grid: bool,
    out: str | None,
    title: str | None,
    ropes: tuple[str, ...],
    force: bool,
    quiet: bool,
) -> None:
    """Parse, solve, write: see the help text."""
    import shlex

    from excavkin.cli.progress import progress, solve_with_progress
    from excavkin.default_sweep import default_sweep
    from excavkin.outputs.report import write_report
    from excavkin.outputs.tables import check_target

    target = Path(out) if out else Path(f"{Path(model).stem}.html")
    check_target(target, force=force, suffixes=(".html", ".htm"))
    mech = _load(model)
    elements = [e.name for e in mech.plan.elements]
    for name in ropes:
        if name not in elements:
            from excavkin.errors import InputError, unknown_name

            raise InputError(f"--rope: {unknown_name('linear element', name, elements)}")

    values, rate, accel = build_inputs(mech, sweeps, sets, rates, accels, grid)
    if not sweeps:
        for name, arr in default_sweep(mech).items():
            values.setdefault(name, arr)
    result = solve_with_progress(mech, values, rate, accel, quiet=quiet)
    if not result.status.ok.any():
        fail(
            f"{result.summary()}. No sample solved, so there is nothing to report; "
            "nothing was written (check the --sweep ranges against `excavkin check`).",
            EXIT_SAMPLES,
        )
    given = [("--sweep", sweeps), ("--set", sets), ("--rate", rates), ("--accel", accels)]
    command_line = " ".join(
        ["excavkin report", shlex.quote(model)]
        + [f"{opt} {shlex.quote(v)}" for opt, vals in given for v in vals]
    )
    with progress("writing the report", quiet=quiet):
        path = write_report(
            mech,
            result,
            target,
            force=force,
            title=title,
            ropes=ropes,
            command=command_line,
        )
    if not quiet:
        bad = int((~result.status.ok).sum())
        note = f"; {bad} of {len(result)} samples did not solve (see Warnings)" if bad else ""
        click.echo(f"wrote {path} ({len(result)} samples{note})", err=True)
