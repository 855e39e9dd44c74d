"""Run a :class:`~excavkin.structure.plan.SolvePlan` over a batch of driver inputs.

Inputs are arrays of shape (n,) per driver: values, rates and accelerations. The plan's steps
run in order over cache-sized chunks of samples; there is no Python loop over samples. When the
plan has a Newton group, positions are found by continuation from the assembled sketch: the
inputs move from their sketch values to the requested ones in a few stages, each corrected by
Newton, so that every sample stays on the sketch's assembly branch.
"""

from __future__ import annotations

import dataclasses
import importlib
import os
import threading
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from excavkin.errors import AssemblyError
from excavkin.kinematics import kernels, precision
from excavkin.kinematics.change_points import ChangePoint, Tail, find_change_points
from excavkin.kinematics.kernels import Chunk, Code, F
from excavkin.kinematics.newton import rotary_branch_ok
from excavkin.kinematics.result import Derived, KinematicResult, Status
from excavkin.kinematics.steps import run_steps
from excavkin.structure.design import DesignBatch, take
from excavkin.structure.plan import (
    Dyad,
    NewtonGroup,
    SolvePlan,
)


@dataclass(frozen=True, slots=True)
class Tolerances:
    """Thresholds for declaring a sample failed.

    Attributes
    ----------
    close : float
        A dyad whose squared half-chord (relative to the base) is below ``-close`` cannot close;
        between ``-close`` and ``close`` it is taken as just closing (a dead position).
    singular : float
        A dyad is at a dead position where sin(transmission angle) ≤ ``singular``.
    """

    close: float = 1e-10
    singular: float = 1e-7


@dataclass(frozen=True, slots=True)
class Assembly:
    """The sketch re-assembled to the model's exact lengths.

    Attributes
    ----------
    positions : ndarray, shape (n_points, 2)
    newton_signs : tuple of float
        Sign of each Newton group's Jacobian determinant at the sketch (its assembly branch).
    """

    positions: F
    newton_signs: tuple[float, ...]


#: A block: 65 536 consecutive samples, aligned at sample 0 (block k holds samples k·BLOCK to
#: (k + 1)·BLOCK − 1). What a sample's result depends on beyond its own inputs is defined over
#: its block — the precision check's scales, which dyads are searched for change points, where a
#: Newton group's continuation starts (the block before's last reached sample) — so that a sweep
#: solved whole and one solved part by part give the same numbers to the bit.
BLOCK = 65536


@dataclass(frozen=True, slots=True)
class Carry:
    """What one part of a sweep hands the next, so that the parts solve as the whole would.

    Attributes
    ----------
    start : int
        The next part's first sample (a multiple of :data:`BLOCK`).
    tail : Tail, optional
        The last samples before it, for the change points between the two.
    reached : (ndarray, ndarray), optional
        The positions (n_points, 2) and inputs (n_inputs,) of the last sample a Newton group
        reached: the next block's continuation starts there.
    """

    start: int = 0
    tail: Tail | None = None
    reached: tuple[F, F] | None = None


