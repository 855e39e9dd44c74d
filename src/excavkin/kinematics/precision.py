"""Honest precision near dead and change positions.

Near a dead position (a dyad or a slider folding flat, a Newton group's Jacobian nearly
singular) the rates are a ratio of two small numbers, and double precision loses digits as the
triangle flattens: at the MO-100 hammer's change point the rocker's ε computed in double
precision is off by about 1e-2·eps/θ³ (θ the crank angle from the change point).

Every sample that comes within `NEAR` of a dead position (the sine of a transmission
angle, or the Newton Jacobian's determinant over the product of its rows' norms) is solved a
second time, by the same plan, in extended precision (x87's 64-bit significand, 2¹¹ times finer
than double; IEEE quad where ``long double`` is that). The difference measures the double
evaluation's error directly. Where it exceeds `SUBSTITUTE` of a quantity's scale, the
extended values are returned (rounded to double), with an error estimated as that difference
scaled by the ratio of the two precisions and a margin of `MARGIN`. A sample whose
estimate still exceeds `TOLERANCE` is marked ``IMPRECISE`` ("rates lose precision near a
dead position"), so that no row marked ``ok`` is off by more than that.

The scale of a quantity is its largest magnitude over the solved samples checked together —
a block of `BLOCK` samples of the sweep, so that a sweep
solved part by part is judged as the whole is — per kind: lengths (positions and element
lengths), velocities, accelerations, angles, angular velocities and angular accelerations.
"""

from __future__ import annotations

import dataclasses
import functools
import os
import sys
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from excavkin import backends
from excavkin.arrays import FloatArray as F
from excavkin.kinematics.kernels import Chunk, Code
from excavkin.kinematics.result import Derived
from excavkin.kinematics.steps import run_steps
from excavkin.step_kinds import kind_of
from excavkin.structure.design import take
from excavkin.structure.plan import SolvePlan

#: samples nearer a dead position than this (sine of a transmission angle) are checked
NEAR = 0.05
#: a row is ``ok`` only if every value is within this fraction of its quantity's scale
TOLERANCE = 1e-8
#: double values off by more than this fraction of their scale are replaced by extended ones
SUBSTITUTE = 1e-13
#: the wide solve's own error is measured by moving its roundings by this many units
NUDGE = 16.0
#: margin on the wide solve's error so measured
MARGIN = 64.0

#: the wider type, or None where ``long double`` is only double (then a conditioning bound)
WIDE: type | None = np.longdouble if np.finfo(np.longdouble).eps < 1e-18 else None
RATIO = float(np.finfo(WIDE).eps / np.finfo(np.float64).eps) if WIDE is not None else 1.0


@dataclasses.dataclass(slots=True)
class Arrays:
    """The solve's arrays for a set of samples: points (n_points, 2, n) and the rest."""

    x: F
    v: F
    a: F
    trans: F
    derived: Derived


def nearness(plan: SolvePlan, trans: F, newton_near: F | None = None) -> tuple[F, np.ndarray]:
    """How near each sample is to a dead position (0 at one, 1 far from any), and the plan
    step nearest it."""
    n = trans.shape[-1]
    near = np.ones(n)
    step = np.full(n, -1, dtype=np.int16)
    steps_of = {}
    for k, st in enumerate(plan.steps):
        index = kind_of(st).transmission(st)
        if index is not None:
            steps_of[index] = k
    for i in range(trans.shape[0]):
        s = np.abs(np.sin(trans[i]))
        closer = s < near
        near = np.where(closer, s, near)
        step[closer] = steps_of[i]
    if newton_near is not None:
        group = next(k for k, st in enumerate(plan.steps) if kind_of(st).iterative)
        closer = newton_near < near
        near = np.where(closer, newton_near, near)
        step[closer] = group
    return near, step


