"""A study's metrics at engine speed: each design's constants made once, and the metrics'
series taken block by block while the block's state is in cache, never the whole state.

[`evaluate`][excavkin.studies.metrics.evaluate] asks the mechanism for every sample's full
state (designs × poses) and then reduces a few columns of it. Here, for a study's kinematic
metrics on a closed-form plan:

- the plan's constants (lengths, sketch angles, a dyad's side) are computed once per design,
  from the design parameters (`excavkin.structure.design.vary`), and each pose of a design
  takes its design's column (a copy, not a computation);
- the designs × poses samples are solved in blocks of `excavkin.kinematics.solve.BLOCK`
  samples — the blocks a solve of the chunk would check its precision over, so that each
  sample's values are the full solve's to the bit — on a thread per core, each block into a
  reused workspace (`excavkin.kinematics.solve.Workspace`: no fresh pages, no page faults);
- of each block only the metrics' series (and whether each pose solved) are kept, and the
  change points, meaningless between one design's last pose and the next design's first, are
  not searched.

So memory is bounded by a workspace per thread plus the metrics' series of the chunk, and the
table is the one `evaluate` gives, to the bit (tested for every kind of metric a study file
can name).
"""

from __future__ import annotations

import dataclasses
import os
import threading
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.execution import current
from excavkin.kinematics.solve import BLOCK, Workspace, solve_part
from excavkin.kinematics.threads import over_chunks
from excavkin.structure.design import take, vary
from excavkin.studies.metrics import (
    Constraint,
    Metric,
    Poses,
    check_pose_sets,
    evaluate,
    pose_sets_of,
    tabulate_sets,
)

if TYPE_CHECKING:
    import pandas as pd

    from excavkin.mechanism import Mechanism
    from excavkin.structure.plan import SolvePlan

__all__ = ["evaluate_designs", "evaluate_fused", "fusable"]


def fusable(mech: Mechanism, loads: Any = None) -> bool:
    """Whether a study's metrics of ``mech`` can be evaluated here (`evaluate_fused`): a
    closed-form plan (no Newton group, whose continuation runs along the samples) and no
    loads (force metrics take the full solve).

    Parameters
    ----------
    mech : Mechanism
    loads : optional
        The study's loads (None: kinematics alone).

    Returns
    -------
    bool
    """
    return loads is None and not mech.plan.has_newton


def evaluate_designs(
    mech: Mechanism,
    designs: Mapping[str, F],
    poses: Poses,
    metrics: Sequence[Metric],
    constraints: Sequence[Constraint] = (),
    loads: Any = None,
    pose_sets: Mapping[str, Poses] | None = None,
) -> pd.DataFrame:
    """A study's table of ``designs``: by `evaluate_fused` where it can (`fusable`), else by
    [`evaluate`][excavkin.studies.metrics.evaluate]'s full solve; the two give the same
    table, to the bit.

    Parameters
    ----------
    mech : Mechanism
    designs : mapping of str to ndarray, shape (d,)
        Parameter values (SI) per design.
    poses : Poses
    metrics : sequence of Metric
    constraints : sequence of Constraint
    loads : optional
        As for `evaluate` (``"model"``: force metrics, the full solve).
    pose_sets : mapping of str to Poses, optional

    Returns
    -------
    pandas.DataFrame
        As `evaluate`.
    """
    if fusable(mech, loads):
        return evaluate_fused(mech, designs, poses, metrics, constraints, pose_sets)
    return evaluate(mech, designs, poses, metrics, constraints, loads, pose_sets)


