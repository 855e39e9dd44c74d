"""The dyads inside a Newton group: points held by two distances alone.

A point P of a group that appears in exactly two of its constraints, both distances (from A
and from B), is a dyad of the group: the other equations do not hold P, so the Jacobian is
block-triangular with P's 2×2 block ``2·[(P − A)ᵀ; (P − B)ᵀ]`` last, and its determinant has
the factor ``4·cross(P − A, P − B)``. P's mirror image in the line A→B solves the group as
well, with that factor's sign turned over: the group's two assembly branches at P, as a
closed-form dyad's two sides. Peeled off one after another (a dyad removed can leave another
point held by two distances alone, and so can a point attached to a body by its frame alone,
whose block is the identity), they come out last-solved first::

    O2 ── A ── B ── O4        group {A, B}: B from A and O4 is its dyad; A (a distance and a
    (crank)      (rocker)     driver angle) is what remains

A group of a model whose closed form has dyads (``method="newton"``) so knows the same
dyads, with the same partners, and the solve keeps each on its sketch side as the closed form
does (or, with ``continuation="smooth"``, flips it at its change points).
"""

from __future__ import annotations

import heapq
from collections.abc import Sequence

from excavkin.structure.plan import CAngle, CDist, CFrame, CLine, Constraint, CRope, GroupDyad


def _touches(con: Constraint) -> tuple[int, ...]:
    """The points a constraint holds."""
    if isinstance(con, CDist):
        return con.p, con.q
    if isinstance(con, CFrame):
        return con.p, con.a, con.b
    if isinstance(con, CLine):
        return con.p, con.l1, con.l2
    if isinstance(con, CRope):
        return con.points
    assert isinstance(con, CAngle)
    return (con.p, con.pivot) + (() if con.ref is None else con.ref)


def group_dyads(
    points: Sequence[int],
    constraints: Sequence[Constraint],
    sketch: Sequence[tuple[float, float]],
    scale: float,
) -> tuple[GroupDyad, ...]:
    """A group's dyads, each after the points it hangs from.

    Parameters
    ----------
    points : sequence of int
        The group's points (plan indices).
    constraints : sequence of Constraint
        Its constraints.
    sketch : sequence of (float, float)
        Every point's sketch position, by plan index.
    scale : float
        The mechanism's size: a point drawn within 1e-12·scale of its partners' line shows no
        side (its dyad's sign is 0).

    Returns
    -------
    tuple of GroupDyad
        Partners in the order of the constraints (a closed-form dyad's order: bodies first, then
        elements).
    """
    touches = [set(_touches(con)) for con in constraints]
    using: dict[int, list[int]] = {p: [] for p in points}
    for i, held in enumerate(touches):
        for q in held:
            if q in using:
                using[q].append(i)
    alive = [True] * len(constraints)
    place = {p: i for i, p in enumerate(points)}

    def peelable(p: int) -> tuple[tuple[int, int] | None, list[int]] | None:
        """(partners of a dyad, or None for a point on a body's frame; its constraints)."""
        uses = [i for i in using[p] if alive[i]]
        held = [constraints[i] for i in uses]
        if len(held) == 1 and isinstance(held[0], CFrame) and held[0].p == p:
            return None, uses  # attached to a body: its block is the identity
        if len(held) == 2 and all(isinstance(con, CDist) for con in held):
            a, b = (con.q if con.p == p else con.p for con in held if isinstance(con, CDist))
            if a != b and p not in (a, b):
                return (a, b), uses
        return None

    # the first peelable point in the group's order each time (a heap of the candidates, each
    # checked again when taken: peeling changes only its partners' constraints)
    heap = [place[p] for p in points if peelable(p) is not None]
    heapq.heapify(heap)
    peeled: list[GroupDyad] = []
    done: set[int] = set()
    while heap:
        p = points[heapq.heappop(heap)]
        found = None if p in done else peelable(p)
        if found is None:
            continue
        partners, uses = found
        if partners is not None:
            a, b = partners
            (ax, ay), (bx, by), (px, py) = sketch[a], sketch[b], sketch[p]
            cross = (bx - ax) * (py - ay) - (by - ay) * (px - ax)
            sign = 0.0 if abs(cross) <= 1e-12 * scale * scale else (1.0 if cross > 0 else -1.0)
            peeled.append(GroupDyad(p, a, b, sign))
        done.add(p)
        for i in uses:
            alive[i] = False
            for q in touches[i]:
                if q in using and q not in done and peelable(q) is not None:
                    heapq.heappush(heap, place[q])
    return tuple(reversed(peeled))
