r"""The ground reactions under a crane's supports over a 360° slew.

The carrier is rigid and stands on its contact points (outrigger pads; a crawler's track
corners) as on equal springs that push but never pull: each point's reaction is
``R_i = a + b·u_i + c·v_i`` over the points that touch (plan coordinates u forward, v left,
about the slew axis), a, b, c from the three equilibrium equations::

    Σ R_i = W,   Σ R_i·u_i = W·ū,   Σ R_i·v_i = W·v̄

W the weight of the crane and the hook load, (ū, v̄) their centre of gravity in plan. A point
whose reaction comes out negative lifts off: the most negative is dropped and the rest solved
again, until every reaction is ≥ 0 (three pads left are statically determinate). Where fewer
than three points can carry it, the crane tips: NaN.
"""

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
class SupportReactions:
    """Reactions at every contact point over the slew angles (SI).

    Attributes
    ----------
    machine : str
    radius : float
        The hook's radius (m).
    second : float
        The second cylinder's length (m): the boom configuration.
    load : float
        The hook load (kg, hook block included).
    slew : ndarray, shape (n,)
        Slew angles (rad).
    points : ndarray, shape (p, 2)
        Each contact point in plan (u, v) (m).
    labels : list of str
        Each point's name (``"pad 1"`` … in the file's order; ``"left track 1"`` … the
        corners of a track).
    reaction : ndarray, shape (n, p)
        N; NaN where the crane tips.
    weight : float
        The crane's and the load's weight (N).
    centre : ndarray, shape (n, 2)
        Their centre of gravity in plan (m).
    """

    machine: str
    radius: float
    second: float
    load: float
    slew: F
    points: F
    labels: list[str]
    reaction: F
    weight: float
    centre: F

    def to_frame(self) -> pd.DataFrame:
        """One row per slew angle: each point's reaction (N) and the centre of gravity (m).

        Returns
        -------
        pandas.DataFrame
        """
        import pandas as pd

        cols: dict[str, object] = {"slew": self.slew}
        for j, name in enumerate(self.labels):
            cols[name] = self.reaction[:, j]
        cols["centre_u"], cols["centre_v"] = self.centre[:, 0], self.centre[:, 1]
        frame = pd.DataFrame(cols)
        frame.attrs["machine"] = self.machine
        return frame

    def summary(self) -> str:
        """Each point's largest and least reaction (kN) and the slew angles of them.

        Returns
        -------
        str
        """
        lines = [
            f"{self.machine}: support reactions over 360° of slew, {self.load:g} kg at "
            f"{self.radius:g} m, second cylinder {self.second * 1e3:.0f} mm; total "
            f"{self.weight / 1000:.1f} kN",
        ]
        if np.isnan(self.reaction).any():
            tip = np.degrees(self.slew[np.isnan(self.reaction).any(axis=1)])
            lines.append(f"  TIPS at slew {tip.min():.0f}°..{tip.max():.0f}°")
        for j, name in enumerate(self.labels):
            r = self.reaction[:, j]
            if np.isnan(r).all():
                continue
            hi, lo = int(np.nanargmax(r)), int(np.nanargmin(r))
            lines.append(
                f"  {name:<14} max {r[hi] / 1000:8.1f} kN at {np.degrees(self.slew[hi]):4.0f}°"
                f"   min {r[lo] / 1000:8.1f} kN at {np.degrees(self.slew[lo]):4.0f}°"
            )
        return "\n".join(lines)

    def plot(self, *, ax: Axes | None = None) -> MachinePlot:
        """Each point's reaction over the slew angle.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Drawn on; a new figure when omitted.

        Returns
        -------
        MachinePlot
        """
        from excavkin.outputs.machine_plot import MachinePlot, figure_axes

        fig, ax = figure_axes(ax, (7.0, 4.5))
        lines = {}
        for j, name in enumerate(self.labels):
            (lines[name],) = ax.plot(np.degrees(self.slew), self.reaction[:, j] / 1000, label=name)
        ax.set_xlabel("slew angle (°)")
        ax.set_ylabel("reaction (kN)")
        ax.set_title(self.machine)
        ax.grid(True, alpha=0.3)
        ax.legend()
        return MachinePlot(fig, ax, lines)


