"""Figures of ``excavkin reproduce pasika | rope-shovel | arm``: the seed papers' plots, redrawn.

Each function takes the engine's quantities (:class:`~excavkin.applications.papers.PaperRun`)
and returns a :class:`PaperFigure`; curves go through
:func:`excavkin.outputs.plots.plot_columns` (display units on every axis). matplotlib is
imported inside the functions only and figures are built on
:class:`matplotlib.figure.Figure`, without pyplot. Write them with
:func:`excavkin.outputs.paper_figures.save_png`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.outputs.plots import plot_columns

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from excavkin.applications.papers import PaperRun

__all__ = [
    "PaperFigure",
    "arm_cylinders_figure",
    "arm_vector_figure",
    "pasika_fig3",
    "pasika_fig5",
    "rope_shovel_angles",
    "rope_shovel_rates",
    "rope_shovel_scheme",
]


@dataclass
class PaperFigure:
    """The artists of one reproduced figure.

    Attributes
    ----------
    figure : matplotlib.figure.Figure
    axes : dict of str to Axes
        The panels by name.
    """

    figure: Figure
    axes: dict[str, Axes] = field(default_factory=dict)


def _figure(width: float, height: float) -> Figure:
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), layout="constrained")


def _frame(run: PaperRun, names: Mapping[str, str], x: str) -> pd.DataFrame:
    """A DataFrame of ``run``'s columns renamed for display, with their kinds attached."""
    import pandas as pd

    def curve(key: str) -> Any:
        v = run.columns[key]
        ok = np.isfinite(v)
        if run.kinds[key] == "angle" and ok.sum() > 1:  # continuous curves through ±180°
            v = v.copy()
            v[ok] = np.unwrap(v[ok])
        return v

    cols = {x: curve(x), **{label: curve(key) for key, label in names.items()}}
    frame = pd.DataFrame(cols)
    frame.attrs["excavkin.kinds"] = {
        x: run.kinds[x],
        **{label: run.kinds[key] for key, label in names.items()},
    }
    return frame


def _panel(
    ax: Axes,
    run: PaperRun,
    names: Mapping[str, str],
    x: str,
    *,
    units: Mapping[str, str],
    ylabel: str,
    xlabel: str,
    title: str | None = None,
    styles: Sequence[Mapping[str, Any]] = (),
) -> None:
    frame = _frame(run, names, x)
    labels = list(names.values())
    for k, lab in enumerate(labels):
        style = dict(styles[k]) if k < len(styles) else {}
        plot_columns(frame, [lab], x, units=units, ax=ax, mark=False, legend=False, **style)
    ax.set_ylabel(ylabel)
    ax.set_xlabel(xlabel)
    if title:
        ax.set_title(title, fontsize="medium")
    if len(labels) > 1:
        ax.legend(fontsize="small", loc="best")


# ------------------------------------------------------------------------------------------
# Pasika & Koruniak
# ------------------------------------------------------------------------------------------

_PASIKA_UNITS = {"length": "m", "angle": "deg", "time": "s"}


def pasika_fig3(run: PaperRun) -> PaperFigure:
    """Fig. 3 of the paper: rod displacement s, velocity v21 and acceleration a21 against t.

    Parameters
    ----------
    run : PaperRun
        From :func:`excavkin.applications.papers.pasika_run`.

    Returns
    -------
    PaperFigure
        Panels ``"s"``, ``"v"``, ``"a"``.
    """
    fig = _figure(6.4, 6.4)
    axes = fig.subplots(3, 1, sharex=True)
    out = PaperFigure(fig)
    for ax, key, ylabel in zip(
        axes,
        ("s", "v21", "a21"),
        ("s [m]", "v₂₁ [m/s]", "a₂₁ [m/s²]"),
        strict=True,
    ):
        _panel(
            ax,
            run,
            {key: key},
            "t",
            units=_PASIKA_UNITS,
            ylabel=ylabel,
            xlabel="t [s]" if key == "a21" else "",
            styles=[{"color": "#1f77b4"}],
        )
        out.axes[key.rstrip("21") or key] = ax
    axes[2].axhline(0.0, color="0.6", lw=0.8)
    fig.suptitle(
        "Pasika & Koruniak, Fig. 3: cubic law of the rod, H = 0.5 m, T = 5 s", fontsize="medium"
    )
    return out


