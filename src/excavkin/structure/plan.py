"""What a solve plan is: ordered closed-form steps, and the mechanism's index tables.

`excavkin.structure.builder.compile_plan` makes a plan from a model, once. The unknowns
are point positions. Starting from the ground's points, steps are chosen greedily, each needing
only points already known (DESIGN.md §3):

=========  ==================================================  ================================
step       known                                               gives
=========  ==================================================  ================================
Fixed      —                                                   the ground's points
Rotate     pivot, reference orientation, driver angle          the driven body's point
Attach     two known points of the same body                   any other point of that body
Dyad       A, B and distances |PA|, |PB| (body, cylinder,      P, on the sketch's side of AB
           rope; fixed or driven)                              (RRR dyad, internal driving link)
Slider     A, |PA|, a line through two known points            P on the line (RRP)
Newton     what is left: a higher-class group                  all its points, by Newton–Raphson
=========  ==================================================  ================================

Every constraint of the model is used by exactly one step; one left over means the model is
over-constrained somewhere, and the error names it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

from excavkin.model.entities import Model
from excavkin.model.validate import Mobility
from excavkin.structure.shapes import BodyShape


@dataclass(frozen=True, slots=True)
class Dist:
    """A distance used by a step: fixed (a body or a locked element) or an input's value."""

    kind: Literal["fixed", "input"]
    value: float
    input: int = -1
    label: str = ""
    #: where a fixed distance comes from, so that a design of other dimensions can recompute
    #: it: the two points (plan indices), and the body they are on ("" for a locked element)
    pair: tuple[int, int] = (-1, -1)
    body: str = ""


@dataclass(frozen=True, slots=True)
class Fixed:
    """Ground points at their coordinates."""

    points: tuple[int, ...]
    coords: tuple[tuple[float, float], ...]


@dataclass(frozen=True, slots=True)
class Rotate:
    """``point = pivot + radius·(cos θ, sin θ)``, ``θ = θ_ref + q[input]``."""

    point: int
    pivot: int
    radius: float
    input: int
    ref: tuple[int, int] | None
    driver: str


@dataclass(frozen=True, slots=True)
class Attach:
    """``point = a + s·(b − a) + t·perp(b − a)``, ``perp(v) = (−v_y, v_x)``."""

    point: int
    a: int
    b: int
    s: float
    t: float
    body: str


@dataclass(frozen=True, slots=True)
class Dyad:
    """``|P − A| = da``, ``|P − B| = db``; ``sign`` = sign of cross(B − A, P − A) at the sketch."""

    point: int
    a: int
    b: int
    da: Dist
    db: Dist
    sign: float
    index: int


@dataclass(frozen=True, slots=True)
class SliderStep:
    """``|P − A| = da`` and P on the line l1→l2; ``sign`` = side of A's foot P lies on."""

    point: int
    a: int
    da: Dist
    l1: int
    l2: int
    sign: float
    index: int
    slider: str


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


Constraint = CDist | CFrame | CLine | CAngle


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


@dataclass(frozen=True, slots=True)
class NewtonGroup:
    """Points solved together by batched Newton–Raphson, started from the sketch.

    ``dyads``: its points held by two distances alone, in the order they could be solved (each
    after the points it hangs from; `group_dyads`).
    """

    points: tuple[int, ...]
    constraints: tuple[Constraint, ...]
    dyads: tuple[GroupDyad, ...] = ()


Step = Fixed | Rotate | Attach | Dyad | SliderStep | NewtonGroup


@dataclass(frozen=True, slots=True)
class Element:
    """A linear element (cylinder, rope, strut) as the solver sees it."""

    name: str
    p: int
    q: int
    mode: Literal["driven", "locked", "free"]
    input: int
    length: float


@dataclass(frozen=True, slots=True)
class SolvePlan:
    """Everything the kinematic kernels need, in index form.

    Attributes
    ----------
    points : tuple of str
        Point names; index i is row i of the position arrays.
    bodies : tuple of str
        Body names; ground included.
    body_base : tuple of (int, int)
        The first two points of each body (``(-1, -1)`` for a one-point ground).
    inputs : tuple of str
        Driver names whose values are inputs (rotary first, then driven linear).
    input_kinds : tuple of str
        ``"angle"`` or ``"length"`` per input.
    input_sketch : tuple of float
        Each input's value at the sketch.
    elements : tuple of Element
    transmissions : tuple of str
        Point names of the dyads and sliders, whose transmission angles are reported.
    steps : tuple of Step
    sketch : tuple of (float, float)
        The sketch as the user drew it (before re-assembly to exact lengths).
    scale : float
        A characteristic size of the mechanism (m), for tolerances.
    """

    model: Model
    points: tuple[str, ...]
    bodies: tuple[str, ...]
    ground: int
    body_base: tuple[tuple[int, int], ...]
    inputs: tuple[str, ...]
    input_kinds: tuple[str, ...]
    input_sketch: tuple[float, ...]
    elements: tuple[Element, ...]
    transmissions: tuple[str, ...]
    steps: tuple[Step, ...]
    sketch: tuple[tuple[float, float], ...]
    shapes: dict[str, BodyShape]
    mobility: Mobility
    scale: float
    method: str = "closed-form"
    notes: tuple[str, ...] = field(default=())

    @property
    def has_newton(self) -> bool:
        """Whether any step is solved iteratively."""
        return any(isinstance(s, NewtonGroup) for s in self.steps)

    def describe(self) -> str:
        """The plan as text, one step a line, in the order it runs."""
        name = self.points.__getitem__
        lines = []
        for k, st in enumerate(self.steps, 1):
            if isinstance(st, Fixed):
                text = f"fixed    {', '.join(name(i) for i in st.points)} (ground)"
            elif isinstance(st, Rotate):
                ref = "ground" if st.ref is None else f"{name(st.ref[0])}→{name(st.ref[1])}"
                text = (
                    f"rotate   {name(st.point)} about {name(st.pivot)} by driver "
                    f"{st.driver!r} (from {ref}, r = {st.radius:.6g} m)"
                )
            elif isinstance(st, Attach):
                text = (
                    f"attach   {name(st.point)} to body {st.body!r} via {name(st.a)}, {name(st.b)}"
                )
            elif isinstance(st, Dyad):
                text = (
                    f"dyad     {name(st.point)} from {name(st.a)} ({_d(st.da)}) and "
                    f"{name(st.b)} ({_d(st.db)}), branch {'+' if st.sign > 0 else '−'}"
                )
            elif isinstance(st, SliderStep):
                text = (
                    f"slider   {name(st.point)} on line {name(st.l1)}→{name(st.l2)} "
                    f"({st.slider!r}) at {_d(st.da)} from {name(st.a)}, "
                    f"branch {'+' if st.sign > 0 else '−'}"
                )
            else:
                text = (
                    f"newton   {', '.join(name(i) for i in st.points)} together "
                    f"({len(st.constraints)} constraints)"
                )
            lines.append(f"{k:3d}. {text}")
        return "\n".join(lines)


def _d(d: Dist) -> str:
    if d.kind == "input":
        return f"driver {d.label!r}"
    return f"{d.label} {d.value:.6g} m"
