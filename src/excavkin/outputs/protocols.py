"""What the outputs take: small protocols that results and mechanisms satisfy.

Outputs read results through these, never through the concrete classes, so that a wing's own
result (or a user's) can be drawn and tabulated if it offers the same few members.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any, Protocol, TypeAlias

if TYPE_CHECKING:
    import numpy as np
    import pandas as pd

    from excavkin.kinematics.columns import Column
    from excavkin.model.entities import Model
    from excavkin.outputs.events import Table
    from excavkin.structure.plan import SolvePlan


class TableSource(Protocol):
    """A result that can be shown: it makes a table and describes its columns."""

    @property
    def columns(self) -> tuple[Column, ...]: ...

    def to_frame(self) -> pd.DataFrame: ...


class Solved(Protocol):
    """A kinematic result: a plan, positions over the samples and a table."""

    @property
    def plan(self) -> SolvePlan: ...

    @property
    def positions(self) -> np.ndarray: ...

    @property
    def columns(self) -> tuple[Column, ...]: ...

    def to_frame(self) -> pd.DataFrame: ...


class MechanismLike(Protocol):
    """A mechanism as the outputs use it: its plan, its assembly and a way to solve it."""

    @property
    def plan(self) -> SolvePlan: ...

    @property
    def assembly(self) -> Any: ...

    @property
    def model(self) -> Model: ...

    @property
    def name(self) -> str: ...

    def describe(self) -> str: ...

    @property
    def inputs(self) -> tuple[str, ...]: ...

    def input_kind(self, name: str) -> str: ...

    def sketch_values(self) -> dict[str, float]: ...

    def solve(self, values: Mapping[str, Any] | None = None, *args: Any, **kwargs: Any) -> Any: ...


#: anything `as_table` takes
TableData: TypeAlias = "TableSource | Table | pd.DataFrame"
#: anything that can be drawn: a mechanism at its sketch, or a result over its samples
Drawable: TypeAlias = "MechanismLike | TableSource"
#: names a sample in messages: ``describe(i) -> "crank = 35°"``
SampleNamer: TypeAlias = Callable[[int], str]
