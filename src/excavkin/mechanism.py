"""The user-facing mechanism: a validated model compiled once into a solve plan.

>>> import numpy as np, excavkin
>>> mech = excavkin.load(excavkin.example_path("fourbar"))
>>> res = mech.solve({"crank": np.radians([0.0, 90.0])})
>>> res.status.all_ok
True
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal, overload

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError, SolveFailure, did_you_mean
from excavkin.execution import DEFAULT, Execution, settings
from excavkin.kinematics import Assembly, KinematicResult, Tolerances, assemble
from excavkin.kinematics.sweep import Part, solve_parts
from excavkin.model.entities import Model, rope_line
from excavkin.model.gears import describe_meshes
from excavkin.model.validate import validate
from excavkin.structure.builder import compile_plan
from excavkin.structure.plan import SolvePlan
from excavkin.sweeps import Lazy, part_of

if TYPE_CHECKING:
    import pandas as pd

    from excavkin.kinematics.selection import SelectedResult
    from excavkin.kinetostatics import ForceResult, Load, StaticsSystem


#: the names ``backend=`` takes (`excavkin.backends`)
Backend = Literal["auto", "numpy", "numba", "cuda"]

#: the kinds of a driver's value, rate and acceleration, by the kind of its value
_ORDER_KINDS = {
    "angle": ("angle", "angular_velocity", "angular_acceleration"),
    "length": ("length", "velocity", "acceleration"),
}


def as_si(value: Any, kind: str, what: str) -> Any:
    """A value given to the Python API in SI: plain numbers and arrays as they are; a pint
    quantity (of any registry) or a string with a unit converted by its dimension.

    Raises
    ------
    UnitError
        A wrong dimension or an unreadable string, naming ``what``.
    """
    if isinstance(value, str) or (hasattr(value, "magnitude") and hasattr(value, "units")):
        from excavkin.units import quantity_to_si  # pint only where a unit was given

        return quantity_to_si(value, kind, where=f"{what}: ")
    if isinstance(value, (list, tuple)) and any(isinstance(v, str) for v in value):
        from excavkin.units import quantity_to_si

        return np.array([quantity_to_si(v, kind, where=f"{what}: ") for v in value])
    return value


def _vector_si(value: Any, kind: str, what: str) -> Any:
    """A force vector (Fx, Fy) — a quantity array, a pair of quantities or strings, or plain
    numbers — in SI."""
    if isinstance(value, (list, tuple)) and any(
        isinstance(v, str) or hasattr(v, "units") for v in value
    ):
        return np.array([as_si(v, kind, what) for v in value], dtype=np.float64)
    return as_si(value, kind, what)


def _load_in_si(load: Load) -> Load:
    """A load given to the Python API, with any units converted by dimension (a function's
    result converted when it is called)."""
    from excavkin.kinetostatics import Gravity, PointForce, Torque

    if isinstance(load, Gravity):
        return dataclasses.replace(load, g=float(as_si(load.g, "acceleration", "gravity")))
    if not isinstance(load, PointForce | Torque):
        return load  # not a load record: the loads' own check names it
    kind = "force" if isinstance(load, PointForce) else "torque"
    what = f"load {load.name!r}"
    convert = _vector_si if isinstance(load, PointForce) else as_si
    value = load.value
    if callable(value):
        given = value

        def value(result: KinematicResult) -> Any:
            return convert(given(result), kind, what)

    else:
        value = convert(value, kind, what)
    return dataclasses.replace(load, value=value)


def _loads_of_designs(loads: Iterable[Load], params: Mapping[str, Any], n: int) -> list[Load]:
    """The loads with the magnitudes a family of designs gives (``LOAD.Fx`` …) per sample."""
    from excavkin.kinetostatics import PointForce, Torque

    out: list[Load] = []
    for ld in loads:
        if isinstance(ld, PointForce) and {f"{ld.name}.Fx", f"{ld.name}.Fy"} & set(params):
            fx, fy = np.asarray(ld.value, dtype=np.float64)
            value = np.column_stack(
                [
                    np.broadcast_to(params.get(f"{ld.name}.Fx", fx), (n,)),
                    np.broadcast_to(params.get(f"{ld.name}.Fy", fy), (n,)),
                ]
            )
            ld = dataclasses.replace(ld, value=value)
        elif isinstance(ld, Torque) and f"{ld.name}.torque" in params:
            tau = np.broadcast_to(params[f"{ld.name}.torque"], (n,)).copy()
            ld = dataclasses.replace(ld, value=tau)
        out.append(ld)
    return out


#: what a part of [`Mechanism.solve_stream`][excavkin.mechanism.Mechanism.solve_stream] may hold by
#: default, bytes of its result
PART_BYTES = 64 * 2**20


@dataclass(frozen=True, slots=True)
class SolvedPart:
    """Consecutive samples of a sweep, solved
    ([`Mechanism.solve_stream`][excavkin.mechanism.Mechanism.solve_stream]).

    Attributes
    ----------
    start : int
        The first sample's number in the sweep: row ``i`` of ``result`` is sample
        ``start + i``.
    result : KinematicResult, SelectedResult or ForceResult
        The part's result. Its change points are numbered in the whole sweep (one whose two
        samples lie in two parts is the later part's). A kinematic stream of some columns
        (``columns=``) gives a
        [`SelectedResult`][excavkin.kinematics.selection.SelectedResult]: those columns
        alone, and every sample's status (the whole sample's).
    total : int
        The number of samples in the whole sweep.
    columns : tuple of str, optional
        The columns `to_frame` keeps (``solve_stream(columns=...)``); None: every one.
    """

    start: int
    result: KinematicResult | SelectedResult | ForceResult
    total: int
    columns: tuple[str, ...] | None = None

    def to_frame(self) -> pd.DataFrame:
        """The part's table: its result's ``to_frame``, only the columns asked of the stream.

        Returns
        -------
        pandas.DataFrame
            One row per sample of the part, SI.
        """
        return self.result.to_frame(columns=self.columns)

    @property
    def stop(self) -> int:
        """One past the part's last sample."""
        return self.start + len(self.result)


