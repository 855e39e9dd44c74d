"""Regenerate the figure and the figures of docs/studies.md's bucket-linkage section: the
optimum of examples/studies/excavator_bucket_linkage.toml, its working ranges against the
nominal machine's, and the brute-force slice of the two parameters not at a bound.
Run: python scripts/excavator_linkage_docs.py"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import excavkin  # noqa: E402
from excavkin.excavator.designs import design_machine  # noqa: E402
from excavkin.excavator.ranges import working_ranges  # noqa: E402
from excavkin.excavator.study import load_machine_study, optimize_machine  # noqa: E402

IMG = Path(__file__).parents[1] / "docs" / "img"


def main() -> None:
    study = load_machine_study(excavkin.example_path("excavator_bucket_linkage"))
    nominal = {k: study.machine.mechanism.parameters[k] for k in study.bounds}
    base = study.evaluate({k: np.array([v]) for k, v in nominal.items()})
    t0 = time.perf_counter()
    best = optimize_machine(study)
    took = time.perf_counter() - t0
    f0 = float(base["force_min"][0])
    print(
        f"nominal {f0 / 1e3:.2f} kN, optimum {best.value / 1e3:.2f} kN, "
        f"gain {100 * (best.value / f0 - 1):.1f} %, {best.evaluations} designs, {took:.1f} s"
    )
    for k, v in best.params.items():
        print(
            f"  {k}: {nominal[k] * 1e3:.1f} -> {v * 1e3:.1f} mm ({(v - nominal[k]) * 1e3:+.1f})"
            f" {best.at_bounds.get(k, '')}"
        )
    for k in ("open_angle", "curled_angle"):
        print(f"  {k}: {np.degrees(base[k][0]):.3f} -> {np.degrees(best.metrics[k]):.3f} deg")
    before = working_ranges(study.machine).figures
    after = {
        f.key: f.value for f in working_ranges(design_machine(study.machine, best.params)).figures
    }
    for f in before:
        print(
            f"  | {f.label} | {f.value:.3f} | {after[f.key]:.3f} | "
            f"{100 * (after[f.key] / f.value - 1):+.2f} % |"
        )
    # the slice of the two parameters not at a bound, the others at the optimum: the whole
    # box, and 4 mm around the optimum
    a, b = (k for k in study.bounds if k not in best.at_bounds)
    fig, axes = plt.subplots(1, 2, figsize=(11.5, 5.2), width_ratios=[1.25, 1])
    boxes = (
        (study.bounds[a], study.bounds[b], 161),
        ((best.params[a] - 0.004, best.params[a] + 0.004),
         (best.params[b] - 0.004, best.params[b] + 0.004), 81),
    )  # fmt: skip
    for ax, (ra, rb, n) in zip(axes, boxes, strict=True):
        A, B = np.meshgrid(np.linspace(*ra, n), np.linspace(*rb, n), indexing="ij")
        designs = {k: np.full(A.size, v) for k, v in best.params.items()}
        designs[a], designs[b] = A.ravel(), B.ravel()
        table = study.evaluate(designs)
        force = table["force_min"].to_numpy().reshape(n, n) / 1e3
        feasible = table["feasible"].to_numpy().reshape(n, n)
        top = force[feasible].max()
        print(
            f"grid {n}x{n}: {feasible.sum()} feasible, best {top:.3f} kN "
            f"({100 * (top * 1e3 / best.value - 1):+.3f} % of the optimum)"
        )
        x, y = (A - nominal[a]) * 1e3, (B - nominal[b]) * 1e3
        cs = ax.contourf(x, y, force, levels=20, cmap="viridis")
        fig.colorbar(cs, ax=ax, label="smallest rated bucket force over the curl (kN)")
        for key, colour in (("open_angle", "white"), ("curled_angle", "orange")):
            off = np.degrees(np.angle(np.exp(1j * (table[key].to_numpy() - base[key][0]))))
            ax.contour(x, y, off.reshape(n, n), levels=[-0.5, 0.5], colors=colour,
                       linewidths=1.4, linestyles="solid")  # fmt: skip
            ax.plot([], [], color=colour, label=f"{key.replace('_', ' ')}: nominal ± 0.5°")
        ax.plot(
            x[feasible],
            y[feasible],
            "w.",
            ms=2 if n > 100 else 3,
            label=f"feasible grid points ({feasible.sum()})",
        )
        ax.plot(
            (best.params[a] - nominal[a]) * 1e3,
            (best.params[b] - nominal[b]) * 1e3,
            "r*",
            ms=16,
            mec="k",
            label=f"optimum {best.value / 1e3:.2f} kN",
        )
        ax.set_xlabel(f"{a} − nominal (mm)")
        ax.set_ylabel(f"{b} − nominal (mm)")
        ax.set_title(f"{n} × {n} grid: best feasible {top:.2f} kN", fontsize=10)
    axes[0].legend(loc="upper right", fontsize=8, framealpha=0.9)
    others = ", ".join(f"{k} {(v - nominal[k]) * 1e3:+.0f} mm" for k, v in best.params.items()
                       if k in best.at_bounds)  # fmt: skip
    fig.suptitle(f"Bucket linkage: the slice through the optimum ({others})", fontsize=11)
    fig.tight_layout()
    fig.savefig(IMG / "studies-excavator-linkage.png", dpi=110)


if __name__ == "__main__":
    main()
