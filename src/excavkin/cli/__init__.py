"""The ``excavkin`` command. Subcommands live one per module in this package and are found here.

Each module ``excavkin/cli/<name>.py`` (not starting with ``_``) exposes ``command``, a
``click.Command``; this thin layer only parses arguments, calls library functions and writes
files through :mod:`excavkin.outputs`.
"""

from __future__ import annotations

import importlib
import pkgutil
from typing import Any

import click

from excavkin import __version__


class _Discovered(click.Group):
    """A group whose commands are the modules of this package, imported on demand."""

    def _modules(self) -> dict[str, str]:
        mods = {}
        for info in pkgutil.iter_modules(__path__):
            if not info.name.startswith("_"):
                mods[info.name.replace("_", "-")] = f"{__name__}.{info.name}"
        return mods

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(self._modules())

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        mod = self._modules().get(cmd_name)
        if mod is None:
            return None
        command: Any = importlib.import_module(mod).command
        return command  # type: ignore[no-any-return]


@click.group(cls=_Discovered, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="excavkin")
def main() -> None:
    """Analytical kinematics and kinetostatics of planar excavator mechanisms."""
