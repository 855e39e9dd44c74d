r"""Working range of an excavator front: the tip's side-view envelope and the standard figures.

Every figure is a constrained optimum over the three strokes, found by a vectorised pattern
search (a coarse grid over the free strokes, then a shrinking grid around the best few points,
to ~1e-9 m), with the constraints its definition imposes solved exactly by the closed-form
:func:`~excavkin.applications.excavator.inverse`; the reported pose is re-solved by the general
engine. Definitions (heights from the ground line, reaches from the swing axis, to the tooth
tip; SAE J1193 double-letter codes where known):

===========================  ====  ===========================================================
figure                       code  bucket orientation / constraint
===========================  ====  ===========================================================
max digging reach                  any (farthest tip from the swing axis, any height)
max reach at ground line           any, tip on the ground line
max digging depth            AC    any (lowest tip); also its radius (AE)
max vertical wall depth      AF    stick vertical and bucket hanging (Q→tip straight down)
max cutting height                 any (highest tip)
max dumping height                 bucket hanging (tip straight below the bucket pin)
min dumping height                 boom fully raised, stick fully crowded, bucket hanging
level-bottom depth                 any; deepest level tip path of ``level_bottom`` (2.44 m)
===========================  ====  ===========================================================

The envelope is exact in polar coordinates about the boom foot A: the boom turns everything
beyond it rigidly, so at each distance ρ from A the reachable directions run from the boom's
lowest position plus the lowest direction the stick and bucket give at that ρ, to the boom's
highest plus the highest (assuming, as for every backhoe front, that at each ρ those directions
form one interval). It is built from two dense sweeps of (arm, bucket) at the boom's end stops.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from excavkin.applications.excavator import (
    F,
    FrontPose,
    Machine,
    _angle,
    _wrap,
    forward,
    inverse,
)

B = NDArray[np.bool_]
Evaluate = Callable[[F], tuple[F, F]]


@dataclass(frozen=True, slots=True)
class RangeFigure:
    """One working-range figure and the pose where it occurs.

    Attributes
    ----------
    key : str
        Identifier, e.g. ``"max_digging_depth"``.
    code : str
        SAE J1193 letter code, ``""`` where none is known.
    label : str
    value : float
        Metres (depths positive downwards).
    tip : ndarray, shape (2,)
        Tooth tip where it occurs (m).
    lengths : ndarray, shape (3,)
        Boom, arm, bucket cylinder lengths there (m).
    bucket_angle : float
        Direction of bucket pin → tip there (rad).
    orientation : str
        The bucket orientation / constraint its definition requires.
    """

    key: str
    code: str
    label: str
    value: float
    tip: F
    lengths: F
    bucket_angle: float
    orientation: str


@dataclass(frozen=True, slots=True)
class WorkingRanges:
    """The standard figures and the envelope.

    Attributes
    ----------
    figures : tuple of RangeFigure
    envelope : ndarray, shape (m, 2)
        Closed polygon (first vertex not repeated) of the tip's reachable region (m).
    extra : dict of str to ndarray
        Supporting points: ``"level_bottom"`` shape (2, 2), the level cut's end points.
    """

    figures: tuple[RangeFigure, ...]
    envelope: F
    extra: dict[str, F]

    def figure(self, key: str) -> RangeFigure:
        """The figure called ``key``."""
        for f in self.figures:
            if f.key == key:
                return f
        raise KeyError(f"no figure {key!r} (known: {', '.join(f.key for f in self.figures)})")


# ---------------------------------------------------------------------------- sweeps
def sweep(machine: Machine, n: int | tuple[int, int, int] = 41) -> FrontPose:
    """Forward kinematics over a full 3-D grid of strokes, flattened to one batch.

    Parameters
    ----------
    machine : Machine
    n : int or (int, int, int)
        Grid points per cylinder (boom, arm, bucket), ends included.

    Returns
    -------
    FrontPose
        Of ``n_boom · n_arm · n_bucket`` samples, bucket length varying fastest.
    """
    counts = (n, n, n) if isinstance(n, int) else n
    axes = [
        np.linspace(lo, hi, k)
        for lo, hi, k in zip(machine.lengths_min, machine.lengths_max, counts, strict=True)
    ]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    return forward(machine, grid)


def envelope(machine: Machine, n: int = 201) -> F:
    """The side-view envelope of the tooth tip over all strokes, as a polygon.

    Parameters
    ----------
    machine : Machine
    n : int
        Samples per stroke of the arm and bucket sweeps, and radial bins.

    Returns
    -------
    ndarray, shape (m, 2)
        Vertices (m), counter-clockwise, not closed.
    """
    lo, hi = machine.lengths_min, machine.lengths_max
    la, lk = np.meshgrid(np.linspace(lo[1], hi[1], n), np.linspace(lo[2], hi[2], n), indexing="ij")
    m = la.size
    grid = np.empty((2 * m, 3))
    grid[:m, 0], grid[m:, 0] = lo[0], hi[0]
    grid[:, 1] = np.tile(la.ravel(), 2)
    grid[:, 2] = np.tile(lk.ravel(), 2)
    pose = forward(machine, grid)
    a = machine._ground_xy[machine.pins.foot]
    rel = pose.tip - a
    ok = pose.ok
    rho = np.hypot(rel[:, 0], rel[:, 1])
    theta = _angle(rel)
    ref = float(np.arctan2(np.sin(theta[ok]).mean(), np.cos(theta[ok]).mean()))
    th = _wrap(theta - ref)
    r0, r1 = float(rho[ok].min()), float(rho[ok].max())
    edges = np.linspace(r0, r1, n + 1)
    bins = np.clip(np.searchsorted(edges, rho, side="right") - 1, 0, n - 1)

    def chain(sel: B, sign: float) -> tuple[F, F]:
        idx = np.flatnonzero(sel)
        order = idx[np.lexsort((sign * th[idx], bins[idx]))]
        first = np.r_[True, bins[order][1:] != bins[order][:-1]]
        pick = order[first]
        return rho[pick], th[pick]

    rl, tl = chain(ok & (np.arange(2 * m) < m), 1.0)  # boom down: lowest directions
    rh, th_hi = chain(ok & (np.arange(2 * m) >= m), -1.0)  # boom up: highest directions
    k = max(8, n // 8)
    outer = np.linspace(tl[-1], th_hi[-1], k)[1:-1]
    inner = np.linspace(th_hi[0], tl[0], k)[1:-1]
    rr = np.concatenate([rl, np.full(outer.size, r1), rh[::-1], np.full(inner.size, r0)])
    tt = np.concatenate([tl, outer, th_hi[::-1], inner]) + ref
    return np.stack([a[0] + rr * np.cos(tt), a[1] + rr * np.sin(tt)], axis=-1)


# ---------------------------------------------------------------------------- optimiser
def _maximize(
    evaluate: Evaluate,
    machine: Machine,
    free: tuple[int, ...],
    problems: int = 1,
    *,
    coarse: int = 17,
    keep: int = 3,
    rounds: int = 32,
    m: int = 5,
) -> tuple[F, F]:
    """Maximise ``evaluate`` over the free strokes, for ``problems`` independent problems.

    ``evaluate(L)`` takes lengths of shape (problems, k, 3) (entries not in ``free`` at
    mid-stroke) and returns the objective (problems, k) (−inf where infeasible) and the full
    lengths of the pose it scored (problems, k, 3). Returns the best objective (problems,) and
    lengths (problems, 3).
    """
    lo, hi = machine.lengths_min, machine.lengths_max
    mid = 0.5 * (lo + hi)
    nf = len(free)
    axes = [np.linspace(lo[d], hi[d], coarse) for d in free]
    g = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, nf)
    L = np.broadcast_to(mid, (problems, len(g), 3)).copy()
    L[:, :, free] = g
    obj, full = evaluate(L)
    full = np.where(np.isfinite(full), full, L)
    top = np.argsort(-obj, axis=1)[:, :keep]
    centre = np.take_along_axis(full, top[:, :, None], axis=1)  # (P, keep, 3)
    w = (hi - lo)[list(free)] / (coarse - 1)
    offs = np.stack(np.meshgrid(*[np.linspace(-1.0, 1.0, m)] * nf, indexing="ij"), axis=-1).reshape(
        -1, nf
    )  # (m^nf, nf)
    best_obj = np.take_along_axis(obj, top, axis=1)
    best_L = centre.copy()
    for _ in range(rounds):
        trial = np.broadcast_to(best_L[:, :, None, :], (problems, keep, len(offs), 3)).copy()
        trial[..., free] = np.clip(
            best_L[:, :, None, free] + offs * w, lo[list(free)], hi[list(free)]
        )
        o, full = evaluate(trial.reshape(problems, -1, 3))
        o = o.reshape(problems, keep, -1)
        full = full.reshape(problems, keep, -1, 3)
        j = np.argmax(o, axis=2)
        oj = np.take_along_axis(o, j[:, :, None], axis=2)[:, :, 0]
        better = oj > best_obj
        best_obj = np.where(better, oj, best_obj)
        best_L = np.where(
            better[..., None],
            np.take_along_axis(full, j[:, :, None, None], axis=2)[:, :, 0],
            best_L,
        )
        best_L[..., free] = np.where(
            np.isfinite(best_L[..., free]), best_L[..., free], centre[..., free]
        )
        w = w / 2.0
    k = np.argmax(best_obj, axis=1)
    return best_obj[np.arange(problems), k], best_L[np.arange(problems), k]


def _target_lengths(machine: Machine, tip: F, beta: F, given: F, match: tuple[int, ...]) -> F:
    """Lengths reaching ``tip``/``beta`` whose ``match`` entries equal ``given``; NaN if none.

    Shapes: tip (N, 2), beta (N,), given (N, 3) → (N, 3).
    """
    sol = inverse(machine, tip, beta)
    agree = sol.valid.copy()
    scale = machine.lengths_max - machine.lengths_min
    for d in match:
        agree &= np.abs(sol.lengths[:, :, d] - given[:, None, d]) <= 1e-7 * scale[d]
    k = np.argmax(agree, axis=1)
    out: F = np.array(sol.lengths[np.arange(len(k)), k], dtype=np.float64)
    out[~agree.any(axis=1)] = np.nan
    return out


def _at_height(machine: Machine, y: F, sign: float) -> Evaluate:
    """Objective ``sign · x`` of the tip moved to height ``y`` (per problem) by the boom alone."""
    a = machine._ground_xy[machine.pins.foot]

    def evaluate(L: F) -> tuple[F, F]:
        P, k = L.shape[:2]
        flat = L.reshape(-1, 3)
        pose = forward(machine, flat)
        rel = pose.tip - a
        rho = np.hypot(rel[:, 0], rel[:, 1])
        th0 = _angle(rel)
        yy = np.repeat(y, k)
        s = (yy - a[1]) / rho
        best = np.full(len(flat), -np.inf)
        best_L = np.full_like(flat, np.nan)
        with np.errstate(invalid="ignore"):
            base = np.arcsin(s)
        for th in (base, np.pi - base):
            tip = a + rho[:, None] * np.stack([np.cos(th), np.sin(th)], axis=-1)
            beta = pose.bucket_angle + (th - th0)
            good = np.isfinite(th) & pose.ok
            Lt = np.full_like(flat, np.nan)
            if good.any():
                Lt[good] = _target_lengths(machine, tip[good], beta[good], flat[good], (1, 2))
            o = np.where(np.isfinite(Lt[:, 0]), sign * tip[:, 0], -np.inf)
            upd = o > best
            best = np.where(upd, o, best)
            best_L = np.where(upd[:, None], Lt, best_L)
        return best.reshape(P, k), best_L.reshape(P, k, 3)

    return evaluate


def _free_objective(machine: Machine, fn: Callable[[FrontPose], F]) -> Evaluate:
    def evaluate(L: F) -> tuple[F, F]:
        flat = L.reshape(-1, 3)
        pose = forward(machine, flat)
        o = np.where(pose.ok, fn(pose), -np.inf)
        return o.reshape(L.shape[:2]), L

    return evaluate


def _hanging(machine: Machine, stick_vertical: bool) -> Evaluate:
    """Tip straight below the bucket pin (and, optionally, the bucket pin below the stick pivot)."""
    p = machine.pins
    l_stick = machine.mechanism.plan.shapes[machine.front.stick].distance(
        p.stick_pivot, p.bucket_pin
    )
    down = np.array([0.0, -1.0])

    def evaluate(L: F) -> tuple[F, F]:
        flat = L.reshape(-1, 3)
        pose = forward(machine, flat)
        if stick_vertical:
            q = pose.result.point(p.stick_pivot)[0] + l_stick * down
            match: tuple[int, ...] = (0,)
        else:
            q = pose.result.point(p.bucket_pin)[0]
            match = (0, 1)
        tip = q + machine.tip_radius * down
        Lt = _target_lengths(machine, tip, np.full(len(flat), -np.pi / 2), flat, match)
        o = np.where(np.isfinite(Lt[:, 0]) & pose.ok, tip[:, 1], -np.inf)
        if stick_vertical:
            o = -o
            o[~np.isfinite(Lt[:, 0])] = -np.inf
        return o.reshape(L.shape[:2]), Lt.reshape(L.shape)

    return evaluate


# ---------------------------------------------------------------------------- figures
def working_ranges(machine: Machine, *, envelope_samples: int = 201) -> WorkingRanges:
    """The standard working-range figures of the machine, and its envelope.

    Parameters
    ----------
    machine : Machine
    envelope_samples : int
        ``n`` of :func:`envelope`.

    Returns
    -------
    WorkingRanges
    """
    g0, x0 = machine.ground_line, machine.swing_axis
    figs: list[RangeFigure] = []

    def add(
        key: str,
        code: str,
        label: str,
        lengths: F,
        value_fn: Callable[[F], float],
        orientation: str,
    ) -> None:
        pose = forward(machine, lengths[None, :])
        tip = pose.tip[0]
        figs.append(
            RangeFigure(
                key,
                code,
                label,
                float(value_fn(tip)),
                tip,
                lengths,
                float(pose.bucket_angle[0]),
                orientation,
            )
        )

    all3 = (0, 1, 2)
    _, L = _maximize(_free_objective(machine, lambda p: p.tip[:, 0]), machine, all3)
    add(
        "max_digging_reach",
        "",
        "Maximum digging reach",
        L[0],
        lambda t: t[0] - x0,
        "any (farthest tip)",
    )
    _, L = _maximize(_at_height(machine, np.array([g0]), 1.0), machine, (1, 2))
    add(
        "max_reach_ground",
        "",
        "Maximum reach at ground line",
        L[0],
        lambda t: t[0] - x0,
        "any, tip on the ground line",
    )
    _, L = _maximize(_free_objective(machine, lambda p: -p.tip[:, 1]), machine, all3)
    add(
        "max_digging_depth",
        "AC",
        "Maximum digging depth",
        L[0],
        lambda t: g0 - t[1],
        "any (lowest tip)",
    )
    deep = figs[-1]
    figs.append(
        RangeFigure(
            "radius_at_max_depth",
            "AE",
            "Radius at maximum digging depth",
            float(deep.tip[0] - x0),
            deep.tip,
            deep.lengths,
            deep.bucket_angle,
            deep.orientation,
        )
    )
    _, L = _maximize(_hanging(machine, True), machine, (0,), coarse=65)
    add(
        "max_vertical_wall_depth",
        "AF",
        "Maximum vertical wall digging depth",
        L[0],
        lambda t: g0 - t[1],
        "stick vertical, bucket hanging",
    )
    _, L = _maximize(_free_objective(machine, lambda p: p.tip[:, 1]), machine, all3)
    add(
        "max_cutting_height",
        "",
        "Maximum cutting height",
        L[0],
        lambda t: t[1] - g0,
        "any (highest tip)",
    )
    _, L = _maximize(_hanging(machine, False), machine, (0, 1))
    add(
        "max_dumping_height",
        "",
        "Maximum dumping height",
        L[0],
        lambda t: t[1] - g0,
        "bucket hanging (tip below bucket pin)",
    )
    lo, hi = machine.lengths_min, machine.lengths_max
    crowd = hi[1] if machine.cylinders[1].dig == "extend" else lo[1]
    start = np.array([[[hi[0], crowd, 0.5 * (lo[2] + hi[2])]]])
    _, Lh = _hanging(machine, False)(start)
    add(
        "min_dumping_height",
        "",
        "Minimum dumping height",
        Lh[0, 0],
        lambda t: t[1] - g0,
        "boom up, stick crowded, bucket hanging",
    )
    depth, ends, L = _level_bottom(machine, g0 - deep.value)
    figs.append(
        RangeFigure(
            "level_bottom_depth",
            "",
            f"Digging depth for {machine.level_bottom:.2f} m level bottom",
            depth,
            ends[1],
            L,
            float(forward(machine, L[None, :]).bucket_angle[0]),
            "any; level tip path",
        )
    )
    return WorkingRanges(tuple(figs), envelope(machine, envelope_samples), {"level_bottom": ends})


def _x_extent(machine: Machine, ys: F) -> tuple[F, F, F, F]:
    hi_obj, hi_L = _maximize(
        _at_height(machine, ys, 1.0), machine, (1, 2), len(ys), coarse=13, keep=2, rounds=24
    )
    lo_obj, lo_L = _maximize(
        _at_height(machine, ys, -1.0), machine, (1, 2), len(ys), coarse=13, keep=2, rounds=24
    )
    return -lo_obj, hi_obj, lo_L, hi_L


def _level_bottom(machine: Machine, y_deep: float) -> tuple[float, F, F]:
    """Deepest height with a reachable level segment of ``machine.level_bottom``."""
    need = machine.level_bottom
    y0, y1 = y_deep + 1e-6, machine.ground_line
    xl = xh = np.array([np.nan])
    Lh = np.full((1, 3), np.nan)
    for _ in range(7):
        ys = np.linspace(y0, y1, 10)
        xl, xh, _, Lh = _x_extent(machine, ys)
        width = np.where(np.isfinite(xl) & np.isfinite(xh), xh - xl, -np.inf)
        ok = np.flatnonzero(width >= need)
        if not ok.size:
            return float("nan"), np.full((2, 2), np.nan), np.full(3, np.nan)
        k = int(ok[0])
        if k == 0:
            y1 = ys[0]
            break
        y0, y1 = ys[k - 1], ys[k]
    xl, xh, _, Lh = _x_extent(machine, np.array([y1]))
    ends = np.array([[xh[0] - need, y1], [xh[0], y1]])
    return float(machine.ground_line - y1), ends, Lh[0]
