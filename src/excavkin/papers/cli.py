"""``excavkin reproduce NAME``: re-run a source paper's study and write its tables and figures.

Each paper's package has a ``cli`` module with its command; this group names them, with each
one's help line, and imports one only when it is run. To add a paper, add its package and a line
here. This module is the wing's entry point and stays light: ``excavkin --help`` imports it.
"""

from __future__ import annotations

import click

from excavkin.cli.lazy_group import Lazy, LazyGroup

#: ``excavkin reproduce <name>`` → its ``module:attribute`` and the first sentence of its help.
STUDIES = {
    "mo100": Lazy(
        "excavkin.papers.mo100.cli:command",
        "MO-100 crank-rocker hammer: inertia loads, reactions on the housing, half-sine fit.",
    ),
    "pasika": Lazy(
        "excavkin.papers.pasika.cli:command",
        "Cylinder–rocker module with an internal driving link: φ, ω, ε of cylinder and rocker.",
    ),
    "pasika-laws": Lazy(
        "excavkin.papers.pasika.cli_laws:command",
        "Compare all motion laws on the paper's module; find which remove the soft shocks.",
    ),
    "rope-shovel": Lazy(
        "excavkin.papers.rope_shovel.cli:command",
        "Rope-shovel bucket rotation: drag rope → stick, two four-bars, Ц2 locked, Ц1 free.",
    ),
    "arm": Lazy(
        "excavkin.papers.arm_vector.cli:command",
        "Excavator arm vector model: forward, inverse (both solutions), cylinder relations.",
    ),
}


@click.group("reproduce", cls=LazyGroup, lazy=STUDIES)
def command() -> None:
    """Reproduce a source paper's study: print its tables, write its figures."""
