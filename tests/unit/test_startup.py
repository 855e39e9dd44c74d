"""Start-up: ``excavkin --help`` lists the commands without importing them (nor NumPy, pandas or
pint), the help lines stored for that are the commands' own, and the unit registry is built on
first use."""

from __future__ import annotations

import subprocess
import sys

import click
import pytest
from click.testing import CliRunner

from excavkin.cli import main
from excavkin.cli.lazy_group import LazyGroup, entry_point_targets

HEAVY = ("numpy", "pandas", "pint")


def lazy_groups() -> list[LazyGroup]:
    """The command and every group of subcommands it lists that is itself lazy."""
    ctx = click.Context(main)
    groups: list[LazyGroup] = [main]
    for name in main.list_commands(ctx):
        command = main.get_command(ctx, name)
        if isinstance(command, LazyGroup):
            groups.append(command)
    return groups


def test_every_stored_help_line_is_the_commands_own() -> None:
    groups = lazy_groups()
    assert {g.name for g in groups} >= {"main", "reproduce"}
    checked = 0
    for group in groups:
        ctx = click.Context(group)
        for name, entry in group.lazy.items():
            command = group.get_command(ctx, name)
            assert command is not None and not command.short_help
            assert entry.summary == command.get_short_help_str(limit=10**6), name
            checked += 1
    assert checked >= 11  # six general commands and five papers


@pytest.mark.parametrize("width", [40, 80, 250])
def test_the_listing_is_the_one_click_makes_from_the_commands(width: int) -> None:
    """The listing with the stored lines equals click's own, which imports every command."""
    for group in lazy_groups():
        ctx = click.Context(group)
        stored, imported = click.HelpFormatter(width=width), click.HelpFormatter(width=width)
        group.format_commands(ctx, stored)
        click.Group.format_commands(group, ctx, imported)
        assert "Commands:" in stored.getvalue()
        assert stored.getvalue() == imported.getvalue()


PROBE = """
import sys
from excavkin.cli import main
try:
    main({args!r})
except SystemExit as exc:
    assert exc.code == 0, exc.code
print(" ".join(sorted(sys.modules)), file=sys.stderr)
"""


@pytest.mark.parametrize(
    "args", [["--help"], ["reproduce", "--help"], ["excavator", "--help"], ["loader", "--help"]]
)
def test_help_imports_neither_numpy_pandas_nor_pint(args: list[str]) -> None:
    r = subprocess.run(
        [sys.executable, "-c", PROBE.format(args=args)], capture_output=True, text=True
    )
    assert r.returncode == 0, r.stderr
    loaded = set(r.stderr.split())
    assert "click" in loaded and "Commands:" in r.stdout
    assert [m for m in HEAVY if m in loaded] == []
    if args == ["--help"]:
        for name in ("check", "solve", "excavator", "loader", "reproduce"):
            assert f"\n  {name} " in r.stdout
        assert not any(m.startswith("excavkin.cli.commands.") for m in loaded)


def test_entry_points_are_read_once() -> None:
    entry_point_targets.cache_clear()
    for args in (["--help"], ["--help"], ["reproduce", "--help"]):
        assert CliRunner().invoke(main, args).exit_code == 0
    assert entry_point_targets.cache_info().misses == 1


def test_a_general_command_runs_without_reading_entry_points() -> None:
    entry_point_targets.cache_clear()
    r = CliRunner().invoke(main, ["check", "fourbar"])
    assert r.exit_code == 0, r.output
    assert entry_point_targets.cache_info().misses == 0


def test_the_unit_registry_is_built_on_first_use() -> None:
    probe = (
        "import sys, excavkin.units as u\n"
        "before = 'pint' in sys.modules\n"
        "from excavkin.units import ureg\n"
        "print(before, ureg is u.registry(), u.to_si('48 mm', 'length'), 'pint' in sys.modules)"
    )
    r = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["False", "True", "0.048", "True"]
    import excavkin.units

    with pytest.raises(AttributeError, match="no attribute 'registry_'"):
        excavkin.units.registry_  # noqa: B018
