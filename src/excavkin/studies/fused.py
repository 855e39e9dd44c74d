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

So memory is bounded by a workspace per thread plus the metrics' series of the chunk (kept,
with its statuses and inputs, for the next chunk: at most `SPARE_BYTES` a core, `_Spares`),
and the table is the one `evaluate` gives, to the bit (tested for every kind of metric a
study file can name).

Where numba solves (`excavkin.backends.choose`: ``"auto"`` with the kernel cached or the
batch large, or ``"numba"``), a pose set takes the study's own kernel instead
(`excavkin.kinematics.compiled.run_designs`): the inputs are checked once for the set; each
design's constants are one column of a table made once, read by its poses; the kernel writes
out only the rows the metrics read (`SPAN` samples into one kept workspace, the other rows'
pages never touched) and keeps each block's far samples' largest magnitudes, the block's
share of its precision scales; a block is one kernel call, without the GIL. The samples near
a dead position are solved again, whole, by the same kernel and checked together
(`excavkin.kinematics.precision.check_picked`), each against its own block's scales, and
the metrics are reduced per design in one compiled pass (`excavkin.studies.reductions`).
The same numbers, to the bit: the same arithmetic sample by sample, the same maxima, NumPy's
own order of summation. ``backend="numpy"``, or numba that cannot be imported, keep the
blocks above.