def check(
    plan: SolvePlan,
    q: F,
    qd: F,
    qdd: F,
    out: Arrays,
    status: np.ndarray,
    failed: np.ndarray,
    nearest: tuple[F, np.ndarray],
    tol: tuple[float, float],
    plan_at: Callable[[NDArray[np.intp]], SolvePlan] | None = None,
) -> F:
    """Check (and where needed improve) the samples near a dead position, in place.

    Returns the estimated error of each row relative to its quantities' scales: NaN where the
    sample was far from any dead position (not checked) or did not solve. ``nearest`` is each
    sample's nearness and nearest step (from `nearness`). ``plan_at`` gives
    the plan of a subset of samples (a family of designs'); default: the plan's own constants
    taken at them.

    Parameters
    ----------
    plan : SolvePlan
        The plan the samples were solved by.
    q, qd, qdd : ndarray, shape (n_inputs, n)
        The inputs and their first and second time derivatives, SI, sample axis last.
    out : Arrays
        The double-precision solution of the n samples (points shape (n_points, 2, n)); where
        the extended solve differs by more than `SUBSTITUTE` of a scale, its values replace
        these.
    status : ndarray of int8, shape (n,)
        Per-sample `Code`; a sample the extended solve fails takes its code, one whose error
        stays above `TOLERANCE` becomes ``IMPRECISE``.
    failed : ndarray of int16, shape (n,)
        Per-sample index of the plan step that failed first (−1 for none), updated alike.
    nearest : tuple of (ndarray, shape (n,), ndarray of int16, shape (n,))
        Each sample's nearness to a dead position (0 at one, 1 far) and the plan step nearest
        it, as `nearness` gives them; samples nearer than `NEAR` are checked.
    tol : tuple of float
        ``(close, singular)``, as in `Tolerances`.
    plan_at : callable, optional
        ``plan_at(index)``: the plan of the samples at ``index`` (ndarray of intp).

    Returns
    -------
    ndarray, shape (n,)
        Estimated error of each checked sample, relative to its quantities' scales; NaN where
        not checked.
    """
    n = status.size
    error = np.full(n, np.nan)
    near, step = nearest
    pick = np.flatnonzero((status == Code.OK) & (near < NEAR))
    if not pick.size:
        return error
    far = status == Code.OK
    far[pick] = False
    if WIDE is None:
        # no wider type: the first-order bound of a ratio of small numbers, cubed for ε
        error[pick] = 64.0 * np.finfo(np.float64).eps / near[pick] ** 3
    else:
        sub = plan_at(pick) if plan_at is not None else take(plan, pick)
        wide = _solve_wide(sub, q, qd, qdd, out, pick, tol)
        ok = wide.status == Code.OK
        # the wide solve's own error: how far it moves when its roundings are emulated by
        # nudges of a few units (two draws of signs, the larger move)
        shaken = [_solve_wide(sub, q, qd, qdd, out, pick, tol, nudge=seed) for seed in (1, 2)]
        # the scales from values believed: the far samples' and the wide solve's, never the
        # double values being judged
        scales = _scales([(out, far), (wide.arrays, ok)])
        diff = _difference(out.x, out, wide.arrays, pick, scales)
        swap = ok & (diff > SUBSTITUTE)
        moved = np.maximum(
            *(_difference(wide.arrays.x, wide.arrays, s.arrays, None, scales) for s in shaken)
        )
        # kept double values: their measured error, plus the wide solve's own and the final
        # rounding; replaced ones: the wide solve's error alone
        wide_error = np.maximum(diff * RATIO, moved / NUDGE) * MARGIN
        error[pick] = np.where(swap, wide_error, diff + wide_error + 4 * np.finfo(np.float64).eps)
        _substitute(out, wide.arrays, pick, swap)
        lost = ~ok
        status[pick[lost]] = wide.status[lost]
        failed[pick[lost]] = wide.failed[lost]
        error[pick[lost]] = np.nan
    bad = pick[error[pick] > TOLERANCE]
    status[bad] = Code.IMPRECISE
    failed[bad] = step[bad]
    return error


