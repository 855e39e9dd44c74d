"""``excavkin excavator MACHINE.toml ranges|forces|ik``: an excavator front's spec sheet.

The wing's entry point: ``excavkin --help`` imports this module, so the heavy modules (NumPy,
the machine, pint) are imported inside the commands.
"""

from __future__ import annotations

import math

import click

from excavkin.cli.common import handle_errors, model_path, si_value


def _machine(path: str):  # type: ignore[no-untyped-def]
    from excavkin.excavator.machine_file import load_machine

    return load_machine(model_path(path, "machine"))


def _save_png(fig, path: str, force: bool) -> None:  # type: ignore[no-untyped-def]
    from excavkin.outputs.tables import check_target, write_atomic

    target = check_target(path, force=force, suffixes=(".png", ".svg", ".pdf"))
    write_atomic(target, lambda tmp: fig.savefig(tmp, dpi=100, format=target.suffix[1:]))
    click.echo(f"wrote {target}")


#: kinds of the excavator tables' columns (SI, plain names, like every excavkin table)
TABLE_KINDS = {
    **dict.fromkeys(("value", "x", "y", "boom", "arm", "bucket", "radius"), "length"),
    "bucket_angle": "angle",
    **dict.fromkeys(("force", "own_limit"), "force"),
    "moment": "torque",
}


def _si_table(rows, model: str):  # type: ignore[no-untyped-def]
    """Rows as a table whose attrs record each column's kind (its unit in a file)."""
    import pandas as pd

    from excavkin.kinematics.columns import kinds_attrs

    frame = pd.DataFrame(rows)
    frame.attrs.update(kinds_attrs(model, {c: k for c, k in TABLE_KINDS.items() if c in frame}))
    return frame


def _mm(v: float) -> str:
    return f"{round(v * 1000) + 0.0:8.0f}"


@click.group("excavator", context_settings={"help_option_names": ["-h", "--help"]})
def command() -> None:
    """Working ranges, tool forces and inverse kinematics of an excavator MACHINE file."""


@command.command("ranges")
@click.argument("machine", type=click.Path(dir_okay=False))
@click.option("--plot", "plot", type=click.Path(dir_okay=False), help="Working-range PNG.")
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    help="The figures as a table (.csv or .parquet).",
)
@click.option(
    "--envelope",
    type=click.Path(dir_okay=False),
    help="The envelope polygon as a table (x_m, y_m).",
)
@click.option("--force", is_flag=True, help="Replace output files that exist.")
@handle_errors
def ranges(
    machine: str, plot: str | None, output: str | None, envelope: str | None, force: bool
) -> None:
    """Print the working-range figures (mm) and the cylinder lengths where they occur."""

    from excavkin.excavator.ranges import working_ranges
    from excavkin.outputs.tables import check_target, write_table

    for p in (output, envelope):
        if p:
            check_target(p, force=force, suffixes=(".csv", ".parquet"))
    m = _machine(machine)
    wr = working_ranges(m)
    click.echo(f"{m.name} — working ranges (tooth tip; mm)")
    click.echo(
        f"{'':4} {'figure':<38} {'value':>8}  {'x':>8} {'y':>8}  "
        f"{'boom':>7} {'arm':>7} {'bucket':>7}  bucket orientation"
    )
    rows = []
    for f in wr.figures:
        click.echo(
            f"{f.code:4} {f.label:<38} {_mm(f.value)}  {_mm(f.tip[0])} {_mm(f.tip[1])}  "
            f"{f.lengths[0] * 1e3:7.0f} {f.lengths[1] * 1e3:7.0f} "
            f"{f.lengths[2] * 1e3:7.0f}  {f.orientation}"
        )
        rows.append(
            {
                "key": f.key,
                "code": f.code,
                "label": f.label,
                "value": f.value,
                "x": f.tip[0],
                "y": f.tip[1],
                "boom": f.lengths[0],
                "arm": f.lengths[1],
                "bucket": f.lengths[2],
                "bucket_angle": f.bucket_angle,
                "orientation": f.orientation,
            }
        )
    if output:
        click.echo(f"wrote {write_table(_si_table(rows, m.name), output, force=force)}")
    if envelope:
        frame = _si_table({"x": wr.envelope[:, 0], "y": wr.envelope[:, 1]}, m.name)
        click.echo(f"wrote {write_table(frame, envelope, force=force)}")
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        from excavkin.excavator.plots import plot_working_range

        _save_png(plot_working_range(m, wr).figure, plot, force)


