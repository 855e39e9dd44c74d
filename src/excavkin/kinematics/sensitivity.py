"""Exact design sensitivities: the derivative of every result column with respect to a model's
dimensions, by forward-mode differentiation through the plan.

The plan's constants are recomputed from the parameters as dual numbers
(`excavkin.kinematics.dual`), each carrying a unit tangent for its own parameter, and the
same closed-form kernels run on them: the tangents that come out are the derivatives of the
closed forms — of positions, velocities, accelerations, transmission angles, body and driver
quantities — to round-off, never difference quotients. A driver held at its sketch value moves
with the dimensions that set that value, and its derivative says so.

The derivatives of the rows whose values are not solved (their status says why) are NaN. Near a
dead position the derivatives lose precision as the values do (see
`excavkin.kinematics.precision`). A Newton group's derivatives come from the implicit
function theorem at its solved values: J·dx = −dΦ, and likewise for the rates.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from excavkin import backends
from excavkin.arrays import FloatArray as F
from excavkin.backends import Job, Kernel
from excavkin.execution import DEFAULT, Execution
from excavkin.kinematics import compiled as compiled_plan
from excavkin.kinematics import compiled_tangents, newton
from excavkin.kinematics.dual import Dual, seed, zeros
from excavkin.kinematics.kernels import Chunk
from excavkin.kinematics.result import Derived, KinematicResult, Status
from excavkin.kinematics.steps import run_steps
from excavkin.step_kinds import kind_of
from excavkin.structure.design import joint_offsets, parameters, take, vary
from excavkin.structure.plan import SolvePlan

#: samples per pass (the tangents multiply the memory of a pass by the parameter count)
CHUNK = 16384


def solve_tangents(
    result: KinematicResult,
    names: Sequence[str],
    values: Mapping[str, Any] | None = None,
    execution: Execution = DEFAULT,
    columns: Sequence[str] | None = None,
) -> dict[str, KinematicResult]:
    """For each parameter in ``names``, a result whose columns are the derivatives of
    ``result``'s columns with respect to it (SI per SI unit).

    Parameters
    ----------
    result : KinematicResult
        A solve of the nominal model or of a family of designs (``params=``).
    names : sequence of str
        Parameters of [`parameters`][excavkin.structure.design.parameters].
    values : mapping, optional
        The parameters given per sample (``result.parameters``); the rest are nominal.
    execution : Execution
        Its backend differentiates a closed-form plan in its compiled loop
        (`excavkin.kinematics.compiled_tangents`) or in NumPy, chosen by the rule of
        every workload (`excavkin.backends.choose`), with a kernel of its own; its
        ``workers`` run the compiled loop's chunks.
    columns : sequence of str, optional
        Only these columns' derivatives are needed: the compiled loop then writes (and
        computes) no others; the result must say so (``tangent_columns``), since theirs are
        left 0. The NumPy path computes all of them anyway.
    """
    plan = result.plan
    known = {**parameters(plan.model), **joint_offsets(plan.model)}
    for name in names:
        if name not in known:
            from excavkin.errors import unknown_name

            raise unknown_name("parameter", name, list(known))
    n, m = len(result), len(names)
    given = dict(values or {})
    base = {**{k: known[k] for k in names}, **{k: v for k, v in given.items() if k in names}}
    q = np.moveaxis(result.inputs, 0, -1)
    qd = np.moveaxis(result.input_rates, 0, -1)
    qdd = np.moveaxis(result.input_accels, 0, -1)
    keep = None if columns is None else compiled_tangents.entries(result, columns)
    out = _Tangents(plan, n, m)

    def compiled(kernel: Kernel, workers: int | None = execution.workers) -> None:
        compiled_tangents.fill(
            out, plan, (q, qd, qdd), list(names), given, base, workers, keep, kernel
        )

    source = functools.cache(lambda: compiled_tangents.source(plan, keep))  # asked twice
    job = Job(
        "tangents",
        source,
        numpy=lambda: _numpy_tangents(out, plan, (q, qd, qdd), names, given, base, result),
        compiled=compiled,
        unsupported=compiled_tangents.unsupported(plan),
        unasked=compiled_plan.size(plan) <= compiled_plan.AUTO_POINTS,
        scalar=source,  # (a plain loop already)
        device=lambda kernel: compiled(kernel, 1),  # the chunks one after another
    )
    backends.choose(execution.backend, job, n).run(job)
    return out.results(result, names)


def _numpy_tangents(
    out: _Tangents,
    plan: SolvePlan,
    inputs: tuple[F, F, F],
    names: Sequence[str],
    given: dict[str, Any],
    base: dict[str, Any],
    result: KinematicResult,
) -> None:
    """The tangents on dual numbers, chunk by chunk, into ``out``."""
    q, qd, qdd = inputs
    n, m = q.shape[1], len(names)
    duals: dict[str, Any] = {**given, **seed(base, list(names), n)}
    dual_plan, held, _ = vary(plan, duals)
    q_dual = _inputs(plan, q, held, m)
    solved = (
        np.moveaxis(result.positions, 0, -1),
        np.moveaxis(result.velocities, 0, -1),
        np.moveaxis(result.accelerations, 0, -1),
    )
    for s in range(0, n, CHUNK):
        part = slice(s, min(s + CHUNK, n))
        here = tuple(arr[..., part] for arr in solved)
        out.solve(take(dual_plan, part), q_dual[:, part], qd[:, part], qdd[:, part], part, here)


def _run_steps(plan: SolvePlan, c: Chunk, values: tuple[F, ...]) -> None:
    """The plan's steps on dual numbers: the closed-form kernels as they are, and each Newton
    group by the implicit function theorem at the values already solved."""
    for st in plan.steps:
        if kind_of(st).iterative:
            newton.tangents(c, st, values)  # type: ignore[arg-type]
        else:
            run_steps(dataclasses.replace(plan, steps=(st,)), c, 2)


def _inputs(plan: SolvePlan, q: F, held: list[Any], m: int) -> Dual:
    """The inputs as duals: a driver held at its sketch value carries that value's tangent
    (where the sketch value does not vary, and for every swept driver, the tangent is 0)."""
    n = q.shape[1]
    tan = np.zeros((m, *q.shape))
    for i, h in enumerate(held):
        if isinstance(h, Dual):
            at_sketch = q[i] == np.broadcast_to(h.val, (n,))
            tan[:, i] = np.where(at_sketch, np.broadcast_to(h.tan, (m, n)), 0.0)
    return Dual(q, tan)


class _Tangents:
    """The tangent arrays of a whole solve, filled chunk by chunk."""

    def __init__(self, plan: SolvePlan, n: int, m: int) -> None:
        npts = len(plan.points)
        self.plan = plan
        self.m = m
        # zeros (pages the system maps only once written): every sample is written by its
        # chunk but for derivatives that are 0 throughout (the unsolved ones NaN afterwards)
        self.x = np.zeros((m, npts, 2, n))
        self.v = np.zeros(self.x.shape)
        self.a = np.zeros(self.x.shape)
        self.q = np.zeros((m, len(plan.inputs), n))
        self.trans = np.zeros((m, len(plan.transmissions), n))
        self.body = np.zeros((m, 3, len(plan.bodies), n))
        self.element = np.zeros((m, 6, len(plan.elements), n))

    def solve(
        self, plan: SolvePlan, q: Dual, qd: F, qdd: F, part: slice, values: tuple[F, ...]
    ) -> None:
        m = self.m
        k = qd.shape[1]
        npts = len(plan.points)
        c = Chunk(
            zeros((npts, 2, k), m),  # type: ignore[arg-type]
            zeros((npts, 2, k), m),  # type: ignore[arg-type]
            zeros((npts, 2, k), m),  # type: ignore[arg-type]
            q,  # type: ignore[arg-type]
            qd,
            qdd,
            zeros((len(plan.transmissions), k), m),  # type: ignore[arg-type]
            np.zeros(k, dtype=np.int8),
            np.full(k, -1, dtype=np.int16),
            1e-10,
            1e-7,
        )
        derived = Derived(
            zeros((3, len(plan.bodies), k), m),  # type: ignore[arg-type]
            zeros((6, len(plan.elements), k), m),  # type: ignore[arg-type]
        )
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            _run_steps(plan, c, values)
            derived.fill(plan, c.x, c.v, c.a, slice(None))
        self.x[..., part] = c.x.tan  # type: ignore[attr-defined]
        self.v[..., part] = c.v.tan  # type: ignore[attr-defined]
        self.a[..., part] = c.a.tan  # type: ignore[attr-defined]
        self.q[..., part] = q.tan
        self.trans[..., part] = c.trans.tan  # type: ignore[attr-defined]
        self.body[..., part] = derived.body.tan  # type: ignore[attr-defined]
        self.element[..., part] = derived.element.tan  # type: ignore[attr-defined]

    def results(self, result: KinematicResult, names: Sequence[str]) -> dict[str, KinematicResult]:
        """One result of derivatives per parameter, NaN where ``result`` did not solve."""
        bad = ~result.status.solved
        if not bad.any():  # nothing to mark: no pass over the (large) tangent arrays
            bad = slice(0, 0)  # type: ignore[assignment]
        out = {}
        zero = np.zeros_like(self.q[0])
        for j, name in enumerate(names):
            arrays = [self.x[j], self.v[j], self.a[j]]
            for arr in arrays:
                arr[..., bad] = np.nan
            derived = Derived(self.body[j], self.element[j])
            derived.body[..., bad] = np.nan
            derived.body[:, self.plan.ground] = 0.0
            derived.element[..., bad] = np.nan
            self.trans[j][..., bad] = np.nan
            st = result.status
            status = Status(st.code, st.step, self.plan, st.unmet, st.miss)
            x, v, a = arrays
            out[name] = KinematicResult.build(
                self.plan, x, v, a, self.q[j], zero, zero, self.trans[j], derived, status
            )
        return out
