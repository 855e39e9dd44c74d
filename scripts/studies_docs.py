"""Regenerate the figures of docs/studies.md: a design study of the crank-rocker and its
optimisation. Run: python scripts/studies_docs.py"""

from __future__ import annotations

import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

import excavkin  # noqa: E402
from excavkin.outputs.convergence import plot_convergence  # noqa: E402
from excavkin.studies.optimize import optimize  # noqa: E402
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
        study, settings = load_optimization(spec)
        table = pd.read_parquet(run_study(study, Path(tmp) / "study.parquet"))
    mech = excavkin.load(study.model)
    by_name = {m.name: m for m in study.metrics}
    best = optimize(
        mech, study.bounds, study.poses, by_name[settings["objective"]], settings["sense"],
        metrics=[m for m in study.metrics if m.name != settings["objective"]],
        constraints=study.constraints, loads=study.loads,
    )  # fmt: skip
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
    ax = plot_convergence(best.history, "torque_peak", unit="N·m")
    fig = ax.get_figure(root=True)
    assert fig is not None
    fig.tight_layout()
    fig.savefig(IMG / "studies-convergence.png", dpi=110)
    print(best)


if __name__ == "__main__":
    main()
