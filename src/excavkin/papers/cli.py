"""``excavkin reproduce NAME``: re-run a source paper's study and write its tables and figures.

Each paper's package has a ``cli`` module with its command; this group names them and imports
one only when it is run or listed. To add a paper, add its package and a line here.
"""

from __future__ import annotations

import click

from excavkin.cli.common import LazyGroup

#: ``excavkin reproduce <name>`` → ``module:attribute``.
STUDIES = {
    "mo100": "excavkin.papers.mo100.cli:command",
    "pasika": "excavkin.papers.pasika.cli:command",
    "pasika-laws": "excavkin.papers.pasika.cli_laws:command",
    "rope-shovel": "excavkin.papers.rope_shovel.cli:command",
    "arm": "excavkin.papers.arm_vector.cli:command",
}


@click.group("reproduce", cls=LazyGroup, lazy=STUDIES)
def command() -> None:
    """Reproduce a source paper's study: print its tables, write its figures."""