def tops(arrays: Arrays, use: np.ndarray) -> dict[str, float]:
    """Each kind's largest magnitude over the samples ``use`` (0 where none), unfloored: a
    block's far samples' share of its scales, as `check` takes it.

    Parameters
    ----------
    arrays : Arrays
        A block's solution.
    use : ndarray of bool, shape (n,)

    Returns
    -------
    dict of str to float
        By kind of quantity (length, velocity, …).
    """
    top = dict.fromkeys(KINDS, 0.0)
    if use.any():
        for kind, group in _groups(arrays).items():
            for arr in group:
                if arr.size:
                    top[kind] = max(top[kind], largest(arr, use))
    return top


def runs_tops(arrays: Arrays, use: np.ndarray, counts: Sequence[int]) -> list[dict[str, float]]:
    """`tops` of consecutive runs of the samples, ``counts[i]`` samples the ``i``-th, all
    at once: the same numbers as `tops` of each run (a largest value is exact in any order),
    a few NumPy calls per kind of quantity instead of some for every run and array.

    Parameters
    ----------
    arrays : Arrays
        The samples' solution (``sum(counts)`` samples), float64 or the wider type.
    use : ndarray of bool, shape (n,)
    counts : sequence of int
        The runs' lengths, in order, adding up to n.

    Returns
    -------
    list of dict of str to float
        One per run, by kind of quantity (0 where none of the run's samples is used).
    """
    out = [dict.fromkeys(KINDS, 0.0) for _ in counts]
    sizes = np.asarray(counts, dtype=np.intp)
    runs = np.flatnonzero(sizes)  # (an empty run has nothing to reduce)
    if not runs.size or not use.any():
        return out
    starts = (np.cumsum(sizes) - sizes)[runs]
    for kind, group in _groups(arrays).items():
        per: F | None = None
        for arr in group:
            if arr.size:
                # each sample's largest over the rows (NaN passed over), in double, as
                # `largest` takes it
                mine = np.fmax.reduce(np.abs(arr), axis=0).astype(np.float64)
                per = mine if per is None else np.fmax(per, mine)
        if per is None:
            continue
        per = np.where(use & ~np.isnan(per), per, 0.0)
        for r, top in zip(runs.tolist(), np.maximum.reduceat(per, starts).tolist(), strict=True):
            out[r][kind] = max(0.0, top)
    return out


