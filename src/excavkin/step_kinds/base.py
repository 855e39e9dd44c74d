"""What a step kind is: every operation a kind of solve-plan step implements, and the registry
that maps a step's record type to its kind.

A kind is a subclass of `StepKind` registered with `register` (a class decorator). Registration
refuses a kind that leaves any of `OPERATIONS` unimplemented, naming what is missing, so that no
caller meets a missing operation at run time; `kind_of` finds a step's kind by its record's type
(and refuses a record no kind registered).

The operations, by who calls them:

===================  =========================================================================
operation            used by
===================  =========================================================================
``build``            the plan builder: the step's record, from what the greedy choice found
``vary``             designs (`excavkin.structure.design`): its constants for a design's geometry
``take``             designs and the solve: its per-sample constants at a subset of samples
``solve``            the NumPy solve: its kernel over a chunk, order 0 (positions) or 2 (rates)
``nudge``            the precision check: the emulated rounding of its output
``transmission``     the precision check: which transmission angle it reports (None: none)
``constants``        the compiled plan: its entries in the constants table
``emit``             the compiled plan: its generated source (the tangents follow from it)
``describe``         ``SolvePlan.describe``: one line of text
``label``            failure messages: a short name of the step
``folding``          change points: the dyads in it that can fold through flat
``turn``             a sweep past a change point: the step with a folding dyad's side flipped
``role``             kinetostatics: the points it places and the drivers whose effort it carries
``drawing``          a drawing of the plan: its lines and marks, as data (no plotting here)
===================  =========================================================================

One operation has a default, which a kind overrides where its steps differ: ``uncompiled``
(why a step cannot be compiled; by default none can or all can, by `StepKind.compiles`).
"""

from __future__ import annotations

import inspect
from abc import ABC, abstractmethod
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, Generic, Literal, Protocol, TypeVar

from excavkin.arrays import FloatArray as F
from excavkin.model.entities import Model
from excavkin.step_kinds.dist import Dist, Index
from excavkin.step_kinds.state import Chunk, Code

#: every operation a kind implements (`StepKind` lists each, with its signature)
OPERATIONS: tuple[str, ...] = (
    "build",
    "vary",
    "take",
    "solve",
    "nudge",
    "transmission",
    "constants",
    "emit",
    "describe",
    "label",
    "folding",
    "turn",
    "role",
    "drawing",
)

#: the class attributes a kind sets
ATTRIBUTES: tuple[str, ...] = ("name", "record", "compiles", "iterative")

S = TypeVar("S")
T = TypeVar("T")


class Frame(Protocol):
    """A body's points in its own frame (`excavkin.structure.shapes.LocalFrame`)."""

    @property
    def local(self) -> dict[str, tuple[Any, Any]]:
        """Point name → (x, y) in the body's frame."""
        ...


class Geometry(Protocol):
    """A family of designs' geometry, as `excavkin.structure.design` makes it: the sketch
    and lengths with the parameters given, and the body frames (values are floats or arrays
    of one value per design)."""

    @property
    def sketch(self) -> dict[str, tuple[Any, Any]]:
        """Point name → (x, y)."""
        ...

    @property
    def frames(self) -> Mapping[str, Frame]:
        """Body name → its frame."""
        ...

    def distance(self, body: str, p: str, q: str) -> Any:
        """The distance of two points of a body, in its frame."""
        ...

    def frame_coords(self, body: str, p: str, a: str, b: str) -> tuple[Any, Any]:
        """(s, t) of point p on the body's vector a→b."""
        ...

    def override(self, p: str, q: str) -> Any:
        """The ``[lengths]`` entry of p and q, or None."""
        ...

    def unit(self, p: str, q: str) -> tuple[Any, Any]:
        """The unit vector q→p of the sketch."""
        ...

    def winch_ratio(self, rope: str) -> Any:
        """A winch rope's length (between blocks: its blocks' distance) per motor angle."""
        ...

    def rope_signed(self, rope: str) -> tuple[Any, ...] | None:
        """A rope's signed sheave radii σ·r (0 at its ends), or None where none is given."""
        ...

    def rack_radius(self, rack: str) -> Any:
        """A rack's pinion pitch radius."""
        ...

    def cam_lifts(self, cam: str) -> tuple[Any, ...] | None:
        """A cam table's lifts (every row but the last), or None where none is given."""
        ...

    @property
    def ratios(self) -> Mapping[str, Any]:
        """Gear pair name → its ratio, for each pair whose ratio is given."""
        ...

    def train(self) -> Mapping[str, Mapping[int, Any]] | None:
        """Each gear train body's angle coefficients (rotary driver index → coefficient)
        with the gear ratios given, or None where no ratio is given (the plan's own hold)."""
        ...


