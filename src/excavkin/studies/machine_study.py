"""Studies of a machine's parameters, for every family: a study file that names a machine file,
whose parameters are the machine's (its mechanism's, its cylinders', its circuits' …) and whose
metrics reduce the family's machine columns.

::

    [study]
    machine = "excavator_machine"   # a machine file beside this one, or a built-in example

    [parameters]                    # the machine's parameters, with bounds
    "K.x" = ["6669.6 mm", "6769.6 mm"]
    "cylinders.bucket.bore" = ["120 mm", "130 mm"]

    [poses]                         # cylinder lengths (a family whose studies have poses)
    bucket_cyl = "1645 mm:2765 mm:57"

    [metrics]
    force_min = { column = "rated.bucket", reduce = "min" }

What differs between families is a [`DesignFamily`][excavkin.machinery.designs.DesignFamily]
(its parameters, its columns, whether it has poses, and the computation); the reading of the
file, the loop over the designs of a design of experiments, the optimiser's problem and the
optimum written back as a machine file are here.

Each design is evaluated at every pose as one batch of designs × poses samples (the family
decides how it solves them). The family's columns have no parameter sensitivities of their
own: the local method takes the gradient of every column by central differences in the scaled
parameters, all 2n + 1 designs of one gradient evaluated as one batch; differential evolution
evaluates its whole population as one batch.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray as F
from excavkin.errors import ExcavkinError, InputError
from excavkin.machinery.designs import DesignFamily
from excavkin.studies.metrics import Constraint, Metric, Poses, tabulate
from excavkin.studies.optimize import Optimum, Problem, run

if TYPE_CHECKING:
    import pandas as pd

__all__ = [
    "MachineStudy",
    "evaluate_designs",
    "load_machine_study",
    "optimize_machine",
    "pose_lengths",
    "write_machine",
]


def pose_lengths(machine: Any, poses: Poses) -> F:
    """The cylinder lengths of a pose set, shape (p, k): each cylinder driver's values, or the
    model's sketch length for a driver not given.

    Parameters
    ----------
    machine : CylinderMachine
        Its cylinders name their drivers, in the order of the family's roles.
    poses : Poses
        The pose set.

    Returns
    -------
    ndarray, shape (p, k)
    """
    sketch = machine.mechanism.sketch_values()
    p = poses.count
    return np.column_stack(
        [
            np.broadcast_to(np.asarray(poses.values.get(c.driver, sketch[c.driver]), float), (p,))
            for c in machine.cylinders
        ]
    )


def metric_kind(m: Metric, columns: Mapping[str, str]) -> str:
    """A metric's physical kind: its column's, or dimensionless for a pose index.

    Parameters
    ----------
    m : Metric
    columns : mapping of str to str
        The family's columns and their kinds.

    Returns
    -------
    str
    """
    return "dimensionless" if m.reduce.startswith("arg") else columns[m.column]


def evaluate_designs(
    family: DesignFamily,
    machine: Any,
    designs: Mapping[str, F],
    lengths: ArrayLike,
    metrics: Sequence[Metric],
    constraints: Sequence[Constraint] = (),
) -> pd.DataFrame:
    """Every design at every pose, as one batch of designs × poses samples; one row per
    design.

    Parameters
    ----------
    family : DesignFamily
    machine : object
        The family's nominal machine.
    designs : mapping of str to ndarray, shape (d,)
        Parameter (of ``family.parameters(machine)``) → its SI value in each of d designs.
    lengths : array_like, shape (p, k)
        The poses' cylinder lengths (k = 0 and p = 1 for a family without poses).
    metrics : sequence of Metric
        Of the family's columns.
    constraints : sequence of Constraint

    Returns
    -------
    pandas.DataFrame
        ``design.<parameter>`` columns, one per metric, ``poses_failed``, ``feasible`` and
        ``status`` ([`excavkin.studies.metrics.evaluate`][]'s columns).

    Raises
    ------
    InputError
        A parameter the machine does not have, with the closest names.
    """
    from excavkin.errors import unknown_name

    known = family.parameters(machine)
    for name in designs:
        if name not in known:
            raise unknown_name("parameter", name, list(known))
    L = np.asarray(lengths, dtype=np.float64)
    d = len(next(iter(designs.values()))) if designs else 1
    p = len(L)
    params = {k: np.repeat(np.asarray(v, dtype=np.float64), p) for k, v in designs.items()}
    names = list(dict.fromkeys(m.column for m in metrics))
    cols, ok = family.evaluate(machine, np.tile(L, (d, 1)), params, names)
    return tabulate(
        designs, {k: v.reshape(d, p) for k, v in cols.items()}, ok.reshape(d, p), metrics,
        constraints, family.angles,
    )  # fmt: skip


@dataclass(frozen=True)
class MachineStudy:
    """A study of a machine's parameters (all values SI).

    Attributes
    ----------
    machine : object
        The family's machine.
    bounds : dict of str to (float, float)
        Design parameters (names of the family's parameters) and their bounds.
    lengths : ndarray, shape (p, k)
        The poses: the cylinders' lengths (one pose of no lengths for a family without poses).
    metrics : tuple of Metric
        Of the family's columns.
    constraints : tuple of Constraint
    optimize : dict
        The ``[optimize]`` settings (empty if the file has none).
    method, samples, seed
        The design of experiments of ``excavkin FAMILY study`` (as a model's study).
    source : str
        The machine file's text and its model file's (for the study's fingerprint).
    units : dict of str to str
        The units to show results in, of each parameter (``design.NAME``) and metric, as the
        study file writes them; SI where absent.
    family : DesignFamily or None
        The machine's family (what it computes); every study a reader makes has one.
    path : Path or None
        The machine file (for writing a design back as a machine file).
    """

    machine: Any
    bounds: dict[str, tuple[float, float]]
    lengths: F
    metrics: tuple[Metric, ...]
    constraints: tuple[Constraint, ...] = ()
    optimize: dict[str, Any] = field(default_factory=dict)
    method: str = "sobol"
    samples: int = 1024
    seed: int = 0
    source: str = ""
    units: dict[str, str] = field(default_factory=dict)
    family: DesignFamily | None = None
    path: Path | None = None

    @property
    def kind(self) -> DesignFamily:
        """The study's family.

        Returns
        -------
        DesignFamily

        Raises
        ------
        InputError
            A study made without one.
        """
        if self.family is None:
            raise InputError("the study names no machine family")
        return self.family

    def evaluate(self, designs: Mapping[str, F]) -> pd.DataFrame:
        """The study's metrics of ``designs``, one row per design.

        Parameters
        ----------
        designs : mapping of str to ndarray, shape (d,)
            Parameter name → its SI value in each of d designs.

        Returns
        -------
        pandas.DataFrame
            ``design.<parameter>`` columns, one per metric, ``poses_failed``, ``feasible`` and
            ``status``, as `excavkin.studies.metrics.evaluate` gives them.
        """
        return evaluate_designs(
            self.kind, self.machine, designs, self.lengths, self.metrics, self.constraints
        )

    # ---- what run_study needs (excavkin.studies.study.Subject)
    @property
    def designs(self) -> int:
        """The designs of the design of experiments.

        Returns
        -------
        int
        """
        return self.samples ** len(self.bounds) if self.method == "grid" else self.samples

    @property
    def pose_count(self) -> int:
        """The poses of each design.

        Returns
        -------
        int
        """
        return len(self.lengths)

    @property
    def motion_note(self) -> str:
        """The machine's figures are static by their standards' definitions: no note."""
        return ""

    def fingerprint(self) -> str:
        """A hash of everything that decides the results, so that parts of another study are
        never mixed in.

        Returns
        -------
        str
            16 hexadecimal digits of a SHA-256.
        """
        import hashlib
        import json

        text = json.dumps(
            {
                "machine": self.source,
                "bounds": self.bounds,
                "lengths": np.asarray(self.lengths).tolist(),
                "metrics": [(m.name, m.column, m.reduce, m.target) for m in self.metrics],
                "constraints": [(c.metric, c.low, c.high) for c in self.constraints],
                "sampling": (self.method, self.samples, self.seed),
            },
            sort_keys=True,
        )
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def kinds(self) -> dict[str, str]:
        """The kind of each parameter (``design.NAME``) and metric.

        Returns
        -------
        dict of str to str
        """
        fam = self.kind
        out = {f"design.{k}": fam.parameter_kind(k, self.machine) for k in self.bounds}
        for m in self.metrics:
            out[m.name] = metric_kind(m, fam.columns)
        return out

    def prepare(self) -> tuple[dict[str, str], str]:
        """Each column's kind and the machine's name, for the table's metadata.

        Returns
        -------
        kinds : dict of str to str
            ``design.<parameter>`` and each metric → its physical kind (``"length"``,
            ``"pressure"``, ``"dimensionless"`` …).
        name : str
            The machine's name.
        """
        return self.kinds(), str(self.machine.name)

    def evaluate_chunk(self, start: int, stop: int) -> pd.DataFrame:
        """The designs ``start:stop`` of the design of experiments, with their index.

        Parameters
        ----------
        start, stop : int
            The first design and one past the last, in the design of experiments' order.

        Returns
        -------
        pandas.DataFrame
            `evaluate`'s table of those designs, with a first column ``design``: their index.
        """
        from excavkin.studies.design_space import sample_designs

        part = sample_designs(self.bounds, self.samples, self.method, self.seed, (start, stop))
        frame = self.evaluate(part)
        frame.insert(0, "design", np.arange(start, stop))
        return frame


def load_machine_study(path: str | Path, family: DesignFamily) -> MachineStudy:
    """Read a study file whose ``[study]`` names a ``machine`` of ``family`` (module
    docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The study file (TOML); its ``machine`` is a file beside it (a path from its folder)
        or a built-in machine example's name.
    family : DesignFamily
        The machine's family.

    Returns
    -------
    MachineStudy
        The machine, the design bounds, poses, metrics, constraints and sampling, SI.

    Raises
    ------
    ModelError, UnitError
        Naming the file, the table and the entry.
    """
    from excavkin.io.toml_model import TomlReader, read_text_file, read_toml
    from excavkin.studies import study_file as sf

    source = str(path)
    r = TomlReader(read_toml(read_text_file(path), source), source)
    r.keys(r.data, {"study", "units", "parameters", "poses", "metrics", "constraints", "optimize"},
           "the file")  # fmt: skip
    head = r.table("study", required=True)
    if "model" in head and "machine" not in head:
        raise r.err(
            "a study of a model, not of a machine: run it with `excavkin study` or "
            "`excavkin optimize`",
            "study",
            "model",
        )
    r.keys(head, {"machine", "method", "samples", "seed"}, "study")
    machine, given, source = _machine(r, head.get("machine"), Path(path).parent, family)
    method, samples, seed = sf.read_sampling(r, head)
    known = family.parameters(machine)
    bounds = sf.read_bounds(r, known, lambda k: family.parameter_kind(k, machine))
    if family.posed:
        table = r.table("poses")
        for key in ("rates", "accels"):
            if key in table:
                raise r.err("a machine study's poses are cylinder lengths alone", "poses", key)
        lengths = pose_lengths(machine, sf.read_poses(r, machine.mechanism))
    else:
        if "poses" in r.data:
            raise r.err(
                f"a {family.name} study has no poses: each of its figures is taken at the pose "
                "its standard defines",
                "poses",
            )
        lengths = np.zeros((1, 0))
        _first_by_default(r)
    metrics = sf.read_metrics(r, family.columns)
    kinds = {m.name: metric_kind(m, family.columns) for m in metrics}
    constraints = sf.read_constraints(r, kinds)
    settings = sf.read_optimize(r, [m.name for m in metrics]) if "optimize" in r.data else {}
    units = sf.study_units(
        r, {f"design.{k}": family.parameter_kind(k, machine) for k in bounds}, kinds
    )
    study = MachineStudy(
        machine, bounds, lengths, tuple(metrics), tuple(constraints), settings, method,
        samples, seed, source, units, family, given,
    )  # fmt: skip
    sf.check_design_count(r, study.designs)
    if settings:
        sf.check_optimization_size(r, settings, len(bounds), study.pose_count)
    return study


def _first_by_default(r: Any) -> None:
    """A study without poses: a metric's ``reduce`` may be left out (one value per design)."""
    metrics = r.data.get("metrics")
    if isinstance(metrics, dict):
        for spec in metrics.values():
            if isinstance(spec, dict) and "column" in spec:
                spec.setdefault("reduce", "first")


def _machine(r: Any, text: Any, folder: Path, family: DesignFamily) -> tuple[Any, Path, str]:
    import excavkin
    from excavkin.io.toml_model import read_text_file

    if not isinstance(text, str) or not text:
        raise r.err("names the machine file (or a built-in machine example)", "study", "machine")
    given = folder / text
    if not given.is_file():
        if text not in excavkin.examples("machine"):
            raise r.err(f"{text!r}: no such file beside the study, nor a built-in machine "
                        "example", "study", "machine")  # fmt: skip
        given = excavkin.example_path(text)
    other = _family_of(given)
    if other is not None and other != family.name:
        raise r.err(
            f"{text!r} is a{'n' if other[0] in 'aeiou' else ''} {other} machine: run the study "
            f"with `excavkin {other} study` or `excavkin {other} optimize`",
            "study",
            "machine",
        )
    try:
        machine = family.load(given)
    except ExcavkinError as exc:
        raise r.err(f"the machine cannot be read: {exc}", "study", "machine") from None
    # what decides the results: the machine file and the model file it names
    texts = [read_text_file(given)]
    model = Path(str(machine.mechanism.model.source or ""))
    if model.is_file() and model.resolve() != given.resolve():
        texts.append(read_text_file(model))
    return machine, given, "\n".join(texts)


def _family_of(path: Path) -> str | None:
    """The family a machine file names (None where it cannot be told: its reader says why)."""
    import tomllib

    from excavkin.families import family_of

    try:
        found = family_of(tomllib.loads(path.read_text(encoding="utf-8")), str(path))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError, ExcavkinError):
        return None
    return found.name if found is not None else None


class MachineProblem(Problem):
    """A machine's designs for the optimiser: gradients by central differences in the scaled
    parameters, each gradient's 2n + 1 designs one batch.

    Parameters
    ----------
    study : MachineStudy
    objective : Metric
    sense : {"min", "max"}
    metrics : sequence of Metric
        The other metrics (the constraints').
    """

    #: the step in the scaled parameters (a 100 mm box: 1 µm)
    STEP = 1e-5
    SCALE_OBJECTIVE = True

    def __init__(
        self, study: MachineStudy, objective: Metric, sense: str, metrics: Sequence[Metric]
    ) -> None:
        family = study.kind
        super().__init__(
            family.parameters(study.machine), study.bounds, Poses({}, {}, {}), objective, sense,
            metrics, study.constraints,
        )  # fmt: skip
        self.study = study
        self.family = family
        self.angles = set(family.angles)
        self.kinds = {f"design.{k}": family.parameter_kind(k, study.machine) for k in self.names}
        for m in self.metrics:
            self.kinds[m.name] = metric_kind(m, family.columns)

    def table(self, designs: Mapping[str, F]) -> pd.DataFrame:
        """The designs' metrics (`evaluate_designs`), without the constraints.

        Parameters
        ----------
        designs : mapping of str to ndarray, shape (d,)

        Returns
        -------
        pandas.DataFrame
        """
        return evaluate_designs(
            self.family, self.study.machine, designs, self.study.lengths, self.metrics
        )

    def columns_at(self, u: F) -> tuple[dict[str, F], dict[str, F], bool]:
        """Each metric's column at every pose at the scaled design ``u``, its gradient in u by
        central differences (poses × parameters), and whether every pose is valid.

        Parameters
        ----------
        u : ndarray, shape (n,)

        Returns
        -------
        values : dict of str to ndarray, shape (p,)
        gradients : dict of str to ndarray, shape (p, n)
        ok : bool
        """
        key = u.tobytes()
        if key in self._memo:
            return self._memo[key]
        n, h = len(self.names), self.STEP
        steps = np.vstack([np.zeros(n), h * np.eye(n), -h * np.eye(n)])  # (2n + 1, n)
        x = self.lo + (np.clip(u, 0.0, 1.0) + steps) * (self.hi - self.lo)
        L = self.study.lengths
        p = len(L)
        params = {k: np.repeat(x[:, j], p) for j, k in enumerate(self.names)}
        names = list(dict.fromkeys(m.column for m in self.metrics))
        cols, ok = self.family.evaluate(
            self.study.machine, np.tile(L, (2 * n + 1, 1)), params, names
        )
        self.evaluations += 2 * n + 1
        values, grads = {}, {}
        for name, c in cols.items():
            c = c.reshape(2 * n + 1, p)
            values[name] = c[0]
            grads[name] = ((c[1 : n + 1] - c[n + 1 :]) / (2.0 * h)).T  # (p, n)
        return self.remember(u, (values, grads, bool(ok[:p].all())))


def optimize_machine(
    study: MachineStudy,
    objective: str | None = None,
    sense: str | None = None,
    *,
    method: str | None = None,
    x0: Mapping[str, float] | None = None,
    seed: int = 0,
    maxiter: int | None = None,
    popsize: int | None = None,
    tol: float = 1e-12,
    progress: Callable[[int, int], None] | None = None,
) -> Optimum:
    """The best design of the study's box under its constraints (arguments left out come from
    its ``[optimize]`` table): differential evolution over whole populations evaluated as one
    batch, then polished by SLSQP on central-difference gradients; or SLSQP alone. The optimum
    is shown in the study's units.

    Parameters
    ----------
    study : MachineStudy
        The design box (its bounds), poses, metrics and constraints.
    objective : str, optional
        The name of the metric to optimise.
    sense : {"min", "max"}, optional
        Minimise or maximise the objective (default: ``"max"``).
    method : {"slsqp", "differential-evolution"}, optional
        The optimiser (default: ``"slsqp"``).
    x0 : mapping of str to float, optional
        Start of SLSQP, SI (default: the machine's own values, clipped to the bounds).
    seed : int, default 0
        Differential evolution's seed.
    maxiter, popsize : int, optional
        The optimisers' iteration limit (default 200) and differential evolution's population
        size per parameter (default 32).
    tol : float, default 1e-12
        The optimisers' tolerance.
    progress : callable, optional
        ``progress(iterations, maxiter)`` after each iteration.

    Returns
    -------
    Optimum
        The best design, its metrics and the optimiser's history.

    Raises
    ------
    InputError
        No objective, an unknown metric or method, or a bad sense.
    """
    s = study.optimize
    objective = objective or s.get("objective")
    if objective is None:
        raise InputError("the study has no [optimize] table naming its objective")
    by_name = {m.name: m for m in study.metrics}
    if objective not in by_name:
        from excavkin.errors import unknown_name

        raise unknown_name("metric (the objective)", str(objective), list(by_name))
    problem = MachineProblem(
        study, by_name[objective], sense or s.get("sense", "max"),
        [m for m in study.metrics if m.name != objective],
    )  # fmt: skip
    how = method or s.get("method", "slsqp")
    if how not in ("slsqp", "differential-evolution"):
        raise InputError(f"unknown method {how!r} (known: slsqp, differential-evolution)")
    best = run(
        problem, how, x0, seed=seed, maxiter=maxiter or s.get("maxiter", 200),
        popsize=popsize or s.get("popsize", 32), tol=tol, progress=progress,
    )  # fmt: skip
    return replace(best, units=dict(study.units))


def check_machine_target(study: MachineStudy, out: str | PathLike[str], *, force: bool) -> Path:
    """Refuse, before any work, a machine file to write that exists (without ``force``), is
    not ``.toml``, or is the study's machine file or its model file.

    Parameters
    ----------
    study : MachineStudy
    out : path
        The machine file to write.
    force : bool
        Replace ``out`` if it exists.

    Returns
    -------
    Path
        ``out``.

    Raises
    ------
    OutputError
        Naming ``out``.
    """
    from excavkin.io.files import OutputError, check_target

    target = check_target(Path(out), force=force, suffixes=(".toml",))
    if target.exists():
        model = study.machine.mechanism.model.source
        for own, what in ((study.path, "machine"), (model, "model")):
            mine = own is not None and Path(str(own)).exists()
            if mine and target.resolve() == Path(str(own)).resolve():
                raise OutputError(
                    f"{target} is the study's {what} file; write the design elsewhere"
                )
    return target


def write_machine(
    study: MachineStudy,
    params: Mapping[str, float],
    out: str | PathLike[str],
    *,
    force: bool = False,
    note: str = "",
) -> Path:
    """Write a design of the study as a machine file of its own: the study's machine file with
    the machine file's parameters (cylinders, circuits …) replaced and its model written inline
    (``[model]``) with the mechanism's parameters replaced, each value in the unit the file
    writes it in, so that the file loads as that design; whole or not at all.

    Parameters
    ----------
    study : MachineStudy
        The study (its machine file and family).
    params : mapping of str to float
        Parameter → SI value (an optimum's ``params``).
    out : path
        The new machine file (``.toml``); never the study's machine or model file.
    force : bool
        Replace ``out`` if it exists.
    note : str
        Where the values come from, written as a comment line.

    Returns
    -------
    Path
        The design's machine file, ``out``.

    Raises
    ------
    InputError
        The study knows no machine file, or a parameter the machine does not have.
    OutputError
        ``out`` exists (without ``force``), is the machine or model file, or is not ``.toml``.
    """
    from excavkin.errors import unknown_name
    from excavkin.io.machine_write import write_machine_file

    if study.path is None:
        raise InputError("the study knows no machine file to write a design from")
    fam = study.kind
    known = fam.parameters(study.machine)
    for name in params:
        if name not in known:
            raise unknown_name("parameter", name, list(known))
    target = check_machine_target(study, out, force=force)
    mechanism = set(study.machine.mechanism.parameters)
    kinds = {k: fam.parameter_kind(k, study.machine) for k in params}
    return write_machine_file(
        study.path, dict(params), kinds, mechanism, target, force=force, note=note
    )
