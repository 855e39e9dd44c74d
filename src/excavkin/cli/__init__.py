"""The ``excavkin`` command: a thin layer that parses arguments, calls the library and writes
files through `excavkin.outputs`.

The general commands live one per module in `excavkin.cli.commands`, each exposing a
``click.Command`` named ``command``. A wing (a paper, a machine family) adds its own group by an
entry point in the group ``excavkin.commands`` (see ``pyproject.toml``), so that the core never
imports a wing. A general command is imported only when it is run; a wing's group module is
light (no NumPy, no pint), as listing it imports it.
"""

from __future__ import annotations

import click

from excavkin import __version__
from excavkin.cli.lazy_group import Lazy, LazyGroup


def _core(name: str, summary: str) -> Lazy:
    return Lazy(f"excavkin.cli.commands.{name}:command", summary)


#: The general commands, by name, with the first sentence of each one's help (listed by
#: ``excavkin --help`` without importing the command; a test keeps them equal).
CORE_COMMANDS = {
    "check": _core(
        "check",
        "Validate MODEL (a .toml file or a built-in example's name); print bodies, joints, "
        "drivers, mobility and the solve plan.",
    ),
    "demo": _core(
        "demo",
        "Analyse a built-in model (the four-bar, a full crank turn at 300 rpm) and write its "
        "table (CSV) and its self-contained HTML report into OUT_DIR.",
    ),
    "optimize": _core(
        "optimize",
        "Find the design in STUDY.toml's parameter box that minimises or maximises its "
        "[optimize] objective (a metric) under its constraints: SLSQP with exact sensitivities, "
        "or differential evolution over whole populations solved as one batch; print the "
        "optimum and the constraints that bind.",
    ),
    "report": _core(
        "report",
        "Write a self-contained HTML report of MODEL (a .toml file or the name of a built-in "
        "example): the mechanism moving over a sweep (slider, play/pause), its main curves, the "
        "warnings (dead positions, non-closure, shocks), the model, its solve plan and the table.",
    ),
    "simulate": _core(
        "simulate",
        "Solve MODEL.toml over time with drivers moved by motion laws; write one row per time.",
    ),
    "solve": _core("solve", "Solve MODEL.toml over driver sweeps and write one row per sample."),
    "study": _core(
        "study",
        "Evaluate a design study: designs sampled in the box of STUDY.toml's parameter bounds "
        "(Sobol', Halton, Latin hypercube or a grid), each solved at every pose of its pose sets "
        "in one batch, its metrics reduced over the poses and its constraints checked; write one "
        "row per design to a Parquet table.",
    ),
    "tolerance": _core(
        "tolerance",
        "Bands of MODEL's columns over a sweep when its dimensions are made within --tol and its "
        "pins sit anywhere in their --clearance: the linear worst case and root-sum-square from "
        "exact sensitivities, and a Monte Carlo over --draws designs per sample solved as one "
        "batch over the geometry axis.",
    ),
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
