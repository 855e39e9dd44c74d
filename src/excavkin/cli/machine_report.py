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

__all__ = [
    "machine_report_options",
    "report_options",
    "report_target",
    "run_report",
    "write_report",
]

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


def machine_report_options(samples: int, most: int, what: str) -> Callable[[_Command], _Command]:
    """The MACHINE argument and the options of a family's ``report`` command: ``--samples``
    (``samples`` by default, 2 to ``most``: ``what`` they are) and `report_options`.

    Parameters
    ----------
    samples : int
        ``--samples``' default.
    most : int
        Its largest value.
    what : str
        Its help.

    Returns
    -------
    callable
        The decorator.
    """

    def decorate(command: _Command) -> _Command:
        command = report_options(command)
        command = click.option(
            "--samples",
            default=samples,
            show_default=True,
            type=click.IntRange(min=2, max=most),
            help=what,
        )(command)
        return click.argument("machine", type=click.Path(dir_okay=False))(command)

    return decorate


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


def run_report(
    family: str,
    machine: str,
    loaded: Any,
    samples: int,
    build: Callable[..., MachineReport],
    *,
    out: str | None,
    force: bool,
    quiet: bool,
) -> Path:
    """A family's ``excavkin FAMILY report MACHINE``: the target checked, then the report
    built with a bar over its sections and written.

    Parameters
    ----------
    family : str
        The family's command (``"excavator"``, ``"loader"``): the report names the command
        line that made it.
    machine : str
        The MACHINE argument.
    loaded : object
        The machine it names, loaded.
    samples : int
        ``--samples``.
    build : callable
        The wing's ``machine_report(loaded, *, samples, command, progress) -> MachineReport``.
    out : str or None
        ``--out``.
    force : bool
    quiet : bool

    Returns
    -------
    Path
    """
    import shlex

    target = report_target(machine, out, force)
    line = f"excavkin {family} report {shlex.quote(machine)} --samples {samples}"
    return write_report(
        lambda progress: build(loaded, samples=samples, command=line, progress=progress),
        target,
        force=force,
        quiet=quiet,
    )
