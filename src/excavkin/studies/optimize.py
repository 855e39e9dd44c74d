"""The best design in a box of parameter bounds, under constraints on metrics over a pose set.

Two ways, both on the engine's batch axes:

- **Local** (``"slsqp"``): scipy's SLSQP with exact
  gradients — every column's sensitivity to every parameter at every pose comes from the
  differentiated plan in the same solve as its values. A sum of squares with no constraints
  (a target to follow: a function generator, a path) goes to least squares on its residuals
  and their exact Jacobian. A metric that is a least or greatest
  value over the poses is not smooth; it is written in epigraph form instead: maximising
  ``min_k c_k`` becomes maximising ``t`` with ``c_k ≥ t`` at every pose k, and a constraint
  ``min_k c_k ≥ b`` becomes ``c_k ≥ b`` at every pose. Both are exact reformulations.
- **Global** (``"differential-evolution"``): scipy's differential evolution with
  ``vectorized=True``, its whole population solved as one batch over the geometry axis; a
  design that breaks a constraint or does not solve at every pose is penalised. The best design
  is then polished by the local method.

Parameters are scaled to [0, 1] within their bounds, so that millimetres and kilograms weigh
alike.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.studies.metrics import (
    Constraint,
    Metric,
    Poses,
    angle_change,
    column_of,
    pose_sets_of,
    probe_execution,
    target_of,
)

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.mechanism import Mechanism
    from excavkin.studies.study import Study


Method = Literal["slsqp", "differential-evolution"]
#: reductions that are smooth functions of the design (no epigraph needed)
SMOOTH: tuple[str, ...] = ("mean", "sumsq", "change", "first", "last")
METHODS: tuple[str, ...] = ("slsqp", "differential-evolution")


@dataclass(frozen=True, repr=False)
class Optimum:
    """What an optimisation found.

    Attributes
    ----------
    params : dict of str to float
        The best design's parameters, SI.
    value : float
        Its objective.
    metrics : dict of str to float
        Its metrics (the objective's and the constraints').
    active : tuple of str
        Constraints at their bound (within 1e-6 of the bound's scale) at the optimum.
    at_bounds : dict of str to str
        Parameters at a bound of their box (within 1e-9 of its width): "low" or "high".
    feasible : bool
        Every pose solves and every constraint holds (to 1e-9 of its scale).
    success : bool
        The optimiser's own verdict.
    message : str
        The optimiser's own message.
    history : tuple of float
        The best objective after each iteration (for a convergence plot), SI.
    evaluations : int
        Designs solved.
    objective, sense, method : str
        The objective metric's name, "min" or "max", and the optimiser.
    bounds : dict of str to (float, float)
        Each parameter's box, SI.
    kinds : dict of str to str
        The kind of each parameter (``design.NAME``) and metric (its name).
    units : dict of str to str
        The units to show them in (a study file's own); SI where absent.
    model : Path or None
        The model file the designs are of (a study's), for
        [`write_model`][excavkin.studies.optimize.Optimum.write_model].
    """

    params: dict[str, float]
    value: float
    metrics: dict[str, float]
    active: tuple[str, ...]
    at_bounds: dict[str, str]
    feasible: bool
    success: bool
    message: str
    history: tuple[float, ...] = field(default=())
    evaluations: int = 0
    objective: str = ""
    sense: str = ""
    method: str = ""
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)
    kinds: dict[str, str] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)
    model: Path | None = None

    def write_model(
        self, out: str | PathLike[str], *, model: str | PathLike[str] | None = None,
        force: bool = False,
    ) -> Path:  # fmt: skip
        """Write the optimum as a model file: the model file with the design parameters'
        values replaced, each in the unit the file writes it in, so that loading the written
        file and solving it gives the optimum's metrics.

        Parameters
        ----------
        out : path
            The new model file (``.toml``).
        model : path, optional
            The model file (default: the study's, ``self.model``).
        force : bool
            Replace ``out`` if it exists.

        Returns
        -------
        Path
            The file written.

        Raises
        ------
        InputError
            No model file is known.
        OutputError
            ``out`` exists (without ``force``) or is the model file itself.
        """
        from excavkin.io.model_write import write_model

        source = model if model is not None else self.model
        if source is None:
            raise InputError("the optimum knows no model file: give model=")
        what = f"{self.sense}imum of {self.objective}" if self.sense else "the optimum"
        return write_model(source, self.params, out, force=force, note=f"design at the {what}")

    # ---- display, in the study's units
    def unit(self, column: str) -> str:
        """The unit ``column`` is shown in.

        Parameters
        ----------
        column : str
            ``design.NAME`` or a metric's name.

        Returns
        -------
        str
            The study's unit for it, or the SI unit of its kind.
        """
        from excavkin.kinematics.columns import si_unit

        kind = self.kinds.get(column, "dimensionless")
        return self.units.get(column) or si_unit(kind)

    def shown(self, column: str, value: ArrayLike) -> Any:
        """A value of ``column`` in the unit it is shown in.

        Parameters
        ----------
        column : str
            ``design.NAME`` or a metric's name.
        value : array_like
            SI.

        Returns
        -------
        float or ndarray
            In [`unit`][excavkin.studies.optimize.Optimum.unit]``(column)``.
        """
        kind = self.kinds.get(column)
        unit = self.units.get(column)
        if kind is None or kind == "dimensionless" or not unit:
            return value
        from excavkin.units import from_si

        return from_si(value, kind, unit)

    def _rows(self) -> list[tuple[str, float, str, str]]:
        """(column, value in its unit, unit, note) of each parameter and metric."""
        rows = []
        for k, v in self.params.items():
            col = f"design.{k}"
            side = self.at_bounds.get(k)
            rows.append((col, float(self.shown(col, v)), self.unit(col), f"at its {side} bound"
                         if side else ""))  # fmt: skip
        for k, v in self.metrics.items():
            note = "objective" if k == self.objective else ""
            if k in self.active:
                note = "constraint active"
            rows.append((k, float(self.shown(k, v)), self.unit(k), note))
        return rows

    def summary(self) -> str:
        """The optimum as a user reads it: the objective, the verdict, each parameter and
        metric in the study's units, the constraints that bind and the parameters at the box's
        bounds.

        Returns
        -------
        str
        """
        verdict = "feasible" if self.feasible else "NOT feasible"
        head = f"{self.sense}imum of {self.objective}" if self.sense else "optimum"
        how = f"{self.method}, " if self.method else ""
        value = f"{self.shown(self.objective, self.value):.10g} {self.unit(self.objective)}"
        lines = [f"{head} ({how}{self.evaluations:,} designs solved): {value.strip()} — {verdict}"]
        for col, v, unit, _ in self._rows():
            name = col.removeprefix("design.") if col.startswith("design.") else col
            lines.append(f"  {name:<24} {v:.10g} {unit}".rstrip())
        lines.append(f"  active constraints: {', '.join(self.active) or 'none'}")
        bounds = ", ".join(f"{k} ({side})" for k, side in self.at_bounds.items())
        lines.append(f"  at the box's bounds: {bounds or 'none'}")
        if not self.success:
            lines.append(f"  the optimiser says: {self.message}")
        return "\n".join(lines)

    def __repr__(self) -> str:
        shown = ", ".join(f"{c} = {v:.6g} {u}".rstrip() for c, v, u, _ in self._rows())
        verdict = "feasible" if self.feasible else "NOT feasible"
        return f"Optimum({verdict}; {shown})"

    def _repr_html_(self) -> str:
        import html

        from excavkin.kinematics.summary import html_table

        e = html.escape
        verdict = "feasible" if self.feasible else "<b>NOT feasible</b>"
        head = e(f"{self.sense}imum of {self.objective}" if self.sense else "optimum")
        rows = [[e(c), f"{v:.10g}", e(u), e(note)] for c, v, u, note in self._rows()]
        return (
            f"<p>{head} ({e(self.method)}, {self.evaluations:,} designs solved): {verdict}</p>"
            + html_table(rows, ["", "value", "unit", ""])
        )

    def to_frame(self, units: Literal["study", "si"] = "study") -> pd.DataFrame:
        """The optimum as a one-row table: ``design.NAME`` per parameter, one column per
        metric, and ``feasible``.

        Parameters
        ----------
        units : {"study", "si"}
            In the study's units (``frame.attrs["excavkin.units"]`` names them), or in SI
            (with each column's kind in ``frame.attrs["excavkin.kinds"]``, as a result's table,
            ready for [`write_table`][excavkin.outputs.tables.write_table]).

        Returns
        -------
        pandas.DataFrame
        """
        import pandas as pd

        from excavkin.kinematics.columns import si_unit

        if units not in ("study", "si"):
            raise InputError(f"units must be 'study' or 'si', not {units!r}")
        si = {f"design.{k}": v for k, v in self.params.items()} | self.metrics
        if units == "si":
            row = {c: [v] for c, v in si.items()}
            shown = {c: si_unit(self.kinds.get(c, "dimensionless")) for c in si}
        else:
            row = {c: [float(self.shown(c, v))] for c, v in si.items()}
            shown = {c: self.unit(c) for c in si}
        frame = pd.DataFrame({**row, "feasible": [self.feasible]})
        frame.attrs["excavkin.units"] = {**shown, "feasible": ""}
        if units == "si":
            frame.attrs["excavkin.kinds"] = {c: self.kinds.get(c, "dimensionless") for c in si}
        return frame

    def plot(self, *, ax: Axes | None = None) -> Axes:
        """The objective after each iteration, in its unit, if the optimiser recorded it; else
        each parameter's place in its box.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional

        Returns
        -------
        matplotlib.axes.Axes
        """
        from excavkin.studies.plots import plot_convergence, plot_in_bounds

        if self.history:
            history = [float(self.shown(self.objective, v)) for v in self.history]
            unit = self.unit(self.objective)
            return plot_convergence(history, self.objective or "objective", unit=unit, ax=ax)
        return plot_in_bounds(
            {k: (v - self.bounds[k][0]) for k, v in self.params.items()},
            {k: (0.0, hi - lo) for k, (lo, hi) in self.bounds.items()},
            ax=ax,
        )


def optimize(
    mech: Mechanism,
    bounds: Mapping[str, tuple[float, float]],
    poses: Poses,
    objective: Metric,
    sense: Literal["min", "max"] = "max",
    *,
    metrics: Sequence[Metric] = (),
    constraints: Sequence[Constraint] = (),
    method: Method = "slsqp",
    x0: Mapping[str, float] | None = None,
    loads: Any = None,
    seed: int = 0,
    maxiter: int = 200,
    popsize: int = 32,
    tol: float = 1e-12,
    units: Mapping[str, str] | None = None,
    progress: Callable[[int, int], None] | None = None,
    pose_sets: Mapping[str, Poses] | None = None,
) -> Optimum:
    """Minimise or maximise ``objective`` over designs within ``bounds``.

    Parameters
    ----------
    mech : Mechanism
    bounds : mapping of str to (float, float)
        Design parameters (names of ``mech.parameters``) and their bounds, SI.
    poses : Poses
        Every design is solved at these poses.
    objective : Metric
        Its reduce is ``min``, ``max``, ``absmax`` (from a target, if it has one), ``mean``,
        ``first``, ``last``, ``change`` or ``sumsq`` (with a target).
    sense : {"min", "max"}
    metrics : sequence of Metric
        Metrics the constraints refer to (besides the objective).
    constraints : sequence of Constraint
        For a local method, a constraint on a ``min`` metric needs a lower bound and one on a
        ``max`` or ``absmax`` metric an upper bound (those are exact per-pose constraints). A
        smooth metric (``mean``, ``sumsq``, ``change``) whose bounds are equal is an equality.
    method : {"slsqp", "differential-evolution"}
    x0 : mapping, optional
        Start of a local method (default: the model's own values, clipped to the bounds).
    loads : optional
        Loads for the kinetostatics (``"model"``), needed by force columns.
    seed : int
        Differential evolution's seed.
    maxiter, popsize, tol
        The optimisers' iteration limit, population size per parameter (differential
        evolution) and tolerance.
    units : mapping of str to str, optional
        The units to show the optimum in, by ``design.NAME`` and metric name (a study's
        ``units``); SI where absent. Nothing computed depends on them.
    progress : callable, optional
        ``progress(iterations, maxiter)`` after each iteration (the optimiser may stop
        before ``maxiter``).
    pose_sets : mapping of str to Poses, optional
        Named pose sets besides ``poses`` (a metric reads the set its ``poses`` names);
        every design is solved at every pose of every set
        ([`pose_sets_of`][excavkin.studies.metrics.pose_sets_of]).

    Returns
    -------
    Optimum
    """
    problem = _MechanismProblem(
        mech, bounds, poses, objective, sense, metrics, constraints, loads, pose_sets
    )
    best = run(
        problem, method, x0, seed=seed, maxiter=maxiter, popsize=popsize, tol=tol,
        progress=progress,
    )  # fmt: skip
    return replace(best, units=dict(units or {}))


def run(
    problem: Problem,
    method: str,
    x0: Mapping[str, float] | None = None,
    *,
    seed: int = 0,
    maxiter: int = 200,
    popsize: int = 32,
    tol: float = 1e-12,
    progress: Callable[[int, int], None] | None = None,
) -> Optimum:
    """Optimise ``problem`` (see [`optimize`][excavkin.studies.optimize.optimize] for the
    arguments)."""
    problem.progress = progress
    if method == "differential-evolution":
        return replace(problem.differential_evolution(seed, maxiter, popsize, tol), method=method)
    if method != "slsqp":
        raise InputError(f"unknown method {method!r} (known: {', '.join(METHODS)})")
    start = problem.start(x0)
    return replace(problem.local(start, method, maxiter, tol), method=method)


class Problem:
    """The optimisation in scaled variables u ∈ [0, 1]ⁿ (and an epigraph variable t).

    A subclass gives the designs' metrics: `columns_at` (each metric's column at every
    pose and its gradient) and `table` (a table of designs, as
    [`evaluate`][excavkin.studies.metrics.evaluate] makes).
    """

    #: divide a smooth objective by its size at the start (a subclass's choice: a machine's
    #: figures in N or kg would otherwise dwarf the scaled parameters' unit box)
    SCALE_OBJECTIVE = False

    def __init__(
        self,
        parameters: Mapping[str, float],
        bounds: Mapping[str, tuple[float, float]],
        poses: Poses,
        objective: Metric,
        sense: str,
        metrics: Sequence[Metric],
        constraints: Sequence[Constraint],
    ) -> None:
        from excavkin.errors import unknown_name

        for name in bounds:
            if name not in parameters:
                raise unknown_name("parameter", name, list(parameters))
        if sense not in ("min", "max"):
            raise InputError(f"sense must be 'min' or 'max', not {sense!r}")
        by_name = {m.name: m for m in (objective, *metrics)}
        for c in constraints:
            if c.metric not in by_name:
                raise unknown_name("metric (in a constraint)", c.metric, sorted(by_name))
        self.nominal = dict(parameters)
        self.names = list(bounds)
        self.lo = np.array([bounds[k][0] for k in self.names], dtype=np.float64)
        self.hi = np.array([bounds[k][1] for k in self.names], dtype=np.float64)
        if not (
            np.isfinite(self.lo).all() and np.isfinite(self.hi).all() and (self.lo < self.hi).all()
        ):
            raise InputError("every parameter's bounds must be finite with low < high")
        self.poses = poses
        self.objective = objective
        self.sign = 1.0 if sense == "min" else -1.0
        self.metrics = list(by_name.values())
        self.by_name = by_name
        self.constraints = list(constraints)
        self.history: list[float] = []
        #: the angle columns (their ``change`` is followed along the poses); a subclass's
        self.angles: set[str] = set()
        self.evaluations = 0
        #: the kind of each parameter (``design.NAME``) and metric; a subclass's
        self.kinds: dict[str, str] = {}
        #: ``progress(iterations, maxiter)`` after each iteration, if given
        self.progress: Callable[[int, int], None] | None = None
        self.iterations = 0
        self._memo: dict[bytes, tuple[dict[str, F], dict[str, F], bool]] = {}
        # an epigraph variable when the objective is a least or greatest value over poses
        self.epigraph = objective.reduce in ("min", "max", "absmax")

    def columns_at(self, u: F) -> tuple[dict[str, F], dict[str, F], bool]:
        """Each metric's column at every pose, its gradient in u (poses × parameters), and
        whether every pose solved."""
        raise NotImplementedError

    def table(self, designs: Mapping[str, F]) -> pd.DataFrame:
        """The metrics of designs (parameter → values, SI), one row per design."""
        raise NotImplementedError

    def remember(
        self, u: F, out: tuple[dict[str, F], dict[str, F], bool]
    ) -> tuple[dict[str, F], dict[str, F], bool]:
        """Keep ``columns_at(u)`` for the next call at the same u."""
        if len(self._memo) > 8:
            self._memo.clear()
        self._memo[u.tobytes()] = out
        return out

    def tick(self, of: int) -> None:
        """Report one more iteration (of at most ``of``) to ``progress``."""
        self.iterations += 1
        if self.progress is not None:
            self.progress(self.iterations, of)

    # ---- designs
    def params_of(self, u: F) -> dict[str, float]:
        x = self.lo + np.clip(u, 0.0, 1.0) * (self.hi - self.lo)
        return {k: float(v) for k, v in zip(self.names, x, strict=True)}

    def start(self, x0: Mapping[str, float] | None) -> F:
        given = dict(self.nominal)
        if x0 is not None:
            given.update(x0)
        x = np.array([given[k] for k in self.names], dtype=np.float64)
        return np.asarray(np.clip((x - self.lo) / (self.hi - self.lo), 0.0, 1.0))

    def column(self, m: Metric, u: F) -> tuple[F, F]:
        """A metric's column at every pose, less its target if it has one, and its gradient."""
        values, grads, _ = self.columns_at(u)
        c = values[m.key]
        return (c if m.target is None else c - target_of(m, c.size)), grads[m.key]

    def smooth(self, m: Metric, u: F) -> tuple[float, F]:
        """A smooth metric (mean, sumsq, change, first, last) and its gradient in u."""
        c, g = self.column(m, u)
        if m.reduce == "mean":
            return float(c.mean()), g.mean(axis=0)
        if m.reduce in ("first", "last"):
            k = 0 if m.reduce == "first" else -1
            return float(c[k]), g[k]
        if m.reduce == "sumsq":
            return float(c @ c), 2.0 * c @ g
        if m.reduce == "change":
            turn = angle_change(c) if m.column in self.angles else c[-1] - c[0]
            return float(turn), g[-1] - g[0]
        raise InputError(f"metric {m.name!r} ({m.reduce}) is not smooth")

    def true_value(self, u: F) -> float:
        """The objective metric at u, from the solve kept for u."""
        c, _ = self.column(self.objective, u)
        how = self.objective.reduce
        if how in SMOOTH:
            return self.smooth(self.objective, u)[0]
        if how == "absmax":
            return float(np.max(np.abs(c)))
        return float(np.min(c) if how == "min" else np.max(c))

    def metric_values(self, params: Mapping[str, float]) -> tuple[dict[str, float], bool]:
        table = self.table({k: np.array([v]) for k, v in params.items()})
        return {m.name: float(table[m.name][0]) for m in self.metrics}, bool(
            table["poses_failed"][0] == 0
        )

    # ---- local
    def local(self, u0: F, method: str, maxiter: int, tol: float) -> Optimum:
        from scipy.optimize import Bounds, minimize

        n = len(self.names)
        obj = self.objective
        if obj.reduce == "sumsq" and not self.constraints and self.sign > 0:
            return self._least_squares(u0, maxiter)
        if self.epigraph:
            c0, _ = self.column(obj, u0)
            c0 = np.abs(c0) if obj.reduce == "absmax" else c0
            t0 = float(np.min(c0) if obj.reduce == "min" else np.max(c0))
            self.scale = max(abs(t0), 1e-300)
            z0 = np.append(u0, t0 / self.scale)
        else:
            self.scale = 1.0
            if self.SCALE_OBJECTIVE:  # the objective's size at the start is 1
                v0 = self.smooth(obj, u0)[0]
                self.scale = abs(v0) if np.isfinite(v0) and v0 != 0.0 else 1.0
            z0 = u0
        constraints = self._local_constraints(n)

        def fun(z: F) -> tuple[float, F]:
            if self.epigraph:
                grad = np.zeros(z.size)
                grad[-1] = self.sign
                return self.sign * float(z[-1]), grad
            value, grad = self.smooth(obj, z[:n])
            return self.sign * value / self.scale, self.sign * grad / self.scale

        def record(z: F, *_: Any) -> None:
            value = self.true_value(z[:n])  # the metric itself, not its epigraph bound
            if np.isfinite(value):
                self.history.append(value)
            self.tick(maxiter)

        lo = np.zeros(z0.size)
        hi = np.ones(z0.size)
        if self.epigraph:
            lo[-1], hi[-1] = -np.inf, np.inf
        cons = [
            {"type": kind, "fun": (lambda z, f=f: f(z)[0]), "jac": (lambda z, f=f: f(z)[1])}
            for kind, f in constraints
        ]
        res = minimize(
            fun, z0, jac=True, method="SLSQP", bounds=Bounds(lo, hi), constraints=cons,
            options={"maxiter": maxiter, "ftol": tol}, callback=record,
        )  # fmt: skip
        return self._optimum(res.x[:n], bool(res.success), str(res.message))

    def _least_squares(self, u0: F, maxiter: int) -> Optimum:
        """A sum of squares with no constraints: scipy's least_squares on the residuals and
        their exact Jacobian (quadratic convergence to the round-off of the residuals)."""
        from scipy.optimize import least_squares

        m = self.objective

        def residuals(u: F) -> F:
            r, _ = self.column(m, u)
            if np.isfinite(r).all():
                self.history.append(float(r @ r))
            self.tick(10 * maxiter)
            return np.nan_to_num(r, nan=1e3)

        def jacobian(u: F) -> F:
            return np.nan_to_num(self.columns_at(u)[1][m.key])

        res = least_squares(
            residuals, u0, jac=jacobian, bounds=(0.0, 1.0), method="trf",
            xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=10 * maxiter,
        )  # fmt: skip
        return self._optimum(res.x, bool(res.success), str(res.message))

    def _local_constraints(self, n: int) -> list[tuple[str, Any]]:
        """Each constraint (and the epigraph) as ("ineq", z → (g(z) ≥ 0, jacobian)) or
        ("eq", z → (g(z) = 0, jacobian))."""
        out: list[tuple[str, Any]] = []
        obj = self.objective
        if self.epigraph:
            out.append(("ineq", self._per_pose(obj, n, epigraph=True)))
        for c in self.constraints:
            m = self.by_name[c.metric]
            if m.reduce in SMOOTH:
                if c.low is not None and c.low == c.high:
                    out.append(("eq", self._smooth_bound(m, c.low, 1.0, n)))
                    continue
                for bound, sign in ((c.low, 1.0), (c.high, -1.0)):
                    if bound is not None:
                        out.append(("ineq", self._smooth_bound(m, bound, sign, n)))
                continue
            if (
                (m.reduce == "min" and c.high is not None)
                or (m.reduce in ("max", "absmax") and c.low is not None)
                or m.reduce in ("argmin", "argmax")
            ):
                raise InputError(
                    f"constraint on {c.metric!r}: a local method needs a lower bound on a min "
                    "metric and an upper bound on a max one; use differential-evolution"
                )
            out.append(("ineq", self._per_pose(m, n, bound=c.low if m.reduce == "min" else c.high)))
        return out

    def _per_pose(
        self, m: Metric, n: int, epigraph: bool = False, bound: float | None = None
    ) -> Any:
        """``c_k − t ≥ 0`` (min), ``t − c_k ≥ 0`` (max), ``t ∓ c_k ≥ 0`` (absmax) at every pose,
        t the epigraph variable or the bound."""

        def g(z: F) -> tuple[F, F]:
            c, dc = self.column(m, z[:n])
            t = z[-1] * self.scale if epigraph else float(bound)  # type: ignore[arg-type]
            jac_t = np.full((c.size, 1), self.scale)
            if m.reduce == "min":
                val, jac = c - t, np.hstack([dc, -jac_t]) if epigraph else dc
            elif m.reduce == "max":
                val, jac = t - c, np.hstack([-dc, jac_t]) if epigraph else -dc
            else:
                val = np.concatenate([t - c, t + c])
                jac = np.vstack([-dc, dc])
                if epigraph:
                    jac = np.hstack([jac, np.vstack([jac_t, jac_t])])
            if not epigraph and self.epigraph:
                jac = np.hstack([jac, np.zeros((jac.shape[0], 1))])
            return np.nan_to_num(val, nan=-1e30), np.nan_to_num(jac)

        return g

    def _smooth_bound(self, m: Metric, bound: float, sign: float, n: int) -> Any:
        def g(z: F) -> tuple[F, F]:
            value, grad = self.smooth(m, z[:n])
            jac = sign * grad
            if self.epigraph:
                jac = np.append(jac, 0.0)
            return np.array([sign * (value - bound)]), jac[None, :]

        return g

    # ---- global
    def differential_evolution(self, seed: int, maxiter: int, popsize: int, tol: float) -> Optimum:
        from scipy.optimize import differential_evolution

        n = len(self.names)

        def population(u: F) -> F:
            """The objective of every design of a population (u: n × S), one batch solve."""
            u = np.atleast_2d(u.T if u.ndim == 2 else u[None, :]).reshape(-1, n)
            designs = {
                k: self.lo[j] + u[:, j] * (self.hi[j] - self.lo[j])
                for j, k in enumerate(self.names)
            }
            table = self.table(designs)
            self.evaluations += len(u)
            f = self.sign * table[self.objective.name].to_numpy(dtype=np.float64)
            penalty = np.where(table["poses_failed"].to_numpy() > 0, 1.0, 0.0)
            for c in self.constraints:
                v = table[c.metric].to_numpy(dtype=np.float64)
                scale = max(abs(c.low or 0.0), abs(c.high or 0.0), 1e-12)
                if c.low is not None:
                    penalty += np.maximum(c.low - v, 0.0) / scale
                if c.high is not None:
                    penalty += np.maximum(v - c.high, 0.0) / scale
            big = 1e3 * max(float(np.nanmax(np.abs(f), initial=0.0)), 1.0)
            return np.where(np.isfinite(f), f, big) + big * np.nan_to_num(penalty, nan=1.0)

        def record(xk: F, convergence: float = 0.0) -> None:
            self.history.append(self.sign * float(population(np.asarray(xk))[0]))
            self.tick(maxiter)

        res = differential_evolution(
            population, [(0.0, 1.0)] * n, vectorized=True, updating="deferred", seed=seed,
            maxiter=maxiter, popsize=popsize, tol=tol, polish=False, callback=record,
        )  # fmt: skip
        best = np.asarray(res.x)
        # polish locally where the constraints allow it
        try:
            polished = self.local(best, "slsqp", maxiter, tol)
        except InputError:
            return self._optimum(best, bool(res.success), str(res.message))
        if polished.feasible and self.sign * polished.value <= self.sign * self.value_of(best):
            return polished
        return self._optimum(best, bool(res.success), str(res.message))

    def value_of(self, u: F) -> float:
        values, _ = self.metric_values(self.params_of(u))
        return values[self.objective.name]

    # ---- the answer
    def _optimum(self, u: F, success: bool, message: str) -> Optimum:
        params = self.params_of(u)
        values, solved = self.metric_values(params)
        active, feasible = [], solved
        for c in self.constraints:
            v = values[c.metric]
            scale = max(abs(v), abs(c.low or 0.0), abs(c.high or 0.0), 1e-300)
            for bound, below in ((c.low, True), (c.high, False)):
                if bound is None:
                    continue
                gap = (v - bound) if below else (bound - v)
                if gap < -1e-9 * scale:
                    feasible = False
                if abs(gap) <= 1e-6 * scale:
                    active.append(c.metric)
        return Optimum(
            params=params,
            value=values[self.objective.name],
            metrics=values,
            active=tuple(dict.fromkeys(active)),
            at_bounds={
                k: "low" if v <= 1e-9 else "high"
                for k, v in zip(self.names, np.clip(u, 0.0, 1.0), strict=True)
                if v <= 1e-9 or v >= 1.0 - 1e-9
            },
            feasible=feasible,
            success=success,
            message=message,
            history=tuple(self.history),
            evaluations=self.evaluations,
            objective=self.objective.name,
            sense="min" if self.sign > 0 else "max",
            bounds={
                k: (float(a), float(b))
                for k, a, b in zip(self.names, self.lo, self.hi, strict=True)
            },
            kinds=dict(self.kinds),
        )


class _MechanismProblem(Problem):
    """A mechanism's designs: exact sensitivities from the differentiated plan."""

    def __init__(
        self,
        mech: Mechanism,
        bounds: Mapping[str, tuple[float, float]],
        poses: Poses,
        objective: Metric,
        sense: str,
        metrics: Sequence[Metric],
        constraints: Sequence[Constraint],
        loads: Any,
        pose_sets: Mapping[str, Poses] | None = None,
    ) -> None:
        from excavkin.studies.metrics import check_pose_sets, needs_forces
        from excavkin.studies.study import metric_kind

        super().__init__(mech.parameters, bounds, poses, objective, sense, metrics, constraints)
        self.mech = mech
        self.loads = loads
        self.pose_sets = dict(pose_sets or {})
        self.sets = pose_sets_of(poses, self.pose_sets)
        check_pose_sets(self.sets, self.metrics)
        needs_forces(mech, self.metrics)  # unknown columns and points, named
        #: the columns to differentiate in each set: the metrics' and their clearances' points
        self.wanted: dict[str | None, list[str]] = {}
        for name in self.sets:
            cols: list[str] = []
            for m in self.metrics:
                if m.poses == name:
                    ends = m.clearance or ()
                    cols += [f"{p}.{a}" for p in ends for a in "xy"] if ends else [m.column]
            self.wanted[name] = list(dict.fromkeys(cols))
        run = probe_execution()
        probe = (
            mech.solve({}, loads=[], execution=run)
            if loads is not None
            else mech.solve({}, execution=run)
        )
        self.angles = {c.name for c in probe.columns if c.kind == "angle"}
        from excavkin.structure.design import parameter_kind

        of = {c.name: c.kind for c in probe.columns}
        self.kinds = {f"design.{k}": parameter_kind(k, mech.model) for k in self.names}
        for m in self.metrics:
            self.kinds[m.name] = metric_kind(m, of)

    def table(self, designs: Mapping[str, F]) -> pd.DataFrame:
        from excavkin.studies.fused import evaluate_designs

        return evaluate_designs(
            self.mech, designs, self.poses, self.metrics, (), self.loads, self.pose_sets
        )

    def columns_at(self, u: F) -> tuple[dict[str, F], dict[str, F], bool]:
        """Each metric's column at every pose, its gradient in u (poses × parameters), and
        whether every pose solved — one solve with sensitivities, kept for the next call at
        the same u."""
        key = u.tobytes()
        if key in self._memo:
            return self._memo[key]
        params = self.params_of(u)
        values: dict[str, F] = {}
        grads: dict[str, F] = {}
        solved = True
        span = self.hi - self.lo

        def gradient(res: Any, column: str, size: int) -> F:
            """∂column/∂u at every pose, shape (poses, parameters)."""
            return np.stack(
                [
                    np.asarray(res.sensitivity(column, k)) * s
                    for k, s in zip(self.names, span, strict=True)
                ],
                axis=-1,
            ).reshape(size, len(self.names))

        for name, poses in self.sets.items():  # one solve with sensitivities per pose set
            # only the metrics' columns are differentiated (every one when forces are)
            wanted = None if self.loads is not None else self.wanted[name]
            res: Any = self.mech.solve(  # type: ignore[call-overload]
                poses.values, poses.rates, poses.accels,
                params=params, sensitivities=self.names, loads=self.loads,
                sensitivity_columns=wanted,
            )  # fmt: skip
            kin = res if self.loads is None else res.kinematics
            ok = (
                kin.status.solved
                if self.loads is None
                else kin.status.solved & ~res.singular & ~res.slack
            )
            solved = solved and bool(np.all(ok))
            for m in self.metrics:
                if m.poses != name:
                    continue
                if m.clearance is None:
                    col = column_of(res, m.column)
                    values[m.key], grads[m.key] = col, gradient(res, m.column, col.size)
                    continue
                values[m.key], grads[m.key] = self._clearance(res, m.clearance, gradient)
        self.evaluations += 1
        return self.remember(u, (values, grads, solved))

    @staticmethod
    def _clearance(
        res: Any, points: tuple[str, ...], gradient: Callable[[Any, str, int], F]
    ) -> tuple[F, F]:
        """A clearance at every pose and its gradient in u: the segments' gradient in their
        ends' coordinates times the ends' sensitivities."""
        from excavkin.studies.clearance import segment_clearance

        ends = [
            np.stack([column_of(res, f"{p}.x"), column_of(res, f"{p}.y")], axis=-1) for p in points
        ]
        value, by_end = segment_clearance(*ends, gradient=True)
        size = value.size
        grad = np.zeros((size, 0))
        for i, p in enumerate(points):
            for a, axis in enumerate("xy"):
                term = by_end[:, i, a, None] * gradient(res, f"{p}.{axis}", size)
                grad = term if grad.shape[1] == 0 else grad + term
        return value, grad


def optimize_study(
    study: str | PathLike[str] | Study,
    objective: str | None = None,
    sense: Literal["min", "max"] | None = None,
    *,
    method: Method | None = None,
    x0: Mapping[str, float] | None = None,
    maxiter: int | None = None,
    popsize: int | None = None,
    tol: float = 1e-12,
    progress: Callable[[int, int], None] | None = None,
) -> Optimum:
    """The best design of a study's box under its constraints, in one call: what
    ``excavkin optimize STUDY`` does. Arguments left out come from the study file's
    ``[optimize]`` table; the optimum is shown in the study's units.

    Parameters
    ----------
    study : path or Study
        A study file (a path, or a built-in example's name) or a loaded
        [`Study`][excavkin.studies.study.Study].
    objective : str, optional
        A metric's name (default: the ``[optimize]`` table's ``objective``).
    sense : {"min", "max"}, optional
        Default the table's, else "max".
    method : {"slsqp", "differential-evolution"}, optional
        Default the table's, else "slsqp".
    x0 : mapping, optional
        Start of a local method (default: the model's own values, clipped to the bounds).
    maxiter, popsize : int, optional
        Default the table's, else 200 and 32.
    tol : float
    progress : callable, optional
        ``progress(iterations, maxiter)`` after each iteration.

    Returns
    -------
    Optimum

    Raises
    ------
    InputError
        The study names no objective, or an unknown one.
    """
    from excavkin import load
    from excavkin.studies.study import Study

    if not isinstance(study, Study):
        study = _load(study)
    s = study.optimize
    name = objective or s.get("objective")
    if name is None:
        raise InputError("the study has no [optimize] table naming its objective: give objective=")
    by_name = {m.name: m for m in study.metrics}
    if name not in by_name:
        from excavkin.errors import unknown_name

        raise unknown_name("metric (the objective)", str(name), list(by_name))
    best = optimize(
        load(study.model), study.bounds, study.poses, by_name[name],
        sense or s.get("sense", "max"),
        metrics=[m for m in study.metrics if m.name != name],
        constraints=study.constraints, method=method or s.get("method", "slsqp"), x0=x0,
        loads=study.loads, seed=study.seed, maxiter=maxiter or s.get("maxiter", 200),
        popsize=popsize or s.get("popsize", 32), tol=tol, units=study.units, progress=progress,
        pose_sets=study.pose_sets,
    )  # fmt: skip
    return replace(best, model=study.model)


def _load(path: str | PathLike[str]) -> Study:
    """A study file: a path, or a built-in example's name."""
    import excavkin
    from excavkin.studies.study_file import load_study

    given = Path(path)
    if not given.exists() and str(path) in excavkin.examples("study"):
        given = excavkin.example_path(str(path))
    return load_study(given)
