"""The ``excavkin`` command: a thin layer that parses arguments, calls the library and writes
files through :mod:`excavkin.outputs`.

The general commands live one per module in :mod:`excavkin.cli.commands`, each exposing a
``click.Command`` named ``command``. A wing (a paper, a machine family) adds its own group by an
entry point in the group ``excavkin.commands`` (see ``pyproject.toml``), so that the core never
imports a wing. Every command is imported only when it is run or listed.
"""

from __future__ import annotations

import click

from excavkin import __version__
from excavkin.cli.common import LazyGroup

#: The general commands, by name: ``module:attribute``.
CORE_COMMANDS = {
    name: f"excavkin.cli.commands.{name}:command"
    for name in ("check", "demo", "report", "simulate", "solve", "tolerance")
}


@click.group(
    cls=LazyGroup,
    lazy=CORE_COMMANDS,
    entry_point_group="excavkin.commands",
    context_settings={"help_option_names": ["-h", "--help"]},
)
@click.version_option(__version__, prog_name="excavkin")
def main() -> None:
    """Analytical kinematics and kinetostatics of planar excavator mechanisms."""
