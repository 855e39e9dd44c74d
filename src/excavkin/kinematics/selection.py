"""A solve of some columns: the compiled kernel's rows that hold them, and a result that gives
those columns alone.

``solve_stream(..., columns=...)`` asks for some columns of the table. A row's status never
depends on the columns asked: every sample is solved whole, in registers, and checked as a
solve of every column checks it (the finiteness of every value, the precision check near a
dead position, the change points). What a selection saves is the rest: the compiled kernel
(`excavkin.kinematics.compiled.run_designs`, the study's kernel, one design or one column of
constants a sample) writes out only the rows of the columns asked and of those the checks
read back (`kept_rows`), so that the other rows of the result's arrays are never written,
and their pages never touched. Such a result holds no values in those rows: it is handed out
as a `SelectedResult`, which gives the columns asked and refuses the others by name.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass
from fnmatch import fnmatchcase
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError, UnknownNameError, unknown_name
from excavkin.kinematics.change_points import ChangePoint
from excavkin.kinematics.columns import Column, select_columns
from excavkin.kinematics.result import Derived, KinematicResult, Status
from excavkin.structure.plan import SolvePlan

if TYPE_CHECKING:
    import pandas as pd


def _marked(
    plan: SolvePlan,
    rows: dict[tuple[str, tuple[int, ...]], int],
    rest: list[tuple[str, tuple[int, ...]]] | None = None,
) -> KinematicResult:
    """A one-sample result whose every row written by the kernel holds 1000 + its scratch
    row's number, the inputs negative numbers: its columns read back say which row holds
    each. ``rest``: each row that no kernel writes holds −10⁶ − its place in ``rest``,
    appended (else 0)."""
    n_pts = len(plan.points)
    arrays = {
        "x": np.zeros((n_pts, 2, 1)), "v": np.zeros((n_pts, 2, 1)),
        "a": np.zeros((n_pts, 2, 1)), "trans": np.zeros((len(plan.transmissions), 1)),
    }  # fmt: skip
    derived = Derived(np.zeros((3, len(plan.bodies), 1)), np.zeros((6, len(plan.elements), 1)))
    arrays |= {"body": derived.body, "element": derived.element}
    for (name, lead), row in rows.items():
        arrays[name][(*lead, 0)] = 1000.0 + row
    if rest is not None:
        for name, arr in arrays.items():
            for lead in np.ndindex(*arr.shape[:-1]):
                if (name, lead) not in rows:
                    arr[(*lead, 0)] = -1e6 - len(rest)
                    rest.append((name, lead))
    n_in = len(plan.inputs)
    marks = -1.0 - np.arange(3 * n_in, dtype=np.float64).reshape(3, n_in, 1)
    status = Status(np.zeros(1, dtype=np.int8), np.full(1, -1, dtype=np.int16), plan)
    return KinematicResult.build(
        plan, arrays["x"], arrays["v"], arrays["a"], marks[0], marks[1], marks[2],
        arrays["trans"], derived, status,
    )  # fmt: skip


def kinematic_names(plan: SolvePlan) -> list[str]:
    """The names of a kinematic result's columns of ``plan``, in table order (no time, no
    design parameters, no ``status``).

    Parameters
    ----------
    plan : SolvePlan

    Returns
    -------
    list of str
    """
    return [c.name for c in _marked(plan, {}).columns]


def asked_names(plan: SolvePlan, columns: Sequence[str]) -> frozenset[str]:
    """The kinematic columns of ``plan`` that names or glob patterns ask for (as
    `excavkin.kinematics.columns.select_columns` reads them). A name of no kinematic column
    (a design parameter's, the time's, or none: the table's check names that one) asks for
    none here.

    Parameters
    ----------
    plan : SolvePlan
    columns : sequence of str

    Returns
    -------
    frozenset of str
    """
    names = kinematic_names(plan)
    given = [columns] if isinstance(columns, str) else list(columns)
    out: set[str] = set()
    for pattern in given:
        pattern = str(pattern).strip()
        out.update(n for n in names if n == pattern or fnmatchcase(n, pattern))
    return frozenset(out)


def kept_rows(
    plan: SolvePlan,
    rows: dict[tuple[str, tuple[int, ...]], int],
    n_rows: int,
    names: Collection[str],
    change_points: bool = True,
) -> NDArray[np.int8]:
    """The kernel's scratch rows to write out (1) for the columns ``names``: each column's
    own row (a column that is its input's, such as a driven length, or zero throughout, such
    as a fixed point's velocity, needs none; one made of several rows keeps every row), and
    with ``change_points`` every transmission angle: the change-point search reads them to
    find the dyads that come near flat (a block where one whose positions and velocities
    were not kept does is solved again whole,
    `excavkin.kinematics.solve.solve_selected`). The precision check reads none: the
    kernel keeps its scales (`tops`) and the samples it checks are solved again whole.

    Parameters
    ----------
    plan : SolvePlan
    rows : dict of (str, tuple of int) to int
        The kernel's written rows (`excavkin.kinematics.vectorise.written_rows`).
    n_rows : int
        The kernel's scratch rows.
    names : collection of str
        Kinematic columns (`asked_names`).
    change_points : bool
        Whether the change points are searched.

    Returns
    -------
    ndarray of int8, shape (n_rows,)
        (One array per plan, columns and kernel, kept: not to be changed.)
    """
    key = ("kept", id(plan), frozenset(names), change_points, id(rows))
    made = _made.get(key)
    if made is None or made[0] is not plan or made[1] is not rows:
        made = (plan, rows, _kept_rows(plan, rows, n_rows, names, change_points))
        _keep(key, made)
    out: NDArray[np.int8] = made[2]
    return out


#: the last rows found (a stream asks again for each of its parts), by what they are of:
#: the plan and kernel rows themselves kept, so that an id reused is not taken for them
_made: dict[tuple[object, ...], tuple[SolvePlan, object, Any]] = {}


def _keep(key: tuple[object, ...], made: tuple[SolvePlan, object, Any]) -> None:
    if len(_made) >= 32:
        _made.clear()
    _made[key] = made


def _kept_rows(
    plan: SolvePlan,
    rows: dict[tuple[str, tuple[int, ...]], int],
    n_rows: int,
    names: Collection[str],
    change_points: bool,
) -> NDArray[np.int8]:
    """`kept_rows`, made."""
    keep = np.zeros(n_rows, dtype=np.int8)
    marked = _marked(plan, rows)
    for value in marked.columns_named(list(names)).values():
        mark = float(value[0])
        if mark >= 1000.0 and mark - 1000.0 < n_rows and mark.is_integer():
            keep[int(mark) - 1000] = 1
        elif not (mark <= 0.0 and mark.is_integer()):  # (0: at rest, never written)
            keep[:] = 1  # (not a row of its own: every row, to be sure)
    if change_points:
        for i in range(len(plan.transmissions)):
            if ("trans", (i,)) in rows:
                keep[rows[("trans", (i,))]] = 1
    return keep


def resting_rows(
    plan: SolvePlan, rows: dict[tuple[str, tuple[int, ...]], int], names: Collection[str]
) -> list[tuple[str, tuple[int, ...]]]:
    """The rows that no kernel writes (a fixed point's velocity and acceleration, the
    ground's angle: zero throughout) that the columns ``names`` read: those a solve of
    some columns sets to zero, and no others.

    Parameters
    ----------
    plan : SolvePlan
    rows : dict of (str, tuple of int) to int
        The kernel's written rows (`excavkin.kinematics.vectorise.written_rows`).
    names : collection of str
        Kinematic columns (`asked_names`).

    Returns
    -------
    list of (str, tuple of int)
        Each row's array and its indices before the sample's. (One list per plan, columns
        and kernel, kept: not to be changed.)
    """
    key = ("resting", id(plan), frozenset(names), id(rows))
    made = _made.get(key)
    if made is None or made[0] is not plan or made[1] is not rows:
        rest: list[tuple[str, tuple[int, ...]]] = []
        marked = _marked(plan, rows, rest)
        found = []
        for value in marked.columns_named(list(names)).values():
            mark = float(value[0])
            if mark <= -1e6:
                found.append(rest[int(-1e6 - mark)])
        made = (plan, rows, found)
        _keep(key, made)
    out: list[tuple[str, tuple[int, ...]]] = made[2]
    return out


@dataclass(frozen=True, slots=True, repr=False)
class SelectedResult:
    """A kinematic result solved for some of its columns (``solve_stream(..., columns=...)``):
    it gives those columns, by name or as a table, and each sample's status — the status of
    the sample solved whole, whatever the columns asked. Its other values were not kept: the
    arrays of a `KinematicResult` (``positions``, ``velocities`` …) and any column not asked
    raise an error naming it, never a number. Made by `of`.

    Parameters
    ----------
    _whole : KinematicResult
        The result solved: only the rows of the columns asked hold values.
    names : tuple of str
        The columns asked, in table order (``status`` aside).
    """

    _whole: KinematicResult
    names: tuple[str, ...]

    @classmethod
    def of(cls, result: KinematicResult, columns: Sequence[str]) -> SelectedResult:
        """``result`` restricted to the columns that names or glob patterns ask for.

        Parameters
        ----------
        result : KinematicResult
            A result whose columns ``columns`` asks for hold their values (its other rows
            may hold none).
        columns : sequence of str
            Names or glob patterns (`excavkin.kinematics.columns.select_columns`).

        Returns
        -------
        SelectedResult

        Raises
        ------
        UnknownNameError
            A name or pattern that matches no column.
        """
        names = [c.name for c in result.columns]
        kept = select_columns([*names, "status"], columns)
        return cls(result, tuple(n for n in kept if n != "status"))

    def __len__(self) -> int:
        return len(self._whole)

    def __repr__(self) -> str:
        return (
            f"<SelectedResult of {self._whole.plan.model.name!r}: {len(self)} samples, "
            f"columns {', '.join(self.names)}>"
        )

    def __getattr__(self, name: str) -> Any:
        if name in _WHOLE_ONLY:
            raise AttributeError(
                f"{name}: this result was solved for the columns {', '.join(self.names)} "
                "only (columns=...), its other values were not kept: read those by name "
                "(column(), to_frame()), or solve without columns= for the whole state"
            )
        raise AttributeError(f"'SelectedResult' object has no attribute {name!r}")

    @property
    def plan(self) -> SolvePlan:
        """The plan solved."""
        return self._whole.plan

    @property
    def status(self) -> Status:
        """Each sample's status: the whole sample's, whatever the columns asked."""
        return self._whole.status

    @property
    def change_points(self) -> tuple[ChangePoint, ...]:
        """The change points found (`KinematicResult`'s)."""
        return self._whole.change_points

    @property
    def error_estimate(self) -> F | None:
        """Each sample's estimated error (`KinematicResult`'s)."""
        return self._whole.error_estimate

    @property
    def time(self) -> F | None:
        """The samples' time, where solved in time."""
        return self._whole.time

    @property
    def inputs(self) -> F:
        """The drivers' values as given, shape (n, n_inputs)."""
        return self._whole.inputs

    @property
    def input_rates(self) -> F:
        """Their rates, shape (n, n_inputs)."""
        return self._whole.input_rates

    @property
    def input_accels(self) -> F:
        """Their accelerations, shape (n, n_inputs)."""
        return self._whole.input_accels

    @property
    def parameters(self) -> dict[str, F] | None:
        """The design parameters given per sample, if any."""
        return self._whole.parameters

    @property
    def unit_rates(self) -> tuple[str, ...]:
        """The drivers swept without a rate (rate 1)."""
        return self._whole.unit_rates

    @property
    def motion_note(self) -> str:
        """`KinematicResult.motion_note`."""
        return self._whole.motion_note

    @property
    def columns(self) -> tuple[Column, ...]:
        """What each column asked holds, in table order."""
        return tuple(c for c in self._whole.columns if c.name in self.names)

    def _refused(self, name: str) -> InputError:
        if name in {c.name for c in self._whole.columns}:
            return InputError(
                f"column {name!r} was not solved: this result holds the columns asked of it "
                f"({', '.join(self.names)}); ask for it in columns=, or solve without columns="
            )
        return unknown_name("column", name, list(self.names))

    def column(self, name: str) -> F:
        """One column asked, by name.

        Parameters
        ----------
        name : str

        Returns
        -------
        ndarray, shape (n,)

        Raises
        ------
        InputError
            A column not asked (`UnknownNameError`: no column of that name).
        """
        if name not in self.names:
            raise self._refused(name)
        return self._whole.column(name)

    def columns_named(self, names: Collection[str]) -> dict[str, F]:
        """Several columns asked, by name.

        Parameters
        ----------
        names : collection of str

        Returns
        -------
        dict of str to ndarray, shape (n,)

        Raises
        ------
        InputError
            A column not asked (`UnknownNameError`: no column of that name).
        """
        for name in names:
            if name not in self.names:
                raise self._refused(name)
        return self._whole.columns_named(names)

    def to_frame(self, columns: Sequence[str] | None = None) -> pd.DataFrame:
        """The table of the columns asked (`KinematicResult.to_frame`), ``status`` always.

        Parameters
        ----------
        columns : sequence of str, optional
            Only these of them (names or glob patterns, matched among the columns asked).

        Returns
        -------
        pandas.DataFrame

        Raises
        ------
        InputError
            A name of a column not asked (`UnknownNameError`: one that matches no column).
        """
        if columns is None:
            return self._whole.to_frame(columns=list(self.names))
        try:
            kept = select_columns([*self.names, "status"], columns)
        except UnknownNameError:
            for name in [columns] if isinstance(columns, str) else list(columns):
                if name not in self.names and name != "status":
                    raise self._refused(str(name)) from None
            raise
        return self._whole.to_frame(columns=[n for n in kept if n != "status"])

    def rows(self, start: int, stop: int, origin: int = 0) -> SelectedResult:
        """Samples ``start`` … ``stop − 1`` (`KinematicResult.rows`).

        Parameters
        ----------
        start, stop : int
        origin : int, default 0

        Returns
        -------
        SelectedResult
        """
        return SelectedResult(self._whole.rows(start, stop, origin), self.names)

    def describe_sample(self, i: int) -> str:
        """`KinematicResult.describe_sample`.

        Parameters
        ----------
        i : int

        Returns
        -------
        str
        """
        return self._whole.describe_sample(i)

    def summary(self, limit: int = 10) -> str:
        """`KinematicResult.summary`.

        Parameters
        ----------
        limit : int, default 10

        Returns
        -------
        str
        """
        return self._whole.summary(limit)


#: what a whole result has and a selected one refuses (its arrays, and what reads them)
_WHOLE_ONLY = frozenset(
    {
        "positions", "velocities", "accelerations", "body_angle", "body_omega",
        "body_epsilon", "element_length", "element_rate", "element_accel", "element_angle",
        "element_omega", "element_epsilon", "transmission", "point", "body", "driver",
        "tangents", "sensitivity", "at_rest", "with_time", "plot",
    }
)  # fmt: skip
