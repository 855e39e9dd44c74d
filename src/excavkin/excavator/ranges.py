r"""Working range of an excavator front: the tip's side-view envelope and the standard figures.

Every figure is a constrained optimum over the three strokes, found by a vectorised pattern
search (a coarse grid over the free strokes, then a shrinking grid around the best few points,
to ~1e-9 m), with the constraints its definition imposes solved exactly by the closed-form
[`inverse`][excavkin.excavator.machine.inverse]; the reported pose is re-solved by the general
engine. Definitions (heights from the ground line, reaches from the swing axis, to the tooth
tip; SAE J1193 double-letter codes where known):

===========================  ====  ===========================================================
figure                       code  bucket orientation / constraint
===========================  ====  ===========================================================
max digging reach                  any (farthest tip from the swing axis, any height)
max reach at ground line           any, tip on the ground line
max digging depth            AC    any (lowest tip); also its radius (AE)
max vertical wall depth      AF    teeth vertical (lip → tip straight down), deepest tip;
                                   without teeth the floor (floor → lip); left out when
                                   the machine names neither
max cutting height                 any (highest tip)
max dumping height                 bucket hanging (tip straight below the bucket pin)
min dumping height                 boom fully raised, stick fully crowded, bucket hanging
level-bottom depth                 any; deepest level tip path of ``level_bottom`` (2.44 m)
===========================  ====  ===========================================================

The envelope is the union, over the boom's swing, of the region the tip covers with the boom
held (`envelope`); its boundary follows the true one (stroke limits and the arm–bucket
fold) to about 0.1 mm.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from scipy.optimize import brentq
from shapely.geometry.polygon import orient

from excavkin.arrays import FloatArray as F
from excavkin.errors import ExcavkinWarning, ModelError
from excavkin.excavator.machine import (
    FrontPose,
    Machine,
    direction_angle,
    forward,
    inverse,
    length_columns,
    mm_field,
    wrap_angle,
)
from excavkin.machinery.search import Evaluate, Progress, maximize_strokes, part

if TYPE_CHECKING:
    import pandas as pd


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
    machine : str
        The machine's name (for the table and the summary).
    """

    figures: tuple[RangeFigure, ...]
    envelope: F
    extra: dict[str, F]
    machine: str = ""

    def __repr__(self) -> str:
        shown = ", ".join(f"{f.label} {f.value * 1000:.0f} mm" for f in self.figures[:3])
        return f"WorkingRanges({len(self.figures)} figures: {shown}, …)"

    def figure(self, key: str) -> RangeFigure:
        """The figure called ``key``."""
        for f in self.figures:
            if f.key == key:
                return f
        raise KeyError(f"no figure {key!r} (known: {', '.join(f.key for f in self.figures)})")

    def to_frame(self) -> pd.DataFrame:
        """One row per figure, SI.

        Returns
        -------
        pandas.DataFrame
            ``key``, ``code``, ``label``, ``value``, the tip ``x``, ``y``, the cylinder
            lengths ``boom``, ``arm``, ``bucket`` (m), ``bucket_angle`` (rad) and
            ``orientation``; its ``attrs`` name the machine and each column's kind.
        """
        rows = [
            {
                "key": f.key,
                "code": f.code,
                "label": f.label,
                "value": f.value,
                "x": f.tip[0],
                "y": f.tip[1],
                **length_columns(f.lengths),
                "bucket_angle": f.bucket_angle,
                "orientation": f.orientation,
            }
            for f in self.figures
        ]
        kinds = dict.fromkeys(("value", "x", "y", "boom", "arm", "bucket"), "length")
        return _frame(rows, self.machine, {**kinds, "bucket_angle": "angle"})

    def envelope_frame(self) -> pd.DataFrame:
        """The envelope's vertices as a table, SI.

        Returns
        -------
        pandas.DataFrame
            ``x``, ``y`` (m), one row per vertex.
        """
        xy = {"x": self.envelope[:, 0], "y": self.envelope[:, 1]}
        return _frame(xy, self.machine, {"x": "length", "y": "length"})

    def summary(self) -> str:
        """The figures as ``excavkin excavator ranges`` prints them (mm).

        Returns
        -------
        str
        """

        lines = [
            f"{self.machine} — working ranges (tooth tip; mm)",
            f"{'':4} {'figure':<38} {'value':>8}  {'x':>8} {'y':>8}  "
            f"{'boom':>7} {'arm':>7} {'bucket':>7}  bucket orientation",
        ]
        lines += [
            f"{f.code:4} {f.label:<38} {mm_field(f.value)}  "
            f"{mm_field(f.tip[0])} {mm_field(f.tip[1])}  "
            f"{f.lengths[0] * 1e3:7.0f} {f.lengths[1] * 1e3:7.0f} "
            f"{f.lengths[2] * 1e3:7.0f}  {f.orientation}"
            for f in self.figures
        ]
        return "\n".join(lines)


