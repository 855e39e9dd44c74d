"""Kinematic results: arrays with the batch axis first, a per-sample status, a tidy table."""

from __future__ import annotations

import html
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import unknown_name
from excavkin.kinematics import summary
from excavkin.kinematics.change_points import ChangePoint
from excavkin.kinematics.columns import (
    QUANTITIES,
    TIME,
    WINCH_LENGTH,
    Column,
    column,
    derivative_column,
    design_column,
    driver_columns,
    select_columns,
    table_attrs,
)
from excavkin.kinematics.kernels import Code
from excavkin.step_kinds import CAngle, CDist, CFrame, CLine, CRope, NewtonGroup, kind_of
from excavkin.step_kinds.newton_solve import out_of_reach
from excavkin.step_kinds.state import Chunk
from excavkin.structure.design import parameter_kind, take_step
from excavkin.structure.plan import SolvePlan

if TYPE_CHECKING:
    import pandas as pd

_REASON = {
    Code.NO_CLOSURE: "cannot close",
    Code.SINGULAR: "dead position",
    Code.NO_CONVERGENCE: "Newton did not converge",
    Code.BRANCH_CHANGED: "assembly branch changed",
    Code.BAD_INPUT: "input is NaN or infinite",
    Code.BAD_LENGTH: "a driven length is zero or negative",
    Code.NOT_FINITE: "a result overflows (inputs or rates too large for double precision)",
    Code.UNDETERMINED: "undetermined (its two partners coincide)",
    Code.IMPRECISE: "rates lose precision near a dead position",
    Code.BAD_DESIGN: "the design's dimensions build no mechanism",
    Code.OUT_OF_REACH: "out of reach",
    Code.ROPE_OFF_SHEAVE: "a rope leaves a sheave (its wrap would be negative)",
}


