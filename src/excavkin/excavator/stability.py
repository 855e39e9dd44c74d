r"""Tipping and slipping of an excavator, and its tool forces capped by them.

The whole machine's equilibrium on the ground (the tipping load about any line of the
support polygon, the slipping load) is the machinery layer's
[`equilibrium`][excavkin.machinery.equilibrium.equilibrium], whose docstring writes the model;
this module loads it with the excavator's loads: a tool force at the lip or tooth tip along a
direction, a load hung at the bucket pin, with the upper structure swung over the front or the
side of the tracks.

Tool forces (ISO 6015) are then capped by these limits as well
([`capped_tool_forces`][excavkin.excavator.stability.capped_tool_forces],
[`base_rated_force`][excavkin.excavator.stability.base_rated_force]), with the limit that binds
named, as ISO 6015 §3.17–3.19 and §4.5
name them: the hydraulic limit (a cylinder), the tipping limit, the slipping limit.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.excavator.forces import At, RatedForce, ToolForces, Working, rated_force, tool_forces
from excavkin.excavator.machine import Machine, as_lengths
from excavkin.kinematics.summary import batch_repr
from excavkin.machinery.base import BaseMachine
from excavkin.machinery.capped_force import cap_by, stability_caps
from excavkin.machinery.equilibrium import Stability, equilibrium
from excavkin.machinery.equilibrium import need_base as need_support
from excavkin.machinery.search import Progress, part

__all__ = [
    "SWING",
    "BaseRatedForce",
    "CappedToolForces",
    "Over",
    "Stability",
    "base_limits",
    "base_rated_force",
    "capped_tool_forces",
    "equilibrium",
    "need_base",
    "stability",
]

#: where the machine's front points: over the front (idler) end of the tracks, or over the side
Over = Literal["front", "side"]
SWING: dict[str, float] = {"front": 0.0, "side": 0.5 * np.pi}


def need_base(machine: Machine) -> BaseMachine:
    """The excavator's base machine (its ``[base]`` table).

    Parameters
    ----------
    machine : Machine

    Returns
    -------
    BaseMachine

    Raises
    ------
    ModelError
        Naming the missing ``[base]`` table and the machine file.
    """
    return cast("BaseMachine", need_support(machine))


def _swing(swing: float | Over) -> float:
    if isinstance(swing, str):
        if swing not in SWING:
            raise InputError(f"swing must be 'front', 'side' or an angle, not {swing!r}")
        return SWING[swing]
    return float(swing)


def stability(
    machine: Machine,
    lengths: ArrayLike,
    point: str,
    direction: ArrayLike = (0.0, -1.0),
    *,
    swing: float | Over = "front",
) -> Stability:
    """Tipping and slipping loads of a force at a point of the front, at each pose.

    Parameters
    ----------
    machine : Machine
        With a base.
    lengths : array_like, shape (n, 3)
        Boom, arm, bucket cylinder lengths (m).
    point : str
        The model's point where the load acts (``machine.front.lip``, ``machine.pins.bucket_pin``).
    direction : array_like, shape (2,) or (n, 2)
        Direction of the force on the machine, in the front's plane; default straight down (a
        hanging load).
    swing : float or {"front", "side"}
        Swing angle of the upper structure (rad), or over the front (0) or the side (π/2).

    Returns
    -------
    Stability
    """
    L = as_lengths(lengths)
    res = machine.solve(L)
    if point not in machine.mechanism.plan.points:
        raise InputError(f"no point {point!r} in the machine's model")
    return equilibrium(
        machine,
        res.positions,
        res.point(point)[0],
        np.asarray(direction, dtype=np.float64),
        _swing(swing),
        res.status.ok,
    )


# ------------------------------------------------------------------------- capped tool forces
@dataclass(frozen=True, slots=True)
class CappedToolForces:
    """ISO 6015 tool forces capped by the hydraulic, tipping and slipping limits.

    Attributes
    ----------
    force : ndarray, shape (n,)
        The least of the three (N).
    limiting : ndarray of str, shape (n,)
        The cylinder of the hydraulic limit (``"arm"``, ``"boom"``, …), ``"tipping (<line>)"``
        or ``"slipping"``.
    hydraulic : ToolForces
        The cylinders' limit ([`tool_forces`][excavkin.excavator.forces.tool_forces]).
    stability : Stability
        Tipping and slipping loads of the tool force (acting on the machine along
        ``−hydraulic.direction``).
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    force: F
    limiting: NDArray[np.str_]
    hydraulic: ToolForces
    stability: Stability


def base_limits(tf: ToolForces, st: Stability) -> list[tuple[NDArray[np.str_], F]]:
    """The tipping and slipping caps of a tool force, named per sample
    ([`stability_caps`][excavkin.machinery.capped_force.stability_caps])."""
    return stability_caps(st)