def pasika_fig5(
    run: PaperRun,
    table: Mapping[str, Sequence[float]] | None = None,
    times: Sequence[float] = (),
) -> PaperFigure:
    """Fig. 5 of the paper: (a) cylinder φ1, ω1, ε1 and (b) rocker φ3, ω3, ε3 against t.

    Parameters
    ----------
    run : PaperRun
        From :func:`excavkin.applications.papers.pasika_run`.
    table : mapping, optional
        Points to overlay (spec §4.3: ``phi1`` in degrees, ``omega1``, ``eps1``, ...).
    times : sequence of float
        The times of ``table``'s rows [s].

    Returns
    -------
    PaperFigure
        Panels ``"phi1"``, ``"omega1"``, ``"eps1"``, ``"phi3"``, ``"omega3"``, ``"eps3"``.
    """
    fig = _figure(9.0, 6.6)
    axes = fig.subplots(3, 2, sharex=True)
    out = PaperFigure(fig)
    rows = (("phi", "φ{} [°]"), ("omega", "ω{} [rad/s]"), ("eps", "ε{} [rad/s²]"))
    for col, (link, title) in enumerate((("1", "(a) cylinder 1"), ("3", "(b) rocker 3"))):
        for row, (q, ylabel) in enumerate(rows):
            ax = axes[row, col]
            key = f"{q}{link}"
            _panel(
                ax,
                run,
                {key: f"{key} engine"},
                "t",
                units=_PASIKA_UNITS,
                ylabel=ylabel.format(link),
                xlabel="t [s]" if row == 2 else "",
                title=title if row == 0 else None,
                styles=[{"color": "#1f77b4"}],
            )
            if table is not None and times:
                ax.plot(
                    list(times),
                    list(table[key]),
                    "o",
                    ms=5,
                    mfc="none",
                    color="#d62728",
                    label="spec §4.3",
                )
                ax.legend(["engine", "spec §4.3"], fontsize="small", loc="best")
            if row > 0:
                ax.axhline(0.0, color="0.6", lw=0.8)
            out.axes[key] = ax
    fig.suptitle(
        "Pasika & Koruniak, Fig. 5: cylinder and rocker under the cubic law", fontsize="medium"
    )
    return out


# ------------------------------------------------------------------------------------------
# Maksimov rope shovel
# ------------------------------------------------------------------------------------------

_ROPE_UNITS = {"angle": "deg", "length": "m", "time": "s"}
_PHI1 = "φ1 stick angle"


def rope_shovel_scheme(run: PaperRun, samples: Sequence[int]) -> PaperFigure:
    """The paper's only figure, «Схема механизма поворота ковша»: the mechanism drawn.

    Parameters
    ----------
    run : PaperRun
        From :func:`excavkin.applications.papers.rope_shovel_sweep`.
    samples : sequence of int
        Samples to draw; the last one in full, the others faded.

    Returns
    -------
    PaperFigure
        Panel ``"scheme"``.
    """
    from excavkin.outputs.drawing import draw_mechanism

    fig = _figure(7.5, 5.2)
    ax = fig.subplots()
    draw_mechanism(run.result, list(samples), ax=ax, ropes=["drag"], length_unit="m")
    phis = ", ".join(f"{np.degrees(run['phi1'][s]):.0f}°" for s in samples)
    ax.set_title(
        f"EO-4112 bucket-turning mechanism at φ1 = {phis} (last drawn in full)\n"
        "paper's frame: X from the stick pivot O1 towards the boom foot",
        fontsize="medium",
    )
    ax.set_xlabel("X [m]")
    ax.set_ylabel("Y [m]")
    return PaperFigure(fig, {"scheme": ax})


def rope_shovel_angles(run: PaperRun) -> PaperFigure:
    """Angles of the links against the stick angle φ1 (the paper's outputs, §1, §3).

    Parameters
    ----------
    run : PaperRun
        From :func:`excavkin.applications.papers.rope_shovel_sweep`.

    Returns
    -------
    PaperFigure
        Panels ``"absolute"`` (φ2 = φ5, φ3, bucket to the horizon) and ``"stick"``
        (φ6, φ7', γ relative to the stick).
    """
    fig = _figure(7.0, 6.4)
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    frame_run = _with_phi1(run)
    _panel(
        ax1,
        frame_run,
        {
            "phi2": "φ2 = φ5 lever",
            "phi3": "φ3 cylinder Ц2 (locked)",
            "bucket_to_horizon": "bucket to the horizon",
        },
        _PHI1,
        units=_ROPE_UNITS,
        ylabel="absolute angle [°]",
        xlabel="",
        title="absolute angles (paper's frame)",
    )
    _panel(
        ax2,
        frame_run,
        {"phi7p": "φ7' bucket to the handle", "phi6": "φ6 coupler", "gamma": "γ cylinder Ц1"},
        _PHI1,
        units=_ROPE_UNITS,
        ylabel="angle to the stick [°]",
        xlabel="φ1 stick angle [°]",
        title="relative to the stick (handle)",
    )
    return PaperFigure(fig, {"absolute": ax1, "stick": ax2})