def solve_part(
    plan: SolvePlan,
    assembly: Assembly,
    q: F,
    qd: F,
    qdd: F,
    *,
    tol: Tolerances = Tolerances(),
    chunk: int = 32768,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    unbuildable: np.ndarray | None = None,
    designs: DesignBatch | None = None,
    carry: Carry | None = None,
) -> tuple[KinematicResult, Carry]:
    """Positions, velocities and accelerations of every point for consecutive samples of a
    sweep, each dyad on its sketch side.

    Parameters
    ----------
    plan : SolvePlan
        The plan (with a family of designs' constants taken at these samples, if any).
    assembly : Assembly
        From :func:`assemble`.
    q, qd, qdd : ndarray, shape (n_inputs, n)
        Driver values, rates and accelerations, SI, in ``plan.inputs`` order.
    tol : Tolerances
    chunk : int
        Samples per pass; chosen so a chunk's temporaries stay in cache.
    workers : int, optional
        Threads solving chunks side by side (NumPy releases the GIL in its loops, and chunks
        write disjoint slices). Default: the machine's cores.
    progress : callable, optional
        ``progress(done, n)``, called after each chunk with the samples finished so far;
        calls are serialised (never two at once, ``done`` increasing), though they may come
        from worker threads.
    unbuildable : ndarray of bool, shape (n,), optional
        Samples whose design (a plan with per-sample dimensions) builds no mechanism.
    designs : DesignBatch, optional
        A family of designs of ``plan`` (a closed-form one), one per sample: each chunk's
        constants are made as the chunk is solved.
    carry : Carry, optional
        What the part before handed on (none: these samples start the sweep).

    Returns
    -------
    KinematicResult
        Its change points are numbered in the whole sweep.
    Carry
        For the part after.
    """
    carry = carry or Carry()
    n_in, n = q.shape
    n_pts = len(plan.points)
    per_sample = 8 * (6 * n_pts + len(plan.transmissions) + 3 * len(plan.bodies))
    with _small_pages(n * (per_sample + 48 * len(plan.elements))):
        x = np.empty((n_pts, 2, n))
        v = np.empty((n_pts, 2, n))
        a = np.empty((n_pts, 2, n))
        trans = np.empty((len(plan.transmissions), n))
        derived = Derived.empty(plan, n)
    status = np.zeros(n, dtype=np.int8)
    failed = np.full(n, -1, dtype=np.int16)
    q_given = q
    q = _check_inputs(plan, q, qd, qdd, status)
    if unbuildable is not None and unbuildable.any():
        status[unbuildable & (status == Code.OK)] = Code.BAD_DESIGN
        q = q.copy()
        q[:, unbuildable] = np.nan
    report = _Reporter(progress, n)
    newton_near = np.ones(n) if plan.has_newton else None
    full = Chunk(x, v, a, q, qd, qdd, trans, status, failed, tol.close, tol.singular, newton_near)
    blocks = _blocks(carry.start, n)
    reached = carry.reached
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if plan.has_newton:
            for b in blocks:
                part = _view(full, b)
                reached = _solve_newton(take(plan, b), assembly, part, reached)
                derived.fill(plan, part.x, part.v, part.a, b)
                _flag_not_finite(part.x, part.v, part.a, part.trans, derived, b, part.status)
                report(b.stop - b.start)
        else:
            _solve_chunks(plan, full, derived, chunk, workers, report, designs)
    error, found, tail = _check_blocks(
        plan, (q_given, q, qd, qdd), precision.Arrays(x, v, a, trans, derived), status, failed,
        newton_near, tol, designs, carry, blocks,
    )  # fmt: skip
    result = KinematicResult.build(
        plan, x, v, a, q_given, qd, qdd, trans, derived, Status(status, failed, plan)
    )
    result = dataclasses.replace(result, change_points=tuple(found), error_estimate=error)
    return result, Carry(carry.start + n, tail, reached)


def _check_blocks(
    plan: SolvePlan,
    inputs: tuple[F, F, F, F],
    out: precision.Arrays,
    status: np.ndarray,
    failed: np.ndarray,
    newton_near: F | None,
    tol: Tolerances,
    designs: DesignBatch | None,
    carry: Carry,
    blocks: list[slice],
) -> tuple[F, list[ChangePoint], Tail | None]:
    """Block by block, the precision check (its scales are the block's) and the change
    points (searched in the dyads that come near flat in the block, and between it and the
    block before): the error estimates, the change points in plan order and the last tail.
    ``inputs``: the inputs as given, and as solved (q, qd, qdd)."""
    q_given, q, qd, qdd = inputs
    x, v, a, trans, derived = out.x, out.v, out.a, out.trans, out.derived
    error = np.full(q.shape[1], np.nan)
    found: list[ChangePoint] = []
    tail = carry.tail
    for b in blocks:
        near = None if newton_near is None else newton_near[b]
        arrays = precision.Arrays(
            x[..., b], v[..., b], a[..., b], trans[:, b],
            Derived(derived.body[..., b], derived.element[..., b]),
        )  # fmt: skip
        error[b] = _check_precision(
            take(plan, b), (q[:, b], qd[:, b], qdd[:, b]), arrays, status[b], failed[b], near,
            tol, designs, b.start,
        )  # fmt: skip
        here = (x[..., b], v[..., b], q_given[:, b], qd[:, b], trans[:, b])
        found += find_change_points(
            plan, here[0], v=here[1], q=here[2], qd=here[3], trans=here[4],
            offset=carry.start + b.start, tail=tail,
        )  # fmt: skip
        tail = Tail.of(*here, before=tail)
    order = {plan.points[st.point]: k for k, st in enumerate(plan.steps) if isinstance(st, Dyad)}
    found.sort(key=lambda cp: order[cp.point])  # plan order, each dyad's in sample order
    return error, found, tail


