"""Figures of ``excavkin reproduce mo100``: the MO-100 hammer paper's Fig. 3 and Fig. 5, redrawn.

Both take the engine's quantities (`MO100Run` on an open
grid of one crank turn) and return a
`PaperFigure`; curves go through
[`excavkin.outputs.plots.plot_columns`][] (display units on every axis). The change point
(the blow, φ = 0 ≡ 360°) is drawn as a vertical line, with the engine's one-sided limits as
markers at 0° (after the blow) and 360° (before it). matplotlib is imported inside the
functions only; write the figures with `excavkin.papers.figures.save_png`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from excavkin.outputs.plots import plot_columns
from excavkin.papers.figures import PaperFigure

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from excavkin.papers.mo100.study import FitRow, MO100Run, OneSided

__all__ = ["mo100_fig3", "mo100_fig5"]

_PHI = "φ crank angle"
_UNITS = {"angle": "deg", "force": "kN", "torque": "kN*m"}
_COLORS = {"p_tau": "#1f77b4", "p_n": "#d62728", "m_u": "#2ca02c", "rx": "#1f77b4"}


def _figure(width: float, height: float) -> Figure:
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), layout="constrained")


def _frame(phi: npt.NDArray[np.float64], cols: Mapping[str, tuple[Any, str]]) -> pd.DataFrame:
    import pandas as pd

    frame = pd.DataFrame({_PHI: phi, **{k: v for k, (v, _) in cols.items()}})
    frame.attrs["excavkin.kinds"] = {_PHI: "angle", **{k: kind for k, (_, kind) in cols.items()}}
    return frame


def _time_axis(ax: Axes, omega1: float) -> None:
    """A second x axis on top: t = φ / ω1 [s]."""
    deg_per_s = math.degrees(omega1)

    def to_t(deg: Any) -> Any:
        return np.asarray(deg, dtype=np.float64) / deg_per_s

    def to_deg(t: Any) -> Any:
        return np.asarray(t, dtype=np.float64) * deg_per_s

    sec = ax.secondary_xaxis("top", functions=(to_t, to_deg))
    sec.set_xlabel(f"t [s]  (ω1 = {omega1:.3f} s⁻¹)", fontsize="small")


def _blow(ax: Axes, label: bool) -> None:
    ax.axvline(360.0, color="0.35", ls="--", lw=1.0, label="blow: change point" if label else None)
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.set_xlim(-5.0, 370.0)
    ax.set_xticks(np.arange(0.0, 361.0, 30.0))


def _limits(ax: Axes, key: str, scale: float, limits: OneSided | None, color: str) -> None:
    if limits is None:
        return
    ax.plot([360.0], [limits.before[key] * scale], "o", color=color, ms=5, zorder=5)
    ax.plot([0.0], [limits.after[key] * scale], "o", mfc="white", color=color, ms=5, zorder=5)


def mo100_fig3(
    run: MO100Run,
    limits: OneSided | None = None,
    reference: Mapping[str, npt.NDArray[np.float64]] | None = None,
) -> PaperFigure:
    """Fig. 3 of the paper: the rocker's inertia loads against the crank angle.

    Panels (a) P_u^τ, (b) P_u^n (as the paper's Fig. 3) and (c) the inertia torque M_u, in the
    paper's sign convention (eq. 1: P_u^n = m3·ω3²·lS, P_u^τ = m3·ε3·lS, M_u = I·ε3).

    Parameters
    ----------
    run : MO100Run
        The engine over an open grid of one turn (`mo100_run`
        on `cycle_grid`).
    limits : OneSided, optional
        One-sided limits at the change point, drawn at 360° (filled, before the blow) and 0°
        (open, after it).
    reference : mapping of str to ndarray, shape (m,), optional
        The paper's formulas on a coarse grid: ``"phi"`` [rad], ``"p_n"``, ``"p_tau"`` [N],
        ``"m_u"`` [N·m]; drawn as markers.

    Returns
    -------
    PaperFigure
        Panels ``"p_tau"``, ``"p_n"``, ``"m_u"``.
    """
    fig = _figure(7.4, 8.0)
    axes = fig.subplots(3, 1, sharex=True)
    out = PaperFigure(fig)
    panels = (
        ("p_tau", r"$P_u^\tau$", "force", r"$P_u^\tau$ [kN]", "(a) tangential: m3·ε3·lS"),
        ("p_n", r"$P_u^n$", "force", r"$P_u^n$ [kN]", "(b) normal: m3·ω3²·lS"),
        ("m_u", r"$M_u$", "torque", r"$M_u$ [kN·m]", "(c) inertia torque: I·ε3"),
    )
    scale = 1e-3  # N -> kN, N m -> kN m
    for k, (ax, (key, label, kind, ylabel, title)) in enumerate(zip(axes, panels, strict=True)):
        frame = _frame(run.phi, {f"{label} (engine)": (getattr(run, key), kind)})
        plot_columns(
            frame,
            [f"{label} (engine)"],
            _PHI,
            units=_UNITS,
            ax=ax,
            mark=False,
            legend=False,
            color=_COLORS[key],
        )
        _blow(ax, k == 0)
        _limits(ax, key, scale, limits, _COLORS[key])
        if reference is not None:
            ax.plot(
                np.degrees(reference["phi"]),
                reference[key] * scale,
                "x",
                color="k",
                ms=5,
                label="paper's formulas (reference), 10° grid",
            )
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize="small", loc="right")
        ax.set_xlabel("φ crank angle [°]" if k == 2 else "")
        ax.legend(fontsize="small", loc="upper left" if key == "p_n" else "lower left")
        out.axes[key] = ax
    _time_axis(axes[0], run.omega1)
    fig.suptitle(
        "MO-100 hammer, Fig. 3: inertia loads of the rocker over a crank turn\n"
        f"(m3 = 35.2 kg, I = 0.737 kg·m², ω1 = {run.omega1:g} s⁻¹; signs as eq. 1)",
        fontsize="medium",
    )
    return out


def mo100_fig5(
    run: MO100Run,
    fit: FitRow,
    limits: OneSided | None = None,
    paper_fit: tuple[float, float, float] | None = None,
    grid: tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]] | None = None,
    lobe: Sequence[float] | None = None,
) -> PaperFigure:
    """Fig. 5 of the paper: Rx, Ry on the housing against φ (and t), with the half-sine fit.

    Parameters
    ----------
    run : MO100Run
        The engine over an open grid of one turn.
    fit : FitRow
        Our half-sine fit (eq. 15 corrected: ``Ry = H sin μ(t − t1)`` on ``t1 ≤ t ≤ T``), drawn
        dashed.
    limits : OneSided, optional
        One-sided limits at the change point (markers at 360° and 0°).
    paper_fit : (H, mu, t1), optional
        The paper's printed fit (39 895 N, 170 s⁻¹, 0.1815 s), drawn dotted.
    grid : (phi, ry), optional
        The 10° grid of Ry the paper's H is read from, shape (m,) each [rad, N]; markers.
    lobe : (start, stop), optional
        The main Ry lobe [rad], shaded.

    Returns
    -------
    PaperFigure
        Panels ``"rx"`` and ``"ry"``.
    """
    from excavkin.papers.mo100.reference import half_sine_pulse

    fig = _figure(7.4, 6.6)
    ax_x, ax_y = fig.subplots(2, 1, sharex=True)
    out = PaperFigure(fig, {"rx": ax_x, "ry": ax_y})
    period = 2.0 * math.pi / run.omega1

    frame = _frame(run.phi, {"Rx engine": (run.rx, "force")})
    plot_columns(frame, ["Rx engine"], _PHI, units=_UNITS, ax=ax_x, mark=False, legend=False)
    _blow(ax_x, True)
    _limits(ax_x, "rx", 1e-3, limits, _COLORS["rx"])
    ax_x.set_ylabel("Rx, across the tool [kN]")
    ax_x.set_xlabel("")
    ax_x.legend(fontsize="small", loc="upper left")

    frame = _frame(run.phi, {"Ry engine": (run.ry, "force")})
    plot_columns(
        frame, ["Ry engine"], _PHI, units=_UNITS, ax=ax_y, mark=False, legend=False, color="k"
    )
    _blow(ax_y, False)
    _limits(ax_y, "ry", 1e-3, limits, "k")
    t = np.linspace(0.0, period, 3601)
    deg = np.degrees(run.omega1 * t)
    pulse = half_sine_pulse(t, fit.h, fit.mu, fit.t1, period)
    ax_y.plot(
        deg,
        pulse * 1e-3,
        "--",
        color="#d62728",
        lw=1.8,
        label=(
            f"half-sine fit (ours): H = {fit.h:.0f} N, μ = {fit.mu:.1f} s⁻¹, t1 = {fit.t1:.4f} s"
        ),
    )
    if paper_fit is not None:
        h, mu, t1 = paper_fit
        ax_y.plot(
            deg,
            half_sine_pulse(t, h, mu, t1, period) * 1e-3,
            ":",
            color="#9467bd",
            lw=1.8,
            label=f"paper's fit: H = {h:.0f} N, μ = {mu:g} s⁻¹, t1 = {t1:g} s",
        )
    if grid is not None:
        ax_y.plot(
            np.degrees(grid[0]), grid[1] * 1e-3, "o", ms=3.5, color="#ff7f0e", label="10° grid"
        )
    if lobe is not None:
        ax_y.axvspan(
            math.degrees(lobe[0]),
            math.degrees(lobe[1]),
            color="#d62728",
            alpha=0.08,
            lw=0,
            label="main lobe: impulse S",
        )
    ax_y.set_ylabel("Ry, along the tool (up) [kN]")
    ax_y.set_xlabel("φ crank angle [°]")
    ax_y.legend(fontsize="small", loc="upper left")
    _time_axis(ax_x, run.omega1)
    fig.suptitle(
        "MO-100 hammer, Fig. 5: force of the mechanism on the housing (housing axes)",
        fontsize="medium",
    )
    return out