def rope_shovel_rates(run: PaperRun) -> PaperFigure:
    """Angular velocities, the stroke rate and length of cylinder Ц1 against φ1.

    Parameters
    ----------
    run : PaperRun
        From :func:`excavkin.applications.papers.rope_shovel_sweep` (winch at constant speed).

    Returns
    -------
    PaperFigure
        Panels ``"omega"``, ``"v_c1"``, ``"hk"``.
    """
    fig = _figure(7.0, 7.6)
    ax1, ax2, ax3 = fig.subplots(3, 1, sharex=True)
    r = _with_phi1(run)
    v = float(np.median(run["v_rope"]))
    _panel(
        ax1,
        r,
        {
            "omega1": "ω1 stick",
            "omega2": "ω2 lever",
            "omega3": "ω3 Ц2",
            "omega7p": "ω7 bucket / stick",
            "omega10": "ω10 Ц1 / stick",
        },
        _PHI1,
        units=_ROPE_UNITS,
        ylabel="angular velocity [rad/s]",
        xlabel="",
        title=f"drag rope hauled in at v_тк = {v:.3f} m/s",
    )
    ax1.axhline(0.0, color="0.6", lw=0.8)
    _panel(
        ax2,
        r,
        {"v_c1": "v_Ц1"},
        _PHI1,
        units=_ROPE_UNITS,
        ylabel="v_Ц1 = d(HK)/dt [m/s]",
        xlabel="",
        styles=[{"color": "#9467bd"}],
    )
    ax2.axhline(0.0, color="0.6", lw=0.8)
    _panel(
        ax3,
        r,
        {"hk": "HK"},
        _PHI1,
        units=_ROPE_UNITS,
        ylabel="HK, length of Ц1 [m]",
        xlabel="φ1 stick angle [°]",
        styles=[{"color": "#8c564b"}],
    )
    return PaperFigure(fig, {"omega": ax1, "v_c1": ax2, "hk": ax3})


def _with_phi1(run: PaperRun) -> PaperRun:
    from excavkin.applications.papers import PaperRun

    return PaperRun(
        {**run.columns, _PHI1: run.columns["phi1"]}, {**run.kinds, _PHI1: "angle"}, run.result
    )


# ------------------------------------------------------------------------------------------
# Excavator arm vector model
# ------------------------------------------------------------------------------------------


