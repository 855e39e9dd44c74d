"""What every family's ``report`` command shares: its options, its target, its progress.

A wing's ``excavkin <family> report MACHINE -o FILE.html`` parses its own options, then hands
the building of its report over to `write_report`: a bar over the sections on stderr (none
under ``--quiet`` or off a terminal), the file written atomically, one line saying where.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click

if TYPE_CHECKING:
    from excavkin.outputs.machine_report import MachineReport, Progress

__all__ = ["report_options", "report_target", "write_report"]

_Command = TypeVar("_Command", bound=Callable[..., Any])


def report_options(command: _Command) -> _Command:
    """``-o/--out``, ``--force`` and ``-q/--quiet`` of a family's ``report`` command.

    Parameters
    ----------
    command : callable
        The command's function.

    Returns
    -------
    callable
        The function with the three options.
    """
    for option in (
        click.option("-q", "--quiet", is_flag=True, help="No progress and no summary line."),
        click.option("--force", is_flag=True, help="Replace an existing report."),
        click.option(
            "-o",
            "--out",
            "out",
            default=None,
            metavar="PATH",
            type=click.Path(dir_okay=False),
            help="The report to write (.html); default MACHINE's name + .html here.",
        ),
    ):
        command = option(command)
    return command


def report_target(machine: str, out: str | None, force: bool) -> Path:
    """The file to write, checked before any work: never over a file without ``force``.

    Parameters
    ----------
    machine : str
        The MACHINE argument (a path or a built-in name): the default file is its name.
    out : str or None
        ``--out``.
    force : bool

    Returns
    -------
    Path

    Raises
    ------
    OutputError
        The file exists (without ``force``), its folder does not, or it is not ``.html``.
    """
    from excavkin.outputs.machine_report import HTML_SUFFIXES
    from excavkin.outputs.tables import check_target

    target = Path(out) if out else Path(f"{Path(machine).stem or 'machine'}.html")
    return check_target(target, force=force, suffixes=HTML_SUFFIXES)


def write_report(
    build: Callable[[Progress], MachineReport], target: Path, *, force: bool, quiet: bool
) -> Path:
    """Build a report with a bar over its sections, then write it.

    Parameters
    ----------
    build : callable
        ``build(progress) -> MachineReport``; calls ``progress(done, total)`` after each
        section.
    target : Path
        From `report_target`.
    force : bool
    quiet : bool
        No progress and no summary line.

    Returns
    -------
    Path
    """
    import matplotlib

    from excavkin.cli.progress import progress, staged
    from excavkin.outputs.machine_report import write_machine_report

    matplotlib.use("Agg")
    with staged("machine report", 1, quiet=quiet) as next_stage:
        report = build(next_stage())
    with progress("writing the report", quiet=quiet):
        path = write_machine_report(report, target, force=force)
    if not quiet:
        click.echo(f"wrote {path} ({len(report.sections)} sections)", err=True)
    return path
