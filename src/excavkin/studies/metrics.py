"""Metrics of a family of designs over a pose set: each design solved at every pose in one
batch over the geometry axis, a column reduced over the poses (min, max, …), and constraints
on the metrics."""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError

if TYPE_CHECKING:
    import pandas as pd

    from excavkin.mechanism import Mechanism


Reduce = Literal[
    "min", "max", "absmax", "mean", "sumsq", "change", "argmin", "argmax", "first", "last"
]  # fmt: skip
REDUCTIONS: tuple[str, ...] = (
    "min", "max", "absmax", "mean", "sumsq", "change", "argmin", "argmax", "first", "last",
)  # fmt: skip


@dataclass(frozen=True, slots=True)
class Metric:
    """One number per design: ``column`` reduced over the pose set.

    ``argmin``/``argmax`` give the index of the pose where the column is least or greatest;
    ``first``/``last`` its value at the first or the last pose (NaN if that pose fails);
    ``sumsq`` the sum over the poses of the squared differences from ``target`` and ``absmax``
    the largest absolute difference from it (``target``: one value, or one per pose, SI; absmax
    without a target is the largest magnitude); ``change`` the value at the last pose minus
    that at the first (a rocker's swing between its two dead centres, say; an angle's followed
    along the poses, so that passing ±180° is no jump).

    Attributes
    ----------
    name : str
        The metric's name: its column in the study's table.
    column : str
        A column of the solve's table (kinematic or force), e.g. ``"rocker.angle"``.
    reduce : str
        How the column is reduced over the poses: ``min``, ``max``, ``absmax``, ``mean``,
        ``sumsq``, ``change``, ``argmin``, ``argmax``, ``first`` or ``last``.
    target : tuple of float, optional
        For ``sumsq`` (needed) and ``absmax`` only: one value, or one per pose, in the
        column's SI unit.
    """

    name: str
    column: str
    reduce: Reduce
    target: tuple[float, ...] | None = None


@dataclass(frozen=True, slots=True)
class Constraint:
    """Bounds on a metric, SI (either may be None).

    Attributes
    ----------
    metric : str
        The metric's name.
    low, high : float or None
        Its least and greatest allowed values, in the metric's SI unit; None: unbounded.
    """

    metric: str
    low: float | None = None
    high: float | None = None


@dataclass(frozen=True, slots=True)
class Poses:
    """The pose set every design is solved at: driver values (arrays of one length, or
    scalars held), rates and accelerations, SI.

    Attributes
    ----------
    values : mapping of str to array_like
        Input name → its value at each pose, shape (p,), or a scalar held at every pose (rad
        or m).
    rates, accels : mapping of str to array_like
        Input name → its rate (rad/s or m/s) and acceleration (rad/s² or m/s²), as
        ``Mechanism.solve`` takes them.
    """

    values: Mapping[str, Any]
    rates: Mapping[str, Any]
    accels: Mapping[str, Any]

    @property
    def count(self) -> int:
        sizes = {np.size(v) for v in self.values.values() if np.ndim(v)}
        if len(sizes) > 1:
            raise InputError(f"the poses' sweeps have different lengths: {sorted(sizes)}")
        return sizes.pop() if sizes else 1


def needs_forces(mech: Mechanism, metrics: Sequence[Metric]) -> bool:
    """Whether a metric reads a force column (the designs then get their kinetostatics); an
    unknown column is an error naming it."""
    from excavkin.errors import unknown_name

    kin = {c.name for c in mech.solve({}).columns}
    forces = {c.name for c in mech.solve({}, loads=[]).columns} - kin
    for m in metrics:
        if m.column not in kin and m.column not in forces:
            raise unknown_name(f"column (metric {m.name!r})", m.column, sorted(kin | forces))
        if m.reduce not in REDUCTIONS:
            raise InputError(
                f"metric {m.name!r}: reduce must be one of {', '.join(REDUCTIONS)}, "
                f"not {m.reduce!r}"
            )
    return any(m.column in forces for m in metrics)


def evaluate(
    mech: Mechanism,
    designs: Mapping[str, F],
    poses: Poses,
    metrics: Sequence[Metric],
    constraints: Sequence[Constraint] = (),
    loads: Any = None,
) -> pd.DataFrame:
    """Every design at every pose, as one solve of designs × poses samples; one row per design.

    Parameters
    ----------
    mech : Mechanism
    designs : mapping of str to ndarray, shape (d,)
        Parameter values (SI) per design.
    poses : Poses
    metrics : sequence of Metric
    constraints : sequence of Constraint
    loads : optional
        Loads for the kinetostatics (``"model"``: the model's own), needed by force metrics.

    Returns
    -------
    pandas.DataFrame
        ``design.<parameter>`` columns, one column per metric, ``poses_failed`` (poses that did
        not solve, or are statically singular), ``feasible`` (every pose solved and every
        constraint met) and ``status`` ("ok", or why not). A metric is over the poses that
        solved; NaN if none did.
    """
    d = len(next(iter(designs.values())))
    p = poses.count
    params = {k: np.repeat(np.asarray(v, dtype=np.float64), p) for k, v in designs.items()}
    values = {k: _tile(v, p, d) for k, v in poses.values.items()}
    rates = {k: _tile(v, p, d) for k, v in poses.rates.items()}
    accels = {k: _tile(v, p, d) for k, v in poses.accels.items()}
    n = d * p
    res: Any = mech.solve(values, rates, accels, params=params, loads=loads)
    ok = res.status.solved if loads is None else res.kinematics.status.solved & ~res.singular
    columns = {c.name for c in res.columns}
    ok = np.broadcast_to(ok, (n,)).reshape(d, p)
    cols: dict[str, F] = {}
    for m in metrics:
        if m.column not in columns:
            from excavkin.errors import unknown_name

            raise unknown_name(f"column (metric {m.name!r})", m.column, sorted(columns))
        cols[m.column] = column_of(res, m.column).reshape(d, p)
    angles = {c.name for c in res.columns if c.kind == "angle"}
    return tabulate(designs, cols, ok, metrics, constraints, angles)


