"""The constraints a Newton group solves, and the dyads found inside a group.

A group's unknowns are its points' coordinates; each constraint gives one equation (two for a
rigid frame): `CDist` a distance, `CFrame` a point carried by a body's frame, `CLine` a point on
a line, `CAngle` a driver's angle. A `GroupDyad` is a point of the group held by two distances
alone, whose side the solve keeps as a closed-form dyad's.
"""

from __future__ import annotations

from dataclasses import dataclass

from excavkin.step_kinds.dist import Dist


@dataclass(frozen=True, slots=True)
class CDist:
    """Newton constraint ``|p − q|² = d²``."""

    p: int
    q: int
    dist: Dist


@dataclass(frozen=True, slots=True)
class CFrame:
    """Newton constraint (two equations) ``p = a + s·(b − a) + t·perp(b − a)``."""

    p: int
    a: int
    b: int
    s: float
    t: float
    body: str = ""


@dataclass(frozen=True, slots=True)
class CLine:
    """Newton constraint ``cross(l2 − l1, p − l1) = 0``."""

    p: int
    l1: int
    l2: int


@dataclass(frozen=True, slots=True)
class CAngle:
    """Newton constraint ``cross(R(q)·e_ref, p − pivot) = 0`` (e_ref = +x for the ground)."""

    p: int
    pivot: int
    ref: tuple[int, int] | None
    input: int


@dataclass(frozen=True, slots=True)
class CRope:
    """Newton constraint ``L² = d²``: L the length of a rope over sheaves
    (`excavkin.step_kinds.rope_path`), d its winch's payout or its locked length."""

    points: tuple[int, ...]
    #: each path point's signed sheave radius σ·r (0 at the ends), m
    signed: tuple[float, ...]
    #: each path point's wrap angle at the sketch (0 at the ends), rad
    wraps0: tuple[float, ...]
    dist: Dist
    name: str = ""


Constraint = CDist | CFrame | CLine | CAngle | CRope


@dataclass(frozen=True, slots=True)
class GroupDyad:
    """A point of a Newton group held by two distances alone, from A and B: the group's
    Jacobian is block-triangular with the point's 2×2 block last, so its determinant has the
    factor cross(P − A, P − B), and P's mirror image in the line A→B is another solution of
    the group. ``sign`` = sign of cross(B − A, P − A) at the sketch (0: drawn flat, not kept),
    the side the solve keeps, as a `Dyad`'s."""

    point: int
    a: int
    b: int
    sign: float
