r"""A rope shovel's digging envelope, from the engine over the hoist's and crowd's ranges.

The figures a shovel's working-range diagram gives, each at the pose the engine finds in the box
of hoist-rope lengths × crowd extensions ([`Shovel.solve`][excavkin.shovel.machine.Shovel.solve]):

* **cutting height**: the tooth tip's greatest height above the ground;
* **cutting radius**: the tooth tip's greatest radius from the slew axis;
* **dump height**: the greatest height of the open door's lower edge — the door hinge's height
  less the door's length, the door hanging open — and the **dump radius**, the hinge's radius
  at that pose;
* **radius at floor level**: the tooth tip's greatest radius on the ground (height 0).

Each maximum is found in batches: the box on a grid (one solve), then windows of 7 × 7 poses
about the best one, a third as wide each time (one solve per round for all three maxima), until
the window is below 1 µm of rope and crowd. The floor radius is a maximum on the curve where the
tip touches the ground: on each crowd extension of a grid the rope length that puts the tip on
the ground (Newton's method with the engine's transfer function, all extensions at once), the
best extension refined the same way. Poses the engine does not assemble (the rope would leave
its sheave) are left out. The envelope is the drives' reach: the forces that hold a pose are
the dig's and the loads' business.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.shovel.machine import Shovel, table_attrs

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.outputs.machine_plot import MachinePlot

#: the refinement's window (poses a side) and the width (m) at which it stops
_WINDOW, _TOL = 7, 1e-6
#: Newton iterations for the floor-level rope length
_NEWTON = 20


@dataclass(frozen=True, slots=True)
class Figure:
    """One figure of the envelope and the pose it is taken at.

    Attributes
    ----------
    name : str
    value : float
        m; NaN where no pose of the box reaches it.
    length, extension : float
        The pose: the hoist rope's length and the crowd's extension (m).
    x, y : float
        The point it is measured at (m, model coordinates).
    definition : str
    """

    name: str
    value: float
    length: float
    extension: float
    x: float
    y: float
    definition: str


@dataclass(frozen=True, slots=True)
class Envelope:
    """A shovel's digging envelope.

    Attributes
    ----------
    machine : str
        The machine's name.
    figures : tuple of Figure
    grid_length, grid_extension : ndarray, shape (n, n)
        The box's grid (m).
    grid_teeth : ndarray, shape (n, n, 2)
        The tooth tip over the grid (m); NaN where the pose does not assemble.
    """

    machine: str
    figures: tuple[Figure, ...]
    grid_length: F
    grid_extension: F
    grid_teeth: F

    def __getitem__(self, name: str) -> float:
        for f in self.figures:
            if f.name == name:
                return f.value
        raise KeyError(f"no figure {name!r}; figures: {', '.join(f.name for f in self.figures)}")

    def figure(self, name: str) -> Figure:
        """One figure with its pose.

        Parameters
        ----------
        name : str
            ``"cutting height"``, ``"cutting radius"``, ``"dump height"``, ``"dump radius"``
            or ``"radius at floor level"``.

        Returns
        -------
        Figure
        """
        for f in self.figures:
            if f.name == name:
                return f
        raise KeyError(f"no figure {name!r}; figures: {', '.join(f.name for f in self.figures)}")

    def summary(self) -> str:
        """The figures in metres with their poses, one line each.

        Returns
        -------
        str
        """
        lines = [f"{self.machine}: digging envelope"]
        for f in self.figures:
            lines.append(
                f"  {f.name:<24} {f.value:8.3f} m   (hoist rope {f.length:7.3f} m, "
                f"crowd {f.extension:6.3f} m)"
            )
        return "\n".join(lines)

    def to_frame(self) -> pd.DataFrame:
        """The figures as a table, SI: one row each, with its pose.

        Returns
        -------
        pandas.DataFrame
            Columns ``figure``, ``value``, ``hoist_length``, ``crowd_extension``, ``x``, ``y``
            (m) and ``definition``; ``attrs`` record the machine and the columns' kinds and
            units.
        """
        import pandas as pd

        frame = pd.DataFrame(
            {
                "figure": [f.name for f in self.figures],
                "value": [f.value for f in self.figures],
                "hoist_length": [f.length for f in self.figures],
                "crowd_extension": [f.extension for f in self.figures],
                "x": [f.x for f in self.figures],
                "y": [f.y for f in self.figures],
                "definition": [f.definition for f in self.figures],
            }
        )
        kinds = dict.fromkeys(("value", "hoist_length", "crowd_extension", "x", "y"), "length")
        frame.attrs.update(table_attrs(self.machine, kinds))
        return frame

    def plot(self, machine: Shovel, *, ax: Axes | None = None) -> MachinePlot:
        """The working-range diagram: the tooth tip's reach over the box, the front at the
        cutting-height pose, each figure marked.

        Parameters
        ----------
        machine : Shovel
            The machine this envelope is of.
        ax : matplotlib Axes, optional
            Drawn on; a new figure when omitted.

        Returns
        -------
        MachinePlot
        """
        from excavkin.shovel.plots import plot_envelope

        return plot_envelope(machine, self, ax=ax)


def _points(machine: Shovel, length: F, extension: F) -> tuple[F, F]:
    """The tooth tip and the door hinge over a batch of poses, NaN where it fails."""
    res = machine.solve(length, extension)
    return res.point(machine.front.teeth)[0], res.point(machine.front.door_hinge)[0]


def _objectives(machine: Shovel, teeth: F, hinge: F) -> F:
    """Per pose (n, 3): tooth height, tooth radius, open door's lower edge."""
    return np.stack([teeth[:, 1], teeth[:, 0], hinge[:, 1] - machine.dipper.door_length], axis=1)