#: the study table's own columns: a metric of one of these names would collide with it (the
#: parameters' columns are ``design.<name>``, so no metric name may begin with ``design.``)
RESERVED_COLUMNS = ("design", "poses_failed", "feasible", "status")


def reserved_name(name: str) -> str | None:
    """Why ``name`` cannot name a metric (it is one of the study table's own columns), or
    ``None`` when it can.

    Parameters
    ----------
    name : str
        A metric's name.

    Returns
    -------
    str or None
    """
    if name in RESERVED_COLUMNS or name.startswith("design."):
        return (
            f"{name!r} is a column of the study table itself; a metric cannot take a reserved "
            f"name ({', '.join(RESERVED_COLUMNS)}, design.<parameter>)"
        )
    return None


def tabulate(
    designs: Mapping[str, F],
    columns: Mapping[str, F],
    ok: NDArray[np.bool_],
    metrics: Sequence[Metric],
    constraints: Sequence[Constraint] = (),
    angles: Collection[str] = (),
) -> pd.DataFrame:
    """The study's table from each metric's column at every design and pose (shape
    (designs, poses)) and whether each pose solved (same shape): the metrics reduced over
    the poses that solved, and each design's feasibility (see
    [`evaluate`][excavkin.studies.metrics.evaluate]). The
    ``change`` of a column in ``angles`` is taken along the poses (`angle_change`)."""
    import pandas as pd

    d, p = ok.shape
    out: dict[str, Any] = {f"design.{k}": np.asarray(v) for k, v in designs.items()}
    for m in metrics:
        col = columns[m.column]
        if m.reduce == "sumsq" or m.target is not None:
            col = col - target_of(m, p)
        if m.reduce == "change" and m.column in angles:
            out[m.name] = angle_change(np.where(ok, col, np.nan))
        else:
            out[m.name] = _reduce(np.where(ok, col, np.nan), m.reduce)
    failed = (~ok).sum(axis=1)
    out["poses_failed"] = failed
    met = failed == 0
    why = np.where(failed > 0, np.char.add(failed.astype(str), f" of {p} poses do not solve"), "")
    for c in constraints:
        value = out[c.metric]
        inside = np.ones(d, dtype=bool)
        if c.low is not None:
            inside &= value >= c.low
        if c.high is not None:
            inside &= value <= c.high
        hit = met & ~inside
        why = np.where(hit, f"constraint on {c.metric} not met", why)
        met &= inside
    out["feasible"] = met
    out["status"] = np.where(why == "", "ok", why)
    return pd.DataFrame(out)


def _tile(v: Any, p: int, d: int) -> Any:
    """A pose set's values repeated for every design (design-major order)."""
    a = np.asarray(v, dtype=np.float64)
    return np.tile(a, d) if a.ndim else float(a)


def column_of(res: Any, name: str) -> F:
    """A kinematic or force column of a result by name."""
    kin = res if not hasattr(res, "kinematics") else res.kinematics
    if name in {c.name for c in kin.columns}:
        return np.asarray(kin.column(name), dtype=np.float64)
    return np.asarray(res.column(name), dtype=np.float64)


def target_of(m: Metric, p: int) -> F:
    """A metric's target at each of ``p`` poses (one value is held at every pose)."""
    if m.target is None:
        raise InputError(f"metric {m.name!r}: {m.reduce} needs a target value per pose")
    if m.reduce not in ("sumsq", "absmax"):
        raise InputError(f"metric {m.name!r}: a target belongs to a sumsq or absmax metric")
    t = np.asarray(m.target, dtype=np.float64)
    if t.size not in (1, p):
        raise InputError(f"metric {m.name!r}: {t.size} targets for {p} poses")
    return np.broadcast_to(t, (p,)) if t.size == 1 else t


def angle_change(a: F) -> F:
    """An angle's change from the first pose to the last (axis 1), followed along the poses:
    each step the shorter way round, so that an angle passing ±180° turns on rather than
    jumps by 360° (neighbouring poses must be less than 180° apart; NaN unless every pose
    solved)."""
    step = np.diff(a, axis=-1)
    return np.asarray(np.sum((step + np.pi) % (2.0 * np.pi) - np.pi, axis=-1))


def _reduce(a: F, how: str) -> F:
    """Reduce over the poses (axis 1), ignoring poses that did not solve (NaN)."""
    if how in ("first", "last"):
        return np.asarray(a[:, 0 if how == "first" else -1])
    empty = np.asarray(np.isnan(a).all(axis=1))
    filled = np.where(empty[:, None], 0.0, a)
    if how == "min":
        r = np.nanmin(filled, axis=1)
    elif how == "max":
        r = np.nanmax(filled, axis=1)
    elif how == "absmax":
        r = np.nanmax(np.abs(filled), axis=1)
    elif how == "mean":
        r = np.nanmean(filled, axis=1)
    elif how == "sumsq":
        r = np.nansum(filled * filled, axis=1)
    elif how == "change":  # NaN unless both ends solved
        r = a[:, -1] - a[:, 0]
    elif how == "argmin":
        r = np.nanargmin(np.where(np.isnan(filled), np.inf, filled), axis=1).astype(np.float64)
    else:
        r = np.nanargmax(np.where(np.isnan(filled), -np.inf, filled), axis=1).astype(np.float64)
    return np.where(empty, np.nan, r)
