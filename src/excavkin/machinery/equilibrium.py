r"""Tipping and slipping: the whole machine in equilibrium on the ground.

The machine (front at its pose, the masses of its two frames, its contact elements; see
`excavkin.machinery.base`) stands on its support polygon. A load of magnitude λ along a
unit direction f = (f_x, f_y) in the front's plane acts at a point P of the front (a tool force
at the lip or tooth tip, a load hung at the bucket pin, a rated load in a loader's bucket).
With the turning frame (an excavator's upper structure, a loader's front frame) at angle θ
(d = (cos θ, sin θ) in plan), a point of the front's plane at model abscissa x lies in plan at
(x − x_s)·d, x_s the axis (swing axis, articulation joint). About a tipping line with outward
normal n and offset c (n·p = c on the line) the moment that tips the machine outwards is::

    M(λ) = g·[ Σ_k m_k·((x_k − x_s)·(n·d) − c) + Σ_u m_u·(n·p_u − c) ]          (weights)
         + λ·[ −f_y·((x_P − x_s)·(n·d) − c) + f_x·(n·d)·(y_P − y_g) ]        (the load)
         = M_0 + λ·M_1

over the front's mass points and the turning frame's masses (k), the fixed frame's (u, at
p_u = (x_u − x_s, 0)) and the load at height y_P above the ground line y_g. The machine
stands while M < 0 about every line: the **tipping load** is min over the lines with M_1 > 0
of −M_0/M_1 (0 where some M_0 > 0 already: the machine tips without the load; inf where no
line has M_1 > 0). The weights' heights do not enter: the ground is level. The support polygon
is the one at θ: contact elements on the turning frame (a loader's front axle) turn with it.

The **slipping load** is where the load's horizontal part exceeds friction on the normal
load: λ·|f_x| = μ·(W − λ·f_y), so λ_slip = μ·W / (|f_x| + μ·f_y) where that denominator is
positive (inf otherwise); W is the whole machine's weight (NaN where the support gives no μ).

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
from excavkin.machinery.base import Base, Support, TippingLine
from excavkin.machinery.machine import StandingMachine
from excavkin.machinery.masses import MassPoints


def need_base(machine: StandingMachine) -> Base:
    """The machine's base (what builds its `Support`).

    Parameters
    ----------
    machine : StandingMachine

    Returns
    -------
    Base

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
        The turning frame's angle (rad): an upper structure's swing (0 over the front of the
        tracks), a front frame's articulation.
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
        Magnitude of the load at which the machine slides (N); inf where it never does, NaN
        where the support gives no friction coefficient.
    moment : ndarray, shape (n, n_lines)
        M_0: the weights' moment about each tipping line without the load (N·m; < 0 stable).
    margin : ndarray, shape (n,)
        Least distance of the whole machine's centre of mass inside the support polygon, in
        plan, without the load (m; negative outside).
    com : ndarray, shape (n, 3)
        Whole machine's centre of mass: plan (u, v) about the axis and height above the
        ground line (m), without the load.
    mass : float
        Whole machine (kg).
    lines : tuple of TippingLine
    ok : ndarray of bool, shape (n,)
        The pose assembles.
    margin_line : ndarray of str, shape (n,)
        The tipping line nearest the centre of mass, the one `margin` is measured to ("" where
        the pose does not assemble).
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
    margin_line: NDArray[np.str_]


def _turning_points(support: Support, mass_points: MassPoints, positions: F) -> tuple[F, F]:
    """Masses (k,) and positions (n, k, 2) of everything that turns with the front."""
    front = mass_points.locate(positions)  # (n, k, 2)
    turning = support.turning
    fixed = np.array([[m.x, m.y] for m in turning]).reshape(len(turning), 2)
    n = positions.shape[0]
    pts = np.concatenate([front, np.broadcast_to(fixed, (n, len(turning), 2))], axis=1)
    masses = np.concatenate([mass_points.mass, [m.mass for m in turning]])
    return masses, pts


def equilibrium(
    machine: StandingMachine,
    positions: F,
    point: F,
    direction: F,
    swing: float,
    ok: B | None = None,
    *,
    support: Support | None = None,
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
        The turning frame's angle (rad): an upper structure's swing, a front frame's
        articulation.
    ok : ndarray of bool, shape (n,), optional
        Poses that assemble (others give NaN); default every finite one.
    support : Support, optional
        The support to stand on instead of the machine's own (its base's with further
        contacts, `Support.with_contacts`).

    Returns
    -------
    Stability
    """
    if support is None:
        support = need_base(machine).support
    g, xs, yg = machine.gravity, machine.swing_axis, machine.ground_line
    n = positions.shape[0]
    f = np.broadcast_to(np.asarray(direction, dtype=np.float64), (n, 2))
    norm = np.hypot(f[:, 0], f[:, 1])
    if not np.all(norm > 0.0):
        raise InputError("the load's direction must not be zero")
    f = f / norm[:, None]
    lines = support.tipping_lines(xs, swing)
    nrm = np.array([ln.normal for ln in lines])  # (E, 2)
    c = np.array([ln.offset for ln in lines])  # (E,)
    d = np.array([np.cos(swing), np.sin(swing)])
    nd = nrm @ d  # (E,)
    masses, pts = _turning_points(support, machine.mass_points, positions)
    fixed = support.fixed  # they do not turn: in plan at (x − x_s, 0)
    total = float(masses.sum() + sum(m.mass for m in fixed))
    s_up = np.einsum("k,nk->n", masses, pts[:, :, 0] - xs)  # first moment along d
    h_up = np.einsum("k,nk->n", masses, pts[:, :, 1] - yg)
    M0 = g * (  # (n, E)
        s_up[:, None] * nd + sum(m.mass * (nrm[:, 0] * (m.x - xs)) for m in fixed) - total * c
    )
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
    slipping = _slipping(support.friction, f, g, total)
    com_plan = (s_up[:, None] * d + sum(m.mass * np.array([m.x - xs, 0.0]) for m in fixed)) / total
    h_fixed = sum(m.mass * (m.y - yg) for m in fixed)
    com = np.column_stack([com_plan, (h_up + h_fixed) / total])
    inside = c - com_plan @ nrm.T  # (n, E): distance inside each line
    margin = np.min(inside, axis=1)
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
        np.where(good, names[np.argmin(inside, axis=1)], ""),
    )


def _slipping(mu: float | None, f: F, g: float, total: float) -> F:
    """λ_slip = μ·W / (|f_x| + μ·f_y) where the denominator is positive, inf elsewhere; NaN
    without a friction coefficient."""
    if mu is None:
        return np.full(f.shape[0], np.nan)
    denom = np.abs(f[:, 0]) + mu * f[:, 1]
    with np.errstate(divide="ignore"):
        return np.where(denom > 0.0, mu * g * total / denom, np.inf)
