"""``excavkin study``: a design of experiments over a model's design parameters, one row per
design (parameters, metrics over a pose set, feasibility), streamed and resumable."""

from __future__ import annotations

from typing import TYPE_CHECKING

import click

from excavkin.cli.common import backend_option, handle_errors
from excavkin.cli.study_options import study_options

if TYPE_CHECKING:
    from pathlib import Path

    from excavkin.studies.study import Subject


@click.command("study")
@click.argument("spec", metavar="STUDY")
@study_options
@backend_option
@handle_errors
def command(
    spec: str,
    out: str | None,
    force: bool,
    restart: bool,
    scheduler: str | None,
    quiet: bool,
    backend: str,
) -> None:
    """Evaluate a design study: designs sampled in the box of STUDY.toml's parameter bounds
    (Sobol', Halton, Latin hypercube or a grid), each solved at every pose of its pose sets in
    one batch, its metrics reduced over the poses and its constraints checked; write one row
    per design to a Parquet table.
    """
    from pathlib import Path

    from excavkin.backends import require
    from excavkin.cli.common import model_path
    from excavkin.studies.study_file import load_study

    require(backend, f"--backend {backend}")
    path = model_path(spec, "study")
    study = load_study(path)
    # by default beside where the command runs (a built-in example's folder is not the user's)
    target = Path(out) if out else Path(path.stem + ".parquet")
    title = f"{study.model.stem} ({study.method}, seed {study.seed})"
    run_with_progress(study, title, target, force, restart, scheduler, quiet, backend)


def run_with_progress(
    study: Subject,
    title: str,
    target: Path,
    force: bool,
    restart: bool,
    scheduler: str | None,
    quiet: bool,
    backend: str = "auto",
) -> None:
    """Run a study (of a model, or of a machine) into ``target`` with a progress bar, and say
    how many designs are feasible (``quiet``: no header, no bar; the closing line alone);
    every solve on ``backend``."""
    from excavkin.cli.progress import compile_notes, progress
    from excavkin.errors import ExcavkinError
    from excavkin.studies.study import SchedulerError, check_scheduler, run_study

    if scheduler is not None:
        try:
            check_scheduler(scheduler)
        except SchedulerError as exc:
            raise ExcavkinError(f"--scheduler {scheduler}: {exc}") from None
    total = study.designs
    if not quiet:
        click.echo(f"{total:,} designs × {study.pose_count:,} poses of {title}", err=True)
    with compile_notes(quiet), progress("designs", total, quiet=quiet) as advance:
        seen = [0]

        def report(done: int, _total: int) -> None:
            advance(done - seen[0])
            seen[0] = done

        try:
            result = run_study(
                study, target, force=force, resume=not restart, progress=report,
                scheduler=scheduler, backend=backend,
            )  # fmt: skip
        except SchedulerError as exc:
            raise ExcavkinError(f"--scheduler {scheduler}: {exc}") from None
    import pyarrow.parquet as pq

    feasible = pq.read_table(result.path, columns=["feasible"]).column(0).to_numpy()
    click.echo(f"wrote {total:,} designs ({int(feasible.sum()):,} feasible) to {result.path}")
    if study.motion_note and not quiet:
        click.echo(f"excavkin: note: force metrics: {study.motion_note}", err=True)
