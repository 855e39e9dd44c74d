"""The report's mechanism section: the mechanism moving over the samples, in Plotly.

The plotly renderer of `Scene`: static traces (ground, paths of
the moving points, dead-position and non-closure marks), the traces that move (sliders, bodies,
cylinders, pins), one frame per shown sample, a values box and a play/pause slider.
"""

from __future__ import annotations

import html
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from excavkin.outputs.cam_profiles import cam_profiles
from excavkin.outputs.display_units import pretty_unit
from excavkin.outputs.meshes import circle_paths
from excavkin.outputs.protocols import Solved
from excavkin.outputs.report.data import ReportData, thin
from excavkin.outputs.scene import Overlays, Scene, overlays, source
from excavkin.outputs.style import (
    CYLINDER_COLOR,
    DEAD_COLOR,
    FAIL_COLOR,
    GROUND_COLOR,
    PATH_COLOR,
    ROD_COLOR,
    SLIDER_FILL,
    rgba,
)

__all__ = ["MAX_FRAMES", "mechanism_figure"]

#: most frames in the interactive view; longer results are thinned evenly
MAX_FRAMES = 361


def mechanism_figure(
    result: Solved,
    *,
    units: Mapping[str, str] | None = None,
    show: Iterable[str] | None = None,
    ropes: Iterable[str] = (),
    length_unit: str = "mm",
    max_frames: int = MAX_FRAMES,
    title: str | None = None,
) -> Any:
    """A Plotly figure of the mechanism with a slider over the samples and play/pause.

    Parameters
    ----------
    result : KinematicResult or a result with ``.kinematics`` and ``to_frame()``
    units : mapping of str to str, optional
        Display units of the shown values (see
        `DisplayUnits`).
    show : iterable of str, optional
        Columns whose current value is shown in the corner; default the varying inputs and the
        transmission angles.
    ropes : iterable of str
        Linear elements drawn as lines rather than cylinders.
    length_unit : str
    max_frames : int
        Most slider positions; longer results are thinned evenly.
    title : str, optional

    Returns
    -------
    plotly.graph_objects.Figure
        Its ``frames`` are named by sample index; trace ``"pins"`` holds the joint positions.
    """
    import plotly.graph_objects as go

    data = ReportData(result, units)
    plan, positions, _ = source(result)
    scene = Scene(plan, positions, tuple(ropes), length_unit)
    show_cols = _shown_columns(data, show)
    samples = thin(len(scene), max_frames)
    fig = go.Figure()
    for tr in _static_traces(scene, overlays(scene, data.table)):
        fig.add_trace(tr)
    first_dynamic = len(fig.data)
    i0 = int(samples[0])
    for tr in _dynamic_traces(scene, i0):
        fig.add_trace(tr)
    idx = list(range(first_dynamic, len(fig.data)))
    fig.frames = [
        go.Frame(
            data=_dynamic_traces(scene, int(i)),
            traces=idx,
            name=str(int(i)),
            layout={"annotations": [_note(data, show_cols, int(i))]},
        )
        for i in samples
    ]
    fig.update_layout(
        title=title,
        plot_bgcolor="white",
        hovermode="closest",
        legend={"orientation": "h", "yanchor": "bottom", "y": 1.0, "x": 1.0, "xanchor": "right"},
        annotations=[_note(data, show_cols, i0)],
        **_axes_layout(scene, length_unit),
        **_player(data, samples),
    )
    # the values box stands right of the plot, so it never hides the mechanism
    fig.layout.height = 700
    fig.layout.margin = {"l": 60, "r": 230, "t": 40 if title else 20, "b": 110}
    return fig


def _shown_columns(data: ReportData, show: Iterable[str] | None) -> list[str]:
    """The columns whose value the view shows: the moving inputs and transmission angles."""
    frame = data.table.frame
    if show is None:
        cols = data.moving_inputs()
        if "t" in frame:
            cols.insert(0, "t")
        return cols + data.table.of_quantity("transmission")[:4]
    cols = list(show)
    for c in cols:
        if c not in frame:
            raise KeyError(f"show: no column {c!r} in the result")
    return cols


def _xy(a: np.ndarray) -> tuple[list[float | None], list[float | None]]:
    """Coordinates as lists with None for NaN (JSON null: a gap)."""
    a = np.asarray(a, dtype=np.float64).reshape(-1, 2)
    xs = [None if not np.isfinite(v) else round(float(v), 6) for v in a[:, 0]]
    ys = [None if not np.isfinite(v) else round(float(v), 6) for v in a[:, 1]]
    return xs, ys


def _scatter(xy: np.ndarray, **kw: Any) -> Any:
    import plotly.graph_objects as go

    xs, ys = _xy(xy)
    return go.Scatter(x=xs, y=ys, **kw)


