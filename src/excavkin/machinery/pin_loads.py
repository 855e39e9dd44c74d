r"""Pin loads of a machine at rest: what each pin passes to each of its members.

From the general kinetostatics ([`Mechanism.forces`][excavkin.mechanism.Mechanism.forces]) of
any load case, over a batch of poses: the force of every pin on every member it joins and every
cylinder's force. The **load of a pin** is the largest force it passes to any one of its
members — the bodies pinned there and, at a cylinder's end, the cylinder's eye (whose force is
the cylinder's) — so that for a pin of two members it is the force between them::

    load(p) = max( |F[p, b]| over the bodies b at p ,  |f_c| over the cylinders c ending at p )

Where ``count`` cylinders act together, their pins are drawn as one and carry all of them: each
of the real pins carries its share. A family's load cases (an excavator's tool forces and lift
loads) and its pins' names are its own (`excavkin.excavator.pin_loads`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.kinetostatics import ForceResult
from excavkin.machinery.cylinders import Cylinder


@dataclass(frozen=True, slots=True)
class PinForces:
    """Every pin's members and load, and every cylinder's force, at n poses (N).

    Attributes
    ----------
    pins : tuple of str
        The pins' point names, in the engine's order.
    members : tuple of tuple of str
        Per pin, its members: the bodies pinned there and ``"<role> cylinder"`` at a cylinder's
        end.
    member_force : tuple of ndarray, shape (n, k)
        Per pin, the magnitude of the force it passes to each of its k members.
    load : ndarray, shape (n, n_pins)
        The pin's load: its largest member force; NaN where the pose does not assemble.
    cylinder_force : ndarray, shape (n, c)
        The cylinders' forces (> 0 pushing), one column per role.
    """

    pins: tuple[str, ...]
    members: tuple[tuple[str, ...], ...]
    member_force: tuple[F, ...]
    load: F
    cylinder_force: F


def pin_forces(
    forces: ForceResult, cylinders: Sequence[Cylinder], ends: Sequence[tuple[str, str]]
) -> PinForces:
    """Pin loads and cylinder forces of a solved static state.

    Parameters
    ----------
    forces : ForceResult
        The kinetostatics of the machine's mechanism under a load case, at n poses.
    cylinders : sequence of Cylinder
        The machine's cylinders, one per role; each ``driver`` is a driver of the mechanism.
    ends : sequence of (str, str)
        Each cylinder's end pins (base, rod end), in the order of ``cylinders``.

    Returns
    -------
    PinForces
    """
    cyl = np.stack([forces.force(c.driver) for c in cylinders], axis=1)
    pins = tuple(dict.fromkeys(p for p, _ in forces.pins))
    members: list[tuple[str, ...]] = []
    member_force: list[F] = []
    for p in pins:
        names = [b for q, b in forces.pins if q == p]
        cols = [np.hypot(*forces.pin(p, b).T) for b in names]
        for c, pair in enumerate(ends):
            if p in pair:
                names.append(f"{cylinders[c].role} cylinder")
                cols.append(np.abs(cyl[:, c]))
        members.append(tuple(names))
        member_force.append(np.stack(cols, axis=1))
    load = np.stack([m.max(axis=1) for m in member_force], axis=1)
    return PinForces(pins, tuple(members), tuple(member_force), load, cyl)


#: values this close to the largest, relative to it, are the same largest load: a load capped
#: by a relief pressure is equal over many poses, and round-off must not choose among them
TIE_RTOL = 1e-9


def first_largest(values: F, prefer: F | None = None) -> int:
    """The index at which ``values`` reach their largest, ties taken within `TIE_RTOL`.

    A pin load capped by a relief pressure is the same over many poses of a sweep; the pose a
    table names for it is then chosen among them by ``prefer`` (the largest of it: the pose
    with the largest tool load that still meets the cap), or the first in the sweep's order,
    whatever the last bits of each value.

    Parameters
    ----------
    values : ndarray
        One value a pose (``-inf`` where a pose does not count).
    prefer : ndarray, optional
        One value a pose: among the tied poses, the largest of it wins (then the first).

    Returns
    -------
    int
        The chosen index (0 when every value is ``-inf`` or NaN).
    """
    v = np.asarray(values, dtype=float)
    if not np.isfinite(v).any():
        return 0
    top = float(np.nanmax(np.where(np.isfinite(v), v, -np.inf)))
    tied = v >= top - TIE_RTOL * abs(top)
    if prefer is None:
        return int(np.argmax(tied))
    p = np.where(tied, np.nan_to_num(np.asarray(prefer, dtype=float), nan=-np.inf), -np.inf)
    return int(np.argmax(p))
