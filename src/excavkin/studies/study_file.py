"""Read a study file (TOML): the model, the design space, the poses, metrics and constraints.

::

    [study]
    model = "fourbar"            # a model file (relative to this file) or a built-in example
    method = "sobol"             # sobol | halton | lhs | grid
    samples = 1024               # designs (grid: levels of each parameter)
    seed = 0
    loads = "model"              # optional: forces under the model's loads and gravity

    [units]                      # optional, as in a model file: units of bare numbers
    length = "mm"

    [parameters]                 # design parameters (see `excavkin check`) and their bounds
    "A-B" = [110, 130]
    "O4.x" = ["90 mm", "110 mm"]

    [poses]                      # the drivers at every pose: START:STOP:N, or one value
    crank = "0 deg:360 deg:73"
    [poses.rates]
    crank = "10 rad/s"

    [metrics]                    # a column reduced over the poses
    gamma_min = { column = "B.transmission", reduce = "min" }

    [constraints]                # bounds of metrics, in the metric's kind
    gamma_min = { min = "40 deg" }

Several pose sets: besides ``[poses]`` (the default set), each ``[pose_sets.NAME]`` table is a
pose set written as ``[poses]`` is (with ``[pose_sets.NAME.rates]`` and ``.accels``); a
metric reads the set its ``poses`` names, the default where it names none. A clearance
metric is the signed distance of two segments between named points, reduced over its set
(least, by default)::

    [pose_sets.dump]
    crank = "170 deg:190 deg:5"

    [metrics]
    dump_gamma = { column = "B.transmission", reduce = "min", poses = "dump" }
    gap = { clearance = ["O2-A", "O4-B"], poses = "dump" }

Errors name the file, the table and the entry; nothing in the file is evaluated.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from excavkin.errors import ExcavkinError, ModelError
from excavkin.io.toml_model import TomlReader, read_text_file, read_toml
from excavkin.studies.design_space import METHODS
from excavkin.studies.metrics import REDUCTIONS, Constraint, Metric, Poses, probe_execution
from excavkin.studies.study import Study, metric_kind
from excavkin.units import KINDS

#: rate and acceleration kinds of each driver kind
_RATE = {"angle": "angular_velocity", "length": "velocity"}
_ACCEL = {"angle": "angular_acceleration", "length": "acceleration"}
#: the SI unit of each kind
_SI = {**KINDS, "power": "W"}
#: the most designs or poses a study file may ask for
MAX_DESIGNS = 10**10
MAX_POSES = 10**7


def load_study(path: str | Path) -> Study:
    """Read and check a study file.

    Parameters
    ----------
    path : str or Path
        The study file (TOML); its ``model`` is a file beside it (a path from its folder) or
        a built-in example's name.

    Returns
    -------
    Study
        The model, the design bounds, poses, metrics, constraints and sampling, SI.

    Raises
    ------
    ModelError, UnitError
        Naming the file, the table and the entry.
    """
    import excavkin

    source = str(path)
    r = TomlReader(read_toml(read_text_file(path), source), source)
    r.keys(
        r.data,
        {"study", "units", "parameters", "poses", "pose_sets", "metrics", "constraints",
         "optimize"},
        "the file",
    )  # fmt: skip
    head = r.table("study", required=True)
    if "machine" in head:
        family = _machine_family(head.get("machine"), Path(path).parent)
        raise r.err(
            f"a study of a{'n' if family[0] in 'aeiou' else ''} {family} machine: run it with "
            f"`excavkin {family} study` or `excavkin {family} optimize`",
            "study",
            "machine",
        )
    r.keys(head, {"model", "method", "samples", "seed", "loads"}, "study")
    model = _model(r, head, Path(path).parent)
    try:
        mech = excavkin.load(model)
    except ExcavkinError as exc:
        raise r.err(f"the model cannot be read: {exc}", "study", "model") from None
    method, samples, seed = read_sampling(r, head)
    loads = head.get("loads")
    if loads not in (None, "model"):
        raise r.err('must be "model" (the model\'s own loads and gravity)', "study", "loads")
    from excavkin.structure.design import parameter_kind

    bounds = read_bounds(r, mech.parameters, lambda k: parameter_kind(k, mech.model))
    poses = read_poses(r, mech)
    pose_sets = read_pose_sets(r, mech)
    columns = {c.name: c.kind for c in mech.solve({}, execution=probe_execution()).columns}
    table = r.data.get("metrics")
    named = (
        [e.get("column") for e in table.values() if isinstance(e, dict) and "clearance" not in e]
        if isinstance(table, dict)
        else [None]
    )
    if any(c not in columns for c in named):  # a force column, or a name to be refused: the
        # forces' columns too (a kinematic study neither imports nor solves the kinetostatics)
        columns.update(
            {c.name: c.kind for c in mech.solve({}, loads=[], execution=probe_execution()).columns}
        )
    default = bool(r.data.get("poses")) or not pose_sets
    metrics = read_metrics(r, columns, (list(pose_sets), default), tuple(mech.model.points))
    from excavkin.studies.metrics import needs_forces

    try:
        needs_forces(mech, metrics)
    except ExcavkinError as exc:
        raise r.err(str(exc), "metrics") from None
    kinds = {m.name: metric_kind(m, columns) for m in metrics}
    constraints = read_constraints(r, kinds)
    units = study_units(r, {f"design.{k}": parameter_kind(k, mech.model) for k in bounds}, kinds)
    study = Study(
        model=model,
        bounds=bounds,
        poses=poses,
        metrics=tuple(metrics),
        constraints=tuple(constraints),
        method=method,
        samples=samples,
        seed=seed,
        loads=loads,
        units=units,
        optimize=read_optimize(r, [m.name for m in metrics]) if "optimize" in r.data else {},
        pose_sets=pose_sets,
    )
    check_design_count(r, study.designs)
    return study


def _machine_family(name: Any, folder: Path) -> str:
    """The family of the machine file a study names (beside it or built in), as its commands
    are named; ``FAMILY`` where it cannot be told."""
    import tomllib

    import excavkin
    from excavkin.families import family_of

    if not isinstance(name, str) or not name:
        return "FAMILY"
    path = folder / name
    if not path.is_file() and name in excavkin.examples("machine"):
        path = excavkin.example_path(name)
    try:
        family = family_of(tomllib.loads(path.read_text(encoding="utf-8")), str(path))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError, ExcavkinError):
        return "FAMILY"
    return family.name if family is not None else "FAMILY"


def study_units(
    r: TomlReader, parameters: Mapping[str, str], metrics: Mapping[str, str]
) -> dict[str, str]:
    """The units the file writes its quantities in, to show its results in: of each parameter
    (``design.NAME`` → kind) and metric (name → kind), the unit its bounds are written in, else
    the ``[units]`` table's for its kind, else degrees for an angle and SI for the rest."""
    given: dict[str, list[Any]] = {}
    for name, bounds in dict(r.data.get("parameters", {})).items():
        given[f"design.{name}"] = bounds if isinstance(bounds, list) else []
    for name, spec in dict(r.data.get("constraints", {})).items():
        given[name] = list(spec.values()) if isinstance(spec, dict) else []
    out = {}
    for column, kind in {**parameters, **metrics}.items():
        written = [_unit_written(v) for v in given.get(column, [])]
        out[column] = next(
            (u for u in written if u), r.units.get(kind) or ("deg" if kind == "angle" else "")
        )
        if not out[column]:
            out[column] = _SI.get(kind, "")
    return out