def check_picked(
    plan: SolvePlan,
    inputs: tuple[F, F, F],
    out: Arrays,
    nearest: tuple[F, np.ndarray],
    tol: tuple[float, float],
    blocks: Sequence[tuple[int, Mapping[str, float]]],
) -> tuple[F, np.ndarray, np.ndarray]:
    """`check` of the samples picked (ok, and nearer a dead position than `NEAR`) in
    several blocks at once, in place: each block's picks judged against that block's
    scales, as `check` judges them block by block — the same numbers, to the bit, with one
    wide solve (and its two nudged ones) for every block.

    Parameters
    ----------
    plan : SolvePlan
        The plan of the picked samples (one column of constants a sample, or one for all).
    inputs : (ndarray, ndarray, ndarray), each shape (n_inputs, k)
        The picked samples' inputs, rates and accelerations.
    out : Arrays
        Their double-precision solution (k samples), improved in place.
    nearest : (ndarray, ndarray), shape (k,) each
        Their nearness to a dead position and nearest step (`nearness`).
    tol : tuple of float
        ``(close, singular)``.
    blocks : sequence of (int, mapping of str to float)
        Per block, in the picks' order: how many of the samples are its, and its far
        samples' `tops`.

    Returns
    -------
    error : ndarray, shape (k,)
        As `check` gives it (NaN where a wide solve lost the sample).
    status : ndarray of int8, shape (k,)
        0, the wide solve's failure, or ``IMPRECISE``.
    failed : ndarray of int16, shape (k,)
        The failed step (−1 for none).
    """
    q, qd, qdd = inputs
    near, step = nearest
    k = q.shape[1]
    status = np.zeros(k, dtype=np.int8)
    failed = np.full(k, -1, dtype=np.int16)
    if WIDE is None:
        error = 64.0 * np.finfo(np.float64).eps / near**3
    else:
        every = np.arange(k)
        counts = [c for c, _ in blocks]
        wide = _solve_wide(plan, q, qd, qdd, out, every, tol)
        ok = wide.status == Code.OK
        # the two nudged solves as one of both draws' samples in turn (a sample's solve is
        # its own: the same numbers as two solves), then taken apart
        twice = np.concatenate([every, every])
        signs = np.concatenate([nudge_signs(seed, counts) for seed in (1, 2)])
        both = _solve_wide(take(plan, twice), q, qd, qdd, out, twice, tol, signs=signs)
        shaken = [_samples(both.arrays, slice(0, k)), _samples(both.arrays, slice(k, 2 * k))]
        # each block's scales: its far samples' tops and its wide solve's, one per sample
        per: dict[str, list[float]] = {kind: [] for kind in KINDS}
        for (_, far), mine in zip(blocks, runs_tops(wide.arrays, ok, counts), strict=True):
            scale = floored({kind: max(far[kind], mine[kind]) for kind in KINDS})
            for kind in KINDS:
                per[kind].append(scale[kind])
        scales = {kind: np.repeat(np.array(v), counts) for kind, v in per.items()}
        diff = _difference(out.x, out, wide.arrays, every, scales)
        swap = ok & (diff > SUBSTITUTE)
        moved = np.maximum(
            *(_difference(wide.arrays.x, wide.arrays, s, None, scales) for s in shaken)
        )
        wide_error = np.maximum(diff * RATIO, moved / NUDGE) * MARGIN
        error = np.where(swap, wide_error, diff + wide_error + 4 * np.finfo(np.float64).eps)
        _substitute(out, wide.arrays, every, swap)
        lost = ~ok
        status[lost] = wide.status[lost]
        failed[lost] = wide.failed[lost]
        error[lost] = np.nan
    bad = error > TOLERANCE
    status[bad] = Code.IMPRECISE
    failed[bad] = step[bad]
    return error, status, failed


def nudge_signs(seed: int, counts: Sequence[int]) -> F:
    """The signs of a wide solve's nudges for several blocks' samples in turn, ``counts[i]``
    the ``i``-th block's: each block's signs drawn anew from ``seed`` —
    ``default_rng(seed).choice([-1.0, 1.0], c)`` — taken from one draw of the longest, whose
    first ``c`` signs those are (a generator draws its values one after another: tested).

    Parameters
    ----------
    seed : int
    counts : sequence of int

    Returns
    -------
    ndarray, shape (sum(counts),)
        ±1.0.
    """
    sizes = list(counts)
    draw = np.random.default_rng(seed).choice([-1.0, 1.0], max(sizes, default=0))
    return np.concatenate([draw[:c] for c in sizes]) if sizes else draw


def _samples(arr: Arrays, part: slice) -> Arrays:
    """The arrays of the samples ``part`` (views)."""
    return Arrays(
        arr.x[..., part], arr.v[..., part], arr.a[..., part], arr.trans[:, part],
        Derived(arr.derived.body[..., part], arr.derived.element[..., part]),
    )  # fmt: skip


@dataclasses.dataclass(slots=True)
class _Wide:
    arrays: Arrays
    status: np.ndarray
    failed: np.ndarray