def evaluate_fused(
    mech: Mechanism,
    designs: Mapping[str, F],
    poses: Poses,
    metrics: Sequence[Metric],
    constraints: Sequence[Constraint] = (),
    pose_sets: Mapping[str, Poses] | None = None,
) -> pd.DataFrame:
    """Every design at every pose of every pose set, the metrics reduced per design: the
    table [`evaluate`][excavkin.studies.metrics.evaluate] gives without loads, to the bit,
    each design's constants made once and no full state kept (see the module's text).

    Parameters
    ----------
    mech : Mechanism
        With a closed-form plan (`fusable`).
    designs : mapping of str to ndarray, shape (d,)
        Parameter values (SI) per design.
    poses : Poses
        The default pose set.
    metrics : sequence of Metric
        Kinematic metrics (a column of the kinematics, or a clearance).
    constraints : sequence of Constraint
    pose_sets : mapping of str to Poses, optional
        Named pose sets.

    Returns
    -------
    pandas.DataFrame
        As `evaluate`.
    """
    if not fusable(mech):
        raise ValueError("evaluate_fused: a plan with a Newton group takes evaluate()")
    sets = pose_sets_of(poses, pose_sets)
    check_pose_sets(sets, metrics)
    for pose_set in sets.values():
        _check_poses(mech, pose_set)
    arrays = _check_designs(mech, designs)
    d = len(next(iter(arrays.values())))
    varied, sketch, bad = vary(mech.plan, arrays)  # once per design
    unbuildable = np.broadcast_to(np.asarray(bad, dtype=bool), (d,))
    series: dict[str, F] = {}
    oks: dict[str | None, NDArray[np.bool_]] = {}
    angles: set[str] = set()
    for name, pose_set in sets.items():
        wanted = [m for m in metrics if m.poses == name]
        p = pose_set.count
        got, oks[name], kinds = _solve_set(mech, varied, sketch, unbuildable, pose_set, d, wanted)
        angles |= kinds
        for m in wanted:
            series[m.key] = got[m.key].reshape(d, p)
    return tabulate_sets(arrays, series, oks, metrics, constraints, angles)


def _check_designs(mech: Mechanism, designs: Mapping[str, Any]) -> dict[str, F]:
    """The designs' parameters as arrays of one length, SI; an unknown name, or arrays of
    other shapes, refused as a solve refuses them."""
    from excavkin.errors import unknown_name
    from excavkin.structure.design import joint_offsets, parameters

    known = {**parameters(mech.model), **joint_offsets(mech.model)}
    out: dict[str, F] = {}
    for name, value in designs.items():
        if name not in known:
            raise unknown_name("parameter", name, list(known))
        arr = np.asarray(value)
        if arr.dtype.kind not in "fiu" or arr.ndim != 1:
            raise InputError(f"parameter {name!r}: one number (SI) per design, got {arr.shape}")
        out[name] = arr.astype(np.float64)
    sizes = {len(v) for v in out.values()}
    if len(sizes) != 1:
        listing = ", ".join(f"{k}: {len(v)}" for k, v in out.items())
        raise InputError(f"the designs' parameters have different lengths ({listing or 'none'})")
    return out


def _check_poses(mech: Mechanism, poses: Poses) -> None:
    """Refuse, as a solve does, a driver the mechanism does not have and an array that is not
    one value per pose (or one value)."""
    p = poses.count
    for part in (poses.values, poses.rates, poses.accels):
        for name, value in part.items():
            mech.input_kind(name)  # an unknown driver: its error, with the nearest names
            if np.asarray(value).dtype.kind not in "fiu":
                raise InputError(f"driver {name!r}: a pose set's values are numbers (SI)")
            shape = np.shape(value)
            if len(shape) > 1 or (len(shape) == 1 and shape[0] != p):
                raise InputError(
                    f"driver {name!r}: a pose set's values, rates and accelerations are one "
                    f"value or one per pose ({p}), got shape {shape}"
                )


