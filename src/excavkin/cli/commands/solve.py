"""``excavkin solve``: sweep drivers and write every point's and body's kinematics."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import click
import numpy as np

import excavkin
from excavkin.cli.common import (
    ACCEL_KIND,
    EXIT_SAMPLES,
    RATE_KIND,
    check_samples,
    fail,
    handle_errors,
    model_path,
    parse_assignment,
    parse_sweep,
    si_value,
    units_row_option,
)
from excavkin.cli.progress import solve_with_progress
from excavkin.errors import InputError
from excavkin.kinematics import KinematicResult
from excavkin.mechanism import Mechanism
from excavkin.outputs.tables import TABLE_SUFFIXES, check_target, write_table


def build_inputs(
    mech: Mechanism,
    sweeps: Sequence[str],
    sets: Sequence[str],
    rates: Sequence[str],
    accels: Sequence[str],
    grid: bool = False,
    params: Sequence[str] = (),
) -> tuple[dict[str, np.ndarray | float], dict[str, float], dict[str, float]]:
    """Turn ``--sweep/--set/--rate/--accel/--param`` texts into SI solve inputs.

    Several sweeps run side by side (sample k of each), so they must have the same N; with
    ``grid`` they form every combination instead (the first sweep varying slowest), N₁·N₂·…
    samples. A design parameter swept by ``--param NAME=START:STOP:N`` (or set by
    ``NAME=VALUE``) is one more such axis; the parameters come back in the values under
    ``"design." + NAME`` (:func:`split_params` takes them out).
    """
    values: dict[str, np.ndarray | float] = {}
    for option, texts in (
        ("--sweep", sweeps),
        ("--set", sets),
        ("--rate", rates),
        ("--accel", accels),
        ("--param", params),
    ):
        names = [parse_assignment(t, option)[0] for t in texts]
        twice = sorted({n for n in names if names.count(n) > 1})
        if twice:
            raise InputError(f"{option} is given more than once for {', '.join(twice)}")
    for text in sweeps:
        name, spec = parse_assignment(text, "--sweep")
        kind = mech.input_kind(name)
        values[name] = parse_sweep(spec, kind, f"--sweep {name}")
    for text in params:
        name, spec = parse_assignment(text, "--param")
        kind = parameter_kind(mech, name)
        what = f"--param {name}"
        values[PARAM + name] = (
            parse_sweep(spec, kind, what) if ":" in spec else si_value(spec, kind, what)
        )
    lengths = {k: v.size for k, v in values.items() if isinstance(v, np.ndarray)}
    if grid and len(lengths) > 1:
        check_samples(int(np.prod(list(lengths.values()), dtype=object)), "--grid")
        axes = np.meshgrid(*[values[k] for k in lengths], indexing="ij")
        values.update({k: a.ravel() for k, a in zip(lengths, axes, strict=True)})
    elif len(set(lengths.values())) > 1:
        raise InputError(
            "sweeps run side by side and need the same number of samples (or --grid for "
            "every combination); got " + ", ".join(f"{k}: {n}" for k, n in lengths.items())
        )
    for text in sets:
        name, spec = parse_assignment(text, "--set")
        if name in values:
            raise InputError(f"driver {name!r} is both swept and set")
        values[name] = si_value(spec, mech.input_kind(name), f"--set {name}")
    rate_v = {}
    for text in rates:
        name, spec = parse_assignment(text, "--rate")
        rate_v[name] = si_value(spec, RATE_KIND[mech.input_kind(name)], f"--rate {name}")
    accel_v = {}
    for text in accels:
        name, spec = parse_assignment(text, "--accel")
        accel_v[name] = si_value(spec, ACCEL_KIND[mech.input_kind(name)], f"--accel {name}")
    return values, rate_v, accel_v


#: how build_inputs marks a design parameter among the drivers' values
PARAM = "design."


def parameter_kind(mech: Mechanism, name: str) -> str:
    """What a parameter measures, after checking the name (with the nearest names)."""
    from excavkin.errors import unknown_name
    from excavkin.structure.design import parameter_kind as kind_of

    if name not in mech.parameters:
        raise unknown_name("parameter", name, list(mech.parameters))
    return kind_of(name, mech.model)


def split_params(
    values: dict[str, np.ndarray | float],
) -> tuple[dict[str, np.ndarray | float], dict[str, np.ndarray | float]]:
    """The drivers' values and the design parameters, apart."""
    drivers = {k: v for k, v in values.items() if not k.startswith(PARAM)}
    designs = {k[len(PARAM) :]: v for k, v in values.items() if k.startswith(PARAM)}
    return drivers, designs


def _columns_per_sample(mech: Mechanism, with_forces: bool) -> int:
    """Float columns of a solve's table (forces roughly double them), and its status."""
    plan = mech.plan
    kin = 6 * len(plan.points) + 3 * len(plan.bodies) + 3 * len(plan.inputs)
    kin += 6 * len(plan.elements) + len(plan.transmissions) + 1
    return 2 * kin if with_forces else kin


