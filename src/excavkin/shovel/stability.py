r"""A rope shovel standing on its crawlers along a dig: tipping by the machinery layer.

The whole machine — the front at each row of a dig (its bodies' masses at their centres of
mass, from the engine's points), the upper works, counterweight and crawlers of the machine
file's ``[base]`` — stands on its tracks; the machinery layer's whole-machine equilibrium
([`equilibrium`][excavkin.machinery.equilibrium.equilibrium]) gives, per row, over the front
of the tracks (swing 0):

* the **tipping payload**: the least weight at the payload's centre of gravity that tips the
  machine, as a mass (kg), against the payload the dipper holds there;
* the **tipping digging force**: the least force on the teeth along the digging resistance's
  direction that tips it (N), against the resistance;
* the tipping line each binds about, and the **centre-of-mass margin**: the whole machine's
  centre of mass inside its support polygon without the payload (m).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.machinery.equilibrium import equilibrium
from excavkin.shovel.dig import Dig
from excavkin.shovel.machine import Shovel, table_attrs

if TYPE_CHECKING:
    import pandas as pd


@dataclass(frozen=True, slots=True)
class ShovelStability:
    """The machine's tipping limits at the rows of a dig, SI.

    Attributes
    ----------
    machine : str
    time : ndarray, shape (n,)
    payload : ndarray, shape (n,)
        The payload the dipper holds (kg).
    tipping_payload : ndarray, shape (n,)
        The least payload that tips the machine (kg; inf where none does).
    payload_line : ndarray of str, shape (n,)
    resistance : ndarray, shape (n,)
        The digging resistance's magnitude (N).
    tipping_force : ndarray, shape (n,)
        The least force along the resistance that tips the machine (N; inf where none does).
    force_line : ndarray of str, shape (n,)
    margin : ndarray, shape (n,)
        The centre of mass's least distance inside the support polygon, no payload (m).
    """

    machine: str
    time: F
    payload: F
    tipping_payload: F
    payload_line: np.ndarray
    resistance: F
    tipping_force: F
    force_line: np.ndarray
    margin: F

    def summary(self) -> str:
        """The least tipping payload and force over the dig, and the least margin.

        Returns
        -------
        str
        """
        k = int(np.nanargmin(self.tipping_payload))
        j = int(np.nanargmin(self.tipping_force))
        return "\n".join(
            [
                f"{self.machine}: stability on the crawlers along the dig",
                f"  tipping payload  least {self.tipping_payload[k] / 1e3:9.0f} t at "
                f"{self.time[k]:.2f} s ({self.payload_line[k]}); the dipper holds "
                f"{self.payload[k] / 1e3:.0f} t there",
                f"  tipping digging force least {self.tipping_force[j] / 1e3:6.0f} kN at "
                f"{self.time[j]:.2f} s ({self.force_line[j]}); the resistance is "
                f"{self.resistance[j] / 1e3:.0f} kN",
                f"  centre of mass   {np.nanmin(self.margin):9.2f} m inside the support at least",
            ]
        )

    def to_frame(self) -> pd.DataFrame:
        """The rows as a table, SI; ``attrs`` record the machine and the columns' kinds.

        Returns
        -------
        pandas.DataFrame
        """
        import pandas as pd

        cols = {
            "time": (self.time, "time"),
            "payload": (self.payload, "mass"),
            "tipping_payload": (self.tipping_payload, "mass"),
            "resistance": (self.resistance, "force"),
            "tipping_force": (self.tipping_force, "force"),
            "margin": (self.margin, "length"),
        }
        frame = pd.DataFrame({k: v for k, (v, _) in cols.items()})
        frame["payload_line"] = self.payload_line
        frame["force_line"] = self.force_line
        frame.attrs.update(table_attrs(self.machine, {k: kind for k, (_, kind) in cols.items()}))
        return frame


def stability(machine: Shovel, dug: Dig) -> ShovelStability:
    """The tipping limits at the rows of a dig (module docstring).

    Parameters
    ----------
    machine : Shovel
        With a ``[base]``.
    dug : Dig
        From [`dig`][excavkin.shovel.dig.dig] on this machine.

    Returns
    -------
    ShovelStability

    Raises
    ------
    ModelError
        The machine file has no ``[base]``.
    """
    kin = dug.forces.kinematics
    pos = kin.positions
    n = pos.shape[0]
    pc = kin.point(machine.dipper.payload_point)[0]
    down = np.broadcast_to(np.array([0.0, -1.0]), (n, 2))
    by_payload = equilibrium(machine, pos, pc, down, 0.0)
    tip = kin.point(machine.front.teeth)[0]
    _, vel, _ = kin.point(machine.front.teeth)
    speed = np.hypot(vel[:, 0], vel[:, 1])
    unit = vel / np.where(speed > 0.0, speed, 1.0)[:, None]
    into = np.stack([unit[:, 1], -unit[:, 0]], axis=1)
    soil = -dug.resistance_along[:, None] * unit + dug.resistance_normal[:, None] * into
    by_force = equilibrium(machine, pos, tip, soil, 0.0)
    return ShovelStability(
        machine=machine.name,
        time=dug.time,
        payload=machine.dipper.payload * dug.fill,
        tipping_payload=by_payload.tipping_load / machine.gravity,
        payload_line=by_payload.tipping_line,
        resistance=np.hypot(soil[:, 0], soil[:, 1]),
        tipping_force=by_force.tipping_load,
        force_line=by_force.tipping_line,
        margin=by_payload.margin,
    )
