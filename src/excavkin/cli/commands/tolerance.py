"""``excavkin tolerance``: bands of every column over a sweep, from the dimensions' tolerances
and the pins' clearances (worst case, root-sum-square, Monte Carlo)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import click

from excavkin.cli.commands.solve import build_inputs, with_sweep_options
from excavkin.cli.common import backend_option, handle_errors, model_path, parse_assignment
from excavkin.errors import InputError

TABLE_SUFFIXES = (".csv", ".parquet")


#: the most Monte Carlo solves (draws × samples) a run may ask for: 10⁹, about half an hour for
#: a four-bar here
MAX_SOLVES = 10**9


@click.command("tolerance")
@click.argument("model", metavar="MODEL")
@with_sweep_options
@click.option(
    "--tol",
    "tols",
    multiple=True,
    metavar="NAME=±VALUE",
    help="Tolerance of a dimension (a parameter, see `excavkin check`), e.g. A-B=±0.1mm.",
)
@click.option(
    "--clearance",
    "clearances",
    multiple=True,
    metavar="VALUE|JOINT=VALUE",
    help="Radial pin clearance of every joint (0.05mm), or of one (B=0.05mm).",
)
@click.option(
    "--column",
    "columns",
    multiple=True,
    metavar="COLUMN",
    help="Band these columns (default: every kinematic column); the first few are printed.",
)
@click.option(
    "--draws",
    default=1_000_000,
    show_default=True,
    type=click.IntRange(0, 10**9),
    help="Monte Carlo designs per sample (0: the linear bands alone).",
)
@click.option("--seed", default=0, show_default=True, help="Seed of the random draws.")
@click.option(
    "--distribution",
    type=click.Choice(["normal", "uniform"]),
    default="normal",
    show_default=True,
    help="A dimension within its tolerance: normal with σ = tol/3 cut at ±tol, or uniform.",
)
@click.option(
    "--forces",
    "with_forces",
    is_flag=True,
    help="Also band the forces (joints, cylinders, driver torques) under the model's loads.",
)
@click.option("-o", "--out", type=click.Path(dir_okay=False), help="Bands table, .csv or .parquet.")
@click.option(
    "--plot",
    "plot_to",
    type=click.Path(dir_okay=False),
    help="Plot the first column's bands (.png, .svg, .pdf).",
)
@click.option("--force", is_flag=True, help="Replace output files that exist.")
@backend_option
@click.option("-q", "--quiet", is_flag=True, help="No progress.")
@handle_errors
def command(
    model: str,
    sweeps: tuple[str, ...],
    sets: tuple[str, ...],
    rates: tuple[str, ...],
    accels: tuple[str, ...],
    grid: bool,
    tols: tuple[str, ...],
    clearances: tuple[str, ...],
    columns: tuple[str, ...],
    draws: int,
    seed: int,
    distribution: str,
    with_forces: bool,
    out: str | None,
    plot_to: str | None,
    force: bool,
    backend: str,
    quiet: bool,
) -> None:
    """Bands of MODEL's columns over a sweep when its dimensions are made within --tol and its
    pins sit anywhere in their --clearance: the linear worst case and root-sum-square from
    exact sensitivities, and a Monte Carlo over --draws designs per sample solved as one batch
    over the geometry axis. Prints, per column, the largest half-width of each band and the
    dimension that matters most."""
    import excavkin
    from excavkin.backends import require
    from excavkin.outputs.tables import check_target, write_atomic, write_table
    from excavkin.studies.tolerance import summary_rows, tolerance_bands

    require(backend, f"--backend {backend}")
    table = check_target(out, force=force, suffixes=TABLE_SUFFIXES) if out else None
    figure = (
        check_target(plot_to, force=force, suffixes=(".png", ".svg", ".pdf")) if plot_to else None
    )
    mech = excavkin.load(model_path(model))
    values, rate_v, accel_v = build_inputs(mech, sweeps, sets, rates, accels, grid)
    tolerances = dict(parse_assignment(t, "--tol") for t in tols)
    if len(tolerances) < len(tols):
        twice = sorted(
            {
                n
                for n in (parse_assignment(t, "--tol")[0] for t in tols)
                if [parse_assignment(u, "--tol")[0] for u in tols].count(n) > 1
            }
        )
        raise InputError(f"--tol is given more than once for {', '.join(twice)}")
    clearance = _clearances(mech, clearances)
    import numpy as np

    n = max([int(np.size(v)) for v in values.values()] or [1])
    if draws * n > MAX_SOLVES:
        raise InputError(
            f"--draws {draws:,}: {draws:,} draws at each of {n:,} samples are "
            f"{draws * n:,} solves, more than {MAX_SOLVES:,} (about half an hour here); give "
            f"fewer --draws (at most {max(MAX_SOLVES // n, 0):,} for this sweep)"
        )
    from excavkin.cli.progress import compile_notes, staged

    stages = staged("Monte Carlo draws", 1, quiet=quiet or draws == 0)
    with compile_notes(quiet), stages as next_stage:
        bands = tolerance_bands(
            mech,
            values,
            rate_v,
            accel_v,
            tolerances=tolerances,
            clearance=clearance,
            columns=list(columns) or None,
            draws=draws,
            seed=seed,
            distribution=distribution,
            loads="model" if with_forces else None,
            progress=next_stage(),
            backend=backend,
        )
    shown = list(columns) or _widest(bands, 8)
    head = ["column (SI)", "worst case ±", "root-sum-square ±", "Monte Carlo ±", "matters most"]
    rows = [head, *summary_rows(bands, shown)]
    widths = [max(len(r[i]) for r in rows) for i in range(len(head))]
    for r in rows:
        click.echo("  ".join(cell.ljust(w) for cell, w in zip(r, widths, strict=True)).rstrip())
    if bands.motion and not quiet:
        click.echo(f"excavkin: note: {bands.motion.replace('no rate', 'no --rate')}", err=True)
    if bands.failed.any():
        click.echo(
            f"excavkin: warning: {int(bands.failed.sum()):,} Monte Carlo designs did not solve "
            "at their sample (left out of the Monte Carlo band)",
            err=True,
        )
    if table is not None:
        write_table(bands.to_frame(), table, force=force)
        n = bands.nominal.shape[0]
        click.echo(f"wrote {len(bands.columns)} columns × {n} samples of bands to {table}")
    if figure is not None:
        import matplotlib

        matplotlib.use("Agg")
        from excavkin.outputs.bands import plot_bands

        x, label = _abscissa(mech, values)
        fig = plot_bands(bands, shown[0], x, x_label=label).ax.get_figure(root=True)
        assert fig is not None
        fig.tight_layout()
        import matplotlib.pyplot as plt

        try:
            write_atomic(
                figure, lambda tmp: fig.savefig(tmp, dpi=110, format=Path(figure).suffix[1:])
            )
        finally:
            plt.close(fig)
        click.echo(f"wrote {figure}")


def _clearances(mech: Any, texts: tuple[str, ...]) -> Any:
    """``--clearance VALUE`` for every joint and ``--clearance JOINT=VALUE`` for one, the
    joint's own winning over the one for all; each at most once."""
    from excavkin.structure.design import joint_offsets

    every = [t for t in texts if "=" not in t]
    if len(every) > 1:
        raise InputError("--clearance for every joint is given more than once")
    own: dict[str, str] = {}
    for text in texts:
        if "=" in text:
            point, value = parse_assignment(text, "--clearance")
            if point in own:
                raise InputError(f"--clearance is given more than once for joint {point}")
            own[point] = value
    if not own:
        return every[0] if every else 0.0
    joints = sorted({name.partition("@")[0] for name in joint_offsets(mech.model)})
    default = every[0] if every else 0.0
    return {**dict.fromkeys(joints, default), **own}


def _abscissa(mech: Any, values: Mapping[str, Any]) -> tuple[Any, str]:
    """The first swept input, in degrees or millimetres, or the sample number."""
    import numpy as np

    for name, v in values.items():
        arr = np.asarray(v, dtype=np.float64)
        if arr.ndim == 1 and arr.size > 1:
            if mech.input_kind(name) == "angle":
                return np.degrees(arr), f"{name} [°]"
            return arr * 1e3, f"{name} [mm]"
    return None, "sample"


def _widest(bands: object, k: int) -> list[str]:
    """The k columns of length kind with the widest worst-case band (points' coordinates)."""
    import numpy as np

    cols = bands.columns  # type: ignore[attr-defined]
    worst = np.nanmax(bands.worst, axis=0)  # type: ignore[attr-defined]
    coords = [i for i, c in enumerate(cols) if c.endswith((".x", ".y"))]
    order = sorted(coords, key=lambda i: -worst[i])
    return [cols[i] for i in order[:k]] or list(cols[:k])