#: a result at least this large (bytes) is made of ordinary pages (:func:`_small_pages`)
LARGE_RESULT = 2**30


@contextmanager
def _small_pages(nbytes: int) -> Iterator[None]:
    """Arrays made here get ordinary pages when they add up to :data:`LARGE_RESULT` or more.
    NumPy advises the kernel to back a large array with huge pages, each found (compacted,
    zeroed) when first touched: fewer faults than ordinary pages (a result of 10⁶ samples is
    made 10–15 % faster), but the threads writing a fresh result of 10⁷ samples (≈ 3 GB) were
    seen to stall on them, 5× slower, where memory had to be compacted. The setting is
    NumPy's, process-wide: it is put back as it was at once."""
    if nbytes < LARGE_RESULT:
        yield
        return
    try:
        advise = importlib.import_module("numpy._core.multiarray")._set_madvise_hugepage
    except (ImportError, AttributeError):  # NumPy 1.x
        advise = importlib.import_module("numpy.core.multiarray")._set_madvise_hugepage
    previous = advise(False)
    try:
        yield
    finally:
        advise(previous)


def _blocks(start: int, n: int) -> list[slice]:
    """The samples 0 … n − 1 of a part starting at sample ``start``, cut where blocks begin."""
    cuts = [0, *range(-start % BLOCK or BLOCK, n, BLOCK), n]
    return [slice(s, e) for s, e in zip(cuts[:-1], cuts[1:], strict=True) if e > s]


def _view(full: Chunk, part: slice) -> Chunk:
    """A chunk of views of ``full``'s samples ``part``."""
    return Chunk(
        full.x[:, :, part],
        full.v[:, :, part],
        full.a[:, :, part],
        full.q[:, part],
        full.qd[:, part],
        full.qdd[:, part],
        full.trans[:, part],
        full.status[part],
        full.failed[part],
        full.close_tol,
        full.singular_tol,
        None if full.near is None else full.near[part],
    )


def _check_precision(
    plan: SolvePlan,
    inputs: tuple[F, F, F],
    arrays: precision.Arrays,
    status: np.ndarray,
    failed: np.ndarray,
    newton_near: F | None,
    tol: Tolerances,
    designs: DesignBatch | None,
    offset: int = 0,
) -> F:
    """The precision check near dead positions (:mod:`excavkin.kinematics.precision`), and
    the finiteness check again on the samples it may have given extended values; ``offset``
    is the first sample's place in ``designs``."""
    q, qd, qdd = inputs
    limits = (tol.close, tol.singular)
    plan_at = None if designs is None else (lambda index: designs.at(index + offset)[0])
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        error = precision.check(
            plan, q, qd, qdd, arrays, status, failed, newton_near, limits, plan_at
        )
    checked = np.flatnonzero(np.isfinite(error))
    if checked.size:
        d = arrays.derived
        part = status[checked]  # a copy (fancy index): written back below
        _flag_not_finite(
            arrays.x[..., checked], arrays.v[..., checked], arrays.a[..., checked],
            arrays.trans[:, checked], Derived(d.body[..., checked], d.element[..., checked]),
            slice(None), part,
        )  # fmt: skip
        status[checked] = part
    return error


