"""Joint forces and driver efforts for a kinematic result: loads + inertia → equilibrium.

For each cache-sized chunk of samples: the known load of every moving body (its applied forces
and couples, its weight and its d'Alembert inertia, reduced to a force and a moment about the
body's first point), then the back-substitution along the solve plan of
`excavkin.kinetostatics.structured` (linear in the model's size), in NumPy or compiled as one
machine-code loop (`excavkin.kinetostatics.compiled`; in NumPy for a model with cams). Each
gear pair's radial tooth force is added afterwards (`excavkin.kinetostatics.gears`). A model
whose gear pairs, racks or cams the plan cannot take
(`excavkin.kinetostatics.structured.along_plan`) is solved with the whole matrix per sample
(LAPACK). Samples whose kinematics failed stay NaN.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from excavkin import backends
from excavkin.arrays import FloatArray as F
from excavkin.backends import Job, Kernel
from excavkin.errors import InputError
from excavkin.execution import Execution, settings
from excavkin.kinematics.compiled import AUTO_POINTS, PIECES_PER_POINT, too_large
from excavkin.kinematics.result import KinematicResult
from excavkin.kinematics.split import split
from excavkin.kinetostatics.body_loads import body_loads
from excavkin.kinetostatics.equilibrium import (
    StaticsSystem,
    compile_statics,
    dense_matrix,
)
from excavkin.kinetostatics.gears import add_radial, mesh_forces, pitch_fractions, with_pitch
from excavkin.kinetostatics.inertia import MassProperties
from excavkin.kinetostatics.loads import EvaluatedLoads, Load, check_loads, evaluate_loads
from excavkin.kinetostatics.result import ForceResult
from excavkin.kinetostatics.structured import (
    StructuredSystem,
    along_plan,
    solve_structured,
)
from excavkin.structure.design import expand
from excavkin.structure.plan import SolvePlan

__all__ = ["solve_forces"]


def solve_forces(
    result: KinematicResult,
    loads: Iterable[Load] = (),
    *,
    system: StaticsSystem | None = None,
    inertia: bool = True,
    method: str = "sparse",
    chunk: int = 8192,
    execution: Execution | None = None,
    backend: str | None = None,
    compiled: bool | None = None,
) -> ForceResult:
    """Joint forces, linear-driver forces and rotary-driver torques for every sample.

    Parameters
    ----------
    result : KinematicResult
        n samples of the mechanism's motion.
    loads : iterable of PointForce, Torque, Gravity
        Applied loads (the model's own are not added: see
        `model_loads`).
    system : StaticsSystem, optional
        From `compile_statics` on the result's model
        (compiled here if not given).
    inertia : bool
        Include the d'Alembert inertia loads (default); ``False`` solves statics at each pose.
    method : {"sparse", "dense"}
        ``"sparse"``: the back-substitution along the solve plan (fast, linear in the model's
        size). ``"dense"``: the full matrix per sample with LAPACK (slow; for
        cross-checking).
    chunk : int
        Samples per pass (memory beyond the result's arrays is bounded by a pass).
    execution : Execution, optional
        Its backend runs the ``"sparse"`` back-substitution as one compiled loop over samples
        (`excavkin.kinetostatics.compiled`) or in NumPy, by the rule of every workload
        (`excavkin.backends.choose`); its ``workers`` run the compiled loop's chunks.
    backend : {"auto", "numpy", "numba", "cuda"}, optional
        Replaces ``execution``'s backend.
    compiled : bool, optional
        Deprecated: ``backend="numba"`` (True) or ``"numpy"`` (False).

    Returns
    -------
    ForceResult
        Arrays with the batch axis first; NaN where the kinematics failed or the equilibrium is
        singular.

    Raises
    ------
    ModelError
        A load names an unknown body or point.
    InputError
        A load value of the wrong shape, or a bad ``method`` or ``chunk``.
    StaticallyIndeterminateError
        Redundant joints (from compiling the system).
    """
    if method not in ("sparse", "dense"):
        raise InputError(f"method must be 'sparse' or 'dense', not {method!r}")
    if chunk < 1:
        raise InputError(f"chunk must be at least 1, got {chunk}")
    execution = settings(execution, backend=backend, compiled=compiled)
    plan = result.plan
    model = plan.model
    checked = check_loads(model, loads)
    sy = system if system is not None else compile_statics(model)
    mp = MassProperties.of(result)
    ev = evaluate_loads(model, checked, result)
    n = len(result)
    x = np.moveaxis(result.positions, 0, -1)
    a = np.moveaxis(result.accelerations, 0, -1) if inertia else None
    eps = np.moveaxis(result.body_epsilon, 0, -1) if inertia else None
    out = np.empty((sy.size, n))
    singular = np.zeros(n, dtype=bool)
    lam = pitch_fractions(model, expand(model, result.parameters or {}))
    with np.errstate(divide="ignore", invalid="ignore"):
        _solve_by_method(
            plan, (sy, mp, ev), (x, a, eps), (out, singular), lam, method, chunk, execution
        )
    add_radial(sy, x, out)
    # a row whose rates lose precision near a dead position keeps its forces (its status says
    # how far to trust them)
    bad = singular | ~result.status.solved
    if bad.any():
        out[:, bad] = np.nan
    singular &= result.status.solved
    return _force_result(result, sy, (out, singular), checked, ev, mp)


def _force_result(
    result: KinematicResult,
    sy: StaticsSystem,
    solved: tuple[F, np.ndarray],
    checked: tuple[Load, ...],
    ev: EvaluatedLoads,
    mp: MassProperties,
) -> ForceResult:
    """The solved unknowns (one row an unknown, a column a sample) as a `ForceResult`."""
    out, singular = solved
    n = out.shape[1]
    ns = len(sy.slots)
    e0, s0, t0, r0 = sy.element_col0, sy.slider_col0, sy.torque_col0, sy.rope_col0
    gears, racks, cams = mesh_forces(sy, out)
    return ForceResult(
        kinematics=result,
        system=sy,
        pin_force=np.moveaxis(out[: 2 * ns].reshape(ns, 2, n), -1, 0),
        element_force=out[e0:s0].T,
        slider_force=out[s0:t0].T,
        driver_torque=out[t0:r0].T,
        gear_force=gears,
        rack_force=racks,
        cam_force=cams,
        singular=singular,
        loads=checked,
        evaluated=ev,
        mass=mp,
        rope_tension=out[r0 : sy.gear_col0].T,
    )


def _solve_by_method(
    plan: SolvePlan,
    known: tuple[StaticsSystem, MassProperties, EvaluatedLoads],
    motion: tuple[F, F | None, F | None],
    into: tuple[F, np.ndarray],
    lam: Mapping[tuple[str, int], Any],
    method: str,
    chunk: int,
    execution: Execution,
) -> None:
    """Fill ``out`` and ``singular`` by the method asked: along the plan (on the backend
    chosen), or with the whole matrix — for a method ``"dense"``, for meshes the plan cannot
    take, and per chunk where gear ratios vary by design (``lam``: each chunk's pitch points)."""
    sy, mp, ev = known
    x, a, eps = motion
    out, singular = into
    n = out.shape[1]
    if lam:  # gear ratios per design: each chunk's pitch points, in NumPy
        for s in range(0, n, chunk):
            part = slice(s, min(s + chunk, n))
            own = with_pitch(sy, lam, part)
            structured_part = None if method == "dense" else along_plan(plan, own)
            if structured_part is None:
                _solve_dense(own, mp, ev, (x, a, eps), out, singular, part, fast=True)
                continue
            _solve_sparse((structured_part, mp, ev), (x, a, eps), out, singular, chunk, part)
    elif method == "dense":
        _solve_dense(sy, mp, ev, (x, a, eps), out, singular, slice(None))
    elif (structured := along_plan(plan, sy)) is None:  # meshes the plan cannot take
        for s in range(0, n, chunk):
            part = slice(s, min(s + chunk, n))
            _solve_dense(sy, mp, ev, (x, a, eps), out, singular, part, fast=True)
    else:
        _solve_chosen((structured, mp, ev), (x, a, eps), out, singular, chunk, execution)


def _solve_sparse(
    known: tuple[StructuredSystem, MassProperties, EvaluatedLoads],
    motion: tuple[F, F | None, F | None],
    out: F,
    singular: np.ndarray,
    chunk: int,
    samples: slice | None = None,
) -> None:
    """The back-substitution along the plan in NumPy, chunk by chunk (of ``samples``: all of
    them unless given)."""
    structured, mp, ev = known
    sy = structured.system
    x, a, eps = motion
    lo, hi, _ = (samples or slice(None)).indices(out.shape[1])
    for s in range(lo, hi, chunk):
        sl = slice(s, min(s + chunk, hi))
        xc = np.ascontiguousarray(x[:, :, sl])
        rhs = body_loads(
            sy,
            mp.at(sl),
            ev,
            xc,
            None if a is None else a[:, :, sl],
            None if eps is None else eps[:, sl],
            sl,
        )
        out[:, sl], singular[sl] = solve_structured(structured, xc, rhs)


def _solve_chosen(
    known: tuple[StructuredSystem, MassProperties, EvaluatedLoads],
    motion: tuple[F, F | None, F | None],
    out: F,
    singular: np.ndarray,
    chunk: int,
    execution: Execution,
) -> None:
    """The back-substitution on the backend chosen for it (`excavkin.backends.choose`):
    its compiled kernel, or NumPy chunk by chunk. A model of more than
    `excavkin.kinematics.compiled.AUTO_POINTS` points (its cams' table pieces counted, as
    `excavkin.kinematics.compiled.size` counts them) is never compiled unasked (numba's
    compile grows with it), and under ``"auto"`` it is not traced either."""
    from excavkin.kinetostatics import compiled as kernel

    x, a, eps = motion
    traced: list[tuple[str, list[float | F]]] = []

    def source() -> str:  # traced once, and only if a compiled backend asks
        if not traced:
            traced.append(kernel.source(*known, inertia=a is not None))
        return traced[0][0]

    def compiled(k: Kernel, workers: int | None = execution.workers) -> None:
        source()
        kernel.solve(k, traced[0][1], x, a, eps, out, singular, workers)

    sy = known[0].system
    pieces = sum(max(len(getattr(cm.law, "knots", ())) - 1, 0) for cm in sy.cams)
    points = len(sy.points) + -(-pieces // PIECES_PER_POINT)
    big = points > AUTO_POINTS
    if big and execution.backend == "auto":
        _solve_sparse(known, motion, out, singular, chunk)
        return
    job = Job(
        "forces",
        lambda: split(source()),  # a large model's kernel in passes compiled one by one
        numpy=lambda: _solve_sparse(known, motion, out, singular, chunk),
        compiled=compiled,
        # a cam's lift law given as a function cannot be traced
        unsupported=too_large(points)
        if kernel.traceable(known[0].system)
        else "of a model with a cam whose lift law is a function, solved in NumPy",
        unasked=not big,
        scalar=source,  # (a plain loop already)
        device=lambda k: compiled(k, 1),  # the chunks one after another
    )
    backends.choose(execution.backend, job, out.shape[1]).run(job)


def _solve_dense(
    sy: StaticsSystem,
    mp: MassProperties,
    ev: EvaluatedLoads,
    motion: tuple[F, F | None, F | None],
    out: F,
    singular: np.ndarray,
    sl: slice,
    *,
    fast: bool = False,
) -> None:
    """The whole matrix per sample with LAPACK, for the samples ``sl``; a sample is singular
    where the matrix's condition number is 1e12 or more (2-norm, by SVD; ``fast``: 1-norm, from
    the LU inverse, a quarter of the time)."""
    x, a, eps = (None if v is None else v[..., sl] for v in motion)
    assert x is not None
    n = x.shape[-1]
    mat = dense_matrix(sy, x)
    rhs = np.zeros((n, len(sy.rows)))
    r0 = 2 * len(sy.nodes)
    for m, (fx, fy, mz) in enumerate(body_loads(sy, mp.at(sl), ev, x, a, eps, sl)):
        rhs[:, r0 + 3 * m] = -np.asarray(fx)
        rhs[:, r0 + 3 * m + 1] = -np.asarray(fy)
        rhs[:, r0 + 3 * m + 2] = -np.asarray(mz)
    finite = np.isfinite(mat).all(axis=(1, 2)) & np.isfinite(rhs).all(axis=1)
    cond = np.full(n, np.inf)
    if finite.any():
        cond[finite] = _condition_1(mat[finite]) if fast else np.linalg.cond(mat[finite])
    good = cond < 1e12
    singular[sl] |= finite & ~good
    part = np.full((out.shape[0], n), np.nan)
    if good.any():
        part[:, good] = np.linalg.solve(mat[good], rhs[good][:, :, None])[:, :, 0].T
    out[:, sl] = part


def _condition_1(mat: F) -> F:
    """Each matrix's 1-norm condition number, ``‖A‖₁·‖A⁻¹‖₁`` (by SVD, the 2-norm's, where
    one of them is exactly singular: LAPACK's inverse refuses the whole batch)."""
    try:
        inv = np.linalg.inv(mat)
    except np.linalg.LinAlgError:
        return np.asarray(np.linalg.cond(mat))
    norm_a = np.abs(mat).sum(axis=-2).max(axis=-1)
    norm_inv = np.abs(inv).sum(axis=-2).max(axis=-1)
    return np.asarray(norm_a * norm_inv)