class Emitter(Protocol):
    """The compiled plan's source being written (`excavkin.kinematics.compiled`): the
    calls a kind's ``emit`` makes."""

    #: the name of the two-argument arctangent in the generated source
    atan2: str
    #: (transmission index, plan step) of each step that reports a transmission angle
    finite: list[tuple[int, int]]
    #: the points placed at rest (their rates are zero)
    at_rest: set[int]

    def emit(self, *lines: str) -> None:
        """Append lines of the loop body."""
        ...

    def const(self) -> str:
        """The source that reads the next constant of the table."""
        ...

    def flag(self, cond: str, code: Code, k: int, indent: str = "") -> None:
        """Give ``code`` where ``cond`` holds, as step ``k``."""
        ...

    def dist(self, d: Dist, name: str) -> tuple[str, str | None, str | None]:
        """A distance read into ``name``, and its rates' names (None: at rest)."""
        ...


@dataclass(frozen=True, slots=True)
class Role:
    """A step's part in the statics: the points it places (their force balance is written
    where the step places them) and the inputs whose driver's effort it carries (a rotary
    driver's torque, a driven element's force: the unknowns beside the joint reactions)."""

    places: tuple[int, ...]
    efforts: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class Primitive:
    """One mark of a drawing of a step, as data: ``kind`` and the plan's point indices.

    ``"ground"``: a point held fixed; ``"link"``: a rigid segment p→q (a body's distance, or
    a driven element when ``driven``); ``"arc"``: a point swung about a pivot (p the pivot,
    q the point); ``"slide"``: a line l1→l2 a point runs on; ``"group"``: points solved
    together; ``"profile"``: a cam's profile about its pivot p touching the follower's point q
    (`excavkin.outputs.cam_profiles` draws it from the model's law).
    """

    kind: Literal["ground", "link", "arc", "slide", "group", "profile"]
    points: tuple[int, ...]
    driven: bool = False


class StepKind(ABC, Generic[S]):
    """One kind of solve-plan step: its record type and every operation on it.

    A subclass sets `name`, `record`, `compiles` and `iterative` and implements every method
    below; `register` checks it.
    """

    #: a short name ("dyad")
    name: ClassVar[str]
    #: the record type of its steps
    record: ClassVar[type]
    #: whether the closed-form plan's compiled kernel can hold it (else a plan with it runs in
    #: NumPy; an iterative kind's ``emit`` writes the kernels of a plan with Newton groups,
    #: `excavkin.kinematics.compiled_newton`)
    compiles: ClassVar[bool]
    #: whether it is solved by iteration (a Newton group) rather than in closed form
    iterative: ClassVar[bool]

    @abstractmethod
    def build(self, *args: Any, **kwargs: Any) -> S:
        """The step's record, from what the plan builder found (the record's fields)."""

    @abstractmethod
    def vary(self, st: S, geo: Geometry, names: tuple[str, ...], model: Model) -> S:
        """The step with its constants for a family of designs (``st`` itself where none
        varies)."""

    @abstractmethod
    def take(self, st: S, index: Index) -> S:
        """The step's per-sample constants taken at ``index`` (``st`` itself where none is
        per sample)."""

    @abstractmethod
    def solve(
        self, c: Chunk, st: S, k: int, order: int, scale: float, newton: bool = True
    ) -> F | None:
        """Run the NumPy kernel of step ``k`` over a chunk: positions, and with ``order`` 2
        velocities and accelerations too. ``newton=False``: an iterative step keeps the
        positions it has and solves only its rates. Returns an iterative step's determinant
        sign (``order`` 2), else None."""

    @abstractmethod
    def nudge(self, c: Chunk, st: S, order: int) -> None:
        """The precision check's emulated rounding of the step's output (``c.nudge``)."""

    @abstractmethod
    def transmission(self, st: S) -> int | None:
        """The index of the transmission angle the step reports, or None."""

    def uncompiled(self, st: S) -> str | None:
        """Why step ``st`` cannot be compiled (None: it can). By default a kind's steps all
        compile or none does (`compiles`); a kind whose steps differ says so per step (a
        cam's, by its lift law)."""
        return None if self.compiles else f"a {self.name} step"

    @abstractmethod
    def constants(self, st: S) -> list[Any]:
        """The step's entries of the compiled plan's constants table, in the order its
        source reads them."""

    @abstractmethod
    def emit(self, g: Emitter, st: S, k: int) -> None:
        """Write step ``k``'s compiled source (a kind that does not compile raises
        TypeError; an iterative kind writes only into an emitter that says which of a Newton
        plan's kernels it writes, its ``newton`` attribute)."""

    @abstractmethod
    def describe(self, st: S, names: tuple[str, ...]) -> str:
        """One line of the plan's description."""

    @abstractmethod
    def label(self, st: S, names: tuple[str, ...], k: int) -> str:
        """A short name of step ``k`` for failure messages."""

    @abstractmethod
    def folding(self, st: S) -> list[tuple[int, Any]]:
        """The dyads of the step that can fold flat (change points): (place, dyad) with place
        −1 for the step itself, else the index among a group's dyads."""

    @abstractmethod
    def turn(self, st: S, place: int, turn: Any) -> S:
        """The step with the side of its folding dyad at ``place`` multiplied by ``turn``
        (±1, or one per sample)."""

    @abstractmethod
    def role(self, st: S) -> Role:
        """The step's part in the statics."""

    @abstractmethod
    def drawing(self, st: S) -> tuple[Primitive, ...]:
        """The step's marks in a drawing of the plan."""


