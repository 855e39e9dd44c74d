"""``excavkin reproduce NAME``: re-run a seed paper's study and write its tables and figures.

Subcommands are found, not listed: every module ``excavkin/cli/_reproduce_<name>.py`` that
exposes a ``click.Command`` named ``command`` becomes ``excavkin reproduce <name>`` (underscores
become hyphens), imported only when it is run or listed. To add a study, add such a module;
nothing here changes.
"""

from __future__ import annotations

import importlib
import pkgutil
from typing import Any

import click

import excavkin.cli as _cli

PREFIX = "_reproduce_"


class _Studies(click.Group):
    """A group whose commands are the ``_reproduce_*`` modules of :mod:`excavkin.cli`."""

    def _modules(self) -> dict[str, str]:
        mods = {}
        for info in pkgutil.iter_modules(_cli.__path__):
            if info.name.startswith(PREFIX) and len(info.name) > len(PREFIX):
                name = info.name[len(PREFIX) :].replace("_", "-")
                mods[name] = f"{_cli.__name__}.{info.name}"
        return mods

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(self._modules())

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        mod = self._modules().get(cmd_name)
        if mod is None:
            return None
        command: Any = importlib.import_module(mod).command
        return command  # type: ignore[no-any-return]


@click.group("reproduce", cls=_Studies)
def command() -> None:
    """Reproduce a seed paper's study: print its tables, write its figures."""