def _frame(rows: Any, machine: str, kinds: dict[str, str]) -> pd.DataFrame:
    """A table whose attrs name the machine and its columns' kinds."""
    import pandas as pd

    from excavkin.kinematics.columns import kinds_attrs

    frame = pd.DataFrame(rows)
    frame.attrs.update(kinds_attrs(machine, {c: k for c, k in kinds.items() if c in frame}))
    return frame


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
    return forward(machine, stroke_grid(machine, n))


def stroke_grid(machine: Machine, n: int | tuple[int, int, int] = 41) -> F:
    """The cylinder lengths of `sweep`: a full 3-D grid of strokes, shape
    (n_boom · n_arm · n_bucket, 3), ends included, bucket length varying fastest."""
    counts = (n, n, n) if isinstance(n, int) else n
    axes = [
        np.linspace(lo, hi, k)
        for lo, hi, k in zip(machine.lengths_min, machine.lengths_max, counts, strict=True)
    ]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


def _even_in_angle(machine: Machine, c: int, n: int) -> F:
    """``n`` lengths of cylinder ``c`` (arm or bucket) that turn its body in equal angles.

    Near a linkage's toggle a stroke step turns the bucket much further than mid-stroke; equal
    angle steps keep every chord of the envelope equally close to its arc.
    """
    lo, hi = machine.lengths_min, machine.lengths_max
    fine = np.linspace(lo[c], hi[c], 16 * n + 1)
    L = np.broadcast_to(0.5 * (lo + hi), (fine.size, 3)).copy()
    L[:, c] = fine
    pose = forward(machine, L)
    p = machine.pins
    stick = direction_angle(
        pose.result.point(p.bucket_pin)[0] - pose.result.point(p.stick_pivot)[0]
    )
    turn = stick if c == 1 else pose.bucket_angle - stick
    ok = np.isfinite(turn)  # where part of a stroke does not assemble, grid what does
    if ok.sum() < 2:
        return np.linspace(lo[c], hi[c], n)
    s = np.r_[0.0, np.cumsum(np.abs(np.diff(np.unwrap(turn[ok]))))]
    if not s[-1] > 0.0:
        return np.linspace(lo[c], hi[c], n)
    return np.asarray(np.interp(np.linspace(0.0, s[-1], n), s, fine[ok]))


def _fold_strokes(machine: Machine) -> F:
    """Bucket lengths at which the stick pivot, bucket pin and tip line up.

    There ∂tip/∂L_arm ∥ ∂tip/∂L_bucket (both perpendicular to the line): the arm–bucket map
    folds, and the fold's image (arcs about the stick pivot) bounds the working range. They
    depend on the bucket stroke alone, so they enter the bucket grid exactly.
    """
    lo, hi = machine.lengths_min, machine.lengths_max
    p = machine.pins

    def cross(lk: F) -> F:
        L = np.broadcast_to(0.5 * (lo + hi), (lk.size, 3)).copy()
        L[:, 2] = lk
        res = forward(machine, L)
        f = res.result.point(p.stick_pivot)[0]
        q = res.result.point(p.bucket_pin)[0]
        u, v = res.tip - f, res.tip - q
        return np.asarray(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])

    grid = np.linspace(lo[2], hi[2], 513)
    c = cross(grid)
    out = []
    for i in np.flatnonzero(np.sign(c[:-1]) * np.sign(c[1:]) < 0):
        out.append(brentq(lambda x: float(cross(np.array([x]))[0]), grid[i], grid[i + 1]))
    return np.asarray(out, dtype=np.float64)