def _solve_chunks(
    plan: SolvePlan,
    full: Chunk,
    derived: Derived,
    chunk: int,
    workers: int | None,
    report: _Reporter,
    designs: DesignBatch | None = None,
) -> None:
    """The closed-form plan over chunks of samples, on a thread per core: each chunk runs the
    steps and then its derived quantities while it is in cache (and, for a family of designs,
    makes its own constants first)."""
    n = full.status.size

    def one(s: int) -> None:
        e = min(s + chunk, n)
        part = slice(s, e)
        q = full.q[:, part]
        if designs is None:
            here = take(plan, part)  # per-sample constants where the plan holds them
        else:
            here, bad = designs.at(part)
            if bad.any():  # a design that builds no mechanism: a status, and no values
                status = full.status[part]
                status[bad & (status == Code.OK)] = Code.BAD_DESIGN
                q = q.copy()
                q[:, bad] = np.nan
        c = Chunk(
            full.x[:, :, part],
            full.v[:, :, part],
            full.a[:, :, part],
            q,
            full.qd[:, part],
            full.qdd[:, part],
            full.trans[:, part],
            full.status[part],
            full.failed[part],
            full.close_tol,
            full.singular_tol,
        )
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            run_steps(here, c, 2)
            derived.fill(plan, c.x, c.v, c.a, part)
            _flag_not_finite(c.x, c.v, c.a, c.trans, derived, part, c.status)
        report(e - s)

    starts = range(0, n, chunk)
    threads = min(workers or os.cpu_count() or 1, len(starts))
    if threads > 1:
        with ThreadPoolExecutor(threads) as pool:
            list(pool.map(one, starts))
    else:
        for s in starts:
            one(s)


def _flag_not_finite(
    x: F, v: F, a: F, trans: F, derived: Derived, s: slice, status: np.ndarray
) -> None:
    """No non-finite number on a row marked ok: an overflow (a rate of 1e300) is a status.

    ``x``, ``v``, ``a``, ``trans`` and ``status`` are the chunk's own slices; ``derived`` is
    the whole result's, read at ``s``.
    """
    finite = (
        np.isfinite(x).all(axis=(0, 1))
        & np.isfinite(v).all(axis=(0, 1))
        & np.isfinite(a).all(axis=(0, 1))
        & np.isfinite(trans).all(axis=0)
        & np.isfinite(derived.body[:, :, s]).all(axis=(0, 1))
        & np.isfinite(derived.element[:, :, s]).all(axis=(0, 1))
    )
    status[~finite & (status == Code.OK)] = Code.NOT_FINITE


def _check_inputs(plan: SolvePlan, q: F, qd: F, qdd: F, status: np.ndarray) -> F:
    """Mark non-finite inputs and non-positive driven lengths; those samples' q become NaN."""
    bad_in = ~(
        np.isfinite(q).all(axis=0) & np.isfinite(qd).all(axis=0) & np.isfinite(qdd).all(axis=0)
    )
    status[bad_in] = Code.BAD_INPUT
    # a length is a distance: zero or negative would be solved as its mirror image
    lengths = [i for i, kind in enumerate(plan.input_kinds) if kind == "length"]
    if lengths:
        bad_len = ~(q[lengths] > 0.0).all(axis=0) & (status == 0)
        if bad_len.any():
            status[bad_len] = Code.BAD_LENGTH
            q = q.copy()
            q[:, bad_len] = np.nan
    return q


class _Reporter:
    """Counts finished samples and calls ``progress(done, total)`` under a lock."""

    def __init__(self, progress: Callable[[int, int], None] | None, total: int) -> None:
        self.progress = progress
        self.total = total
        self.done = 0
        self.lock = threading.Lock()

    def __call__(self, finished: int) -> None:
        if self.progress is None:
            return
        with self.lock:
            self.done += finished
            self.progress(self.done, self.total)


