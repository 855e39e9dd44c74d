"""Run a `SolvePlan` over a batch of driver inputs.

Inputs are arrays of shape (n,) per driver: values, rates and accelerations. The plan's steps
run in order over cache-sized chunks of samples; there is no Python loop over samples. When the
plan has a Newton group, positions are found by continuation from the assembled sketch: the
inputs move from their sketch values to the requested ones in a few stages, each corrected by
Newton, so that every sample stays on the sketch's assembly branch.
"""

from __future__ import annotations

import dataclasses
import functools
import importlib
import os
import threading
from collections.abc import Callable, Collection, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from excavkin import backends
from excavkin.arrays import FloatArray as F
from excavkin.backends import Kernel
from excavkin.errors import AssemblyError
from excavkin.execution import DEFAULT, Execution
from excavkin.kinematics import compiled as compiled_plan
from excavkin.kinematics import compiled_newton, kernels, precision
from excavkin.kinematics.change_points import (
    MAX_GAP,
    ChangePoint,
    Tail,
    dyads,
    find_change_points,
    searched,
)
from excavkin.kinematics.columns import driver_columns
from excavkin.kinematics.kernels import Chunk, Code
from excavkin.kinematics.newton import rotary_branch_ok, side, wrong_side
from excavkin.kinematics.result import Derived, KinematicResult, Status
from excavkin.kinematics.selection import kept_rows, resting_rows
from excavkin.kinematics.steps import run_steps
from excavkin.kinematics.threads import even, over_chunks
from excavkin.kinematics.vectorise import written_rows
from excavkin.step_kinds import NewtonGroup, of_kind
from excavkin.structure.design import DesignBatch, take
from excavkin.structure.plan import SolvePlan


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
#: samples per pass of the kinematics, unless the execution sets it: a chunk's temporaries stay
#: in cache
CHUNK = 32768
#: samples per pass on a device (`excavkin.gpu`), unless the execution sets it: each pass's
#: arrays are copied to the device and back
DEVICE_CHUNK = 1 << 20


@dataclass(frozen=True, slots=True)
class Workspace:
    """The output arrays of solves of ``n`` samples of one plan's structure, made once and
    written again by every solve given them (`solve_part`'s ``workspace``): a loop of solves
    of blocks — a study's — pays no page faults and stays in the pages it has already touched.

    A result solved into a workspace is views of these arrays: it is good until the next
    solve into the same workspace. The velocity and acceleration rows of a fixed point and
    the ground's body row are zero when made and never written (as a fresh solve's).

    Attributes
    ----------
    x, v, a : ndarray, shape (n_points, 2, n)
    trans : ndarray, shape (n_transmissions, n)
    derived : Derived
    status : ndarray of int8, shape (n,)
    failed : ndarray of int16, shape (n,)
    near : ndarray, shape (n,)
    near_step : ndarray of int16, shape (n,)
    """

    x: F
    v: F
    a: F
    trans: F
    derived: Derived
    status: np.ndarray
    failed: np.ndarray
    near: F
    near_step: np.ndarray

    @classmethod
    def of(cls, plan: SolvePlan, n: int) -> Workspace:
        """The arrays of a solve of ``n`` samples of ``plan`` (or of any plan of its
        structure: a design's).

        Parameters
        ----------
        plan : SolvePlan
        n : int
            Samples.

        Returns
        -------
        Workspace
        """
        n_pts = len(plan.points)
        return cls(
            np.empty((n_pts, 2, n)), np.zeros((n_pts, 2, n)), np.zeros((n_pts, 2, n)),
            np.empty((len(plan.transmissions), n)), Derived.empty(plan, n),
            np.zeros(n, dtype=np.int8), np.empty(n, dtype=np.int16), np.empty(n),
            np.empty(n, dtype=np.int16),
        )  # fmt: skip

    def fits(self, plan: SolvePlan, n: int) -> bool:
        """Whether it holds a solve of ``n`` samples of ``plan``'s structure.

        Parameters
        ----------
        plan : SolvePlan
        n : int

        Returns
        -------
        bool
        """
        return self.x.shape == (len(plan.points), 2, n) and self.trans.shape[0] == len(
            plan.transmissions
        )


