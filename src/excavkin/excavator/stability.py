r"""Tipping and slipping of an excavator: the whole machine in equilibrium on the ground.

The machine (front at its pose, upper structure, counterweight, undercarriage; see
`excavkin.excavator.base`) stands on its support polygon. A load of magnitude λ along a
unit direction f = (f_x, f_y) in the front's plane acts at a point P of the front (a tool force
at the lip or tooth tip, a load hung at the bucket pin). With the upper structure swung by θ
(d = (cos θ, sin θ) in plan), a point of the front's plane at model abscissa x lies in plan at
(x − x_s)·d, x_s the swing axis. About a tipping line with outward normal n and offset c
(n·p = c on the line) the moment that tips the machine outwards is::

    M(λ) = g·[ Σ_k m_k·((x_k − x_s)·(n·d) − c) + m_u·(n·p_u − c) ]          (weights)
         + λ·[ −f_y·((x_P − x_s)·(n·d) − c) + f_x·(n·d)·(y_P − y_g) ]        (the load)
         = M_0 + λ·M_1

over the front's mass points and the upper structure's (k, turning with the front), the
undercarriage's (u, fixed) and the load at height y_P above the ground line y_g. The machine
stands while M < 0 about every line: the **tipping load** is min over the lines with M_1 > 0
of −M_0/M_1 (0 where some M_0 > 0 already: the machine tips without the load; inf where no
line has M_1 > 0). The weights' heights do not enter: the ground is level.

The **slipping load** is where the load's horizontal part exceeds friction on the normal
load: λ·|f_x| = μ·(W − λ·f_y), so λ_slip = μ·W / (|f_x| + μ·f_y) where that denominator is
positive (inf otherwise); W is the whole machine's weight.

Everything is vectorised over poses (and the few tipping lines); the front's weight at each pose
comes from the engine's positions
([`Machine.mass_points`][excavkin.excavator.machine.Machine.mass_points]).

Tool forces (ISO 6015) are then capped by these limits as well
([`capped_tool_forces`][excavkin.excavator.stability.capped_tool_forces],
[`base_rated_force`][excavkin.excavator.stability.base_rated_force]), with the limit that binds
named, as ISO 6015 §3.17–3.19 and §4.5
name them: the hydraulic limit (a cylinder), the tipping limit, the slipping limit.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from excavkin.arrays import BoolArray as B
from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError, ModelError
from excavkin.excavator.base import BaseMachine, TippingLine
from excavkin.excavator.forces import At, RatedForce, ToolForces, Working, rated_force, tool_forces
from excavkin.excavator.machine import Machine, as_lengths
from excavkin.excavator.search import Progress, part
from excavkin.kinematics.summary import batch_repr

#: where the machine's front points: over the front (idler) end of the tracks, or over the side
Over = Literal["front", "side"]
SWING: dict[str, float] = {"front": 0.0, "side": 0.5 * np.pi}


def need_base(machine: Machine) -> BaseMachine:
    """The machine's base, or an error naming the missing ``[base]`` table."""
    if machine.base is None:
        raise ModelError(
            "the machine has no base machine: add a [base] table (upper structure, "
            "counterweight, undercarriage, ground support) for tipping, slipping and lift capacity",
            table="base",
            source=machine.source,
        )
    return machine.base


