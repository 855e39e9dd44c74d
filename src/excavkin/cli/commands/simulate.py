"""``excavkin simulate``: run a mechanism in time, drivers moved by motion laws.

Drive syntax (``--drive``, repeatable; values may carry units, bare numbers are SI)::

    NAME=LAW:STROKE:DURATION[:start=T0][:from=Q0][:PARAM=VALUE ...]
        LAW one of excavkin.motion.LAW_NAMES; PARAM: accel_fraction, jerk_fraction,
        v_max, a_max, j_max (DURATION "auto" for s-curve with v_max, a_max, j_max)
    NAME=crank:OMEGA[:from=PHI0]                  rotary driver at constant speed
    NAME=winch:motor=W:drum=R:gear=I[:blocks=N][:start=T0][:from=L0]
        linear driver (rope) hauled in at v = W·R/(I·N): its length L0 − v·(t − T0)

A driver given several law drives runs them one after the other (sorted by start, holding in
the gaps). Drivers without a drive stay at their sketch values, or where --set puts them.
"""

from __future__ import annotations

from collections.abc import Sequence

import click
import numpy as np

import excavkin
from excavkin.cli.commands.solve import report_failures
from excavkin.cli.common import (
    ACCEL_KIND,
    JERK_KIND,
    RATE_KIND,
    check_count,
    handle_errors,
    model_path,
    parse_assignment,
    si_value,
    units_row_option,
)
from excavkin.errors import InputError
from excavkin.mechanism import Mechanism
from excavkin.motion import (
    LAW_NAMES,
    ConstantSpeedCrank,
    MotionLaw,
    Profile,
    RopeWinch,
    Segment,
    dwell,
    get_law,
)
from excavkin.outputs.tables import TABLE_SUFFIXES, check_target, write_table
from excavkin.simulation.shocks import shock_report
from excavkin.simulation.timeline import Drive, simulate

#: the most time samples a run may have (10⁷: a few minutes; a longer run is a
#: ``excavkin solve --inputs`` table, streamed)
MAX_TIME_SAMPLES = 10**7

_FRACTIONS = ("accel_fraction", "jerk_fraction")


def _options(parts: Sequence[str], what: str) -> dict[str, str]:
    out: dict[str, str] = {}
    for p in parts:
        key, sep, val = p.partition("=")
        if not sep or not key.strip() or not val.strip():
            raise InputError(f"{what}: expected KEY=VALUE after the fixed fields, got {p!r}")
        if key.strip() in out:
            raise InputError(f"{what}: {key.strip()!r} given twice")
        out[key.strip()] = val.strip()
    return out


def parse_drive(mech: Mechanism, text: str) -> tuple[str, MotionLaw | Drive]:
    """Read one ``--drive`` text.

    Returns
    -------
    name : str
    law_or_drive : MotionLaw or Drive
        A bare law (with its ``start``; ``from=`` is then returned as a Drive with the law) or a
        crank / winch [`Drive`][excavkin.simulation.timeline.Drive].
    """
    name, spec = parse_assignment(text, "--drive")
    what = f"--drive {name}"
    kind = mech.input_kind(name)
    parts = [p.strip() for p in spec.split(":")]
    head = parts[0]
    if head == "crank":
        if len(parts) < 2:
            raise InputError(f"{what}: a crank is crank:OMEGA[:from=PHI0]")
        omega = si_value(parts[1], "angular_velocity", what)
        opts = _options(parts[2:], what)
        unknown = set(opts) - {"from"}
        if unknown:
            raise InputError(f"{what}: a crank takes only from=, not {', '.join(sorted(unknown))}")
        init = si_value(opts["from"], kind, what) if "from" in opts else None
        try:
            return name, Drive(ConstantSpeedCrank(omega), initial=init)
        except ValueError as exc:
            raise InputError(f"{what}: {exc}") from None
    if head == "winch":
        opts = _options(parts[1:], what)
        need = {"motor", "drum", "gear"}
        if not need <= set(opts):
            raise InputError(
                f"{what}: a winch is winch:motor=W:drum=R:gear=I[:blocks=N]"
                f"[:start=T0][:from=L0]; missing {', '.join(sorted(need - set(opts)))}"
            )
        unknown = set(opts) - need - {"blocks", "start", "from"}
        if unknown:
            raise InputError(f"{what}: unknown winch option(s) {', '.join(sorted(unknown))}")
        try:
            winch = RopeWinch(
                si_value(opts["motor"], "angular_velocity", what),
                si_value(opts["drum"], "length", what),
                si_value(opts["gear"], "dimensionless", what),
                si_value(opts.get("blocks", "1"), "dimensionless", what),
                start=si_value(opts.get("start", "0"), "time", what),
            )
        except ValueError as exc:
            raise InputError(f"{what}: {exc}") from None
        init = si_value(opts["from"], kind, what) if "from" in opts else None
        try:
            return name, Drive(winch, initial=init)
        except ValueError as exc:
            raise InputError(f"{what}: {exc}") from None
    if len(parts) < 3:
        raise InputError(
            f"{what}: a law drive is LAW:STROKE:DURATION[:start=T0][:from=Q0]"
            f"[:PARAM=VALUE], LAW one of {', '.join(LAW_NAMES)}, crank or winch"
        )
    law_name = head
    stroke = si_value(parts[1], kind, what)
    duration = None if parts[2].lower() == "auto" else si_value(parts[2], "time", what)
    opts = _options(parts[3:], what)
    params: dict[str, float] = {}
    init = None
    for key, val in opts.items():
        if key == "from":
            init = si_value(val, kind, what)
        elif key == "start":
            params[key] = si_value(val, "time", what)
        elif key in _FRACTIONS:
            params[key] = si_value(val, "dimensionless", what)
        elif key == "v_max":
            params[key] = si_value(val, RATE_KIND[kind], what)
        elif key == "a_max":
            params[key] = si_value(val, ACCEL_KIND[kind], what)
        elif key == "j_max":
            params[key] = si_value(val, JERK_KIND[kind], what)
        else:
            raise InputError(
                f"{what}: unknown option {key!r} (start, from, accel_fraction, "
                "jerk_fraction, v_max, a_max, j_max)"
            )
    try:
        law = get_law(law_name, stroke, duration, **params)
        return name, (law if init is None else Drive(law, initial=init))
    except (ValueError, TypeError) as exc:
        raise InputError(f"{what}: {exc}") from None


