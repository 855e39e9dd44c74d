"""A click group that imports a subcommand only when it is run, so that ``--help`` is fast.

A listing (``excavkin --help``) shows each subcommand's one-line help. For the commands named in
the group's own table that line is stored beside the module's name, so listing them imports
nothing; a command found by entry point is imported for its line, so an entry point must name a
light module (one that imports click and this package's CLI helpers, not NumPy or pint).
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Mapping
from functools import cache
from typing import Any, NamedTuple

import click

from excavkin.errors import did_you_mean


class Lazy(NamedTuple):
    """A subcommand by where it lives, with the help line a listing shows for it."""

    #: ``"module:attribute"``, a ``click.Command``
    target: str
    #: the first sentence of the command's help, as its own listing line would show it
    summary: str


@cache
def entry_point_targets(group: str) -> Mapping[str, str]:
    """The commands registered under the entry-point group ``group``: name → ``module:attribute``.

    Read once per process: scanning the installed packages costs tens of milliseconds.
    """
    from importlib.metadata import entry_points

    return {ep.name: ep.value for ep in entry_points(group=group)}


class LazyGroup(click.Group):
    """A click group whose subcommands are imported only when run.

    ``lazy`` maps a subcommand's name to a `Lazy` (its ``module:attribute`` and its help
    line); ``entry_point_group`` adds the commands other packages register under that
    entry-point group (a wing of excavkin, or a package of the user's), in the same
    ``module:attribute`` form. Loading lazily keeps ``--help`` fast and lets the core name no
    wing.
    """

    def __init__(
        self,
        *args: Any,
        lazy: Mapping[str, Lazy] | None = None,
        entry_point_group: str | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(*args, **kwargs)
        self.lazy = dict(lazy or {})
        self.entry_point_group = entry_point_group

    def _registered(self) -> Mapping[str, str]:
        if not self.entry_point_group:
            return {}
        return entry_point_targets(self.entry_point_group)

    def _target(self, name: str) -> str | None:
        """Where the command ``name`` lives; the group's own table first (which spares a
        scan of the entry points to run a general command)."""
        if name in self.lazy:
            return self.lazy[name].target
        return self._registered().get(name)

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted({*self.lazy, *self._registered(), *self.commands})

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        """List the subcommands as click does, taking a stored help line where there is one."""
        listed: list[tuple[str, click.Command]] = []
        for name in self.list_commands(ctx):
            if name not in self.commands and name in self.lazy:
                # a stand-in with the same first sentence shortens it exactly as the command would
                listed.append((name, click.Command(name, help=self.lazy[name].summary)))
                continue
            command = self.get_command(ctx, name)
            if command is not None and not command.hidden:
                listed.append((name, command))
        if listed:
            limit = formatter.width - 6 - max(len(name) for name, _ in listed)
            rows = [(name, command.get_short_help_str(limit)) for name, command in listed]
            with formatter.section("Commands"):
                formatter.write_dl(rows)

    def resolve_command(
        self, ctx: click.Context, args: list[str]
    ) -> tuple[str | None, click.Command | None, list[str]]:
        name = args[0] if args else ""
        if name and not name.startswith("-") and self.get_command(ctx, name) is None:
            known = self.list_commands(ctx)
            hint = did_you_mean(name, known)
            raise click.UsageError(f"no command {name!r}{hint} (commands: {', '.join(known)})", ctx)
        return super().resolve_command(ctx, args)

    def main(  # type: ignore[override]
        self, args: Any = None, prog_name: str | None = None, **extra: Any
    ) -> Any:
        """Run, with every error — click's usage errors too — in excavkin's one style."""
        if extra.get("standalone_mode") is False:
            return super().main(args, prog_name, **extra)
        extra["standalone_mode"] = False
        try:
            code = super().main(args, prog_name, **extra)
            sys.stdout.flush()  # a closed pipe shows here, not at the interpreter's exit
        except BrokenPipeError:
            from excavkin.cli.common import end_on_closed_stdout

            end_on_closed_stdout()
        except click.UsageError as exc:
            where = exc.ctx.command_path if exc.ctx is not None else "excavkin"
            click.echo(f"excavkin: error: {exc.format_message()} (see '{where} --help')", err=True)
            sys.exit(exc.exit_code)
        except click.ClickException as exc:
            click.echo(f"excavkin: error: {exc.format_message()}", err=True)
            sys.exit(exc.exit_code)
        except click.Abort:
            click.echo("excavkin: error: aborted; no output was written", err=True)
            sys.exit(130)
        sys.exit(code if isinstance(code, int) else 0)

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        if cmd_name in self.commands:
            return self.commands[cmd_name]
        target = self._target(cmd_name)
        if target is None:
            return None
        module, _, attribute = target.partition(":")
        command = getattr(importlib.import_module(module), attribute or "command")
        if not isinstance(command, click.Command):
            raise TypeError(f"{target} is not a click command")
        return command