def _solve_set(
    mech: Mechanism,
    varied: SolvePlan,
    sketch: list[Any],
    unbuildable: NDArray[np.bool_],
    poses: Poses,
    d: int,
    metrics: Sequence[Metric],
) -> tuple[dict[str, F], NDArray[np.bool_], set[str]]:
    """One pose set's designs × poses samples (design-major), block by block on threads:
    each metric's series, whether each pose solved (shape (d, p)) and the angle columns."""
    plan = mech.plan
    p = poses.count
    n = d * p
    values = {k: np.asarray(v, dtype=np.float64) for k, v in poses.values.items()}
    rates = {k: np.asarray(v, dtype=np.float64) for k, v in poses.rates.items()}
    accels = {k: np.asarray(v, dtype=np.float64) for k, v in poses.accels.items()}
    held = [np.asarray(v, dtype=np.float64) for v in sketch]
    any_bad = bool(unbuildable.any())
    out = {m.key: np.empty(n) for m in metrics}
    ok = np.empty(n, dtype=bool)
    angles: list[set[str]] = []
    run = dataclasses.replace(current(), workers=1, progress=None)  # a block per thread
    names = {
        f"{pt}.{axis}" for m in metrics if m.clearance for pt in m.clearance for axis in "xy"
    } | {m.column for m in metrics if m.clearance is None}

    def at(v: F, index: NDArray[np.intp]) -> Any:
        return v[index] if v.ndim else float(v)

    def one(s: int) -> None:
        e = min(s + BLOCK, n)
        design, pose = np.divmod(np.arange(s, e), p)
        q = np.empty((len(plan.inputs), e - s))
        qd: list[Any] = []
        qdd: list[Any] = []
        for i, name in enumerate(plan.inputs):
            val = values.get(name)
            q[i] = at(held[i], design) if val is None else at(val, pose)
            rate = rates.get(name)
            swept = val is not None and val.ndim == 1
            qd.append((1.0 if swept else 0.0) if rate is None else at(rate, pose))
            accel = accels.get(name)
            qdd.append(0.0 if accel is None else at(accel, pose))
        workspace = _borrow(plan, e - s)
        try:
            res, _ = solve_part(
                take(varied, design), mech.assembly, q, _rows(qd, e - s), _rows(qdd, e - s),
                execution=run, unbuildable=unbuildable[design] if any_bad else None,
                workspace=workspace, change_points=False,
            )  # fmt: skip
            cols = res.columns_named(names)  # (the result's columns listed once)
            for m in metrics:
                out[m.key][s:e] = _series(cols, m)
            ok[s:e] = res.status.solved
            if not angles:
                angles.append({c.name for c in res.columns if c.kind == "angle"})
        finally:
            _give_back(plan, workspace)

    over_chunks(n, BLOCK, current().workers, one)
    return out, ok.reshape(d, p), angles[0] if angles else set()


def _series(cols: Mapping[str, F], m: Metric) -> F:
    """A metric's per-sample series from the block's columns, as
    [`metric_series`][excavkin.studies.metrics.metric_series] takes it from a result."""
    if m.clearance is None:
        return cols[m.column]
    from excavkin.studies.clearance import segment_clearance

    ends = [np.stack([cols[f"{pt}.x"], cols[f"{pt}.y"]], axis=-1) for pt in m.clearance]
    return np.asarray(segment_clearance(*ends))


def _rows(values: list[Any], k: int) -> F:
    """Rates or accelerations as (n_inputs, k), as a solve makes them: one value per input
    broadcast when none varies, else an array."""
    if all(np.ndim(v) == 0 for v in values):
        return np.broadcast_to(np.array(values, dtype=np.float64).reshape(-1, 1), (len(values), k))
    out = np.empty((len(values), k))
    for i, v in enumerate(values):
        out[i] = v
    return out


#: free workspaces, by the plan they were made for: a study's blocks take them in turn
_free: list[tuple[SolvePlan, Workspace]] = []
_lock = threading.Lock()


def _borrow(plan: SolvePlan, n: int) -> Workspace:
    """A free workspace for ``n`` samples of ``plan`` (its fixed rows zero), or a new one."""
    with _lock:
        for i, (owner, ws) in enumerate(_free):
            if owner is plan and ws.fits(plan, n):
                return _free.pop(i)[1]
    return Workspace.of(plan, n)


def _give_back(plan: SolvePlan, workspace: Workspace) -> None:
    """Keep a workspace for the next block: two per core at most, the newest (a chunk's
    blocks are of two sizes, whole blocks and its last)."""
    with _lock:
        _free.append((plan, workspace))
        del _free[: max(0, len(_free) - 2 * (os.cpu_count() or 1))]
