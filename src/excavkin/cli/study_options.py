"""The options every study command takes (a model's ``excavkin study``, a machine's
``excavkin excavator study``): light to import, so that ``excavkin --help`` stays quick."""

from __future__ import annotations

from collections.abc import Callable

import click


def study_options(f: Callable[..., None]) -> Callable[..., None]:
    """The options of a study command (a model's, a machine's): the table, --force,
    --restart, --scheduler, --quiet."""
    for option in reversed(_OPTIONS):
        f = option(f)
    return f


_OPTIONS = [
    click.option(
        "-o",
        "--out",
        default=None,
        metavar="FILE.parquet",
        help="The table, one row per design (default: STUDY.parquet in the current folder).",
    ),
    click.option("--force", is_flag=True, help="Replace the table if it exists."),
    click.option(
        "--restart",
        is_flag=True,
        help="Start anew instead of resuming the finished designs of an interrupted run.",
    ),
    click.option(
        "--scheduler",
        default=None,
        metavar="dask|tcp://HOST:PORT",
        help="Run the chunks of designs on a local Dask cluster ('dask') or an existing Dask "
        "scheduler (its address); the table is the same as a local run's.",
    ),
    click.option("-q", "--quiet", is_flag=True, help="No progress bar and no header."),
]


#: ``--write-machine``: the machine-study optimisers' option (``excavkin FAMILY optimize``)
write_machine_option = click.option(
    "--write-machine",
    "machine_out",
    default=None,
    metavar="FILE.toml",
    help="Write the optimum as a machine file: the study's machine file with the design "
    "parameters' values replaced, each in the file's own unit, and its model inline.",
)
