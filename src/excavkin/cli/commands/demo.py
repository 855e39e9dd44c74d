"""``excavkin demo``: analyse the built-in default model and write its results and report."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

import excavkin
from excavkin.cli.common import handle_errors
from excavkin.errors import ExcavkinError
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
    help="Built-in example model to analyse (see `excavkin demo --list`).",
)
@click.option(
    "--list",
    "list_models",
    is_flag=True,
    help="List every built-in example by kind (models, machines, studies) and stop.",
)
@click.option("-q", "--quiet", is_flag=True, help="No progress.")
@handle_errors
def command(out_dir: str, model_name: str, list_models: bool, quiet: bool) -> None:
    """Analyse a built-in model (the four-bar, a full crank turn at 300 rpm) and write its
    table (CSV) and its self-contained HTML report into OUT_DIR."""
    from excavkin.default_sweep import default_sweep
    from excavkin.outputs.report import write_report

    if list_models:
        click.echo(_listing())
        return
    if model_name not in excavkin.examples("model"):
        raise ExcavkinError(
            f"--model: {model_name!r} is not a built-in model (built-in models: "
            f"{', '.join(excavkin.examples('model'))})"
        )
    path = excavkin.example_path(model_name)
    folder = Path(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    mech = excavkin.load(path)
    click.echo(mech.describe())
    if model_name == DEFAULT_MODEL:
        angles = mech.sketch_values()["crank"] + np.linspace(0.0, 2 * np.pi, 361)
        result = mech.solve({"crank": angles}, rates={"crank": 31.416})
    else:
        result = mech.solve(default_sweep(mech))
    table = write_table(result.to_frame(), folder / f"{path.stem}.csv", force=True)
    from excavkin.cli.progress import progress

    with progress("writing the report", quiet=quiet):
        report = write_report(mech, result, folder / f"{path.stem}-report.html", force=True)
    click.echo(f"\n{result.summary()}")
    for k, p in enumerate(result.plan.transmissions):
        mu = np.degrees(result.transmission[:, k])
        click.echo(f"transmission angle at {p}: {np.nanmin(mu):.2f}° … {np.nanmax(mu):.2f}°")
    click.echo(f"wrote {table}\nwrote {report} (open it in a browser)")


#: each kind of built-in example, with the commands that take it
_KINDS = (
    ("model", "models (excavkin check, solve, simulate, report, tolerance; demo --model)"),
    ("machine", "machines (each with its family's commands)"),
    ("study", "studies (excavkin study, optimize)"),
)


def _family(name: str) -> str:
    """The family a built-in machine file names (its ``family`` key, else the one that
    recognises it)."""
    import tomllib

    from excavkin.families import family_of

    path = excavkin.example_path(name)
    family = family_of(tomllib.loads(path.read_text("utf-8")), str(path))
    return family.name if family else "?"


def _study_machine(name: str) -> str | None:
    """The built-in machine a built-in study names (``[study] machine``), None for a model's."""
    import tomllib

    head = tomllib.loads(excavkin.example_path(name).read_text("utf-8")).get("study", {})
    machine = head.get("machine") if isinstance(head, dict) else None
    return machine if isinstance(machine, str) and machine in excavkin.examples("machine") else None


def _listing() -> str:
    """Every built-in example, by kind; a study of a machine is marked as one."""
    lines = []
    for kind, title in _KINDS:
        lines.append(f"{title}:")
        for name in excavkin.examples(kind):
            mark = ""
            machine = _study_machine(name) if kind == "study" else None
            if machine is not None:
                mark = f"  (a machine's: excavkin {_family(machine)} study)"
            if kind == "machine":
                mark = f"  (excavkin {_family(name)} …)"
            lines.append(f"  {name}{mark}")
    return "\n".join(lines)
