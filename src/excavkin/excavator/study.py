"""Design studies and optimisation of an excavator machine: a study file that names a machine
file, whose parameters are the machine's
([`machine_parameters`][excavkin.excavator.designs.machine_parameters])
and whose metrics read the machine's columns at a set of cylinder lengths.

::

    [study]
    machine = "excavator_machine"   # a machine file beside this one, or a built-in example

    [parameters]                    # mechanism and machine parameters, with bounds
    "K.x" = ["6669.6 mm", "6769.6 mm"]
    "cylinders.bucket.bore" = ["120 mm", "130 mm"]

    [poses]                         # cylinder lengths: START:STOP:N, or one value
    boom_cyl = "2768 mm"
    arm_cyl = "2972 mm"
    bucket_cyl = "1645 mm:2765 mm:57"

    [metrics]
    force_min = { column = "rated.bucket", reduce = "min" }

A design's pose fails where the front does not assemble or a cylinder length lies outside that
design's stroke; a design whose cylinders or circuits are impossible fails at every pose.

The machine columns (`COLUMNS`) come from the engine's transfer functions, which have no
parameter sensitivities of their own here: the local method takes the gradient of every column
at every pose by central differences in the scaled parameters, all 2n + 1 designs of one
gradient solved as one batch. Differential evolution solves its whole population as one batch.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from excavkin.arrays import FloatArray as F
from excavkin.errors import ExcavkinError, InputError
from excavkin.excavator.designs import (
    bucket_angle_to_stick,
    check_designs,
    check_parameters,
    design_tool_forces,
    design_transfer,
    machine_parameter_kind,
    machine_parameters,
    within_strokes,
)
from excavkin.excavator.forces import Working
from excavkin.excavator.machine import Machine, as_lengths
from excavkin.studies.metrics import Constraint, Metric, Poses, tabulate
from excavkin.studies.optimize import Optimum, Problem, run

if TYPE_CHECKING:
    import pandas as pd

#: The machine's columns and their kinds. ``rated.*``: the ISO 6015 tool force of the bucket
#: or arm cylinder at the lip, at working pressure, capped by the holding cylinders' reliefs,
#: without the front's weight (as rated forces are given); ``force.*``: the same with the
#: weight; ``bucket.angle_to_stick``: the bucket's angle relative to the stick
#: (`bucket_angle_to_stick`); ``tip.x``, ``tip.y``: the
#: tooth tip; ``range.*``: the design's working-range figure
#: (`design_ranges`), the same at every pose.
COLUMNS: dict[str, str] = {
    "rated.bucket": "force",
    "rated.arm": "force",
    "force.bucket": "force",
    "force.arm": "force",
    "bucket.angle_to_stick": "angle",
    "tip.x": "length",
    "tip.y": "length",
    "range.max_digging_reach": "length",
    "range.max_digging_depth": "length",
    "range.max_cutting_height": "length",
}
#: the angle columns (their ``change`` is followed along the poses)
ANGLES = frozenset(k for k, kind in COLUMNS.items() if kind == "angle")


def machine_columns(
    machine: Machine,
    lengths: ArrayLike,
    params: Mapping[str, ArrayLike],
    names: Sequence[str],
) -> tuple[dict[str, F], NDArray[np.bool_]]:
    """The columns ``names`` (of `COLUMNS`) at cylinder ``lengths`` (shape (n, 3)),
    sample i the design ``params[name][i]``, and which samples are valid (assembled, within
    their design's strokes, possible cylinders and circuits), shape (n,)."""
    L = as_lengths(lengths)
    n = len(L)
    for name in names:
        if name not in COLUMNS:
            from excavkin.errors import unknown_name

            raise unknown_name("machine column", name, list(COLUMNS))
    tr = design_transfer(machine, L, params)
    within = within_strokes(machine, L, params)
    ok = np.asarray(tr.result.status.solved & within & check_designs(machine, params, n))
    out: dict[str, F] = {}
    for name in names:
        if name.startswith(("rated.", "force.")):
            working: Working = "arm" if name.endswith("arm") else "bucket"
            f = design_tool_forces(
                machine, L, params, working, gravity=name.startswith("force."), transfer=tr
            )
            out[name] = f.force
        elif name == "bucket.angle_to_stick":
            out[name] = bucket_angle_to_stick(machine, tr)
        elif name.startswith("range."):
            out[name] = _design_figure(machine, params, n, name.removeprefix("range."))
        else:
            tip, _ = tr.point(machine, machine.front.tip)
            out[name] = np.asarray(tip[:, 0 if name == "tip.x" else 1])
    return out, ok


def _design_figure(machine: Machine, params: Mapping[str, ArrayLike], n: int, figure: str) -> F:
    """A working-range figure of each sample's design, searched once per distinct design."""
    from excavkin.excavator.design_ranges import design_ranges

    if not params:
        return np.full(n, design_ranges(machine, {}, [figure])[figure][0])
    names = sorted(params)
    rows = np.column_stack([np.broadcast_to(np.asarray(params[k], float), (n,)) for k in names])
    designs, which = np.unique(rows, axis=0, return_inverse=True)
    values = design_ranges(machine, dict(zip(names, designs.T, strict=True)), [figure])[figure]
    return np.asarray(values[which.reshape(-1)])


def pose_lengths(machine: Machine, poses: Poses) -> F:
    """The cylinder lengths of a pose set, shape (p, 3): each driver's values, or the model's
    sketch length for a driver not given."""
    sketch = machine.mechanism.sketch_values()
    p = poses.count
    return np.column_stack(
        [
            np.broadcast_to(np.asarray(poses.values.get(d, sketch[d]), float), (p,))
            for d in machine.drivers
        ]
    )


def evaluate_machine(
    machine: Machine,
    designs: Mapping[str, F],
    lengths: ArrayLike,
    metrics: Sequence[Metric],
    constraints: Sequence[Constraint] = (),
) -> pd.DataFrame:
    """Every design at every pose (cylinder lengths, shape (p, 3)), as one batch of
    designs × poses samples; one row per design (columns as
    [`excavkin.studies.metrics.evaluate`][]'s)."""
    check_parameters(machine, designs)
    L = as_lengths(lengths)
    d = len(next(iter(designs.values())))
    p = len(L)
    params = {k: np.repeat(np.asarray(v, dtype=np.float64), p) for k, v in designs.items()}
    names = list(dict.fromkeys(m.column for m in metrics))
    cols, ok = machine_columns(machine, np.tile(L, (d, 1)), params, names)
    return tabulate(
        designs, {k: v.reshape(d, p) for k, v in cols.items()}, ok.reshape(d, p), metrics,
        constraints, ANGLES,
    )  # fmt: skip


@dataclass(frozen=True)
class MachineStudy:
    """A study of an excavator machine (all values SI).

    Attributes
    ----------
    machine : Machine
    bounds : dict of str to (float, float)
        Design parameters (names of
        [`machine_parameters`][excavkin.excavator.designs.machine_parameters]) and their bounds.
    lengths : ndarray, shape (p, 3)
        The poses: boom, arm and bucket cylinder lengths.
    metrics : tuple of Metric
        Of `COLUMNS`.
    constraints : tuple of Constraint
    optimize : dict
        The ``[optimize]`` settings (empty if the file has none).
    method, samples, seed
        The design of experiments of ``excavkin excavator study`` (as a model's study).
    source : str
        The machine file's text (for the study's fingerprint).
    units : dict of str to str
        The units to show results in, of each parameter (``design.NAME``) and metric, as the
        study file writes them; SI where absent.
    """

    machine: Machine
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

    def evaluate(self, designs: Mapping[str, F]) -> pd.DataFrame:
        """The study's metrics of ``designs``, one row per design.

        Parameters
        ----------
        designs : mapping of str to ndarray, shape (d,)
            Parameter name (of `machine_parameters`) → its SI value in each of d designs.

        Returns
        -------
        pandas.DataFrame
            ``design.<parameter>`` columns, one per metric, ``poses_failed``, ``feasible`` and
            ``status``, as `excavkin.studies.metrics.evaluate` gives them.
        """
        return evaluate_machine(self.machine, designs, self.lengths, self.metrics, self.constraints)

    # ---- what run_study needs (excavkin.studies.study.Subject)
    @property
    def designs(self) -> int:
        return self.samples ** len(self.bounds) if self.method == "grid" else self.samples

    @property
    def pose_count(self) -> int:
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
        kinds = {f"design.{k}": machine_parameter_kind(k, self.machine) for k in self.bounds}
        for m in self.metrics:
            kinds[m.name] = "dimensionless" if m.reduce.startswith("arg") else COLUMNS[m.column]
        return kinds, self.machine.name

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


def load_machine_study(path: str | Path) -> MachineStudy:
    """Read a study file whose ``[study]`` names a ``machine`` (module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The study file (TOML); its ``machine`` is a file beside it (a path from its folder)
        or a built-in machine example's name.

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
    machine, source = _machine(r, head.get("machine"), Path(path).parent)
    method, samples, seed = sf.read_sampling(r, head)
    known = machine_parameters(machine)
    bounds = sf.read_bounds(r, known, lambda k: machine_parameter_kind(k, machine))
    table = r.table("poses")
    for key in ("rates", "accels"):
        if key in table:
            raise r.err("a machine study's poses are cylinder lengths alone", "poses", key)
    poses = sf.read_poses(r, machine.mechanism)
    metrics = sf.read_metrics(r, COLUMNS)
    kinds = {m.name: "dimensionless" if m.reduce.startswith("arg") else COLUMNS[m.column]
             for m in metrics}  # fmt: skip
    constraints = sf.read_constraints(r, kinds)
    settings = sf.read_optimize(r, [m.name for m in metrics]) if "optimize" in r.data else {}
    units = sf.study_units(
        r, {f"design.{k}": machine_parameter_kind(k, machine) for k in bounds}, kinds
    )
    study = MachineStudy(
        machine, bounds, pose_lengths(machine, poses), tuple(metrics), tuple(constraints),
        settings, method, samples, seed, source, units,
    )  # fmt: skip
    sf.check_design_count(r, study.designs)
    if settings:
        sf.check_optimization_size(r, settings, len(bounds), study.pose_count)
    return study


def _machine(r: Any, text: Any, folder: Path) -> tuple[Machine, str]:
    import excavkin
    from excavkin.excavator.machine_file import load_machine
    from excavkin.io.toml_model import read_text_file

    if not isinstance(text, str) or not text:
        raise r.err("names the machine file (or a built-in machine example)", "study", "machine")
    given = folder / text
    if not given.is_file():
        if text not in excavkin.examples("machine"):
            raise r.err(f"{text!r}: no such file beside the study, nor a built-in machine "
                        "example", "study", "machine")  # fmt: skip
        given = excavkin.example_path(text)
    try:
        machine = load_machine(given)
    except ExcavkinError as exc:
        raise r.err(f"the machine cannot be read: {exc}", "study", "machine") from None
    # what decides the results: the machine file and the model file it names
    texts = [read_text_file(given)]
    model = Path(str(machine.mechanism.model.source or ""))
    if model.is_file() and model.resolve() != given.resolve():
        texts.append(read_text_file(model))
    return machine, "\n".join(texts)


class _MachineProblem(Problem):
    """A machine's designs: gradients by central differences, each gradient one batch."""

    #: the step in the scaled parameters (a 100 mm box: 1 µm)
    STEP = 1e-5

    def __init__(
        self, study: MachineStudy, objective: Metric, sense: str, metrics: Sequence[Metric]
    ) -> None:
        poses = Poses({}, {}, {})
        super().__init__(
            machine_parameters(study.machine), study.bounds, poses, objective, sense, metrics,
            study.constraints,
        )  # fmt: skip
        self.study = study
        self.angles = set(ANGLES)
        self.kinds = {f"design.{k}": machine_parameter_kind(k, study.machine) for k in self.names}
        for m in self.metrics:
            self.kinds[m.name] = (
                "dimensionless" if m.reduce.startswith("arg") else COLUMNS[m.column]
            )

    def table(self, designs: Mapping[str, F]) -> pd.DataFrame:
        return evaluate_machine(self.study.machine, designs, self.study.lengths, self.metrics)

    def columns_at(self, u: F) -> tuple[dict[str, F], dict[str, F], bool]:
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
        cols, ok = machine_columns(self.study.machine, np.tile(L, (2 * n + 1, 1)), params, names)
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
    its ``[optimize]`` table): differential evolution over whole populations solved as one
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
    problem = _MachineProblem(
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