def _solve_newton(
    plan: SolvePlan, assembly: Assembly, full: Chunk, reached: tuple[F, F] | None = None
) -> tuple[F, F] | None:
    """Positions by continuation along the sweep's own order, then the rates; returns the
    last sample reached (positions and inputs), where the next block starts.

    The sample nearest the start — the sketch, or the last sample the block before reached —
    is reached from it; every other sample then follows the sweep from there, through the
    samples between, in stages small enough for Newton. A sweep is a path the user asked for,
    so this keeps each sample on the branch the sweep itself is on — through a full turn, too.
    Samples the sweep cannot reach (the path passes a position that does not close) try the
    straight way from the sketch, the shorter way round and then the longer.
    """
    q, x, status = full.q, full.x, full.status
    steps = _step_sizes(plan)
    if reached is None:
        reached = (assembly.positions, np.asarray(plan.input_sketch, dtype=np.float64))
    _continue_along_sweep(plan, reached, full, steps)
    for long_way in (False, True):
        done = (status == Code.OK) | (status == Code.BAD_INPUT) | (status == Code.BAD_LENGTH)
        retry = np.flatnonzero(~done)
        if not retry.size or (long_way and "angle" not in plan.input_kinds):
            break
        _continue_from_sketch(plan, assembly, full, steps, retry, long_way)
    full.q = q
    signs = run_steps(plan, full, 2, newton=False)
    groups = [(k, st) for k, st in enumerate(plan.steps) if isinstance(st, NewtonGroup)]
    for (k, st), sign, ref in zip(groups, signs, assembly.newton_signs, strict=True):
        flipped = (sign != ref) | ~rotary_branch_ok(full, st)
        kernels.flag(full, flipped & np.isfinite(x[st.points[0], 0]), Code.BRANCH_CHANGED, k)
    ok = np.flatnonzero(status == Code.OK)
    if not ok.size:
        return reached
    return x[:, :, ok[-1]].copy(), q[:, ok[-1]].copy()


def _step_sizes(plan: SolvePlan) -> F:
    """The largest move of each input in one continuation stage: 0.1 rad, or 5 % of the size."""
    return np.array(
        [0.1 if kind == "angle" else 0.05 * plan.scale for kind in plan.input_kinds]
    ).reshape(-1, 1)


def _wrapped(delta: F, plan: SolvePlan) -> F:
    """Input differences, angles the shorter way round (q and q ± 2π are one pose)."""
    out = delta.copy()
    for i, kind in enumerate(plan.input_kinds):
        if kind == "angle":
            out[i] = np.angle(np.exp(1j * out[i]))
    return out


def _positions_only(full: Chunk, samples: np.ndarray | slice, q: F) -> Chunk:
    """A chunk of ``full``'s samples (copies when ``samples`` picks some) for position passes."""
    zero = np.zeros_like(q)
    return Chunk(
        full.x[:, :, samples],
        full.v[:, :, samples],
        full.a[:, :, samples],
        q,
        zero,
        zero,
        full.trans[:, samples],
        full.status[samples],
        full.failed[samples],
        full.close_tol,
        full.singular_tol,
    )


def _continue_along_sweep(plan: SolvePlan, start: tuple[F, F], full: Chunk, steps: F) -> None:
    """Every sample from ``start`` (positions (n_points, 2), inputs (n_inputs,)): to the
    sample nearest it, then along the sweep."""
    q = full.q
    n = q.shape[1]
    q0 = start[1].reshape(-1, 1)
    given = np.isfinite(q).all(axis=0)
    if not given.any():  # no sample to reach (every input refused): no positions either
        full.x[:] = np.nan
        return
    far = np.abs(_wrapped(q - q0, plan)) / steps
    k0 = int(np.argmin(np.where(given, far.max(axis=0), np.inf)))
    # the start → sample k0, for that one sample, then every sample starts there
    mini = _positions_only(full, np.array([k0]), q0.copy())
    mini.x[:] = start[0][:, :, None]
    mini.status[:] = 0
    leg = _wrapped(q[:, k0 : k0 + 1] - q0, plan)
    first = max(int(np.ceil(np.nanmax(np.abs(leg) / steps))), 1)
    first_plan = take(plan, np.array([k0]))
    for k in range(1, first + 1):
        mini.q = q0 + leg * (k / first)
        run_steps(first_plan, mini, 0)
    full.x[:] = mini.x
    # then along the sweep: at stage s, sample i stands s/S of its way from k0 along the sweep
    jump = np.abs(_wrapped(np.diff(q, axis=1), plan)) / steps
    jump = np.where(np.isfinite(jump), jump, 0.0).max(axis=0)
    walked = np.concatenate([[0.0], np.cumsum(jump)])
    stages = int(min(max(np.ceil(np.max(np.abs(walked - walked[k0]))), 1), 4000))
    idx = np.arange(n)
    after = idx >= k0
    c = _positions_only(full, slice(None), q)
    for s in range(1, stages + 1):
        target = walked[k0] + (walked[idx] - walked[k0]) * (s / stages)
        ahead = np.searchsorted(walked, target, side="right") - 1
        behind = np.searchsorted(walked, target, side="left")
        at = np.where(after, np.clip(ahead, k0, idx), np.clip(behind, idx, k0))
        if s == stages:  # its own value at last, whatever the rounding of ``target``
            at = idx
        c.q = q[:, at]  # the sweep's own values: its path, its turns
        run_steps(plan, c, 0)