def _swept(region: shapely.Polygon, centre: F, swing: float) -> shapely.Geometry:
    """The set ``region`` covers while turning about ``centre`` through ``swing`` (rad).

    In polar coordinates (θ, ρ) about the centre a turn is a shift in θ, so the swept set is
    the Minkowski sum of the polar region with the segment [0, swing]: the region at both ends
    and the parallelogram each boundary edge sweeps. The polar θ axis is cut in the widest gap
    of the region's directions; long edges are split before mapping back so that the arcs stay
    arcs.
    """
    # short edges, so that a straight chord and its polar image stay within ~1e-6 m
    ring = np.asarray(shapely.segmentize(region.exterior, 0.002).coords)[:-1]
    rel = ring - centre
    rho = np.hypot(rel[:, 0], rel[:, 1])
    theta = np.sort(direction_angle(rel))
    gaps = np.diff(np.r_[theta, theta[0] + 2.0 * np.pi])
    k = int(np.argmax(gaps))
    if gaps[k] <= abs(swing) + 1e-6 or rho.min() <= 0.0:
        raise ModelError("the working range winds round the boom foot; its envelope is not defined")
    cut = theta[k] + 0.5 * gaps[k]
    scale = float(rho.max())  # θ in metres of arc at the largest radius
    th = np.mod(direction_angle(rel) - cut, 2.0 * np.pi) * scale
    pts = np.stack([th, rho], axis=-1)
    shift = np.array([swing * scale, 0.0])
    nxt = np.roll(pts, -1, axis=0)
    quads = np.stack([pts, nxt, nxt + shift, pts + shift], axis=1)
    polar = shapely.unary_union(
        [shapely.Polygon(pts), shapely.Polygon(pts + shift), *shapely.polygons(quads)]
    )
    polar = shapely.segmentize(polar, 0.005)

    def back(c: F) -> F:
        t = c[:, 0] / scale + cut
        return np.stack([centre[0] + c[:, 1] * np.cos(t), centre[1] + c[:, 1] * np.sin(t)], axis=-1)

    return shapely.transform(polar, back)


def envelope(machine: Machine, n: int = 161) -> F:
    """The side-view envelope of the tooth tip over all strokes, as a polygon.

    The boom turns everything beyond it rigidly about the boom foot, so the working range is
    the union, over the boom's swing, of the region W the tip covers with the boom held. W is
    the union of the images of the cells of an (arm, bucket) grid, split into triangles; the
    grid is even in the stick's and bucket's angles and contains the fold strokes exactly
    (`_fold_strokes`), so its boundary is sampled on the true boundary. W is then swept
    through the boom's range exactly (`_swept`). Chords leave the polygon within about
    0.1 mm of the true boundary for a 20 t front.

    Parameters
    ----------
    machine : Machine
    n : int
        Grid points along the arm and bucket strokes.

    Returns
    -------
    ndarray, shape (m, 2)
        Vertices (m), counter-clockwise, not closed.
    """
    lo, hi = machine.lengths_min, machine.lengths_max
    la = _even_in_angle(machine, 1, n)
    lk = np.unique(np.r_[_even_in_angle(machine, 2, n), _fold_strokes(machine)])
    A, K = np.meshgrid(la, lk, indexing="ij")
    grid = np.stack([np.full(A.size, lo[0]), A.ravel(), K.ravel()], axis=-1)
    pose = forward(machine, grid)
    tip = np.where(pose.ok[:, None], pose.tip, np.nan).reshape(*A.shape, 2)
    c00, c10, c11, c01 = tip[:-1, :-1], tip[1:, :-1], tip[1:, 1:], tip[:-1, 1:]
    tri = np.concatenate(
        [
            np.stack([c00, c10, c11], axis=2).reshape(-1, 3, 2),
            np.stack([c00, c11, c01], axis=2).reshape(-1, 3, 2),
        ]
    )
    tri = tri[np.isfinite(tri).all(axis=(1, 2))]
    held = shapely.unary_union(shapely.polygons(tri))
    if held.geom_type != "Polygon":
        parts = sorted(held.geoms, key=lambda g: -g.area)
        warnings.warn(
            f"{machine.name}: with the boom held, the tip's region falls apart into "
            f"{len(parts)} pieces (arm and bucket strokes that do not assemble split it); the "
            "envelope sweeps the largest",
            ExcavkinWarning,
            stacklevel=2,
        )
        held = parts[0]
    p = machine.pins
    a = machine._ground_xy[p.foot]
    ends = forward(machine, np.array([lo, [hi[0], lo[1], lo[2]]]))
    f = ends.result.point(p.stick_pivot)[0]
    swing = float(wrap_angle(direction_angle(f[1] - a) - direction_angle(f[0] - a)))
    if not (ends.ok.all() and np.isfinite(swing)):
        raise ModelError(
            f"{machine.name}: the front does not assemble with the boom cylinder at both ends "
            "of its stroke (arm and bucket retracted), so the boom's swing is unknown"
        )
    region = _swept(held, a, swing)
    if region.geom_type != "Polygon":
        parts = sorted(region.geoms, key=lambda g: -g.area)
        warnings.warn(
            f"{machine.name}: the working range falls apart into {len(parts)} pieces (poses that "
            "do not assemble split it); the envelope is the largest",
            ExcavkinWarning,
            stacklevel=2,
        )
        region = parts[0]
    pockets = [h for h in region.interiors if shapely.Polygon(h).area > 1e-4]
    if pockets:
        warnings.warn(
            f"{machine.name}: {len(pockets)} unreachable pocket(s) inside the working range; the "
            "envelope is its outer boundary",
            ExcavkinWarning,
            stacklevel=2,
        )
    # drop the vertices the 5 mm split added along straight runs; keep 0.02 mm
    ring = orient(shapely.Polygon(region.exterior).simplify(2e-5), 1.0)
    return np.asarray(ring.exterior.coords)[:-1]


