"""Kinetostatic results: joint forces, driver forces and torques, batch axis first.

Columns of [`ForceResult.to_frame`][excavkin.kinetostatics.result.ForceResult.to_frame] (SI: N,
N·m)::

    <point>.<body>.Fx, .Fy   the force the pin at <point> exerts on <body> (every body at the
                             pin, the ground included; at a pin of one body where a cylinder
                             acts, the cylinder's force passed through the pin)
    <driver>.force           axial force of a driven or locked linear element; > 0 pushes its
                             two points apart (a rope in tension is negative)
    <rope>.tension           a rope's tension, N (its blocks' force / its parts); a sample
                             where it would be < 0 (the rope would push) is "slack rope", not ok
    <rope>.torque            a winch rope's motor torque, N·m, in the sense of its angle
                             (power = torque · motor speed; < 0 holds a load hanging on it)
    <driver>.torque          torque of a rotary driver on its body (CCW > 0); its reference body
                             receives the opposite torque
    <slider>.normal          normal force on the slider's point, along perp(l2 − l1); the body
                             carrying the line receives the opposite force
    <body>.Rx, .Ry           resultant of all joint forces on a body (default: the ground only,
                             under the ground body's name)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import unknown_name
from excavkin.kinematics import summary
from excavkin.kinematics.columns import (
    Column,
    column,
    derivative_column,
    select_columns,
    table_attrs,
)
from excavkin.kinematics.result import KinematicResult
from excavkin.kinetostatics.equilibrium import StaticsSystem
from excavkin.kinetostatics.gears import CAM_COLUMNS, RACK_COLUMNS, RACK_KINDS
from excavkin.kinetostatics.inertia import MassProperties, centre_of_mass, kinetic_energy_rate
from excavkin.kinetostatics.loads import EvaluatedLoads, Load
from excavkin.model.entities import Rope
from excavkin.structure.design import parameter_kind

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["ForceResult", "PowerBalance", "motion_note", "winch_drive"]


def motion_note(static: bool, at_rest: Sequence[str]) -> str:
    """What forces are, in one line: static, or with the inertia of the given rates; and the
    swept drivers given no rate, taken at rest.

    Parameters
    ----------
    static : bool
        No driver moves: every rate and acceleration is zero.
    at_rest : sequence of str
        The swept drivers given no rate (taken as 0).

    Returns
    -------
    str
        ``"static forces, no inertia (no rate given for crank: taken as 0)"`` and the like.
    """
    why = f" (no rate given for {', '.join(at_rest)}: taken as 0)" if at_rest else ""
    if static:
        return f"static forces, no inertia{why}"
    return f"forces with the inertia of the given driver rates and accelerations{why}"


def winch_drive(rope: Rope, params: Mapping[str, Any] | None) -> tuple[Any, Any]:
    """A winch's drum radius and gear ratio, per design where the result's parameters give
    them.

    Parameters
    ----------
    rope : Rope
        A winch rope.
    params : mapping of str to array_like, or None
        The parameters the result was solved with.

    Returns
    -------
    radius, ratio : float or ndarray, shape (n,)
        m, and motor turns per drum turn.
    """
    given = params or {}
    return (
        given.get(f"{rope.name}.drum_radius", rope.drum_radius),
        given.get(f"{rope.name}.gear_ratio", rope.gear_ratio),
    )


def _with_unit(value: float, kind: str) -> str:
    """A force (N) or torque (N·m) with its unit, in kN or kN·m from 1000 on."""
    unit = "N" if kind == "force" else "N·m"
    if abs(value) >= 1e3:
        return f"{value / 1e3:.4g} k{unit}"
    return f"{value:.4g} {unit}"


@dataclass(frozen=True, slots=True)
class PowerBalance:
    """The power balance of a kinetostatic solution, per sample (W).

    With the d'Alembert inertia included the joint forces of ideal joints do no work, so
    ``driver = kinetic_rate − load`` where ``kinetic_rate = dT/dt = Σ m·a_S·v_S + J·ε·ω``.

    Attributes
    ----------
    driver : ndarray, shape (n,)
        Σ τ·(ω_body − ω_reference) + Σ f·(rate of length) over the drivers.
    kinetic_rate : ndarray, shape (n,)
        dT/dt.
    load : ndarray, shape (n,)
        Power of the applied loads (gravity, forces, couples).
    scale : ndarray, shape (n,)
        The reference for ``relative``, the size of the numbers whose round-off the residual
        carries: ``Σ |force|·|velocity of its point|`` over every force — each load, each
        body's weight and inertia force ``m·(|a_S| + |g|)·|v_S|``, each pin force on each body
        and each slider's normal force — plus ``|τ·ω|`` of every couple and driver and
        ``|J·ε·ω|``. The joint forces' powers cancel in the balance but not their round-off:
        where the net power terms all pass through zero together (a crank acting as a
        two-force member, the rocker at a dead centre) the joint forces stay finite.
    """

    driver: F
    kinetic_rate: F
    load: F
    scale: F

    @property
    def residual(self) -> F:
        """``driver − (kinetic_rate − load)``, W, shape (n,)."""
        return np.asarray(self.driver - (self.kinetic_rate - self.load))

    @property
    def relative(self) -> F:
        """``|residual| / scale`` (0 where every term is 0), shape (n,)."""
        scale = np.where(self.scale > 0, self.scale, 1.0)
        return np.asarray(np.abs(self.residual) / scale)


@dataclass(frozen=True, slots=True, repr=False)
class ForceResult:
    """Joint forces and driver efforts of a mechanism over n samples (SI).

    Attributes
    ----------
    kinematics : KinematicResult
        The motion these forces belong to.
    system : StaticsSystem
        Names and structure of the unknowns.
    pin_force : ndarray, shape (n, n_pins, 2)
        Force of each pin on each body it joins; ``pins`` names them.
    element_force : ndarray, shape (n, n_loaded_elements)
        Axial force of each driven or locked linear element, N (> 0 pushes apart).
    slider_force : ndarray, shape (n, n_sliders)
        Normal force of each slider on its point, N, along perp(l2 − l1).
    driver_torque : ndarray, shape (n, n_rotary)
        Torque of each rotary driver on its body, N·m.
    gear_force : ndarray, shape (n, n_gears)
        The tangential tooth force of each gear pair on its gear 2, N, along
        perp(O2 − O1) at the pitch point (gear 1 gets the opposite; the radial part,
        ``|W|·tan φ``, is in the pivots' pin forces).
    rack_force : ndarray, shape (n, n_racks, 3)
        Each rack's tooth force along its guide (N, on the rack; the radial part is in its
        guide's force), its guide's normal force along perp(guide) at the pitch point (N) and
        its guide's couple (N·m), on the rack.
    cam_force : ndarray, shape (n, n_cams, 3)
        Each cam's contact force on its follower along the common normal (N; < 0: the
        follower would leave the cam), its guide's normal force at the follower's first point
        (N) and couple (N·m), on the follower.
    singular : ndarray of bool, shape (n,)
        Samples whose equilibrium equations are singular although the kinematics solved
        (their forces are NaN).
    loads : tuple of PointForce, Torque, Gravity
        The loads applied.
    evaluated : EvaluatedLoads
        The loads resolved to body and point indices and evaluated over the samples.
    mass : MassProperties
        The mass properties the forces were solved with (per sample for a family of designs).
    tangents : dict, optional
        Per parameter (``solve(..., sensitivities=)``), the derivative of every force column:
        read them with `sensitivity`.
    at_rest : tuple of str
        The swept drivers given no rate, taken at rest (rate 0) for these forces: forces
        without given rates are static (`static`, `motion_note`).
    rope_tension : ndarray, shape (n, n_sheaved), optional
        The tension of each rope over sheaves, N (`tension` reads every rope's).
    """

    kinematics: KinematicResult
    system: StaticsSystem
    pin_force: F
    element_force: F
    slider_force: F
    driver_torque: F
    gear_force: F
    rack_force: F
    cam_force: F
    singular: np.ndarray
    loads: tuple[Load, ...]
    evaluated: EvaluatedLoads
    mass: MassProperties
    tangents: dict[str, dict[str, F]] | None = None
    at_rest: tuple[str, ...] = ()
    rope_tension: F | None = None

    @property
    def static(self) -> bool:
        """Whether these are static forces: no driver moves (every rate and acceleration is
        zero), so there is no inertia."""
        k = self.kinematics
        solved = k.status.solved
        return not (np.any(k.input_rates[solved]) or np.any(k.input_accels[solved]))

    @property
    def motion_note(self) -> str:
        """Whether the forces are static or include the inertia of a motion, and why, in one
        line (the tables' ``attrs["excavkin.motion"]``, the command line)."""
        return motion_note(self.static, self.at_rest)

    def __len__(self) -> int:
        return int(self.pin_force.shape[0])

    def __repr__(self) -> str:
        return summary.text("ForceResult", len(self), self.status_labels(), self.columns)

    def _repr_html_(self) -> str:
        title = f"ForceResult of {self.kinematics.plan.model.name!r}"
        return summary.result_html(title, len(self), self.status_labels(), self.columns)

    def summary(self, limit: int = 10) -> str:
        """The statuses and the extreme forces, as a user reads them.

        The first line lists the failing samples by reason, as
        [`KinematicResult.summary`][excavkin.kinematics.result.KinematicResult.summary] does,
        statically singular samples among them; then, over the samples that solved,
        each driver's largest force or torque (signed) and the ``limit`` pins with the largest
        force on a body (its magnitude), each with its unit and the sample where it occurs,
        named by its inputs.

        Parameters
        ----------
        limit : int
            Failing samples listed per reason, and pins listed.

        Returns
        -------
        str
        """
        kin = self.kinematics
        labels = self.status_labels()
        bad = np.flatnonzero(~self.ok)
        groups = []
        for lab in dict.fromkeys(labels[bad]):
            idx = bad[labels[bad] == lab]
            shown = [f"{int(i)} ({kin.describe_sample(int(i))})" for i in idx[:limit]]
            groups.append((str(lab), int(idx.size), shown))
        lines = [summary.failures(len(self), groups, limit)]
        ok = self.ok
        if not ok.any():
            return lines[0]

        def at(i: int) -> str:
            return f"sample {i} ({kin.describe_sample(i)})"

        efforts: list[tuple[str, F, str]] = [
            *((f"{e[0]}.force", self.element_force[:, k], "force")
              for k, e in enumerate(self.system.elements)),
            *((f"{d[0]}.torque", self.driver_torque[:, k], "torque")
              for k, d in enumerate(self.system.rotary)),
            *((f"{sl[0]}.normal", self.slider_force[:, k], "force")
              for k, sl in enumerate(self.system.sliders)),
            *((f"{r.name}.tension", t, "force") for r, t in self._ropes() if r.over_sheaves),
        ]  # fmt: skip
        solved = int(ok.sum())
        if efforts:
            lines.append(f"largest driver efforts over the {solved} solved samples:")
            for name, values, kind in efforts:
                i = int(np.nanargmax(np.where(ok, np.abs(values), -np.inf)))
                lines.append(f"  {name:<24} {_with_unit(float(values[i]), kind)} at {at(i)}")
        if self.pins:
            mag = np.hypot(self.pin_force[..., 0], self.pin_force[..., 1])
            mag = np.where(ok[:, None], mag, -np.inf)
            peak = mag.max(axis=0)
            order = np.argsort(-peak, kind="stable")[:limit]
            more = len(self.pins) - len(order)
            lines.append(
                f"largest pin forces over the {solved} solved samples"
                + (f" ({len(order)} of {len(self.pins)} pins)" if more else "")
                + ":"
            )
            for k in order:
                p, b = self.pins[k]
                i = int(np.argmax(mag[:, k]))
                size = f"|F| {_with_unit(float(peak[k]), 'force')}"
                lines.append(f"  {p} on {b:<{max(1, 20 - len(p))}} {size} at {at(i)}")
        return "\n".join(lines)

    # ---- names
    @property
    def pins(self) -> tuple[tuple[str, str], ...]:
        """(point, body) of each row of ``pin_force``."""
        sy = self.system
        return tuple((sy.points[i], sy.bodies[j]) for i, j in sy.slots)

    @property
    def ok(self) -> np.ndarray:
        """Samples with both kinematics and forces solved and no rope slack, shape (n,)."""
        return np.asarray(self.kinematics.status.ok & ~self.singular & ~self.slack)

    # ---- ropes: tension only
    def _ropes(self) -> list[tuple[Rope, F]]:
        """Each rope of the model with its tension (N, shape (n,)): a rope between blocks
        carries its blocks' force over its parts, one over sheaves its own unknown."""
        names = [e[0] for e in self.system.elements]
        sheaved = [r[0] for r in self.system.ropes]
        out: list[tuple[Rope, F]] = []
        for rope in self.kinematics.plan.model.ropes:
            if rope.over_sheaves:
                assert self.rope_tension is not None
                t = self.rope_tension[:, sheaved.index(rope.name)]
            else:
                t = -self.element_force[:, names.index(rope.name)] / rope.parts
            out.append((rope, np.asarray(t)))
        return out

    @property
    def slack(self) -> np.ndarray:
        """Samples where some rope would have to push (its tension < 0): a rope carries tension
        only, so these forces are not the mechanism's (not `ok`), shape (n,)."""
        out = np.zeros(len(self), dtype=bool)
        for _, tension in self._ropes():
            out |= tension < 0.0
        return out

    def tension(self, name: str) -> F:
        """A rope's tension, N, shape (n,).

        Parameters
        ----------
        name : str
            The rope's name.

        Returns
        -------
        ndarray, shape (n,)
            Between two blocks, ``−force / parts``; over sheaves, the tension along each free
            segment (N). Negative where the rope would have to push (`slack`).

        Raises
        ------
        UnknownNameError
            No rope of that name, with the nearest names (a `KeyError` too).
        """
        ropes = self._ropes()
        for rope, tension in ropes:
            if rope.name == name:
                return tension
        raise unknown_name("rope", name, [r.name for r, _ in ropes])

    def winch_torque(self, name: str) -> F:
        """A winch rope's motor torque, N·m, shape (n,), in the sense of the motor's angle.

        A motor angle θ pays out ``θ·R/i`` of rope, so by virtual work the motor's torque is
        ``−T·R/i`` and its power ``torque·ω`` is the rope's on the mechanism.

        Parameters
        ----------
        name : str
            The winch rope's name.

        Returns
        -------
        ndarray, shape (n,)
            The torque (N·m); negative while the rope holds a load (hauling in, ω < 0,
            then takes power from the motor).

        Raises
        ------
        UnknownNameError
            No winch rope of that name, with the nearest names (a `KeyError` too).
        """
        winches = [(r, t) for r, t in self._ropes() if r.mode == "winch"]
        for rope, tension in winches:
            if rope.name == name:
                radius, ratio = winch_drive(rope, self.kinematics.parameters)
                return np.asarray(-tension * (radius / ratio))
        raise unknown_name("winch rope", name, [r.name for r, _ in winches])

    # ---- lookups by name
    def pin(self, point: str, body: str) -> F:
        """Force of the pin at ``point`` on ``body``, shape (n, 2).

        Parameters
        ----------
        point : str
            The joint's point.
        body : str
            One of the bodies it joins; `pins` lists the pairs.

        Returns
        -------
        ndarray, shape (n, 2)
            ``(Fx, Fy)`` of the pin on the body (N).

        Raises
        ------
        UnknownNameError
            No such pin, with the nearest ones (a `KeyError` too).
        """
        try:
            k = self.pins.index((point, body))
        except ValueError:
            known = [f"{p}.{b}" for p, b in self.pins]
            raise unknown_name("pin (point.body)", f"{point}.{body}", known) from None
        return self.pin_force[:, k]

    def force(self, name: str) -> F:
        """Axial force of a driven or locked linear element, or a slider's normal force.

        Parameters
        ----------
        name : str
            The element's or the slider's name.

        Returns
        -------
        ndarray, shape (n,)
            The element's force (N, > 0 pushes its points apart), or the slider's normal force
            on its point (N, along perp(l2 − l1)).

        Raises
        ------
        UnknownNameError
            No driven or locked linear element or slider of that name, with the nearest
            names (a `KeyError` too).
        """
        names = [e[0] for e in self.system.elements]
        if name in names:
            return self.element_force[:, names.index(name)]
        sliders = [s[0] for s in self.system.sliders]
        if name in sliders:
            return self.slider_force[:, sliders.index(name)]
        raise unknown_name("driven or locked linear element or slider", name, [*names, *sliders])

    def torque(self, name: str) -> F:
        """Torque of a rotary driver, shape (n,).

        Parameters
        ----------
        name : str
            The rotary driver's name.

        Returns
        -------
        ndarray, shape (n,)
            Its torque on its body (N·m, counter-clockwise positive); its reference body gets
            the opposite.

        Raises
        ------
        UnknownNameError
            No rotary driver of that name, with the nearest names (a `KeyError` too).
        """
        names = [d[0] for d in self.system.rotary]
        if name not in names:
            raise unknown_name("rotary driver", name, names)
        return self.driver_torque[:, names.index(name)]

    def resultant(self, body: str) -> F:
        """Resultant of all joint forces on ``body`` (pins and slider contacts), shape (n, 2).

        For the ground: the total force the mechanism exerts on its frame through its joints.

        Parameters
        ----------
        body : str
            The body's name.

        Returns
        -------
        ndarray, shape (n, 2)
            ``(Rx, Ry)`` (N); NaN where the sample did not solve or is statically singular.

        Raises
        ------
        UnknownNameError
            No body of that name, with the nearest names (a `KeyError` too).
        """
        sy = self.system
        if body not in sy.bodies:
            raise unknown_name("body", body, list(sy.bodies))
        j = sy.bodies.index(body)
        out = np.zeros((len(self), 2))
        for k, (_, jj) in enumerate(sy.slots):
            if jj == j:
                out += self.pin_force[:, k]
        if any(s[4] == j for s in sy.sliders):
            x = self.kinematics.positions
            for k, (_, _, l1, l2, carrier) in enumerate(sy.sliders):
                if carrier != j:
                    continue
                e = x[:, l2] - x[:, l1]
                n = np.stack([-e[:, 1], e[:, 0]], axis=1) / np.hypot(e[:, 0], e[:, 1])[:, None]
                out -= self.slider_force[:, k, None] * n
        out[~(self.kinematics.status.solved & ~self.singular)] = np.nan
        return out

    # ---- tables
    def _columns(self, resultants: Sequence[str]) -> list[tuple[Column, F]]:
        sy = self.system
        cols: list[tuple[Column, F]] = []
        for k, (p, b) in enumerate(self.pins):
            for c, qty in enumerate(("Fx", "Fy")):
                cols.append((column(f"{p}.{b}", "pin", qty, "force"), self.pin_force[:, k, c]))
        for k, e in enumerate(sy.elements):
            cols.append((column(e[0], "driver", "force", "force"), self.element_force[:, k]))
        for k, d in enumerate(sy.rotary):
            cols.append((column(d[0], "driver", "torque", "torque"), self.driver_torque[:, k]))
        for k, s in enumerate(sy.sliders):
            cols.append((column(s[0], "slider", "normal", "force"), self.slider_force[:, k]))
        for k, g in enumerate(sy.gears):
            cols.append((column(g[0], "other", "tooth", "force"), self.gear_force[:, k]))
        for k, rk in enumerate(sy.racks):
            for c, (qty, kind) in enumerate(zip(RACK_COLUMNS, RACK_KINDS, strict=True)):
                cols.append((column(rk[0], "other", qty, kind), self.rack_force[:, k, c]))
        for k, cm in enumerate(sy.cams):
            kinds = zip(CAM_COLUMNS[: cm.unknowns], RACK_KINDS[: cm.unknowns], strict=True)
            for c, (qty, kind) in enumerate(kinds):
                cols.append((column(cm.name, "other", qty, kind), self.cam_force[:, k, c]))
        for rope, tension in self._ropes():
            cols.append((column(rope.name, "driver", "tension", "force"), tension))
            if rope.mode == "winch":
                torque = self.winch_torque(rope.name)
                cols.append((column(rope.name, "driver", "torque", "torque"), torque))
        for b in resultants:
            r = self.resultant(b)
            cols += [(column(b, "body", q, "force"), r[:, c]) for c, q in enumerate(("Rx", "Ry"))]
        return cols

    @property
    def columns(self) -> tuple[Column, ...]:
        """What each column of `to_frame` holds (``status`` aside), in table order."""
        ground = self.system.bodies[self.system.ground]
        return self.kinematics.columns + tuple(c for c, _ in self._columns((ground,)))

    def column(self, name: str) -> F:
        """One force column of `to_frame` by name (any body's ``.Rx``/``.Ry`` too).

        Parameters
        ----------
        name : str
            The column's name, e.g. ``"B.coupler.Fx"``, ``"crank.torque"``, ``"ground.Ry"``.

        Returns
        -------
        ndarray, shape (n,)
            Its values, SI (N, N·m).

        Raises
        ------
        UnknownNameError
            No such column, with the nearest names.
        """
        owner, _, qty = name.rpartition(".")
        if qty in ("Rx", "Ry") and owner in self.system.bodies:
            return self.resultant(owner)[:, 0 if qty == "Rx" else 1]
        cols = self._columns(())
        for c, arr in cols:
            if c.name == name:
                return np.asarray(arr)
        raise unknown_name("force column", name, [c.name for c, _ in cols])

    def sensitivity(self, column: str, parameter: str) -> F:
        """d(column)/d(parameter) per sample, SI per SI unit, shape (n,), for a force column
        or a kinematic one (exact: the equilibrium differentiated on dual numbers).

        Parameters
        ----------
        column : str
            A column of `to_frame`, e.g. ``"O2.ground.Fx"`` or ``"B.x"``.
        parameter : str
            A parameter the result was solved with sensitivities to (a name of
            ``Mechanism.parameters``).

        Returns
        -------
        ndarray, shape (n,)
            The derivative, in the column's SI unit per the parameter's; NaN where the sample
            did not solve.

        Raises
        ------
        InputError
            No sensitivities, an unknown parameter, or a column whose derivative was not
            computed.
        """
        if self.tangents and parameter in self.tangents and column in self.tangents[parameter]:
            return self.tangents[parameter][column]
        return self.kinematics.sensitivity(column, parameter)

    def status_labels(self) -> np.ndarray:
        """Per-sample label: the kinematic status, ``"statically singular"`` or ``"slack
        rope"``, shape (n,).

        Returns
        -------
        ndarray of object, shape (n,)
            ``"ok"``, why the kinematics failed, or ``"statically singular (redundant joint at
            this position)"``.
        """
        labels = self.kinematics.status.labels()
        bad = self.singular & self.kinematics.status.ok
        labels[bad] = "statically singular (redundant joint at this position)"
        for rope, tension in self._ropes():
            pushes = (tension < 0.0) & self.kinematics.status.ok & ~bad
            labels[pushes] = f"slack rope {rope.name!r} (it would have to push)"
        return labels

    def to_frame(
        self,
        *,
        kinematics: bool = True,
        resultants: Sequence[str] | None = None,
        columns: Sequence[str] | None = None,
    ) -> pd.DataFrame:
        """A table with one row per sample, SI units (N, N·m).

        Parameters
        ----------
        kinematics : bool
            Start with the kinematic columns and ``status`` (default); ``False`` gives the
            force columns only.
        resultants : sequence of str, optional
            Bodies whose joint-force resultant ``<body>.Rx .Ry`` is added (default: the
            ground, under its own name).
        columns : sequence of str, optional
            Only these columns (names or glob patterns such as ``"B.*"``, ``"*.Fx"``), in the
            table's order, ``status`` always
            ([`select_columns`][excavkin.kinematics.columns.select_columns]). Default: every
            column.

        Returns
        -------
        pandas.DataFrame
            Columns ``<point>.<body>.Fx .Fy``, ``<driver>.force`` (linear), ``<driver>.torque``
            (rotary), ``<slider>.normal``, ``<gear pair>.tooth`` (the tangential tooth force),
            ``<rack>.tooth .guide .couple``, ``<cam>.contact .guide .couple``,
            ``<body>.Rx .Ry`` — after the kinematic ones.

        Raises
        ------
        UnknownNameError
            A name or pattern in ``columns`` that matches no column.
        """
        import pandas as pd

        if resultants is None:
            resultants = (self.system.bodies[self.system.ground],)
        described = self._columns(resultants)
        for name, tangent in (self.tangents or {}).items():
            kind = parameter_kind(name, self.kinematics.plan.model)
            described += [
                (derivative_column(c, name, kind), tangent[c.name])
                for c, _ in self._columns(resultants)
                if c.name in tangent
            ]
        kin = self.kinematics._columns() if kinematics else []
        if columns is not None:
            names = [c.name for c, _ in [*kin, *described]]
            kept = set(select_columns([*names, *(["status"] if kinematics else [])], columns))
            kin = [(c, arr) for c, arr in kin if c.name in kept]
            described = [(c, arr) for c, arr in described if c.name in kept]
        force_cols = [c for c, _ in described]
        model = self.kinematics.plan.model.name
        if not kinematics:
            forces = pd.DataFrame({c.name: arr for c, arr in described}, copy=False)
            forces.attrs.update(table_attrs(model, force_cols))
            forces.attrs["excavkin.motion"] = self.motion_note
            return forces
        # one frame from all the columns at once, each a view of its result's array: no
        # copies, no insertions
        data: dict[str, Any] = {c.name: arr for c, arr in [*kin, *described]}
        status = self.kinematics.status
        if self.singular.any() or self.slack.any():
            data["status"] = pd.Categorical(self.status_labels())
        else:
            data["status"] = status.categorical()
        frame = pd.DataFrame(data, copy=False)
        frame.attrs.update(table_attrs(model, [*(c for c, _ in kin), *force_cols]))
        frame.attrs["excavkin.motion"] = self.motion_note
        return frame

    # ---- checks
    def power_balance(self) -> PowerBalance:
        """Driver power against dT/dt minus load power, per sample.

        Returns
        -------
        PowerBalance
        """
        kin = self.kinematics
        sy = self.system
        n = len(self)
        om = kin.body_omega
        v = kin.velocities
        speed = np.hypot(v[..., 0], v[..., 1])  # (n, n_points)
        scale = np.zeros(n)
        driver = np.zeros(n)
        for k, (_, body, ref) in enumerate(sy.rotary):
            p = self.driver_torque[:, k] * (om[:, body] - om[:, ref])
            driver += p
            scale += np.abs(p)
        for k, (_, _, _, e) in enumerate(sy.elements):
            p = self.element_force[:, k] * kin.element_rate[:, e]
            driver += p
            scale += np.abs(p)
        inputs = kin.plan.inputs
        for rope, _ in self._ropes():  # a winch over sheaves: its motor's torque times speed
            if rope.over_sheaves and rope.mode == "winch":
                p = self.winch_torque(rope.name) * kin.input_rates[:, inputs.index(rope.name)]
                driver += p
                scale += np.abs(p)
        load = np.zeros(n)
        ev = self.evaluated
        for _, point, fx, fy in ev.forces:
            load += fx * v[:, point, 0] + fy * v[:, point, 1]
            scale += np.hypot(fx, fy) * speed[:, point]
        for body, reaction, tau in ev.torques:
            w = om[:, body] - om[:, reaction] if reaction >= 0 else om[:, body]
            load += tau * w
            scale += np.abs(tau * w)
        mp = self.mass
        if mp.massive:
            _, vs, acc = centre_of_mass(kin, mp)
            g = np.asarray(ev.gravity or (0.0, 0.0))
            for j in mp.massive:
                vsj = vs[:, j]
                load += mp.mass[j] * (vsj @ g)
                vmag = np.hypot(vsj[:, 0], vsj[:, 1])
                amag = np.hypot(acc[:, j, 0], acc[:, j, 1]) + float(np.hypot(*g))
                scale += mp.mass[j] * amag * vmag
                scale += np.abs(mp.inertia[j] * kin.body_epsilon[:, j] * om[:, j])
        for k, (i, _) in enumerate(sy.slots):
            scale += np.hypot(self.pin_force[:, k, 0], self.pin_force[:, k, 1]) * speed[:, i]
        for k, s in enumerate(sy.sliders):
            scale += np.abs(self.slider_force[:, k]) * speed[:, s[1]]
        return PowerBalance(driver, kinetic_energy_rate(kin, mp), load, scale)
