"""``excavkin demo``: analyse the built-in default model and write its results."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

import excavkin
from excavkin.cli._common import handle_errors
from excavkin.outputs.tables import write_table

DEFAULT_MODEL = "fourbar"


@click.command("demo")
@click.option(
    "--out-dir",
    default="excavkin-demo",
    type=click.Path(file_okay=False),
    show_default=True,
    help="Folder for the demo's outputs (regenerated each run).",
)
@click.option(
    "--model",
    "model_name",
    default=DEFAULT_MODEL,
    show_default=True,
    help="Built-in example to analyse.",
)
@handle_errors
def command(out_dir: str, model_name: str) -> None:
    """Sweep the built-in four-bar through a full crank turn and write its results."""
    folder = Path(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    path = excavkin.example_path(model_name)
    mech = excavkin.load(path)
    click.echo(mech.describe())
    name = mech.inputs[0]
    n = 361
    if mech.input_kind(name) == "angle":
        start = mech.sketch_values()[name]
        values = start + np.linspace(0.0, 2 * np.pi, n)
        rate = 31.416
    else:
        s0 = mech.sketch_values()[name]
        values = np.linspace(0.9 * s0, 1.1 * s0, n)
        rate = 0.1
    result = mech.solve({name: values}, rates={name: rate})
    table = write_table(result.to_frame(), folder / f"{path.stem}.csv", force=True)
    click.echo(f"\n{result.status.summary()}")
    click.echo(f"wrote {table}")
    trans = np.degrees(result.transmission)
    if trans.size:
        for k, p in enumerate(result.plan.transmissions):
            click.echo(
                f"transmission angle at {p}: {np.nanmin(trans[:, k]):.2f}° … "
                f"{np.nanmax(trans[:, k]):.2f}°"
            )
