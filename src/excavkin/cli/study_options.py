"""The options every study command takes (a model's ``excavkin study``, a machine's
``excavkin excavator study``): light to import, so that ``excavkin --help`` stays quick."""

from __future__ import annotations

import functools
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


def machine_optimize_options(f: Callable[..., None]) -> Callable[..., None]:
    """The options of a family's ``optimize`` command (``excavkin FAMILY optimize STUDY``):
    ``--method``, ``-o/--output``, ``--plot``, ``--write-machine``, ``--force``, ``-q/--quiet``.

    Parameters
    ----------
    f : callable
        The command's function.

    Returns
    -------
    callable
        The function with the options.
    """
    return functools.reduce(lambda g, option: option(g), reversed(_OPTIMIZE_OPTIONS), f)


_OPTIMIZE_OPTIONS = [
    click.option(
        "--method",
        type=click.Choice(["slsqp", "differential-evolution"]),
        default=None,
        help="Override the study's [optimize] method.",
    ),
    click.option(
        "-o",
        "--output",
        type=click.Path(dir_okay=False),
        help="The optimum (parameters, metrics, feasibility) as a one-row table (.csv or "
        ".parquet).",
    ),
    click.option(
        "--plot",
        type=click.Path(dir_okay=False),
        help="Draw the convergence: the objective after each iteration (.png, .svg or .pdf).",
    ),
    write_machine_option,
    click.option("--force", is_flag=True, help="Replace the output files if they exist."),
    click.option("-q", "--quiet", is_flag=True, help="No progress."),
]