def read_inputs(
    mech: Mechanism, path: str
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray], dict[str, np.ndarray], np.ndarray | None]:
    """One row per sample from a CSV or Parquet table, SI: ``<driver>`` (or
    ``<driver>.value``), ``<driver>.rate``, ``<driver>.accel`` and ``t``.

    A CSV may carry the units row that ``--units-row`` writes; it is skipped.
    """
    import pandas as pd

    from excavkin.errors import did_you_mean

    p = check_target_readable(path)
    try:
        if p.suffix.lower() == ".parquet":
            frame = pd.read_parquet(p)
        else:
            frame = pd.read_csv(p, dtype=str, keep_default_na=False)
            if len(frame) and _units_row(frame.iloc[0]):
                frame = frame.iloc[1:].reset_index(drop=True)
            frame = frame.apply(pd.to_numeric, errors="coerce")
    except (OSError, ValueError) as exc:
        raise InputError(f"--inputs {path}: cannot read the table: {exc}") from None
    values: dict[str, np.ndarray] = {}
    rates: dict[str, np.ndarray] = {}
    accels: dict[str, np.ndarray] = {}
    time = None
    known = [*mech.inputs, *(f"{d}.{q}" for d in mech.inputs for q in ("value", "rate", "accel"))]
    for col in map(str, frame.columns):
        data = frame[col].to_numpy(dtype=np.float64)
        name, _, qty = col.partition(".")
        if col == "t":
            time = data
        elif name in mech.inputs and qty in ("", "value"):
            values[name] = data
        elif name in mech.inputs and qty == "rate":
            rates[name] = data
        elif name in mech.inputs and qty == "accel":
            accels[name] = data
        else:
            raise InputError(
                f"--inputs {path}: column {col!r} is not an input of {mech.name!r}"
                f"{did_you_mean(col, known)} (columns: <driver>, <driver>.rate, "
                f"<driver>.accel, t; inputs: {', '.join(mech.inputs) or 'none'})"
            )
    if not len(frame):
        raise InputError(f"--inputs {path}: the table has no samples")
    bad = [c for c in map(str, frame.columns) if not np.isfinite(frame[c].to_numpy(float)).all()]
    if bad:
        raise InputError(f"--inputs {path}: column {bad[0]!r} holds a value that is not a number")
    return values, rates, accels, time


def _units_row(row: object) -> bool:
    """A row of unit names (as ``--units-row`` writes), not of numbers."""
    from excavkin.units import is_unit_text

    cells = [str(v) for v in row]  # type: ignore[attr-defined]
    numbers = sum(_is_number(c) for c in cells)
    return numbers == 0 and all(is_unit_text(c) for c in cells)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def check_target_readable(path: str) -> Path:
    """The input table's path, if it exists and ends in .csv or .parquet."""
    p = Path(path)
    if p.suffix.lower() not in TABLE_SUFFIXES:
        raise InputError(f"--inputs {path}: the table must end in .csv or .parquet")
    if not p.is_file():
        raise InputError(f"--inputs {path}: no such file")
    return p


def report_failures(result: KinematicResult, keep_going: bool) -> None:
    """Stop with the failing samples listed, unless asked to keep going (then warn)."""
    if result.status.all_ok:
        return
    summary = result.summary()
    if keep_going:
        click.echo(f"excavkin: warning: {summary} (rows marked in the status column)", err=True)
        return
    fail(
        f"{summary}. Nothing was written; pass --keep-going to write the table with these "
        "rows marked in its status column.",
        EXIT_SAMPLES,
    )


sweep_options = [
    click.option(
        "--sweep",
        "sweeps",
        multiple=True,
        metavar="NAME=START:STOP:N",
        help="Sweep a driver, e.g. crank=0deg:360deg:361 (bare numbers are SI).",
    ),
    click.option(
        "--set",
        "sets",
        multiple=True,
        metavar="NAME=VALUE",
        help="Hold a driver at a value, e.g. boom_cyl=2.1m.",
    ),
    click.option(
        "--rate",
        "rates",
        multiple=True,
        metavar="NAME=VALUE",
        help="Driver rate, e.g. crank=31.416rad/s (default 1 for a swept driver).",
    ),
    click.option(
        "--accel",
        "accels",
        multiple=True,
        metavar="NAME=VALUE",
        help="Driver acceleration (default 0).",
    ),
    click.option(
        "--grid",
        is_flag=True,
        help="Sweeps form every combination (the first varying slowest) instead of moving "
        "together, e.g. a boom × stick map.",
    ),
]


def with_sweep_options(fn: click.decorators.FC) -> click.decorators.FC:
    """Add the shared --sweep/--set/--rate/--accel options to a command."""
    for opt in reversed(sweep_options):
        fn = opt(fn)
    return fn