def _unit_written(value: Any) -> str | None:
    """The unit of a quantity written as text (``"90 mm"`` → ``"mm"``), or None."""
    if not isinstance(value, str):
        return None
    from excavkin.units import registry

    try:
        quantity: Any = registry().Quantity(value)
    except Exception:  # not a quantity: the reader has refused it already
        return None
    unit = f"{quantity.units:~}"
    return unit or None


def read_sampling(r: TomlReader, head: Mapping[str, Any]) -> tuple[str, int, int]:
    """``[study]``'s ``method`` (default sobol), ``samples`` (1024) and ``seed`` (0)."""
    method = head.get("method", "sobol")
    if method not in METHODS:
        raise r.err(f"must be one of {', '.join(METHODS)}, not {method!r}", "study", "method")
    samples = _whole(r, head.get("samples", 1024), "samples", 1, MAX_DESIGNS)
    seed = _whole(r, head.get("seed", 0), "seed", 0, 2**63 - 1)
    return str(method), samples, seed


def check_design_count(r: TomlReader, designs: int) -> None:
    """Refuse more designs than a study may have (a grid's count grows with its levels)."""
    if designs > MAX_DESIGNS:
        raise r.err(f"{designs:,} designs is more than {MAX_DESIGNS:,}", "study", "samples")


