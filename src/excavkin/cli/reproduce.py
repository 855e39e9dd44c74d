"""``excavkin reproduce NAME``: re-run a seed paper's study and write its tables and figures.

Subcommands are found, not listed: every module ``excavkin/cli/_reproduce_<name>.py`` that
exposes a ``click.Command`` named ``command`` becomes ``excavkin reproduce <name>`` (underscores
become hyphens), imported only when it is run or listed. To add a study, add such a module;
nothing here changes.
"""

from __future__ import annotations

import click

from excavkin.cli._common import ModuleGroup

PREFIX = "_reproduce_"


@click.group("reproduce", cls=ModuleGroup, package="excavkin.cli", prefix=PREFIX)
def command() -> None:
    """Reproduce a seed paper's study: print its tables, write its figures."""
