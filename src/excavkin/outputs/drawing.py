"""Draw a mechanism: bodies, pins, ground hatching, cylinders as barrel + rod, labels.

The geometry of a drawing is computed here with NumPy alone (:class:`Scene`), then rendered by
matplotlib (:func:`draw_mechanism`, :func:`trace_paths`) or by the HTML report (Plotly), so every
view of a mechanism looks the same::

        cylinder (linear driver, barrel at its first point)      binary body   ternary body
      p o===[##########]-------------o q                        o-------o      o-----o
            barrel          rod                                                 \\###/
                                                                                 \\#/
      ground pivot:   o        slider:  [=o=]  on its guide                       o
                     /_\\
                    //////

matplotlib is imported only inside the drawing functions; :class:`Scene` needs only NumPy.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.lines import Line2D
    from matplotlib.patches import Polygon
    from matplotlib.text import Annotation

#: body colours (matplotlib's "tab10" without its grey), cycled over the moving bodies
BODY_COLORS = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#bcbd22",
    "#17becf",
)
CYLINDER_COLOR = "#4d4d4d"
ROD_COLOR = "#a8a8a8"
GROUND_COLOR = "#333333"
FAIL_COLOR = "#d62728"
DEAD_COLOR = "#9467bd"


def _source(mech_or_result: Any) -> tuple[Any, np.ndarray, Any]:
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
        Linear elements to draw as plain lines rather than cylinders.
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


def _scene(mech_or_result: Any, ropes: Iterable[str], length_unit: str) -> tuple[Scene, Any]:
    plan, positions, result = _source(mech_or_result)
    return Scene(plan, positions, tuple(ropes), length_unit), result


class MechanismDrawing:
    """The artists of a mechanism drawn at one sample; :meth:`set_sample` moves them.

    Attributes
    ----------
    ax : matplotlib.axes.Axes
    scene : Scene
    sample : int
        The sample shown.
    bodies : dict of str to Line2D or Polygon
        A line for a binary body, the outline of a polygon for a body of three or more points.
    fills : dict of str to Polygon
        The translucent fill of each polygon body.
    cylinders : dict of str to (Line2D, Line2D)
        Barrel and rod of each linear element (the same line twice for a rope).
    pins : Line2D
        Joint markers; ``pins.get_data()`` are their positions in display units.
    dots : Line2D
        Other points.
    labels : dict of str to Annotation
        Point labels (empty when drawn without labels).
    ground : tuple of Line2D
        Pivot triangles and hatching.
    sliders : dict of str to (Polygon, Line2D)
        Block and guide of each slider.
    ghosts : list of MechanismDrawing
        Fainter drawings of the other samples asked for.
    """

    def __init__(
        self,
        ax: Axes,
        scene: Scene,
        sample: int,
        *,
        labels: bool,
        alpha: float,
        zorder: float,
        show_ground: bool,
    ) -> None:
        from matplotlib.patches import Polygon

        self.ax = ax
        self.scene = scene
        self.sample = sample
        self.bodies: dict[str, Line2D | Polygon] = {}
        self.cylinders: dict[str, tuple[Line2D, Line2D]] = {}
        self.sliders: dict[str, tuple[Polygon, Line2D]] = {}
        self.labels: dict[str, Annotation] = {}
        self.ghosts: list[MechanismDrawing] = []
        self.fills: dict[str, Polygon] = {}
        z = zorder
        if show_ground and (scene.ground_pivots or scene.sliders):
            tri, hatch = scene.ground_symbols()
            (t,) = ax.plot(tri[:, 0], tri[:, 1], color=GROUND_COLOR, lw=1.3, zorder=z, alpha=alpha)
            (h,) = ax.plot(
                hatch[:, 0], hatch[:, 1], color=GROUND_COLOR, lw=1.0, zorder=z, alpha=alpha
            )
            self.ground: tuple[Line2D, ...] = (t, h)
        else:
            self.ground = ()
        for sl in scene.sliders:
            guide = scene.slider_guide(sl, sample)
            (g,) = ax.plot(
                guide[:, 0],
                guide[:, 1],
                color=GROUND_COLOR,
                lw=1.2,
                ls="--",
                zorder=z + 0.5,
                alpha=alpha,
            )
            block = Polygon(
                scene.slider_block(sl, sample),
                closed=True,
                facecolor="#dddddd",
                edgecolor=GROUND_COLOR,
                lw=1.3,
                zorder=z + 3,
                alpha=alpha,
            )
            ax.add_patch(block)
            self.sliders[sl[0]] = (block, g)
        for body in scene.bodies:
            path = scene.body_path(body, sample)
            if body.closed:
                patch = Polygon(
                    path[:-1],
                    closed=True,
                    facecolor=body.color,
                    edgecolor=body.color,
                    alpha=0.35 * alpha,
                    lw=2.5,
                    zorder=z + 1,
                )
                ax.add_patch(patch)
                edge = Polygon(
                    path[:-1],
                    closed=True,
                    fill=False,
                    edgecolor=body.color,
                    lw=2.5,
                    zorder=z + 1,
                    alpha=alpha,
                )
                ax.add_patch(edge)
                self.bodies[body.name] = edge
                self.fills[body.name] = patch
            else:
                (line,) = ax.plot(
                    path[:, 0],
                    path[:, 1],
                    color=body.color,
                    lw=5,
                    solid_capstyle="round",
                    zorder=z + 1,
                    alpha=alpha,
                    label=body.name,
                )
                self.bodies[body.name] = line
        for el in scene.elements:
            barrel, rod = scene.element_segments(el, sample)
            if el.style == "line":
                (line,) = ax.plot(
                    barrel[:, 0],
                    barrel[:, 1],
                    color=CYLINDER_COLOR,
                    lw=1.5,
                    zorder=z + 2,
                    alpha=alpha,
                )
                self.cylinders[el.name] = (line, line)
                continue
            (r,) = ax.plot(
                rod[:, 0],
                rod[:, 1],
                color=ROD_COLOR,
                lw=3.5,
                zorder=z + 2,
                solid_capstyle="butt",
                alpha=alpha,
            )
            (b,) = ax.plot(
                barrel[:, 0],
                barrel[:, 1],
                color=CYLINDER_COLOR,
                lw=9,
                zorder=z + 2.1,
                solid_capstyle="butt",
                alpha=alpha,
            )
            self.cylinders[el.name] = (b, r)
        xy = scene.xy[sample]
        (self.pins,) = ax.plot(
            xy[scene.pins, 0],
            xy[scene.pins, 1],
            "o",
            ms=7,
            mfc="white",
            mec="black",
            mew=1.5,
            zorder=z + 4,
            alpha=alpha,
            ls="none",
        )
        (self.dots,) = ax.plot(
            xy[scene.dots, 0],
            xy[scene.dots, 1],
            "o",
            ms=4,
            color="black",
            zorder=z + 4,
            alpha=alpha,
            ls="none",
        )
        if labels:
            for i, p in enumerate(scene.plan.points):
                self.labels[p] = ax.annotate(
                    p,
                    xy[i],
                    xytext=(5, 5),
                    textcoords="offset points",
                    fontsize=10,
                    zorder=z + 5,
                    alpha=alpha,
                    bbox={"boxstyle": "round,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.7},
                )

    def artists(self) -> list[Any]:
        """Every artist that moves with the sample (for blitting)."""
        out: list[Any] = [*self.bodies.values(), *self.fills.values()]
        for b, r in self.cylinders.values():
            out += [b, r] if b is not r else [b]
        for block, g in self.sliders.values():
            out += [block, g]
        out += [self.pins, self.dots, *self.labels.values()]
        return out

    def set_sample(self, sample: int) -> list[Any]:
        """Move the drawing to ``sample``; return the artists changed.

        Parameters
        ----------
        sample : int
            Index into the result the drawing was made from.
        """
        sc = self.scene
        if not -len(sc) <= sample < len(sc):
            raise IndexError(f"sample {sample} out of range for a result of {len(sc)} samples")
        self.sample = sample
        fills = self.fills
        for body in sc.bodies:
            path = sc.body_path(body, sample)
            art = self.bodies[body.name]
            if body.closed:
                art.set_xy(path[:-1])  # type: ignore[union-attr]
                fills[body.name].set_xy(path[:-1])
            else:
                art.set_data(path[:, 0], path[:, 1])  # type: ignore[union-attr]
        for el in sc.elements:
            barrel, rod = sc.element_segments(el, sample)
            b, r = self.cylinders[el.name]
            b.set_data(barrel[:, 0], barrel[:, 1])
            if r is not b:
                r.set_data(rod[:, 0], rod[:, 1])
        for sl in sc.sliders:
            block, g = self.sliders[sl[0]]
            block.set_xy(sc.slider_block(sl, sample)[:-1])
            guide = sc.slider_guide(sl, sample)
            g.set_data(guide[:, 0], guide[:, 1])
        xy = sc.xy[sample]
        self.pins.set_data(xy[sc.pins, 0], xy[sc.pins, 1])
        self.dots.set_data(xy[sc.dots, 0], xy[sc.dots, 1])
        for i, p in enumerate(sc.plan.points):
            if p in self.labels:
                self.labels[p].xy = tuple(xy[i])
                self.labels[p].set_visible(bool(np.isfinite(xy[i]).all()))
        return self.artists()


def _axes(ax: Axes | None) -> Axes:
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    _, new = plt.subplots(figsize=(7, 5.5), layout="constrained")
    return new


def _frame_axes(ax: Axes, scene: Scene) -> None:
    from excavkin.outputs.display_units import pretty_unit

    ax.set_aspect("equal", adjustable="datalim")
    unit = pretty_unit(scene.length_unit)
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.grid(True, color="#e5e5e5", lw=0.8)
    ax.set_axisbelow(True)
    finite = scene.xy[np.isfinite(scene.xy).all(axis=-1)]
    if finite.size:
        lo, hi = finite.min(axis=0), finite.max(axis=0)
        pad = 0.06 * scene.extent
        ax.update_datalim(
            [(lo[0] - pad, lo[1] - pad - 2.2 * scene.size), (hi[0] + pad, hi[1] + pad)]
        )
        ax.autoscale_view()


def draw_mechanism(
    mech_or_result: Any,
    sample: int | Sequence[int] = 0,
    *,
    ax: Axes | None = None,
    labels: bool = True,
    ropes: Iterable[str] = (),
    length_unit: str = "mm",
    show_ground: bool = True,
    ghost_alpha: float = 0.25,
) -> MechanismDrawing:
    """Draw a mechanism at one sample (or several, overlaid) of a result, or at its sketch.

    Parameters
    ----------
    mech_or_result : Mechanism, KinematicResult or a result with ``.kinematics``
        A mechanism is drawn at its assembled sketch (``sample`` must be 0).
    sample : int or sequence of int
        Sample(s) to draw. With several, the last is drawn fully and the others faded
        (``ghost_alpha``), without labels.
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; a new figure is made without one.
    labels : bool
        Write the point names.
    ropes : iterable of str
        Linear elements drawn as thin lines (ropes, struts) instead of cylinders.
    length_unit : str
        Unit of the axes, ``"mm"`` by default.
    show_ground : bool
        Draw the ground pivots with their hatching.
    ghost_alpha : float
        Opacity of the faded samples.

    Returns
    -------
    MechanismDrawing
        Its artists; ``set_sample(i)`` moves the drawing.

    Raises
    ------
    IndexError
        If a sample is out of range.

    Examples
    --------
    >>> import numpy as np, excavkin
    >>> from excavkin.outputs.drawing import draw_mechanism
    >>> mech = excavkin.load(excavkin.example_path("fourbar"))
    >>> res = mech.solve({"crank": np.radians(np.arange(0, 360, 30))})
    >>> drawing = draw_mechanism(res, sample=3)
    >>> [round(float(v), 3) for v in drawing.pins.get_data()[0][:2]]
    [0.0, 0.0]
    """
    scene, _ = _scene(mech_or_result, ropes, length_unit)
    samples = [sample] if isinstance(sample, int | np.integer) else list(sample)
    if not samples:
        raise ValueError("sample: give at least one sample")
    for s in samples:
        if not -len(scene) <= int(s) < len(scene):
            raise IndexError(f"sample {s} out of range for a result of {len(scene)} samples")
    ax = _axes(ax)
    ghosts = [
        MechanismDrawing(
            ax, scene, int(s), labels=False, alpha=ghost_alpha, zorder=2, show_ground=False
        )
        for s in samples[:-1]
    ]
    drawing = MechanismDrawing(
        ax, scene, int(samples[-1]), labels=labels, alpha=1.0, zorder=10, show_ground=show_ground
    )
    drawing.ghosts = ghosts
    _frame_axes(ax, scene)
    return drawing


@dataclass
class TracedPaths:
    """The artists of :func:`trace_paths`.

    Attributes
    ----------
    ax : matplotlib.axes.Axes
    lines : dict of str to Line2D
        One path per point; ``get_data()`` are its coordinates in display units.
    dead : Line2D or None
        Markers at dead positions.
    failures : Line2D or None
        Markers at the last solved position before each run of samples that does not close.
    """

    ax: Axes
    lines: dict[str, Line2D]
    dead: Line2D | None = None
    failures: Line2D | None = None


def trace_paths(
    result: Any,
    points: Sequence[str] | None = None,
    *,
    ax: Axes | None = None,
    length_unit: str = "mm",
    mark: bool = True,
    **style: Any,
) -> TracedPaths:
    """Draw the paths traced by points over a result's samples.

    Parameters
    ----------
    result : KinematicResult or a result with ``.kinematics``
    points : sequence of str, optional
        Point names; default every point that moves.
    ax : matplotlib.axes.Axes, optional
    length_unit : str
    mark : bool
        Mark dead positions (purple ×) and the last solved position before samples that do not
        close (red ○).
    **style
        matplotlib ``Line2D`` properties for the paths (``lw``, ``ls``, ``alpha``, ...).

    Returns
    -------
    TracedPaths

    Raises
    ------
    TypeError
        On a keyword that is not a ``Line2D`` property.
    KeyError
        On an unknown point.
    """
    from excavkin.outputs.events import dead_samples, failed_runs
    from excavkin.outputs.plots import check_line_style

    style = check_line_style(style)
    scene, res = _scene(result, (), length_unit)
    if res is None:
        raise TypeError("trace_paths needs a result with samples, not a mechanism")
    names = list(scene.plan.points)
    if points is None:
        moving = np.nanmax(np.ptp(np.nan_to_num(scene.xy, nan=0.0), axis=0), axis=1)
        points = [p for i, p in enumerate(names) if moving[i] > 1e-9 * scene.extent]
    for p in points:
        if p not in names:
            raise KeyError(f"no point {p!r} (points: {', '.join(names)})")
    ax = _axes(ax)
    lines: dict[str, Line2D] = {}
    for p in points:
        i = names.index(p)
        kw = {"linewidth": 1.4, "label": f"path of {p}", **style}
        (lines[p],) = ax.plot(scene.xy[:, i, 0], scene.xy[:, i, 1], **kw)
    out = TracedPaths(ax, lines)
    if mark and points:
        idx = [names.index(p) for p in points]
        dead = dead_samples(res)
        if dead.size:
            xy = scene.xy[dead][:, idx].reshape(-1, 2)
            (out.dead,) = ax.plot(
                xy[:, 0],
                xy[:, 1],
                "x",
                color=DEAD_COLOR,
                ms=9,
                mew=2.2,
                ls="none",
                label="dead position",
                zorder=20,
            )
        last = [a - 1 for a, _, _ in failed_runs(res) if a > 0]
        last += [b + 1 for _, b, _ in failed_runs(res) if b + 1 < len(scene)]
        if last:
            xy = scene.xy[sorted(set(last))][:, idx].reshape(-1, 2)
            (out.failures,) = ax.plot(
                xy[:, 0],
                xy[:, 1],
                "o",
                mfc="none",
                mec=FAIL_COLOR,
                ms=10,
                mew=2,
                ls="none",
                label="last position before non-closure",
                zorder=20,
            )
    _frame_axes(ax, scene)
    return out


def positions_in(mech_or_result: Any, length_unit: str = "mm") -> Mapping[str, np.ndarray]:
    """Point positions in ``length_unit``: ``{point: array of shape (n, 2)}``."""
    from excavkin.outputs.display_units import convert

    plan, positions, _ = _source(mech_or_result)
    xy = convert(positions, "length", length_unit)
    return {p: xy[:, i] for i, p in enumerate(plan.points)}