def build_drives(mech: Mechanism, texts: Sequence[str]) -> dict[str, Drive]:
    """Turn ``--drive`` texts into drives; several law drives of one driver are chained.

    Raises
    ------
    InputError
        Bad syntax, unknown driver or law, overlapping laws, a crank or winch combined with
        another drive of the same driver, or ``from=`` on a later law.
    """
    if not texts:
        raise InputError("give at least one --drive NAME=LAW:STROKE:DURATION")
    grouped: dict[str, list[MotionLaw | Drive]] = {}
    for text in texts:
        name, item = parse_drive(mech, text)
        grouped.setdefault(name, []).append(item)
    drives: dict[str, Drive] = {}
    for name, items in grouped.items():
        if len(items) == 1:
            it = items[0]
            drives[name] = it if isinstance(it, Drive) else Drive(it)
            continue
        init: float | None = None
        init_start = 0.0
        laws: list[MotionLaw] = []
        for it in items:
            law = it.law if isinstance(it, Drive) else it
            if not isinstance(law, MotionLaw):
                raise InputError(
                    f"--drive {name}: a crank or winch cannot be combined with "
                    "other drives of the same driver"
                )
            if isinstance(it, Drive) and it.initial is not None:
                if init is not None:
                    raise InputError(f"--drive {name}: from= given twice")
                init, init_start = it.initial, law.start
            laws.append(law)
        laws.sort(key=lambda law: law.start)
        if init is not None and init_start != laws[0].start:
            raise InputError(f"--drive {name}: from= belongs on the earliest law")
        segs: list[Segment] = []
        offset, t_end = 0.0, laws[0].start
        for law in laws:
            gap = law.start - t_end
            tol = 1e-12 * max(1.0, abs(t_end))
            if gap < -tol:
                raise InputError(
                    f"--drive {name}: a law starting at t = {law.start:g} s overlaps "
                    f"the previous one, which ends at t = {t_end:g} s"
                )
            if gap > tol:
                segs.append(Segment(dwell(gap, start=t_end), offset))
            segs.append(Segment(law, offset))
            offset += law.stroke
            t_end = law.end
        try:
            drives[name] = Drive(Profile(tuple(segs)), initial=init)
        except ValueError as exc:
            raise InputError(f"--drive {name}: {exc}") from None
    return drives


