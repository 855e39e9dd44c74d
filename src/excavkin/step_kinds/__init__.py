"""Step kinds: one module each, a registry.

A solve plan (`excavkin.structure.plan`) is a sequence of steps of a few kinds: `Fixed`,
`Rotate`, `Attach`, `Dyad`, `SliderStep`, `NewtonGroup`, `GearStep`, `RackStep`, `CamStep` and
`CamRockerStep`.
Each kind's module holds its record and every operation on it
(`excavkin.step_kinds.base.StepKind` lists them): building it, its constants for a family of
designs, its NumPy kernel, its compiled source, the precision check's part, its description, its
part in the statics and its drawing. Importing this package registers every kind; `kind_of`
finds a step's kind by its record's type.

To add a kind: write a module here with its record (a frozen dataclass) and a `StepKind`
subclass decorated with `register` that implements every operation, import it below, and add
its record to `Step`.
"""

from __future__ import annotations

from excavkin.step_kinds import (
    attach,
    cam,
    cam_rocker,
    dyad,
    fixed,
    gear,
    newton_group,
    rack,
    rotate,
    slider,
)
from excavkin.step_kinds.attach import Attach
from excavkin.step_kinds.base import (
    OPERATIONS,
    Primitive,
    Role,
    StepKind,
    kind_of,
    of_kind,
    register,
    registered,
)
from excavkin.step_kinds.cam import CamStep
from excavkin.step_kinds.cam_rocker import CamRockerStep
from excavkin.step_kinds.constraints import (
    CAngle,
    CDist,
    CFrame,
    CLine,
    Constraint,
    CRope,
    GroupDyad,
)
from excavkin.step_kinds.dist import Dist
from excavkin.step_kinds.dyad import Dyad
from excavkin.step_kinds.fixed import Fixed
from excavkin.step_kinds.gear import GearStep
from excavkin.step_kinds.newton_group import NewtonGroup
from excavkin.step_kinds.rack import RackStep
from excavkin.step_kinds.rotate import Rotate
from excavkin.step_kinds.slider import SliderStep

#: a step of a solve plan: a record of one of the registered kinds
Step = (
    Fixed
    | Rotate
    | Attach
    | Dyad
    | SliderStep
    | NewtonGroup
    | GearStep
    | RackStep
    | CamStep
    | CamRockerStep
)

__all__ = [
    "OPERATIONS",
    "Attach",
    "CAngle",
    "CamRockerStep",
    "CamStep",
    "CRope",
    "CDist",
    "CFrame",
    "CLine",
    "Constraint",
    "Dist",
    "Dyad",
    "Fixed",
    "GearStep",
    "GroupDyad",
    "NewtonGroup",
    "Primitive",
    "RackStep",
    "Role",
    "Rotate",
    "SliderStep",
    "Step",
    "StepKind",
    "attach",
    "cam",
    "cam_rocker",
    "dyad",
    "fixed",
    "gear",
    "kind_of",
    "newton_group",
    "of_kind",
    "rack",
    "register",
    "registered",
    "rotate",
    "slider",
]
