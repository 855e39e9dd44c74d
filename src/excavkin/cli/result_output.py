"""What a family's analysis command does with its result: the summary on the terminal, the
table to a file checked before the work and written whole; and the MACHINE argument and the
``-o``/``--force`` options those commands share.

Imported by the wings' command modules at ``excavkin --help``: nothing heavy at import.
"""

from __future__ import annotations

from typing import Any

import click

__all__ = ["FORCE_OPTION", "MACHINE_ARGUMENT", "OUTPUT_OPTION", "check_output", "print_result"]

#: a machine file, or a built-in machine's name
MACHINE_ARGUMENT = click.argument("machine", type=click.Path(dir_okay=False))
#: the result's table
OUTPUT_OPTION = click.option(
    "-o", "--output", type=click.Path(dir_okay=False), help="The table (.csv or .parquet), SI."
)
#: replace the table's file
FORCE_OPTION = click.option("--force", is_flag=True, help="Replace an output file that exists.")


def check_output(output: str | None, force: bool) -> None:
    """Refuse a table's target before any work: a file that exists (without ``force``), a
    folder that does not, a suffix other than ``.csv`` or ``.parquet``.

    Parameters
    ----------
    output : str or None
        ``-o``; nothing to check when None.
    force : bool
        ``--force``.
    """
    from excavkin.outputs.tables import check_target

    if output:
        check_target(output, force=force, suffixes=(".csv", ".parquet"))


def print_result(result: Any, output: str | None, force: bool) -> None:
    """Print a result's ``summary()`` and write its ``to_frame()`` to ``output`` (if given).

    Parameters
    ----------
    result : object
        Any analysis result with ``summary()`` and ``to_frame()``.
    output : str or None
        ``-o``.
    force : bool
        ``--force``.
    """
    from excavkin.outputs.tables import write_table

    click.echo(result.summary())
    if output:
        click.echo(f"wrote {write_table(result.to_frame(), output, force=force)}")