def _selected(
    parts: Iterator[SolvedPart], columns: tuple[str, ...], some: bool
) -> Iterator[SolvedPart]:
    """The parts, each to make a table of only ``columns``; the names checked on the first.
    ``some``: the kinematics were solved for those columns, and each part's result gives
    them alone (`excavkin.kinematics.selection.SelectedResult`: its other rows may hold
    no values)."""
    from excavkin.kinematics.selection import SelectedResult

    for i, part in enumerate(parts):
        if i == 0:
            part.result.to_frame(columns=columns)  # views only: raises on a name unknown
        if some and isinstance(part.result, KinematicResult):
            selected = SelectedResult.of(part.result, columns)
            part = dataclasses.replace(part, result=selected)
        yield dataclasses.replace(part, columns=columns)


@dataclass(frozen=True, slots=True)
class _Batch:
    """A solve's inputs, checked and in SI, made into the solver's arrays part by part."""

    mech: Mechanism
    n: int
    values: dict[str, Any]
    rates: dict[str, Any]
    accels: dict[str, Any]
    time: Any
    params: dict[str, Any]
    continuation: str
    #: forces are asked for: a swept driver given no rate is at rest (rate 0), not at rate 1
    forces: bool = False

    @property
    def unrated(self) -> tuple[str, ...]:
        """The swept drivers given no rate, in plan order."""
        return tuple(
            name
            for name in self.mech.plan.inputs
            if name in self.values and self.values[name].ndim == 1 and name not in self.rates
        )

    def part(self, start: int, stop: int) -> Part:
        """Samples ``start`` … ``stop − 1``: their inputs in plan order and their plan."""
        from excavkin.structure.design import DesignBatch, design_plan

        plan = self.mech.plan
        k = stop - start
        n_in = len(plan.inputs)
        q = np.empty((n_in, k))
        given = {name: part_of(v, start, stop) for name, v in self.params.items()}
        held: Any = np.asarray(plan.input_sketch)[:, None]
        here, unbuildable, batch = plan, None, None
        if given and (plan.has_newton or self.continuation == "smooth"):
            # these take a part's designs at once: its constants made for every sample
            designs = design_plan(plan, given, k)
            here, held, unbuildable = designs.plan, designs.input_sketch, designs.unbuildable
        elif given:
            batch = DesignBatch(plan, {name: np.broadcast_to(v, (k,)) for name, v in given.items()})
            if any(name not in self.values for name in plan.inputs):
                held = batch.held(k)
        rates, accels = [], []
        unit = 0.0 if self.forces else 1.0
        for i, name in enumerate(plan.inputs):
            val = self.values.get(name)
            swept = val is not None and val.ndim == 1
            q[i] = held[i] if val is None else part_of(val, start, stop)
            rate = self.rates.get(name)
            rates.append((unit if swept else 0.0) if rate is None else part_of(rate, start, stop))
            accel = self.accels.get(name)
            accels.append(0.0 if accel is None else part_of(accel, start, stop))
        return Part(start, q, _rows(rates, k), _rows(accels, k), here, unbuildable, batch)


def _rows(values: list[Any], k: int) -> F:
    """Rates or accelerations as (n_inputs, k): a read-only broadcast of one value per input
    when none varies (nothing written per sample), else an array of their own."""
    if all(np.ndim(v) == 0 for v in values):
        column = np.array(values, dtype=np.float64).reshape(-1, 1)
        return np.broadcast_to(column, (len(values), k))
    out = np.empty((len(values), k))
    for i, v in enumerate(values):
        out[i] = v
    return out


