r"""Tipping and slipping: the whole machine in equilibrium on the ground.

The machine (front at its pose, upper structure, counterweight, undercarriage; see
`excavkin.machinery.base`) stands on its support polygon. A load of magnitude λ along a
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
comes from the engine's positions (the machine's ``mass_points``,
[`MassPoints`][excavkin.machinery.masses.MassPoints]).

A family caps its tool forces by these limits as well
([`stability_caps`][excavkin.machinery.capped_force.stability_caps]; the excavator's
[`capped_tool_forces`][excavkin.excavator.stability.capped_tool_forces]).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import BoolArray as B
from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError, ModelError
from excavkin.kinematics.summary import batch_repr
from excavkin.machinery.base import BaseMachine, TippingLine
from excavkin.machinery.machine import StandingMachine


def need_base(machine: StandingMachine) -> BaseMachine:
    """The machine's base.

    Parameters
    ----------
    machine : StandingMachine

    Returns
    -------
    BaseMachine

    Raises
    ------
    ModelError
        Naming the missing ``[base]`` table and the machine file.
    """
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


def _upper_points(machine: StandingMachine, positions: F) -> tuple[F, F]:
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
    machine: StandingMachine,
    positions: F,
    point: F,
    direction: F,
    swing: float,
    ok: B | None = None,
) -> Stability:
    """Tipping and slipping limits from the engine's point positions (the vectorised core).

    Parameters
    ----------
    machine : StandingMachine
        With a base (its ``base``).
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
