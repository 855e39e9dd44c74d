"""A self-contained HTML report of a solved mechanism.

One file, no network needed to view it: the model summary and solve plan, an interactive view of
the mechanism with a slider over the samples and play/pause, the main curves (zoomable), the
warnings (dead positions, non-closure, shocks, low transmission angles) and the result table as
a download. The interactive parts are Plotly figures; plotly.js is embedded in the file.

>>> import excavkin
>>> from excavkin.outputs.report import default_sweep, write_report
>>> mech = excavkin.load(excavkin.example_path("fourbar"))
>>> sweep = default_sweep(mech)
>>> round(float(sweep["crank"][-1] - sweep["crank"][0]), 4)   # a full turn of the crank
6.2832
>>> # write_report(mech, mech.solve(sweep), "fourbar.html")

Plotly is imported inside the functions only.
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from string import Template
from typing import Any

import numpy as np

from excavkin.outputs.display_units import KIND_NAMES, DisplayUnits, pretty_unit
from excavkin.outputs.events import (
    Event,
    ShockLike,
    Table,
    as_table,
    dead_samples,
    failed_runs,
    find_events,
    varies,
)
from excavkin.outputs.protocols import MechanismLike, Solved, TableData
from excavkin.outputs.scene import Overlays, Scene, overlays, source
from excavkin.outputs.style import (
    BODY_COLORS,
    CYLINDER_COLOR,
    DEAD_COLOR,
    FAIL_COLOR,
    GROUND_COLOR,
    PATH_COLOR,
    ROD_COLOR,
)

#: samples in a default sweep of a rotary input (a full turn in 2° steps)
N_ROTARY = 181
#: samples in a default sweep of a linear input
N_LINEAR = 121
#: a linear input's default stroke, as fractions of its sketch length (a ratio of about 1.56,
#: a usual extended/retracted ratio of hydraulic cylinders)
STROKE = (0.8, 1.25)
#: most frames in the interactive view; longer results are thinned evenly
MAX_FRAMES = 361
#: most samples per curve; longer results are thinned evenly
MAX_CURVE_POINTS = 5000

HTML_SUFFIXES = (".html", ".htm")


# --------------------------------------------------------------------------------------- sweep
def _run_containing(ok: np.ndarray, i0: int, circular: bool) -> tuple[int, int] | None:
    """Inclusive (start, stop) of the run of True containing ``i0``; stop < start if it wraps."""
    n = ok.size
    if not ok[i0]:
        return None
    if circular and ok.all():
        return 0, n - 1
    lo = i0
    while True:
        nxt = lo - 1
        if nxt < 0:
            if not circular:
                break
            nxt += n
        if not ok[nxt] or nxt == i0:
            break
        lo = nxt
    hi = i0
    while True:
        nxt = hi + 1
        if nxt >= n:
            if not circular:
                break
            nxt -= n
        if not ok[nxt] or nxt == i0:
            break
        hi = nxt
    return lo, hi


def _passable(code: np.ndarray) -> np.ndarray:
    """Samples a sweep may pass: solved, or exactly at a dead position it can go through."""
    from excavkin.kinematics.kernels import Code

    return np.asarray((code == Code.OK) | (code == Code.SINGULAR) | (code == Code.IMPRECISE))


def default_sweep(mech: MechanismLike, n: int | None = None) -> dict[str, np.ndarray]:
    """A sensible sweep of every input of a mechanism, all moving together.

    * A rotary input turns a full turn, 0 to 2π (from the sketch value instead if 0 is a dead
      position), if the mechanism closes all the way round;
      otherwise it sweeps the range around the sketch over which it closes (found by probing
      720 positions), from one dead position to the other.
    * A linear input (a cylinder, a rope) sweeps its ``stroke`` when the model gives one,
      else from 0.8 to 1.25 times its sketch length (`STROKE`), cut to the range around
      the sketch over which the mechanism closes.

    Each input's range is found with the others held at their sketch values.

    Parameters
    ----------
    mech : Mechanism
    n : int, optional
        Samples; default 181 when any input is rotary, else 121.

    Returns
    -------
    dict of str to ndarray, shape (n,)
        Input values, SI, for [`Mechanism.solve`][excavkin.mechanism.Mechanism.solve]. Empty for a
        mechanism without inputs.
    """
    names = list(mech.inputs)
    if not names:
        return {}
    kinds = {name: mech.input_kind(name) for name in names}
    if n is None:
        n = N_ROTARY if "angle" in kinds.values() else N_LINEAR
    if n < 2:
        raise ValueError(f"n: a sweep needs at least 2 samples, got {n}")
    sketch = mech.sketch_values()
    out: dict[str, np.ndarray] = {}
    for name in names:
        q0 = sketch[name]
        if kinds[name] == "angle":
            m = 720
            probe = q0 + np.linspace(0.0, 2 * np.pi, m, endpoint=False)
            ok = _passable(mech.solve({name: probe}).status.code)
            run = _run_containing(ok, 0, circular=True)
            if run is None or run == (0, m - 1):
                # a full turn: from the reference orientation, or from the sketch if the
                # reference orientation is a dead position
                start = 0.0 if mech.solve({name: [0.0]}).status.all_ok else q0
                out[name] = start + np.linspace(0.0, 2 * np.pi, n)
                continue
            lo, hi = run
            # the run starts at or before the sketch (index 0: lo > 0 wraps round) and ends after
            start = probe[lo] - (2 * np.pi if lo > 0 else 0.0)
            out[name] = np.linspace(start, probe[hi], n)
        else:
            m = 401
            stroke = next((d.stroke for d in mech.model.linear if d.name == name), None)
            if stroke is not None:  # the cylinder's own stroke, pin to pin
                probe = np.linspace(stroke[0], stroke[1], m)
            else:
                probe = q0 * np.linspace(STROKE[0], STROKE[1], m)
            i0 = int(np.argmin(np.abs(probe - q0)))
            ok = _passable(mech.solve({name: probe}).status.code)
            run = _run_containing(ok, i0, circular=False)
            lo, hi = run if run is not None else (0, m - 1)
            out[name] = np.linspace(probe[lo], probe[hi], n)
    return out


def solve_default(mech: MechanismLike, n: int | None = None) -> Any:
    """``mech.solve(default_sweep(mech, n))``: the result ``excavkin demo`` reports."""
    return mech.solve(default_sweep(mech, n))


# ------------------------------------------------------------------------------------- helpers
def _thin(n: int, most: int) -> np.ndarray:
    if n <= most:
        return np.arange(n)
    return np.unique(np.round(np.linspace(0, n - 1, most)).astype(np.int64))


def _xy(a: np.ndarray) -> tuple[list[float | None], list[float | None]]:
    """Coordinates as lists with None for NaN (JSON null: a gap)."""
    a = np.asarray(a, dtype=np.float64).reshape(-1, 2)
    xs = [None if not np.isfinite(v) else round(float(v), 6) for v in a[:, 0]]
    ys = [None if not np.isfinite(v) else round(float(v), 6) for v in a[:, 1]]
    return xs, ys


def _fmt(v: float, unit: str) -> str:
    if not np.isfinite(v):
        return "—"
    pu = pretty_unit(unit)
    return f"{v:.4g}{pu}" if pu == "°" else (f"{v:.4g} {pu}" if pu else f"{v:.4g}")


class _Context:
    """What the pieces of a report share: the table, display units, the x column."""

    def __init__(self, result: TableData, units: Mapping[str, str] | None) -> None:
        from excavkin.outputs.plots import default_x

        self.result = result
        self.table: Table = as_table(result)
        self.units = DisplayUnits(units, self.table.kinds)
        self.x = default_x(self.table)
        self.xd = self.units(self.x)
        if self.x == "sample":
            self.xv = np.arange(len(self.table.frame), dtype=np.float64)
        else:
            self.xv = np.asarray(
                self.xd.convert(self.table.frame[self.x].to_numpy(dtype=np.float64))
            )

    def x_name(self) -> str:
        if self.x == "t":
            return "t"
        if self.x == "sample":
            return "sample"
        return self.table.describe(self.x).owner

    def moving_inputs(self) -> list[str]:
        """The value columns of the inputs that vary over the result (the x column first)."""
        frame = self.table.frame
        names = [c for c in self.table.of_quantity("value", "driver") if varies(frame[c])]
        if self.table.plan is not None:
            inputs = {f"{n}.value" for n in self.table.plan.inputs}
            names = [c for c in names if c in inputs]
        return sorted(names, key=lambda c: c != self.x)

    def name(self, i: int) -> str:
        """Sample ``i`` in words, by every input that moves: ``"crank = 35°"``."""
        if self.x == "t":
            return f"t = {_fmt(float(self.xv[i]), self.xd.unit)}"
        moving = self.moving_inputs()
        if not moving:
            return f"sample {i}"
        return ", ".join(
            f"{self.table.describe(c).owner} = {_fmt(self._display(c, i), self.units(c).unit)}"
            for c in moving
        )

    def _display(self, column: str, i: int) -> float:
        d = self.units(column)
        return float(d.convert(self.table.frame[column].to_numpy(dtype=np.float64)[i]))

    def values(self, columns: Iterable[str], i: int) -> str:
        parts = []
        for c in columns:
            described = self.table.describe(c)
            label = described.owner if described.quantity == "value" else c
            parts.append(f"{label} = {_fmt(self._display(c, i), self.units(c).unit)}")
        return "<br>".join(parts)


# ------------------------------------------------------------------------------ mechanism view
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

    ctx = _Context(result, units)
    plan, positions, _ = source(result)
    scene = Scene(plan, positions, tuple(ropes), length_unit)
    show_cols = _shown_columns(ctx, show)
    samples = _thin(len(scene), max_frames)
    fig = go.Figure()
    for tr in _static_traces(scene, overlays(scene, ctx.table)):
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
            layout={"annotations": [_note(ctx, show_cols, int(i))]},
        )
        for i in samples
    ]
    fig.update_layout(
        title=title,
        plot_bgcolor="white",
        hovermode="closest",
        legend={"orientation": "h", "yanchor": "bottom", "y": 1.0, "x": 1.0, "xanchor": "right"},
        annotations=[_note(ctx, show_cols, i0)],
        **_axes_layout(scene, length_unit),
        **_player(ctx, samples),
    )
    # the values box stands right of the plot, so it never hides the mechanism
    fig.layout.height = 700
    fig.layout.margin = {"l": 60, "r": 230, "t": 40 if title else 20, "b": 110}
    return fig


def _shown_columns(ctx: _Context, show: Iterable[str] | None) -> list[str]:
    """The columns whose value the view shows: the moving inputs and transmission angles."""
    frame = ctx.table.frame
    if show is None:
        cols = ctx.moving_inputs()
        if "t" in frame:
            cols.insert(0, "t")
        return cols + ctx.table.of_quantity("transmission")[:4]
    cols = list(show)
    for c in cols:
        if c not in frame:
            raise KeyError(f"show: no column {c!r} in the result")
    return cols


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
        _slider_traces(scene, i)
        + _body_traces(scene, i)
        + _element_traces(scene, i)
        + _point_traces(scene, i)
    )


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
                fillcolor="#dddddd",
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
                "fillcolor": _rgba(body.color, 0.35),
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


def _note(ctx: _Context, show_cols: list[str], i: int) -> dict[str, Any]:
    """The values box at sample ``i``, beside the plot (right of it)."""
    ok = bool(ctx.table.ok[i])
    text = ctx.values(show_cols, i)
    if not ok:
        text += ("<br>" if text else "") + f"<b>{html.escape(str(ctx.table.labels[i]))}</b>"
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


def _player(ctx: _Context, samples: np.ndarray) -> dict[str, Any]:
    """Play/pause buttons and a slider over the samples, labelled by the moving inputs."""
    still = {"duration": 0, "redraw": False}
    anim = {"mode": "immediate", "frame": still, "transition": {"duration": 0}}
    steps = [
        {"method": "animate", "args": [[str(int(i))], anim], "label": ctx.name(int(i))}
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


def _curves_note(result: Solved, in_time: bool) -> str:
    """How to read the rates: real ones, or per unit input rate (transfer functions)."""
    if in_time:
        return "Velocities and accelerations are in time, from the motion laws' rates."
    kin: Any = getattr(result, "kinematics", result)
    rates = np.asarray(getattr(kin, "input_rates", np.ones((0, 0))))
    accels = np.asarray(getattr(kin, "input_accels", np.zeros((0, 0))))
    unit_rates = rates.size == 0 or bool(np.all((rates == 1.0) | (rates == 0.0)))
    if unit_rates and not np.any(accels):
        return (
            "Velocities and accelerations are per unit input rate (the transfer functions "
            "dφ/dq and d²φ/dq²): no input rate was given."
        )
    return "Velocities and accelerations are for the input rates and accelerations given."


def _rgba(hex_color: str, alpha: float) -> str:
    h = hex_color.lstrip("#")
    r, g, b = (int(h[k : k + 2], 16) for k in (0, 2, 4))
    return f"rgba({r},{g},{b},{alpha})"


# ----------------------------------------------------------------------------------- curves
def curves_figure(
    result: Solved,
    y: Iterable[str] | None = None,
    *,
    units: Mapping[str, str] | None = None,
    max_points: int = MAX_CURVE_POINTS,
) -> Any:
    """A Plotly figure of result columns, one zoomable panel per kind, sharing the x axis.

    Parameters
    ----------
    result : result or DataFrame
    y : iterable of str, optional
        Default `excavkin.outputs.plots.main_columns`.
    units : mapping of str to str, optional
    max_points : int
        Most samples per curve; longer results are thinned evenly.

    Returns
    -------
    plotly.graph_objects.Figure
    """
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    from excavkin.outputs.plots import main_columns

    ctx = _Context(result, units)
    cols = list(y) if y is not None else main_columns(ctx.table)
    groups: dict[tuple[str, str], list[str]] = {}
    for d in ctx.units.all(cols):
        groups.setdefault((d.kind, d.unit), []).append(d.column)
    rows = max(len(groups), 1)
    fig = make_subplots(rows=rows, cols=1, shared_xaxes=True, vertical_spacing=0.035)
    keep = _thin(len(ctx.xv), max_points)
    xs = [float(v) if np.isfinite(v) else None for v in ctx.xv[keep]]
    palette = BODY_COLORS
    for r, ((kind, unit), group) in enumerate(groups.items(), start=1):
        for k, c in enumerate(group):
            d = ctx.units(c)
            v = d.values(ctx.table.frame[c].to_numpy(dtype=np.float64))[keep]
            fig.add_trace(
                go.Scatter(
                    x=xs,
                    y=[float(a) if np.isfinite(a) else None for a in v],
                    mode="lines",
                    name=c,
                    line={"width": 2, "color": palette[k % len(palette)]},
                    hovertemplate=f"{c}: %{{y:.4g}}<extra></extra>",
                    legendgroup=str(r),
                ),
                row=r,
                col=1,
            )
        name = KIND_NAMES.get(kind, "Value")
        fig.update_yaxes(title_text=f"{name} [{pretty_unit(unit)}]" if unit else name, row=r, col=1)
    step = float(np.nanmedian(np.abs(np.diff(ctx.xv)))) if ctx.xv.size > 1 else 0.0
    first = True
    for a, b, _ in failed_runs(ctx.table):
        seg = ctx.xv[a : b + 1]
        fig.add_vrect(
            x0=float(np.nanmin(seg)) - step / 2,
            x1=float(np.nanmax(seg)) + step / 2,
            fillcolor=FAIL_COLOR,
            opacity=0.12,
            line_width=0,
            row="all",
            col=1,
        )
        if first:
            fig.add_trace(
                go.Scatter(
                    x=[None],
                    y=[None],
                    mode="lines",
                    name="does not close",
                    line={"color": FAIL_COLOR, "width": 8},
                    opacity=0.3,
                )
            )
            first = False
    dead = dead_samples(ctx.table)
    for i in dead:
        fig.add_vline(
            x=float(ctx.xv[i]),
            line={"color": DEAD_COLOR, "dash": "dash", "width": 1.5},
            row="all",
            col=1,
        )
    if dead.size:
        fig.add_trace(
            go.Scatter(
                x=[None],
                y=[None],
                mode="lines",
                name="dead position",
                line={"color": DEAD_COLOR, "dash": "dash"},
            )
        )
    x_title = (
        "Time [s]"
        if ctx.x == "t"
        else ("Sample" if ctx.x == "sample" else f"{ctx.x_name()} [{pretty_unit(ctx.xd.unit)}]")
    )
    fig.update_xaxes(title_text=x_title, row=rows, col=1)
    fig.update_xaxes(gridcolor="#ececec", zeroline=False)
    fig.update_yaxes(gridcolor="#ececec", zeroline=False)
    fig.update_layout(
        height=90 + 230 * rows,
        margin={"l": 70, "r": 20, "t": 20, "b": 50},
        plot_bgcolor="white",
        hovermode="x unified",
        legend={"orientation": "v", "x": 1.01, "y": 1.0},
    )
    return fig


# ----------------------------------------------------------------------------------- the page
def _sweep_text(ctx: _Context) -> str:
    plan = ctx.table.plan
    frame = ctx.table.frame
    n = len(frame)
    if plan is None:
        return f"{n} samples."
    parts = []
    for name in plan.inputs:
        c = f"{name}.value"
        d = ctx.units(c)
        v = np.asarray(d.convert(frame[c].to_numpy(dtype=np.float64)))
        if varies(v):
            parts.append(f"{name} from {_fmt(float(v[0]), d.unit)} to {_fmt(float(v[-1]), d.unit)}")
        else:
            parts.append(f"{name} held at {_fmt(float(v[0]), d.unit)}")
    return f"{n} samples: {'; '.join(parts)}." if parts else f"{n} samples."


def _warnings_html(events: list[Event]) -> str:
    if not events:
        return (
            '<li class="ok"><span class="tag">OK</span>No dead positions, non-closure, shocks '
            "or low transmission angles found.</li>"
        )
    return "".join(
        f'<li class="{e.severity}"><span class="tag">{html.escape(e.kind)}</span>'
        f"{html.escape(e.message)}</li>"
        for e in events
    )


def _extremes_html(ctx: _Context, cols: list[str]) -> str:
    rows = []
    for c in cols:
        d = ctx.units(c)
        v = d.values(ctx.table.frame[c].to_numpy(dtype=np.float64))
        if not np.isfinite(v).any():
            continue
        i, j = int(np.nanargmin(v)), int(np.nanargmax(v))
        rows.append(
            f"<tr><td>{html.escape(c)}</td><td>{html.escape(pretty_unit(d.unit))}</td>"
            f'<td class="num">{v[i]:.5g}</td><td>{html.escape(ctx.name(i))}</td>'
            f'<td class="num">{v[j]:.5g}</td><td>{html.escape(ctx.name(j))}</td></tr>'
        )
    if not rows:
        return '<p class="muted">No solved samples.</p>'
    return (
        "<table><thead><tr><th>column</th><th>unit</th><th>min</th><th>at</th><th>max</th>"
        f"<th>at</th></tr></thead><tbody>{''.join(rows)}</tbody></table>"
    )


def build_report(
    mech: MechanismLike,
    result: Solved,
    *,
    title: str | None = None,
    units: Mapping[str, str] | None = None,
    show: Iterable[str] | None = None,
    curves: Iterable[str] | None = None,
    ropes: Iterable[str] = (),
    length_unit: str = "mm",
    max_frames: int = MAX_FRAMES,
    command: str | None = None,
    shocks: Sequence[ShockLike] = (),
) -> str:
    """The HTML text of a report on ``result`` of ``mech``.

    Parameters
    ----------
    mech : Mechanism
    result : KinematicResult or a result with ``.kinematics`` and ``to_frame()``
    title : str, optional
        Default: the model's name.
    units : mapping of str to str, optional
        Display units by kind or column.
    show : iterable of str, optional
        Columns whose current value the mechanism view shows (see `mechanism_figure`).
    curves : iterable of str, optional
        Columns plotted (default `main_columns`).
    ropes : iterable of str
        Linear elements drawn as lines rather than cylinders.
    length_unit : str
    max_frames : int
    command : str, optional
        The command line that made the report, for the record.
    shocks : sequence of Shock, optional
        For a run in time, the exact shock report's shocks
        ([`excavkin.simulation.shocks.shock_report`][]), listed among the warnings.

    Returns
    -------
    str
        A complete HTML document; plotly.js is embedded, nothing is fetched when viewing.
    """
    from importlib.resources import files

    import plotly.offline

    from excavkin import __version__
    from excavkin.outputs.plots import main_columns

    ctx = _Context(result, units)
    title = title or mech.name
    curve_cols = list(curves) if curves is not None else main_columns(ctx.table)
    mfig = mechanism_figure(
        result, units=units, show=show, ropes=ropes, length_unit=length_unit, max_frames=max_frames
    )
    cfig = curves_figure(result, curve_cols, units=units)
    config = {
        "displaylogo": False,
        "responsive": True,
        "toImageButtonOptions": {"format": "png", "scale": 2},
    }
    mech_html = mfig.to_html(
        full_html=False, include_plotlyjs=False, div_id="mechanism", config=config, auto_play=False
    )
    curves_html = cfig.to_html(
        full_html=False, include_plotlyjs=False, div_id="curves", config=config
    )
    events = find_events(ctx.table, describe_sample=ctx.name, shocks=shocks)
    frame = ctx.table.frame
    csv = frame.to_csv(index=False, float_format="%.10g")
    src = mech.model.source
    now = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")
    subtitle = " · ".join(
        x
        for x in (
            html.escape(str(src)) if src else "model built in Python",
            f"{len(frame)} samples",
            f"{int(ctx.table.ok.sum())} solved",
            html.escape(command) if command else "",
        )
        if x
    )
    notes = ""
    if getattr(mech.plan, "notes", ()):
        notes = "<ul>" + "".join(f"<li>{html.escape(n)}</li>" for n in mech.plan.notes) + "</ul>"
    curves_note = _curves_note(result, "t" in frame)
    template = Template(
        files("excavkin.outputs").joinpath("report_template.html").read_text(encoding="utf-8")
    )
    stem = "".join(ch if ch.isalnum() or ch in "-_" else "-" for ch in title).strip("-") or "result"
    return template.substitute(
        version=html.escape(__version__),
        title=html.escape(title),
        subtitle=subtitle,
        plotlyjs=plotly.offline.get_plotlyjs(),
        sweep=html.escape(_sweep_text(ctx)),
        mechanism=mech_html,
        curves=curves_html,
        curves_note=html.escape(curves_note),
        warnings=_warnings_html(events),
        describe=html.escape(mech.describe().split("\n  plan    :")[0]),
        plan=html.escape(mech.plan.describe()),
        notes=notes,
        csv_name=html.escape(f"{stem}.csv"),
        csv=base64.b64encode(csv.encode("utf-8")).decode("ascii"),
        n_rows=len(frame),
        n_cols=len(frame.columns),
        extremes=_extremes_html(ctx, curve_cols),
        date=now,
    )


def write_report(
    mech: MechanismLike,
    result: Solved,
    path: str | Path,
    *,
    force: bool = False,
    **options: Any,
) -> Path:
    """Write the HTML report of ``result`` to ``path``, atomically.

    Parameters
    ----------
    mech : Mechanism
    result : KinematicResult or a result with ``.kinematics`` and ``to_frame()``
    path : str or Path
        Ends in ``.html`` or ``.htm``.
    force : bool
        Replace an existing file.
    **options
        Passed to `build_report` (``title``, ``units``, ``show``, ``curves``, ``ropes``,
        ``length_unit``, ``max_frames``, ``command``, ``shocks``).

    Returns
    -------
    Path

    Raises
    ------
    excavkin.outputs.tables.OutputError
        If the file exists and ``force`` is false, or the folder does not exist.
    TypeError
        On an unknown option.
    """
    from excavkin.outputs.tables import check_target, write_atomic

    p = check_target(path, force=force, suffixes=HTML_SUFFIXES)
    text = build_report(mech, result, **options)

    def write(tmp: Path) -> None:
        tmp.write_text(text, encoding="utf-8")

    return write_atomic(p, write)