def _static_traces(scene: Scene, over: Overlays) -> list[Any]:
    """Ground symbols, the paths of the moving points, dead-position and non-closure marks."""
    plan = scene.plan
    tri, hatch = scene.ground_symbols()
    skip: dict[str, Any] = {"mode": "lines", "hoverinfo": "skip", "showlegend": False}
    traces = [
        _scatter(tri, name="ground", line={"color": GROUND_COLOR, "width": 1.6}, **skip),
        _scatter(hatch, name="hatching", line={"color": GROUND_COLOR, "width": 1.1}, **skip),
    ]
    for k, i in enumerate(over.moving):
        traces.append(
            _scatter(
                scene.xy[:, i],
                mode="lines",
                name="paths",
                legendgroup="paths",
                showlegend=k == 0,
                hovertemplate=f"path of {plan.points[i]}<extra></extra>",
                line={"color": PATH_COLOR, "width": 1, "dash": "dot"},
            )
        )
    if over.dead.size:
        traces.append(
            _scatter(
                scene.xy[over.dead][:, scene.pins].reshape(-1, 2),
                mode="markers",
                name="dead position",
                marker={"symbol": "x", "size": 10, "color": DEAD_COLOR},
            )
        )
    if over.edges:
        traces.append(
            _scatter(
                scene.xy[over.edges][:, scene.pins].reshape(-1, 2),
                mode="markers",
                name="last position before non-closure",
                marker={
                    "symbol": "circle-open",
                    "size": 12,
                    "color": FAIL_COLOR,
                    "line": {"width": 2},
                },
            )
        )
    return traces


def _dynamic_traces(scene: Scene, i: int) -> list[Any]:
    """Everything that moves, at sample ``i``: sliders, bodies, cylinders, pins and labels."""
    return (
        _circle_traces(scene, i)
        + _cam_traces(scene, i)
        + _slider_traces(scene, i)
        + _body_traces(scene, i)
        + _element_traces(scene, i)
        + _point_traces(scene, i)
    )


def _circle_traces(scene: Scene, i: int) -> list[Any]:
    """The pitch circles of the gears and pinions (`excavkin.outputs.meshes`)."""
    return [
        _scatter(
            path,
            mode="lines",
            showlegend=False,
            name="pitch circle",
            hoverinfo="skip",
            line={"color": "#595959", "width": 1, "dash": "dashdot"},
        )
        for path in circle_paths(scene, i)
    ]


def _cam_traces(scene: Scene, i: int) -> list[Any]:
    """The cams' profiles and flat faces (`excavkin.outputs.cam_profiles`)."""
    return [
        _scatter(
            path,
            mode="lines",
            showlegend=False,
            name="cam profile",
            hoverinfo="skip",
            line={"color": "#333333", "width": 1.5},
        )
        for path in cam_profiles(scene, i)
    ]


def _slider_traces(scene: Scene, i: int) -> list[Any]:
    traces = []
    for sl in scene.sliders:
        traces.append(
            _scatter(
                scene.slider_guide(sl, i),
                mode="lines",
                showlegend=False,
                name=f"{sl[0]} guide",
                hoverinfo="skip",
                line={"color": GROUND_COLOR, "width": 1.5, "dash": "dash"},
            )
        )
        traces.append(
            _scatter(
                scene.slider_block(sl, i),
                mode="lines",
                fill="toself",
                fillcolor=SLIDER_FILL,
                name=sl[0],
                showlegend=False,
                line={"color": GROUND_COLOR, "width": 1.5},
            )
        )
    return traces


def _body_traces(scene: Scene, i: int) -> list[Any]:
    traces = []
    for body in scene.bodies:
        hover = f"{body.name}<extra></extra>"
        if body.closed:
            style = {
                "fill": "toself",
                "fillcolor": rgba(body.color, 0.35),
                "line": {"color": body.color, "width": 3},
            }
        else:
            style = {"line": {"color": body.color, "width": 7}}
        traces.append(
            _scatter(
                scene.body_path(body, i), mode="lines", name=body.name, hovertemplate=hover, **style
            )
        )
    return traces


def _element_traces(scene: Scene, i: int) -> list[Any]:
    traces = []
    for el in scene.elements:
        barrel, rod = scene.element_segments(el, i)
        hover = f"{el.name}<extra></extra>"
        if el.style == "line":
            line = {"color": CYLINDER_COLOR, "width": 2}
            traces.append(
                _scatter(barrel, mode="lines", name=el.name, line=line, hovertemplate=hover)
            )
            continue
        traces.append(
            _scatter(
                rod,
                mode="lines",
                name=f"{el.name} rod",
                showlegend=False,
                line={"color": ROD_COLOR, "width": 5},
                hovertemplate=f"{el.name} (rod)<extra></extra>",
            )
        )
        line = {"color": CYLINDER_COLOR, "width": 13}
        traces.append(_scatter(barrel, mode="lines", name=el.name, line=line, hovertemplate=hover))
    return traces