def _continue_from_sketch(
    plan: SolvePlan,
    assembly: Assembly,
    full: Chunk,
    steps: F,
    samples: np.ndarray,
    long_way: bool,
) -> None:
    """Samples the sweep could not reach: straight from the sketch, the shorter way round (or
    the longer, past what the shorter way could not pass)."""
    q0 = np.asarray(plan.input_sketch, dtype=np.float64)[:, None]
    target = full.q[:, samples]
    delta = _wrapped(target - q0, plan)
    if long_way:
        for i, kind in enumerate(plan.input_kinds):
            if kind == "angle":
                delta[i] -= 2 * np.pi * np.sign(delta[i])
    stages = int(min(max(np.ceil(np.nanmax(np.abs(delta) / steps)), 1), 400))
    c = _positions_only(full, samples, q0.copy())
    c.x[:] = assembly.positions[:, :, None]
    c.status[:] = 0
    c.failed[:] = -1
    plan = take(plan, samples)
    for k in range(1, stages + 1):
        c.q = q0 + delta * (k / stages)
        run_steps(plan, c, 0)
    c.q = target
    run_steps(plan, c, 0)
    full.x[:, :, samples] = c.x
    full.status[samples] = c.status
    full.failed[samples] = c.failed


def assemble(plan: SolvePlan) -> Assembly:
    """Re-assemble the sketch to the exact lengths, with every driver at its sketch value.

    Raises
    ------
    AssemblyError
        When the lengths cannot be assembled, naming the step that does not close.
    """
    n_in = len(plan.inputs)
    q = np.asarray(plan.input_sketch, dtype=np.float64).reshape(n_in, 1)
    zero = np.zeros_like(q)
    n_pts = len(plan.points)
    x = np.asarray(plan.sketch, dtype=np.float64).reshape(n_pts, 2, 1).copy()
    v = np.zeros_like(x)
    a = np.zeros_like(x)
    trans = np.zeros((len(plan.transmissions), 1))
    status = np.zeros(1, dtype=np.int8)
    failed = np.full(1, -1, dtype=np.int16)
    tol = Tolerances()
    c = Chunk(x, v, a, q, zero, zero.copy(), trans, status, failed, tol.close, tol.singular)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        run_steps(plan, c, 0)
        signs = run_steps(plan, c, 2, newton=False) if status[0] == 0 else []
    if status[0] != Code.OK:
        st = Status(status, failed, plan)
        if status[0] == Code.SINGULAR:
            problem = (
                f"the sketch (with its [lengths]) is at a dead position of "
                f"{st.where(int(failed[0]))}, so it does not show which way the mechanism is "
                "assembled; draw the sketch away from it"
            )
        else:
            problem = f"the lengths cannot be assembled at the sketch: {st.message(0)}"
        raise AssemblyError(problem, table="lengths", source=plan.model.source)
    return Assembly(x[:, :, 0].copy(), tuple(float(s[0]) for s in signs))