@dataclass(frozen=True, slots=True, repr=False)
class Status:
    """Per-sample outcome.

    Attributes
    ----------
    code : ndarray of int8, shape (n,)
        0 where the sample solved; otherwise a `Code`.
    step : ndarray of int16, shape (n,)
        Index of the plan step that failed first, −1 where none did.
    plan : SolvePlan
        The plan solved, whose steps ``step`` indexes.
    unmet : ndarray of int16, shape (n,), optional
        Where a pose is out of reach (`Code.OUT_OF_REACH`), the index of the constraint that
        cannot be met among its Newton group's constraints; −1 elsewhere. None: not looked at.
    miss : ndarray, shape (n,), optional
        By how much that constraint is missed with every other one met, in its own terms
        (`excavkin.step_kinds.newton_solve.out_of_reach`): a distance achieved less the
        required (m), a point's distance from its body's frame or its slider's line (m), a
        driver's angle error (rad); NaN elsewhere.
    """

    code: np.ndarray
    step: np.ndarray
    plan: SolvePlan
    unmet: np.ndarray | None = None
    miss: np.ndarray | None = None

    @property
    def ok(self) -> np.ndarray:
        """Boolean mask of solved samples, shape (n,)."""
        return np.asarray(self.code == 0)

    @property
    def solved(self) -> np.ndarray:
        """Samples that have values: ``ok``, or solved with rates that lose precision near a
        dead position (the values are the best available; the status says how far to trust
        them), shape (n,)."""
        return np.asarray((self.code == 0) | (self.code == Code.IMPRECISE))

    @property
    def all_ok(self) -> bool:
        """Whether every sample solved."""
        return bool(np.all(self.code == 0))

    def where(self, k: int) -> str:
        """The step a failure happened at, in words.

        Parameters
        ----------
        k : int
            Index of a step of `plan`, as in `step`.

        Returns
        -------
        str
            ``"dyad C (from B and D)"``, ``"slider 's' (P on A→B)"``, ``"group P, Q"`` or
            ``"step k+1"``.
        """
        st = self.plan.steps[k]
        return kind_of(st).label(st, self.plan.points, k)

    def constraint(self, k: int, j: int) -> str:
        """Constraint ``j`` of the Newton group at step ``k``, in words.

        Parameters
        ----------
        k : int
            Index of a Newton group among the steps of `plan`.
        j : int
            Index of one of its constraints.

        Returns
        -------
        str
            ``"A–B (body 'coupler')"``, ``"tip–bail (driven 'hoist')"``, ``"C on body
            'stick'"``, ``"P on slider 's' (A→B)"`` or ``"driver 'crank'"``.
        """
        st = self.plan.steps[k]
        assert isinstance(st, NewtonGroup)
        con, pts = st.constraints[j], self.plan.points
        if isinstance(con, CDist):
            what = con.dist.label if con.dist.kind == "fixed" else f"driven {con.dist.label!r}"
            return f"{pts[con.p]}–{pts[con.q]} ({what})"
        if isinstance(con, CFrame):
            return f"{pts[con.p]} on body {con.body!r}"
        if isinstance(con, CLine):
            line = (pts[con.p], (pts[con.l1], pts[con.l2]))
            names = [s.name for s in self.plan.model.sliders if (s.point, s.along) == line]
            slider = f"slider {names[0]!r}" if names else "the line"
            return f"{pts[con.p]} on {slider} ({pts[con.l1]}→{pts[con.l2]})"
        if isinstance(con, CRope):
            over = "–".join(pts[p] for p in con.points)
            return (
                f"rope {con.name!r} {over} ({'driven' if con.dist.kind == 'input' else 'locked'})"
            )
        return f"driver {self.plan.inputs[con.input]!r}"

    def _unmet(self, i: int) -> int:
        return -1 if self.unmet is None else int(self.unmet[i])

    def label(self, i: int) -> str:
        """Why sample ``i`` failed, without its own amounts (the text the samples that failed
        alike share), or ``"ok"``.

        Parameters
        ----------
        i : int
            The sample's index.

        Returns
        -------
        str
            The reason, and the step where one failed (``"cannot close at dyad C (from B and
            D)"``, ``"out of reach at group A, B: O4–B (body 'rocker') cannot be met"``).
        """
        code = Code(int(self.code[i]))
        if code == Code.OK:
            return "ok"
        if code in (Code.BAD_INPUT, Code.BAD_LENGTH, Code.NOT_FINITE, Code.BAD_DESIGN):
            return _REASON[code]
        k = int(self.step[i])
        text = f"{_REASON[code]} at {self.where(k)}"
        if code == Code.OUT_OF_REACH and self._unmet(i) >= 0:
            text += f": {self.constraint(k, self._unmet(i))} cannot be met"
        return text

    def shortfall(self, i: int, unit: str = "m") -> str | None:
        """By how much sample ``i``'s pose is out of reach, in words, or None.

        Parameters
        ----------
        i : int
            The sample's index.
        unit : {"m", "mm"}
            The unit of a length.

        Returns
        -------
        str or None
            ``"0.231 m short"`` (a distance the points cannot stretch to), ``"0.231 m too
            long"`` (one they cannot come down to), ``"0.012 m off"`` (a point off its body's
            frame or its slider's line) or ``"3.2° off"`` (a driver's angle); None where the
            sample is not out of reach.
        """
        j = self._unmet(i)
        if j < 0 or self.miss is None or int(self.code[i]) != Code.OUT_OF_REACH:
            return None
        st = self.plan.steps[int(self.step[i])]
        assert isinstance(st, NewtonGroup)
        con, amount = st.constraints[j], float(self.miss[i])
        if isinstance(con, CAngle):
            return f"{np.degrees(abs(amount)):.3g}° off"
        size = f"{abs(amount) * 1e3:.1f} mm" if unit == "mm" else f"{abs(amount):.4g} m"
        if isinstance(con, CDist | CRope):
            return f"{size} {'short' if amount < 0 else 'too long'}"
        return f"{size} off"

    def message(self, i: int) -> str:
        """Why sample ``i`` failed, or ``"ok"``.

        Parameters
        ----------
        i : int
            The sample's index.

        Returns
        -------
        str
            The reason, and the step where one failed (``"cannot close at dyad C (from B and
            D)"``); for a pose out of reach, the constraint that cannot be met and by how much
            (``"out of reach at group A, B: O4–B (body 'rocker') is 0.01274 m too long"``).
        """
        short = self.shortfall(i)
        if short is None:
            return self.label(i)
        return f"{self.label(i).removesuffix(' cannot be met')} is {short}"

    def labels(self) -> np.ndarray:
        """A short label per sample (``"ok"`` or the reason and place), shape (n,).

        Returns
        -------
        ndarray of object, shape (n,)
            `label` of each sample: its `message` without the amounts of its own.
        """
        codes, labels = self.label_codes()
        return np.asarray(np.array(labels, dtype=object)[codes])

    def label_codes(self) -> tuple[np.ndarray, list[str]]:
        """The labels as codes into the distinct labels (sorted), without a text per sample:
        ``labels()[i] == distinct[codes[i]]``.

        Returns
        -------
        codes : ndarray of int16, shape (n,)
        distinct : list of str
        """
        bad = np.flatnonzero(self.code != 0)
        if not bad.size:
            return np.zeros(self.code.size, dtype=np.int16), ["ok"] if self.code.size else []
        keys = (self.code[bad].astype(np.int64) * 100000 + self.step[bad]) * 100000
        if self.unmet is not None:
            keys += self.unmet[bad].astype(np.int64) + 1
        _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
        texts = [self.label(int(bad[f])) for f in first]
        distinct = sorted({*texts, *(["ok"] if bad.size < self.code.size else [])})
        index = {text: k for k, text in enumerate(distinct)}
        codes = np.full(self.code.size, index.get("ok", 0), dtype=np.int16)
        codes[bad] = np.array([index[t] for t in texts], dtype=np.int16)[inverse.reshape(-1)]
        return codes, distinct

    def categorical(self) -> pd.Categorical[str]:
        """The labels as a ``pandas.Categorical`` (one code per sample, not a text).

        Returns
        -------
        pandas.Categorical
            Categories: the distinct labels, sorted.
        """
        import pandas as pd

        codes, distinct = self.label_codes()
        return pd.Categorical.from_codes(codes, categories=pd.Index(distinct, dtype=str))

    def __repr__(self) -> str:
        counts = ", ".join(f"{lab} {k}" for lab, k in summary.status_counts(self.labels()))
        return f"Status({self.code.size} samples: {counts or 'none'})"

    def _repr_html_(self) -> str:
        rows = [[html.escape(lab), str(k)] for lab, k in summary.status_counts(self.labels())]
        return summary.html_table(rows, ["status", "samples"])

    def summary(self, limit: int = 10, describe: Callable[[int], str] | None = None) -> str:
        """One paragraph listing the failing samples, grouped by reason.

        Parameters
        ----------
        limit : int
            Samples listed per reason.
        describe : callable, optional
            ``describe(i)`` names sample ``i`` by its inputs (``"crank = 132°"``).

        Returns
        -------
        str
            ``"all samples solved"``, or how many failed and, per reason, which (the first
            ``limit``, then a count).
        """
        bad = np.flatnonzero(self.code != 0)
        labels = self.labels()
        groups = []
        for lab in dict.fromkeys(labels[bad]):
            idx = bad[labels[bad] == lab]
            shown = [
                sample_named(
                    int(i), describe(int(i)) if describe else None, self.shortfall(int(i), "mm")
                )
                for i in idx[:limit]
            ]
            groups.append((str(lab), int(idx.size), shown))
        return summary.failures(int(self.code.size), groups, limit)


