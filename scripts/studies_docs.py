"""Regenerate the figures of docs/studies.md: a design study of the crank-rocker and its
optimisation. Run: python scripts/studies_docs.py"""

from __future__ import annotations

import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import excavkin  # noqa: E402
from excavkin.studies.optimize import optimize, optimize_study  # noqa: E402
from excavkin.studies.study import run_study  # noqa: E402
from excavkin.studies.study_file import load_optimization  # noqa: E402

ROOT = Path(__file__).parents[1]
IMG = ROOT / "docs" / "img"


def study_text() -> str:
    """The study file shown in docs/studies.md (between its ```toml fences)."""
    text = (ROOT / "docs" / "studies.md").read_text(encoding="utf-8")
    return text.split("```toml\n", 1)[1].split("```", 1)[0]


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        spec = Path(tmp) / "crank_rocker.toml"
        spec.write_text(study_text(), encoding="utf-8")
        study, _ = load_optimization(spec)
        table = run_study(study, Path(tmp) / "study.parquet").to_frame()
    best = optimize_study(study)
    ok = table["feasible"].to_numpy()
    fig, ax = plt.subplots(figsize=(7.5, 5))
    x, y = table["design.A-B"] * 1e3, table["design.O4-B"] * 1e3
    torque = np.minimum(table["torque_peak"], 2.0)
    ax.scatter(x[~ok], y[~ok], s=6, c="0.8", label="infeasible (γ_min < 35° or does not turn)")
    sc = ax.scatter(x[ok], y[ok], s=8, c=torque[ok], cmap="viridis")
    fig.colorbar(sc, ax=ax, label="peak crank torque [N·m]")
    ax.plot(best.params["A-B"] * 1e3, best.params["O4-B"] * 1e3, marker="*", ms=16, color="red",
            ls="none", label=f"optimum: {best.value:.3f} N·m")  # fmt: skip
    ax.set_xlabel("coupler A-B [mm]")
    ax.set_ylabel("rocker O4-B [mm]")
    ax.set_title(
        "4 096 crank-rocker designs (Sobol'), each over a full turn\n"
        "(projected: the ground O4.x varies from 90 to 115 mm too)",
        fontsize=10,
    )
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    fig.savefig(IMG / "studies-crank-rocker.png", dpi=110)
    plt.close(fig)
    fig = best.plot().get_figure(root=True)
    assert fig is not None
    fig.tight_layout()
    fig.savefig(IMG / "studies-convergence.png", dpi=110)
    print(best.summary())
    transmission_problem()


def dead_centre_family(lam: np.ndarray, psi: float, phi: float) -> tuple[np.ndarray, ...]:
    """Crank, coupler and rocker (ground 1) of the crank-rockers whose rocker swings psi while
    the crank turns phi, coupler/crank = lam: the loop equations at the two dead centres."""
    a11, a12 = 1 + lam, -1.0
    a21, a22 = np.exp(1j * phi) * (1 - lam), -np.exp(1j * psi)
    det = a11 * a22 - a12 * a21
    z1, z2 = (a22 - a12) / det, (a11 - a21) / det
    return np.abs(z1), lam * np.abs(z1), np.abs(z2)


def transmission_problem() -> None:
    """docs/studies.md: the classical transmission-angle problem, the family and the optimum."""
    study, settings = load_optimization(excavkin.example_path("crank_rocker_transmission"))
    mech = excavkin.load(study.model)
    by_name = {m.name: m for m in study.metrics}
    best = optimize(
        mech, study.bounds, study.poses, by_name[settings["objective"]], settings["sense"],
        metrics=study.metrics, constraints=study.constraints,
        x0={"crank": 0.3, "coupler": 1.0},
    )  # fmt: skip
    lam = np.linspace(1.2, 7.0, 400)
    a2, a3, a4 = dead_centre_family(lam, np.radians(45), np.radians(210))
    mu_lo = np.degrees(np.arccos((a3**2 + a4**2 - (1 - a2) ** 2) / (2 * a3 * a4)))
    mu_hi = np.degrees(np.arccos((a3**2 + a4**2 - (1 + a2) ** 2) / (2 * a3 * a4)))
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.6), width_ratios=(1.2, 1))
    ax.plot(lam, mu_lo, color="tab:blue", label="least transmission angle (crank at 0°)")
    ax.plot(lam, mu_hi, color="tab:orange", label="greatest (crank at 180°)")
    ax.axhline(90.0, color="0.5", lw=0.8)
    lam_best = best.params["coupler"] / best.params["crank"]
    mu_best = 90.0 - np.degrees(best.value)
    ax.plot(lam_best, mu_best, marker="*", ms=15, color="red", ls="none",
            label=f"optimiser: λ = {lam_best:.4f}, {mu_best:.3f}°")  # fmt: skip
    ax.set_xlabel("coupler / crank  λ  (the family: swing 45° while the crank turns 210°)")
    ax.set_ylabel("transmission angle [°]")
    ax.set_title("the one-parameter family and its best member", fontsize=10)
    ax.legend(fontsize=8, loc="center right")
    ax.grid(alpha=0.3)
    res = mech.solve(study.poses.values, params=best.params)  # continued from one to the other
    assert res.status.all_ok
    xy = {p: res.point(p)[0][[0, -1]] for p in ("O2", "O4", "A2", "B2")}
    for k, (style, label) in enumerate((("-", "extended dead centre"), ("--", "folded"))):
        chain = np.array([xy["O2"][k], xy["A2"][k], xy["B2"][k], xy["O4"][k]])
        ax2.plot(chain[:, 0], chain[:, 1], style, marker="o", color=f"C{k}", label=label)
    ax2.plot([0, 1], [0, 0], color="0.2", lw=3)
    ax2.set_aspect("equal")
    ax2.set_title("the optimum at its two dead centres (ground 1 m)", fontsize=10)
    ax2.legend(fontsize=8, loc="upper right")
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(IMG / "studies-transmission.png", dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