With ``backend="cuda"`` a pose set is solved and its metrics reduced on the GPU
(`excavkin.studies.device`), a chunk of whole designs at a time: its inputs made and
checked there from the pose set's and the designs' tables, its state kept there, the
samples near a dead position solved again and checked here by the study's kernel as above
and written back, each design's metrics and count of poses solved the only numbers that
come back (the same table, to the bit, in numba's CUDA simulator). A metric that is not one
row of the state or of the inputs (a clearance) keeps the blocks above, solved on the
device a block at a time.
"""

from __future__ import annotations

import dataclasses
import functools
import os
import threading
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from excavkin import backends
from excavkin.arrays import FloatArray as F
from excavkin.backends import Kernel
from excavkin.errors import InputError
from excavkin.execution import current
from excavkin.kinematics import compiled, precision
from excavkin.kinematics.kernels import Chunk, Code
from excavkin.kinematics.result import KinematicResult, Status
from excavkin.kinematics.selection import kept_rows
from excavkin.kinematics.solve import (
    BLOCK,
    Tolerances,
    Workspace,
    check_inputs,
    check_solved_again,
    solve_part,
)
from excavkin.kinematics.threads import over_chunks
from excavkin.kinematics.vectorise import written_rows
from excavkin.structure.design import take, vary
from excavkin.structure.plan_memo import PlanMemo
from excavkin.studies import device, reductions
from excavkin.studies.metrics import (
    Constraint,
    Metric,
    Poses,
    SolvedPoses,
    check_pose_sets,
    evaluate,
    pose_sets_of,
    tabulate_columns,
)

if TYPE_CHECKING:
    import pandas as pd

    from excavkin.mechanism import Mechanism
    from excavkin.structure.plan import SolvePlan

__all__ = ["evaluate_designs", "evaluate_fused", "evaluate_fused_columns", "fusable"]


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
    import pandas as pd

    return pd.DataFrame(
        evaluate_fused_columns(mech, designs, poses, metrics, constraints, pose_sets)
    )


def evaluate_fused_columns(
    mech: Mechanism,
    designs: Mapping[str, F],
    poses: Poses,
    metrics: Sequence[Metric],
    constraints: Sequence[Constraint] = (),
    pose_sets: Mapping[str, Poses] | None = None,
) -> dict[str, Any]:
    """`evaluate_fused`'s columns by name, in the table's order, without making the table
    ([`tabulate_columns`][excavkin.studies.metrics.tabulate_columns]).

    Parameters
    ----------
    mech, designs, poses, metrics, constraints, pose_sets
        As `evaluate_fused` takes them.

    Returns
    -------
    dict of str to array
        One value per design each.
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
    oks: dict[str | None, NDArray[np.bool_] | SolvedPoses] = {}
    angles: set[str] = set()
    reduced: dict[str, F] = {}
    kernel = _study_kernel(mech, d * max(s.count for s in sets.values()))
    on_device = _device_solver(mech, metrics) if kernel is None else None
    spares = _Spares()  # (the compiled path's chunk-sized arrays, kept for the next chunk)
    got: dict[str, F] = {}
    for name, pose_set in sets.items():
        wanted = [m for m in metrics if m.poses == name]
        p = pose_set.count
        if on_device is not None:
            lay = on_device.layout
            metric_of, oks[name] = _solve_set_device(
                mech, on_device, varied, sketch, unbuildable, pose_set, d, wanted
            )
            reduced |= metric_of
            angles |= lay.angles
            continue
        if kernel is None:
            got, ok, kinds = _solve_set(mech, varied, sketch, unbuildable, pose_set, d, wanted)
        else:
            got, ok, kinds = _solve_set_compiled(
                mech, kernel, varied, sketch, unbuildable, pose_set, d, wanted, spares
            )
        oks[name] = ok
        angles |= kinds
        for m in wanted:
            series[m.key] = got[m.key].reshape(d, p)
            if kernel is not None and reductions.compiled(m, kinds):
                reduced[m.name] = reductions.reduce_designs(series[m.key], ok, m)
    table = tabulate_columns(arrays, series, oks, metrics, constraints, angles, reduced)
    del series, oks, got  # (no view of the spares left: the table's columns are its own)
    spares.give_back()
    return table


@dataclasses.dataclass(frozen=True, slots=True)
class _StudyKernel:
    """A plan's study kernel, its written rows (by array and indices) and its scratch rows
    (`excavkin.kinematics.vectorise.written_rows`)."""

    kernel: Kernel
    rows: dict[tuple[str, tuple[int, ...]], int]
    n_rows: int


def _device_solver(mech: Mechanism, metrics: Sequence[Metric]) -> device.Solver | None:
    """The study's solver on the device (`excavkin.studies.device`), where ``backend="cuda"``
    is asked for, the plan compiles and every metric's series is one row of the state or of
    the inputs (a clearance, or a column computed from several, is not: such a study's
    blocks solve as a solve does, on the device, their state copied back); None: not so."""
    if current().backend != "cuda" or compiled.unsupported(mech.plan) is not None:
        return None
    backends.require("cuda")
    lay = device.layout(mech.plan)
    if any(lay.row_of(m) is None for m in metrics):
        return None
    return device.Solver(mech.plan, lay)


def _cpu_kernel(plan: SolvePlan) -> _StudyKernel:
    """The plan's study kernel on the CPU (numba), whatever the backend: the one that solves
    the samples near a dead position again."""
    text = compiled.kernel_source(plan, by_design=True)
    return _StudyKernel(backends.kernel_of(text, "kinematics"), *written_rows(text))


def _solve_set_device(
    mech: Mechanism,
    solver: device.Solver,
    varied: SolvePlan,
    sketch: list[Any],
    unbuildable: NDArray[np.bool_],
    poses: Poses,
    d: int,
    metrics: Sequence[Metric],
) -> tuple[dict[str, F], SolvedPoses]:
    """`_solve_set_compiled` on the device, a chunk of whole designs at a time: the pose
    set's inputs go there as tables (a row a pose's or a design's), each sample's made and
    checked there as `check_inputs` checks them and solved; the samples near a dead
    position (and their blocks' scales) come back, are solved again and checked on the host
    as there and written back; the metrics are reduced on the device. Only each design's
    metrics and count of poses solved come back: the metrics by name, and the counts."""
    plan = mech.plan
    p = poses.count
    if p == 0:  # no poses: no value (an angle's change, a sum of none: 0), none solved
        angles = solver.layout.angles
        return {
            m.name: np.full(d, 0.0 if m.reduce == "change" and m.column in angles else np.nan)
            for m in metrics
        }, SolvedPoses(np.zeros(d, dtype=np.int64), 0)
    tol = Tolerances()
    consts, stride = compiled.table(compiled.constants(varied), d)
    if not stride:  # (no constant varies: every design reads the one column)
        consts = np.broadcast_to(consts, (consts.shape[0], max(d, 1)))
    out = {m.name: np.empty(d) for m in metrics}
    solved = np.empty(d, dtype=np.int64)
    per = device.designs_per_chunk(d, p, solver.bytes_per_sample)
    tables = _input_tables(plan, poses, sketch, d)
    for d0 in range(0, d, per):
        with device.LOCK:  # (a study's chunks on threads: one at a time on the device)
            _device_chunk(
                plan, solver, varied, consts, tables, unbuildable, p, d0, min(d, d0 + per),
                metrics, tol, out, solved,
            )  # fmt: skip
    return out, SolvedPoses(solved, p)


def _device_chunk(
    plan: SolvePlan,
    solver: device.Solver,
    varied: SolvePlan,
    consts: F,
    tables: device.Inputs,
    unbuildable: NDArray[np.bool_],
    p: int,
    d0: int,
    d1: int,
    metrics: Sequence[Metric],
    tol: Tolerances,
    out: dict[str, F],
    solved: NDArray[np.int64],
) -> None:
    """`_solve_set_device`'s designs ``d0`` to ``d1``: their metrics into ``out`` and their
    counts of poses solved into ``solved``."""
    lay = solver.layout
    names = {m.column for m in metrics}
    state = solver.solve(
        consts[:, d0:d1], p, tables.part(d0, d1), unbuildable[d0:d1],
        (tol.close, tol.singular),
    )  # fmt: skip
    pick, tops = state.scan(precision.NEAR)
    if pick.size:  # (the chunk starts on a block's boundary: its blocks are the set's)
        blocks = []
        block = device.BLOCK  # (the scan's blocks: the solve's)
        for b, at in zip(*np.unique(pick // block, return_index=True), strict=True):
            upto = int(np.searchsorted(pick, (b + 1) * block))
            far = dict(zip(precision.KINDS, tops[b].tolist(), strict=True))
            blocks.append((upto - int(at), far))
        inputs = tables.at(pick + d0 * p, p)  # (solved: their inputs passed the checks)
        part = _check_near(
            plan, _cpu_kernel(plan), varied, consts, d0 + pick // p,
            np.zeros(pick.size, dtype=np.int8), inputs, inputs[0], blocks, tol,
        )  # fmt: skip
        cols = part.columns_named(names)
        rows = {lay.columns[m.column]: _series(cols, m) for m in metrics}
        state.patch(pick, part.status.code, rows)
    for m in metrics:
        where = lay.columns[m.column]
        out[m.name][d0:d1] = state.reduce(where, m, p, m.column in lay.angles)
    solved[d0:d1] = state.solved(p)


def _study_kernel(mech: Mechanism, n: int) -> _StudyKernel | None:
    """The plan's kernel for a study's samples (constants a column per design,
    `excavkin.kinematics.compiled.run_designs`), where the backend in use compiles the
    solve (`excavkin.backends.choose`, as a solve of ``n`` samples chooses); None: the
    blocks solve as a solve does (NumPy, or a device)."""
    backend = current().backend
    plan = mech.plan
    if backend not in ("auto", "numba") or compiled.unsupported(plan) is not None:
        return None
    job = backends.Job(
        "kinematics",
        lambda: compiled.kernel_source(plan, by_design=True),
        lambda: None,
        lambda kernel: None,
        unasked=compiled.size(plan) <= compiled.AUTO_POINTS,
        slower=lambda: compiled.split(compiled.kernel_source(plan, by_design=True)),
    )
    if backends.choose(backend, job, n).name != "numba":
        return None
    return _cpu_kernel(plan)


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


def _solve_set_compiled(
    mech: Mechanism,
    kernel: _StudyKernel,
    varied: SolvePlan,
    sketch: list[Any],
    unbuildable: NDArray[np.bool_],
    poses: Poses,
    d: int,
    metrics: Sequence[Metric],
    spares: _Spares,
) -> tuple[dict[str, F], NDArray[np.bool_], set[str]]:
    """`_solve_set` by the study's kernel: the inputs checked once for the set, each
    design's constants a column of one table read by its poses, a block one kernel call
    (only the metrics' rows written out, its far samples' precision scales kept), the
    metrics' series taken once a `SPAN`, and the samples near a dead position of every
    block solved again and checked together; the same numbers, to the bit, as the blocks
    solved by `solve_part`. Its chunk-sized arrays are ``spares``' (`_Spares`)."""
    plan = mech.plan
    p = poses.count
    n = d * p
    tol = Tolerances()
    consts, stride = compiled.table(compiled.constants(varied), d)
    if not stride:  # (no constant varies: every design reads the one column)
        consts = np.broadcast_to(consts, (consts.shape[0], max(d, 1)))
    q, qd, qdd = _inputs(plan, poses, sketch, d, spares)
    status = spares.empty(n, np.int8)
    status.fill(0)
    bad = np.repeat(unbuildable, p) if unbuildable.any() else None
    solving = check_inputs(plan, q, qd, qdd, status, bad)
    out = {m.key: spares.empty(n, np.float64) for m in metrics}
    ok = spares.empty(n, np.bool_)
    angles: list[set[str]] = []
    names = {
        f"{pt}.{axis}" for m in metrics if m.clearance for pt in m.clearance for axis in "xy"
    } | {m.column for m in metrics if m.clearance is None}

    keep = _kept(plan, kernel, names)
    picked: dict[int, tuple[NDArray[np.intp], dict[str, float]]] = {}
    span = max(1, min(n, SPAN))

    def one(s: int, s0: int, e0: int, here: Workspace, tops: Any) -> None:
        e = min(s + BLOCK, e0 - s0)
        first, last = (s0 + s) // p, (s0 + e - 1) // p
        c = Chunk(
            here.x, here.v, here.a, solving[:, s0 + s : s0 + e], qd[:, s0 + s : s0 + e],
            qdd[:, s0 + s : s0 + e], here.trans, here.status, here.failed, tol.close,
            tol.singular,
        )  # fmt: skip
        compiled.run_designs(
            kernel.kernel, consts[:, first : last + 1], p, s0 + s - first * p, c,
            here.derived.body, here.derived.element, here.near, here.near_step, keep,
            tops[s // BLOCK], precision.NEAR, s,
        )  # fmt: skip

    for s0 in range(0, n, span):
        e0 = min(s0 + span, n)
        # only the rows kept, and the statuses, are written: the others' pages are never
        # touched (a workspace kept from a set before has its pages already)
        here = _borrow(plan, e0 - s0)
        try:
            here.status[:] = status[s0:e0]
            here.failed.fill(-1)
            tops = np.zeros((-(-(e0 - s0) // BLOCK), len(precision.KINDS)), dtype=np.int64)
            over_chunks(
                e0 - s0, BLOCK, current().workers,
                functools.partial(one, s0=s0, e0=e0, here=here, tops=tops),
            )  # fmt: skip
            pick = np.flatnonzero((here.status == Code.OK) & (here.near < precision.NEAR))
            for b, at in zip(*np.unique(pick // BLOCK, return_index=True), strict=True):
                # solved again and checked with every block's, below
                upto = np.searchsorted(pick, (b + 1) * BLOCK)
                far = tops[b].view(np.float64).tolist()
                picked[s0 + b * BLOCK] = (
                    pick[at:upto] + s0,
                    dict(zip(precision.KINDS, far, strict=True)),
                )
            res = KinematicResult.build(
                plan, here.x, here.v, here.a, q[:, s0:e0], qd[:, s0:e0], qdd[:, s0:e0],
                here.trans, here.derived, Status(here.status, here.failed, plan),
            )  # fmt: skip
            cols = res.columns_named(names)
            for m in metrics:
                out[m.key][s0:e0] = _series(cols, m)
            ok[s0:e0] = res.status.solved
            if not angles:
                angles.append({c.name for c in res.columns if c.kind == "angle"})
        finally:
            _give_back(plan, here)
    if picked:  # the samples near a dead position, every block's at once
        blocks = [picked[s] for s in sorted(picked)]
        index = np.concatenate([b[0] for b in blocks])
        part = _check_near(
            plan, kernel, varied, consts, index // p, status[index],
            (q[:, index], qd[:, index], qdd[:, index]), solving[:, index],
            [(len(b[0]), b[1]) for b in blocks], tol,
        )  # fmt: skip
        cols = part.columns_named(names)
        for m in metrics:
            out[m.key][index] = _series(cols, m)
        ok[index] = part.status.solved
    return out, ok.reshape(d, p), angles[0] if angles else set()


def _check_near(
    plan: SolvePlan,
    kernel: _StudyKernel,
    varied: SolvePlan,
    consts: F,
    designs: NDArray[np.intp],
    status: NDArray[np.int8],
    inputs: tuple[F, F, F],
    solving: F,
    blocks: list[tuple[int, dict[str, float]]],
    tol: Tolerances,
) -> KinematicResult:
    """The samples picked near a dead position (their designs ``designs``, columns of
    ``consts`` and of ``varied``'s constants), solved again whole by the study's kernel and
    checked together, each against its own block's scales (``blocks``: per block, in the
    picks' order, how many are its and its far samples' tops): their result."""
    k = designs.size
    solved = Workspace.of(plan, k)  # their whole state, as their blocks' solve made it
    solved.status[:] = status
    solved.failed.fill(-1)
    c = Chunk(
        solved.x, solved.v, solved.a, solving, inputs[1], inputs[2],
        solved.trans, solved.status, solved.failed, tol.close, tol.singular,
    )  # fmt: skip
    compiled.run_designs(
        kernel.kernel, np.ascontiguousarray(consts[:, designs]), 1, 0, c,
        solved.derived.body, solved.derived.element, solved.near, solved.near_step,
        np.ones(kernel.n_rows, dtype=np.int8),
        np.zeros(len(precision.KINDS), dtype=np.int64), precision.NEAR,
    )  # fmt: skip
    arrays, _, code, step = check_solved_again(take(varied, designs), inputs, solved, tol, blocks)
    return KinematicResult.build(
        plan, arrays.x, arrays.v, arrays.a, *inputs, arrays.trans, arrays.derived,
        Status(code, step, plan),
    )  # fmt: skip


def _kept(plan: SolvePlan, kernel: _StudyKernel, names: set[str]) -> NDArray[np.int8]:
    """The kernel's rows that hold the columns ``names`` (1; the statuses are always
    written): `excavkin.kinematics.selection.kept_rows`, no change points searched. Found
    once for a plan and columns (each chunk of a study asks again)."""
    key = frozenset(names)  # (a plan has one study kernel, its rows)
    found = _kept_rows.get(plan, key)
    if found is not None:
        return found
    keep = kept_rows(plan, kernel.rows, kernel.n_rows, names, change_points=False)
    return _kept_rows.put(plan, keep, key)


#: `_kept`'s rows found, by plan and columns
_kept_rows: PlanMemo[NDArray[np.int8]] = PlanMemo()


def _inputs(
    plan: SolvePlan, poses: Poses, sketch: list[Any], d: int, spares: _Spares
) -> tuple[F, F, F]:
    """A pose set's inputs, rates and accelerations at every design's every pose
    (design-major, shape (n_inputs, d·p) each, a broadcast where one value serves all, else
    an array of ``spares``), as `_solve_set`'s blocks take them: a driver the set does not
    give held at each design's sketch value, its rate 0 (1 where swept without a rate
    given)."""
    p = poses.count
    rows: list[list[Any]] = [[], [], []]
    for i, name in enumerate(plan.inputs):
        val, given = _given(poses, name, sketch[i])
        for k, v in enumerate(given):
            a = np.asarray(v, dtype=np.float64)
            if a.ndim and (val is None and k == 0):
                rows[k].append(a[:, None])  # a design's own value at each of its poses
            elif a.ndim:
                rows[k].append(a[None, :])  # a pose's value for every design
            else:
                rows[k].append(float(a))
    q, qd, qdd = (_full(r, d, p, spares) for r in rows)
    return q, qd, qdd


def _given(poses: Poses, name: str, held: Any) -> tuple[Any, tuple[Any, Any, Any]]:
    """A driver's value as the pose set gives it (None: not given), and its value, rate and
    acceleration at the set's poses: one not given held at ``held`` (each design's sketch
    value), its rate 0 (1 where swept without a rate given)."""
    val = poses.values.get(name)
    rate = poses.rates.get(name)
    accel = poses.accels.get(name)
    swept = val is not None and np.ndim(val) == 1
    return val, (
        held if val is None else val,
        (1.0 if swept else 0.0) if rate is None else rate,
        0.0 if accel is None else accel,
    )


def _input_tables(plan: SolvePlan, poses: Poses, sketch: list[Any], d: int) -> device.Inputs:
    """`_inputs` as tables (`excavkin.studies.device.Inputs`): a row a pose's or a
    design's, not a sample's."""
    p = poses.count
    n_in = len(plan.inputs)
    by_pose = np.zeros((3, n_in, max(p, 1)))
    by_design = np.zeros((3, n_in, max(d, 1)))
    design = np.zeros((3, n_in), dtype=np.int8)
    for i, name in enumerate(plan.inputs):
        val, given = _given(poses, name, sketch[i])
        for k, v in enumerate(given):
            a = np.asarray(v, dtype=np.float64)
            if a.ndim and (val is None and k == 0):
                by_design[k, i] = a  # a design's own value at each of its poses
                design[k, i] = 1
            else:
                by_pose[k, i] = a  # a pose's value, or one for all
    return device.Inputs(by_pose, by_design, design)


def _full(values: list[Any], d: int, p: int, spares: _Spares) -> F:
    """Rows of ``d·p`` samples (`_rows` for the whole set), each value broadcast over the
    designs × poses (an array of ``spares`` where one varies)."""
    if all(np.ndim(v) == 0 for v in values):
        shape = (len(values), d * p)
        return np.broadcast_to(np.array(values, dtype=np.float64).reshape(-1, 1), shape)
    out = spares.empty(len(values) * d * p, np.float64).reshape(len(values), d, p)
    for i, v in enumerate(values):
        out[i] = v
    return out.reshape(len(values), d * p)


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


#: samples of a pose set that a study's kernel solves into one workspace (16 blocks), of
#: which it writes only the rows its metrics read: the pages of the others are never touched
SPAN = 16 * BLOCK

#: bytes of a study's chunk-sized arrays kept for the next chunks, per core (`_Spares`)
SPARE_BYTES = 128 << 20

#: chunk-sized arrays given back by a study's chunks, newest last, for the next chunks
_spare: list[NDArray[Any]] = []


class _Spares:
    """A chunk's arrays of a study (its metrics' series, its statuses, its inputs), taken
    from those earlier chunks gave back and given back together once its table is made.

    A fresh array's pages are mapped as they are first written and unmapped when it is
    freed, holding the GIL — for the 45 MB of a chunk of 2²⁰ four-bar samples, ≈ 1.5 ms of
    the GIL and several of page faults; an array kept is written again in place. At most
    `SPARE_BYTES` a core are kept (the newest: about two chunks' of 2²¹ four-bar samples,
    68 MB each)."""

    def __init__(self) -> None:
        self.taken: list[NDArray[Any]] = []

    def empty(self, n: int, dtype: Any) -> NDArray[Any]:
        """``n`` values of ``dtype``, not set: a kept array's, of ``n`` to ``2n`` values, or
        a new one.

        Parameters
        ----------
        n : int
        dtype : numpy dtype

        Returns
        -------
        ndarray, shape (n,)
        """
        kind = np.dtype(dtype)
        with _lock:
            for i, arr in enumerate(_spare):
                if arr.dtype == kind and n <= arr.size <= 2 * n:
                    whole = _spare.pop(i)
                    break
            else:
                whole = np.empty(n, dtype=kind)
        self.taken.append(whole)
        return whole[:n]

    def give_back(self) -> None:
        """Keep the arrays taken for the next chunks (no view of them may be in use)."""
        cap = SPARE_BYTES * (os.cpu_count() or 1)
        with _lock:
            _spare.extend(self.taken)
            while sum(a.nbytes for a in _spare) > cap:
                del _spare[0]
        self.taken = []


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