def _point_traces(scene: Scene, i: int) -> list[Any]:
    names = scene.plan.points
    xy = scene.xy[i]
    where = "%{text}: (%{x:.1f}, %{y:.1f})<extra></extra>"
    return [
        _scatter(
            xy[scene.pins],
            mode="markers",
            name="pins",
            showlegend=False,
            text=[names[k] for k in scene.pins],
            hovertemplate=where,
            marker={"size": 10, "color": "white", "line": {"color": "black", "width": 2}},
        ),
        _scatter(
            xy[scene.dots],
            mode="markers",
            name="points",
            showlegend=False,
            text=[names[k] for k in scene.dots],
            hovertemplate=where,
            marker={"size": 6, "color": "black"},
        ),
        _scatter(
            xy + 0.3 * scene.size,
            mode="text",
            name="labels",
            showlegend=False,
            text=list(names),
            textposition="top right",
            hoverinfo="skip",
            textfont={"size": 13, "color": "#111111"},
        ),
    ]


def _note(data: ReportData, show_cols: list[str], i: int) -> dict[str, Any]:
    """The values box at sample ``i``, beside the plot (right of it)."""
    ok = bool(data.table.ok[i])
    text = data.values(show_cols, i)
    if not ok:
        text += ("<br>" if text else "") + f"<b>{html.escape(str(data.table.labels[i]))}</b>"
    return {
        "text": text or " ",
        "xref": "paper",
        "yref": "paper",
        "x": 1.02,
        "y": 1.0,
        "xanchor": "left",
        "yanchor": "top",
        "align": "left",
        "showarrow": False,
        "font": {
            "family": "DejaVu Sans Mono, monospace",
            "size": 13,
            "color": "black" if ok else FAIL_COLOR,
        },
        "bgcolor": "rgba(255,255,255,0.9)",
        "bordercolor": "#999999",
        "borderpad": 5,
    }


def _axes_layout(scene: Scene, length_unit: str) -> dict[str, Any]:
    """Equal-scale x and y axes around every sample of the mechanism."""
    finite = scene.xy[np.isfinite(scene.xy).all(axis=-1)]
    lo, hi = (finite.min(axis=0), finite.max(axis=0)) if finite.size else (np.zeros(2), np.ones(2))
    pad = 0.06 * scene.extent
    unit = pretty_unit(length_unit)
    grid = {"constrain": "domain", "gridcolor": "#ececec", "zeroline": False}
    return {
        "xaxis": {
            "title": {"text": f"x [{unit}]"},
            "range": [lo[0] - pad, hi[0] + pad],
            **grid,
        },
        "yaxis": {
            "title": {"text": f"y [{unit}]"},
            "range": [lo[1] - pad - 2.2 * scene.size, hi[1] + pad],
            "scaleanchor": "x",
            "scaleratio": 1,
            **grid,
        },
    }


def _player(data: ReportData, samples: np.ndarray) -> dict[str, Any]:
    """Play/pause buttons and a slider over the samples, labelled by the moving inputs."""
    still = {"duration": 0, "redraw": False}
    anim = {"mode": "immediate", "frame": still, "transition": {"duration": 0}}
    steps = [
        {"method": "animate", "args": [[str(int(i))], anim], "label": data.name(int(i))}
        for i in samples
    ]
    play = {
        "mode": "immediate",
        "fromcurrent": True,
        "frame": {"duration": 60, "redraw": False},
        "transition": {"duration": 0},
    }
    buttons = [
        {"label": "▶ Play", "method": "animate", "args": [None, play]},
        {"label": "❚❚ Pause", "method": "animate", "args": [[None], anim]},
    ]
    return {
        "updatemenus": [
            {
                "type": "buttons",
                "direction": "left",
                "showactive": False,
                "x": 0.0,
                "y": 0.0,
                "xanchor": "left",
                "yanchor": "top",
                "pad": {"t": 45, "r": 10},
                "buttons": buttons,
            }
        ],
        "sliders": [
            {
                "active": 0,
                "steps": steps,
                "x": 0.17,
                "len": 0.83,
                "y": 0.0,
                "yanchor": "top",
                "pad": {"t": 35, "b": 10},
                # the step labels name every moving input: too long for ticks, so only the
                # current one is shown, above the slider
                "font": {"color": "rgba(0,0,0,0)"},
                "currentvalue": {"prefix": "", "font": {"size": 14, "color": "#111111"}},
            }
        ],
    }