def sample_named(i: int, inputs: str | None, short: str | None) -> str:
    """A failing sample as a summary lists it: its number, then its inputs and by how much
    it is out of reach, each where known.

    Parameters
    ----------
    i : int
        The sample's number.
    inputs : str or None
        Its inputs in words (``"crank = 132°"``).
    short : str or None
        By how much it is out of reach (`Status.shortfall`).

    Returns
    -------
    str
        ``"12 (crank = 132°; 4.3 mm too long)"``, ``"12 (crank = 132°)"`` or ``"12"``.
    """
    said = [text for text in (inputs, short) if text]
    return f"{i} ({'; '.join(said)})" if said else str(i)


def diagnose(plan: SolvePlan, x: F, q: F, status: Status) -> Status:
    """The status with every sample that a Newton group did not solve looked at again: out of
    reach (which constraint, by how much), or Newton's failure to converge.

    Parameters
    ----------
    plan : SolvePlan
        The plan solved.
    x : ndarray, shape (n_points, 2, n)
        The solved positions (m): those of the points before a failing group are its start.
    q : ndarray, shape (n_inputs, n)
        The inputs.
    status : Status
        The solve's status.

    Returns
    -------
    Status
        With ``unmet`` and ``miss`` (`Status`), and ``Code.OUT_OF_REACH`` for the samples that
        `excavkin.step_kinds.newton_solve.out_of_reach` finds cannot be reached.
    """
    n = status.code.size
    # none looked at yet: read-only views of one value, no memory per sample
    unmet, miss = np.broadcast_to(np.int16(-1), (n,)), np.broadcast_to(np.nan, (n,))
    code = status.code
    sketch = np.asarray(plan.sketch, dtype=np.float64)
    for k, st in enumerate(plan.steps):
        if not isinstance(st, NewtonGroup):
            continue
        idx = np.flatnonzero((code == Code.NO_CONVERGENCE) & (status.step == k))
        if not idx.size:
            continue
        if code is status.code:
            code, unmet, miss = code.copy(), np.full(n, -1, dtype=np.int16), np.full(n, np.nan)
        pts = list(st.points)
        sub = np.take(x, idx, axis=-1)
        # the start: the group's points at the nearest sample that has them, else the sketch
        have = np.flatnonzero(np.isfinite(x[pts]).all(axis=(0, 1)))
        if have.size:
            at = np.clip(np.searchsorted(have, idx), 1, have.size) - 1
            after = np.minimum(at + 1, have.size - 1)
            near = np.where(np.abs(have[after] - idx) < np.abs(have[at] - idx), after, at)
            sub[pts] = x[pts][:, :, have[near]]
        else:
            sub[pts] = sketch[pts][:, :, None]
        out, j, amount = out_of_reach(
            Chunk(
                sub,
                sub,
                sub,
                np.take(q, idx, axis=-1),
                np.zeros((q.shape[0], idx.size)),
                np.zeros((q.shape[0], idx.size)),
                np.empty((0, idx.size)),
                np.zeros(idx.size, dtype=np.int8),
                np.full(idx.size, -1, dtype=np.int16),
                0.0,
                0.0,
            ),
            take_step(st, idx),  # type: ignore[arg-type]
            plan.scale,
        )
        code[idx[out]] = Code.OUT_OF_REACH
        unmet[idx[out]] = j[out]
        miss[idx[out]] = amount[out]
    return Status(code, status.step, status.plan, unmet, miss)


