"""Regenerate the figures of docs/designs.md: the rope shovel's bucket attitude against its
link lengths, and the excavator's tolerance bands. Run: python scripts/designs_docs.py"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import excavkin  # noqa: E402
from excavkin.outputs.bands import plot_bands  # noqa: E402

IMG = Path(__file__).parents[1] / "docs" / "img"


def rope_shovel() -> None:
    mech = excavkin.load(excavkin.example_path("rope_shovel"))
    drag = np.linspace(5.3, 6.3, 101)
    names = ["C-D", "A-B", "D.x", "B.x"]
    res = mech.solve({"drag": drag}, sensitivities=names)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    top.plot(drag * 1e3, np.degrees(res.column("bucket.angle")), color="black")
    for cd in (2330.0, 2430.0):
        other = mech.solve({"drag": drag}, params={"C-D": cd / 1e3})
        top.plot(
            drag * 1e3,
            np.degrees(other.column("bucket.angle")),
            ls="--",
            label=f"C-D = {cd:.0f} mm",
        )
    top.set_ylabel("bucket.angle [°]")
    top.legend(title="nominal C-D = 2380 mm (solid)", fontsize=8)
    top.grid(alpha=0.3)
    for name in names:  # degrees of bucket attitude per millimetre
        bottom.plot(
            drag * 1e3,
            np.degrees(res.sensitivity("bucket.angle", name)) / 1e3,
            label=f"d(bucket.angle)/d({name})",
        )
    bottom.set_xlabel("drag rope length F–E [mm]")
    bottom.set_ylabel("[°/mm]")
    bottom.legend(fontsize=8)
    bottom.grid(alpha=0.3)
    fig.suptitle("EO-4112 rope backhoe: bucket attitude and its exact sensitivities", fontsize=10)
    fig.tight_layout()
    fig.savefig(IMG / "designs-rope-shovel.png", dpi=100)


def excavator() -> None:
    mech = excavkin.load(excavkin.example_path("excavator"))
    bucket = np.linspace(1.80, 2.55, 31)  # within the stroke, away from its toggles
    tols = {n: "±0.5 mm" for n in ("F.x", "F.y", "K.x", "K.y", "N.x", "N.y")}
    tols["bucket.mass"] = "±25 kg"
    bands = excavkin.tolerance_bands(
        mech,
        {"bucket_cyl": bucket},
        tolerances=tols,
        clearance="0.3 mm",
        loads="model",
        columns=["W.y", "bucket_cyl.force"],
        draws=100_000,
    )
    fig, axes = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    plot_bands(bands, "W.y", bucket * 1e3, x_label="bucket_cyl [mm]", ax=axes[0])
    plot_bands(bands, "bucket_cyl.force", bucket * 1e3, x_label="bucket_cyl [mm]", ax=axes[1])
    fig.tight_layout()
    fig.savefig(IMG / "designs-excavator-bands.png", dpi=100)


if __name__ == "__main__":
    rope_shovel()
    excavator()