@command.command("forces")
@click.argument("machine", type=click.Path(dir_okay=False))
@click.option(
    "--samples", default=31, show_default=True, help="Grid points per stroke of the sweep."
)
@click.option("--no-gravity", is_flag=True, help="Leave the weight of the front out of the sweep.")
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    help="The rated forces and the sweep's maxima as a table (.csv or .parquet).",
)
@click.option(
    "--map",
    "map_prefix",
    type=click.Path(dir_okay=False),
    help="Write force-map PNGs PREFIX-arm.png and PREFIX-bucket.png.",
)
@click.option("--force", is_flag=True, help="Replace output files that exist.")
@handle_errors
def forces(
    machine: str,
    samples: int,
    no_gravity: bool,
    output: str | None,
    map_prefix: str | None,
    force: bool,
) -> None:
    """Print the rated ISO 6015 (lip) and SAE J1179 (tooth tip) tool forces, and the largest
    over a sweep of the strokes."""

    from excavkin.excavator.forces import (
        ForceMaximum,
        RatedForce,
        force_maximum,
        rated_force,
        tool_forces,
    )
    from excavkin.excavator.ranges import sweep
    from excavkin.outputs.tables import check_target, write_table

    if samples < 2:
        raise click.BadParameter("at least 2", param_hint="--samples")
    if output:
        check_target(output, force=force, suffixes=(".csv", ".parquet"))
    if map_prefix:
        for working in ("arm", "bucket"):
            check_target(f"{map_prefix}-{working}.png", force=force, suffixes=(".png",))
    m = _machine(machine)
    grav = not no_gravity
    kinds = (("lip", "ISO 6015"), ("tip", "SAE J1179"))
    rows = []

    def row(kind: str, std: str, gravity: bool, r: RatedForce | ForceMaximum) -> None:
        lim = r.limiting + (" (working pressure)" if r.limiting == r.working else " (relief)")
        click.echo(
            f"{std:<10} {r.working:<8} {r.force / 1e3:7.1f} {r.uncapped / 1e3:7.1f}  "
            f"{r.point[0] * 1e3:6.0f} {r.point[1] * 1e3:6.0f}  {r.lengths[0] * 1e3:6.0f} "
            f"{r.lengths[1] * 1e3:6.0f} {r.lengths[2] * 1e3:6.0f}  {lim}"
        )
        moment, radius = (r.moment, r.radius) if isinstance(r, RatedForce) else (math.nan, math.nan)
        rows.append(
            {
                "kind": kind,
                "standard": std,
                "cylinder": r.working,
                "gravity": gravity,
                "force": r.force,
                "own_limit": r.uncapped,
                "moment": moment,
                "radius": radius,
                "x": r.point[0],
                "y": r.point[1],
                "boom": r.lengths[0],
                "arm": r.lengths[1],
                "bucket": r.lengths[2],
                "limited_by": r.limiting,
            }
        )

    click.echo(f"{m.name} — tool forces (kN; positions mm)")
    click.echo(
        "Rated: bucket at its cylinder's largest moment, stick at the arm cylinder's "
        "(ISO 6015 §5.2, SAE J1179 §3.3); no gravity"
    )
    click.echo(
        f"{'standard':<10} {'cylinder':<8} {'force':>7} {'own':>7}  {'x':>6} {'y':>6}  "
        f"{'boom':>6} {'arm':>6} {'bucket':>6}  limited by"
    )
    for at, std in kinds:
        for working in ("arm", "bucket"):
            row("rated", std, False, rated_force(m, working, at=at))  # type: ignore[arg-type]
    pose = sweep(m, samples)
    click.echo(
        f"Largest over a {samples}³ stroke sweep ({'with' if grav else 'without'} gravity "
        "of the front)"
    )
    maps = {}
    for at, std in kinds:
        for working in ("arm", "bucket"):
            tf = tool_forces(m, pose.lengths, working, at=at, gravity=grav)  # type: ignore[arg-type]
            row("sweep_max", std, grav, force_maximum(tf))
            if at == "lip":
                maps[working] = tf
    click.echo("force: capped by the holding cylinders' reliefs; own: the working cylinder's limit")
    if output:
        click.echo(f"wrote {write_table(_si_table(rows, m.name), output, force=force)}")
    if map_prefix:
        import matplotlib

        matplotlib.use("Agg")
        from excavkin.excavator.plots import plot_force_map

        for working, tf in maps.items():
            _save_png(plot_force_map(m, tf).figure, f"{map_prefix}-{working}.png", force)