class Mechanism:
    """A planar mechanism ready to solve.

    Parameters
    ----------
    model : Model
        From [`excavkin.load`][] or built in Python.
    method : {"closed-form", "newton"}
        ``"newton"`` solves every moving point with the generic Newton–Raphson solver instead of
        the closed-form steps (slower; for cross-checking), but the bodies of gear trains,
        racks and cam followers, which it places in closed form (their angles and travels
        are linear in the inputs).
    """

    def __init__(
        self, model: Model, *, method: Literal["closed-form", "newton"] = "closed-form"
    ) -> None:
        validate(model)
        self.model: Model = model
        self.plan: SolvePlan = compile_plan(model, method=method)
        self.assembly: Assembly = assemble(self.plan)
        self._statics: StaticsSystem | None = None
        self._kinds: tuple[SolvePlan, dict[str, str]] | None = None

    @property
    def name(self) -> str:
        """The model's name."""
        return self.model.name

    @property
    def inputs(self) -> tuple[str, ...]:
        """Names of the drivers whose values are inputs."""
        return self.plan.inputs

    def sketch_values(self) -> dict[str, float]:
        """Each input's value at the (re-assembled) sketch, SI.

        Returns
        -------
        dict of str to float
            Input name → its value there (rad or m).
        """
        return dict(zip(self.plan.inputs, self.plan.input_sketch, strict=True))

    def input_kind(self, name: str) -> str:
        """``"angle"`` or ``"length"``: what the input ``name`` drives.

        Parameters
        ----------
        name : str
            One of `inputs`.

        Returns
        -------
        str
            ``"angle"`` for a rotary driver (rad), ``"length"`` for a linear one (m).

        Raises
        ------
        InputError
            A name that is not an input, with the nearest ones.
        """
        if self._kinds is None or self._kinds[0] is not self.plan:  # by name, not by a scan
            self._kinds = (
                self.plan,
                dict(zip(self.plan.inputs, self.plan.input_kinds, strict=True)),
            )
        kind = self._kinds[1].get(name) if isinstance(name, str) else None
        if kind is None:
            self._check_names([name])
        return self._kinds[1][name]

    def _check_names(self, names: object) -> None:
        inputs = frozenset(self.plan.inputs)
        for n in names:  # type: ignore[attr-defined]
            if not (isinstance(n, str) and n in inputs):
                element = next((e for e in self.plan.elements if e.name == n), None)
                if element is not None:
                    raise InputError(
                        f"driver {n!r} is {element.mode}, not an input: its length "
                        + ("is fixed" if element.mode == "locked" else "follows the mechanism")
                        + f' (set mode = "driven" in the model to drive it); the inputs of '
                        f"{self.name!r} are {', '.join(self.plan.inputs) or 'none'}"
                    )
                raise InputError(
                    f"unknown driver {n!r} for {self.name!r}"
                    f"{did_you_mean(n, self.plan.inputs)}: its inputs are "
                    f"{', '.join(self.plan.inputs) or 'none'}"
                )

    @property
    def parameters(self) -> dict[str, float]:
        """Every dimension of the model by name, at its nominal SI value: ``P.x``, ``P.y`` of
        each sketch point, each ``[lengths]`` entry by its key (``"A-B"``), and each body's
        ``.mass``, ``.inertia`` and ``.center_of_mass.x``/``.y`` where given. Any of them may
        vary per sample: ``solve(..., params={"A-B": lengths})``."""
        from excavkin.structure.design import parameters

        return parameters(self.model)

    @property
    def design_variables(self) -> dict[str, tuple[float, tuple[float, float] | None, str]]:
        """The model file's named design variables: name → (nominal SI value, bounds or
        None, kind). Each is also a parameter, setting every entry that refers to it."""
        return {v.name: (v.value, v.bounds, v.kind) for v in self.model.design}

    def _params_in_si(self, params: Mapping[str, Any] | None, lazy: bool = False) -> dict[str, Any]:
        """Parameter values in SI, each a scalar or a 1-D array (or, ``lazy``, a column made
        on demand)."""
        from excavkin.structure.design import joint_offsets, parameter_kind, parameters

        out: dict[str, Any] = {}
        known = {**parameters(self.model), **joint_offsets(self.model)}
        for name, value in (params or {}).items():
            if name not in known:
                from excavkin.errors import unknown_name

                raise unknown_name("parameter", name, list(known))
            if lazy and isinstance(value, Lazy):
                out[name] = value
                continue
            given = as_si(value, parameter_kind(name, self.model), f"parameter {name!r}")
            kind = np.asarray(given).dtype.kind
            if kind not in "fiu" or isinstance(given, bool):
                raise InputError(
                    f"parameter {name!r}: a value is a number or an array of numbers "
                    f"(with a unit or SI), got {value!r}"[:200]
                )
            arr = np.asarray(given, dtype=np.float64)
            if arr.ndim > 1:
                raise InputError(
                    f"parameter {name!r}: values must be a scalar or a 1-D array, got shape "
                    f"{arr.shape}"
                )
            out[name] = arr
        return out

    def _in_si(self, given: Mapping[str, Any] | None, order: int) -> dict[str, Any]:
        """Driver values (order 0), rates (1) or accelerations (2) as SI floats or arrays: a
        quantity of any pint registry or a string such as ``"30 deg"`` is converted by its
        dimension; a plain number is SI already."""
        out = {}
        for name, value in (given or {}).items():
            kind = _ORDER_KINDS[self.input_kind(name)][order]
            what = ("driver", "rate of driver", "acceleration of driver")[order]
            out[name] = as_si(value, kind, f"{what} {name!r}")
        return out

    @overload
    def solve(
        self,
        values: Mapping[str, ArrayLike] | None = None,
        rates: Mapping[str, ArrayLike] | None = None,
        accels: Mapping[str, ArrayLike] | None = None,
        *,
        time: ArrayLike | None = None,
        strict: bool = False,
        tol: Tolerances | None = None,
        workers: int | None = None,
        progress: Callable[[int, int], None] | None = None,
        chunk: int | None = None,
        continuation: Literal["side", "smooth"] = "side",
        backend: Backend | None = None,
        execution: Execution | None = None,
        compiled: bool | None = None,
        loads: None = None,
        params: Mapping[str, Any] | None = None,
        sensitivities: Sequence[str] | None = None,
        sensitivity_columns: Sequence[str] | None = None,
    ) -> KinematicResult: ...

    @overload
    def solve(
        self,
        values: Mapping[str, ArrayLike] | None = None,
        rates: Mapping[str, ArrayLike] | None = None,
        accels: Mapping[str, ArrayLike] | None = None,
        *,
        time: ArrayLike | None = None,
        strict: bool = False,
        tol: Tolerances | None = None,
        workers: int | None = None,
        progress: Callable[[int, int], None] | None = None,
        chunk: int | None = None,
        continuation: Literal["side", "smooth"] = "side",
        backend: Backend | None = None,
        execution: Execution | None = None,
        compiled: bool | None = None,
        loads: Iterable[Load] | Literal["model"],
        params: Mapping[str, Any] | None = None,
        sensitivities: Sequence[str] | None = None,
        sensitivity_columns: Sequence[str] | None = None,
    ) -> ForceResult: ...

    def solve(
        self,
        values: Mapping[str, ArrayLike] | None = None,
        rates: Mapping[str, ArrayLike] | None = None,
        accels: Mapping[str, ArrayLike] | None = None,
        *,
        time: ArrayLike | None = None,
        strict: bool = False,
        tol: Tolerances | None = None,
        workers: int | None = None,
        progress: Callable[[int, int], None] | None = None,
        chunk: int | None = None,
        continuation: Literal["side", "smooth"] = "side",
        backend: Backend | None = None,
        execution: Execution | None = None,
        compiled: bool | None = None,
        loads: Iterable[Load] | Literal["model"] | None = None,
        params: Mapping[str, Any] | None = None,
        sensitivities: Sequence[str] | None = None,
        sensitivity_columns: Sequence[str] | None = None,
    ) -> KinematicResult | ForceResult:
        """Positions, velocities and accelerations for a batch of driver inputs.

        What a sample's values depend on beyond its own inputs — the precision check's
        scales, the change points between neighbouring samples, a Newton group's continuation
        — is defined over blocks of 65 536 samples (``docs/streaming.md``), so that
        `solve_stream` gives the same numbers part by part.

        Parameters
        ----------
        values : mapping of str to array_like, shape (n,) or scalar
            Driver values in SI (rad, m). A driver not given is held at its sketch value.
        rates, accels : mapping of str to array_like, optional
            First and second time derivatives of the driver values. Defaults: acceleration 0;
            rate 0 for a driver held at a scalar; for a driver given as an array, rate 1 —
            which makes the velocities the first-order transfer functions d(·)/dq and the
            accelerations the second-order ones (``result.unit_rates`` names these drivers) —
            except with ``loads``, where it is 0: forces without given rates are static.
        time : array_like, shape (n,), optional
            Sample times; adds a ``t`` column.
        strict : bool
            Raise [`SolveFailure`][excavkin.errors.SolveFailure] if any sample fails (the default
            marks
            the samples in ``result.status`` and leaves their values NaN).
        tol : Tolerances, optional
        workers : int, optional
            Threads for large batches (default: all cores; 1 for a single thread).
        progress : callable, optional
            ``progress(done, total)`` after each solved chunk of samples (thread-safe: the calls
            are serialised and ``done`` increases); for progress bars.
        chunk : int, optional
            Samples per chunk (default: a cache-sized 32 768).
        continuation : {"side", "smooth"}
            At a change point between neighbouring samples (a dyad folding flat): keep each
            dyad on its sketch side, or continue the motion onto the other side (the samples
            taken in order, as a path). ``result.change_points`` lists them either way.
        backend : {"auto", "numpy", "numba", "cuda"}, optional
            Where a closed-form plan, its ``sensitivities`` and (with ``loads``) the
            equilibrium run (``docs/design.md``, "Backends"): ``"numba"`` as one compiled
            loop over samples (results equal the NumPy path's to round-off), ``"numpy"`` as
            array operations. Default ``"auto"``: a compiled kernel whenever it is ready
            (compiled before, in this process or cached on disk), at any sample count; NumPy
            otherwise, and for a plan with a Newton group. A kernel not yet compiled is
            compiled unasked only for 20 million samples or more. ``"cuda"`` is not
            available in this version (an error says so).
        execution : Execution, optional
            ``backend``, ``workers``, ``chunk`` and ``progress`` as one object
            ([`Execution`][excavkin.execution.Execution]); a keyword also given replaces
            its field.
        compiled : bool, optional
            Deprecated (a `DeprecationWarning`): ``backend="numba"`` (True) or
            ``backend="numpy"`` (False).
        loads : iterable of PointForce, Torque, Gravity, or "model", optional
            Also solve the kinetostatics (`forces`) with these loads (``"model"``: the
            model's own loads and gravity; an empty list: inertia only), and return a
            ``ForceResult`` instead of the ``KinematicResult``: a shortcut for
            ``mech.forces(mech.solve(...), loads)``, the return type fixed by the typing
            overloads. A swept driver given no rate is then at rest (rate 0): without any
            rates the forces are static.
        params : mapping of str to array_like, optional
            Dimensions per sample: a parameter name of
            [`parameters`][excavkin.structure.design.parameters] → a scalar or an
            array of shape (n,), SI or with units. Each sample is solved with its own geometry
            (the plan and each dyad's sketch side are shared); a held driver keeps its own
            design's sketch value; a design that builds no mechanism is marked "the design's
            dimensions build no mechanism".
        sensitivities : sequence of str, optional
            Parameters to differentiate every column by (exactly, forward mode through the
            plan): ``result.sensitivity("B.x", "A-B")`` then gives dB.x/d(A-B) per sample.
        sensitivity_columns : sequence of str, optional
            Only these kinematic columns' derivatives (default: every column's). The
            compiled tangent loop then computes and stores no others, which is most of its
            cost; asking for another column's derivative is an error. Not with ``loads``
            (the forces' derivatives need every kinematic one).

        Returns
        -------
        KinematicResult
            Without ``loads``.
        ForceResult
            With ``loads``: forces plus the kinematics (``.kinematics``); its ``to_frame()``
            has the kinematic columns followed by the force columns.
        """
        if sensitivity_columns is not None and (loads is not None or not sensitivities):
            raise InputError(
                "sensitivity_columns selects kinematic columns of sensitivities: give it with "
                "sensitivities and without loads (the forces' derivatives need all of them)"
            )
        run = settings(
            execution, backend=backend, compiled=compiled, workers=workers, chunk=chunk,
            progress=progress,
        )  # fmt: skip
        batch = self._batch(
            values, rates, accels, time, params, continuation, lazy=False, forces=loads is not None
        )
        whole = batch.part(0, batch.n)
        result = next(
            iter(
                solve_parts(
                    self.plan,
                    self.assembly,
                    lambda: [whole],
                    total=batch.n,
                    tol=tol or Tolerances(),
                    execution=run,
                    continuation=continuation,
                )  # fmt: skip
            )
        )
        result = self._finish(result, batch, 0, batch.n, sensitivities, run, sensitivity_columns)
        if strict and not result.status.all_ok:
            raise SolveFailure(result.summary(), result)
        if loads is None:
            return result
        given = None if isinstance(loads, str) and loads == "model" else loads
        return self._forces(result, given, run, batch.unrated)

    def solve_stream(
        self,
        values: Mapping[str, Any] | None = None,
        rates: Mapping[str, Any] | None = None,
        accels: Mapping[str, Any] | None = None,
        *,
        time: Any = None,
        tol: Tolerances | None = None,
        workers: int | None = None,
        progress: Callable[[int, int], None] | None = None,
        chunk: int | None = None,
        continuation: Literal["side", "smooth"] = "side",
        backend: Backend | None = None,
        execution: Execution | None = None,
        compiled: bool | None = None,
        loads: Iterable[Load] | Literal["model"] | None = None,
        params: Mapping[str, Any] | None = None,
        sensitivities: Sequence[str] | None = None,
        size: int | None = None,
        columns: Sequence[str] | None = None,
    ) -> Iterator[SolvedPart]:
        """`solve`, part by part: consecutive samples at a time, so that memory is
        bounded by a part whatever the sample count.

        The parts put together are the result `solve` gives for the whole sweep, to the
        bit, status and change points included (``docs/streaming.md``). The inputs are taken
        part by part too: arrays (a ``numpy.memmap`` is read as needed) or columns made on
        demand, such as [`excavkin.sweeps.Linspace`][] and [`excavkin.sweeps.grid`][].

        Parameters
        ----------
        values, rates, accels, time, params
            As for `solve`; every array may also be an [`excavkin.sweeps.Lazy`][]
            column.
        tol, workers, chunk, continuation, backend, execution, compiled, loads, sensitivities
            As for `solve`.
        progress : callable, optional
            ``progress(done, total)`` over the whole sweep, after each solved chunk.
        size : int, optional
            Samples per part at most (default: as many as keep a part's result near
            `PART_BYTES`). A part never spans two blocks of
            `BLOCK` samples unless it holds whole ones.
        columns : sequence of str, optional
            The columns each part's ``to_frame()`` keeps: names or glob patterns (``"B.*"``,
            ``"*.x"``, ``"crank.*"``), in the table's order, ``status`` always. A name or
            pattern that matches no column raises
            [`UnknownNameError`][excavkin.errors.UnknownNameError] when the first part comes.
            Without ``loads`` and ``sensitivities`` only those columns are solved for
            (the compiled kernel writes out only their rows; every status is the full
            solve's, ``docs/streaming.md``) and each part's result is a
            [`SelectedResult`][excavkin.kinematics.selection.SelectedResult] of them.

        Yields
        ------
        SolvedPart
            Each part's first sample and result, in order. ``continuation="smooth"`` goes over
            the inputs several times before the first part comes (``docs/streaming.md``).

        Examples
        --------
        >>> import excavkin
        >>> from excavkin.sweeps import Linspace
        >>> mech = excavkin.load(excavkin.example_path("fourbar"))
        >>> parts = mech.solve_stream({"crank": Linspace(0.0, 6.283, 150_000)}, size=65536)
        >>> [(p.start, len(p.result)) for p in parts]
        [(0, 65536), (65536, 65536), (131072, 18928)]
        """
        from excavkin.kinematics.solve import BLOCK

        run = settings(
            execution, backend=backend, compiled=compiled, workers=workers, chunk=chunk,
            progress=progress,
        )  # fmt: skip
        batch = self._batch(
            values, rates, accels, time, params, continuation, lazy=True, forces=loads is not None
        )
        if isinstance(sensitivities, str):
            sensitivities = [sensitivities]
        if size is None:
            per = 8 * self._columns(loads is not None) * (1 + len(sensitivities or ()))
            size = max(PART_BYTES // per, 1)
            size = size // BLOCK * BLOCK if size >= BLOCK else max(size // 4096 * 4096, 4096)
        if size < 1:
            raise InputError(f"size: a part holds at least one sample, got {size}")
        span = -(-size // BLOCK) * BLOCK  # the kinematics: whole blocks at a time
        n = batch.n

        def parts() -> Iterator[Part]:
            for s in range(0, n, span):
                yield batch.part(s, min(s + span, n))

        asked = None  # the kinematic columns asked: only their rows are written out
        if columns is not None and loads is None and not sensitivities:
            from excavkin.kinematics.selection import asked_names

            asked = asked_names(self.plan, (columns,) if isinstance(columns, str) else columns)
        kinematics = solve_parts(
            self.plan, self.assembly, parts, total=n, tol=tol or Tolerances(), execution=run,
            continuation=continuation, columns=asked,
        )  # fmt: skip
        given = None if loads is None or loads == "model" else list(loads)  # type: ignore[arg-type]
        # the inputs are checked above, at the call; the parts come as they are asked for
        stream = self._stream(kinematics, batch, span, size, sensitivities, loads, given, run)
        if columns is None:
            return stream
        names = (columns,) if isinstance(columns, str) else tuple(columns)
        return _selected(stream, names, asked is not None)

    def _stream(
        self,
        kinematics: Iterator[KinematicResult],
        batch: _Batch,
        span: int,
        size: int,
        sensitivities: Sequence[str] | None,
        loads: object,
        given: list[Load] | None,
        execution: Execution = DEFAULT,
    ) -> Iterator[SolvedPart]:
        """The parts of `solve_stream`: each span's kinematics cut into parts of
        ``size`` samples, with their parameters, sensitivities, time and forces."""
        n = batch.n
        for s, whole in zip(range(0, n, span), kinematics, strict=True):
            for first in range(0, len(whole), size):
                last = min(first + size, len(whole))
                result = self._finish(
                    whole.rows(first, last, s),
                    batch,
                    s + first,
                    s + last,
                    sensitivities,
                    execution,
                )
                out: KinematicResult | ForceResult = result
                if loads is not None:
                    out = self._forces(result, given, execution, batch.unrated)
                yield SolvedPart(s + first, out, n)

    def _finish(
        self,
        result: KinematicResult,
        batch: _Batch,
        start: int,
        stop: int,
        sensitivities: Sequence[str] | None,
        execution: Execution = DEFAULT,
        columns: Sequence[str] | None = None,
    ) -> KinematicResult:
        """A kinematic result of samples ``start`` … ``stop − 1`` with its design parameters,
        sensitivities (on ``execution``'s backend) and time."""
        given = {k: part_of(v, start, stop) for k, v in batch.params.items()}
        if given:
            result = dataclasses.replace(result, parameters=given)
        if batch.unrated and not batch.forces:
            result = dataclasses.replace(result, unit_rates=batch.unrated)
        if isinstance(sensitivities, str):  # one name, not its letters
            sensitivities = [sensitivities]
        if sensitivities:
            from excavkin.kinematics.sensitivity import solve_tangents

            tangents = solve_tangents(result, list(sensitivities), given, execution, columns)
            kept = None if columns is None else frozenset(columns)
            result = dataclasses.replace(result, tangents=tangents, tangent_columns=kept)
        if batch.time is not None:
            t = np.asarray(part_of(batch.time, start, stop), dtype=np.float64)
            result = result.with_time(np.broadcast_to(t, (stop - start,)).reshape(stop - start))
        return result

    def _columns(self, forces: bool) -> int:
        """About how many columns a result's table has (forces roughly double them)."""
        plan = self.plan
        kin = 6 * len(plan.points) + 3 * len(plan.bodies) + 3 * len(plan.inputs)
        kin += 6 * len(plan.elements) + len(plan.transmissions) + 1
        return 2 * kin if forces else kin

    def _batch(
        self,
        values: Mapping[str, Any] | None,
        rates: Mapping[str, Any] | None,
        accels: Mapping[str, Any] | None,
        time: Any,
        params: Mapping[str, Any] | None,
        continuation: str,
        lazy: bool,
        forces: bool = False,
    ) -> _Batch:
        """The inputs checked and in SI, to be made part by part (``lazy``: columns made on
        demand stay so; otherwise every input is an array)."""
        self._check_names([*(values or {}), *(rates or {}), *(accels or {})])

        def column(value: Any, what: str) -> Any:
            if lazy and isinstance(value, Lazy):
                return value
            arr = np.asarray(value, dtype=np.float64)
            if arr.ndim > 1:
                raise InputError(f"{what}, got shape {arr.shape}")
            return arr

        arrays = {
            k: column(v, f"driver {k!r}: values must be a scalar or a 1-D array")
            for k, v in self._in_si(values, 0).items()
        }
        orders = [
            {
                k: column(v, f"driver {k!r}: rates and accelerations must be scalars or 1-D arrays")
                for k, v in self._in_si(src, order).items()
            }
            for order, src in ((1, rates), (2, accels))
        ]
        sizes = {k: len(v) for k, v in arrays.items() if v.ndim == 1}
        for src in orders:
            sizes.update({k + " (rate/accel)": len(v) for k, v in src.items() if v.ndim == 1})
        if time is not None:
            time = as_si(time, "time", "time")
            time = time if lazy and isinstance(time, Lazy) else np.asarray(time)
            sizes["time"] = time.size
        given = {
            k: v if lazy and isinstance(v, Lazy) else np.asarray(v)
            for k, v in self._params_in_si(params, lazy).items()
        }
        sizes.update({f"parameter {k}": len(v) for k, v in given.items() if v.ndim == 1})
        distinct = set(sizes.values())
        if len(distinct) > 1:
            listing = ", ".join(f"{k}: {v}" for k, v in sizes.items())
            raise InputError(f"input arrays have different lengths ({listing})")
        n = distinct.pop() if distinct else 1
        return _Batch(self, n, arrays, orders[0], orders[1], time, given, continuation, forces)

    @property
    def loads(self) -> tuple[Load, ...]:
        """The model's own loads: its ``[loads]`` and its gravity, if enabled."""
        from excavkin.kinetostatics import model_loads

        return model_loads(self.model)

    @property
    def statics(self) -> StaticsSystem:
        """The compiled equilibrium system (built on first use).

        Raises
        ------
        StaticallyIndeterminateError
            The model has redundant joints; the message names them.
        """
        if self._statics is None:
            from excavkin.kinetostatics import compile_statics

            self._statics = compile_statics(self.model, plan=self.plan)
        return self._statics

    def forces(
        self,
        result: KinematicResult,
        loads: Iterable[Load] | None = None,
        *,
        backend: Backend | None = None,
        execution: Execution | None = None,
        compiled: bool | None = None,
    ) -> ForceResult:
        """Joint forces, cylinder forces and driver torques for a kinematic result.

        d'Alembert inertia (from the result's accelerations) plus ``loads``, in equilibrium
        with the pin forces and the drivers' efforts (``docs/kinetostatics.md``).

        Forces without given rates are static: a driver the result swept without a rate
        (``result.unit_rates``, whose velocities are transfer functions) is taken at rest,
        rate 0, its acceleration as given. When no driver then moves the forces are those of
        the poses at rest; otherwise the motion is solved again with those rates 0. The
        force result's ``kinematics`` is the motion the forces belong to, and its
        ``motion_note`` says which it is.

        Parameters
        ----------
        result : KinematicResult
            From `solve` on this mechanism.
        loads : iterable of PointForce, Torque, Gravity, optional
            Default: the model's own ([`loads`][excavkin.loads]). Given, they replace the model's;
            pass
            ``[*mech.loads, extra]`` to add to them. Values may carry units: a pint quantity
            (of any registry) or a string such as ``"5 kN"`` or ``("5 kN", "-2 kN")`` for a
            force, ``"300 N*m"`` for a torque, ``"9.81 m/s^2"`` for gravity; a wrong dimension
            is a [`UnitError`][excavkin.errors.UnitError] naming the load.
        backend : {"auto", "numpy", "numba", "cuda"}, optional
            Solve the equilibrium as one compiled loop over samples (``"numba"``; equal to the
            NumPy path's to round-off) or in NumPy; ``"auto"`` (default) as for `solve`.
        execution : Execution, optional
            The backend and threads as one object
            ([`Execution`][excavkin.execution.Execution]); ``backend`` given replaces its
            own.
        compiled : bool, optional
            Deprecated (a `DeprecationWarning`): ``backend="numba"`` (True) or
            ``backend="numpy"`` (False).

        Returns
        -------
        ForceResult
        """
        run = settings(execution, backend=backend, compiled=compiled)
        if result.plan.model is not self.plan.model:  # (a family of designs has its own plan)
            raise InputError("the kinematic result belongs to another mechanism")
        rest = result.unit_rates
        if rest:
            result = self._at_rest(result, rest, run)
        return self._forces(result, loads, run, rest)

    def _at_rest(
        self, result: KinematicResult, rest: tuple[str, ...], execution: Execution = DEFAULT
    ) -> KinematicResult:
        """``result``'s poses with the drivers ``rest`` at rate 0 (their accelerations and the
        other drivers' rates as they were)."""
        inputs = self.plan.inputs
        moving = [i for i, name in enumerate(inputs) if name not in rest]
        if not np.any(result.input_rates[:, moving]) and not np.any(result.input_accels):
            return result.at_rest()  # nothing moves: the poses at rest, no solve needed
        rates = result.input_rates.copy()
        rates[:, [inputs.index(name) for name in rest]] = 0.0
        smooth = any(c.continued == "smooth" for c in result.change_points)
        return self.solve(
            {name: result.inputs[:, i] for i, name in enumerate(inputs)},
            {name: rates[:, i] for i, name in enumerate(inputs)},
            {name: result.input_accels[:, i] for i, name in enumerate(inputs)},
            time=result.time,
            params=result.parameters,
            continuation="smooth" if smooth else "side",
            execution=dataclasses.replace(execution, progress=None),  # (its bar is done)
            sensitivities=list(result.tangents) if result.tangents else None,
            sensitivity_columns=None
            if result.tangent_columns is None
            else [*result.tangent_columns],
        )

    def _forces(
        self,
        result: KinematicResult,
        loads: Iterable[Load] | None,
        execution: Execution,
        rest: tuple[str, ...],
    ) -> ForceResult:
        """`forces` of a result already at rest in the drivers ``rest`` (those swept
        without a rate, named in the result)."""
        from excavkin.kinetostatics import solve_forces

        if result.plan.model is not self.plan.model:  # (a family of designs has its own plan)
            raise InputError("the kinematic result belongs to another mechanism")
        given = self.loads if loads is None else [_load_in_si(load) for load in loads]
        if result.parameters:
            given = _loads_of_designs(given, result.parameters, len(result))
        forces = solve_forces(result, given, system=self.statics, execution=execution)
        if rest:
            forces = dataclasses.replace(forces, at_rest=rest)
        if result.tangents:
            from excavkin.kinetostatics.sensitivity import force_tangents

            tangents = force_tangents(forces, list(result.tangents))
            forces = dataclasses.replace(forces, tangents=tangents)
        return forces

    def describe(self) -> str:
        """Bodies, joints, drivers, mobility and the solve plan, as text.

        Returns
        -------
        str
            The lines ``excavkin check`` prints.
        """
        m = self.model
        lines = [f"mechanism {m.name!r}" + (f" ({m.source})" if m.source else "")]
        lines.append(f"  points  : {len(m.points)}")
        lines.append("  bodies  :")
        for b in m.bodies:
            extra = " (ground)" if b.ground else ""
            if b.mass is not None:
                extra += f", m = {b.mass:g} kg"
                if b.inertia is not None:
                    extra += f", J = {b.inertia:g} kg·m²"
            lines.append(f"    {b.name:<12} {', '.join(b.points)}{extra}")
        joints = []
        bodies_at = m.bodies_at()
        for p in m.points:
            owners = [b.name for b in bodies_at.get(p, ())]
            if len(owners) > 1:
                joints.append(f"{p} ({' + '.join(owners)})")
        lines.append(f"  joints  : {', '.join(joints) or 'none'}")
        for d in m.rotary:
            lines.append(
                f"  driver  : {d.name} rotary — body {d.body} about {d.pivot} from {d.reference}"
            )
        for ld in m.linear:
            lines.append(
                f"  driver  : {ld.name} linear {ld.mode} — {ld.between[0]}–{ld.between[1]}"
            )
        for s in m.sliders:
            lines.append(f"  slider  : {s.name} — {s.point} on {s.along[0]}→{s.along[1]}")
        lines += describe_meshes(m)
        lines += [f"  rope    : {rope_line(r)}" for r in m.ropes]
        mob = self.plan.mobility
        lines.append(f"  mobility: {mob.describe()}; inputs: {', '.join(self.inputs) or 'none'}")
        params = self.parameters
        lengths = [k for k in params if "-" in k]
        named = ", ".join(lengths) + (", " if lengths else "")
        lines.append(
            f"  params  : {len(params)} ({named}P.x, P.y of each point, and each body's mass, "
            "inertia, center_of_mass.x/.y where given)"
        )
        lines.append("  plan    :")
        lines += ["    " + line for line in self.plan.describe().splitlines()]
        return "\n".join(lines)

    def __repr__(self) -> str:
        return (
            f"Mechanism({self.name!r}, {len(self.plan.points)} points, "
            f"{len(self.plan.bodies)} bodies, inputs={list(self.inputs)}, "
            f"{len(self.plan.steps)} solve steps)"
        )

    def _repr_html_(self) -> str:
        """The mechanism at its sketch as a small drawing, with its description and plan."""
        from excavkin.outputs.sketch import mechanism_html

        return mechanism_html(self)

    def sketch_svg(self, size: int = 240) -> str:
        """The assembled sketch as an SVG drawing (`excavkin.outputs.sketch.sketch_svg`).

        Parameters
        ----------
        size : int
            Width and height of the drawing, pixels.

        Returns
        -------
        str
            An ``<svg>`` element.
        """
        from excavkin.outputs.sketch import sketch_svg

        return sketch_svg(self, size)
