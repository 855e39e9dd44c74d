"""Animate a result: the mechanism moving through its samples, with chosen values shown.

Saved as GIF (Pillow, always available) or MP4 (when ``ffmpeg`` is on the PATH)::

    anim = animate(result, show=["crank.value", "rocker.angle"], trace=["B"])
    anim.save("fourbar.gif", fps=20)

matplotlib is imported inside the functions only.
"""

from __future__ import annotations

import shutil
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.outputs.display_units import DisplayUnits, pretty_unit

if TYPE_CHECKING:
    from matplotlib.animation import FuncAnimation
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.text import Text

    from excavkin.outputs.drawing import MechanismDrawing
    from excavkin.outputs.protocols import Solved

#: most frames an animation gets when ``samples`` is not given
MAX_FRAMES = 180


def frame_samples(n: int, max_frames: int = MAX_FRAMES) -> np.ndarray:
    """Evenly spread sample indices, at most ``max_frames``, first and last included."""
    if n <= max_frames:
        return np.arange(n)
    return np.unique(np.round(np.linspace(0, n - 1, max_frames)).astype(np.int64))


def value_text(table: Any, columns: Sequence[str], units: DisplayUnits, sample: int) -> str:
    """``"crank = 30.0 °"`` lines for ``columns`` at ``sample`` (display units)."""
    lines = []
    for c in columns:
        d = units(c)
        v = float(d.convert(table.frame[c].to_numpy(dtype=np.float64)[sample]))
        name = d.owner if d.quantity == "value" else c
        pu = pretty_unit(d.unit)
        unit = "" if not pu else pu if pu == "°" else f" {pu}"
        lines.append(f"{name} = {v:.4g}{unit}" if np.isfinite(v) else f"{name} = —")
    return "\n".join(lines)


@dataclass
class MechanismAnimation:
    """An animation of a mechanism and its artists.

    Attributes
    ----------
    fig : matplotlib.figure.Figure
    ax : matplotlib.axes.Axes
    drawing : MechanismDrawing
        Moved to each frame's sample.
    text : matplotlib.text.Text
        The values shown.
    samples : ndarray of int
        The sample of each frame.
    animation : matplotlib.animation.FuncAnimation
    """

    fig: Figure
    ax: Axes
    drawing: MechanismDrawing
    text: Text
    samples: np.ndarray
    animation: FuncAnimation

    def save(
        self, path: str | Path, *, fps: int = 20, dpi: float = 100.0, force: bool = False
    ) -> Path:
        """Write the animation as ``.gif`` (Pillow) or ``.mp4`` (ffmpeg), atomically.

        Parameters
        ----------
        path : str or Path
        fps : int
            Frames per second.
        dpi : float
            Resolution.
        force : bool
            Replace an existing file.

        Returns
        -------
        Path

        Raises
        ------
        excavkin.outputs.tables.OutputError
            If the file exists (without ``force``), its suffix is neither, or MP4 is asked for
            and ffmpeg is not installed.
        """
        from matplotlib.animation import FFMpegWriter, PillowWriter

        from excavkin.outputs.tables import OutputError, check_target, write_atomic

        p = check_target(path, force=force, suffixes=(".gif", ".mp4"))
        if p.suffix.lower() == ".mp4":
            if shutil.which("ffmpeg") is None:
                raise OutputError(
                    f"{p}: writing MP4 needs ffmpeg on the PATH "
                    "(apt-get install ffmpeg), or write .gif"
                )
            writer: Any = FFMpegWriter(fps=fps, codec="h264", extra_args=["-pix_fmt", "yuv420p"])
        else:
            writer = PillowWriter(fps=fps)

        def write(tmp: Path) -> None:
            self.animation.save(str(tmp), writer=writer, dpi=dpi)

        return write_atomic(p, write)