def floor_length(machine: Shovel, length: F, extension: F) -> F:
    """The hoist rope's length that puts the tooth tip on the ground, per crowd extension:
    Newton's method from ``length``, all at once, with the engine's transfer function dy/dθ of
    the hoist motor's angle.

    Parameters
    ----------
    machine : Shovel
    length : ndarray, shape (n,)
        Where each search starts (m).
    extension : ndarray, shape (n,)
        Crowd extensions (m).

    Returns
    -------
    ndarray, shape (n,)
        Rope lengths (m) within the hoist's range; NaN where none was found.
    """
    rope, crowd = machine.hoist.rope, machine.crowd.driver
    i_r = machine.hoist.gear_ratio / machine.hoist.drum_radius
    L = length.copy()
    for _ in range(_NEWTON):
        res = machine.mechanism.solve(
            {rope: machine.hoist.angle(L), crowd: extension},
            rates={rope: np.ones_like(L), crowd: np.zeros_like(L)},
        )
        pos, vel, _ = res.point(machine.front.teeth)
        step = pos[:, 1] / (vel[:, 1] * i_r)  # dy/dL = dy/dθ · i/R
        L = np.clip(L - step, *machine.hoist.length)
        if not np.nanmax(np.abs(step), initial=0.0) > 1e-12:
            break
    res = machine.solve(L, extension)
    y = res.point(machine.front.teeth)[0][:, 1]
    return np.where(np.abs(y) < 1e-9, L, np.nan)


