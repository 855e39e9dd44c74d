"""``excavkin excavator MACHINE.toml ranges|forces|ik``: an excavator front's spec sheet."""

from __future__ import annotations

import click
import numpy as np

from excavkin.cli._common import handle_errors, si_value


def _machine(path: str):  # type: ignore[no-untyped-def]
    from excavkin.io.machine import load_machine

    return load_machine(path)


def _save_png(fig, path: str, force: bool) -> None:  # type: ignore[no-untyped-def]
    from excavkin.outputs.tables import check_target, write_atomic

    target = check_target(path, force=force, suffixes=(".png", ".svg", ".pdf"))
    write_atomic(target, lambda tmp: fig.savefig(tmp, dpi=100, format=target.suffix[1:]))
    click.echo(f"wrote {target}")


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
    import pandas as pd

    from excavkin.applications.excavator_ranges import working_ranges
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
                "value_m": f.value,
                "x_m": f.tip[0],
                "y_m": f.tip[1],
                "boom_m": f.lengths[0],
                "arm_m": f.lengths[1],
                "bucket_m": f.lengths[2],
                "bucket_angle_rad": f.bucket_angle,
                "orientation": f.orientation,
            }
        )
    if output:
        click.echo(f"wrote {write_table(pd.DataFrame(rows), output, force=force)}")
    if envelope:
        frame = pd.DataFrame({"x_m": wr.envelope[:, 0], "y_m": wr.envelope[:, 1]})
        click.echo(f"wrote {write_table(frame, envelope, force=force)}")
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        from excavkin.outputs.excavator_plots import plot_working_range

        _save_png(plot_working_range(m, wr).figure, plot, force)


@command.command("forces")
@click.argument("machine", type=click.Path(dir_okay=False))
@click.option(
    "--samples", default=31, show_default=True, help="Grid points per stroke of the sweep."
)
@click.option("--no-gravity", is_flag=True, help="Leave out the weight of the front.")
@click.option(
    "--map",
    "map_prefix",
    type=click.Path(dir_okay=False),
    help="Write force-map PNGs PREFIX-arm.png and PREFIX-bucket.png.",
)
@click.option("--force", is_flag=True, help="Replace output files that exist.")
@handle_errors
def forces(
    machine: str, samples: int, no_gravity: bool, map_prefix: str | None, force: bool
) -> None:
    """Print the maximum ISO 6015 (lip) and SAE J1179 (tooth tip) tool forces."""
    from excavkin.applications.excavator_forces import force_maximum, tool_forces
    from excavkin.applications.excavator_ranges import sweep

    if samples < 2:
        raise click.BadParameter("at least 2", param_hint="--samples")
    m = _machine(machine)
    pose = sweep(m, samples)
    grav = not no_gravity
    click.echo(
        f"{m.name} — maximum tool forces over a {samples}³ stroke sweep "
        f"({'with' if grav else 'without'} gravity of the front)"
    )
    click.echo(
        f"{'standard':<10} {'cylinder':<8} {'force kN':>9}  {'x mm':>7} {'y mm':>7}  "
        f"{'boom':>6} {'arm':>6} {'bucket':>6}  limited by"
    )
    maps = {}
    for at, std in (("lip", "ISO 6015"), ("tip", "SAE J1179")):
        for working in ("arm", "bucket"):
            tf = tool_forces(m, pose.lengths, working, at=at, gravity=grav)  # type: ignore[arg-type]
            mx = force_maximum(tf)
            lim = mx.limiting + (" (working pressure)" if mx.limiting == working else " (relief)")
            click.echo(
                f"{std:<10} {working:<8} {mx.force / 1e3:9.1f}  {mx.point[0] * 1e3:7.0f} "
                f"{mx.point[1] * 1e3:7.0f}  {mx.lengths[0] * 1e3:6.0f} "
                f"{mx.lengths[1] * 1e3:6.0f} {mx.lengths[2] * 1e3:6.0f}  {lim}"
            )
            if at == "lip":
                maps[working] = tf
    if map_prefix:
        import matplotlib

        matplotlib.use("Agg")
        from excavkin.outputs.excavator_plots import plot_force_map

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
    from excavkin.applications.excavator import BRANCHES, forward, inverse

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
