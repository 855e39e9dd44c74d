r"""The boom's loads along a dig: suspension ropes, boom-foot pin, shipper shaft, sheave.

The boom is a body of the general model, pivoted at its foot and held by its locked
suspension ropes; the general kinetostatics of the dig ([`dig`][excavkin.shovel.dig.dig])
holds it in equilibrium under what the front puts on it — the saddle's pin at the shipper shaft
and the hoist rope's wrap on the boom-point sheave, the resultant T·(u₁ + u₂) of its two free
segments (u the directions from the sheave along them) — and its own weight. The pinion on the
shipper shaft is the boom's, not the saddle's: the drives' efforts by virtual work
([`pinion_efforts`][excavkin.shovel.dig.pinion_efforts]) give the bail pull T', so the shaft
carries ΔT·t more (t the rope's direction at the bail, towards the sheave, ΔT = T' − T), the
sheave ΔT·(u₁ + u₂) more, and the boom the crowd drive's reaction couple σ·i·τm; the boom's
moment about its foot and its force balance take them up. From that equilibrium:

* the **suspension-rope tension** (all the ropes; per rope with the machine's count of
  suspension ropes — the model's rope is all of them);
* the **boom-foot pin**'s force on the boom, and its magnitude;
* the **shipper shaft**'s and the **boom-point sheave**'s forces on the boom.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.shovel.dig import Dig
from excavkin.shovel.machine import Shovel, table_attrs

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.outputs.machine_plot import MachinePlot


@dataclass(frozen=True, slots=True)
class BoomLoads:
    """The boom's loads at the rows of a dig, SI.

    Attributes
    ----------
    machine : str
    time : ndarray, shape (n,)
        s, the dig's.
    teeth : ndarray, shape (n, 2)
        The tooth tip (m).
    suspension : ndarray, shape (n,)
        The suspension ropes' tension, all of them (N).
    boom_foot, shipper_shaft, sheave : ndarray, shape (n, 2)
        The forces on the boom at its foot pin, the shipper shaft and the boom-point sheave's
        pin (N).
    status : ndarray of str, shape (n,)
        The dig's.
    """

    machine: str
    time: F
    teeth: F
    suspension: F
    boom_foot: F
    shipper_shaft: F
    sheave: F
    status: np.ndarray

    @property
    def ok(self) -> np.ndarray:
        """Rows whose status is ``"ok"``, shape (n,)."""
        return np.asarray(self.status == "ok")

    def summary(self) -> str:
        """Each load's largest magnitude over the rows that are ok, and where.

        Returns
        -------
        str
        """
        ok = self.ok
        lines = [f"{self.machine}: boom loads along the dig ({ok.sum()} of {ok.size} rows ok)"]
        if not ok.any():
            return "\n".join(lines)
        rows = np.flatnonzero(ok)
        for name, mag in (
            ("suspension ropes", self.suspension),
            ("boom-foot pin", np.hypot(*self.boom_foot.T)),
            ("shipper shaft", np.hypot(*self.shipper_shaft.T)),
            ("boom-point sheave", np.hypot(*self.sheave.T)),
        ):
            k = rows[np.argmax(mag[rows])]
            lines.append(
                f"  {name:<18} max {mag[k] / 1e3:8.0f} kN at {self.time[k]:6.2f} s "
                f"(tooth tip at {self.teeth[k, 1]:5.2f} m)"
            )
        return "\n".join(lines)

    def to_frame(self) -> pd.DataFrame:
        """The rows as a table, SI; ``attrs`` record the machine and the columns' kinds and
        units.

        Returns
        -------
        pandas.DataFrame
        """
        import pandas as pd

        cols = {
            "time": (self.time, "time"),
            "teeth_y": (self.teeth[:, 1], "length"),
            "suspension": (self.suspension, "force"),
            "boom_foot_x": (self.boom_foot[:, 0], "force"),
            "boom_foot_y": (self.boom_foot[:, 1], "force"),
            "shipper_shaft_x": (self.shipper_shaft[:, 0], "force"),
            "shipper_shaft_y": (self.shipper_shaft[:, 1], "force"),
            "sheave_x": (self.sheave[:, 0], "force"),
            "sheave_y": (self.sheave[:, 1], "force"),
        }
        frame = pd.DataFrame({k: v for k, (v, _) in cols.items()})
        frame["status"] = self.status
        frame.attrs.update(table_attrs(self.machine, {k: kind for k, (_, kind) in cols.items()}))
        return frame

    def plot(self, *, ax: Axes | None = None) -> MachinePlot:
        """The loads' magnitudes over the tooth tip's height.

        Parameters
        ----------
        ax : matplotlib Axes, optional

        Returns
        -------
        MachinePlot
        """
        from excavkin.shovel.plots import plot_boom_loads

        return plot_boom_loads(self, ax=ax)


def boom_loads(machine: Shovel, dug: Dig) -> BoomLoads:
    """The boom's loads at the rows of a dig (module docstring).

    Parameters
    ----------
    machine : Shovel
    dug : Dig
        From [`dig`][excavkin.shovel.dig.dig] on this machine.

    Returns
    -------
    BoomLoads
    """
    fr, front = dug.forces, machine.front
    kin = fr.kinematics
    rope = next(r for r in machine.mechanism.model.ropes if r.name == machine.hoist.rope)
    drum, centre, bail = (kin.point(p)[0] for p in rope.path)
    u_drum, u_bail = rope_segments(drum, centre, bail, rope.radii[0], rope.wraps[0] == "cw")
    delta = dug.bail_pull - fr.tension(machine.hoist.rope)
    extra_shaft = -delta[:, None] * u_bail  # the bail pulled towards the sheave: −u_bail
    extra_sheave = delta[:, None] * (u_drum + u_bail)
    couple = machine.crowd.sigma * machine.crowd.gear_ratio * dug.crowd_torque
    couple = couple * machine.crowd.motor.count
    foot = kin.point(front.boom_foot)[0]
    shaft = kin.point(front.shipper_shaft)[0]
    hang = next(r for r in machine.mechanism.model.ropes if r.name == front.suspension)
    anchor, pin = (kin.point(p)[0] for p in (hang.path[0], hang.path[-1]))
    along = (anchor - pin) / np.hypot(*(anchor - pin).T)[:, None]

    def moment(at: F, force: F) -> F:
        return (at[:, 0] - foot[:, 0]) * force[:, 1] - (at[:, 1] - foot[:, 1]) * force[:, 0]

    extra = moment(shaft, extra_shaft) + moment(centre, extra_sheave) + couple
    d_tension = -extra / moment(pin, along)
    d_foot = -(extra_shaft + extra_sheave + d_tension[:, None] * along)
    return BoomLoads(
        machine=machine.name,
        time=dug.time,
        teeth=dug.teeth,
        suspension=fr.tension(front.suspension) + d_tension,
        boom_foot=fr.pin(front.boom_foot, front.boom) + d_foot,
        shipper_shaft=fr.pin(front.shipper_shaft, front.boom) + extra_shaft,
        sheave=fr.pin(front.sheave, front.boom) + extra_sheave,
        status=dug.status,
    )


def rope_segments(a: F, centre: F, b: F, radius: float, cw: bool) -> tuple[F, F]:
    """The directions from a sheave along the two free segments of a rope over it, to its
    ends ``a`` and ``b``, shape (n, 2) each.

    Parameters
    ----------
    a, centre, b : ndarray, shape (n, 2)
        The rope's first end, the sheave's centre, its last end (m).
    radius : float
        The sheave's radius (m).
    cw : bool
        The rope turns clockwise around the sheave as it runs from ``a`` to ``b``.

    Returns
    -------
    to_a, to_b : ndarray, shape (n, 2)
        Unit vectors from the sheave's tangent points towards ``a`` and ``b``.
    """
    side = 1.0 if cw else -1.0

    def towards_tangent(p: F, turn: float) -> F:
        d = centre - p
        ang = np.arctan2(d[:, 1], d[:, 0]) + turn * np.arcsin(radius / np.hypot(d[:, 0], d[:, 1]))
        return np.stack([np.cos(ang), np.sin(ang)], axis=1)

    return -towards_tangent(a, side), -towards_tangent(b, -side)