@click.command("simulate")
@click.argument("model", type=click.Path(dir_okay=False))
@click.option(
    "--drive",
    "drive_texts",
    multiple=True,
    required=True,
    metavar="NAME=LAW:STROKE:DURATION[:start=…][:from=…]",
    help="Move a driver by a motion law, e.g. cyl=cubic:0.5m:5s, "
    "boom=345:200mm:2s:start=1s, crank=crank:31.416rad/s, "
    "rope=winch:motor=1000rpm:drum=0.4m:gear=20:blocks=2. Repeatable.",
)
@click.option(
    "--samples",
    default=501,
    show_default=True,
    type=int,
    help="Number of time samples (2 to 10⁷, and as many as fit in memory).",
)
@click.option(
    "--duration",
    default=None,
    metavar="TIME",
    help="Length of the time grid, e.g. 6s (default: up to the last law's end).",
)
@click.option(
    "--start",
    "t_start",
    default=None,
    metavar="TIME",
    help="First time of the grid (default: the first law's start).",
)
@click.option(
    "-o",
    "--out",
    required=True,
    type=click.Path(dir_okay=False),
    help="Output table, .csv or .parquet, with a time column t.",
)
@click.option(
    "--shocks/--no-shocks",
    default=True,
    show_default=True,
    help="Print the shock report (exact velocity and acceleration jumps, peaks).",
)
@click.option(
    "--shock-table",
    default=None,
    type=click.Path(dir_okay=False),
    help="Also write the shocks as a table (.csv or .parquet).",
)
@click.option(
    "--set",
    "sets",
    multiple=True,
    metavar="NAME=VALUE",
    help="Hold a driver without a drive at VALUE (default: its sketch value), e.g. "
    "arm_cyl=2.5m. Repeatable.",
)
@click.option(
    "--keep-going",
    is_flag=True,
    help="Write the table even if some samples fail (rows marked in 'status').",
)
@click.option("--force", is_flag=True, help="Replace output files that exist.")
@units_row_option
@click.option("-q", "--quiet", is_flag=True, help="No progress.")
@handle_errors
def command(
    model: str,
    drive_texts: tuple[str, ...],
    samples: int,
    duration: str | None,
    t_start: str | None,
    out: str,
    shocks: bool,
    shock_table: str | None,
    sets: tuple[str, ...],
    keep_going: bool,
    force: bool,
    units_row: bool,
    quiet: bool,
) -> None:
    """Solve MODEL.toml over time with drivers moved by motion laws; write one row per time.

    Columns (SI: m, rad, s): t, <point>.x .y .vx .vy .ax .ay, <body>.angle .omega .epsilon,
    <driver>.value .rate .accel, <point>.transmission, status. Rates and accelerations come
    from the laws exactly. The shock report lists, for every driver and body, the jumps of
    velocity (hard shocks) and acceleration (soft shocks) at the laws' breakpoints, and the
    peaks of ε (with J·ε where the model gives a body's inertia).
    """
    target = check_target(out, force=force, suffixes=TABLE_SUFFIXES)
    shock_target = (
        check_target(shock_table, force=force, suffixes=TABLE_SUFFIXES) if shock_table else None
    )
    if shock_target is not None and shock_target.resolve() == target.resolve():
        raise InputError("--out and --shock-table name the same file")
    mech = excavkin.load(model_path(model))
    # the whole run is held at once: about 40 bytes per column and sample
    columns = 6 * len(mech.plan.points) + 3 * len(mech.model.bodies) + 4 * len(mech.inputs) + 2
    check_count(samples, "--samples", least=2, most=MAX_TIME_SAMPLES,
                bytes_per_sample=40 * columns, what="time samples")  # fmt: skip
    drives = build_drives(mech, drive_texts)
    held: dict[str, float] = {}
    for text in sets:
        name, spec = parse_assignment(text, "--set")
        if name in held:
            raise InputError(f"--set is given more than once for {name}")
        held[name] = si_value(spec, mech.input_kind(name), f"--set {name}")
    dur = si_value(duration, "time", "--duration") if duration is not None else None
    t0 = si_value(t_start, "time", "--start") if t_start is not None else None
    from excavkin.cli.progress import MIN_SAMPLES_FOR_BAR, progress, staged

    long = samples >= MIN_SAMPLES_FOR_BAR
    with staged("solving", 1, quiet=quiet or not long) as next_stage:
        result = simulate(
            mech, drives, samples=samples, duration=dur, start=t0, held=held,
            progress=next_stage(),
        )  # fmt: skip
    report_failures(result, keep_going)
    frame = result.to_frame()
    with progress("writing the table", quiet=quiet or not long):
        write_table(frame, target, force=force, units_row=units_row)
    t = np.asarray(result.time)
    click.echo(
        f"wrote {len(result)} samples × {frame.shape[1]} columns "
        f"(t = {t[0]:g} … {t[-1]:g} s) to {target}"
    )
    if shocks or shock_target is not None:
        with progress("finding the shocks", quiet=quiet or not long):
            rep = shock_report(mech, drives, result, held=held)
        if shocks:
            click.echo(rep.format())
        if shock_target is not None:
            write_table(rep.to_frame(), shock_target, force=force)
            click.echo(f"wrote {len(rep.shocks)} shocks to {shock_target}")