@dataclass(frozen=True, slots=True, repr=False)
class KinematicResult:
    """Positions, velocities and accelerations of a mechanism over n samples (SI).

    Attributes
    ----------
    plan : SolvePlan
        The plan solved: its ``points``, ``bodies``, ``inputs`` and ``elements`` name the
        arrays' columns.
    positions, velocities, accelerations : ndarray, shape (n, n_points, 2)
        Views of the solver's struct-of-arrays storage.
    body_angle, body_omega, body_epsilon : ndarray, shape (n, n_bodies)
        Orientation (first→second point, CCW from +x, in (−π, π]), ω and ε.
    inputs, input_rates, input_accels : ndarray, shape (n, n_inputs)
        The driven inputs (rad or m) and their rates and accelerations.
    element_length, element_rate, element_accel : ndarray, shape (n, n_elements)
        Every linear element (driven, locked or free).
    element_angle, element_omega, element_epsilon : ndarray, shape (n, n_elements)
        Direction of each element from its first point to its second, and its rates.
    transmission : ndarray, shape (n, n_transmissions)
        Transmission angle of each dyad (between its two links, in [0, π]) and each slider
        (between the link and the slide's normal, in [0, π/2]); dead at 0 or π.
    status : Status
        Per-sample outcome.
    time : ndarray, shape (n,), optional
        The time of each sample (s), for a result solved in time; None otherwise.
    change_points : tuple of ChangePoint
        Dyads that fold between neighbouring samples, and how the engine went on
        (`excavkin.kinematics.change_points`).
    error_estimate : ndarray, shape (n,), optional
        For the samples near a dead position, the estimated error of the row's values relative
        to their quantities' scales over the sweep (measured against an extended-precision
        solve, `excavkin.kinematics.precision`); NaN for the samples far from one (not
        checked, their rounding error is far below 1e-8) and for those that did not solve.
        Rows whose estimate exceeds 1e-8 are marked "rates lose precision".
    parameters : dict, optional
        The dimensions given per sample (``Mechanism.solve(..., params=)``), SI, each a scalar
        or shape (n,).
    tangents : dict, optional
        Per parameter asked for (``solve(..., sensitivities=)``), a result whose columns are the
        derivatives of these columns with respect to it: read them with `sensitivity`.
    tangent_columns : frozenset of str, optional
        The columns whose derivatives were asked for (``sensitivity_columns``); None: all.
    unit_rates : tuple of str
        The swept drivers given no rate: each moves at rate 1 (acceleration as given, default
        0), so that the velocities and accelerations are transfer functions with respect to
        them, not a motion in time. Forces from such a result are taken at rest in these
        drivers (`excavkin.Mechanism.forces`).
    """

    plan: SolvePlan
    positions: F
    velocities: F
    accelerations: F
    body_angle: F
    body_omega: F
    body_epsilon: F
    inputs: F
    input_rates: F
    input_accels: F
    element_length: F
    element_rate: F
    element_accel: F
    element_angle: F
    element_omega: F
    element_epsilon: F
    transmission: F
    status: Status
    time: F | None = None
    change_points: tuple[ChangePoint, ...] = ()
    error_estimate: F | None = None
    parameters: dict[str, F] | None = None
    tangents: dict[str, KinematicResult] | None = None
    tangent_columns: frozenset[str] | None = None
    unit_rates: tuple[str, ...] = ()

    @classmethod
    def build(
        cls,
        plan: SolvePlan,
        x: F,
        v: F,
        a: F,
        q: F,
        qd: F,
        qdd: F,
        trans: F,
        derived: Derived,
        status: Status,
        lengths: bool = True,
    ) -> KinematicResult:
        """Wrap the solver's arrays (n_points, 2, n) etc. as batch-first views.

        The element rows of ``derived`` that are driven lengths are set to their inputs.

        Parameters
        ----------
        plan : SolvePlan
            The plan solved.
        x, v, a : ndarray, shape (n_points, 2, n)
            Positions (m), velocities (m/s) and accelerations (m/s²) of the points.
        q, qd, qdd : ndarray, shape (n_inputs, n)
            The inputs and their first and second time derivatives (rad or m, per s, per s²).
        trans : ndarray, shape (n_transmissions, n)
            Transmission angles (rad).
        derived : Derived
            Body and element quantities, shapes (3, n_bodies, n) and (6, n_elements, n).
        status : Status
            Per-sample outcome. One not yet looked at for poses out of reach (its ``unmet``
            None) is (`diagnose`).
        lengths : bool, default True
            Set the element rows of driven lengths to their inputs (False: the caller has
            set those it keeps).

        Returns
        -------
        KinematicResult
            Views of those arrays with the sample axis first, without time, change points or
            sensitivities.
        """
        if status.unmet is None:
            status = diagnose(plan, x, q, status)
        for j, e in enumerate(plan.elements):
            # a driven length is its input, exactly (failed samples too); a winch rope's, its
            # motor's angle times each design's R/(i·n), is its blocks' distance as solved
            if e.input >= 0 and not e.ratio and lengths:
                derived.element[0, j] = q[e.input]
                derived.element[1, j] = qd[e.input]
                derived.element[2, j] = qdd[e.input]
        return cls(
            plan=plan,
            positions=np.moveaxis(x, -1, 0),
            velocities=np.moveaxis(v, -1, 0),
            accelerations=np.moveaxis(a, -1, 0),
            body_angle=derived.body[0].T,
            body_omega=derived.body[1].T,
            body_epsilon=derived.body[2].T,
            inputs=q.T,
            input_rates=qd.T,
            input_accels=qdd.T,
            element_length=derived.element[0].T,
            element_rate=derived.element[1].T,
            element_accel=derived.element[2].T,
            element_angle=derived.element[3].T,
            element_omega=derived.element[4].T,
            element_epsilon=derived.element[5].T,
            transmission=trans.T,
            status=status,
        )

    def __len__(self) -> int:
        return int(self.positions.shape[0])

    def __repr__(self) -> str:
        return summary.text("KinematicResult", len(self), self.status.labels(), self.columns)

    def _repr_html_(self) -> str:
        title = f"KinematicResult of {self.plan.model.name!r}"
        return summary.result_html(title, len(self), self.status.labels(), self.columns)

    def describe_sample(self, i: int) -> str:
        """Sample ``i`` by its inputs that vary: ``"crank = 132°"``, ``"boom_cyl = 2.315 m"``.

        Parameters
        ----------
        i : int
            The sample's index.

        Returns
        -------
        str
            Its time (where solved in time) and the inputs that vary over the result, or
            ``"sample i"`` where none does.
        """
        q = self.inputs
        held = (len(self) > 1) & (np.fmax.reduce(q, axis=0) == np.fmin.reduce(q, axis=0))
        t = None if self.time is None else float(self.time[i])
        return describe_inputs(self.plan, q[i], held, t, i)

    def summary(self, limit: int = 10) -> str:
        """The failing samples grouped by reason, each named by its inputs.

        Parameters
        ----------
        limit : int, default 10
            Samples listed per reason.

        Returns
        -------
        str
            One paragraph (see `Status.summary`).
        """
        return self.status.summary(limit, describe=self.describe_sample)

    # ---- lookups by name
    def _index(self, what: str, names: Sequence[str], name: str) -> int:
        try:
            return names.index(name)
        except ValueError:
            raise unknown_name(what, name, names) from None

    def point(self, name: str) -> tuple[F, F, F]:
        """Position, velocity and acceleration of a point, each shape (n, 2).

        Parameters
        ----------
        name : str
            The point's name.

        Returns
        -------
        position, velocity, acceleration : ndarray, shape (n, 2)
            In m, m/s and m/s².

        Raises
        ------
        UnknownNameError
            No point of that name, with the nearest names.
        """
        i = self._index("point", self.plan.points, name)
        return self.positions[:, i], self.velocities[:, i], self.accelerations[:, i]

    def body(self, name: str) -> tuple[F, F, F]:
        """Angle, ω and ε of a body, each shape (n,).

        Parameters
        ----------
        name : str
            The body's name.

        Returns
        -------
        angle, omega, epsilon : ndarray, shape (n,)
            Orientation (rad, first→second point, CCW from +x), ω (rad/s) and ε (rad/s²).

        Raises
        ------
        UnknownNameError
            No body of that name, with the nearest names.
        """
        j = self._index("body", self.plan.bodies, name)
        return self.body_angle[:, j], self.body_omega[:, j], self.body_epsilon[:, j]

    def driver(self, name: str) -> tuple[F, F, F]:
        """Value, rate and acceleration of any driver (rotary, driven, locked or free).

        Parameters
        ----------
        name : str
            A rotary driver's or a linear element's name.

        Returns
        -------
        value, rate, accel : ndarray, shape (n,)
            A rotary driver's angle (rad, rad/s, rad/s²) or a linear element's length (m, m/s,
            m/s²).

        Raises
        ------
        UnknownNameError
            No driver of that name, with the nearest names.
        """
        if name in self.plan.inputs:
            i = self.plan.inputs.index(name)
            if self.plan.input_kinds[i] == "angle":
                return self.inputs[:, i], self.input_rates[:, i], self.input_accels[:, i]
        names = [e.name for e in self.plan.elements]
        rotary = [
            n for n, k in zip(self.plan.inputs, self.plan.input_kinds, strict=True) if k == "angle"
        ]
        j = self._index("driver", [*rotary, *names], name) - len(rotary)
        return self.element_length[:, j], self.element_rate[:, j], self.element_accel[:, j]

    @property
    def columns(self) -> tuple[Column, ...]:
        """What each column of `to_frame` holds (``status`` aside), in table order."""
        return tuple(c for c, _ in self._columns())

    def sensitivity(self, column: str, parameter: str) -> F:
        """d(column)/d(parameter) per sample, SI per SI unit, shape (n,): exact derivatives
        by forward-mode differentiation through the plan (``solve(..., sensitivities=[...])``
        asks for them). NaN where the sample did not solve.

        Parameters
        ----------
        column : str
            A column of `to_frame`, e.g. ``"B.x"``.
        parameter : str
            A parameter the result was solved with sensitivities to (a name of
            ``Mechanism.parameters``).

        Returns
        -------
        ndarray, shape (n,)
            The derivative, in the column's SI unit per the parameter's.

        Raises
        ------
        InputError
            No sensitivities, an unknown parameter, or a column whose derivative was not
            computed.
        """
        if not self.tangents:
            from excavkin.errors import InputError

            raise InputError(
                "this result has no sensitivities: solve with sensitivities=[...] naming the "
                "parameters"
            )
        if parameter not in self.tangents:
            raise unknown_name("parameter with sensitivities", parameter, list(self.tangents))
        if self.tangent_columns is not None and column not in self.tangent_columns:
            from excavkin.errors import InputError

            raise InputError(
                f"the derivative of {column!r} was not computed: solve with "
                f"sensitivity_columns naming it (asked: {', '.join(sorted(self.tangent_columns))})"
            )
        return self.tangents[parameter].column(column)

    def column(self, name: str) -> F:
        """One column of `to_frame` by name, without building the table.

        Parameters
        ----------
        name : str
            The column's name, e.g. ``"B.vx"``, ``"rocker.omega"``, ``"crank.value"``.

        Returns
        -------
        ndarray, shape (n,)
            Its values, SI.

        Raises
        ------
        UnknownNameError
            No column of that name, with the nearest names.
        """
        cols = self._columns()
        for c, arr in cols:
            if c.name == name:
                return np.asarray(arr, dtype=np.float64)
        raise unknown_name("column", name, [c.name for c, _ in cols])

    def columns_named(self, names: Collection[str]) -> dict[str, F]:
        """Several columns by name at once (`column` of each, the table's columns listed
        once).

        Parameters
        ----------
        names : collection of str
            Column names, e.g. ``["B.x", "B.y"]``.

        Returns
        -------
        dict of str to ndarray, shape (n,)
            Each column's values, SI.

        Raises
        ------
        UnknownNameError
            A name of no column, with the nearest names.
        """
        cols = self._columns()
        got = {c.name: arr for c, arr in cols if c.name in names}
        for name in names:
            if name not in got:
                raise unknown_name("column", name, [c.name for c, _ in cols])
        return {name: np.asarray(got[name], dtype=np.float64) for name in names}

    def _columns(self) -> list[tuple[Column, F]]:
        plan = self.plan
        cols: list[tuple[Column, F]] = []
        if self.time is not None:
            cols.append((TIME, self.time))
        point_quantities = ("x", "y", "vx", "vy", "ax", "ay")
        point_arrays = (self.positions, self.velocities, self.accelerations)
        for i, p in enumerate(plan.points):
            for k, qty in enumerate(point_quantities):
                kind = QUANTITIES[qty][1]
                cols.append((column(p, "point", qty, kind), point_arrays[k // 2][:, i, k % 2]))
        body_arrays = (self.body_angle, self.body_omega, self.body_epsilon)
        for j, b in enumerate(plan.bodies):
            if j == plan.ground:
                continue
            for qty, arr in zip(("angle", "omega", "epsilon"), body_arrays, strict=True):
                cols.append((column(b, "body", qty, QUANTITIES[qty][1]), arr[:, j]))
        input_arrays = (self.inputs, self.input_rates, self.input_accels)
        for i, name in enumerate(plan.inputs):
            if plan.input_kinds[i] == "angle":
                for c, arr in zip(driver_columns(name, "angle"), input_arrays, strict=True):
                    cols.append((c, arr[:, i]))
        element_arrays = (
            self.element_length,
            self.element_rate,
            self.element_accel,
            self.element_angle,
            self.element_omega,
            self.element_epsilon,
        )
        for j, e in enumerate(plan.elements):
            line = [
                column(e.name, "driver", qty, QUANTITIES[qty][1])
                for qty in ("angle", "omega", "epsilon")
            ]
            # a winch rope's value is its motor's angle: its blocks' distance is its length
            lengths = (
                [column(e.name, "driver", q, QUANTITIES[q][1]) for q in WINCH_LENGTH]
                if e.ratio
                else driver_columns(e.name, "length")
            )
            for c, arr in zip([*lengths, *line], element_arrays, strict=True):
                cols.append((c, arr[:, j]))
        for k, p in enumerate(plan.transmissions):
            cols.append((column(p, "point", "transmission", "angle"), self.transmission[:, k]))
        n = len(self)
        for name, value in (self.parameters or {}).items():
            arr = np.broadcast_to(np.asarray(value, dtype=np.float64), (n,))
            cols.append((design_column(name, parameter_kind(name, plan.model)), arr))
        for name, tangent in (self.tangents or {}).items():
            kind = parameter_kind(name, plan.model)
            for c, arr in tangent._columns():
                wanted = self.tangent_columns is None or c.name in self.tangent_columns
                if c.owner_kind != "time" and wanted:
                    cols.append((derivative_column(c, name, kind), arr))
        return cols

    def to_frame(self, columns: Sequence[str] | None = None) -> pd.DataFrame:
        """A table with one row per sample, SI units (m, rad, s).

        Columns: ``t`` (when solved in time), ``<point>.x .y .vx .vy .ax .ay``,
        ``<body>.angle .omega .epsilon`` (moving bodies), ``<driver>.value .rate .accel`` (every
        driver; linear ones also ``.angle .omega .epsilon`` of the line between their points),
        ``<point>.transmission`` for each dyad and slider, and ``status`` ("ok" or why not).
        ``frame.attrs`` holds the model's name and each column's kind
        (``"excavkin.kinds"``), so that a table keeps its meaning apart from its result.

        Parameters
        ----------
        columns : sequence of str, optional
            Only these columns (names or glob patterns such as ``"B.*"`` or ``"*.x"``), in the
            table's order, ``status`` always (`select_columns`). Default: every column.

        Returns
        -------
        pandas.DataFrame
            n rows; the numeric columns are views of the result's arrays, not copies.

        Raises
        ------
        UnknownNameError
            A name or pattern in ``columns`` that matches no column.
        """
        import pandas as pd

        cols = self._columns()
        if columns is not None:
            kept = set(select_columns([*(c.name for c, _ in cols), "status"], columns))
            cols = [(c, arr) for c, arr in cols if c.name in kept]
        data: dict[str, Any] = {c.name: arr for c, arr in cols}
        data["status"] = self.status.categorical()
        # the columns are views of the solver's arrays: no copy
        frame = pd.DataFrame(data, copy=False)
        frame.attrs.update(table_attrs(self.plan.model.name, [c for c, _ in cols]))
        if self.unit_rates:
            frame.attrs["excavkin.motion"] = self.motion_note
        return frame

    @property
    def motion_note(self) -> str:
        """What the velocities and accelerations are, in one line: transfer functions of the
        swept drivers given no rate, or the motion of the given rates."""
        if not self.unit_rates:
            return "velocities and accelerations of the given driver rates"
        names = ", ".join(self.unit_rates)
        return (
            f"velocities and accelerations are transfer functions d(·)/dq of {names} "
            "(no rate given: rate 1), not a motion in time"
        )

    def at_rest(self) -> KinematicResult:
        """The same poses at rest: every velocity, rate and acceleration zero (NaN where the
        sample did not solve), the sensitivities' too.

        Returns
        -------
        KinematicResult
        """
        import dataclasses

        def rest(value: F) -> Any:
            return np.where(np.isnan(value), value, 0.0)

        return dataclasses.replace(
            self,
            **{name: rest(getattr(self, name)) for name in _RATE_ARRAYS},
            unit_rates=(),
            tangents=None
            if self.tangents is None
            else {k: t.at_rest() for k, t in self.tangents.items()},
        )

    def rows(self, start: int, stop: int, origin: int = 0) -> KinematicResult:
        """Samples ``start`` … ``stop − 1`` as a result of their own (views, no copies).

        Parameters
        ----------
        start, stop : int
            The first sample and one past the last.
        origin : int, default 0
            The number of this result's first sample in the numbering of its change points
            (a part of a streamed sweep numbers them in the whole sweep): the change points
            kept are those whose later sample is among the rows.

        Returns
        -------
        KinematicResult
            ``stop - start`` samples, every per-sample array a view of this result's.
        """
        import dataclasses

        s = slice(start, stop)

        def cut(value: Any) -> Any:
            return value if value is None or np.ndim(value) == 0 else value[s]

        low, high = origin + start, origin + stop
        return dataclasses.replace(
            self,
            **{name: getattr(self, name)[s] for name in _ROW_ARRAYS},
            status=Status(
                self.status.code[s],
                self.status.step[s],
                self.status.plan,
                None if self.status.unmet is None else self.status.unmet[s],
                None if self.status.miss is None else self.status.miss[s],
            ),
            time=cut(self.time),
            change_points=tuple(c for c in self.change_points if low <= c.after < high),
            error_estimate=cut(self.error_estimate),
            parameters=None
            if self.parameters is None
            else {k: cut(v) for k, v in self.parameters.items()},
            tangents=None
            if self.tangents is None
            else {k: t.rows(start, stop, origin) for k, t in self.tangents.items()},
        )

    def with_time(self, t: F) -> KinematicResult:
        """The same result with a time column, shape (n,).

        Parameters
        ----------
        t : array_like, shape (n,)
            The time of each sample (s).

        Returns
        -------
        KinematicResult
            A copy that shares every array and has ``time`` set.
        """
        import dataclasses

        return dataclasses.replace(self, time=np.asarray(t, dtype=np.float64))


def describe_inputs(plan: SolvePlan, q: F, held: np.ndarray, t: float | None, i: int) -> str:
    """A sample by its inputs ``q`` (n_inputs,) that vary over the sweep (``held`` marks the
    others) and its time: ``"t = 0.5 s, crank = 132°"``, or ``"sample i"``."""
    parts = [] if t is None else [f"t = {t:.6g} s"]
    for k, (name, kind) in enumerate(zip(plan.inputs, plan.input_kinds, strict=True)):
        if held[k]:
            continue  # held: it does not tell samples apart
        v = float(q[k])
        parts.append(f"{name} = {np.degrees(v):.4g}°" if kind == "angle" else f"{name} = {v:.6g} m")
    return ", ".join(parts) or f"sample {i}"


#: a result's arrays with one row per sample
#: the arrays of rates and accelerations (zero at rest)
_RATE_ARRAYS = (
    "velocities",
    "accelerations",
    "body_omega",
    "body_epsilon",
    "input_rates",
    "input_accels",
    "element_rate",
    "element_accel",
    "element_omega",
    "element_epsilon",
)

_ROW_ARRAYS = (
    "positions",
    "velocities",
    "accelerations",
    "body_angle",
    "body_omega",
    "body_epsilon",
    "inputs",
    "input_rates",
    "input_accels",
    "element_length",
    "element_rate",
    "element_accel",
    "element_angle",
    "element_omega",
    "element_epsilon",
    "transmission",
)


@dataclass(frozen=True, slots=True)
class Derived:
    """Body and element quantities derived from the points.

    ``body`` has shape (3, n_bodies, n): angle, ω, ε. ``element`` has shape (6, n_elements, n):
    length, rate, acceleration, angle, ω, ε.
    """

    body: F
    element: F

    @classmethod
    def empty(cls, plan: SolvePlan, n: int, dtype: type = np.float64) -> Derived:
        """Arrays to fill chunk by chunk (the ground's row stays zero)."""
        return cls(
            np.zeros((3, len(plan.bodies), n), dtype=dtype),
            np.empty((6, len(plan.elements), n), dtype=dtype),
        )

    def fill(self, plan: SolvePlan, x: F, v: F, a: F, s: slice) -> None:
        """Compute the chunk ``s`` from its point arrays (n_points, 2, chunk)."""
        for j, (p0, p1) in enumerate(plan.body_base):
            if j != plan.ground and p0 >= 0:
                ang, om, eps, _, _, _ = _segment(x, v, a, p0, p1, lengths=False)
                self.body[0, j, s], self.body[1, j, s], self.body[2, j, s] = ang, om, eps
        for j, e in enumerate(plan.elements):
            ang, om, eps, ln, rt, ac = _segment(x, v, a, e.p, e.q)
            for k, val in enumerate((ln, rt, ac, ang, om, eps)):
                self.element[k, j, s] = val


def _segment(
    x: F, v: F, a: F, p: int, q: int, lengths: bool = True
) -> tuple[F, F, F, F | None, F | None, F | None]:
    """Angle, ω, ε, length, rate and acceleration of the segment p→q (any length)."""
    rx, ry = x[q, 0] - x[p, 0], x[q, 1] - x[p, 1]
    vx, vy = v[q, 0] - v[p, 0], v[q, 1] - v[p, 1]
    ax, ay = a[q, 0] - a[p, 0], a[q, 1] - a[p, 1]
    r2 = rx * rx + ry * ry
    omega = (rx * vy - ry * vx) / r2
    if not lengths:  # a rigid segment: r·ṙ = 0
        return np.arctan2(ry, rx), omega, (rx * ay - ry * ax) / r2, None, None, None
    dot = rx * vx + ry * vy
    eps = (rx * ay - ry * ax - 2.0 * dot * omega) / r2
    length = np.sqrt(r2)
    rate = dot / length
    accel = (rx * ax + ry * ay + vx * vx + vy * vy - rate * rate) / length
    return np.arctan2(ry, rx), omega, eps, length, rate, accel