def _model(r: TomlReader, head: dict[str, Any], folder: Path) -> Path:
    import excavkin

    text = head.get("model")
    if not isinstance(text, str) or not text:
        raise r.err("the study needs its model: a file or a built-in example's name", "study")
    given = folder / text
    if given.exists():
        return given
    if text in excavkin.examples("model"):
        return excavkin.example_path(text)
    raise r.err(
        f"{text!r}: no such file beside the study, nor a built-in example", "study", "model"
    )


def _whole(r: TomlReader, value: Any, entry: str, low: int, high: int, table: str = "study") -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise r.err(f"must be a whole number from {low} to {high:,}, got {value!r}", table, entry)
    return value


def read_bounds(
    r: TomlReader, known: Mapping[str, float], kind_of: Callable[[str], str]
) -> dict[str, tuple[float, float]]:
    """The ``[parameters]`` table: each parameter (a name of ``known``) and its bounds, SI
    (``kind_of(name)``: the parameter's kind, for its units)."""
    from excavkin.errors import unknown_name

    out = {}
    for name, given in r.table("parameters", required=True).items():
        if name not in known:
            problem = str(unknown_name("parameter", name, list(known)))
            raise r.err(problem, "parameters", name)
        if not isinstance(given, list) or len(given) != 2:
            raise r.err("bounds must be [low, high]", "parameters", name)
        kind = kind_of(name)
        lo, hi = (r.qty(v, kind, "parameters", name) for v in given)
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise r.err(f"bounds must be finite with low < high, got [{lo:g}, {hi:g}]",
                        "parameters", name)  # fmt: skip
        out[name] = (lo, hi)
    return out


def read_poses(
    r: TomlReader, mech: Any, given: Mapping[str, Any] | None = None, where: str = "poses"
) -> Poses:
    """The ``[poses]`` table (or ``given``, the table ``where``): the drivers' values (sweeps
    or single values), rates and accelerations, SI. ``[poses]`` is required unless the study
    has named pose sets: a study without it would silently evaluate every design at its sketch
    alone, so that is asked for explicitly by an empty ``[poses]``."""
    if given is None and "poses" not in r.data and "pose_sets" not in r.data:
        raise r.err(
            "the study has no [poses] table: name the drivers' values every design is "
            'evaluated at (crank = "0 deg:360 deg:37"), or give an empty [poses] table to '
            "evaluate each design at its sketch alone",
            "poses",
        )
    table = dict(r.table("poses") if given is None else given)
    rates_t = table.pop("rates", {})
    accels_t = table.pop("accels", {})
    values = {}
    for name, spec in table.items():
        if isinstance(spec, dict):
            raise r.err(
                f"a table here is not a driver's value; a named pose set is a "
                f"[pose_sets.{name}] table (and its rates [pose_sets.{name}.rates])",
                where, name,
            )  # fmt: skip
        kind = _driver_kind(r, mech, name, where)
        values[name] = _sweep(r, spec, kind, where, name)
    rates = {}
    for name, spec in _sub(r, rates_t, f"{where}.rates").items():
        kind = _RATE[_driver_kind(r, mech, name, f"{where}.rates")]
        rates[name] = r.qty(spec, kind, f"{where}.rates", name)
    accels = {}
    for name, spec in _sub(r, accels_t, f"{where}.accels").items():
        kind = _ACCEL[_driver_kind(r, mech, name, f"{where}.accels")]
        accels[name] = r.qty(spec, kind, f"{where}.accels", name)
    poses = Poses(values, rates, accels)
    try:
        poses.count  # noqa: B018 - checks the sweeps' lengths
    except ExcavkinError as exc:
        raise r.err(str(exc), where) from None
    return poses


