"""``excavkin reproduce pasika-laws``: the follow-up programme of Pasika & Koruniak.

Every motion law on the paper's cylinder–rocker module (a = 0.45 m, b = 0.9 m,
l_OA0 = 0.8 m, l_AB = 1.2 m, H = 0.5 m, T = 5 s): peaks and end values of the rod's
acceleration and of both links' ε, exact soft shocks, and how closely ε follows a21.
"""

from __future__ import annotations

from pathlib import Path

import click

from excavkin.cli.common import handle_errors
from excavkin.outputs.tables import write_atomic, write_table
from excavkin.papers.figures import save_png
from excavkin.papers.pasika.figures import law_comparison_figure
from excavkin.papers.pasika.laws import PASIKA_DURATION, PASIKA_STROKE, compare_laws

FIGURE_TITLE = (
    "Pasika & Koruniak module (a = 0.45, b = 0.9, l_OA0 = 0.8, l_AB = 1.2 m; H = 0.5 m, T = 5 s)"
)
TITLE = (
    "Pasika & Koruniak module (a = 0.45 m, b = 0.9 m, l_OA0 = 0.8 m, l_AB = 1.2 m), "
    "H = 0.5 m, T = 5 s: rod motion laws compared"
)


@click.command("pasika-laws")
@click.option(
    "--out-dir",
    default="excavkin-reproduce",
    show_default=True,
    type=click.Path(file_okay=False),
    help="Folder for pasika-laws.png/.csv/.md (regenerated each run).",
)
@click.option(
    "--intervals",
    default=1000,
    show_default=True,
    type=click.IntRange(10, 10**6),
    help="Samples per stroke time T.",
)
@handle_errors
def command(out_dir: str, intervals: int) -> None:
    """Compare all motion laws on the paper's module; find which remove the soft shocks."""
    folder = Path(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    study = compare_laws(intervals=intervals, stroke=PASIKA_STROKE, duration=PASIKA_DURATION)
    click.echo(TITLE)
    click.echo(
        "SI units: a21 in m/s², ε1 (cylinder) and ε3 (rocker) in rad/s²; J·|ε3| with the "
        "illustrative rocker J = 120 kg·m² (1000 kg, 1.2 m bar)\n"
    )
    click.echo(study.text())
    free = [r.law for r in study.rows if r.shock_free]
    shocky = [
        f"{r.law} ({r.rod_soft} on the rod, {r.link_soft} on the links)"
        for r in study.rows
        if not r.shock_free
    ]
    click.echo(f"\nno soft shocks: {', '.join(free) or 'none'}")
    click.echo(f"soft shocks: {', '.join(shocky) or 'none'}")
    g = study.gains
    click.echo(
        f"at rest ε = u'(s)·a21 for every law: ε1/a21 = {g[0, 0]:.4f} at s = 0 and "
        f"{g[1, 0]:.4f} at s = H; ε3/a21 = {g[0, 1]:.4f} and {g[1, 1]:.4f}"
    )
    png = save_png(
        law_comparison_figure(study, title=FIGURE_TITLE).figure,
        folder / "pasika-laws.png",
        force=True,
    )
    csv = write_table(study.to_frame(), folder / "pasika-laws.csv", force=True)

    def markdown(tmp: Path) -> None:
        tmp.write_text(study.markdown(), encoding="utf-8")

    md = write_atomic(folder / "pasika-laws.md", markdown)
    click.echo(f"\nwrote {png}, {csv} and {md}")