@dataclass(frozen=True, slots=True)
class Carry:
    """What one part of a sweep hands the next, so that the parts solve as the whole would.

    Attributes
    ----------
    start : int
        The next part's first sample (a multiple of `BLOCK`).
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
    execution: Execution = DEFAULT,
    unbuildable: np.ndarray | None = None,
    designs: DesignBatch | None = None,
    carry: Carry | None = None,
    workspace: Workspace | None = None,
    change_points: bool = True,
    columns: Collection[str] | None = None,
) -> tuple[KinematicResult, Carry]:
    """Positions, velocities and accelerations of every point for consecutive samples of a
    sweep, each dyad on its sketch side.

    Parameters
    ----------
    plan : SolvePlan
        The plan (with a family of designs' constants taken at these samples, if any).
    assembly : Assembly
        From `assemble`.
    q, qd, qdd : ndarray, shape (n_inputs, n)
        Driver values, rates and accelerations, SI, in ``plan.inputs`` order.
    tol : Tolerances
    execution : Execution
        The backend (a closed-form plan as one compiled loop, `excavkin.backends`, or in
        NumPy), threads solving chunks side by side (NumPy releases the GIL in its loops,
        and chunks write disjoint slices), samples per chunk (default `CHUNK`, so that a
        chunk's temporaries stay in cache) and ``progress(done, n)``, called after each chunk
        with the samples finished so far (serialised, ``done`` increasing, though the calls
        may come from worker threads).
    unbuildable : ndarray of bool, shape (n,), optional
        Samples whose design (a plan with per-sample dimensions) builds no mechanism.
    designs : DesignBatch, optional
        A family of designs of ``plan`` (a closed-form one), one per sample: each chunk's
        constants are made as the chunk is solved.
    carry : Carry, optional
        What the part before handed on (none: these samples start the sweep).
    workspace : Workspace, optional
        Arrays to solve into (`Workspace.fits` these samples), instead of new ones: the
        result is views of them, good until the next solve into them.
    change_points : bool
        Search the change points (default); False: the result lists none (a family of
        designs one after another, whose neighbouring samples are not a path).
    columns : collection of str, optional
        Only these kinematic columns are asked (`excavkin.kinematics.selection.asked_names`):
        where `solve_selected` can, only their rows hold values (read them through
        `excavkin.kinematics.selection.SelectedResult`). None: every row.

    Returns
    -------
    KinematicResult
        Its change points are numbered in the whole sweep.
    Carry
        For the part after.
    """
    carry = carry or Carry()
    if columns is not None and workspace is None and designs is None:
        selected = solve_selected(
            plan, q, qd, qdd, columns, tol=tol, execution=execution, unbuildable=unbuildable,
            carry=carry, change_points=change_points,
        )  # fmt: skip
        if selected is not None:
            return selected
    n_in, n = q.shape
    workspace = _prepared(plan, n, workspace)
    x, v, a, trans = workspace.x, workspace.v, workspace.a, workspace.trans
    derived, status, failed = workspace.derived, workspace.status, workspace.failed
    q_given = q
    if plan.has_newton:  # the continuation needs every input checked before it starts
        failed.fill(-1)
        q = check_inputs(plan, q, qd, qdd, status, unbuildable)
    # else each chunk checks its own inputs, on its thread, while they are in cache
    report = _Reporter(execution.progress, n)
    newton, newton_near = _newton_kernels(plan, execution, n)
    full = Chunk(x, v, a, q, qd, qdd, trans, status, failed, tol.close, tol.singular, newton_near)
    blocks = _blocks(carry.start, n)
    reached = carry.reached
    near, near_step = workspace.near, workspace.near_step
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if plan.has_newton:  # positions by continuation, block by block; then the rates
            reached, execution = _continue_blocks(
                plan, assembly, full, blocks, reached, execution, newton
            )
        checked = assembly if plan.has_newton else None  # the Newton groups' branch
        _solve_chunks(plan, full, derived, (near, near_step), execution, report, designs,
                      checked, unbuildable, newton)  # fmt: skip
    error, found, tail = _check_blocks(
        plan, (q_given, q, qd, qdd), precision.Arrays(x, v, a, trans, derived), status, failed,
        (near, near_step), tol, designs, carry, blocks, change_points,
    )  # fmt: skip
    result = KinematicResult.build(
        plan, x, v, a, q_given, qd, qdd, trans, derived, Status(status, failed, plan)
    )
    result = dataclasses.replace(result, change_points=tuple(found), error_estimate=error)
    return result, Carry(carry.start + n, tail, reached)


def _newton_kernels(
    plan: SolvePlan, execution: Execution, n: int
) -> tuple[Kernel | None, F | None]:
    """A plan with Newton groups: its compiled kernels, where the backend takes them (one
    choice, here), and the groups' nearness to a dead position a sample for the NumPy rates
    (None where the compiled kernel keeps its own)."""
    if not plan.has_newton:
        return None, None
    newton = compiled_newton.kernel_for(plan, execution.backend, n)
    return newton, np.ones(n) if newton is None else None


def _continue_blocks(
    plan: SolvePlan,
    assembly: Assembly,
    full: Chunk,
    blocks: list[slice],
    reached: tuple[F, F] | None,
    execution: Execution,
    newton: Kernel | None,
) -> tuple[tuple[F, F] | None, Execution]:
    """`solve_part`'s positions of a plan with Newton groups: by continuation, block by block
    (`_solve_newton`), in chunks of the groups' size (`_newton_chunk`), by the compiled
    positions kernel where ``newton`` has one. Returns the last sample reached, and the
    execution with that chunk (the rates' chunks too)."""
    chunk = _newton_chunk(plan, execution.chunk_or(CHUNK))
    positions = None if newton is None else newton.positions  # type: ignore[attr-defined]
    for b in blocks:
        reached = _solve_newton(
            take(plan, b), assembly, _view(full, b), reached, chunk, execution.workers, positions
        )
    return reached, dataclasses.replace(execution, chunk=chunk)


def solve_selected(
    plan: SolvePlan,
    q: F,
    qd: F,
    qdd: F,
    columns: Collection[str],
    *,
    tol: Tolerances = Tolerances(),
    execution: Execution = DEFAULT,
    unbuildable: np.ndarray | None = None,
    carry: Carry | None = None,
    change_points: bool = True,
) -> tuple[KinematicResult, Carry] | None:
    """`solve_part` of some columns by the plan's compiled kernel made to keep some rows
    (`excavkin.kinematics.compiled.kernel_source` ``keep``, run as
    `excavkin.kinematics.compiled.run_designs` runs a study's), where the backend solves
    this plan compiled; None where it does not (NumPy, a
    device, a plan with Newton groups or one that does not compile, a part that does not
    start a block): then `solve_part` solves every column.

    Every sample is solved whole, in registers, and checked as the full solve checks it: the
    finiteness of every value in the kernel; the precision check's scales kept by the kernel
    (its ``tops``), each block's, and the samples near a dead position solved again whole and
    checked together (`excavkin.kinematics.precision.check_picked`), their improved values
    copied to the rows kept; the change points found from the transmission angles, always
    kept (`excavkin.kinematics.selection.kept_rows`), and a block where a dyad whose rows
    were not kept comes near flat solved again whole for them (`_search_selected`). So
    every status, error estimate and change point, and every value of a row kept, is the
    full solve's to the bit. Only the kept rows of the result's arrays are written, and the
    rows no kernel writes that a column asked reads (zero): the others are never touched,
    and hold no values.

    Parameters
    ----------
    plan : SolvePlan
        The plan (its constants one value each, or one a sample).
    q, qd, qdd : ndarray, shape (n_inputs, n)
        Driver values, rates and accelerations, SI, in ``plan.inputs`` order.
    columns : collection of str
        The kinematic columns asked (`excavkin.kinematics.selection.asked_names`).
    tol, execution, unbuildable, carry, change_points
        As for `solve_part`.

    Returns
    -------
    (KinematicResult, Carry) or None
        The result (only the kept rows of its arrays hold values) and the carry for the
        part after.
    """
    carry = carry or Carry()
    n = q.shape[1]
    text = _keep_source(plan, execution, n) if n and not carry.start % BLOCK else None
    if text is None:
        return None
    kernel = backends.kernel_of(text, "kinematics")
    rows, n_rows = written_rows(text)
    keep = kept_rows(plan, rows, n_rows, columns, change_points)
    ws = _unwritten(plan, n, rows, resting_rows(plan, rows, columns))
    consts, stride = compiled_plan.table(compiled_plan.constants(plan), n)
    tops = _run_kept(plan, kernel, (consts, stride), ws, (q, qd, qdd), keep, tol, execution,
                     unbuildable)  # fmt: skip
    derived = ws.derived
    again = functools.partial(
        _solve_again, plan, kernel, (consts, stride), (q, qd, qdd), tol, unbuildable, n_rows
    )
    error = np.full(n, np.nan)
    pick = np.flatnonzero((ws.status == Code.OK) & (ws.near < precision.NEAR))
    improved = None
    if pick.size:  # the samples near a dead position: solved again whole, checked together
        picked = (q[:, pick], qd[:, pick], qdd[:, pick])
        solved = _check_picked(plan, again, picked, pick, tops, tol, ws, error, keep, rows)
        improved = (pick, solved)
    found: list[ChangePoint] = []
    tail = carry.tail
    if change_points:
        found, tail = _search_selected(plan, ws, (q, qd), carry, (keep, rows), again, improved)
    _driven_lengths(plan, derived, columns, (q, qd, qdd))
    result = KinematicResult.build(
        plan, ws.x, ws.v, ws.a, q, qd, qdd, ws.trans, derived,
        Status(ws.status, ws.failed, plan), lengths=False,
    )  # fmt: skip
    result = dataclasses.replace(result, change_points=tuple(found), error_estimate=error)
    return result, Carry(carry.start + n, tail, carry.reached)


def _keep_source(plan: SolvePlan, execution: Execution, n: int) -> str | None:
    """`solve_selected`'s kernel source (``keep``), where the backend a full solve of ``n``
    samples takes is numba and the plan compiles; None: a full solve."""
    if plan.has_newton:
        return None
    each = compiled_plan.per_sample(plan)
    plain = compiled_plan.job(plan, each)
    if plain.unsupported is not None:
        return None
    if backends.choose(execution.backend, plain, n).name != "numba":
        return None  # (the backend a full solve takes: the same numbers)
    return compiled_plan.kernel_source(plan, each, keep=True)


def _run_kept(
    plan: SolvePlan,
    kernel: Kernel,
    table: tuple[F, int],
    ws: Workspace,
    inputs: tuple[F, F, F],
    keep: np.ndarray,
    tol: Tolerances,
    execution: Execution,
    unbuildable: np.ndarray | None,
) -> np.ndarray:
    """`solve_selected`'s samples solved by the ``keep`` kernel into ``ws``, in chunks that
    divide a block (a power of two), each with its own share of the precision check's
    scales. Returns each block's scales, the largest of its chunks' (as integers: 0 is
    none)."""
    q, qd, qdd = inputs
    consts, stride = table
    n = q.shape[1]
    chunk = 1 << (min(max(execution.chunk_or(CHUNK), 1), BLOCK).bit_length() - 1)
    shares = np.zeros((-(-n // chunk), len(precision.KINDS)), dtype=np.int64)
    report = _Reporter(execution.progress, n)
    derived = ws.derived

    def one(s: int) -> None:
        e = min(s + chunk, n)
        part = slice(s, e)
        ws.failed[part] = -1
        bad = None if unbuildable is None else unbuildable[part]
        qb = check_inputs(plan, q[:, part], qd[:, part], qdd[:, part], ws.status[part], bad)
        c = Chunk(
            ws.x, ws.v, ws.a, qb, qd[:, part], qdd[:, part], ws.trans, ws.status, ws.failed,
            tol.close, tol.singular,
        )  # fmt: skip
        compiled_plan.run_designs(
            kernel, consts[:, part] if stride else consts, stride, 0, c, derived.body,
            derived.element, ws.near, ws.near_step, keep, shares[s // chunk], precision.NEAR, s,
        )  # fmt: skip
        report(e - s)

    over_chunks(n, chunk, execution.workers, one)
    per = BLOCK // chunk
    padded = np.zeros((-(-n // BLOCK) * per, len(precision.KINDS)), dtype=np.int64)
    padded[: shares.shape[0]] = shares
    tops: np.ndarray = padded.reshape(-1, per, len(precision.KINDS)).max(axis=1)
    return tops


def _driven_lengths(
    plan: SolvePlan, derived: Derived, columns: Collection[str], inputs: tuple[F, F, F]
) -> None:
    """A driven length's columns asked: its input, rate and acceleration, exactly (no kernel
    writes them)."""
    for j, e in enumerate(plan.elements):
        if e.input < 0 or e.ratio:
            continue
        for k, c in enumerate(driver_columns(e.name, "length")):
            if c.name in columns:
                derived.element[k, j] = inputs[k][e.input]


def _unwritten(
    plan: SolvePlan,
    n: int,
    rows: dict[tuple[str, tuple[int, ...]], int],
    rest: list[tuple[str, tuple[int, ...]]],
) -> Workspace:
    """`solve_selected`'s arrays: none written (not even zeroed, as `Workspace.of` zeroes
    the velocities and accelerations: a fresh array's pages are zeroed when first touched,
    but memory used before is zeroed in full), but the rows ``rest``, which no kernel
    writes and a column asked reads: zero, as a solve's are (a fixed point's rates, the
    ground's angle). (``rows``: the rows the kernel writes.)"""
    n_pts = len(plan.points)
    per_sample = 8 * (6 * n_pts + len(plan.transmissions) + 3 * len(plan.bodies))
    with _small_pages(n * (per_sample + 48 * len(plan.elements))):
        ws = Workspace(
            np.empty((n_pts, 2, n)), np.empty((n_pts, 2, n)), np.empty((n_pts, 2, n)),
            np.empty((len(plan.transmissions), n)),
            Derived(np.empty((3, len(plan.bodies), n)), np.empty((6, len(plan.elements), n))),
            np.zeros(n, dtype=np.int8), np.empty(n, dtype=np.int16), np.empty(n),
            np.empty(n, dtype=np.int16),
        )  # fmt: skip
    arrays = {"x": ws.x, "v": ws.v, "a": ws.a, "trans": ws.trans}
    arrays |= {"body": ws.derived.body, "element": ws.derived.element}
    for name, lead in rest:
        if (name, lead) not in rows:
            arrays[name][lead] = 0.0
    return ws


def _solve_again(
    plan: SolvePlan,
    kernel: Kernel,
    consts: tuple[F, int],
    inputs: tuple[F, F, F],
    tol: Tolerances,
    unbuildable: np.ndarray | None,
    n_rows: int,
    index: np.ndarray,
) -> Workspace:
    """`solve_selected`'s samples ``index`` solved again whole (every row) by its kernel,
    their inputs checked as the first solve checked them: the same values, to the bit
    (``n_rows``: the kernel's scratch rows, every one written out)."""
    table, stride = consts
    q, qd, qdd = (arr[:, index] for arr in inputs)
    out = Workspace.of(plan, index.size)
    out.failed.fill(-1)
    bad = None if unbuildable is None else unbuildable[index]
    checked = check_inputs(plan, q, qd, qdd, out.status, bad)
    c = Chunk(
        out.x, out.v, out.a, checked, qd, qdd, out.trans, out.status, out.failed, tol.close,
        tol.singular,
    )  # fmt: skip
    compiled_plan.run_designs(
        kernel, np.ascontiguousarray(table[:, index]) if stride else table, stride, 0, c,
        out.derived.body, out.derived.element, out.near, out.near_step,
        np.ones(n_rows, dtype=np.int8), np.zeros(len(precision.KINDS), dtype=np.int64),
        precision.NEAR,
    )  # fmt: skip
    return out


def _check_picked(
    plan: SolvePlan,
    again: Callable[[np.ndarray], Workspace],
    inputs: tuple[F, F, F],
    pick: np.ndarray,
    tops: np.ndarray,
    tol: Tolerances,
    ws: Workspace,
    error: F,
    keep: np.ndarray,
    rows: dict[tuple[str, tuple[int, ...]], int],
) -> Workspace:
    """`solve_selected`'s precision check: the samples ``pick`` (ok, near a dead position)
    solved again whole (``again``) and checked together, each against its block's scales
    (``tops``); their statuses, failed steps and error estimates set in ``ws`` and
    ``error``, and their improved values copied to the rows ``keep`` (`written_rows`'
    ``rows``). Returns their whole state, improved."""
    blocks = []
    for b, at in zip(*np.unique(pick // BLOCK, return_index=True), strict=True):
        upto = int(np.searchsorted(pick, (b + 1) * BLOCK))
        far = tops[b].view(np.float64).tolist()
        blocks.append((upto - int(at), dict(zip(precision.KINDS, far, strict=True))))
    solved = again(pick)
    _, err, code, step = check_solved_again(take(plan, pick), inputs, solved, tol, blocks)
    ws.status[pick], ws.failed[pick], error[pick] = code, step, err
    into = {"x": ws.x, "v": ws.v, "a": ws.a, "trans": ws.trans}
    into |= {"body": ws.derived.body, "element": ws.derived.element}
    got = {"x": solved.x, "v": solved.v, "a": solved.a, "trans": solved.trans}
    got |= {"body": solved.derived.body, "element": solved.derived.element}
    for (name, lead), row in rows.items():
        if keep[row]:
            index: tuple[int | np.ndarray, ...] = (*lead, pick)
            into[name][index] = got[name][lead]
    return solved


def _search_selected(
    plan: SolvePlan,
    ws: Workspace,
    inputs: tuple[F, F],
    carry: Carry,
    kept: tuple[np.ndarray, dict[tuple[str, tuple[int, ...]], int]],
    again: Callable[[np.ndarray], Workspace],
    improved: tuple[np.ndarray, Workspace] | None,
) -> tuple[list[ChangePoint], Tail | None]:
    """`_search_blocks` for `solve_selected`: a dyad's change points are searched in its
    positions and velocities only where its triangle comes near flat
    (`excavkin.kinematics.change_points.searched`, from the transmission angles, always
    kept); a block where a dyad whose rows were not kept is searched is solved again whole
    (``again``, the precision check's ``improved`` samples' values put in), and so is the
    tail each block hands the next. The same change points, to the bit."""
    q, qd = inputs
    keep, rows = kept
    unkept = {
        unit
        for unit, st in dyads(plan)
        for p in (st.point, st.a, st.b)
        for key in (("x", (p, 0)), ("x", (p, 1)), ("v", (p, 0)), ("v", (p, 1)))
        if key in rows and not keep[rows[key]]
    }

    def state(index: np.ndarray) -> tuple[F, F]:
        out = again(index)
        if improved is not None:
            pick, solved = improved
            _, i, j = np.intersect1d(index, pick, assume_unique=True, return_indices=True)
            out.x[..., i], out.v[..., i] = solved.x[..., j], solved.v[..., j]
        return out.x, out.v

    found: list[ChangePoint] = []
    tail = carry.tail
    for b in _blocks(carry.start, ws.status.size):
        trans = ws.trans[:, b]
        whole = any(unit in unkept for unit, _ in searched(plan, ws.x[..., b], trans, tail))
        x, v = state(np.arange(b.start, b.stop)) if whole else (ws.x[..., b], ws.v[..., b])
        found += find_change_points(
            plan, x, v=v, q=q[:, b], qd=qd[:, b], trans=trans, offset=carry.start + b.start,
            tail=tail,
        )  # fmt: skip
        last = np.arange(max(b.start, b.stop - MAX_GAP - 1), b.stop)
        if unkept and not whole:
            x, v = state(last)
        else:
            x, v = x[..., last - b.start], v[..., last - b.start]
        tail = Tail.of(x, v, q[:, last], qd[:, last], ws.trans[:, last], before=tail)
    order = {plan.points[st.point]: unit for unit, st in dyads(plan)}
    found.sort(key=lambda cp: order[cp.point])  # plan order, each dyad's in sample order
    return found, tail


def _prepared(plan: SolvePlan, n: int, workspace: Workspace | None) -> Workspace:
    """The arrays a part of n samples solves into: ``workspace`` checked and its statuses
    cleared, or new ones."""
    if workspace is None:
        per_sample = 8 * (6 * len(plan.points) + len(plan.transmissions) + 3 * len(plan.bodies))
        with _small_pages(n * (per_sample + 48 * len(plan.elements))):
            return Workspace.of(plan, n)  # (a fixed point's v and a rows stay zero: the
            # compiled plan leaves them unwritten, and never paged in)
    if not workspace.fits(plan, n):
        raise ValueError(f"a workspace of shape {workspace.x.shape} for {n} samples")
    workspace.status.fill(0)
    return workspace


def _check_blocks(
    plan: SolvePlan,
    inputs: tuple[F, F, F, F],
    out: precision.Arrays,
    status: np.ndarray,
    failed: np.ndarray,
    nearest: tuple[F, np.ndarray],
    tol: Tolerances,
    designs: DesignBatch | None,
    carry: Carry,
    blocks: list[slice],
    change_points: bool = True,
) -> tuple[F, list[ChangePoint], Tail | None]:
    """Block by block, the precision check (its scales are the block's) and the change
    points (searched in the dyads that come near flat in the block, and between it and the
    block before): the error estimates, the change points in plan order and the last tail
    (none searched without ``change_points``). ``inputs``: the inputs as given, and as
    solved (q, qd, qdd)."""
    q_given, q, qd, qdd = inputs
    x, v, a, trans, derived = out.x, out.v, out.a, out.trans, out.derived
    error = np.empty(q.shape[1])  # every block's estimates are written below
    found: list[ChangePoint] = []
    tail = carry.tail
    per_sample = take(plan, slice(0, 0)) is not plan  # (else every block's plan is the plan)
    for b in blocks:
        near = (nearest[0][b], nearest[1][b])
        arrays = precision.Arrays(
            x[..., b], v[..., b], a[..., b], trans[:, b],
            Derived(derived.body[..., b], derived.element[..., b]),
        )  # fmt: skip
        error[b] = _check_precision(
            take(plan, b) if per_sample else plan, (q[:, b], qd[:, b], qdd[:, b]), arrays,
            status[b], failed[b], near, tol, designs, b.start,
        )  # fmt: skip
    if change_points:
        found, tail = _search_blocks(plan, (x, v, q_given, qd, trans), carry, blocks)
    return error, found, tail


def _search_blocks(
    plan: SolvePlan, arrays: tuple[F, F, F, F, F], carry: Carry, blocks: list[slice]
) -> tuple[list[ChangePoint], Tail | None]:
    """The change points, block by block (searched in the dyads that come near flat in
    the block, and between it and the block before), in plan order, and the last tail.
    ``arrays``: x, v, the inputs as given, their rates and the transmission angles."""
    x, v, q_given, qd, trans = arrays
    found: list[ChangePoint] = []
    tail = carry.tail
    for b in blocks:
        here = (x[..., b], v[..., b], q_given[:, b], qd[:, b], trans[:, b])
        found += find_change_points(
            plan, here[0], v=here[1], q=here[2], qd=here[3], trans=here[4],
            offset=carry.start + b.start, tail=tail,
        )  # fmt: skip
        tail = Tail.of(*here, before=tail)
    order = {plan.points[st.point]: unit for unit, st in dyads(plan)}
    found.sort(key=lambda cp: order[cp.point])  # plan order, each dyad's in sample order
    return found, tail


#: a result at least this large (bytes) is made of ordinary pages (`_small_pages`),
#: unless free memory holds it twice over in pieces a huge page can take
LARGE_RESULT = 2**30


@contextmanager
def _small_pages(nbytes: int) -> Iterator[None]:
    """Arrays made here get ordinary pages when they add up to `LARGE_RESULT` or more
    and free memory in pieces of a huge page or more (`free_in_huge_pieces`) is less
    than twice that. NumPy advises the kernel to back a large array with huge pages, each
    found (zeroed, and compacted if memory is in small pieces) when first touched: far fewer
    faults than ordinary pages (a solve of 10⁷ four-bar samples is twice as fast with them),
    but the threads writing a fresh result of 10⁷ samples (≈ 3 GB) were seen to stall on
    them, 5× slower, where memory had to be compacted first. The setting is NumPy's,
    process-wide: it is put back as it was at once."""
    if nbytes < LARGE_RESULT or free_in_huge_pieces() >= 2 * nbytes:
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


def free_in_huge_pieces(buddyinfo: str | None = None) -> int:
    """Bytes of free memory in pieces a huge page can take without compaction, from Linux's
    ``/proc/buddyinfo`` (free blocks of each order, per zone) or the text given; 0 where it
    cannot be read (then large results take ordinary pages)."""
    try:
        text = Path("/proc/buddyinfo").read_text() if buddyinfo is None else buddyinfo
        page = os.sysconf("SC_PAGE_SIZE")
        hpage = Path("/sys/kernel/mm/transparent_hugepage/hpage_pmd_size")
        huge = int(hpage.read_text()) if hpage.exists() else 2**21
    except (OSError, ValueError):
        return 0
    least = max((huge // page).bit_length() - 1, 0)  # the order of a huge page
    total = 0
    for line in text.splitlines():
        counts = line.split()[4:]  # "Node 0, zone Normal" then one count per order
        for order, count in enumerate(counts):
            if order >= least and count.isdigit():
                total += int(count) * page << order
    return total


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
    nearest: tuple[F, np.ndarray],
    tol: Tolerances,
    designs: DesignBatch | None,
    offset: int = 0,
) -> F:
    """`check_precision` of a block; ``offset`` is the first sample's place in ``designs``."""
    plan_at = None if designs is None else (lambda index: designs.at(index + offset)[0])
    return check_precision(plan, inputs, arrays, status, failed, nearest, tol, plan_at)


def check_precision(
    plan: SolvePlan,
    inputs: tuple[F, F, F],
    arrays: precision.Arrays,
    status: np.ndarray,
    failed: np.ndarray,
    nearest: tuple[F, np.ndarray],
    tol: Tolerances,
    plan_at: Callable[[np.ndarray], SolvePlan] | None = None,
) -> F:
    """The precision check near dead positions (`excavkin.kinematics.precision`) of a
    block's samples, in place, and the finiteness check again on the samples it may have
    given extended values.

    Parameters
    ----------
    plan : SolvePlan
        The block's plan.
    inputs : (ndarray, ndarray, ndarray), each shape (n_inputs, n)
        The inputs, their rates and accelerations.
    arrays : precision.Arrays
        The block's solution, improved in place.
    status : ndarray of int8, shape (n,)
    failed : ndarray of int16, shape (n,)
        Updated in place.
    nearest : (ndarray, ndarray)
        Each sample's nearness to a dead position and nearest step.
    tol : Tolerances
    plan_at : callable, optional
        ``plan_at(index)``: the plan of the samples at ``index`` (default: ``plan`` taken
        at them).

    Returns
    -------
    ndarray, shape (n,)
        Each sample's estimated error (NaN where not checked).
    """
    q, qd, qdd = inputs
    limits = (tol.close, tol.singular)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        error = precision.check(plan, q, qd, qdd, arrays, status, failed, nearest, limits, plan_at)
    check_finite(arrays, status, np.isfinite(error))
    return error


def check_solved_again(
    picked: SolvePlan,
    inputs: tuple[F, F, F],
    solved: Workspace,
    tol: Tolerances,
    blocks: list[tuple[int, dict[str, float]]],
) -> tuple[precision.Arrays, F, np.ndarray, np.ndarray]:
    """Samples picked near a dead position and solved again whole (``solved``), checked
    together against their blocks' scales (`excavkin.kinematics.precision.check_picked`),
    and every value not finite flagged (`check_finite`).

    Parameters
    ----------
    picked : SolvePlan
        The plan of the picked samples (their designs' constants, `take`).
    inputs : tuple of ndarray
        Their inputs, rates and accelerations.
    solved : Workspace
        Their whole state.
    tol : Tolerances
    blocks : list of (int, dict)
        Per block, in the picks' order: how many picks are its, and its far samples' tops.

    Returns
    -------
    arrays : precision.Arrays
        The state checked (``solved``'s arrays).
    error, code, step : ndarray
        Each sample's error estimate, status and failed step.
    """
    arrays = precision.Arrays(solved.x, solved.v, solved.a, solved.trans, solved.derived)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        error, code, step = precision.check_picked(
            picked, inputs, arrays, (solved.near, solved.near_step),
            (tol.close, tol.singular), blocks,
        )  # fmt: skip
    check_finite(arrays, code, np.isfinite(error))
    return arrays, error, code, step


def check_finite(arrays: precision.Arrays, status: np.ndarray, which: np.ndarray) -> None:
    """The finiteness check again on the samples ``which`` (those the precision check may
    have given extended values): a value not finite on a row still ok is ``NOT_FINITE``.

    Parameters
    ----------
    arrays : precision.Arrays
        The samples' solution.
    status : ndarray of int8, shape (n,)
        Updated in place.
    which : ndarray of bool, shape (n,)
    """
    checked = np.flatnonzero(which)
    if checked.size:
        d = arrays.derived
        part = status[checked]  # a copy (fancy index): written back below
        _flag_not_finite(
            arrays.x[..., checked], arrays.v[..., checked], arrays.a[..., checked],
            arrays.trans[:, checked], Derived(d.body[..., checked], d.element[..., checked]),
            slice(None), part,
        )  # fmt: skip
        status[checked] = part


def _solve_chunks(
    plan: SolvePlan,
    full: Chunk,
    derived: Derived,
    nearest: tuple[F, np.ndarray],
    execution: Execution,
    report: _Reporter,
    designs: DesignBatch | None = None,
    assembly: Assembly | None = None,
    unbuildable: np.ndarray | None = None,
    newton: Kernel | None = None,
) -> None:
    """The plan over chunks of samples, on a thread per core: each chunk runs the steps and
    then its derived quantities and nearness to dead positions while it is in cache (and, for
    a family of designs, makes its own constants first). Newton groups' positions are already
    found (`_solve_newton`): here they get their rates, and their branch is checked
    against ``assembly``'s. The backend (`excavkin.backends.choose`) runs a closed-form
    plan as its compiled loop or each chunk's steps in NumPy. Fills
    ``nearest`` (each sample's nearness and nearest step, as
    `nearness`). A closed-form plan's inputs are not
    checked yet: each chunk checks its own (`check_inputs`, with the samples whose
    design builds no mechanism, ``unbuildable``) and sets its ``failed`` to −1; a plan with
    Newton groups had them checked before its continuation, and its backend chosen
    (``newton``: its compiled kernel, `excavkin.kinematics.compiled_newton`; None: NumPy)."""
    n = full.status.size
    chunk, workers = execution.chunk_or(CHUNK), execution.workers
    each = designs is not None or compiled_plan.per_sample(plan)  # the kernel's constants
    consts: tuple[F, int] | None = None
    kernel: Kernel | None = None
    scalar = False  # the kernel is the plain loop's, on a device
    refs = None  # a plan with Newton groups: its groups' reference signs
    if plan.has_newton:
        assert assembly is not None
        refs = compiled_newton.references(plan, assembly.newton_signs, assembly.positions)

    def one(s: int) -> None:
        e = min(s + chunk, n)
        part = slice(s, e)
        q = full.q[:, part]
        if not plan.has_newton:
            full.failed[part] = -1
            bad_design = None if unbuildable is None else unbuildable[part]
            q = check_inputs(
                plan, q, full.qd[:, part], full.qdd[:, part], full.status[part], bad_design
            )
        if designs is None:
            here = plan if consts is not None else take(plan, part)  # per-sample constants
        else:
            here, bad = designs.at(part)
            if bad.any():  # a design that builds no mechanism: a status, and no values
                status = full.status[part]
                status[bad & (status == Code.OK)] = Code.BAD_DESIGN
                q = q.copy()
                q[:, bad] = np.nan
        if kernel is not None:  # the chunk's inputs; the whole solve's outputs, from s on
            c = dataclasses.replace(full, q=q, qd=full.qd[:, part], qdd=full.qdd[:, part])
            out = (derived.body, derived.element, *nearest)
            if designs is None and consts is not None:
                k, stride = consts
                table = (k[:, part] if stride else k, stride)
            else:
                table = compiled_plan.table(compiled_plan.constants(here), e - s)
            if refs is not None:  # a plan with Newton groups: its rates kernel
                compiled_newton.run_rates(kernel, table, c, out, part, refs)
            else:
                compiled_plan.run_table(kernel, table, c, *out, s, scalar)
        else:
            c = dataclasses.replace(_view(full, part), q=q)  # the inputs, unbuildable designs NaN
            near, near_step = nearest[0][part], nearest[1][part]
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                signs = run_steps(here, c, 2, newton=False)
                if assembly is not None:
                    _check_branches(here, assembly, c, signs)
                derived.fill(plan, c.x, c.v, c.a, part)
                _flag_not_finite(c.x, c.v, c.a, c.trans, derived, part, c.status)
                near[:], near_step[:] = precision.nearness(plan, c.trans, c.near)
        report(e - s)

    def compiled(k: Kernel) -> None:
        nonlocal consts, kernel
        # the compiled loop's constants, made once: each chunk takes its columns
        consts, kernel = compiled_plan.table(compiled_plan.constants(plan), n), k
        over_chunks(n, chunk, workers, one)

    def device(k: Kernel) -> None:
        nonlocal consts, kernel, scalar, workers, chunk
        consts, kernel = compiled_plan.table(compiled_plan.constants(plan), n), k
        scalar, workers = True, 1  # the chunks one after another: the device runs each whole
        chunk = execution.chunk_or(DEVICE_CHUNK)  # each crosses the bus: large ones
        over_chunks(n, chunk, workers, one)

    def numpy() -> None:
        over_chunks(n, chunk, workers, one)

    if plan.has_newton:  # its backend chosen already
        return numpy() if newton is None else compiled(newton)
    job = compiled_plan.job(plan, each, numpy, compiled, device)
    backends.choose(execution.backend, job, n).run(job)


def _newton_chunk(plan: SolvePlan, chunk: int) -> int:
    """Samples per pass of a plan with Newton groups: its Jacobians (m², m twice a group's
    points) stay in cache as the closed form's few arrays do at ``chunk``."""
    m = max(2 * len(st.points) for _, st in of_kind(plan.steps, NewtonGroup))
    return max(256, min(chunk, chunk * 8 // (m * m)))


def _check_branches(plan: SolvePlan, assembly: Assembly, c: Chunk, signs: list[F]) -> None:
    """A Newton group has changed its assembly branch where one of its dyads is not on the side
    it keeps, where its driven body points the opposite way (θ + π), or where its determinant's
    sign is not the sketch's — turned over once for each dyad kept on the side opposite the
    sketch's (the smooth continuation's, past a change point)."""
    groups = of_kind(plan.steps, NewtonGroup)
    sketch = assembly.positions[:, :, None]
    for (k, st), sign, ref in zip(groups, signs, assembly.newton_signs, strict=True):
        turned = np.ones_like(sign)
        off = np.zeros(sign.shape, dtype=bool)
        for d in st.dyads:
            off |= wrong_side(c.x, d)
            at_sketch = np.sign(side(sketch, d))  # the side at the (assembled) sketch
            turned = turned * np.where(np.asarray(d.sign) * at_sketch < 0, -1.0, 1.0)
        flipped = (sign != ref * turned) | ~rotary_branch_ok(c, st) | off
        kernels.flag(c, flipped & np.isfinite(c.x[st.points[0], 0]), Code.BRANCH_CHANGED, k)


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


def check_inputs(
    plan: SolvePlan, q: F, qd: F, qdd: F, status: np.ndarray, unbuildable: np.ndarray | None
) -> F:
    """Mark non-finite inputs, non-positive driven lengths and then the samples whose design
    builds no mechanism (``unbuildable``); the last two's q become NaN (a copy: the caller's
    arrays are left as they are).

    Parameters
    ----------
    plan : SolvePlan
    q, qd, qdd : ndarray, shape (n_inputs, n)
        The inputs, their rates and accelerations.
    status : ndarray of int8, shape (n,)
        Marked in place.
    unbuildable : ndarray of bool, shape (n,), optional
        Samples whose design builds no mechanism.

    Returns
    -------
    ndarray, shape (n_inputs, n)
        The inputs to solve: ``q``, or a copy with the marked samples NaN.
    """
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
    if unbuildable is not None and unbuildable.any():
        status[unbuildable & (status == Code.OK)] = Code.BAD_DESIGN
        q = q.copy()
        q[:, unbuildable] = np.nan
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
    plan: SolvePlan,
    assembly: Assembly,
    full: Chunk,
    reached: tuple[F, F] | None,
    chunk: int,
    workers: int | None,
    kernel: Kernel | None = None,
) -> tuple[F, F] | None:
    """Positions by continuation along the sweep's own order (their rates come after); returns
    the last sample reached (positions and inputs), where the next block starts.

    The sample nearest the start — the sketch, or the last sample the block before reached —
    is reached from it; every other sample then follows
    the sweep from there, through the samples between, in stages small enough for Newton.
    A sweep is a path the user asked for, so this keeps each sample on the branch the sweep
    itself is on — through a full turn, too. Samples the sweep cannot reach (the path passes
    a position that does not close) try the straight way from the sketch, the shorter way
    round and then the longer.
    """
    q, status = full.q, full.status
    steps = step_sizes(plan)
    if reached is None:
        reached = (assembly.positions, np.asarray(plan.input_sketch, dtype=np.float64))
    _continue_along_sweep(plan, reached, full, steps, chunk, workers, kernel)
    for long_way in (False, True):
        done = (status == Code.OK) | (status == Code.BAD_INPUT) | (status == Code.BAD_LENGTH)
        retry = np.flatnonzero(~done)
        if not retry.size or (long_way and "angle" not in plan.input_kinds):
            break
        _continue_from_sketch(plan, assembly, full, steps, retry, long_way, chunk, workers, kernel)
    full.q = q
    ok = np.flatnonzero(status == Code.OK)
    if not ok.size:
        return reached
    return full.x[:, :, ok[-1]].copy(), q[:, ok[-1]].copy()


def step_sizes(plan: SolvePlan) -> F:
    """The largest move of each input in one continuation stage: 0.1 rad, or 5 % of the size."""
    return np.array(
        [0.1 if kind == "angle" else 0.05 * plan.scale for kind in plan.input_kinds]
    ).reshape(-1, 1)


def wrapped_difference(delta: F, plan: SolvePlan) -> F:
    """Input differences, angles the shorter way round (q and q ± 2π are one pose): an angle
    beyond ±π less the nearest whole turns, one within left as it is."""
    out = delta.copy()
    for i, kind in enumerate(plan.input_kinds):
        if kind == "angle":
            d = out[i]
            far = np.abs(d) > np.pi
            if far.any():
                d[far] -= 2 * np.pi * np.round(d[far] / (2 * np.pi))
    return out


def _positions_only(full: Chunk, samples: np.ndarray | slice, q: F) -> Chunk:
    """A chunk of ``full``'s samples (copies when ``samples`` picks some) for position passes
    (which read no rates: the positions stand in for them, as in `_positions_at`)."""
    zero = np.zeros_like(q)
    x = _at(full.x, samples)
    return Chunk(
        x,
        x,
        x,
        q,
        zero,
        zero,
        _at(full.trans, samples),
        full.status[samples],
        full.failed[samples],
        full.close_tol,
        full.singular_tol,
    )


def _at(arr: F, samples: np.ndarray | slice) -> F:
    """``arr``'s samples (the last axis): a view for a slice, else a copy that keeps the batch
    axis last in memory, as the kernels want it (a fancy index would put it first). The copy
    reads the samples alone (``np.take`` of a block's view would first copy the whole block)."""
    if isinstance(samples, slice):
        return arr[..., samples]
    out = np.empty((*arr.shape[:-1], samples.size), dtype=arr.dtype)
    out[...] = arr[..., samples]
    return out


#: most rungs of a sweep's ladder: a longer sweep spaces them more widely
MAX_RUNGS = 4000
#: each finer ladder divides the spacing of the one before by this
FINER = 8


def _continue_along_sweep(
    plan: SolvePlan,
    start: tuple[F, F],
    full: Chunk,
    steps: F,
    chunk: int,
    workers: int | None,
    kernel: Kernel | None = None,
) -> None:
    """Every sample by continuation along the sweep from the sample nearest ``start``
    (positions (n_points, 2) and inputs (n_inputs,): the sketch, or the block before's last).

    A ladder of the sweep's own samples, one stage apart along its path (the inputs' moves
    added up in stages, both ways from that sample), is solved rung by rung, each from the one
    before: the sequential part of the continuation is as long as the sweep is in stages, not
    in samples. Finer ladders (an eighth of a stage, then a sixty-fourth, while they hold few
    samples) are then solved all at once, each sample from the nearest solved one behind it on
    the sweep (towards the sketch's sample); then every sample, by chunks, from the nearest
    solved one behind it or from itself. A sample so starts at most a stage (beyond any jump
    of the sweep's own) from where it is solved, and mostly far nearer: Newton needs fewer
    passes.
    """
    q = full.q
    valid = np.flatnonzero(np.isfinite(q).all(axis=0))
    if not valid.size:  # no sample to reach (every input refused): no positions either
        full.x[:] = np.nan
        return
    q_valid = q if valid.size == q.shape[1] else q[:, valid]  # (a view, when all are)
    q0 = start[1].reshape(-1, 1).copy()
    far = np.abs(wrapped_difference(q_valid - q0, plan)) / steps
    k0 = int(np.argmin(far.max(axis=0) if far.shape[0] > 1 else far[0]))  # among the valid
    # the sketch → that sample, then its ladder's rungs either way along the sweep
    mini = _positions_only(full, valid[[k0]], q0.copy())
    mini.x[:] = start[0][:, :, None]
    mini.status[:] = 0
    leg = wrapped_difference(q[:, valid[[k0]]] - q0, plan)
    first = max(int(np.ceil(np.nanmax(np.abs(leg) / steps))), 1)
    first_plan = take(plan, valid[[k0]])
    for k in range(1, first + 1):
        mini.q = q0 + leg * (k / first)
        _positions(first_plan, mini, kernel)
    walked = np.concatenate([[0.0], np.cumsum(_moves(np.diff(q_valid, axis=1), plan, steps))])
    span = max(walked[-1] - walked[k0], walked[k0] - walked[0])
    h = max(1.0, span / MAX_RUNGS)
    ahead, behind = _rungs(walked, k0, h)
    rungs = np.concatenate([[k0], ahead, behind])
    at = np.empty((*full.x.shape[:2], rungs.size))  # each rung's solved positions
    at[:, :, 0] = mini.x[:, :, 0]
    _climb(plan, full, valid[rungs], ahead.size, at, kernel)
    order = np.argsort(rungs)
    solved, at = rungs[order], at[:, :, order]  # sorted along the sweep
    # finer ladders, each all at once from the solved samples behind it, while they are few
    while (walked[-1] - walked[0]) * FINER / h <= valid.size / FINER:
        h /= FINER
        found = np.sort(np.concatenate(_rungs(walked, k0, h)))
        new = found[~_among(found, solved)]
        if not new.size:
            break
        behind = at[:, :, _behind(solved, new, k0)]
        x = _from_solved(plan, full, valid[new], behind, chunk, workers, kernel)
        solved = np.concatenate([solved, new])
        order = np.argsort(solved)
        solved, at = solved[order], np.concatenate([at, x], axis=2)[:, :, order]
    # every sample from the nearest solved one behind it (or itself), by chunks, in place
    idx = np.zeros(q.shape[1], dtype=np.intp)  # a sample not valid fails by its own input
    idx[valid] = _behind_each(solved, valid.size, k0)

    # only the groups' points start from there: every other point is solved in the pass
    pts = sorted({p for _, st in of_kind(plan.steps, NewtonGroup) for p in st.points})
    at = np.ascontiguousarray(at[pts])  # (each point's rows read in turn, below)

    at_samples = _taker(plan)

    def one(s: int) -> None:
        part = slice(s, min(s + chunk, q.shape[1]))
        c = _positions_only(full, part, q[:, part])
        behind = idx[part]
        for j, p in enumerate(pts):  # (a fancy index's gather into a view: 3× slower)
            np.take(at[j], behind, axis=1, out=c.x[p], mode="clip")
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            _positions(at_samples(part), c, kernel)

    chunk = even(q.shape[1], chunk)  # (a block's samples in chunks of one size)
    over_chunks(q.shape[1], chunk, workers, one)


def _taker(plan: SolvePlan) -> Callable[[slice | np.ndarray], SolvePlan]:
    """``take(plan, ·)``, or the plan itself where no constant is per sample (one design):
    `take` asks every step, ≈ 30 µs a call, and a continuation takes hundreds of parts."""
    if compiled_plan.per_sample(plan):
        return functools.partial(take, plan)
    return lambda _: plan


def _positions(plan: SolvePlan, c: Chunk, kernel: Kernel | None) -> None:
    """Every step at order 0 over a chunk (a Newton group from its positions in ``c.x``):
    with the compiled positions kernel where there is one, else in NumPy."""
    if kernel is None:
        run_steps(plan, c, 0)
    else:
        compiled_newton.run_positions(kernel, plan, c)


def _rungs(walked: F, k0: int, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Rungs a spacing ``h`` apart along a sweep, as indices into it: those after ``k0`` and
    those before, each in order away from it (``k0`` itself is not listed).

    ``walked`` is the sweep's path length in stages at each sample. A rung is the last sample
    within ``h`` of the previous rung (or the next sample, if the sweep itself jumps further),
    so a sample lies at most ``h``, beyond any jump of the sweep's own, past the last rung
    before it.
    """
    n = walked.size
    up = walked[k0] + h * np.arange(1, int(np.ceil((walked[-1] - walked[k0]) / h)) + 1)
    ahead = _distinct(np.clip(np.searchsorted(walked, up, side="right") - 1, k0, n - 1))
    down = walked[k0] - h * np.arange(1, int(np.ceil((walked[k0] - walked[0]) / h)) + 1)
    behind = _distinct(np.clip(np.searchsorted(walked, down, side="left"), 0, k0))
    return ahead[ahead > k0], behind[behind < k0]


def _distinct(ordered: np.ndarray) -> np.ndarray:
    """The distinct values of an ordered array, in its order (``np.unique`` sorts again)."""
    keep = np.ones(ordered.size, dtype=bool)
    keep[1:] = ordered[1:] != ordered[:-1]
    return ordered[keep]


def _among(values: np.ndarray, ordered: np.ndarray) -> np.ndarray:
    """Which of ``values`` are in ``ordered`` (ascending, not empty)."""
    at = np.minimum(np.searchsorted(ordered, values), ordered.size - 1)
    return ordered[at] == values  # type: ignore[no-any-return]


def _moves(delta: F, plan: SolvePlan, steps: F) -> F:
    """Each step of a sweep in stages: its largest input move over that input's stage size,
    angles the shorter way round (q and q ± 2π are one pose)."""
    moves = np.empty_like(delta)
    for i, kind in enumerate(plan.input_kinds):
        d = delta[i]
        if kind == "angle":
            d = d - 2 * np.pi * np.round(d / (2 * np.pi))
        moves[i] = np.abs(d) / steps[i, 0]
    return moves.max(axis=0) if moves.shape[0] > 1 else moves[0]  # type: ignore[no-any-return]


def _behind(solved: np.ndarray, idx: np.ndarray, k0: int) -> np.ndarray:
    """For each sample of ``idx``, the position in ``solved`` (sorted, holding ``k0``) of the
    nearest solved sample between it and ``k0`` (itself, if solved)."""
    up = np.searchsorted(solved, idx, side="right") - 1  # the last solved ≤ i
    down = np.searchsorted(solved, idx, side="left")  # the first solved ≥ i
    return np.where(idx >= k0, up, down)


def _behind_each(solved: np.ndarray, n: int, k0: int) -> np.ndarray:
    """`_behind` for every sample 0 … n − 1, by counting the solved samples up to each."""
    mark = np.zeros(n, dtype=np.intp)
    mark[solved] = 1
    up: np.ndarray = np.cumsum(mark) - 1  # the last solved ≤ i
    out: np.ndarray = up + (mark == 0)  # the first solved ≥ i
    out[k0:] = up[k0:]
    return out


def _from_solved(
    plan: SolvePlan,
    full: Chunk,
    samples: np.ndarray,
    start: F,
    chunk: int,
    workers: int | None,
    kernel: Kernel | None = None,
) -> F:
    """The positions of ``samples``, each solved from its column of ``start`` (the solution
    of a sample behind it), by chunks; the samples' statuses are left as they are."""
    out = np.empty_like(start)
    at_samples = _taker(plan)

    def one(s: int) -> None:
        part = slice(s, min(s + chunk, samples.size))
        c = _positions_only(full, samples[part], _at(full.q, samples[part]))
        c.x[:] = start[:, :, part]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            _positions(at_samples(samples[part]), c, kernel)
        out[:, :, part] = c.x

    over_chunks(samples.size, chunk, workers, one)
    return out


def _climb(
    plan: SolvePlan,
    full: Chunk,
    rungs: np.ndarray,
    n_ahead: int,
    at: F,
    kernel: Kernel | None = None,
) -> None:
    """Solve the ladder's rungs (``rungs``: the sketch's sample, those ahead, those behind),
    each from the one before it, both ways at once: ``at[:, :, i]`` is rung i's solution,
    filled in from ``at[:, :, 0]``."""
    ahead = list(range(1, 1 + n_ahead))
    behind = list(range(1 + n_ahead, len(rungs)))
    at_samples = _taker(plan)
    for r in range(max(len(ahead), len(behind))):
        here = [side[r] for side in (ahead, behind) if r < len(side)]
        prev = [side[r - 1] if r else 0 for side in (ahead, behind) if r < len(side)]
        samples = rungs[here]
        c = _positions_only(full, samples, _at(full.q, samples))
        c.x[:] = at[:, :, prev]
        c.status[:] = 0
        _positions(at_samples(samples), c, kernel)
        at[:, :, here] = c.x


def _continue_from_sketch(
    plan: SolvePlan,
    assembly: Assembly,
    full: Chunk,
    steps: F,
    samples: np.ndarray,
    long_way: bool,
    chunk: int,
    workers: int | None,
    kernel: Kernel | None = None,
) -> None:
    """Samples the sweep could not reach: straight from the sketch, the shorter way round (or
    the longer, past what the shorter way could not pass), by chunks of them."""
    q0 = np.asarray(plan.input_sketch, dtype=np.float64)[:, None]
    target = _at(full.q, samples)
    delta = wrapped_difference(target - q0, plan)
    if long_way:
        for i, kind in enumerate(plan.input_kinds):
            if kind == "angle":
                delta[i] -= 2 * np.pi * np.sign(delta[i])
    stages = int(min(max(np.ceil(np.nanmax(np.abs(delta) / steps)), 1), 400))
    at_samples = _taker(plan)

    def one(s: int) -> None:
        part = slice(s, min(s + chunk, samples.size))
        these = samples[part]
        c = _positions_only(full, these, q0.copy())
        c.x[:] = assembly.positions[:, :, None]
        c.status[:] = 0
        c.failed[:] = -1
        here = at_samples(these)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            for k in range(1, stages + 1):
                c.q = q0 + delta[:, part] * (k / stages)
                _positions(here, c, kernel)
            c.q = target[:, part]
            _positions(here, c, kernel)
        full.x[:, :, these] = c.x
        full.status[these] = c.status
        full.failed[these] = c.failed

    over_chunks(samples.size, chunk, workers, one)


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