@click.command("solve")
@click.argument("model", type=click.Path(dir_okay=False))
@with_sweep_options
@click.option(
    "-o",
    "--out",
    required=True,
    type=click.Path(dir_okay=False),
    help="Output table, .csv or .parquet.",
)
@click.option(
    "--keep-going",
    is_flag=True,
    help="Write the table even if some samples fail (rows marked in 'status').",
)
@click.option("--force", is_flag=True, help="Replace the output file if it exists.")
@units_row_option
@click.option(
    "--inputs",
    "inputs_file",
    type=click.Path(dir_okay=False),
    help="A table of inputs, one row per sample (SI): <driver> or <driver>.value, "
    "<driver>.rate, <driver>.accel, t.",
)
@click.option(
    "--forces",
    "with_forces",
    is_flag=True,
    help="Append joint forces, cylinder forces and driver torques (d'Alembert inertia plus the "
    "model's [loads]): <point>.<body>.Fx .Fy, <driver>.force, <driver>.torque, <ground>.Rx .Ry.",
)
@click.option(
    "--gravity/--no-gravity",
    default=None,
    help="With --forces: add gravity (the model's, else 9.80665 m/s^2 along -y) or leave it "
    "out (default: as the model says).",
)
@click.option(
    "--continuation",
    type=click.Choice(["side", "smooth"]),
    default="side",
    show_default=True,
    help="At a change point between samples: keep each dyad on its sketch side, or continue "
    "the motion onto the other side (a parallelogram stays a parallelogram).",
)
@click.option(
    "--param",
    "params",
    multiple=True,
    metavar="NAME=START:STOP:N",
    help="Sweep a design parameter (a dimension, mass or inertia; see `excavkin check`): "
    "each sample gets its own design, e.g. A-B=110mm:130mm:21 or O4.x=0.1m.",
)
@click.option(
    "--sensitivity",
    "sensitivities",
    multiple=True,
    metavar="NAME",
    help="Add the exact derivative of every column with respect to this parameter, "
    "d(<column>)/d(NAME).",
)
@click.option("-q", "--quiet", is_flag=True, help="No progress bar.")
@handle_errors
def command(
    model: str,
    sweeps: tuple[str, ...],
    sets: tuple[str, ...],
    rates: tuple[str, ...],
    accels: tuple[str, ...],
    grid: bool,
    out: str,
    keep_going: bool,
    force: bool,
    units_row: bool,
    inputs_file: str | None,
    with_forces: bool,
    gravity: bool | None,
    continuation: str,
    params: tuple[str, ...],
    sensitivities: tuple[str, ...],
    quiet: bool,
) -> None:
    """Solve MODEL.toml over driver sweeps and write one row per sample.

    Columns (SI: m, rad, s): <point>.x .y .vx .vy .ax .ay, <body>.angle .omega .epsilon,
    <driver>.value .rate .accel, <point>.transmission, status; with --forces also (N, N·m)
    <point>.<body>.Fx .Fy, <driver>.force, <driver>.torque, <slider>.normal, <ground>.Rx .Ry.
    """
    target = check_target(out, force=force, suffixes=TABLE_SUFFIXES)
    mech = excavkin.load(model_path(model))
    values, rate_v, accel_v = build_inputs(mech, sweeps, sets, rates, accels, grid, params)
    values, designs = split_params(values)
    for name in sensitivities:
        parameter_kind(mech, name)
    time = None
    if inputs_file:
        if sweeps:
            raise InputError("--inputs and --sweep both give the samples; use one of them")
        t_values, t_rates, t_accels, time = read_inputs(mech, inputs_file)
        twice = sorted(set(t_values) & set(values))
        if twice:
            raise InputError(f"{', '.join(twice)}: given both in --inputs and by --set")
        values.update(t_values)
        rate_v.update(t_rates)  # type: ignore[arg-type]
        accel_v.update(t_accels)  # type: ignore[arg-type]
    n = max(
        (v.size for v in (*values.values(), *designs.values()) if isinstance(v, np.ndarray)),
        default=1,
    )
    # the result, its table and the file's copy: every column three times over
    # each --sensitivity adds a derivative of every column
    copies = 1 + len(sensitivities)
    check_samples(n, "--sweep", 3 * 8 * copies * _columns_per_sample(mech, with_forces))
    result = solve_with_progress(
        mech,
        values,
        rate_v,
        accel_v,
        time=time,
        quiet=quiet,
        continuation=continuation,
        params=designs or None,
        sensitivities=list(sensitivities) or None,
    )
    for cp in result.change_points:
        click.echo(f"excavkin: warning: {cp.describe()}", err=True)
    report_failures(result, keep_going)
    if with_forces:
        from excavkin.kinetostatics import model_loads

        forces = mech.forces(result, model_loads(mech.model, gravity=gravity))
        singular = np.flatnonzero(forces.singular & result.status.ok)
        if singular.size:
            listed = ", ".join(str(int(i)) for i in singular[:10])
            more = f" and {singular.size - 10} more" if singular.size > 10 else ""
            text = (
                f"{singular.size} samples are statically singular (a redundant joint at "
                f"that position; their forces are NaN): samples {listed}{more}"
            )
            if not keep_going:
                fail(
                    f"{text}. Nothing was written; pass --keep-going to write the table with "
                    "these rows marked.",
                    EXIT_SAMPLES,
                )
            click.echo(f"excavkin: warning: {text}", err=True)
        frame = forces.to_frame()
    else:
        frame = result.to_frame()
    write_table(frame, target, force=force, units_row=units_row)
    click.echo(f"wrote {len(result)} samples × {frame.shape[1]} columns to {target}")
