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
Gear       a known point of a body a gear train turns          another, at θ = θ0 + Σ c_i q_i
Rack       the pinion's pivot and the rack's guide             the rack's first two points
Cam        the cam's pivot and the follower's guide            the follower's first two points
CamRocker  the cam's and the follower's pivots                 the follower's roller centre
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
from excavkin.step_kinds import (
    Attach,
    CAngle,
    CDist,
    CFrame,
    CLine,
    Constraint,
    CRope,
    Dist,
    Dyad,
    Fixed,
    GroupDyad,
    NewtonGroup,
    Rotate,
    SliderStep,
    Step,
    kind_of,
)
from excavkin.structure.shapes import BodyShape

# the records of the step kinds live in `excavkin.step_kinds`, one module a kind
__all__ = [
    "Attach",
    "CAngle",
    "CDist",
    "CFrame",
    "CLine",
    "Constraint",
    "CRope",
    "Dist",
    "Dyad",
    "Element",
    "Fixed",
    "GroupDyad",
    "NewtonGroup",
    "Rotate",
    "SliderStep",
    "SolvePlan",
    "Step",
]


@dataclass(frozen=True, slots=True)
class Element:
    """A linear element (cylinder, rope, strut) as the solver sees it."""

    name: str
    p: int
    q: int
    mode: Literal["driven", "locked", "free"]
    input: int
    length: float
    #: a winch rope's blocks' distance per motor angle (m/rad): its distance is ``ratio·q``
    #: (0: a cylinder's length is its input itself)
    ratio: float = 0.0


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
        return any(kind_of(s).iterative for s in self.steps)

    def describe(self) -> str:
        """The plan as text, one step a line, in the order it runs."""
        lines = []
        for k, st in enumerate(self.steps, 1):
            lines.append(f"{k:3d}. {kind_of(st).describe(st, self.points)}")
        return "\n".join(lines)