def _solve_wide(
    plan: SolvePlan,
    q: F,
    qd: F,
    qdd: F,
    out: Arrays,
    pick: np.ndarray,
    tol: tuple[float, float],
    nudge: int = 0,
    counts: Sequence[int] | None = None,
    signs: F | None = None,
) -> _Wide:
    """The picked samples solved again in the wider type, by ``plan`` (already taken at them;
    Newton groups start from the double solution and refine it). ``nudge`` > 0 emulates
    rounding: every step's cancelling difference and output move by `NUDGE` units of the
    wide rounding, with a sign per sample drawn from that seed (``counts``: the picked
    samples are several blocks' in turn, so many each, each block's signs drawn anew), or
    ``signs`` given, one per picked sample."""
    assert WIDE is not None
    k = pick.size
    q, qd, qdd = (arr[:, pick].astype(WIDE) for arr in (q, qd, qdd))
    moves: F | None = None
    if nudge:
        signs = nudge_signs(nudge, counts or [k])
    if signs is not None:  # (given: each sample's own sign, `nudge_signs`)
        moves = (np.finfo(WIDE).eps * NUDGE * signs).astype(WIDE)
    x: F = out.x[:, :, pick].astype(WIDE)
    v = np.zeros_like(x)
    a = np.zeros_like(x)
    trans: F = np.zeros((out.trans.shape[0], k), dtype=WIDE)
    status = np.zeros(k, dtype=np.int8)
    failed = np.full(k, -1, dtype=np.int16)
    c = Chunk(
        x,
        v,
        a,
        q,
        qd,
        qdd,
        trans,
        status,
        failed,
        *tol,
        nudge=moves,
    )
    derived = Derived.empty(plan, k, dtype=WIDE)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        run_steps(plan, c, 2)
        derived.fill(plan, x, v, a, slice(None))
    return _Wide(Arrays(x, v, a, trans, derived), status, failed)


#: the kinds of quantity each with its own scale, in this order (a study's kernel keeps its
#: far samples' largest magnitudes so, `excavkin.kinematics.vectorise`)
KINDS = (
    "length",
    "velocity",
    "acceleration",
    "angle",
    "angular velocity",
    "angular acceleration",
)


def _groups(arr: Arrays) -> dict[str, list[F]]:
    """The arrays by kind of quantity, each (m, n) with the sample axis last."""
    d = arr.derived
    npts = arr.x.shape[0]
    return {
        "length": [arr.x.reshape(2 * npts, -1), d.element[0]],
        "velocity": [arr.v.reshape(2 * npts, -1), d.element[1]],
        "acceleration": [arr.a.reshape(2 * npts, -1), d.element[2]],
        "angle": [d.body[0], d.element[3], arr.trans],
        "angular velocity": [d.body[1], d.element[4]],
        "angular acceleration": [d.body[2], d.element[5]],
    }


def _scales(parts: list[tuple[Arrays, np.ndarray]]) -> dict[str, float]:
    """Each kind's largest magnitude over the given samples of the given arrays (a tiny floor
    for a kind that is zero throughout, such as velocities with every input held)."""
    top: dict[str, float] = {}
    for arrays, use in parts:
        if not use.any():
            continue
        for kind, group in _groups(arrays).items():
            for arr in group:
                if arr.size:
                    top[kind] = max(top.get(kind, 0.0), largest(arr, use))
    return floored({kind: top.get(kind, 0.0) for kind in KINDS})


#: `largest` as one compiled pass (`excavkin.backends`), without the GIL: the scales of a
#: block of a study's designs are most of its precision check in NumPy
LARGEST_SOURCE = '''\
"""Generated by excavkin.kinematics.precision (its scales); do not edit."""
import numba


@numba.njit(nogil=True, cache=True)
def kernel(bits, use):
    # a float's magnitude and its bits without the sign, as integers, order alike: the
    # largest is an integer maximum (NaN's bits, above infinity's, are passed over), which
    # the compiler vectorises
    top = 0
    for r in range(bits.shape[0]):
        for i in range(bits.shape[1]):
            b = bits[r, i] & 0x7FFFFFFFFFFFFFFF
            ok = use[i] & (b <= 0x7FF0000000000000)
            top = max(top, b if ok else 0)
    return top
'''
#: samples from which `largest` is compiled (a compile of about a second, once on a machine)
#: or loaded unasked; below, it is used once compiled and numba is imported, else NumPy does it
LARGEST_COMPILE_AT = 32768