def support_reactions(
    crane: Crane, radius: float, second: float, load: float, samples: int = 73
) -> SupportReactions:
    """The reactions at every contact point over a full slew (module docstring).

    Parameters
    ----------
    crane : Crane
    radius : float
        Hook radius (m).
    second : float
        The second cylinder's length (m).
    load : float
        Hook load (kg, hook block included).
    samples : int
        Slew angles over 360°, both ends included.

    Returns
    -------
    SupportReactions

    Raises
    ------
    InputError
        The pose out of reach, a negative load, or fewer than 2 samples.
    """
    if samples < 2:
        raise InputError("at least 2 slew angles")
    if not np.isfinite(load) or load < 0:
        raise InputError(f"the load must be at least 0 kg, not {load:g}")
    pose = crane.pose(np.array([radius]), np.array([second]))
    if not pose.reached[0]:
        raise InputError(
            f"radius {radius:g} m with the {crane.second.role} cylinder at "
            f"{second * 1e3:.0f} mm is out of reach (see `excavkin crane range`)"
        )
    alpha = np.linspace(-np.pi, np.pi, samples)
    d = np.stack([np.cos(alpha), np.sin(alpha)], -1)
    sup = crane.support
    booms = crane.mass_points
    at = booms.locate(pose.kinematics.positions)[0]  # (k, 2)
    s = float(booms.mass @ at[:, 0]) + sum(m.mass * m.x for m in sup.turning)
    r = float(crane.tip(pose.kinematics)[0, 0])
    total = crane.mass + load
    centre = (s * d + load * r * d) / total
    centre[:, 0] += sum(m.mass * m.x for m in sup.fixed) / total
    pts, owners = sup.contact_points(crane.swing_axis, 0.0)
    kinds = {"outriggers": "pad {k}", "tyres": "{label}"}
    labels = [
        kinds.get(sup.contacts[e].kind, "{label} {i}").format(
            k=k + 1, i=i + 1, label=sup.contacts[e].labels[i]
        )
        for k, (e, i) in enumerate(owners)
    ]
    weight = crane.gravity * total
    reaction = _reactions(pts, centre, weight)
    return SupportReactions(
        crane.name, radius, second, load, alpha, pts, labels, reaction, weight, centre
    )


def _reactions(pts: F, centre: F, weight: float) -> F:
    """Compression-only reactions of equal springs under a rigid body (module docstring)."""
    n, p = centre.shape[0], pts.shape[0]
    active = np.ones((n, p), dtype=bool)
    basis = np.stack([np.ones(p), pts[:, 0], pts[:, 1]], -1)  # (p, 3)
    out = np.full((n, p), np.nan)
    rhs = weight * np.stack([np.ones(n), centre[:, 0], centre[:, 1]], -1)  # (n, 3)
    done = np.zeros(n, dtype=bool)
    for _ in range(p):  # at most one point drops per round; every slew angle at once
        w = active[:, :, None] * basis[None]  # (n, p, 3)
        a = np.einsum("npi,npj->nij", w, basis[None].repeat(n, 0))
        ok = np.abs(np.linalg.det(a)) > 1e-9 * max(1.0, float(np.abs(pts).max()) ** 4)
        coef = np.zeros((n, 3))
        coef[ok] = np.linalg.solve(a[ok], rhs[ok][..., None])[..., 0]
        r = np.where(active, coef @ basis.T, 0.0)
        worst = np.argmin(r, axis=1)
        neg = r[np.arange(n), worst] < -1e-9 * weight
        settle = ok & ~neg & ~done
        out[settle] = r[settle]
        done |= settle | ~ok
        drop = ok & neg & ~done
        active[np.arange(n)[drop], worst[drop]] = False
        if done.all():
            break
    return out
