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

This is the machinery layer's support model ([`Support`][excavkin.machinery.base.Support]),
which the chassis builds (`Chassis.support`): the front axle's tyres (a contact element of the
front frame, at ±tread/2), the rear axle's pivot where it oscillates or its two tyres where it
is rigid (of the rear frame), and any further support (a block under the bucket's hinge pin in
the breakout test). The support polygon is their convex hull at γ; each of its edges is a
tipping line, named by the contact points it joins (``"front axle"`` where both are its tyres).

About a line with outward normal n and offset c, a downward load W at plan point p_L tips the
machine when ``Σ_k m_k·g·(n·p_k − c) + W·(n·p_L − c) > 0``; the **tipping load** is the least
W over the lines with ``n·p_L > c``::

    W_tip = min over those lines of  −g·Σ_k m_k·(n·p_k − c) / (n·p_L − c)

(0 where the machine tips without the load): the machinery layer's
[`equilibrium`][excavkin.machinery.equilibrium.equilibrium] with the load straight down and the
turning frame at γ. The weights' heights do not enter: the ground is level, the machine at
rest (SAE J732, ISO 14397-1). Everything is vectorised over poses.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.loader.machine import Loader
from excavkin.machinery.base import Contact, TippingLine
from excavkin.machinery.equilibrium import equilibrium


@dataclass(frozen=True, slots=True)
class Support:
    """A further point the machine stands on (a block under the bucket).

    Attributes
    ----------
    name : str
        ``"NAME (left)"`` and ``"NAME (right)"`` are the two ends of one support ``NAME``.
    x, v : float
        Model abscissa (m) and lateral offset to the left (m).
    turns : bool
        Whether it turns with the front frame.
    """

    name: str
    x: float
    v: float
    turns: bool


def contacts(extra: Sequence[Support]) -> tuple[Contact, ...]:
    """Further supports as contact elements of the machinery layer's support model.

    Parameters
    ----------
    extra : sequence of Support
        Consecutive points named ``"NAME (left)"``, ``"NAME (right)"`` (or just ``"NAME"``)
        make one element ``NAME``, of kind ``"block"``.

    Returns
    -------
    tuple of Contact
    """
    groups: list[list[Support]] = []
    for s in extra:
        if groups and _element(groups[-1][0]) == _element(s) and groups[-1][0].turns == s.turns:
            groups[-1].append(s)
        else:
            groups.append([s])
    return tuple(
        Contact(
            _element(g[0]),
            "block",
            0.0,
            tuple((s.x, s.v) for s in g),
            tuple(s.name for s in g),
            g[0].turns,
        )
        for g in groups
    )


def _element(s: Support) -> str:
    return s.name.removesuffix(" (left)").removesuffix(" (right)")


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
        Counter-clockwise; both front tyres make ``"front axle"``, both rear tyres of a rigid
        axle ``"rear axle"``, and the left and right of one further support (``"NAME (left)"``,
        ``"NAME (right)"``) make ``"NAME"``; other lines are ``"A – B"`` of the points they join.
    """
    support = machine.chassis.support.with_contacts(contacts(extra))
    return support.tipping_lines(machine.swing_axis, articulation)


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
    support = machine.chassis.support.with_contacts(contacts(extra))
    down = np.array([0.0, -1.0])
    st = equilibrium(machine, positions, point, down, articulation, support=support)
    return Tipping(float(articulation), st.tipping_load, st.tipping_line, st.moment, st.lines)
