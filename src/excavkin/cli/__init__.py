"""The ``excavkin`` command. Subcommands live one per module in this package and are found here.

Each module ``excavkin/cli/<name>.py`` (not starting with ``_``) exposes ``command``, a
``click.Command``; this thin layer only parses arguments, calls library functions and writes
files through :mod:`excavkin.outputs`.
"""

from __future__ import annotations

import click

from excavkin import __version__
from excavkin.cli._common import ModuleGroup


@click.group(
    cls=ModuleGroup,
    package=__name__,
    context_settings={"help_option_names": ["-h", "--help"]},
)
@click.version_option(__version__, prog_name="excavkin")
def main() -> None:
    """Analytical kinematics and kinetostatics of planar excavator mechanisms."""