@dataclass(frozen=True, slots=True)
class Stability:
    """Tipping and slipping limits of a load at n poses.

    Attributes
    ----------
    swing : float
        Swing angle of the upper structure (rad; 0 over the front of the tracks).
    point : ndarray, shape (n, 2)
        Where the load acts, in the front's plane (m).
    direction : ndarray, shape (n, 2)
        Unit direction of the load on the machine (front's plane).
    tipping_load : ndarray, shape (n,)
        Magnitude of the load at which the machine begins to tip (N); 0 where it tips without
        the load, inf where the load never tips it, NaN where the pose does not assemble.
    tipping_line : ndarray of str, shape (n,)
        The line it tips about (`TippingLine` name).
    slipping_load : ndarray, shape (n,)
        Magnitude of the load at which the machine slides (N); inf where it never does.
    moment : ndarray, shape (n, n_lines)
        M_0: the weights' moment about each tipping line without the load (N·m; < 0 stable).
    margin : ndarray, shape (n,)
        Least distance of the whole machine's centre of mass inside the support polygon, in
        plan, without the load (m; negative outside).
    com : ndarray, shape (n, 3)
        Whole machine's centre of mass: plan (u, v) about the swing axis and height above the
        ground line (m), without the load.
    mass : float
        Whole machine (kg).
    lines : tuple of TippingLine
    ok : ndarray of bool, shape (n,)
        The pose assembles.
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    swing: float
    point: F
    direction: F
    tipping_load: F
    tipping_line: NDArray[np.str_]
    slipping_load: F
    moment: F
    margin: F
    com: F
    mass: float
    lines: tuple[TippingLine, ...]
    ok: B


def _upper_points(machine: Machine, positions: F) -> tuple[F, F]:
    """Masses (k,) and positions (n, k, 2) of everything that turns with the front."""
    base = need_base(machine)
    mp = machine.mass_points
    front = mp.locate(positions)  # (n, k, 2)
    fixed = np.array([[base.upper.x, base.upper.y], [base.counterweight.x, base.counterweight.y]])
    n = positions.shape[0]
    pts = np.concatenate([front, np.broadcast_to(fixed, (n, 2, 2))], axis=1)
    masses = np.concatenate([mp.mass, [base.upper.mass, base.counterweight.mass]])
    return masses, pts


def equilibrium(
    machine: Machine,
    positions: F,
    point: F,
    direction: F,
    swing: float,
    ok: B | None = None,
) -> Stability:
    """Tipping and slipping limits from the engine's point positions (the vectorised core).

    Parameters
    ----------
    machine : Machine
        With a base (`Machine.base`).
    positions : ndarray, shape (n, n_points, 2)
        Every point of the model at each pose (a [`KinematicResult`][excavkin.KinematicResult]'s
        ``positions``).
    point : ndarray, shape (n, 2)
        Where the load acts (m).
    direction : ndarray, shape (n, 2) or (2,)
        Direction of the load on the machine; normalised here.
    swing : float
        Upper structure's swing (rad).
    ok : ndarray of bool, shape (n,), optional
        Poses that assemble (others give NaN); default every finite one.

    Returns
    -------
    Stability
    """
    base = need_base(machine)
    g, xs, yg = machine.gravity, machine.swing_axis, machine.ground_line
    n = positions.shape[0]
    f = np.broadcast_to(np.asarray(direction, dtype=np.float64), (n, 2))
    norm = np.hypot(f[:, 0], f[:, 1])
    if not np.all(norm > 0.0):
        raise InputError("the load's direction must not be zero")
    f = f / norm[:, None]
    lines = base.tipping_lines(xs)
    nrm = np.array([ln.normal for ln in lines])  # (E, 2)
    c = np.array([ln.offset for ln in lines])  # (E,)
    d = np.array([np.cos(swing), np.sin(swing)])
    nd = nrm @ d  # (E,)
    masses, pts = _upper_points(machine, positions)
    total = float(masses.sum() + base.undercarriage.mass)
    s_up = np.einsum("k,nk->n", masses, pts[:, :, 0] - xs)  # first moment along d
    h_up = np.einsum("k,nk->n", masses, pts[:, :, 1] - yg)
    p_u = np.array([base.undercarriage.x - xs, 0.0])  # the undercarriage does not turn
    m_u = base.undercarriage.mass
    M0 = g * (s_up[:, None] * nd + m_u * (nrm @ p_u) - total * c)  # (n, E)
    xp = point[:, 0] - xs
    yp = point[:, 1] - yg
    M1 = -f[:, 1, None] * (xp[:, None] * nd - c) + f[:, 0, None] * nd * yp[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = np.where(M1 > 0.0, -M0 / M1, np.inf)
    lam = np.where(M0 > 0.0, 0.0, lam)  # tips without the load
    # of the lines it tips about without the load, the one with the largest moment
    worst_unloaded = np.argmax(M0, axis=1)
    k = np.where(np.any(M0 > 0.0, axis=1), worst_unloaded, np.argmin(lam, axis=1))
    tipping = lam[np.arange(n), k]
    names = np.array([ln.name for ln in lines])
    line = np.where(np.isfinite(tipping), names[k], "")
    mu = base.friction
    denom = np.abs(f[:, 0]) + mu * f[:, 1]
    with np.errstate(divide="ignore"):
        slipping = np.where(denom > 0.0, mu * g * total / denom, np.inf)
    com_plan = (s_up[:, None] * d + m_u * p_u) / total
    com = np.column_stack([com_plan, (h_up + m_u * (base.undercarriage.y - yg)) / total])
    margin = np.min(c - com_plan @ nrm.T, axis=1)
    good = np.all(np.isfinite(positions), axis=(1, 2)) if ok is None else np.asarray(ok)
    good = good & np.all(np.isfinite(point), axis=1)
    nan = np.where(good, 1.0, np.nan)
    return Stability(
        float(swing),
        point,
        f,
        tipping * nan,
        np.where(good, line, ""),
        slipping * nan,
        M0 * nan[:, None],
        margin * nan,
        com * nan[:, None],
        total,
        lines,
        np.asarray(good),
    )


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
    """The tipping and slipping caps of a tool force, named per sample."""
    tip_name = np.char.add(np.char.add("tipping (", st.tipping_line.astype(str)), ")")
    n = len(st.slipping_load)
    return [(tip_name, st.tipping_load), (np.full(n, "slipping"), st.slipping_load)]


def _cap(
    tf: ToolForces, limits: Sequence[tuple[NDArray[np.str_], F]]
) -> tuple[F, NDArray[np.str_]]:
    force = tf.force.copy()
    limiting = tf.limiting.astype("<U40")
    for names, cap in limits:
        lower = cap < force
        force = np.where(lower, cap, force)
        limiting = np.where(lower, names, limiting)
    return force, limiting


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
    force, limiting = _cap(tf, base_limits(tf, st))
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
