r"""Tipping of an articulated wheel loader: the support polygon turns with the front frame.

Seen from above, the **plan** coordinates are centred on the articulation joint: u forward
along the rear frame, v to the left. The front frame (front axle, the linkage, the bucket and
its load) turns by the articulation angle γ (> 0 to the left) about the joint, so a point of
the linkage's plane at model abscissa x lies in plan at (x − x_j)·(cos γ, sin γ); the rear frame
and the counterweight do not turn::

                       front-left tyre ●
             rear axle pivot            \  front frame turned by γ
      ●━━━━━━━━━━━━━━━━●━━━━━━━━━━━━━━━━━○ articulation joint ━━━━━ bucket →
      counterweight                       \
                                           ● front-right tyre

The machine stands on the **support polygon**: the convex hull of the front tyres' contacts
(the front axle at ±tread/2, turning with the front frame), of the rear axle's support (the
point under its oscillation pin, or its two tyres where it is rigid) and of any further
support (a block under the bucket's hinge pin in the breakout test). Each edge of the hull is a
tipping line, a [`TippingLine`][excavkin.machinery.base.TippingLine] of the machinery layer.

About a line with outward normal n and offset c, a downward load W at plan point p_L tips the
machine when ``Σ_k m_k·g·(n·p_k − c) + W·(n·p_L − c) > 0``; the **tipping load** is the least
W over the lines with ``n·p_L > c``::

    W_tip = min over those lines of  −g·Σ_k m_k·(n·p_k − c) / (n·p_L − c)

(0 where the machine tips without the load). The weights' heights do not enter: the ground is
level, the machine at rest (SAE J732, ISO 14397-1). Everything is vectorised over poses.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.loader.machine import Loader
from excavkin.machinery.base import TippingLine, convex_hull


@dataclass(frozen=True, slots=True)
class Support:
    """A point the machine stands on.

    Attributes
    ----------
    name : str
    x, v : float
        Model abscissa (m) and lateral offset to the left (m).
    turns : bool
        Whether it turns with the front frame.
    """

    name: str
    x: float
    v: float
    turns: bool


def supports(machine: Loader, extra: Sequence[Support] = ()) -> tuple[Support, ...]:
    """The loader's ground supports: the front tyres, the rear axle's, and ``extra``.

    Parameters
    ----------
    machine : Loader
    extra : sequence of Support
        Further supports (a block under the hinge pin).

    Returns
    -------
    tuple of Support
    """
    ch = machine.chassis
    half = 0.5 * ch.tread
    out = [
        Support("front-left tyre", ch.front_axle[0], half, True),
        Support("front-right tyre", ch.front_axle[0], -half, True),
    ]
    if ch.oscillating:
        out.append(Support("rear axle pivot", ch.rear_axle, 0.0, False))
    else:
        out += [
            Support("rear-left tyre", ch.rear_axle, half, False),
            Support("rear-right tyre", ch.rear_axle, -half, False),
        ]
    return (*out, *extra)


def _plan(machine: Loader, s: Support, gamma: float) -> tuple[float, float]:
    u, v = s.x - machine.chassis.articulation, s.v
    if not s.turns:
        return u, v
    c, sn = math.cos(gamma), math.sin(gamma)
    return c * u - sn * v, sn * u + c * v


def tipping_lines(
    machine: Loader, articulation: float, extra: Sequence[Support] = ()
) -> tuple[TippingLine, ...]:
    """The support polygon's edges at an articulation angle, named by the supports they join.

    Parameters
    ----------
    machine : Loader
    articulation : float
        γ (rad; > 0 turns the front frame to the left).
    extra : sequence of Support

    Returns
    -------
    tuple of TippingLine
        Counter-clockwise; both front tyres make ``"front axle"``, and the left and right of
        one further support (``"NAME (left)"``, ``"NAME (right)"``) make ``"NAME"``.
    """
    sup = supports(machine, extra)
    pts = np.array([_plan(machine, s, articulation) for s in sup])
    hull = convex_hull(pts)
    out = []
    for i, j in zip(hull, hull[1:] + hull[:1], strict=True):
        a, b = pts[i], pts[j]
        t = (b - a) / math.hypot(*(b - a))
        n = (float(t[1]), float(-t[0]))
        pair = {sup[i].name, sup[j].name}
        sides = {p.removesuffix(" (left)").removesuffix(" (right)") for p in pair}
        if pair == {"front-left tyre", "front-right tyre"}:
            name = "front axle"
        elif len(sides) == 1 and len(pair) == 2:  # a support's two sides: "block (left)", ...
            name = sides.pop()
        else:
            name = f"{sup[i].name} – {sup[j].name}"
        out.append(TippingLine(name, n, float(n[0] * a[0] + n[1] * a[1]), np.array([a, b])))
    return tuple(out)


@dataclass(frozen=True, slots=True)
class Tipping:
    """The tipping load of a downward load at n poses.

    Attributes
    ----------
    articulation : float
        γ (rad).
    load : ndarray, shape (n,)
        The least downward force at the load point that tips the machine (N); 0 where it tips
        without the load, inf where no load tips it, NaN where the pose does not assemble.
    line : ndarray of str, shape (n,)
        The tipping line it tips about.
    moment : ndarray, shape (n, n_lines)
        The weights' moment about each line without the load (N·m; < 0 stable).
    lines : tuple of TippingLine
    """

    articulation: float
    load: F
    line: NDArray[np.str_]
    moment: F
    lines: tuple[TippingLine, ...]


def tipping(
    machine: Loader,
    positions: F,
    point: F,
    articulation: float = 0.0,
    extra: Sequence[Support] = (),
) -> Tipping:
    """The tipping load of a downward load at ``point`` (module docstring), vectorised.

    Parameters
    ----------
    machine : Loader
    positions : ndarray, shape (n, n_points, 2)
        The engine's positions of the linkage at each pose.
    point : ndarray, shape (n, 2)
        Where the load acts, in the linkage's plane (m).
    articulation : float
        γ (rad).
    extra : sequence of Support
        Further ground supports.

    Returns
    -------
    Tipping
    """
    ch, g = machine.chassis, machine.gravity
    lines = tipping_lines(machine, articulation, extra)
    nrm = np.array([ln.normal for ln in lines])  # (E, 2)
    c = np.array([ln.offset for ln in lines])  # (E,)
    d = np.array([math.cos(articulation), math.sin(articulation)])
    nd = nrm @ d  # (E,): n·(cos γ, sin γ), a turning point's along-frame factor
    xj = ch.articulation
    mp = machine.mass_points
    xs = mp.locate(positions)[:, :, 0] - xj  # (n, k): the linkage's masses, turning
    first = np.einsum("k,nk->n", mp.mass, xs) + ch.front_frame.mass * (ch.front_frame.x - xj)
    turning = float(mp.mass.sum()) + ch.front_frame.mass
    fixed = [ch.rear_frame, ch.counterweight]
    rear = sum(m.mass * (nrm[:, 0] * (m.x - xj)) for m in fixed)  # (E,)
    total = turning + sum(m.mass for m in fixed)
    M0 = g * (first[:, None] * nd + rear - total * c)  # (n, E)
    M1 = (point[:, 0] - xj)[:, None] * nd - c  # (n, E): arm of a unit load
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = np.where(M1 > 0.0, -M0 / M1, np.inf)
    lam = np.where(M0 > 0.0, 0.0, lam)
    n = positions.shape[0]
    k = np.where(np.any(M0 > 0.0, axis=1), np.argmax(M0, axis=1), np.argmin(lam, axis=1))
    load = lam[np.arange(n), k]
    names = np.array([ln.name for ln in lines])
    good = np.all(np.isfinite(positions), axis=(1, 2)) & np.all(np.isfinite(point), axis=1)
    nan = np.where(good, 1.0, np.nan)
    line = np.where(good & np.isfinite(load), names[k], "")
    return Tipping(float(articulation), load * nan, line, M0 * nan[:, None], lines)
