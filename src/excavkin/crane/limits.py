r"""The three limits of a crane's hook load at a pose: hydraulic, hoist and stability.

The **hook load** W (N) is everything that hangs on the hook, the hook block included (ASME
B30.5 para. 5-1.1.1(b)(4): "the weight of all auxiliary handling devices such as lower load
block, hooks, and slings shall be considered as part of the load").

**Hydraulic.** The general kinetostatics solves each cylinder's force (compression > 0) twice
at every pose: under the booms' own weight, ``F0``, and under a hook load of 1 N (its falls on
the tip sheave and its lead line), ``F1``; the force is linear in W, ``F = F0 + W·F1``. It
holds while ``−p·A_rod ≤ F ≤ p·A_bore`` at its circuit's port relief pressure p. The largest
W ≥ 0 that keeps it so is the cylinder's limit (0 where the booms alone exceed it).

**Ropes.** A rope of the booms (a telescopic boom's synchronising rope) pulls and never
pushes: its tension ``T0 + W·T1`` must stay ≥ 0, which bounds W where the load slackens it
(`rope_limit`).

**Hoist.** The winch's single-line pull on ``parts`` falls: ``W ≤ line_pull·parts``.

**Stability.** The machinery layer's whole-machine equilibrium
([`equilibrium`][excavkin.machinery.equilibrium.equilibrium]) gives the tipping load at a slew
angle α: the hook load straight down at the hook that brings the crane onto a tipping line.
With the booms slewed by α, about a line of outward normal at angle β, the tipping moment is
``M0 + W·M1`` with both affine in cos(α − β) alone, so over a slew sector the least tipping
load lies at a sector end or where the booms stand square to a line (α = β or β + π):
`sector_candidates`. The stability limit is 85 % of that least tipping load on outriggers or
tyres and 75 % on crawlers (ASME B30.5 para. 5-1.1.1(a) and its Table 1: "the load ratings
shall not exceed" those percentages of the loads that "produce a condition of tipping ... with
the boom in the least stable direction relative to the mounting").

**Stability by factored loads** (an option: `StabilityFactors` on the crane, ``[stability]`` in
its machine file). The crane must stand, about every tipping line and over the sector's least
stable slew, under its own weight and ``γ_P·P + γ_F·F`` at the tip: P the hook load, F the
booms' weight **reduced to the tip**. ISO 4305 and EN 13000 state their stability loads in this
form; the user takes the factors' values from the clause of the standard that rates the crane
(excavkin ships none). Here F, about a tipping line, is the weight at the tip whose moment
about that line equals the booms' own overturning moment about it: with a = (x_t − x_s)·(n·d)
− c the tip's arm beyond the line and ``M_b = g·Σ m_i·((x_i − x_s)·(n·d) − c)`` over the
booms' masses (`Crane.mass_points`: every body of the booms' model, each cylinder's mass half
at either pin; not the turntable's or the carrier's masses), ``F·a = max(M_b, 0)``: the share
is added only where the booms overturn about the line, it never steadies the crane. The
criterion about a line is::

    M_0 + γ_F·max(M_b, 0) + γ_P·P·a ≤ 0

(every moment the one that tips the crane outwards, < 0 while it stands; M_0 the whole
crane's without the load, as in the tipping load), so the rated load is the least over the
lines with a > 0 of ``−(M_0 + γ_F·max(M_b, 0))/(γ_P·a)``, 0 where the left side already
exceeds 0 unloaded (`factored_stability_loads`). M_0, M_b and a are each affine in
cos(α − β), and the bound about a line is the least of the two ratios with M_b and with 0 in
its place, each monotone in cos(α − β) where a > 0; the unloaded left side is convex in it, so
it exceeds 0 somewhere in a sector only if it does at a sector end or a square angle. The
least over a sector lies at the same `sector_candidates` as the tipping load's (the tests
check it against 181 slew angles a sector). With γ_F = 0 and γ_P = 1/share it is the share of
the tipping load.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.crane.machine import Crane, Pose, StabilityFactors
from excavkin.machinery.base import TippingLine
from excavkin.machinery.cylinders import Cylinder
from excavkin.machinery.equilibrium import equilibrium

if TYPE_CHECKING:
    from excavkin.kinetostatics import ForceResult

#: the share of the tipping load a rating may reach (ASME B30.5 para. 5-1.1.1, Table 1: truck
#: and wheel mounted, without outriggers or on outriggers fully extended, 85 %; crawler without
#: outriggers, 75 %)
STABILITY_SHARE = {"outriggers": 0.85, "tyres": 0.85, "crawlers": 0.75}


def force_terms(crane: Crane, pose: Pose) -> tuple[F, F, dict[str, tuple[F, F]]]:
    """Each cylinder's push force and each rope's tension as ``F0 + W·F1`` from the general
    kinetostatics (module docstring).

    Parameters
    ----------
    crane : Crane
    pose : Pose

    Returns
    -------
    F0, F1 : ndarray, shape (n, 2)
        The cylinders' forces (N) under the booms' weight, and per N of hook load, in role
        order; NaN where the pose is out of reach.
    ropes : dict of str to (ndarray, ndarray)
        Each rope of the model (a telescopic boom's synchronising rope): its tension's two
        terms, the same way.
    """
    kin = pose.kinematics
    mech = crane.mechanism
    own = mech.forces(kin, crane.weight_loads())
    unit = mech.forces(kin, crane.hook_loads(kin, 1.0))
    off = ~pose.reached

    def terms(what: str, name: str) -> tuple[F, F]:
        def get(r: ForceResult) -> F:
            return r.force(name) if what == "force" else r.tension(name)

        return np.where(off, np.nan, get(own)), np.where(off, np.nan, get(unit))

    f0, f1 = zip(*(terms("force", d) for d in crane.drivers), strict=True)
    ropes = {r.name: terms("tension", r.name) for r in mech.model.ropes}
    return np.column_stack(f0), np.column_stack(f1), ropes


def rope_limit(t0: F, t1: F) -> F:
    """The largest hook load at which a rope still pulls (N): a rope never pushes, so the
    load is held only while its tension ``T0 + W·T1`` stays ≥ 0 from 0 to W.

    Parameters
    ----------
    t0, t1 : ndarray
        Its tension's terms (`force_terms`).

    Returns
    -------
    ndarray
        0 where it would push under the booms' weight alone, ``−T0/T1`` where the load slackens
        it, inf where the load only tightens it; NaN out of reach.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.where(t0 < 0.0, 0.0, np.where(t1 < 0.0, -t0 / t1, np.inf))
    out: F = np.where(np.isnan(t0) | np.isnan(t1), np.nan, w)
    return out


def cylinder_limit(crane: Crane, cylinder: Cylinder, f0: F, f1: F) -> F:
    """The largest hook load a cylinder holds at its port relief pressure (N).

    Parameters
    ----------
    crane : Crane
    cylinder : Cylinder
    f0, f1 : ndarray
        Its force terms (`force_terms`).

    Returns
    -------
    ndarray
        W ≥ 0; 0 where the booms' weights alone exceed it, inf where W does not load it.
    """
    lo, hi = cylinder.force_limits(crane.circuits[cylinder.circuit].relief)
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.where(f1 > 0, (hi - f0) / f1, np.where(f1 < 0, (lo - f0) / f1, np.inf))
    inside = (f0 >= lo) & (f0 <= hi)
    out: F = np.where(np.isnan(f0), np.nan, np.where(inside, np.maximum(w, 0.0), 0.0))
    return out


def hoist_limit(crane: Crane) -> float:
    """The hoist's limit ``line_pull·parts`` (N).

    Parameters
    ----------
    crane : Crane

    Returns
    -------
    float
    """
    return crane.hoist.line_pull * crane.hoist.parts


def support_kind(crane: Crane) -> str:
    """``"outriggers"``, ``"tyres"`` or ``"crawlers"``: which share of the tipping load rates
    it.

    Parameters
    ----------
    crane : Crane

    Returns
    -------
    str
    """
    return crane.mounting


def tipping_loads(crane: Crane, pose: Pose, alpha: F) -> tuple[F, NDArray[np.str_]]:
    """The tipping load at each pose and slew angle, and the line it tips about, from the
    machinery layer's whole-machine equilibrium.

    Parameters
    ----------
    crane : Crane
    pose : Pose
        Shape (n,).
    alpha : ndarray
        Slew angles (m,) (rad).

    Returns
    -------
    load : ndarray, shape (n, m)
        N; 0 where the crane tips unloaded; NaN where the pose is out of reach.
    line : ndarray of str, shape (n, m)
        The tipping line's name (empty where none binds).
    """
    kin = pose.kinematics
    hook = crane.tip(kin)
    load, line = [], []
    for a in np.asarray(alpha, dtype=np.float64):  # a handful of slew angles; all poses at once
        st = equilibrium(crane, kin.positions, hook, np.array([0.0, -1.0]), float(a))
        load.append(st.tipping_load)
        line.append(st.tipping_line)
    off = ~pose.reached[:, None]
    return np.where(off, np.nan, np.stack(load, -1)), np.where(off, "", np.stack(line, -1))


def factored_stability_loads(
    crane: Crane, pose: Pose, alpha: F, factors: StabilityFactors
) -> tuple[F, NDArray[np.str_]]:
    """The largest hook load the crane holds by the criterion of factored loads (module
    docstring) at each pose and slew angle, and the line it tips about, from the machinery
    layer's whole-machine equilibrium (its moments M_0 about the same lines).

    Parameters
    ----------
    crane : Crane
    pose : Pose
        Shape (n,).
    alpha : ndarray
        Slew angles (m,) (rad).
    factors : StabilityFactors
        γ_P and γ_F.

    Returns
    -------
    load : ndarray, shape (n, m)
        N; 0 where the crane tips under the factored booms' weight alone; inf where no line
        is tipped by the load; NaN where the pose is out of reach.
    line : ndarray of str, shape (n, m)
        The tipping line's name (empty where none binds).
    """
    kin = pose.kinematics
    hook = crane.tip(kin)
    xs, g = crane.swing_axis, crane.gravity
    mp = crane.mass_points
    booms = mp.locate(kin.positions)  # (n, k, 2)
    s_b = np.einsum("k,nk->n", mp.mass, booms[:, :, 0] - xs)
    m_b = float(mp.mass.sum())
    n = hook.shape[0]
    load, line = [], []
    for a in np.asarray(alpha, dtype=np.float64):  # a handful of slew angles; all poses at once
        st = equilibrium(crane, kin.positions, hook, np.array([0.0, -1.0]), float(a))
        nrm = np.array([ln.normal for ln in st.lines])
        c = np.array([ln.offset for ln in st.lines])
        nd = nrm @ np.array([np.cos(a), np.sin(a)])
        arm = (hook[:, 0, None] - xs) * nd - c  # (n, E)
        mb = g * (s_b[:, None] * nd - m_b * c)
        m0 = st.moment + factors.jib * np.maximum(mb, 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            lam = np.where(arm > 0.0, -m0 / (factors.hook * arm), np.inf)
        lam = np.where(m0 > 0.0, 0.0, lam)
        k = np.where(np.any(m0 > 0.0, axis=1), np.argmax(m0, axis=1), np.argmin(lam, axis=1))
        least = lam[np.arange(n), k]
        names = np.array([ln.name for ln in st.lines])
        load.append(least)
        line.append(np.where(np.isfinite(least), names[k], ""))
    off = ~pose.reached[:, None] | np.isnan(np.stack(load, -1))
    return np.where(off, np.nan, np.stack(load, -1)), np.where(off, "", np.stack(line, -1))


def stability_criterion(crane: Crane) -> str:
    """What rates the crane's stability, as a chart names it: ``"85 % of tipping"`` or
    ``"factors 1.3, 0.2"``.

    Parameters
    ----------
    crane : Crane

    Returns
    -------
    str
    """
    if crane.stability is not None:
        return crane.stability.label
    return f"{STABILITY_SHARE[support_kind(crane)]:.0%} of tipping".replace("%", " %")


def stability_limits(crane: Crane, pose: Pose, alpha: F) -> tuple[F, NDArray[np.str_]]:
    """The stability limit at each pose and slew angle by the crane's criterion: its share of
    the tipping load (`tipping_loads`), or the factored loads' (`factored_stability_loads`).

    Parameters
    ----------
    crane : Crane
    pose : Pose
        Shape (n,).
    alpha : ndarray
        Slew angles (m,) (rad).

    Returns
    -------
    load : ndarray, shape (n, m)
        N; NaN where the pose is out of reach.
    line : ndarray of str, shape (n, m)
        The tipping line's name.
    """
    if crane.stability is not None:
        return factored_stability_loads(crane, pose, alpha, crane.stability)
    load, line = tipping_loads(crane, pose, alpha)
    return STABILITY_SHARE[support_kind(crane)] * load, line


def sector_candidates(lines: tuple[TippingLine, ...], start: float, end: float) -> F:
    """The slew angles at which the least tipping load over a sector may lie (rad).

    Parameters
    ----------
    lines : tuple of TippingLine
    start, end : float
        The sector, counter-clockwise from ``start`` to ``end`` (rad, ``end > start``).

    Returns
    -------
    ndarray
        The sector's ends and each line's square angles (β, β + π) inside it.
    """
    out = [start, end]
    for ln in lines:
        beta = float(np.arctan2(ln.normal[1], ln.normal[0]))
        for b in (beta, beta + np.pi):
            k = np.ceil((start - b) / (2 * np.pi))
            a = b + 2 * np.pi * k
            if start < a < end:
                out.append(float(a))
    return np.array(sorted(out), dtype=np.float64)


@dataclass(frozen=True, slots=True)
class Sector:
    """A slew sector: counter-clockwise from ``start`` to ``end`` (rad), α = 0 over the
    carrier's front.

    Attributes
    ----------
    name : str
    start, end : float
    """

    name: str
    start: float
    end: float


def sectors(count: int) -> tuple[Sector, ...]:
    """``count`` equal sectors over 360°, the first centred over the front.

    Parameters
    ----------
    count : int
        1 (the full circle), 2, 4 (front, left, rear, right) or more.

    Returns
    -------
    tuple of Sector
    """
    if count == 1:
        return (Sector("360°", -np.pi, np.pi),)
    named = {2: ("front", "rear"), 4: ("front", "left", "rear", "right")}
    w = 2 * np.pi / count
    out = []
    for k in range(count):
        a0, a1 = k * w - w / 2, k * w + w / 2
        name = named[count][k] if count in named else f"{np.degrees(a0):g}..{np.degrees(a1):g}°"
        out.append(Sector(name, a0, a1))
    return tuple(out)
