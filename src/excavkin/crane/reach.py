"""A crane's working range: the boom tip over both cylinders' strokes."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.crane.machine import Crane
from excavkin.errors import InputError

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.outputs.machine_plot import MachinePlot


@dataclass(frozen=True, slots=True)
class Reach:
    """The tip over a grid of luffing × knuckle cylinder lengths (SI).

    Attributes
    ----------
    machine : str
    luff, second : ndarray, shape (n, n)
        The cylinder lengths (m).
    boom_angle : ndarray, shape (n, n)
        The boom's angle above the horizontal, boom pin to tip for a telescopic crane, boom
        pin to knuckle pin for a knuckle crane (rad).
    config : ndarray, shape (n, n)
        The knuckle angle (rad) or the boom length (m).
    config_name : str
    tip : ndarray, shape (n, n, 2)
        The jib's tip (radius, height) (m).
    booms : ndarray, shape (n, n, k, 2)
        The booms' line at each pair of lengths: the boom pin, the knuckle pin (a knuckle
        crane) and the tip (m).
    """

    machine: str
    luff: F
    second: F
    boom_angle: F
    config: F
    config_name: str
    tip: F
    booms: F

    def to_frame(self) -> pd.DataFrame:
        """One row per pair of lengths.

        Returns
        -------
        pandas.DataFrame
        """
        import pandas as pd

        frame = pd.DataFrame(
            {
                "luff_cyl": self.luff.ravel(),
                "second_cyl": self.second.ravel(),
                "boom_angle": self.boom_angle.ravel(),
                self.config_name.replace(" ", "_"): self.config.ravel(),
                "radius": self.tip[..., 0].ravel(),
                "height": self.tip[..., 1].ravel(),
            }
        )
        frame.attrs["machine"] = self.machine
        return frame

    def summary(self) -> str:
        """The boom's angle range, the configuration's, the radius range, the highest tip, and
        the radius range at each end of the second cylinder's stroke.

        Returns
        -------
        str
        """
        x, y = self.tip[..., 0], self.tip[..., 1]
        k = np.unravel_index(int(np.argmax(y)), y.shape)
        out = [
            f"{self.machine}: working range of the boom tip (the hook hangs below it)",
            f"  boom angle     {np.degrees(self.boom_angle.min()):7.1f}° .. "
            f"{np.degrees(self.boom_angle.max()):7.1f}°",
            f"  {self.config_name:<14} {self._config(self.config.min())} .. "
            f"{self._config(self.config.max())}",
            f"  radius         {x.min():7.2f} .. {x.max():7.2f} m",
            f"  highest tip    {y[k]:7.2f} m at radius {x[k]:.2f} m",
        ]
        for j, end in ((0, "retracted"), (-1, "extended")):
            out.append(
                f"  second cylinder {end:<9} ({self._config(self.config[0, j])}): radius "
                f"{x[:, j].min():6.2f} .. {x[:, j].max():6.2f} m"
            )
        return "\n".join(out)

    def _config(self, v: float) -> str:
        if self.config_name == "knuckle angle":
            return f"{np.degrees(v):7.1f}°"
        return f"{v:7.2f} m"

    def plot(self, *, ax: Axes | None = None) -> MachinePlot:
        """The working-range diagram: the tip over the strokes (one curve per length of each
        cylinder), the envelope's outline, the booms at the strokes' four corners, the ground
        and the slew axis.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Drawn on; a new figure when omitted.

        Returns
        -------
        MachinePlot
        """
        from excavkin.outputs.machine_plot import MachinePlot, figure_axes

        fig, ax = figure_axes(ax, (6.5, 5.5))
        t = self.tip
        (grid,) = ax.plot(t[..., 0], t[..., 1], color="0.8", lw=0.5)[:1]
        ax.plot(t[..., 0].T, t[..., 1].T, color="0.8", lw=0.5)
        edge = np.concatenate([t[0, :], t[:, -1], t[-1, ::-1], t[::-1, 0]])
        (outline,) = ax.plot(edge[:, 0], edge[:, 1], color="C0", lw=1.8, label="tip's envelope")
        for i, j in ((0, 0), (0, -1), (-1, 0), (-1, -1)):
            b = self.booms[i, j]
            (boom,) = ax.plot(b[:, 0], b[:, 1], color="C1", lw=1.2, marker="o", ms=3)
        boom.set_label("booms at the strokes' ends")
        ax.axhline(0.0, color="0.3", lw=1.0)
        ax.axvline(0.0, color="0.3", lw=0.8, ls="--")
        ax.annotate("slew axis", (0.0, 0.02), xycoords=("data", "axes fraction"), rotation=90,
                    ha="right", va="bottom", fontsize=8, color="0.3")  # fmt: skip
        ax.set_aspect("equal")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=8)
        ax.set_xlabel("radius (m)")
        ax.set_ylabel("height (m)")
        ax.set_title(self.machine)
        return MachinePlot(fig, ax, {"grid": grid, "outline": outline, "boom": boom})


def reach(crane: Crane, samples: int = 21) -> Reach:
    """The tip over ``samples`` × ``samples`` lengths of both cylinders' strokes.

    Parameters
    ----------
    crane : Crane
    samples : int
        Lengths over each stroke, both ends included.

    Returns
    -------
    Reach

    Raises
    ------
    InputError
        Fewer than 2 samples.
    """
    if samples < 2:
        raise InputError("at least 2 samples over each stroke")
    lu, se = (np.linspace(c.retracted, c.extended, samples) for c in crane.cylinders)
    ll, kk = np.meshgrid(lu, se, indexing="ij")
    kin = crane.solve(np.column_stack([ll.ravel(), kk.ravel()]))
    p = kin.positions
    a = p[:, crane.index(crane.boom_pin)]
    far = p[:, crane.index(crane.knuckle_pin or crane.linkage.tip)]
    line = [crane.boom_pin, crane.knuckle_pin, crane.linkage.tip]
    booms = p[:, [crane.index(n) for n in line if n is not None]]
    angle = np.arctan2(far[:, 1] - a[:, 1], far[:, 0] - a[:, 0])
    shape = ll.shape
    return Reach(
        crane.name,
        ll,
        kk,
        angle.reshape(shape),
        crane.configuration(kin).reshape(shape),
        crane.configuration_name,
        crane.tip(kin).reshape(*shape, 2),
        booms.reshape(*shape, -1, 2),
    )