# ---------------------------------------------------------------------------- optimiser
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
        th0 = direction_angle(rel)
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


def _bucket_held(machine: Machine, beta: float, sign: float) -> Evaluate:
    """Objective ``sign · y`` of the tip with the bucket turned to the angle ``beta`` (pin →
    tip) wherever the boom and stick put the bucket pin."""
    p = machine.pins
    offset = machine.tip_radius * np.array([np.cos(beta), np.sin(beta)])

    def evaluate(L: F) -> tuple[F, F]:
        flat = L.reshape(-1, 3)
        pose = forward(machine, flat)
        tip = pose.result.point(p.bucket_pin)[0] + offset
        Lt = _target_lengths(machine, tip, np.full(len(flat), beta), flat, (0, 1))
        o = np.where(np.isfinite(Lt[:, 0]) & pose.ok, sign * tip[:, 1], -np.inf)
        return o.reshape(L.shape[:2]), Lt.reshape(L.shape)

    return evaluate


# ---------------------------------------------------------------------------- figures
def working_ranges(
    machine: Machine, *, envelope_samples: int = 161, progress: Progress | None = None
) -> WorkingRanges:
    """The standard working-range figures of the machine, and its envelope.

    Parameters
    ----------
    machine : Machine
    envelope_samples : int
        ``n`` of `envelope`.
    progress : callable, optional
        ``progress(done, total)`` as the figures' searches and the envelope are done.

    Returns
    -------
    WorkingRanges
    """
    g0, x0 = machine.ground_line, machine.swing_axis
    figs: list[RangeFigure] = []
    # the searches (one more with a vertical wall), the least dumping height, the level
    # bottom and the envelope
    steps = 8 + int(machine.has_cutting_direction)
    step = iter(range(steps))

    def search(evaluate: Evaluate, free: tuple[int, ...]) -> F:
        _, L = maximize_strokes(evaluate, machine, free, progress=part(progress, next(step), steps))
        return L

    def done() -> None:
        if progress is not None:
            progress(next(step) + 1, steps)

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
    L = search(_free_objective(machine, lambda p: p.tip[:, 0]), all3)
    add(
        "max_digging_reach",
        "",
        "Maximum digging reach",
        L[0],
        lambda t: t[0] - x0,
        "any (farthest tip)",
    )
    L = search(_at_height(machine, np.array([g0]), 1.0), (1, 2))
    add(
        "max_reach_ground",
        "",
        "Maximum reach at ground line",
        L[0],
        lambda t: t[0] - x0,
        "any, tip on the ground line",
    )
    L = search(_free_objective(machine, lambda p: -p.tip[:, 1]), all3)
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
    if machine.has_cutting_direction:  # a bucket without teeth needs its floor point
        wall = machine.wall_bucket_angle
        L = search(_bucket_held(machine, wall, -1.0), (0, 1))
        add(
            "max_vertical_wall_depth",
            "AF",
            "Maximum vertical wall digging depth",
            L[0],
            lambda t: g0 - t[1],
            f"teeth (lip → tip) vertical: pin → tip at {np.degrees(wall):.1f}°",
        )
    L = search(_free_objective(machine, lambda p: p.tip[:, 1]), all3)
    add(
        "max_cutting_height",
        "",
        "Maximum cutting height",
        L[0],
        lambda t: t[1] - g0,
        "any (highest tip)",
    )
    L = search(_bucket_held(machine, -0.5 * np.pi, 1.0), (0, 1))
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
    _, Lh = _bucket_held(machine, -0.5 * np.pi, 1.0)(start)
    done()
    add(
        "min_dumping_height",
        "",
        "Minimum dumping height",
        Lh[0, 0],
        lambda t: t[1] - g0,
        "boom up, stick crowded, bucket hanging",
    )
    depth, ends, L = _level_bottom(machine, g0 - deep.value)
    done()
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
    outline = envelope(machine, envelope_samples)
    done()
    return WorkingRanges(tuple(figs), outline, {"level_bottom": ends}, machine.name)


def _x_extent(machine: Machine, ys: F) -> tuple[F, F, F, F]:
    hi_obj, hi_L = maximize_strokes(
        _at_height(machine, ys, 1.0), machine, (1, 2), len(ys), coarse=13, keep=2, rounds=24
    )
    lo_obj, lo_L = maximize_strokes(
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
