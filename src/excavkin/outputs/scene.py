"""The drawable geometry of a mechanism, computed once with NumPy for both renderers.

A `Scene` holds, over every sample, the outlines of the bodies, the cylinders as barrel
and rod, the pins, the ground symbols and the sliders, in display length units; its
`overlays` say which points move and where the warnings go (dead positions, the
last solved sample before a run that does not close). The matplotlib renderer
(`excavkin.outputs.drawing`) and the plotly one (`excavkin.outputs.report`) only
translate these primitives::

        cylinder (linear driver, barrel at its first point)      binary body   ternary body
      p o===[##########]-------------o q                        o-------o      o-----o
            barrel          rod                                                 \\###/
                                                                                 \\#/
      ground pivot:   o        slider:  [=o=]  on its guide                       o
                     /_\\
                    //////
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from excavkin.outputs.events import Table, dead_samples, failed_runs
from excavkin.outputs.protocols import Drawable
from excavkin.outputs.style import BODY_COLORS
from excavkin.step_kinds.rope_path import rope_path, sketch_wraps


def source(mech_or_result: Drawable) -> tuple[Any, np.ndarray, Any]:
    """(plan, positions shape (n, n_points, 2) in m, result or None)."""
    obj = mech_or_result
    if hasattr(obj, "positions") and hasattr(obj, "plan"):
        return obj.plan, np.asarray(obj.positions, dtype=np.float64), obj
    kin = getattr(obj, "kinematics", None)
    if kin is not None and hasattr(kin, "positions"):
        return kin.plan, np.asarray(kin.positions, dtype=np.float64), kin
    if hasattr(obj, "assembly") and hasattr(obj, "plan"):
        return obj.plan, np.asarray(obj.assembly.positions, dtype=np.float64)[None], None
    raise TypeError(
        f"expected a Mechanism or a KinematicResult, got {type(mech_or_result).__name__}"
    )


def _hull_order(xy: np.ndarray) -> list[int]:
    """Indices of the convex hull of points ``xy`` (k, 2), counter-clockwise (monotone chain)."""
    idx = sorted(range(len(xy)), key=lambda i: (xy[i, 0], xy[i, 1]))

    def cross(o: int, a: int, b: int) -> float:
        return float(
            (xy[a, 0] - xy[o, 0]) * (xy[b, 1] - xy[o, 1])
            - (xy[a, 1] - xy[o, 1]) * (xy[b, 0] - xy[o, 0])
        )

    lower: list[int] = []
    for i in idx:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], i) <= 0:
            lower.pop()
        lower.append(i)
    upper: list[int] = []
    for i in reversed(idx):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], i) <= 0:
            upper.pop()
        upper.append(i)
    return lower[:-1] + upper[:-1]


@dataclass(frozen=True, slots=True)
class BodyGeometry:
    """How a moving body is drawn.

    Attributes
    ----------
    name : str
    outline : tuple of int
        Point indices of its outline (a path for two or collinear points, a closed polygon
        otherwise).
    closed : bool
        Whether the outline is a filled polygon (points inside it are drawn as pins or dots
        on the fill).
    color : str
    """

    name: str
    outline: tuple[int, ...]
    closed: bool
    color: str


@dataclass(frozen=True, slots=True)
class ElementGeometry:
    """How a linear element is drawn: a cylinder (barrel + rod) or a plain line (rope, strut).

    Attributes
    ----------
    name : str
    p, q : int
        Point indices; the barrel is at ``p``, the rod's eye at ``q``.
    style : {"cylinder", "line"}
    barrel : float
        Barrel length in display units.
    rod : float
        Rod length in display units.
    """

    name: str
    p: int
    q: int
    style: str
    barrel: float
    rod: float


@dataclass
class Scene:
    """The drawable geometry of a mechanism over its samples, in display length units.

    Parameters
    ----------
    plan : SolvePlan
    positions : ndarray, shape (n, n_points, 2)
        Point positions, m.
    ropes : iterable of str
        Linear elements to draw as plain lines rather than cylinders (the model's ropes are
        drawn so always).
    length_unit : str
        Display unit of lengths.

    Attributes
    ----------
    xy : ndarray, shape (n, n_points, 2)
        Positions in ``length_unit``.
    extent : float
        Largest side of the bounding box of every sample (display units); sizes of pins,
        hatching and blocks are fractions of it.
    """

    plan: Any
    positions: np.ndarray
    ropes: Iterable[str] = ()
    length_unit: str = "mm"
    xy: np.ndarray = field(init=False)
    extent: float = field(init=False)
    bodies: list[BodyGeometry] = field(init=False)
    elements: list[ElementGeometry] = field(init=False)
    pins: list[int] = field(init=False)
    dots: list[int] = field(init=False)
    ground_pivots: list[int] = field(init=False)
    sliders: list[tuple[str, int, int, int]] = field(init=False)
    #: each rope over sheaves: name, path point indices, signed sheave radii (display units)
    #: and wraps at the sketch
    rope_paths: list[tuple[str, tuple[int, ...], tuple[float, ...], tuple[float, ...]]] = field(
        init=False
    )

    def __post_init__(self) -> None:
        from excavkin.outputs.display_units import convert

        plan = self.plan
        model = plan.model
        self.xy = convert(np.asarray(self.positions, dtype=np.float64), "length", self.length_unit)
        finite = self.xy[np.isfinite(self.xy).all(axis=-1)]
        if finite.size:
            span = finite.max(axis=0) - finite.min(axis=0)
            self.extent = float(max(span.max(), 1e-12))
        else:
            self.extent = 1.0
        index = {p: i for i, p in enumerate(plan.points)}
        # a representative configuration: the first sample where everything closed
        ok_rows = np.flatnonzero(np.isfinite(self.xy).all(axis=(1, 2)))
        ref = (
            self.xy[ok_rows[0]]
            if ok_rows.size
            else np.asarray(convert(np.asarray(plan.sketch), "length", self.length_unit))
        )
        owners: dict[str, int] = {p: 0 for p in plan.points}
        for b in model.bodies:
            for p in b.points:
                owners[p] += 1
        ropes = set(self.ropes)
        unknown = ropes - {e.name for e in plan.elements}
        if unknown:
            raise ValueError(f"ropes: no linear element named {', '.join(sorted(unknown))}")
        ropes |= {r.name for r in model.ropes}
        ends: set[str] = set()
        self.elements = []
        for e in plan.elements:
            ends |= {plan.points[e.p], plan.points[e.q]}
            lengths = np.linalg.norm(self.xy[:, e.q] - self.xy[:, e.p], axis=-1)
            lengths = lengths[np.isfinite(lengths)]
            if lengths.size:
                lmin, lmax = float(lengths.min()), float(lengths.max())
            else:
                lmin = lmax = float(np.linalg.norm(ref[e.q] - ref[e.p]))
            rod = 0.95 * lmin
            barrel = min(max(lmax - 0.85 * lmin, 0.5 * lmin), 0.9 * lmin)
            style = "line" if e.name in ropes else "cylinder"
            self.elements.append(ElementGeometry(e.name, e.p, e.q, style, barrel, rod))
        self.rope_paths = []
        for r in model.ropes:
            if not r.over_sheaves:
                continue
            ends |= set(r.path)
            radii = [float(convert(np.float64(v), "length", self.length_unit)) for v in r.radii]
            signed = (
                0.0,
                *(v if w == "ccw" else -v for v, w in zip(radii, r.wraps, strict=True)),
                0.0,
            )
            path = tuple(index[p] for p in r.path)
            sketch = convert(np.asarray([plan.sketch[i] for i in path]), "length", self.length_unit)
            wraps0 = sketch_wraps([tuple(p) for p in sketch], signed)
            self.rope_paths.append((r.name, path, signed, wraps0))
        slider_pts: set[str] = set()
        self.sliders = []
        for s in model.sliders:
            slider_pts.add(s.point)
            self.sliders.append((s.name, index[s.point], index[s.along[0]], index[s.along[1]]))
        ground = model.ground
        self.ground_pivots = [
            index[p] for p in ground.points if owners[p] > 1 or p in ends or p in slider_pts
        ]
        self.pins = [
            i for i, p in enumerate(plan.points) if owners[p] > 1 or p in ends or p in slider_pts
        ]
        self.dots = [i for i in range(len(plan.points)) if i not in self.pins]
        self.bodies = []
        k = 0
        for b in model.bodies:
            if b.ground:
                continue
            color = BODY_COLORS[k % len(BODY_COLORS)]
            k += 1
            ids = [index[p] for p in b.points]
            pts = ref[ids]
            if len(ids) <= 2:
                self.bodies.append(BodyGeometry(b.name, tuple(ids), False, color))
                continue
            hull = _hull_order(pts)
            area = 0.5 * abs(
                sum(
                    pts[hull[i - 1], 0] * pts[hull[i], 1] - pts[hull[i], 0] * pts[hull[i - 1], 1]
                    for i in range(len(hull))
                )
            )
            span = float(np.ptp(pts, axis=0).max()) or 1.0
            if len(hull) < 3 or area < 1e-3 * span * span:
                d = pts[np.argmax(np.linalg.norm(pts - pts[0], axis=1))] - pts[0]
                order = np.argsort((pts - pts[0]) @ d)
                self.bodies.append(BodyGeometry(b.name, tuple(ids[i] for i in order), False, color))
                continue
            self.bodies.append(BodyGeometry(b.name, tuple(ids[i] for i in hull), True, color))

    def __len__(self) -> int:
        return int(self.xy.shape[0])

    @property
    def size(self) -> float:
        """The size unit of symbols (pins, hatching): 3.5 % of the extent."""
        return 0.035 * self.extent

    def body_path(self, body: BodyGeometry, i: int) -> np.ndarray:
        """Outline of ``body`` at sample ``i``, shape (k, 2) (closed polygons repeat the first)."""
        pts = self.xy[i, list(body.outline)]
        return np.vstack([pts, pts[:1]]) if body.closed else pts

    def element_segments(self, el: ElementGeometry, i: int) -> tuple[np.ndarray, np.ndarray]:
        """(barrel, rod) segments of ``el`` at sample ``i``, each shape (2, 2).

        For a plain line both are the segment p→q.
        """
        p, q = self.xy[i, el.p], self.xy[i, el.q]
        if el.style == "line":
            seg = np.vstack([p, q])
            return seg, seg
        d = q - p
        length = float(np.hypot(*d))
        u = d / length if length > 0 else np.array([np.nan, np.nan])
        barrel = np.vstack([p, p + u * min(el.barrel, length)])
        rod = np.vstack([q, q - u * min(el.rod, length)])
        return barrel, rod

    def rope_line(
        self, rope: tuple[str, tuple[int, ...], tuple[float, ...], tuple[float, ...]], i: int
    ) -> np.ndarray:
        """A rope over sheaves at sample ``i`` as a polyline: its free tangent segments and
        its arcs on the sheaves (16 points a quarter turn), shape (k, 2).

        Parameters
        ----------
        rope : tuple
            One of `rope_paths`.
        i : int
            The sample.

        Returns
        -------
        ndarray, shape (k, 2)
            Display units; NaN where the sample did not solve.
        """
        _, ids, signed, wraps0 = rope
        pts = [(np.array([x]), np.array([y])) for x, y in self.xy[i, list(ids)]]
        geo = rope_path(pts, signed, wraps0)
        out: list[np.ndarray] = []
        for k in range(len(ids) - 1):
            u = np.array([geo.ux[k][0], geo.uy[k][0]])
            n = np.array([-u[1], u[0]])
            c0, c1 = self.xy[i, ids[k]], self.xy[i, ids[k + 1]]
            start, end = c0 - signed[k] * n, c1 - signed[k + 1] * n
            if k:  # the arc on sheave k, from the last segment's end to this one's start
                r, sigma = abs(signed[k]), np.sign(signed[k])
                a0 = np.arctan2(*(out[-1] - c0)[::-1])
                phi = float(geo.wraps[k - 1][0])
                steps = max(2, int(np.ceil(abs(phi) / (np.pi / 32))) + 1)
                if np.isfinite(phi):
                    t = a0 + sigma * np.linspace(0.0, phi, steps)
                    out += list(c0 + r * np.column_stack([np.cos(t), np.sin(t)]))
            out += [start, end]
        return np.asarray(out, dtype=np.float64)

    def ground_symbols(self) -> tuple[np.ndarray, np.ndarray]:
        """Ground pivot triangles and their hatching, NaN-separated paths, each shape (k, 2).

        Returns
        -------
        triangles, hatching : ndarray
            Both static; the pivots of the ground do not move.
        """
        s = self.size
        tri: list[list[float]] = []
        hatch: list[list[float]] = []
        nan = [np.nan, np.nan]
        base = (
            self.xy[0]
            if np.isfinite(self.xy[0, self.ground_pivots]).all()
            else np.asarray(
                self.xy[np.flatnonzero(np.isfinite(self.xy).all(axis=(1, 2)))[0]]
                if np.isfinite(self.xy).all(axis=(1, 2)).any()
                else self.xy[0]
            )
        )
        for g in self.ground_pivots:
            x, y = base[g]
            tri += [[x, y], [x - 0.8 * s, y - 1.4 * s], [x + 0.8 * s, y - 1.4 * s], [x, y], nan]
            yb = y - 1.4 * s
            hatch += [[x - 1.3 * s, yb], [x + 1.3 * s, yb], nan]
            for k in range(6):
                x0 = x - 1.3 * s + k * 0.5 * s
                hatch += [[x0 + 0.45 * s, yb], [x0, yb - 0.5 * s], nan]
        ground_pts = {self.plan.points.index(p) for p in self.plan.model.ground.points}
        for sl in self.sliders:
            if sl[2] in ground_pts and sl[3] in ground_pts:  # a fixed guide: hatch beneath it
                a, b = self.slider_guide(sl, 0)
                d = b - a
                length = float(np.hypot(*d))
                u = d / length
                nrm = np.array([u[1], -u[0]])
                if nrm[1] > 0:
                    nrm = -nrm
                off = a + 0.8 * s * nrm
                hatch += [list(off), list(off + d), nan]
                for k in range(int(length / (0.5 * s))):
                    x0 = off + (k + 1) * 0.5 * s * u
                    hatch += [list(x0), list(x0 - 0.45 * s * u + 0.5 * s * nrm), nan]
        empty = np.empty((0, 2))
        return (np.asarray(tri) if tri else empty, np.asarray(hatch) if hatch else empty)

    def slider_block(self, slider: tuple[str, int, int, int], i: int) -> np.ndarray:
        """The sliding block of ``slider`` at sample ``i``: a closed rectangle, shape (5, 2)."""
        _, p, l1, l2 = slider
        c = self.xy[i, p]
        d = self.xy[i, l2] - self.xy[i, l1]
        u = d / np.hypot(*d)
        n = np.array([-u[1], u[0]])
        a, b = 1.2 * self.size, 0.7 * self.size
        corners = [c + a * u + b * n, c - a * u + b * n, c - a * u - b * n, c + a * u - b * n]
        return np.vstack([*corners, corners[0]])

    def slider_guide(self, slider: tuple[str, int, int, int], i: int) -> np.ndarray:
        """The guide line of ``slider`` at sample ``i`` through its two points, shape (2, 2),
        extended to cover the block's travel over every sample."""
        _, p, l1, l2 = slider
        a, b = self.xy[i, l1], self.xy[i, l2]
        d = b - a
        u = d / np.hypot(*d)
        # the block's travel along the guide in the guide body's frame
        rel = self.xy[:, p] - self.xy[:, l1]
        dd = self.xy[:, l2] - self.xy[:, l1]
        along = np.einsum("ij,ij->i", rel, dd) / np.linalg.norm(dd, axis=1)
        along = along[np.isfinite(along)]
        lo = min(0.0, float(along.min()) if along.size else 0.0) - 2 * self.size
        hi = max(float(np.hypot(*d)), float(along.max()) if along.size else 0.0) + 2 * self.size
        return np.vstack([a + lo * u, a + hi * u])