def envelope(machine: Shovel, samples: int = 41) -> Envelope:
    """The digging envelope over the hoist's and the crowd's ranges (module docstring).

    Parameters
    ----------
    machine : Shovel
    samples : int, default 41
        Grid poses a side of the box (≥ 3).

    Returns
    -------
    Envelope
    """
    if samples < 3:
        raise ValueError(f"samples must be at least 3, not {samples}")
    lo_l, hi_l = machine.hoist.length
    lo_s, hi_s = machine.crowd.extension
    gl, gs = np.meshgrid(
        np.linspace(lo_l, hi_l, samples), np.linspace(lo_s, hi_s, samples), indexing="ij"
    )
    teeth, hinge = _points(machine, gl.ravel(), gs.ravel())
    obj = _objectives(machine, teeth, hinge)
    safe = np.where(np.isfinite(obj), obj, -np.inf)
    best = np.argmax(safe, axis=0)
    cur_l, cur_s = gl.ravel()[best], gs.ravel()[best]
    hl, hs = (hi_l - lo_l) / (samples - 1), (hi_s - lo_s) / (samples - 1)
    offsets = np.linspace(-1.0, 1.0, _WINDOW)
    ol, os_ = (a.ravel() for a in np.meshgrid(offsets, offsets, indexing="ij"))
    m = ol.size
    while max(hl, hs) > _TOL:
        cand_l = np.clip(cur_l[:, None] + hl * ol[None, :], lo_l, hi_l)  # (3, m)
        cand_s = np.clip(cur_s[:, None] + hs * os_[None, :], lo_s, hi_s)
        t, h = _points(machine, cand_l.ravel(), cand_s.ravel())
        o = _objectives(machine, t, h).reshape(3, m, 3)
        val = np.where(np.isfinite(o), o, -np.inf)[np.arange(3), :, np.arange(3)]  # (3, m)
        k = np.argmax(val, axis=1)
        cur_l, cur_s = cand_l[np.arange(3), k], cand_s[np.arange(3), k]
        hl, hs = hl / 3.0, hs / 3.0
    t, h = _points(machine, cur_l, cur_s)
    o = _objectives(machine, t, h)

    floor_l, floor_s, floor_x = _floor(machine, teeth[:, 1].reshape(gl.shape), gl, gs)
    figs = (
        Figure("cutting height", float(o[0, 0]), float(cur_l[0]), float(cur_s[0]),
               float(t[0, 0]), float(t[0, 1]), "tooth tip's greatest height above the ground"),
        Figure("cutting radius", float(o[1, 1]), float(cur_l[1]), float(cur_s[1]),
               float(t[1, 0]), float(t[1, 1]), "tooth tip's greatest radius from the slew axis"),
        Figure("dump height", float(o[2, 2]), float(cur_l[2]), float(cur_s[2]),
               float(h[2, 0]), float(o[2, 2]),
               "open door's lower edge at its highest (door hinge less the door's length)"),
        Figure("dump radius", float(h[2, 0]), float(cur_l[2]), float(cur_s[2]),
               float(h[2, 0]), float(o[2, 2]), "door hinge's radius at the dump height's pose"),
        Figure("radius at floor level", floor_x, floor_l, floor_s, floor_x, 0.0,
               "tooth tip's greatest radius on the ground"),
    )  # fmt: skip
    return Envelope(machine.name, figs, gl, gs, teeth.reshape(*gl.shape, 2))


def _floor(machine: Shovel, y: F, gl: F, gs: F) -> tuple[float, float, float]:
    """The greatest radius of the tooth tip on the ground: start each crowd extension of the
    grid at its longest rope with the tip above → below the ground, Newton there, then refine
    the best extension by windows a third as wide."""
    lo_s, hi_s = machine.crowd.extension
    n = gl.shape[0]
    # per column (extension): the last rope length before the tip goes below the ground
    above = np.isfinite(y) & (y >= 0.0)
    crosses = above[:-1] & np.isfinite(y[1:]) & (y[1:] < 0.0)
    rows = np.where(crosses.any(axis=0), n - 2 - np.argmax(crosses[::-1], axis=0), -1)
    cols = np.flatnonzero(rows >= 0)
    if cols.size == 0:
        return float("nan"), float("nan"), float("nan")
    start = gl[rows[cols], cols]
    ext = gs[0, cols]
    L = floor_length(machine, start, ext)
    x = machine.solve(np.where(np.isfinite(L), L, start), ext).point(machine.front.teeth)[0][:, 0]
    x = np.where(np.isfinite(L), x, -np.inf)
    k = int(np.argmax(x))
    cur_s, cur_l = float(ext[k]), float(L[k])
    hs = (hi_s - lo_s) / (gs.shape[1] - 1)
    offsets = np.linspace(-1.0, 1.0, _WINDOW)
    while hs > _TOL:
        s = np.clip(cur_s + hs * offsets, lo_s, hi_s)
        Lk = floor_length(machine, np.full_like(s, cur_l), s)
        xk = machine.solve(np.where(np.isfinite(Lk), Lk, cur_l), s).point(machine.front.teeth)[0][
            :, 0
        ]
        xk = np.where(np.isfinite(Lk), xk, -np.inf)
        j = int(np.argmax(xk))
        cur_s, cur_l = float(s[j]), float(Lk[j])
        hs /= 3.0
    tip = machine.solve(np.array([cur_l]), np.array([cur_s])).point(machine.front.teeth)[0]
    return cur_l, cur_s, float(tip[0, 0])
