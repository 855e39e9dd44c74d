"""Draw a mechanism with matplotlib: bodies, pins, ground hatching, cylinders, labels, paths.

The geometry comes from `Scene` (which draws what each part
looks like), computed once with NumPy and shared with the HTML report's plotly renderer, so
every view of a mechanism looks the same; this module only translates its primitives into
matplotlib artists, imported inside the drawing functions.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.outputs.cam_profiles import add_cam_profiles, move_cam_profiles
from excavkin.outputs.events import as_table
from excavkin.outputs.meshes import add_pitch_circles, move_pitch_circles
from excavkin.outputs.scene import Scene, overlays, scene_of, source
from excavkin.outputs.style import (
    CYLINDER_COLOR,
    DEAD_COLOR,
    FAIL_COLOR,
    GROUND_COLOR,
    ROD_COLOR,
    SLIDER_FILL,
    check_line_style,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Polygon
    from matplotlib.text import Annotation

    from excavkin.outputs.protocols import Drawable, Solved


class MechanismDrawing:
    """The artists of a mechanism drawn at one sample; `set_sample` moves them.

    Attributes
    ----------
    ax : matplotlib.axes.Axes
    fig : matplotlib.figure.Figure
        The figure of ``ax`` (to save or show it), as the other plots' handles have.
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
    circles : list of (int, Circle)
        The pitch circles of the gears and pinions, with their centres' point indices.
    profiles : list of Line2D
        The cams' profiles (a roller's pitch curve) and flat followers' faces
        (`excavkin.outputs.cam_profiles`).
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
        figure = ax.get_figure(root=True)
        assert figure is not None  # an axes is always on a figure
        self.fig: Figure = figure
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
        self.circles = add_pitch_circles(ax, scene, sample, z, alpha)
        self.profiles = add_cam_profiles(ax, scene, sample, z, alpha)
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
                facecolor=SLIDER_FILL,
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
        for rope in scene.rope_paths:
            poly = scene.rope_line(rope, sample)
            (line,) = ax.plot(
                poly[:, 0], poly[:, 1], color=CYLINDER_COLOR, lw=1.5, zorder=z + 2, alpha=alpha
            )
            self.cylinders[rope[0]] = (line, line)
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
        out += [c for _, c in self.circles]
        out += self.profiles
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
        for rope in sc.rope_paths:
            poly = sc.rope_line(rope, sample)
            self.cylinders[rope[0]][0].set_data(poly[:, 0], poly[:, 1])
        for sl in sc.sliders:
            block, g = self.sliders[sl[0]]
            block.set_xy(sc.slider_block(sl, sample)[:-1])
            guide = sc.slider_guide(sl, sample)
            g.set_data(guide[:, 0], guide[:, 1])
        move_pitch_circles(self.circles, sc, sample)
        move_cam_profiles(self.profiles, sc, sample)
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
    mech_or_result: Drawable,
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
    scene, _ = scene_of(mech_or_result, ropes, length_unit)
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
    """The artists of [`trace_paths`][excavkin.outputs.drawing.trace_paths].

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
    result: Solved,
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
        Axes to draw into; a new figure is made without one.
    length_unit : str, default "mm"
        Display unit of the axes' lengths.
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
    style = check_line_style(style)
    scene, res = scene_of(result, (), length_unit)
    if res is None:
        raise TypeError("trace_paths needs a result with samples, not a mechanism")
    names = list(scene.plan.points)
    over = overlays(scene, as_table(res))
    if points is None:
        points = [names[i] for i in over.moving]
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
        if over.dead.size:
            xy = scene.xy[over.dead][:, idx].reshape(-1, 2)
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
        if over.edges:
            xy = scene.xy[over.edges][:, idx].reshape(-1, 2)
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

    plan, positions, _ = source(mech_or_result)
    xy = convert(positions, "length", length_unit)
    return {p: xy[:, i] for i, p in enumerate(plan.points)}
