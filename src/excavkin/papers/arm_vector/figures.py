"""Figures of ``excavkin reproduce arm``: the vector model and the cylinders' sweeps.

matplotlib is imported inside the functions only; figures are built on
`matplotlib.figure.Figure` without pyplot. Curves go through
[`excavkin.outputs.plots.plot_columns`][] (display units on every axis).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from excavkin.outputs.plots import plot_columns
from excavkin.papers.figures import PaperFigure, new_figure, run_frame

if TYPE_CHECKING:
    from excavkin.papers.common import PaperRun
# ------------------------------------------------------------------------------------------
# Excavator arm vector model
# ------------------------------------------------------------------------------------------


def arm_vector_figure(solutions: Sequence[PaperRun], sample: int = 0) -> PaperFigure:
    """Fig. 1 of the paper: the vector model l1 + l2 + l3 = r_A, for both inverse solutions.

    Parameters
    ----------
    solutions : sequence of PaperRun
        From `excavkin.papers.arm_vector.study.arm_inverse`, branch +1 then −1.
    sample : int
        Sample to draw.

    Returns
    -------
    PaperFigure
        Panel ``"arm"``.
    """
    fig = new_figure(7.5, 5.4)
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
        `excavkin.papers.arm_vector.study.arm_cylinder_sweep`.

    Returns
    -------
    PaperFigure
        Panels ``"z"``, ``"phi_z"``, ``"omega_z"``, ``"eps_z"``, ``"omega"``, ``"eps"``.
    """
    fig = new_figure(10.0, 7.6)
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
            frame = run_frame(run, {col: link}, x)
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
