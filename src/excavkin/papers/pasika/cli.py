"""``excavkin reproduce pasika``: Pasika & Koruniak's cylinder–rocker module, by the engine.

Runs ``examples/pasika_module.toml`` under the paper's cubic law (H = 0.5 m, T = 5 s), prints
what the paper publishes beside the engine's values, the spec's §4.3 table beside the
engine's, the agreement with the closed-form reference and with numerical differentiation
(the paper's 0.2 % check), and writes Fig. 3 and Fig. 5 as PNG.
"""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from excavkin.cli.common import handle_errors
from excavkin.papers.common import load_paper_model, text_table
from excavkin.papers.figures import save_png
from excavkin.papers.pasika.figures import pasika_fig3, pasika_fig5
from excavkin.papers.pasika.study import (
    PASIKA_DURATION,
    PASIKA_SPEC_TABLE,
    PASIKA_TIMES,
    pasika_derivative_agreement,
    pasika_published,
    pasika_reference_agreement,
    pasika_run,
)


@click.command("pasika")
@click.option(
    "--out-dir",
    default="excavkin-reproduce",
    show_default=True,
    type=click.Path(file_okay=False),
    help="Folder for pasika-fig3.png and pasika-fig5.png (regenerated each run).",
)
@click.option(
    "--samples",
    default=501,
    show_default=True,
    type=click.IntRange(11, 10**6),
    help="Samples over 0 <= t <= T.",
)
@handle_errors
def command(out_dir: str, samples: int) -> None:
    """Cylinder–rocker module with an internal driving link: φ, ω, ε of cylinder and rocker."""
    mech = load_paper_model("pasika_module")
    click.echo(
        "Pasika & Koruniak — cylinder–rocker module with an internal driving link\n"
        f"engine: {mech.model.source} (a = 0.45 m, b = 0.9 m, l_OA0 = 0.8 m, l_AB = 1.2 m), "
        "input: the cylinder length l_OA0 + s(t), cubic law H = 0.5 m, T = 5 s\n"
    )
    rows = [(p.quantity, p.published, p.ours) for p in pasika_published(mech)]
    click.echo("What the paper publishes (its Fig. 3 and Fig. 5 are lost; the text states):")
    click.echo(text_table(("quantity", "paper", "ours (engine)"), rows))

    at = pasika_run(np.array(PASIKA_TIMES), mech)
    click.echo(
        "\nSpec §4.3: the paper's equations with its data (the curves of its Fig. 5), "
        "beside the engine"
    )
    for link, name in (("1", "cylinder 1"), ("3", "rocker 3")):
        spec_rows = []
        for i, ti in enumerate(PASIKA_TIMES):
            row = [f"{ti:g}"]
            for q in ("phi", "omega", "eps"):
                key = q + link
                ours = float(at[key][i])
                if q == "phi":
                    row += [f"{PASIKA_SPEC_TABLE[key][i]:.4f}", f"{np.degrees(ours):.4f}"]
                else:
                    row += [f"{PASIKA_SPEC_TABLE[key][i]:+.5f}", f"{ours:+.5f}"]
            spec_rows.append(row)
        heads = [f"{name}: t [s]"]
        for q, unit in (("φ", "°"), ("ω", "1/s"), ("ε", "1/s²")):
            heads += [f"{q}{link} spec [{unit}]", "engine"]
        click.echo(text_table(heads, spec_rows))

    t = np.linspace(0.0, PASIKA_DURATION, samples)
    run = pasika_run(t, mech)
    ref = pasika_reference_agreement(run)
    fd = pasika_derivative_agreement(mech)
    click.echo(
        f"\nAgreement over {samples} samples, 0 <= t <= T (largest difference / largest value):"
    )
    click.echo(
        text_table(
            ("quantity", "engine vs reference eqs. (1)-(12)", "engine vs 8th-order differences"),
            [
                (k, f"{ref[k]:.1e}", f"{fd[k]:.1e}" if k in fd else "—")
                for k in ("phi1", "phi3", "omega1", "omega3", "eps1", "eps3")
            ],
        )
    )
    click.echo("(the paper: analytic vs numerical ω, ε within 0.2 %)")

    folder = Path(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    # the figures show the rod at rest just before and after the stroke: the soft shocks
    shown = pasika_run(np.round(np.linspace(-0.5, PASIKA_DURATION + 0.5, 601), 12), mech)
    f3 = save_png(pasika_fig3(shown).figure, folder / "pasika-fig3.png", force=True)
    f5 = save_png(
        pasika_fig5(shown, PASIKA_SPEC_TABLE, PASIKA_TIMES).figure,
        folder / "pasika-fig5.png",
        force=True,
    )
    click.echo(f"\nwrote {f3} and {f5}")