def read_pose_sets(r: TomlReader, mech: Any) -> dict[str, Poses]:
    """The ``[pose_sets.NAME]`` tables: each a pose set written as ``[poses]`` is, SI."""
    out = {}
    for name, spec in r.table("pose_sets").items():
        r.name(name, "pose_sets")
        if not isinstance(spec, dict) or not spec:
            raise r.err(
                'must be a table of driver = value, such as { crank = "0 deg:90 deg:10" }',
                "pose_sets", name,
            )  # fmt: skip
        out[name] = read_poses(r, mech, spec, f"pose_sets.{name}")
    return out


def _sub(r: TomlReader, value: Any, table: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise r.err("must be a table of driver = value", table)
    return value


def _driver_kind(r: TomlReader, mech: Any, name: str, table: str) -> str:
    from excavkin.errors import unknown_name

    if name not in mech.plan.inputs:
        raise r.err(str(unknown_name("driver", name, list(mech.plan.inputs))), table, name)
    return str(mech.input_kind(name))


def _sweep(r: TomlReader, spec: Any, kind: str, table: str, entry: str) -> Any:
    """``"START:STOP:N"`` → N evenly spaced values; a single value → that value."""
    if isinstance(spec, str) and spec.count(":") == 2:
        a, b, count = spec.split(":")
        try:
            n = int(count)
        except ValueError:
            raise r.err(f"the sample count {count!r} is not a whole number", table, entry) from None
        if not 1 <= n <= MAX_POSES:
            raise r.err(f"the sample count must be from 1 to {MAX_POSES:,}", table, entry)
        return np.linspace(
            r.qty(a.strip(), kind, table, entry), r.qty(b.strip(), kind, table, entry), n
        )
    return r.qty(spec, kind, table, entry)


def read_metrics(
    r: TomlReader,
    columns: Mapping[str, str],
    sets: tuple[list[str], bool] | None = None,
    points: tuple[str, ...] = (),
) -> list[Metric]:
    """The ``[metrics]`` table: each a column of ``columns`` (name → kind) reduced over the
    poses. With ``sets`` (the named pose sets, and whether there is a default set), a metric
    may name its pose set (``poses``) and be a clearance of two segments between ``points``
    (``clearance = ["P0-P1", "Q0-Q1"]``)."""
    from excavkin.errors import unknown_name

    out = []
    from excavkin.studies.metrics import reserved_name

    for name, spec in r.table("metrics", required=True).items():
        r.name(name, "metrics")
        why = reserved_name(name)
        if why is not None:
            raise r.err(why, "metrics", name)
        if not isinstance(spec, dict):
            raise r.err('must be a table such as { column = "B.transmission", reduce = "min" }',
                        "metrics", name)  # fmt: skip
        allowed = {"column", "reduce", "target"}
        r.keys(spec, allowed | ({"poses", "clearance"} if sets else set()), "metrics", name)
        pose_set = _pose_set(r, spec, sets, name) if sets else None
        if "clearance" in spec:
            out.append(_clearance(r, spec, name, pose_set, points))
            continue
        column, how = spec.get("column"), spec.get("reduce")
        if not isinstance(column, str):
            raise r.err("needs the column it reduces", "metrics", name)
        if column not in columns:
            problem = str(unknown_name(f"column (metric {name!r})", column, sorted(columns)))
            raise r.err(problem, "metrics", name)
        if how not in REDUCTIONS:
            raise r.err(f"reduce must be one of {', '.join(REDUCTIONS)}, not {how!r}",
                        "metrics", name)  # fmt: skip
        target = None
        if how == "sumsq" or (how == "absmax" and "target" in spec):
            target = _target(r, spec.get("target"), columns[column], name)
        elif "target" in spec:
            raise r.err("a target belongs to a sumsq or absmax metric", "metrics", name)
        out.append(Metric(name, column, how, target, pose_set))
    return out


def _pose_set(
    r: TomlReader, spec: Mapping[str, Any], sets: tuple[list[str], bool], name: str
) -> str | None:
    """The pose set a metric names (None: the default set, where the study has one)."""
    from excavkin.errors import unknown_name

    named, default = sets
    given = spec.get("poses")
    if given is None:
        if not default:
            raise r.err(
                f"names no pose set and the study has no [poses] table: give poses = one of "
                f"{', '.join(repr(k) for k in named)}",
                "metrics", name,
            )  # fmt: skip
        return None
    if not isinstance(given, str) or given not in named:
        problem = unknown_name("pose set", str(given), named)
        raise r.err(f"{problem} (sets are [pose_sets.NAME] tables)", "metrics", name)
    return given


def _clearance(
    r: TomlReader, spec: Mapping[str, Any], name: str, pose_set: str | None, points: tuple[str, ...]
) -> Metric:
    """``{ clearance = ["P0-P1", "Q0-Q1"], reduce = "min" }``: two segments between points."""
    from excavkin.errors import unknown_name
    from excavkin.studies.metrics import clearance_metric

    if "column" in spec or "target" in spec:
        raise r.err("a clearance metric has no column or target", "metrics", name)
    given = spec["clearance"]
    shape = 'clearance = ["P0-P1", "Q0-Q1"]: two segments, each two point names joined by "-"'
    if not isinstance(given, list) or len(given) != 2 or not all(isinstance(g, str) for g in given):
        raise r.err(f"must be {shape}", "metrics", name)
    segments = []
    for text in given:
        ends = text.split("-")
        if len(ends) != 2 or not all(ends):
            raise r.err(f"{text!r}: must be {shape}", "metrics", name)
        for point in ends:
            if point not in points:
                problem = unknown_name("point", point, list(points))
                raise r.err(str(problem), "metrics", name)
        if ends[0] == ends[1]:
            raise r.err(f"{text!r}: a segment needs two different points", "metrics", name)
        segments.append((ends[0], ends[1]))
    how = spec.get("reduce", "min")
    if how not in REDUCTIONS or how == "sumsq":
        known = ", ".join(x for x in REDUCTIONS if x != "sumsq")
        raise r.err(f"reduce must be one of {known}, not {how!r}", "metrics", name)
    return clearance_metric(name, segments[0], segments[1], pose_set, how)


def _target(r: TomlReader, given: Any, kind: str, name: str) -> tuple[float, ...]:
    """A sumsq or absmax metric's target: one value, or one per pose, in the column's kind."""
    if isinstance(given, (str, int, float)) and not isinstance(given, bool):
        given = [given]
    if not isinstance(given, list) or not given:
        raise r.err("needs target = a value, or [one value per pose]", "metrics", name)
    return tuple(r.qty(v, kind, "metrics", name) for v in given)


def load_optimization(path: str | Path) -> tuple[Study, dict[str, Any]]:
    """A study file with an ``[optimize]`` table: the study, and the optimisation's settings
    (``objective``: a metric's name; ``sense``: "min" or "max"; ``method``: "slsqp" or
    "differential-evolution"; ``maxiter``; ``popsize``), which the study also keeps as its
    ``optimize``.

    Parameters
    ----------
    path : str or Path
        The study file (TOML).

    Returns
    -------
    study : Study
        As `load_study` reads it.
    settings : dict
        ``objective``, ``sense`` (default ``"max"``), ``method`` (default ``"slsqp"``),
        ``maxiter`` (default 200) and ``popsize`` (default 32).

    Raises
    ------
    ModelError, UnitError
        Naming the file, the table and the entry; a file without ``[optimize]`` too.
    """
    study = load_study(path)
    source = str(path)
    r = TomlReader(read_toml(read_text_file(path), source), source)
    if not study.optimize:
        read_optimize(r, [m.name for m in study.metrics])  # raises: the table is required
    settings = dict(study.optimize)
    check_optimization_size(r, settings, len(study.bounds), study.poses.count)
    return study, settings


def read_optimize(r: TomlReader, names: list[str]) -> dict[str, Any]:
    """The ``[optimize]`` table's settings (see
    [`load_optimization`][excavkin.studies.study_file.load_optimization]); ``names`` are the
    metrics'."""
    from excavkin.studies.optimize import METHODS as OPTIMIZERS

    spec = r.table("optimize", required=True)
    r.keys(spec, {"objective", "sense", "method", "maxiter", "popsize"}, "optimize")
    objective = spec.get("objective")
    if objective not in names:
        from excavkin.errors import unknown_name

        raise r.err(str(unknown_name("metric", str(objective), names)), "optimize", "objective")
    sense = spec.get("sense", "max")
    if sense not in ("min", "max"):
        raise r.err(f"sense must be 'min' or 'max', not {sense!r}", "optimize", "sense")
    method = spec.get("method", "slsqp")
    if method not in OPTIMIZERS:
        raise r.err(f"must be one of {', '.join(OPTIMIZERS)}, not {method!r}", "optimize", "method")
    return {
        "objective": objective,
        "sense": sense,
        "method": method,
        "maxiter": _whole(r, spec.get("maxiter", 200), "maxiter", 1, 100_000, "optimize"),
        "popsize": _whole(r, spec.get("popsize", 32), "popsize", 4, 10_000, "optimize"),
    }


#: the most samples (designs × poses) an optimisation may solve in all: 10¹⁰, hours here
MAX_OPTIMIZE_SAMPLES = 10**10


def check_optimization_size(
    r: TomlReader, settings: Mapping[str, Any], parameters: int, poses: int
) -> None:
    """Refuse an ``[optimize]`` table whose ``maxiter`` and ``popsize`` ask for more samples
    than `MAX_OPTIMIZE_SAMPLES` at the worst: every iteration run, each a generation of
    differential evolution (``popsize`` × parameters designs; more than a step of SLSQP and its
    gradient, so the bound holds whichever method the command line picks).

    Parameters
    ----------
    r : TomlReader
        The study file.
    settings : mapping
        `read_optimize`'s settings.
    parameters, poses : int
        The design parameters and the poses of each design.

    Raises
    ------
    ModelError
        Naming the file, ``[optimize]`` and the entry.
    """
    maxiter = int(settings["maxiter"])
    per = int(settings["popsize"]) * max(parameters, 1)
    total = (maxiter + 1) * per * poses
    if total > MAX_OPTIMIZE_SAMPLES:
        raise r.err(
            f"maxiter = {maxiter:,} iterations of {per:,} designs at {poses:,} poses are "
            f"{total:,} samples at the worst, more than {MAX_OPTIMIZE_SAMPLES:,}; give a smaller "
            f"maxiter or popsize",
            "optimize",
            "maxiter",
        )


def read_constraints(r: TomlReader, kinds: Mapping[str, str]) -> list[Constraint]:
    """The ``[constraints]`` table: bounds of metrics (name → kind), SI."""
    from excavkin.errors import unknown_name

    out = []
    for name, spec in r.table("constraints").items():
        if name not in kinds:
            raise r.err(str(unknown_name("metric", name, list(kinds))), "constraints", name)
        if not isinstance(spec, dict) or not spec:
            raise r.err('must be a table such as { min = "40 deg" } or { equal = "45 deg" }',
                        "constraints", name)  # fmt: skip
        r.keys(spec, {"min", "max", "equal"}, "constraints", name)
        kind = kinds[name]
        if "equal" in spec:
            if "min" in spec or "max" in spec:
                raise r.err("give equal, or min and/or max, not both", "constraints", name)
            value = r.qty(spec["equal"], kind, "constraints", name)
            out.append(Constraint(name, value, value))
            continue
        low = r.qty(spec["min"], kind, "constraints", name) if "min" in spec else None
        high = r.qty(spec["max"], kind, "constraints", name) if "max" in spec else None
        if low is not None and high is not None and not low <= high:
            raise r.err("min must not exceed max", "constraints", name)
        out.append(Constraint(name, low, high))
    return out


__all__ = ["ModelError", "load_study"]
