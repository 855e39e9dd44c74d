"""``excavkin check``: validate a model and print its structure and solve plan."""

from __future__ import annotations

import click

import excavkin
from excavkin.cli.common import handle_errors, model_path


@click.command("check")
@click.argument("model", type=click.Path(dir_okay=False))
@handle_errors
def command(model: str) -> None:
    """Validate MODEL (a .toml file or a built-in example's name); print bodies, joints,
    drivers, mobility and the solve plan."""
    mech = excavkin.load(model_path(model))
    click.echo(mech.describe())
    values = ", ".join(
        f"{k} = {v:.6g} {'rad' if mech.input_kind(k) == 'angle' else 'm'}"
        for k, v in mech.sketch_values().items()
    )
    click.echo(f"  sketch  : {values or 'no inputs'}")
    click.echo("ok: the model is valid and assembles at its sketch")
