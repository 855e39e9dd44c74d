"""What a family gives for studies of its machine's parameters: a protocol.

A study of machine parameters (`excavkin.studies.machine_study`) reads a study file that names
a machine file, samples or optimises the machine's parameters in a box, and reduces the
family's machine columns to metrics. Everything about it is the same for every family but
four things, which the family supplies through a `DesignFamily`:

* its parameters and their kinds (the mechanism's, its cylinders', its circuits' …);
* its columns: what it can tell of a design at a pose (a tool force, a tooth tip) or of the
  design as a whole (a working-range figure, a hinge-pin height), and their kinds;
* whether a study gives poses (cylinder lengths) at all: a family whose figures are each taken
  at the pose its standard defines has none, and each design is one row of one "pose";
* the computation itself: the columns of n samples, sample i a design of its own.

The protocol lives here, below the studies, so that a family's wing implements it with the
machinery it already has; the file reader, the loop over designs and the optimiser's problem
live in the studies layer, which may import this one (not the other way round).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F

if TYPE_CHECKING:
    from excavkin.machinery.cylinders import Circuit, Cylinder
    from excavkin.model.entities import Model

__all__ = [
    "CIRCUIT_KEYS",
    "CYLINDER_KEYS",
    "DesignFamily",
    "Family",
    "cylinder_parameters",
    "design_cylinders",
    "model_parameter",
    "model_with",
]


#: the cylinder entries that are parameters (``cylinders.ROLE.KEY``)
CYLINDER_KEYS: tuple[str, ...] = ("bore", "rod", "retracted", "stroke")
#: the circuit entries that are parameters (``circuits.NAME.KEY``)
CIRCUIT_KEYS: tuple[str, ...] = ("working", "relief")


class DesignFamily(Protocol):
    """A family's side of a study of its machine's parameters.

    Attributes
    ----------
    name : str
        The family's name, as its commands are: ``excavkin NAME study``.
    columns : mapping of str to str
        Each column the family computes and its kind (``"length"``, ``"force"``, ``"mass"``,
        ``"angle"`` …).
    angles : frozenset of str
        The angle columns (their ``change`` is followed along the poses).
    posed : bool
        Whether a study gives poses (``[poses]`` of cylinder lengths); where not, each design
        is evaluated once and every metric's ``reduce`` defaults to ``"first"``.
    """

    name: str
    columns: Mapping[str, str]
    angles: frozenset[str]
    posed: bool

    def load(self, path: Path) -> Any:
        """The family's machine from its machine file.

        Parameters
        ----------
        path : Path
            The machine file.

        Returns
        -------
        object
            The machine (a `CylinderMachine` of the family).
        """
        ...

    def parameters(self, machine: Any) -> dict[str, float]:
        """Every parameter of the machine and its nominal value, SI.

        Parameters
        ----------
        machine : object
            The family's machine.

        Returns
        -------
        dict of str to float
            The mechanism's parameters first, then the machine file's (named by their
            tables: ``cylinders.ROLE.bore``, ``circuits.NAME.working`` …).
        """
        ...

    def parameter_kind(self, name: str, machine: Any) -> str:
        """The physical kind of a parameter (for units at the edges).

        Parameters
        ----------
        name : str
            A name of `parameters`.
        machine : object
            The family's machine.

        Returns
        -------
        str
            ``"length"``, ``"pressure"``, ``"mass"`` …
        """
        ...

    def evaluate(
        self,
        machine: Any,
        lengths: F,
        params: Mapping[str, F],
        names: Sequence[str],
    ) -> tuple[dict[str, F], NDArray[np.bool_]]:
        """The columns ``names`` of n samples, sample i the design ``params[k][i]`` at the
        cylinder lengths ``lengths[i]``.

        Parameters
        ----------
        machine : object
            The nominal machine.
        lengths : ndarray, shape (n, k)
            Cylinder lengths (k = 0 for a family without poses).
        params : mapping of str to ndarray, shape (n,)
            Parameter → its SI value in each sample.
        names : sequence of str
            Names of `columns`.

        Returns
        -------
        columns : dict of str to ndarray, shape (n,)
        ok : ndarray of bool, shape (n,)
            Which samples are valid (the design assembles and its figures exist there).
        """
        ...


@dataclass(slots=True)
class Family:
    """A `DesignFamily` made of a wing's functions: what every family's side of a study is,
    without a class of its own in each wing.

    Attributes
    ----------
    name : str
        As `DesignFamily.name`.
    columns : mapping of str to str
        As `DesignFamily.columns`.
    angles : frozenset of str
        As `DesignFamily.angles`.
    posed : bool
        As `DesignFamily.posed`.
    load : callable
        ``load(path) -> machine``: `DesignFamily.load`.
    parameters : callable
        ``parameters(machine) -> dict``: `DesignFamily.parameters`.
    parameter_kind : callable
        ``parameter_kind(name, machine) -> str``: `DesignFamily.parameter_kind`.
    evaluate : callable
        ``evaluate(machine, lengths, params, names) -> (columns, ok)``:
        `DesignFamily.evaluate`.
    """

    name: str
    columns: Mapping[str, str]
    angles: frozenset[str]
    posed: bool
    load: Callable[[Path], Any]
    parameters: Callable[[Any], dict[str, float]]
    parameter_kind: Callable[[str, Any], str]
    evaluate: Callable[
        [Any, F, Mapping[str, F], Sequence[str]], tuple[dict[str, F], NDArray[np.bool_]]
    ]


def cylinder_parameters(
    cylinders: Sequence[Cylinder], circuits: Mapping[str, Circuit]
) -> dict[str, float]:
    """The cylinders' and circuits' parameters and their nominal values, SI, named after the
    machine file's tables: ``cylinders.ROLE.KEY`` (`CYLINDER_KEYS`), then
    ``circuits.NAME.KEY`` (`CIRCUIT_KEYS`).

    Parameters
    ----------
    cylinders : sequence of Cylinder
    circuits : mapping of str to Circuit
        By name.

    Returns
    -------
    dict of str to float
    """
    out: dict[str, float] = {}
    for c in cylinders:
        for key in CYLINDER_KEYS:
            out[f"cylinders.{c.role}.{key}"] = float(getattr(c, key))
    for name, circ in circuits.items():
        for key in CIRCUIT_KEYS:
            out[f"circuits.{name}.{key}"] = float(getattr(circ, key))
    return out


def design_cylinders(
    cylinders: Sequence[Cylinder], circuits: Mapping[str, Circuit], params: Mapping[str, float]
) -> tuple[dict[str, Cylinder], dict[str, Circuit]]:
    """One design's cylinders and circuits: each with the values of ``params`` named after
    the machine file's tables (``cylinders.ROLE.bore``, ``.rod``, ``.retracted``,
    ``.stroke``; ``circuits.NAME.working``, ``.relief``), the others as they are.

    Parameters
    ----------
    cylinders : sequence of Cylinder
        The nominal machine's.
    circuits : mapping of str to Circuit
        The nominal machine's, by name.
    params : mapping of str to float
        Parameter name → its SI value; other names are left to the caller.

    Returns
    -------
    cylinders : dict of str to Cylinder
        By role.
    circuits : dict of str to Circuit
        By name.
    """
    import dataclasses

    def get(name: str, nominal: float) -> float:
        return float(params.get(name, nominal))

    designed = {
        c.role: dataclasses.replace(
            c,
            bore=get(f"cylinders.{c.role}.bore", c.bore),
            rod=get(f"cylinders.{c.role}.rod", c.rod),
            retracted=get(f"cylinders.{c.role}.retracted", c.retracted),
            stroke=get(f"cylinders.{c.role}.stroke", c.stroke),
        )
        for c in cylinders
    }
    return designed, {
        n: dataclasses.replace(
            c,
            working=get(f"circuits.{n}.working", c.working),
            relief=get(f"circuits.{n}.relief", c.relief),
        )
        for n, c in circuits.items()
    }


def model_parameter(model: Model, name: str) -> bool:
    """Whether `model_with` sets the mechanism parameter ``name`` of ``model``: a point's
    coordinate (``P.x``, ``P.y``), a body's ``mass`` or ``inertia``, or its centre of mass
    (``BODY.center_of_mass.x``, ``.y``).

    Parameters
    ----------
    model : Model
    name : str

    Returns
    -------
    bool
    """
    head, _, key = name.rpartition(".")
    bodies = {b.name for b in model.bodies}
    if key in ("x", "y") and head in model.points:
        return True
    if key in ("mass", "inertia") and head in bodies:
        return True
    return (
        key in ("x", "y")
        and head.endswith(".center_of_mass")
        and (head[: -len(".center_of_mass")] in bodies)
    )


def model_with(model: Model, params: Mapping[str, float]) -> Model:
    """One design's model: ``model`` with the points, bodies' masses, inertias and centres of
    mass of ``params`` (others as they are). A body's other points and its centre of mass stay
    where the sketch puts them when one of its points moves (the engine's convention for
    designs, `excavkin.structure.design`).

    Parameters
    ----------
    model : Model
        The nominal model.
    params : mapping of str to float
        Parameter name (`model_parameter`) → its SI value; names that are not the model's
        (a machine file's ``cylinders.…``) are left to the caller.

    Returns
    -------
    Model
        Not yet validated: a `Mechanism` of it checks that it assembles.
    """
    import dataclasses

    points = dict(model.points)
    bodies = {b.name: b for b in model.bodies}
    for name, value in params.items():
        if not model_parameter(model, name):
            continue
        head, _, key = name.rpartition(".")
        if head in points:
            x, y = points[head]
            points[head] = (float(value), y) if key == "x" else (x, float(value))
        elif key == "mass":
            bodies[head] = dataclasses.replace(bodies[head], mass=float(value))
        elif key == "inertia":
            bodies[head] = dataclasses.replace(bodies[head], inertia=float(value))
        else:
            b = bodies[head[: -len(".center_of_mass")]]
            cx, cy = b.center_of_mass or (0.0, 0.0)
            com = (float(value), cy) if key == "x" else (cx, float(value))
            bodies[b.name] = dataclasses.replace(b, center_of_mass=com)
    return dataclasses.replace(
        model, points=points, bodies=tuple(bodies[b.name] for b in model.bodies)
    )


def rate_designs(
    params: Mapping[str, F],
    names: Sequence[str],
    n: int,
    rate: Callable[[dict[str, float]], Mapping[str, float]],
    known: Mapping[str, str],
    what: str,
) -> tuple[dict[str, F], NDArray[np.bool_]]:
    """The columns ``names`` of n designs, each distinct design rated once by ``rate``, for a
    family whose every design finds its own poses (one machine a design): design i is
    ``params[k][i]``.

    Parameters
    ----------
    params : mapping of str to ndarray, shape (n,)
        Parameter → its SI value in each design (none: n copies of the nominal design).
    names : sequence of str
        The columns asked for, each one of ``known``: checked before any design is rated, so
        that a name that is not one is an error, not a column of NaN.
    n : int
        The designs.
    rate : callable
        ``rate(design) -> {column: value}`` for one design's parameters; an `ExcavkinError`
        (a design that cannot be built or rated) makes that design's row NaN.
    known : mapping of str to str
        The family's columns (name → kind).
    what : str
        What a column is called in the message (``"crane column"``).

    Returns
    -------
    columns : dict of str to ndarray, shape (n,)
    ok : ndarray of bool, shape (n,)
        The design was rated and every column asked for is finite.

    Raises
    ------
    InputError
        A name not among ``known``.
    """
    from excavkin.errors import ExcavkinError, require_known

    require_known(what, names, known)
    keys = sorted(params)
    rows = np.column_stack(
        [np.broadcast_to(np.asarray(params[k], float), (n,)) for k in keys]
    ) if keys else np.zeros((n, 0))  # fmt: skip
    designs, which = np.unique(rows, axis=0, return_inverse=True)
    values = np.full((len(designs), len(names)), np.nan)
    for i, row in enumerate(designs):  # each design finds its own poses: one machine each
        try:
            figures = rate(dict(zip(keys, row.tolist(), strict=True)))
        except ExcavkinError:
            continue
        values[i] = [figures[k] for k in names]
    at = values[which.reshape(-1)]
    ok = np.asarray(np.isfinite(at).all(axis=1))
    return {k: np.asarray(at[:, j]) for j, k in enumerate(names)}, ok


def unposed(
    columns: Callable[[Any, Mapping[str, F], Sequence[str], int], tuple[dict[str, F], Any]],
) -> Callable[[Any, F, Mapping[str, F], Sequence[str]], tuple[dict[str, F], Any]]:
    """`Family.evaluate` of a family whose designs find their own poses (no pose lengths):
    ``columns(machine, params, names, n)`` of as many designs as lengths.

    Parameters
    ----------
    columns : callable
        The family's columns of n designs (``crane_columns`` …).

    Returns
    -------
    callable
    """

    def evaluate(
        machine: Any, lengths: F, params: Mapping[str, F], names: Sequence[str]
    ) -> tuple[dict[str, F], Any]:
        return columns(machine, params, names, len(lengths))

    return evaluate