def largest(arr: F, use: np.ndarray) -> float:
    """The largest magnitude in ``arr`` over the samples ``use``, NaN passed over (0 if
    none): each sample's largest over the rows, then the largest of those.

    Parameters
    ----------
    arr : ndarray, shape (rows, n)
        Values, the sample axis last (float64, or the wider type).
    use : ndarray of bool, shape (n,)

    Returns
    -------
    float
        The same number by either path (a largest value is exact): one compiled pass for
        float64 where numba runs and ``EXCAVKIN_COMPILED`` is not ``0`` (for
        `LARGEST_COMPILE_AT` samples or more, or once compiled and numba imported), else
        NumPy.
    """
    kernel = _largest_kernel(arr.shape[1]) if arr.dtype == np.float64 else None
    if kernel is not None:
        top = kernel(arr.view(np.int64), use)
        return float(np.array(top, dtype=np.int64).view(np.float64))
    # each sample's largest first (fmax passes over NaN), then over the samples used: no copy
    # of the picked columns of every row
    per = np.fmax.reduce(np.abs(arr), axis=0)[use].astype(np.float64)
    return float(np.nanmax(per, initial=0.0))


_largest: list[backends.Kernel] = []  # (compiled, or loaded from the cache, once)


def _largest_kernel(n: int) -> backends.Kernel | None:
    """`largest`'s compiled pass, where it is to be used for ``n`` samples, else None."""
    if os.environ.get("EXCAVKIN_COMPILED", "") == "0":
        return None
    if not _largest:
        # a small check does not import numba for it (a fraction of a second), nor compile it
        loaded = "numba" in sys.modules and backends.is_cached(LARGEST_SOURCE)
        if not _numba() or not (n >= LARGEST_COMPILE_AT or loaded):
            return None
        _largest.append(backends.kernel_of(LARGEST_SOURCE, "precision scales"))
    return _largest[0]


@functools.cache
def _numba() -> bool:
    return backends.REGISTRY["numba"].unavailable() is None


def floored(top: dict[str, float]) -> dict[str, float]:
    """Scales no smaller than the magnitudes the others imply: a velocity's ω·L and an
    acceleration's v²/L (and ω, ω² for the angular ones), so that a quantity that happens to be
    small over a short sweep (ε at a change point) is not judged against its own smallness."""
    tiny = float(np.finfo(np.float64).tiny)
    length = top["length"] or tiny
    v, w = top["velocity"], top["angular velocity"]
    out = dict(top)
    out["velocity"] = max(v, w * length)
    out["angular velocity"] = max(w, v / length)
    out["acceleration"] = max(top["acceleration"], out["velocity"] ** 2 / length)
    out["angular acceleration"] = max(top["angular acceleration"], out["angular velocity"] ** 2)
    return {kind: val or tiny for kind, val in out.items()}


def _difference(
    like: F, out: Arrays, wide: Arrays, pick: np.ndarray | None, scales: Mapping[str, Any]
) -> F:
    """The largest difference of each (picked) sample's values, relative to their kind's
    scale (one, or one per sample); ``like`` is any (·, ·, n) array of ``wide``'s
    samples."""
    worst = np.zeros(like.shape[-1] if pick is None else pick.size)
    ours, theirs = _groups(out), _groups(wide)
    for kind, arrays in ours.items():
        for mine, other in zip(arrays, theirs[kind], strict=True):
            if not mine.size:
                continue
            delta = ((mine if pick is None else mine[:, pick]) - other).astype(np.float64)
            if kind == "angle":  # the same direction either side of ±π
                delta = np.angle(np.exp(1j * delta))
            rel = np.abs(delta).max(axis=0) / scales[kind]
            worst = np.maximum(worst, np.where(np.isnan(rel), np.inf, rel))
    return worst


def _substitute(out: Arrays, wide: Arrays, pick: np.ndarray, swap: np.ndarray) -> None:
    """Put the wide values, rounded to double, into the picked samples where ``swap``."""
    rows = pick[swap]
    if not rows.size:
        return
    out.x[:, :, rows] = wide.x[:, :, swap]
    out.v[:, :, rows] = wide.v[:, :, swap]
    out.a[:, :, rows] = wide.a[:, :, swap]
    out.trans[:, rows] = wide.trans[:, swap]
    out.derived.body[:, :, rows] = wide.derived.body[:, :, swap]
    out.derived.element[:, :, rows] = wide.derived.element[:, :, swap]
