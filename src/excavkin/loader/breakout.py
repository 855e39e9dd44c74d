r"""Breakout force of a wheel loader per SAE J732 / ISO 14397-2.

SAE J732 (JUN92): the largest sustained vertical upward force exerted 100 mm behind the tip of
the bucket's cutting edge, through the lift or the rollback (tilt) circuit about its pivot, with
the loader on a hard level surface, at operating mass, the rear not tied down, and the bottom of
the cutting edge parallel to and within 20 mm of the ground line. Through the **tilt circuit**
the pivot is the bucket hinge pin, the machine blocked under it (the lift arm does not move and
the lift cylinders carry nothing of the test force); through the **lift circuit** the pivot is
the lift-arm pin, the front axle blocked (no tyre deflection) and the tilt cylinder holding.
ISO 14397-2 measures the same force.

The pose: the floor level with the cutting edge on the ground
([`ground_pose`][excavkin.loader.poses.ground_pose]). With the machine at rest, virtual power
over a motion of cylinder c alone gives the force it must carry against a force P on the bucket
at the point Q 100 mm behind the edge (along the floor), its weight included::

    f_c = −P·J_c + G_c          J_c = ∂Q/∂L_c (engine, exact),  G_c the gravity terms

The test restrains the bucket, which pushes up with F: the restraint's force on it is
P = −F·e_y, so only the vertical column of J enters and ``f_c = F·∂y_Q/∂L_c + G_c``. The
working cylinder at its circuit's working pressure, each holding cylinder within its port
relief, gives the hydraulic limit
([`capped_force`][excavkin.machinery.capped_force.capped_force] on J's vertical row, the
binding cylinder named). The restraint's reaction, F downward at Q, tips the machine about its
front support (the block under the hinge pin for the tilt circuit, the front axle for the lift
circuit): F is capped by that tipping load too
([`cap_by`][excavkin.machinery.capped_force.cap_by]), named ``"tipping (LINE)"``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.loader.machine import Loader, table_attrs, transfer
from excavkin.loader.poses import ground_pose
from excavkin.loader.stability import Support, tipping
from excavkin.machinery.capped_force import cap_by, capped_force, gravity_terms, pressure_limits

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.loader.plots import LoaderPlot

#: how far behind the tip of the cutting edge the breakout force acts (SAE J732): 100 mm
BEHIND_EDGE = 0.1


@dataclass(frozen=True, slots=True)
class CircuitBreakout:
    """The breakout force through one circuit.

    Attributes
    ----------
    circuit : {"tilt", "lift"}
        The working cylinder's role.
    pivot : str
        ``"bucket hinge pin"`` or ``"lift-arm pin"``.
    force : float
        The breakout force (N), under every limit.
    hydraulic : float
        The force the working cylinder at working pressure gives, the other within relief (N).
    working : float
        The working cylinder's own limit (N).
    tipping : float
        The tipping limit (N).
    limiting : str
        What binds: the working cylinder's role, the holding cylinder's role, or
        ``"tipping (LINE)"``.
    cylinder_force : ndarray, shape (2,)
        Lift and tilt cylinder forces at the breakout force (N, > 0 pushing); the lift's is NaN
        through the tilt circuit (the block carries the arm).
    """

    circuit: str
    pivot: str
    force: float
    hydraulic: float
    working: float
    tipping: float
    limiting: str
    cylinder_force: F


@dataclass(frozen=True, slots=True)
class Breakout:
    """SAE J732 / ISO 14397-2 breakout forces through both circuits.

    Attributes
    ----------
    machine : str
    lengths : ndarray, shape (2,)
        The pose's lift and tilt lengths (m).
    point : ndarray, shape (2,)
        Where the force acts: 100 mm behind the cutting edge (m).
    tilt, lift : CircuitBreakout
    """

    machine: str
    lengths: F
    point: F
    tilt: CircuitBreakout
    lift: CircuitBreakout

    def to_frame(self) -> pd.DataFrame:
        """Both circuits as a table, SI.

        Returns
        -------
        pandas.DataFrame
            One row per circuit; ``attrs`` record the machine and the columns' kinds and units
            (``excavkin.model``, ``excavkin.kinds``, ``excavkin.units``).
        """
        import pandas as pd

        rows = (self.tilt, self.lift)
        frame = pd.DataFrame(
            {
                "circuit": [r.circuit for r in rows],
                "pivot": [r.pivot for r in rows],
                "force": [r.force for r in rows],
                "hydraulic": [r.hydraulic for r in rows],
                "working": [r.working for r in rows],
                "tipping": [r.tipping for r in rows],
                "limiting": [r.limiting for r in rows],
                "lift_cyl_force": [r.cylinder_force[0] for r in rows],
                "tilt_cyl_force": [r.cylinder_force[1] for r in rows],
            }
        )
        cols = ("force", "hydraulic", "working", "tipping", "lift_cyl_force", "tilt_cyl_force")
        frame.attrs.update(table_attrs(self.machine, dict.fromkeys(cols, "force")))
        return frame

    def plot(self, *, ax: Axes | None = None) -> LoaderPlot:
        """Each circuit's breakout force with the limits that cap it (SAE J732).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Drawn on; a new figure when omitted.

        Returns
        -------
        LoaderPlot
        """
        from excavkin.loader.plots import plot_breakout

        return plot_breakout(self, ax=ax)

    def summary(self) -> str:
        """Both breakout forces in kN with their binding limits.

        Returns
        -------
        str
        """
        lines = [f"{self.machine}: breakout force (SAE J732 / ISO 14397-2)"]
        for r in (self.tilt, self.lift):
            lines.append(
                f"  {r.circuit:<5} circuit about the {r.pivot:<17} {r.force / 1e3:8.1f} kN  "
                f"(limited by {r.limiting}; tipping at {r.tipping / 1e3:.1f} kN)"
            )
        return "\n".join(lines)


def breakout(machine: Loader) -> Breakout:
    """The breakout forces through the tilt and the lift circuit (module docstring).

    Parameters
    ----------
    machine : Loader

    Returns
    -------
    Breakout

    Raises
    ------
    ModelError
        Naming the machine file, where no pose within the strokes sets the floor level
        with the edge on the ground.
    """
    L = ground_pose(machine)[None, :]
    tr = transfer(machine, L)
    edge, d_edge = tr.point(machine, machine.linkage.edge)
    heel, d_heel = tr.point(machine, machine.linkage.heel)
    v, dv = edge - heel, d_edge - d_heel
    r = np.hypot(v[:, 0], v[:, 1])
    u = v / r[:, None]
    # Q = edge − 0.1·u, u the unit floor direction; ∂u = (∂v − u·(u·∂v))/|v|
    du = (dv - u[:, :, None] * np.einsum("ni,nic->nc", u, dv)[:, None, :]) / r[:, None, None]
    point = edge - BEHIND_EDGE * u
    J = d_edge - BEHIND_EDGE * du  # (1, 2, 2)
    Jy = np.zeros_like(J)
    Jy[:, 1, :] = J[:, 1, :]  # only the vertical motion of Q does work on a vertical force
    G = gravity_terms(machine, tr.d)
    hinge_x = tr.positions[0, machine.index(machine.pins.hinge), 0]
    half = 0.5 * machine.chassis.tread
    block = (
        Support("block under the hinge pin (left)", float(hinge_x), half, True),
        Support("block under the hinge pin (right)", float(hinge_x), -half, True),
    )
    out = {}
    for w, role, pivot, extra in (
        (1, "tilt", "bucket hinge pin", block),
        (0, "lift", "lift-arm pin", ()),
    ):
        limits = pressure_limits(machine.cylinders, machine.circuits, w)
        if role == "tilt":  # the block carries the lift arm
            limits[0] = (-np.inf, np.inf)
        sign = machine.rollback_sign() if role == "tilt" else machine.raise_sign()
        force, working, limiting, cyl, direction = capped_force(
            Jy, G, w, sign, limits, machine.roles
        )
        up = direction[:, 1] > 0.0  # the working motion lifts Q
        force = np.where(up, force, 0.0)
        tip = tipping(machine, tr.positions, point, 0.0, extra)
        hydraulic = force.copy()
        tip_name = np.array([f"tipping ({tip.line[0]})"])
        capped, limiting = cap_by(force, limiting, [(tip_name, tip.load)])
        cyl = capped[:, None] * np.einsum("ni,nic->nc", direction, Jy) + G
        if role == "tilt":
            cyl[:, 0] = np.nan
        out[role] = CircuitBreakout(
            role,
            pivot,
            float(capped[0]),
            float(hydraulic[0]),
            float(working[0]) if up[0] else 0.0,
            float(tip.load[0]),
            str(limiting[0]) if up[0] else "the working motion does not lift the edge",
            cyl[0],
        )
    return Breakout(machine.name, L[0], point[0], out["tilt"], out["lift"])