def _tool_stability(machine: Machine, tf: ToolForces, swing: float) -> Stability:
    res = tf.pose.result
    point = tf.pose.lip if tf.at == "lip" else tf.pose.tip
    # the soil pushes the bucket against the tool's motion: −direction on the machine
    direction = np.where(np.isfinite(tf.direction), -tf.direction, 0.0)
    direction[~np.any(direction != 0.0, axis=1)] = (0.0, -1.0)  # unassembled: NaN below
    st = equilibrium(machine, res.positions, point, direction, swing, res.status.ok)
    return st


def capped_tool_forces(
    machine: Machine,
    lengths: ArrayLike,
    working: Working = "bucket",
    *,
    at: At = "lip",
    gravity: bool = True,
    swing: float | Over = "front",
) -> CappedToolForces:
    """Tool forces at each pose, capped by the cylinders, tipping and slipping.

    The hydraulic limit is [`tool_forces`][excavkin.excavator.forces.tool_forces] (its ``gravity``
    switches the front's weight in the cylinders' balance); tipping and slipping always
    count every weight, the front's at its pose included.

    Parameters
    ----------
    machine : Machine
        With a base.
    lengths : array_like, shape (n, 3)
        Boom, arm and bucket cylinder lengths (m).
    working : {"arm", "bucket"}
        The working cylinder, at working pressure; the others hold at relief pressure.
    at : {"lip", "tip"}
        The bucket lip (ISO 6015) or the tooth tip (SAE J1179).
    gravity : bool
        Include the front's weight in the cylinders' balance.
    swing : float or {"front", "side"}
        Swing angle of the upper structure (rad), or over the front (0) or the side (π/2).

    Returns
    -------
    CappedToolForces
    """
    need_base(machine)
    tf = tool_forces(machine, lengths, working, at=at, gravity=gravity)
    st = _tool_stability(machine, tf, _swing(swing))
    force, limiting = cap_by(tf.force, tf.limiting, base_limits(tf, st))
    return CappedToolForces(force, limiting, tf, st)


@dataclass(frozen=True, slots=True)
class BaseRatedForce:
    """A rated tool force capped by tipping and slipping as well (ISO 6015 §4.5).

    Attributes
    ----------
    rated : RatedForce
        At the pose where the capped force is largest; its ``force`` is the capped force and
        its ``limiting`` names every limit reached there (a cylinder, ``"tipping (<line>)"``,
        ``"slipping"``; ``+`` between two reached together).
    hydraulic : float
        The cylinders' limit at that pose (N).
    tipping : float
        Tipping load of the tool force there (N), about ``tipping_line``.
    tipping_line : str
    slipping : float
        Slipping load there (N); beyond it ISO 6015 §4.5 anchors the machine.
    cylinders_only : RatedForce
        The rated force without the base machine's limits
        ([`rated_force`][excavkin.excavator.forces.rated_force]).
    """

    rated: RatedForce
    hydraulic: float
    tipping: float
    tipping_line: str
    slipping: float
    cylinders_only: RatedForce


def base_rated_force(
    machine: Machine,
    working: Working = "bucket",
    *,
    at: At = "lip",
    swing: float | Over = "front",
    progress: Progress | None = None,
) -> BaseRatedForce:
    """The rated tool force (ISO 6015 §5.2, SAE J1179 §3.3) capped by tipping and slipping.

    The standards' positions as in [`rated_force`][excavkin.excavator.forces.rated_force], and the
    positions they leave free (the boom; for the bucket force the stick too) put where the
    force capped by all three limits is largest — a test finds "the optimum position giving
    the maximum force" (ISO 6015 §4.4) on the machine, which tips and slides. The front's
    weight is left out of the cylinders' balance (§5) but not out of the machine's.

    Parameters
    ----------
    machine : Machine
        With a base.
    working : {"arm", "bucket"}
        The arm-cylinder or the bucket-cylinder force.
    at : {"lip", "tip"}
        The bucket lip (ISO 6015) or the tooth tip (SAE J1179).
    swing : float or {"front", "side"}
        Swing angle of the upper structure (rad), or over the front (0) or the side (π/2).
    progress : callable, optional
        ``progress(done, total)`` as the positions' searches advance.

    Returns
    -------
    BaseRatedForce
    """
    need_base(machine)
    sw = _swing(swing)

    def limits(tf: ToolForces) -> list[tuple[NDArray[np.str_], F]]:
        return base_limits(tf, _tool_stability(machine, tf, sw))

    capped = rated_force(machine, working, at=at, limits=limits, progress=part(progress, 0, 2))
    tf = tool_forces(machine, capped.lengths[None, :], working, at=at, gravity=False)
    st = _tool_stability(machine, tf, sw)
    return BaseRatedForce(
        capped,
        float(tf.force[0]),
        float(st.tipping_load[0]),
        str(st.tipping_line[0]),
        float(st.slipping_load[0]),
        rated_force(machine, working, at=at, progress=part(progress, 1, 2)),
    )
