"""``excavkin optimize``: the best design of a study file's box under its constraints."""

from __future__ import annotations

from typing import TYPE_CHECKING

import click

from excavkin.cli.common import handle_errors

if TYPE_CHECKING:
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
@click.option("--force", is_flag=True, help="Replace the output files if they exist.")
@handle_errors
def command(spec: str, plot: str | None, out: str | None, force: bool) -> None:
    """Find the design in STUDY.toml's parameter box that minimises or maximises its
    [optimize] objective (a metric) under its constraints: SLSQP with exact sensitivities, or
    differential evolution over whole populations solved as one batch; print the optimum and
    the constraints that bind.
    """
    import excavkin
    from excavkin.cli.common import model_path
    from excavkin.io.files import check_target
    from excavkin.studies.optimize import optimize
    from excavkin.studies.study_file import load_optimization

    study, settings = load_optimization(model_path(spec, "study"))
    if plot is not None:
        check_target(plot, force=force, suffixes=(".png", ".svg", ".pdf"))
    if out is not None:
        check_target(out, force=force, suffixes=(".csv", ".parquet"))
    mech = excavkin.load(study.model)
    by_name = {m.name: m for m in study.metrics}
    objective = by_name[settings["objective"]]
    best = optimize(
        mech,
        study.bounds,
        study.poses,
        objective,
        settings["sense"],
        metrics=[m for m in study.metrics if m.name != objective.name],
        constraints=study.constraints,
        method=settings["method"],
        loads=study.loads,
        seed=study.seed,
        maxiter=settings["maxiter"],
        popsize=settings["popsize"],
    )
    report_optimum(best, settings["sense"], objective.name, settings["method"], out, plot, force)


def report_optimum(
    best: Optimum,
    sense: str,
    objective: str,
    method: str,
    out: str | None,
    plot: str | None,
    force: bool,
) -> None:
    """Print an optimum (its parameters, metrics, binding constraints and parameters at the
    box's bounds), and write it as a one-row table and its convergence plot if asked."""
    verdict = "feasible" if best.feasible else "NOT feasible"
    click.echo(
        f"{sense}imum of {objective} ({method}, "
        f"{best.evaluations:,} designs solved): {best.value:.10g} — {verdict}"
    )
    for name, value in best.params.items():
        click.echo(f"  {name:<24} {value:.10g}")
    for name, value in best.metrics.items():
        click.echo(f"  {name:<24} {value:.10g}")
    click.echo(f"  active constraints: {', '.join(best.active) or 'none'}")
    bounds = ", ".join(f"{k} ({side})" for k, side in best.at_bounds.items())
    click.echo(f"  at the box's bounds: {bounds or 'none'}")
    if not best.success:
        click.echo(f"excavkin: warning: the optimiser says: {best.message}", err=True)
    if out is not None:
        import pandas as pd

        from excavkin.outputs.tables import write_table

        row: dict[str, list[object]] = {f"design.{k}": [v] for k, v in best.params.items()}
        row.update({k: [v] for k, v in best.metrics.items()})
        row["feasible"] = [best.feasible]
        write_table(pd.DataFrame(row), out, force=force)
        click.echo(f"wrote the optimum to {out}")
    if plot is not None:
        from pathlib import Path

        import matplotlib

        matplotlib.use("Agg")
        from excavkin.io.files import write_atomic
        from excavkin.outputs.convergence import plot_convergence

        fig = plot_convergence(best.history, objective).get_figure(root=True)
        assert fig is not None
        fig.tight_layout()
        write_atomic(plot, lambda tmp: fig.savefig(tmp, dpi=110, format=Path(plot).suffix[1:]))
        click.echo(f"wrote {plot}")