#: record type → its kind
REGISTRY: dict[type, StepKind[Any]] = {}

K = TypeVar("K", bound=type[StepKind[Any]])


def missing_operations(cls: type) -> list[str]:
    """The operations and attributes a kind class leaves unimplemented.

    Parameters
    ----------
    cls : type
        The kind class.

    Returns
    -------
    list of str
        Each name of `OPERATIONS` that is absent, not callable or still abstract, then each
        of `ATTRIBUTES` not set.
    """
    out = []
    for op in OPERATIONS:
        fn = inspect.getattr_static(cls, op, None)
        if fn is None or not callable(fn) or getattr(fn, "__isabstractmethod__", False):
            out.append(op)
    out += [a for a in ATTRIBUTES if not hasattr(cls, a)]
    return out


def register(cls: K) -> K:
    """Register a step kind (a class decorator): one instance, under its record type.

    Parameters
    ----------
    cls : type
        A subclass of `StepKind`.

    Returns
    -------
    type
        ``cls``, registered.

    Raises
    ------
    TypeError
        ``cls`` is not a `StepKind`, leaves an operation unimplemented (named), or its record
        type is registered already.
    """
    if not (isinstance(cls, type) and issubclass(cls, StepKind)):
        raise TypeError(f"{cls!r} is not a StepKind")
    missing = missing_operations(cls)
    if missing:
        raise TypeError(f"step kind {cls.__name__} does not implement: {', '.join(missing)}")
    record = cls.record
    if record in REGISTRY:
        raise TypeError(
            f"step kind {cls.__name__}: record {record.__name__} is registered already, by "
            f"{type(REGISTRY[record]).__name__}"
        )
    REGISTRY[record] = cls()
    return cls


def kind_of(st: Any) -> StepKind[Any]:
    """The kind of a step, by its record's type.

    Parameters
    ----------
    st : step record
        A step of a solve plan.

    Returns
    -------
    StepKind
        Its registered kind.

    Raises
    ------
    TypeError
        No kind is registered for the record's type.
    """
    try:
        return REGISTRY[type(st)]
    except KeyError:
        raise TypeError(f"no step kind is registered for {type(st).__name__}") from None


def registered() -> dict[type, StepKind[Any]]:
    """Every registered kind by its record type.

    Returns
    -------
    dict of type to StepKind
        A copy of the registry.
    """
    return dict(REGISTRY)


def of_kind(steps: Iterable[Any], record: type[T]) -> list[tuple[int, T]]:
    """The steps of one kind, with their places in the plan.

    Parameters
    ----------
    steps : iterable of step records
        A plan's steps, in order.
    record : type
        A registered record type.

    Returns
    -------
    list of (int, record)
        (plan step index, step) of each step whose record is ``record``.
    """
    kind = REGISTRY[record]
    return [(k, st) for k, st in enumerate(steps) if kind_of(st) is kind]
