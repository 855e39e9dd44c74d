"""``excavkin solve``: sweep drivers and write every point's and body's kinematics."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click
import numpy as np

import excavkin
from excavkin.cli.common import (
    ACCEL_KIND,
    EXIT_SAMPLES,
    RATE_KIND,
    backend_option,
    check_samples,
    fail,
    handle_errors,
    model_path,
    parse_assignment,
    parse_sweep,
    si_value,
    units_row_option,
)
from excavkin.cli.input_table import InputTable
from excavkin.cli.progress import MIN_SAMPLES_FOR_BAR, compile_notes, progress
from excavkin.cli.tally import Tally
from excavkin.errors import InputError
from excavkin.kinematics import KinematicResult
from excavkin.kinematics.selection import SelectedResult
from excavkin.mechanism import Mechanism
from excavkin.outputs.table_parts import check_parts_target, write_parts
from excavkin.outputs.tables import TABLE_SUFFIXES, check_target, write_tables
from excavkin.sweeps import Lazy
from excavkin.sweeps import grid as sweep_grid

if TYPE_CHECKING:
    import pandas as pd

    from excavkin.kinetostatics import ForceResult


def build_inputs(
    mech: Mechanism,
    sweeps: Sequence[str],
    sets: Sequence[str],
    rates: Sequence[str],
    accels: Sequence[str],
    grid: bool = False,
    params: Sequence[str] = (),
    lazy: bool = False,
) -> tuple[dict[str, Any], dict[str, float], dict[str, float]]:
    """Turn ``--sweep/--set/--rate/--accel/--param`` texts into SI solve inputs.

    Several sweeps run side by side (sample k of each), so they must have the same N; with
    ``grid`` they form every combination instead (the first sweep varying slowest), N₁·N₂·…
    samples. A design parameter swept by ``--param NAME=START:STOP:N`` (or set by
    ``NAME=VALUE``) is one more such axis; the parameters come back in the values under
    ``"design." + NAME`` (`split_params` takes them out). With ``lazy`` the sweeps are
    columns made part by part ([`excavkin.sweeps`][]), never whole arrays, and no sample
    count is refused for memory.
    """
    values: dict[str, Any] = {}
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
        values[name] = parse_sweep(spec, kind, f"--sweep {name}", lazy)
    for text in params:
        name, spec = parse_assignment(text, "--param")
        kind = parameter_kind(mech, name)
        what = f"--param {name}"
        values[PARAM + name] = (
            parse_sweep(spec, kind, what, lazy) if ":" in spec else si_value(spec, kind, what)
        )
        check_param_sign(mech, name, kind, values[PARAM + name], spec)
    lengths = {k: v.size for k, v in values.items() if isinstance(v, np.ndarray | Lazy)}
    if grid and len(lengths) > 1 and lazy:
        values.update(zip(lengths, sweep_grid(*[values[k] for k in lengths]), strict=True))
    elif grid and len(lengths) > 1:
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


def check_param_sign(mech: Mechanism, name: str, kind: str, value: Any, text: str) -> None:
    """Refuse a ``--param`` that no design can have: a negative mass or inertia, or a distance
    between two points that is not positive (a coordinate may take any sign).

    Parameters
    ----------
    mech : Mechanism
    name : str
        The parameter.
    kind : str
        What it measures (``"length"``, ``"mass"``, ``"inertia"``).
    value : float, ndarray or Linspace
        Its value or sweep, SI.
    text : str
        As given, for the message.

    Raises
    ------
    InputError
        Naming the parameter, its value and why.
    """
    from excavkin.sweeps import Linspace

    if isinstance(value, Linspace):
        low = min(value.start, value.stop)
    else:
        low = float(np.min(np.asarray(value, dtype=np.float64)))
    distance = kind == "length" and "-" in name and not name.endswith((".x", ".y"))
    if kind in ("mass", "inertia") and low < 0.0:
        raise InputError(f"--param {name}={text}: a {kind} cannot be negative")
    if distance and not low > 0.0:
        raise InputError(f"--param {name}={text}: a distance between two points must be positive")


def split_params(values: dict[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
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


def report_failures(result: KinematicResult | Tally, keep_going: bool) -> None:
    """Stop with the failing samples listed, unless asked to keep going (then warn)."""
    ok = result.all_ok if isinstance(result, Tally) else result.status.all_ok
    if ok:
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
    type=click.Path(),
    help="Output table, .csv or .parquet (with --parts: a folder).",
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
@click.option(
    "--columns",
    "columns_text",
    metavar="NAMES",
    help="Write only these columns, comma-separated names or patterns, e.g. "
    "'B.*,*.x,crank.value' (in the model's column order; status always).",
)
@click.option(
    "--parts",
    is_flag=True,
    help="Write OUT as a folder of Parquet files, one a part of the sweep, encoded on "
    "threads while the next parts are solved (read it whole with pandas.read_parquet(OUT)).",
)
@backend_option
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
    columns_text: str | None,
    parts: bool,
    backend: str,
    quiet: bool,
) -> None:
    """Solve MODEL.toml over driver sweeps and write one row per sample.

    Columns (SI: m, rad, s): <point>.x .y .vx .vy .ax .ay, <body>.angle .omega .epsilon,
    <driver>.value .rate .accel, <point>.transmission, status; with --forces also (N, N·m)
    <point>.<body>.Fx .Fy, <driver>.force, <driver>.torque, <slider>.normal, <ground>.Rx .Ry.
    --columns keeps only the columns named (names or patterns such as 'B.*').
    """
    from excavkin.backends import require

    require(backend, f"--backend {backend}")
    selection = parse_columns(columns_text)
    if parts:
        if units_row:
            raise InputError("--units-row is a CSV header row; --parts writes Parquet")
        target = check_parts_target(out, force=force)
    else:
        target = check_target(out, force=force, suffixes=TABLE_SUFFIXES)
    mech = excavkin.load(model_path(model))
    values, rate_v, accel_v = build_inputs(
        mech, sweeps, sets, rates, accels, grid, params, lazy=True
    )
    values, designs = split_params(values)
    for name in sensitivities:
        parameter_kind(mech, name)
    time = None
    if inputs_file:
        if sweeps:
            raise InputError("--inputs and --sweep both give the samples; use one of them")
        table = InputTable(mech, inputs_file)
        twice = sorted(set(table.values) & set(values))
        if twice:
            raise InputError(f"{', '.join(twice)}: given both in --inputs and by --set")
        values.update(table.values)
        rate_v.update(table.rates)  # type: ignore[arg-type]
        accel_v.update(table.accels)  # type: ignore[arg-type]
        time = table.time
    n = max(
        (len(v) for v in (*values.values(), *designs.values()) if np.ndim(v) == 1),
        default=1,
    )
    columns = _columns_per_sample(mech, with_forces) * (1 + len(sensitivities))
    check_disk(target, n, columns, parts)
    loads = None
    if with_forces:
        from excavkin.kinetostatics import model_loads

        loads = model_loads(mech.model, gravity=gravity)
    tally = Tally(mech.plan)
    shape = [0]
    motion = [""]

    def frames() -> Iterator[pd.DataFrame]:
        """The table part by part; at its end, the checks that decide whether it is kept."""
        bar = progress("solving", n, quiet=quiet or n < MIN_SAMPLES_FOR_BAR)
        with compile_notes(quiet), bar as advance:
            parts = mech.solve_stream(
                values,
                rate_v,
                accel_v,
                time=time,
                continuation=continuation,  # type: ignore[arg-type]
                loads=loads,
                params=designs or None,
                sensitivities=list(sensitivities) or None,
                backend=backend,  # type: ignore[arg-type]
                columns=selection,
            )
            for part in _named_columns(parts, selection is not None):
                tally.add(part.start, part.result)
                motion[0] = motion[0] or _motion_note(part.result)
                frame = part.to_frame()
                shape[0] = frame.shape[1]
                advance(len(frame))
                yield frame
        for cp in tally.sorted_change_points():
            click.echo(f"excavkin: warning: {cp.describe()}", err=True)
        report_failures(tally, keep_going)  # stops here: the file is not kept
        for singular in (tally.singular_text(), tally.slack_text()):
            if singular and not keep_going:
                fail(
                    f"{singular}. Nothing was written; pass --keep-going to write the table "
                    "with these rows marked.",
                    EXIT_SAMPLES,
                )
            if singular:
                click.echo(f"excavkin: warning: {singular}", err=True)

    if parts:
        write_parts(frames(), target, force=force)
    else:
        write_tables(frames(), target, force=force, units_row=units_row)
    click.echo(f"wrote {tally.n} samples × {shape[0]} columns to {target}")
    if motion[0] and not quiet:
        click.echo(f"excavkin: note: {motion[0]}", err=True)


def _named_columns(parts: Iterator[Any], selecting: bool) -> Iterator[Any]:
    """The parts of a stream; a column the first does not have is named as ``--columns``'."""
    from excavkin.errors import UnknownNameError

    it = iter(parts)
    try:
        first = next(it)
    except StopIteration:
        return
    except UnknownNameError as e:
        text = str(e.args[0]) if e.args else ""
        if selecting and text.startswith("no column "):
            raise InputError(f"--columns: {text}") from None
        raise
    yield first
    yield from it


