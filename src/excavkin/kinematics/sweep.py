"""A sweep solved whole or part by part, to the same numbers.

A sweep too large for memory is solved in parts of consecutive samples, each handing the next
what it needs (`Carry`): the last few samples, for the change
points between the two, and the last sample a Newton group reached. What a sample's result
depends on beyond its own inputs is defined over its block of
`BLOCK` samples, so a sweep solved whole is the same as the
sweep solved in parts of whole blocks: the in-memory solve is one part.

``continuation="smooth"`` needs the whole sweep before it can solve a sample: the side each
dyad takes after a change point is counted from the sample nearest the sketch. It goes over
the parts several times: once to find that sample, once per dyad with change points (each
pass solves with the flips found so far and finds the next dyad's), and once more for the
result.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Collection, Iterable, Iterator
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.execution import DEFAULT, Execution, settings
from excavkin.kinematics.change_points import ChangePoint, Tail, Unit, dyads, find_change_points
from excavkin.kinematics.result import KinematicResult
from excavkin.kinematics.solve import (
    Assembly,
    Carry,
    Tolerances,
    solve_part,
    step_sizes,
    wrapped_difference,
)
from excavkin.step_kinds import kind_of
from excavkin.structure.design import DesignBatch
from excavkin.structure.plan import SolvePlan


@dataclass(frozen=True, slots=True)
class Part:
    """The inputs of consecutive samples of a sweep.

    Attributes
    ----------
    start : int
        The first sample's number in the sweep (a multiple of ``BLOCK``, but for the first).
    q, qd, qdd : ndarray, shape (n_inputs, k)
        Driver values, rates and accelerations, SI.
    plan : SolvePlan
        The plan for these samples (a family of designs' constants taken at them).
    unbuildable : ndarray of bool, shape (k,), optional
        Samples whose design builds no mechanism.
    designs : DesignBatch, optional
        A family of designs made chunk by chunk (closed-form plans).
    """

    start: int
    q: F
    qd: F
    qdd: F
    plan: SolvePlan
    unbuildable: NDArray[np.bool_] | None = None
    designs: DesignBatch | None = None


#: the parts of a sweep, in order; called again for each pass over them
Parts = Callable[[], Iterable[Part]]


def solve_parts(
    plan: SolvePlan,
    assembly: Assembly,
    parts: Parts,
    *,
    total: int,
    tol: Tolerances | None = None,
    execution: Execution = DEFAULT,
    continuation: str = "side",
    columns: Collection[str] | None = None,
) -> Iterator[KinematicResult]:
    """One kinematic result per part, as `solve_kinematics` gives for the whole.

    Parameters
    ----------
    plan : SolvePlan
        The model's plan.
    assembly : Assembly
    parts : callable
        Returns the parts in order (called once per pass).
    total : int
        Samples in the sweep (for ``progress``).
    tol
        As for `solve_kinematics`.
    execution : Execution
        As for `solve_part`; its ``progress(done, total)`` is over the whole sweep.
    continuation : {"side", "smooth"}
    columns : collection of str, optional
        Only these kinematic columns are asked (`solve_part`'s ``columns``: where the
        compiled kernel solves, the results' other rows hold no values); the smooth
        continuation solves every column.

    Yields
    ------
    KinematicResult
        Each part's, its change points numbered in the whole sweep.
    """
    tol = tol or Tolerances()
    if continuation == "smooth":
        yield from _smooth(plan, assembly, parts, total, tol, execution)
        return
    carry = None
    for p in parts():
        result, carry = solve_part(
            p.plan, assembly, p.q, p.qd, p.qdd, tol=tol,
            execution=_shifted(execution, p.start, total), unbuildable=p.unbuildable,
            designs=p.designs, carry=carry or Carry(p.start), columns=columns,
        )  # fmt: skip
        yield result


def solve_kinematics(
    plan: SolvePlan,
    assembly: Assembly,
    q: F,
    qd: F,
    qdd: F,
    *,
    tol: Tolerances | None = None,
    execution: Execution | None = None,
    continuation: str = "side",
    unbuildable: np.ndarray | None = None,
    designs: DesignBatch | None = None,
    backend: str | None = None,
    chunk: int | None = None,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> KinematicResult:
    """Positions, velocities and accelerations of every point for every sample.

    Parameters
    ----------
    plan : SolvePlan
    assembly : Assembly
        From `assemble`.
    q, qd, qdd : ndarray, shape (n_inputs, n)
        Driver values, rates and accelerations, SI, in ``plan.inputs`` order.
    tol : Tolerances, optional
    execution : Execution, optional
        Backend, threads, samples per chunk and progress (`excavkin.execution.Execution`);
        ``progress(done, total)`` is called after each chunk with the samples finished so
        far (serialised, ``done`` increasing, though the calls may come from worker threads).
    continuation : {"side", "smooth"}
        At a change point between neighbouring samples (a dyad folding flat), keep each dyad on
        its sketch side (``"side"``) or continue the motion onto the other side (``"smooth"``:
        the samples are then taken in order, as a path). Either way the result lists the change
        points it found.
    unbuildable : ndarray of bool, shape (n,), optional
        Samples whose design (a plan with per-sample dimensions) builds no mechanism.
    designs : DesignBatch, optional
        A family of designs of ``plan`` (a closed-form one), one per sample: each chunk's
        constants are made as the chunk is solved.
    backend, chunk, workers, progress : optional
        Each replaces its field of ``execution``.

    Returns
    -------
    KinematicResult
    """
    execution = settings(
        execution, backend=backend, chunk=chunk, workers=workers, progress=progress
    )
    whole = Part(0, q, qd, qdd, plan, unbuildable, designs)
    return next(
        iter(
            solve_parts(
                plan,
                assembly,
                lambda: [whole],
                total=q.shape[1],
                tol=tol,
                execution=execution,
                continuation=continuation,
            )  # fmt: skip
        )
    )


def _shifted(execution: Execution, start: int, total: int) -> Execution:
    """The execution of a part: its progress reported as the whole sweep's."""
    progress = execution.progress
    if progress is None:
        return execution
    return dataclasses.replace(execution, progress=lambda done, _: progress(start + done, total))


def _smooth(
    plan: SolvePlan,
    assembly: Assembly,
    parts: Parts,
    total: int,
    tol: Tolerances,
    execution: Execution,
) -> Iterator[KinematicResult]:
    """Solve with each dyad's side flipped after its change points, dyad by dyad in plan
    order (a flip moves what is built on the dyad, and so its later change points). The
    dyads inside a Newton group (`excavkin.structure.group_dyads`) are flipped as dyad
    steps are: the group keeps each on the side so counted."""
    anchor = _anchor(plan, parts)
    flips: dict[Unit, tuple[NDArray[np.int64], NDArray[np.int64]]] = {}
    found: list[ChangePoint] = []
    todo = [unit for unit, _ in dyads(plan)]
    while todo:
        # one pass with the flips found so far: the change points of every dyad not yet
        # flipped; the first that has some is right (no flip came before it), the rest wait
        seen: dict[Unit, list[ChangePoint]] = {k: [] for k in todo}
        carry, tail = None, None
        for p in parts():
            res, carry = solve_part(
                _signed(p.plan, flips, anchor, p.start, p.q.shape[1]), assembly, p.q, p.qd,
                p.qdd, tol=tol, execution=dataclasses.replace(execution, progress=None),
                unbuildable=p.unbuildable, carry=carry or Carry(p.start),
            )  # fmt: skip
            here = (
                np.moveaxis(res.positions, 0, -1),
                np.moveaxis(res.velocities, 0, -1),
                res.inputs.T,
                res.input_rates.T,
                res.transmission.T,
            )
            for k in todo:
                seen[k] += find_change_points(
                    plan, here[0], v=here[1], q=here[2], qd=here[3], offset=p.start, tail=tail,
                    only=k,
                )  # fmt: skip
            tail = Tail.of(*here, before=tail)
        first = next((k for k in todo if seen[k]), None)
        if first is None:
            break
        pairs = np.array([(cp.before, cp.after) for cp in seen[first]], dtype=np.int64).T
        ahead = pairs[0] >= anchor
        # crossing a change point moving away from the anchor: forwards at its later sample,
        # backwards at its earlier one
        flips[first] = (np.unique(pairs[1][ahead]), np.unique(pairs[0][~ahead]))
        found += [dataclasses.replace(cp, continued="smooth") for cp in seen[first]]
        todo = todo[todo.index(first) + 1 :]
    carry = None
    for p in parts():
        k = p.q.shape[1]
        res, carry = solve_part(
            _signed(p.plan, flips, anchor, p.start, k), assembly, p.q, p.qd, p.qdd, tol=tol,
            execution=_shifted(execution, p.start, total), unbuildable=p.unbuildable,
            carry=carry or Carry(p.start),
        )  # fmt: skip
        mine = tuple(cp for cp in found if p.start <= cp.after < p.start + k)
        yield dataclasses.replace(res, change_points=mine)


def _anchor(plan: SolvePlan, parts: Parts) -> int:
    """The sample nearest the sketch (in continuation stages; the first of equals)."""
    q0 = np.asarray(plan.input_sketch, dtype=np.float64)[:, None]
    steps = step_sizes(plan)
    best, anchor = np.inf, 0
    for p in parts():
        far = np.abs(wrapped_difference(p.q - q0, plan)) / steps
        here = np.where(np.isfinite(far).all(axis=0), far.max(axis=0), np.inf)
        k = int(np.argmin(here))
        if here[k] < best:
            best, anchor = float(here[k]), p.start + k
    return anchor


def _signed(
    plan: SolvePlan,
    flips: dict[Unit, tuple[NDArray[np.int64], NDArray[np.int64]]],
    anchor: int,
    start: int,
    n: int,
) -> SolvePlan:
    """The plan for samples ``start`` … ``start + n − 1`` with each flipped dyad's side per
    sample: its sketch side at the anchor, flipped once more by every change point between."""
    if not flips:
        return plan
    steps = list(plan.steps)
    t = np.arange(start, start + n)
    for (k, j), (up, down) in flips.items():
        count = np.searchsorted(up, t, side="right") + (
            down.size - np.searchsorted(down, t, side="left")
        )
        turn = (-1.0) ** count
        st = steps[k]
        steps[k] = kind_of(st).turn(st, j, turn)
    return dataclasses.replace(plan, steps=tuple(steps))
