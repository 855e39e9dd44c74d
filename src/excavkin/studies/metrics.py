"""Metrics of a family of designs over pose sets: each design solved at every pose of a set in
one batch over the geometry axis, a column (or the clearance of two segments) reduced over the
set's poses (min, max, …), and constraints on the metrics.

A study has a default pose set (a study file's ``[poses]``) and any number of named ones
(``[pose_sets.NAME]``); a metric reads the set it names (``Metric.poses``), the default where
it names none."""

from __future__ import annotations

import functools
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError

if TYPE_CHECKING:
    import pandas as pd

    from excavkin.execution import Execution
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
    poses : str, optional
        The pose set the metric reads (None: the study's default set).
    clearance : (str, str, str, str), optional
        For a clearance metric (made by `clearance_metric`): the points P0, P1, Q0, Q1 of its
        two segments; its ``column`` then only names it.
    """

    name: str
    column: str
    reduce: Reduce
    target: tuple[float, ...] | None = None
    poses: str | None = None
    clearance: tuple[str, str, str, str] | None = None

    @property
    def key(self) -> str:
        """The per-pose series the metric reduces: its column, within its pose set (a
        clearance's column is ``"clearance P0-P1 Q0-Q1"``)."""
        return self.column if self.poses is None else f"{self.poses}/{self.column}"


def clearance_metric(
    name: str,
    first: tuple[str, str],
    second: tuple[str, str],
    poses: str | None = None,
    reduce: Reduce = "min",
) -> Metric:
    """A metric that is the signed clearance of two segments between named points (a
    cylinder's pin-to-pin line, a body's edge), reduced over a pose set (by default its least
    value): their distance where they do not cross, minus the depth of their penetration where
    they do ([`segment_clearance`][excavkin.studies.clearance.segment_clearance]).

    Parameters
    ----------
    name : str
        The metric's name.
    first, second : (str, str)
        Each segment's two points.
    poses : str, optional
        The pose set (default: the study's default set).
    reduce : str
        How the clearance is reduced over the poses (default ``"min"``).

    Returns
    -------
    Metric
    """
    column = f"clearance {first[0]}-{first[1]} {second[0]}-{second[1]}"
    return Metric(name, column, reduce, None, poses, (*first, *second))


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


def probe_execution() -> Execution:
    """The settings of a probe solve (a sample, for the columns' names and kinds): those in
    use (`excavkin.execution.current`), except that ``"auto"`` probes in NumPy (loading
    numba and a kernel for one sample costs more than the solve).

    Returns
    -------
    Execution
    """
    import dataclasses

    from excavkin.execution import current

    run = current()
    return dataclasses.replace(run, backend="numpy") if run.backend == "auto" else run


def needs_forces(mech: Mechanism, metrics: Sequence[Metric]) -> bool:
    """Whether a metric reads a force column (the designs then get their kinetostatics); an
    unknown column or point is an error naming it."""
    from excavkin.errors import unknown_name

    kin = {c.name for c in mech.solve({}, execution=probe_execution()).columns}
    read = {m.column for m in metrics if m.clearance is None}
    # the force columns only where a metric reads no kinematic column (the kinetostatics not
    # imported and solved for a kinematic study)
    forces = (
        {c.name for c in mech.solve({}, loads=[], execution=probe_execution()).columns} - kin
        if read - kin
        else set()
    )
    for m in metrics:
        if m.clearance is not None:
            points = sorted(mech.model.points)
            for point in m.clearance:
                if point not in mech.model.points:
                    raise unknown_name(f"point (clearance {m.name!r})", point, points)
        elif m.column not in kin and m.column not in forces:
            raise unknown_name(f"column (metric {m.name!r})", m.column, sorted(kin | forces))
        if m.reduce not in REDUCTIONS:
            raise InputError(
                f"metric {m.name!r}: reduce must be one of {', '.join(REDUCTIONS)}, "
                f"not {m.reduce!r}"
            )
    return any(m.column in forces for m in metrics if m.clearance is None)


def pose_sets_of(
    poses: Poses, pose_sets: Mapping[str, Poses] | None = None
) -> dict[str | None, Poses]:
    """Every pose set a study solves, by name (None: the default set): the default set and
    the named ones; where there are named sets and the default gives nothing (no driver
    value, rate or acceleration), the named sets alone.

    Parameters
    ----------
    poses : Poses
        The default set.
    pose_sets : mapping of str to Poses, optional
        The named sets.

    Returns
    -------
    dict of (str or None) to Poses
    """
    named = dict(pose_sets or {})
    empty = not (poses.values or poses.rates or poses.accels)
    out: dict[str | None, Poses] = {} if named and empty else {None: poses}
    out.update(named)
    return out


def check_pose_sets(sets: Mapping[str | None, Poses], metrics: Sequence[Metric]) -> None:
    """Refuse a metric that reads a pose set the study does not have.

    Parameters
    ----------
    sets : mapping of (str or None) to Poses
        The study's sets (`pose_sets_of`).
    metrics : sequence of Metric

    Raises
    ------
    InputError
        Naming the metric and the sets there are.
    """
    from excavkin.errors import unknown_name

    for m in metrics:
        if m.poses not in sets:
            if m.poses is None:
                raise InputError(
                    f"metric {m.name!r} names no pose set and the study has no default set "
                    f"([poses]): give it poses = one of {', '.join(str(k) for k in sets)}"
                )
            names = [str(k) for k in sets if k is not None]
            raise unknown_name(f"pose set (metric {m.name!r})", m.poses, names)


def evaluate(
    mech: Mechanism,
    designs: Mapping[str, F],
    poses: Poses,
    metrics: Sequence[Metric],
    constraints: Sequence[Constraint] = (),
    loads: Any = None,
    pose_sets: Mapping[str, Poses] | None = None,
) -> pd.DataFrame:
    """Every design at every pose of every pose set, as one solve of designs × poses samples
    per set; one row per design.

    Parameters
    ----------
    mech : Mechanism
    designs : mapping of str to ndarray, shape (d,)
        Parameter values (SI) per design.
    poses : Poses
        The default pose set (the metrics that name none read it).
    metrics : sequence of Metric
    constraints : sequence of Constraint
    loads : optional
        Loads for the kinetostatics (``"model"``: the model's own), needed by force metrics.
        A set with rates gives forces with their inertia, one without static forces.
    pose_sets : mapping of str to Poses, optional
        Named pose sets (see `pose_sets_of`).

    Returns
    -------
    pandas.DataFrame
        ``design.<parameter>`` columns, one column per metric, ``poses_failed`` (poses of
        every set that did not solve, or are statically singular), ``feasible`` (every pose
        solved and every constraint met) and ``status`` ("ok", or why not). A metric is over
        its set's poses that solved; NaN if none did.
    """
    sets = pose_sets_of(poses, pose_sets)
    check_pose_sets(sets, metrics)
    d = len(next(iter(designs.values())))
    series: dict[str, F] = {}
    oks: dict[str | None, NDArray[np.bool_]] = {}
    angles: set[str] = set()
    for name, pose_set in sets.items():
        res, oks[name] = solve_set(mech, designs, pose_set, d, loads)
        p = pose_set.count
        angles |= {c.name for c in res.columns if c.kind == "angle"}
        for m in metrics:
            if m.poses == name:
                series[m.key] = metric_series(res, m).reshape(d, p)
    return tabulate_sets(designs, series, oks, metrics, constraints, angles)


def solve_set(
    mech: Mechanism, designs: Mapping[str, F], poses: Poses, d: int, loads: Any
) -> tuple[Any, NDArray[np.bool_]]:
    """Every one of ``d`` designs at every pose of one set, one batch (design-major order).

    Parameters
    ----------
    mech : Mechanism
    designs : mapping of str to ndarray, shape (d,)
        Parameter values (SI) per design.
    poses : Poses
        The set: with rates, forces with their inertia; without, static forces.
    d : int
        The number of designs.
    loads : optional
        Loads for the kinetostatics (``"model"``), or None for kinematics alone.

    Returns
    -------
    result : KinematicResult or ForceResult
        The d × p samples, design-major.
    ok : ndarray of bool, shape (d, p)
        Whether each pose solved (and is not statically singular, and no rope is slack).
    """
    p = poses.count
    params = {k: np.repeat(np.asarray(v, dtype=np.float64), p) for k, v in designs.items()}
    values = {k: _tile(v, p, d) for k, v in poses.values.items()}
    rates = {k: _tile(v, p, d) for k, v in poses.rates.items()}
    accels = {k: _tile(v, p, d) for k, v in poses.accels.items()}
    res: Any = mech.solve(values, rates, accels, params=params, loads=loads)
    ok = (
        res.status.solved
        if loads is None
        else res.kinematics.status.solved & ~res.singular & ~res.slack
    )
    return res, np.broadcast_to(ok, (d * p,)).reshape(d, p)


def metric_series(res: Any, m: Metric) -> F:
    """A metric's per-sample series of a result: its column, or its two segments' clearance
    from their points' columns.

    Parameters
    ----------
    res : KinematicResult or ForceResult
    m : Metric

    Returns
    -------
    ndarray, shape (n,)
        One value per sample of ``res``.
    """
    if m.clearance is None:
        names = {c.name for c in res.columns}
        if m.column not in names:
            from excavkin.errors import unknown_name

            raise unknown_name(f"column (metric {m.name!r})", m.column, sorted(names))
        return column_of(res, m.column)
    from excavkin.studies.clearance import segment_clearance

    ends = [
        np.stack([column_of(res, f"{pt}.x"), column_of(res, f"{pt}.y")], axis=-1)
        for pt in m.clearance
    ]
    return np.asarray(segment_clearance(*ends))


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
    return tabulate_sets(designs, columns, {None: ok}, metrics, constraints, angles)


@dataclass(frozen=True, slots=True)
class SolvedPoses:
    """How many poses of a set each design solved, where the per-pose statuses stay where
    they were made (a study reduced on a device, `excavkin.studies.device`).

    Attributes
    ----------
    solved : ndarray of int64, shape (designs,)
        Each design's poses that solved.
    poses : int
        The set's poses.
    """

    solved: NDArray[np.int64]
    poses: int


def tabulate_sets(
    designs: Mapping[str, F],
    columns: Mapping[str, F],
    oks: Mapping[str | None, NDArray[np.bool_] | SolvedPoses],
    metrics: Sequence[Metric],
    constraints: Sequence[Constraint] = (),
    angles: Collection[str] = (),
    reduced: Mapping[str, F] | None = None,
) -> pd.DataFrame:
    """`tabulate` over several pose sets: each metric's series (by `Metric.key`, shape
    (designs, poses of its set)) reduced over its set's poses that solved (``oks``: set name →
    shape (designs, poses)); a design is feasible when every pose of every set solved and
    every constraint holds.

    Parameters
    ----------
    designs : mapping of str to ndarray, shape (d,)
    columns : mapping of str to ndarray, shape (d, p_set)
        Each metric's series by its key.
    oks : mapping of (str or None) to (ndarray of bool, shape (d, p_set), or SolvedPoses)
        Whether each pose of each set solved (`SolvedPoses`: how many, each of the set's
        metrics in ``reduced``).
    metrics, constraints
    angles : collection of str
        The angle columns (their ``change`` is followed along the poses).
    reduced : mapping of str to ndarray, shape (d,), optional
        Metrics already reduced, by name, as they would be here (a study's compiled pass,
        `excavkin.studies.reductions`): their series are not read.

    Returns
    -------
    pandas.DataFrame
        As [`evaluate`][excavkin.studies.metrics.evaluate] gives it.
    """
    import pandas as pd

    return pd.DataFrame(
        tabulate_columns(designs, columns, oks, metrics, constraints, angles, reduced)
    )


def tabulate_columns(
    designs: Mapping[str, F],
    columns: Mapping[str, F],
    oks: Mapping[str | None, NDArray[np.bool_] | SolvedPoses],
    metrics: Sequence[Metric],
    constraints: Sequence[Constraint] = (),
    angles: Collection[str] = (),
    reduced: Mapping[str, F] | None = None,
) -> dict[str, Any]:
    """`tabulate_sets`' columns by name, in the table's order, without making the table
    (a study writes them as Arrow arrays, `excavkin.studies.study.part_table`).

    Parameters
    ----------
    designs, columns, oks, metrics, constraints, angles, reduced
        As `tabulate_sets` takes them.

    Returns
    -------
    dict of str to array
        The columns of the table [`evaluate`][excavkin.studies.metrics.evaluate] gives,
        each an array of one value per design (the status's as pandas makes a column of
        text).
    """
    first = next(iter(oks.values()))
    d = first.solved.shape[0] if isinstance(first, SolvedPoses) else first.shape[0]
    out: dict[str, Any] = {f"design.{k}": np.asarray(v) for k, v in designs.items()}
    for m in metrics:
        if reduced is not None and m.name in reduced:
            out[m.name] = reduced[m.name]
            continue
        ok = oks[m.poses]
        if isinstance(ok, SolvedPoses):
            raise ValueError(f"metric {m.name!r}: its set's poses are counted, not given")
        col = columns[m.key]
        if m.reduce == "sumsq" or m.target is not None:
            col = col - target_of(m, ok.shape[1])
        if m.reduce == "change" and m.column in angles:
            out[m.name] = angle_change(np.where(ok, col, np.nan))
        else:
            out[m.name] = _reduce(np.where(ok, col, np.nan), m.reduce)
    failed = np.zeros(d, dtype=np.int64)
    # each design's status as a code into its texts (0: "ok"), so that no text is made per
    # design: the missing poses' counts and the constraints have a text each
    code = np.zeros(d, dtype=np.int32)
    texts = ["ok"]
    for name, ok in oks.items():
        if isinstance(ok, SolvedPoses):
            total, miss = ok.poses, ok.poses - ok.solved
        else:
            total, miss = ok.shape[1], ok.shape[1] - np.count_nonzero(ok, axis=1)
        where = "" if name is None else f" of set {name!r}"
        told = np.flatnonzero((code == 0) & (miss > 0))  # (a design's first reason kept)
        if told.size:
            counts, which = np.unique(miss[told], return_inverse=True)
            code[told] = len(texts) + which
            texts += [f"{c} of {total} poses{where} do not solve" for c in counts.tolist()]
        failed += miss
    out["poses_failed"] = failed
    met = failed == 0
    for c in constraints:
        value = out[c.metric]
        inside = np.ones(d, dtype=bool)
        if c.low is not None:
            inside &= value >= c.low
        if c.high is not None:
            inside &= value <= c.high
        hit = met & ~inside
        if hit.any():
            code[hit] = len(texts)
            texts.append(f"constraint on {c.metric} not met")
        met &= inside
    out["feasible"] = met
    out["status"] = _status_column(code, texts)
    return out


def _status_column(code: NDArray[np.int32], texts: Sequence[str]) -> Any:
    """Each design's status text, ``texts[code]``, as the column pandas makes of an array of
    text: made from the few texts by Arrow where pandas keeps text in Arrow (pandas 3), never
    one Python string per design.

    Parameters
    ----------
    code : ndarray of int32, shape (d,)
        Each design's text, by its index in ``texts``.
    texts : sequence of str

    Returns
    -------
    ndarray or pandas extension array, shape (d,)
        A column for ``pandas.DataFrame``, equal to ``numpy.array(texts)[code]`` as pandas
        takes it.
    """
    import pandas as pd

    kind = _text_dtype()
    if not (isinstance(kind, pd.StringDtype) and kind.storage == "pyarrow"):
        return np.asarray(texts)[code]
    import pyarrow as pa

    array = pa.DictionaryArray.from_arrays(pa.array(code), pa.array(list(texts), pa.string()))
    return pd.array(array.cast(pa.large_string()), dtype=kind)


@functools.cache
def _text_dtype() -> Any:
    """The dtype pandas gives a column made of an array of text."""
    import pandas as pd

    return pd.Series(np.array(["ok"])).dtype


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