@command.command("ik")
@click.argument("machine", type=click.Path(dir_okay=False))
@click.option("--x", "x", required=True, help="Tip reach from the swing axis, e.g. 7m.")
@click.option("--y", "y", required=True, help="Tip height above the ground line, e.g. -1.5m.")
@click.option(
    "--angle",
    "angle",
    default="-90deg",
    show_default=True,
    help="Bucket angle: direction of bucket pin → tip, CCW from +x.",
)
@handle_errors
def ik(machine: str, x: str, y: str, angle: str) -> None:
    """Cylinder lengths that put the tooth tip at (X, Y) with the given bucket angle."""
    import numpy as np

    from excavkin.excavator.machine import BRANCHES, forward, inverse

    m = _machine(machine)
    tip = np.array(
        [
            [
                si_value(x, "length", "--x") + m.swing_axis,
                si_value(y, "length", "--y") + m.ground_line,
            ]
        ]
    )
    beta = si_value(angle, "angle", "--angle")
    sol = inverse(m, tip, np.array([beta]))
    click.echo(
        f"{m.name} — tip at x = {tip[0, 0] * 1e3:.0f} mm, y = {tip[0, 1] * 1e3:.0f} mm, "
        f"bucket angle {np.degrees(beta):.2f}°"
    )
    click.echo(f"{'branch':<14} {'boom mm':>9} {'arm mm':>9} {'bucket mm':>9}  status")
    lo, hi = m.lengths_min, m.lengths_max
    for k, (s1, s2) in enumerate(BRANCHES):
        L = sol.lengths[0, k]
        name = f"pivot{'+' if s1 > 0 else '−'} link{'+' if s2 > 0 else '−'}"
        if not sol.reachable[0, k]:
            click.echo(f"{name:<14} {'—':>9} {'—':>9} {'—':>9}  out of reach")
            continue
        notes = []
        for c, role in enumerate(("boom", "arm", "bucket")):
            if L[c] < lo[c] - 1e-9 or L[c] > hi[c] + 1e-9:
                notes.append(f"{role} beyond stroke ({lo[c] * 1e3:.0f}–{hi[c] * 1e3:.0f})")
        if not sol.model_branch[0, k]:
            notes.append("other assembly branch")
        status = "; ".join(notes) or "valid"
        click.echo(f"{name:<14} {L[0] * 1e3:9.1f} {L[1] * 1e3:9.1f} {L[2] * 1e3:9.1f}  {status}")
    if sol.valid[0].any():
        k = int(np.argmax(sol.valid[0]))
        fk = forward(m, sol.lengths[0, k][None, :])
        err = float(np.hypot(*(fk.tip[0] - tip[0])))
        click.echo(
            f"check: forward kinematics of the first valid solution is {err:.1e} m from the target"
        )
    else:
        click.echo("no valid solution: the pose is out of the working range")