def parse_columns(text: str | None) -> list[str] | None:
    """``--columns`` as a list of names and patterns (None when not given).

    Parameters
    ----------
    text : str or None
        Comma-separated column names or glob patterns.

    Returns
    -------
    list of str or None

    Raises
    ------
    InputError
        An empty list or an empty name between commas.
    """
    if text is None:
        return None
    names = [t.strip() for t in text.split(",")]
    if not any(names) or not all(names):
        raise InputError(f"--columns {text!r}: name columns or patterns separated by commas")
    return names


def _motion_note(result: KinematicResult | SelectedResult | ForceResult) -> str:
    """What the velocities or forces of a table are, when it is not a plain motion: static
    forces, or transfer functions of the drivers swept without ``--rate``."""
    if isinstance(result, KinematicResult | SelectedResult):
        note = result.motion_note if result.unit_rates else ""
    else:
        note = result.motion_note
    return note.replace("no rate given", "no --rate given")


def check_disk(target: Path, n: int, columns: int, parts: bool = False) -> None:
    """Before anything is solved: refuse a CSV table that cannot fit on the target's disk
    (about 20 characters a value), and warn of a Parquet one whose values, uncompressed (8
    bytes each), would not — Parquet compresses (a ground point's columns to nothing), so it
    is tried; should the disk fill, the temporary file is removed and nothing is written.
    ``parts``: the target is a folder of Parquet parts."""
    import shutil

    parquet = parts or target.suffix.lower() == ".parquet"
    need = n * columns * (8 if parquet else 20)
    free = shutil.disk_usage(target.parent).free
    if need <= free:
        return
    text = (
        f"{n:,} samples × {columns:,} columns need about {need / 2**30:,.1f} GiB on disk"
        + (" uncompressed" if parquet else "")
        + f", more than the {free / 2**30:,.1f} GiB free in {target.parent}"
    )
    if parquet:
        click.echo(f"excavkin: warning: {text}; the run may stop when the disk is full", err=True)
        return
    raise InputError(f"{text}; split the sweep into smaller runs, or write Parquet")