def arm_vector_figure(solutions: Sequence[PaperRun], sample: int = 0) -> PaperFigure:
    """Fig. 1 of the paper: the vector model l1 + l2 + l3 = r_A, for both inverse solutions.

    Parameters
    ----------
    solutions : sequence of PaperRun
        From :func:`excavkin.applications.papers.arm_inverse`, branch +1 then −1.
    sample : int
        Sample to draw.

    Returns
    -------
    PaperFigure
        Panel ``"arm"``.
    """
    fig = _figure(7.5, 5.4)
    ax = fig.subplots()
    colors = ("#1f77b4", "#d62728")
    for k, sol in enumerate(solutions):
        res = sol.result
        pts = [res.point(n)[0][sample] for n in ("O", "J", "Q", "A")]
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        ls = "-" if k == 0 else "--"
        lab = (
            f"branch {'+1' if k == 0 else '−1'}: φ1 = {np.degrees(sol['phi1'][sample]):.1f}°,"
            f" φ2 = {np.degrees(sol['phi2'][sample]):.1f}°"
        )
        ax.plot(xs, ys, ls, color=colors[k % 2], lw=2.2, marker="o", label=lab)
        for (x0, y0), (x1, y1), name in zip(pts[:-1], pts[1:], ("l1", "l2", "l3"), strict=True):
            ax.annotate(
                "",
                (x1, y1),
                (x0, y0),
                arrowprops={"arrowstyle": "-|>", "color": colors[k % 2], "lw": 1.2},
            )
            if k == 0 or name != "l3":
                ax.text(0.5 * (x0 + x1), 0.5 * (y0 + y1), f" {name}", color=colors[k % 2])
        for cyl, (p, q) in (
            ("boom_cyl", ("P1", "C1")),
            ("stick_cyl", ("P2", "C2")),
            ("bucket_cyl", ("P3", "C3")),
        ):
            a, b = res.point(p)[0][sample], res.point(q)[0][sample]
            ax.plot(
                [a[0], b[0]],
                [a[1], b[1]],
                color=colors[k % 2],
                lw=5,
                alpha=0.25,
                solid_capstyle="round",
                label="cylinders" if (k == 0 and cyl == "boom_cyl") else None,
            )
    a = solutions[0].result.point("A")[0][sample]
    ax.annotate(
        "",
        (a[0], a[1]),
        (0.0, 0.0),
        arrowprops={"arrowstyle": "-|>", "color": "0.3", "lw": 1.0, "ls": ":"},
    )
    ax.text(0.45 * a[0], 0.45 * a[1], "r_A", color="0.3")
    ax.text(a[0], a[1], f"  A ({a[0]:.2f}, {a[1]:.2f}) m", va="top")
    ax.text(0.0, 0.0, "O  ", ha="right", va="top")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, color="#e0e0e0", lw=0.8)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(fontsize="small", loc="lower left")
    p3 = np.degrees(solutions[0]["phi3"][sample])
    ax.set_title(
        f"vector model l1 + l2 + l3 = r_A: the inverse problem's two solutions (φ3 = {p3:.1f}°)",
        fontsize="medium",
    )
    return PaperFigure(fig, {"arm": ax})


def arm_cylinders_figure(sweeps: Mapping[str, PaperRun]) -> PaperFigure:
    """Fig. 2 relations for the three cylinders: z, φz, v_r, ωz, a_r, εz against the link angle.

    Each cylinder sweeps its stroke at unit rate (``v_r = 1 m/s``, ``a_r = 0``), so ωz and
    εz are the transfer functions dφz/dz and d²φz/dz², and the link's own ω, ε (right
    column) are dψ/dz and d²ψ/dz².

    Parameters
    ----------
    sweeps : mapping of str to PaperRun
        ``{"boom": ..., "stick": ..., "bucket": ...}`` from
        :func:`excavkin.applications.papers.arm_cylinder_sweep`.

    Returns
    -------
    PaperFigure
        Panels ``"z"``, ``"phi_z"``, ``"omega_z"``, ``"eps_z"``, ``"omega"``, ``"eps"``.
    """
    fig = _figure(10.0, 7.6)
    grid = fig.subplots(3, 2)
    colors = {"boom": "#1f77b4", "stick": "#2ca02c", "bucket": "#d62728"}
    link_index = {"boom": "1", "stick": "2", "bucket": "3"}
    panels = (
        ("z", "z, cylinder length [m]", "{}_z"),
        ("phi_z", "φz, barrel angle (absolute) [°]", "{}_phi_z"),
        ("omega_z", "ωz per unit v_r [rad/m]", "{}_omega_z"),
        ("eps_z", "εz at v_r = 1 m/s, a_r = 0 [rad/m²]", "{}_eps_z"),
        ("omega", "link ω = dψ/dz [rad/m]", "omega{}"),
        ("eps", "link ε = d²ψ/dz² [rad/m²]", "eps{}"),
    )
    out = PaperFigure(fig)
    for ax, (key, ylabel, pattern) in zip(grid.ravel(), panels, strict=True):
        for link, run in sweeps.items():
            col = pattern.format(link if "{}_" in pattern else link_index[link])
            x = f"{link}_psi"
            frame = _frame(run, {col: link}, x)
            plot_columns(
                frame,
                [link],
                x,
                units={"angle": "deg", "length": "m"},
                ax=ax,
                mark=False,
                legend=False,
                color=colors[link],
            )
        ax.set_ylabel(ylabel, fontsize="small")
        ax.set_xlabel("ψ, link angle in its parent's frame [°]", fontsize="small")
        ax.legend(fontsize="small", loc="best")
        out.axes[key] = ax
    fig.suptitle(
        "cylinder ↔ link relations of boom, stick and bucket (paper eqs. 7-12), "
        "each cylinder over its stroke",
        fontsize="medium",
    )
    return out