def scene_of(mech_or_result: Drawable, ropes: Iterable[str], length_unit: str) -> tuple[Scene, Any]:
    plan, positions, result = source(mech_or_result)
    return Scene(plan, positions, tuple(ropes), length_unit), result


@dataclass(frozen=True, slots=True)
class Overlays:
    """What is drawn over a mechanism's samples, found once for both renderers.

    Attributes
    ----------
    moving : list of int
        Points (indices) that move over the samples: their paths are drawn.
    dead : ndarray of int
        Samples at or next to a dead position.
    edges : list of int
        The last solved sample before each run that does not close, and the first after it.
    """

    moving: list[int]
    dead: np.ndarray
    edges: list[int]


def overlays(scene: Scene, table: Table) -> Overlays:
    """The paths, dead-position marks and non-closure edges of ``table`` drawn on ``scene``."""
    moving = np.nanmax(np.ptp(np.nan_to_num(scene.xy, nan=0.0), axis=0), axis=1)
    points = [i for i in range(len(scene.plan.points)) if moving[i] > 1e-9 * scene.extent]
    runs = failed_runs(table)
    n = len(scene)
    edges = sorted({a - 1 for a, _, _ in runs if a > 0} | {b + 1 for _, b, _ in runs if b + 1 < n})
    return Overlays(points, dead_samples(table), edges)