def animate(
    result: Solved,
    *,
    samples: Sequence[int] | None = None,
    show: Sequence[str] | None = None,
    units: Mapping[str, str] | None = None,
    trace: Iterable[str] = (),
    ropes: Iterable[str] = (),
    length_unit: str = "mm",
    labels: bool = True,
    interval: float = 50.0,
    ax: Axes | None = None,
    title: str | None = None,
) -> MechanismAnimation:
    """Animate the mechanism of a result through its samples.

    Parameters
    ----------
    result : KinematicResult or a result with ``.kinematics`` and ``to_frame()``
    samples : sequence of int, optional
        The sample of each frame; default every sample, thinned evenly to at most
        `MAX_FRAMES`.
    show : sequence of str, optional
        Columns whose current value is written in the corner (display units); default the
        inputs that vary, and ``t`` for a result in time.
    units : mapping of str to str, optional
        Display units of the shown values, by kind or column (see
        `DisplayUnits`).
    trace : iterable of str
        Points whose whole path is drawn faintly underneath.
    ropes : iterable of str
        Linear elements drawn as lines rather than cylinders.
    length_unit : str
        Unit of the axes.
    labels : bool
        Write point names.
    interval : float
        Milliseconds between frames when shown on screen.
    ax : matplotlib.axes.Axes, optional
        Axes to animate in (its figure is animated); a new figure without one.
    title : str, optional

    Returns
    -------
    MechanismAnimation
        ``.save("out.gif")`` writes it.

    Raises
    ------
    KeyError
        On an unknown column in ``show`` or point in ``trace``.
    """
    from matplotlib.animation import FuncAnimation

    from excavkin.outputs.drawing import draw_mechanism, trace_paths
    from excavkin.outputs.events import as_table, varies
    from excavkin.outputs.plots import default_x
    from excavkin.outputs.style import FAIL_COLOR

    kin = result if hasattr(result, "positions") else getattr(result, "kinematics", result)
    table = as_table(result)
    n = len(table.frame)
    frames = frame_samples(n) if samples is None else np.asarray(list(samples), dtype=np.int64)
    if frames.size == 0:
        raise ValueError("samples: give at least one sample")
    if frames.min() < -n or frames.max() >= n:
        raise IndexError(f"samples out of range for a result of {n} samples")
    if show is None:
        show = [c for c in ([default_x(table)] if default_x(table) != "sample" else [])]
        if table.plan is not None:
            for name in table.plan.inputs:
                c = f"{name}.value"
                if c not in show and varies(table.frame[c]):
                    show.append(c)
    for c in show:
        if c not in table.frame:
            raise KeyError(f"show: no column {c!r} in the result")
    disp = DisplayUnits(units, table.kinds)
    if ax is None:
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6.4, 5.0), layout="constrained")
    else:
        fig = ax.get_figure()  # type: ignore[assignment]
    trace = list(trace)
    if trace:
        trace_paths(kin, trace, ax=ax, length_unit=length_unit, alpha=0.55, lw=1.2, ls="--")
    drawing = draw_mechanism(
        kin, int(frames[0]), ax=ax, labels=labels, ropes=ropes, length_unit=length_unit
    )
    ok = table.ok
    text = ax.text(
        0.015,
        0.985,
        "",
        transform=ax.transAxes,
        va="top",
        ha="left",
        fontsize=10,
        family="monospace",
        zorder=30,
        bbox={"boxstyle": "round,pad=0.35", "fc": "white", "ec": "#999999", "alpha": 0.9},
    )
    if title:
        ax.set_title(title)

    def update(k: int) -> list[Any]:
        i = int(frames[k])
        arts = drawing.set_sample(i)
        msg = value_text(table, show, disp, i)
        if not ok[i]:
            msg += ("\n" if msg else "") + str(table.labels[i])
            text.set_color(FAIL_COLOR)
        else:
            text.set_color("black")
        text.set_text(msg)
        text.set_visible(bool(msg))
        return [*arts, text]

    update(0)
    anim = FuncAnimation(fig, update, frames=len(frames), interval=interval, blit=False)
    return MechanismAnimation(fig, ax, drawing, text, frames, anim)
