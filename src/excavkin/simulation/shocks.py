"""Shock report of a time-domain run: exact jumps of velocities and accelerations, and peaks.

A **hard shock** is a jump of a velocity (a driver's rate, a body's ω); a **soft shock**
(м'який удар, Pasika & Koruniak) is a jump of an acceleration (a driver's acceleration, a
body's ε). Both can only happen where a motion law is not smooth: at its start, its end and
the joins of its pieces (its *breakpoints*). They are found exactly, never from differences of
samples: at each breakpoint ``t_b`` the mechanism is solved twice, with the drivers' one-sided
limits ``q(t_b⁻), q'(t_b⁻), q''(t_b⁻)`` and ``q(t_b⁺), q'(t_b⁺), q''(t_b⁺)``
([`state`][excavkin.simulation.timeline.Drive.state])::

    Δω = ω(t_b⁺) − ω(t_b⁻)           Δε = ε(t_b⁺) − ε(t_b⁻)

Positions are continuous, so the two solves share the configuration and differ only in the
rates and accelerations they are fed; a body's ε at rest is ``u'(q)·q''`` (``u'`` the
first-order transfer function), so a jump of ``q''`` at rest gives ``Δε = u'·Δq''`` exactly.

A jump is reported when ``|Δ| > rtol · scale``, ``scale`` being the largest magnitude of that
quantity over the run and the one-sided limits, but at least the largest point speed (for
velocity-level quantities) or point acceleration (acceleration level) of the run — divided by
the mechanism's size for angular ones — so that the round-off of a quantity that is zero in
exact arithmetic is never reported. The report also gives, for every
acceleration-level quantity, its peak magnitude (over the samples and the one-sided limits,
the largest sample refined by local resampling) and, for bodies with a moment of inertia
``J`` (about the centre of mass), the inertia torque ``J·ε`` at the peak and ``J·Δε`` of each
soft shock.

Quantities (columns of `to_frame`)
-------------------------------------------------------------------------------
===================  ==================  =======================================
member               velocity level      acceleration level
===================  ==================  =======================================
moving body          ``<body>.omega``    ``<body>.epsilon``
rotary driver        ``<name>.rate``     ``<name>.accel``
linear element       ``<name>.rate``     ``<name>.accel`` (its length)
linear element line  ``<name>.omega``    ``<name>.epsilon`` (direction first→second point,
                                         e.g. a cylinder's angle)
===================  ==================  =======================================
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np

from excavkin.arrays import FloatArray
from excavkin.errors import InputError
from excavkin.kinematics import KinematicResult
from excavkin.mechanism import Mechanism
from excavkin.simulation.timeline import (
    DEFAULT_SAMPLES,
    Drive,
    DriveLaw,
    merge_breakpoints,
    normalise_drives,
    simulate,
)

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["Column", "Peak", "Shock", "ShockReport", "shock_report", "tracked_columns"]

ShockKind = Literal["hard", "soft"]

_REFINE_ROUNDS = 4
_REFINE_POINTS = 33  # odd: the window's centre is kept


@dataclass(frozen=True, slots=True)
class Column:
    """A tracked quantity: table column name, its member, order (1 velocity, 2 accel), unit."""

    name: str
    member: str
    quantity: str
    order: int
    unit: str
    inertia: float | None = None


def tracked_columns(mech: Mechanism) -> tuple[Column, ...]:
    """The velocity- and acceleration-level quantities a shock report looks at.

    Parameters
    ----------
    mech : Mechanism

    Returns
    -------
    tuple of Column
        Rotary drivers, linear elements (length and line direction), then moving bodies.
    """
    plan = mech.plan
    cols: list[Column] = []
    for name, kind in zip(plan.inputs, plan.input_kinds, strict=True):
        if kind == "angle":
            cols += [
                Column(f"{name}.rate", name, "rate", 1, "rad/s"),
                Column(f"{name}.accel", name, "accel", 2, "rad/s²"),
            ]
    for e in plan.elements:
        cols += [
            Column(f"{e.name}.rate", e.name, "rate", 1, "m/s"),
            Column(f"{e.name}.accel", e.name, "accel", 2, "m/s²"),
            Column(f"{e.name}.omega", e.name, "omega", 1, "rad/s"),
            Column(f"{e.name}.epsilon", e.name, "epsilon", 2, "rad/s²"),
        ]
    for j, b in enumerate(plan.bodies):
        if j == plan.ground or plan.body_base[j][0] < 0:
            continue
        inertia = mech.model.body(b).inertia
        cols += [
            Column(f"{b}.omega", b, "omega", 1, "rad/s", inertia),
            Column(f"{b}.epsilon", b, "epsilon", 2, "rad/s²", inertia),
        ]
    return tuple(cols)


def _values(result: KinematicResult, cols: tuple[Column, ...]) -> FloatArray:
    """Column values, shape (n, n_columns)."""
    if not cols:
        return np.empty((len(result), 0))
    return np.stack([np.asarray(result.column(c.name), dtype=np.float64) for c in cols], axis=1)


@dataclass(frozen=True, slots=True)
class Shock:
    """One jump of one quantity at one breakpoint.

    Attributes
    ----------
    time : float
        Breakpoint time [s].
    column : str
        Quantity, as a table column (``"rocker.epsilon"``).
    member, quantity : str
        The two halves of ``column``.
    kind : {"hard", "soft"}
        ``"hard"``: a velocity-level jump; ``"soft"``: an acceleration-level jump.
    before, after : float
        One-sided limits at ``time⁻`` and ``time⁺`` (SI).
    unit : str
    causes : tuple of str
        The drives' breakpoints at this time (``"cyl: start of cubic"``).
    inertia : float or None
        Moment of inertia ``J`` [kg·m²] of the body, for a body's ε with mass properties.
    """

    time: float
    column: str
    member: str
    quantity: str
    kind: ShockKind
    before: float
    after: float
    unit: str
    causes: tuple[str, ...]
    inertia: float | None = None

    @property
    def jump(self) -> float:
        """``after − before``."""
        return self.after - self.before

    @property
    def inertia_torque_jump(self) -> float | None:
        """``J·Δε`` [N·m] for a body's soft shock with mass properties, else ``None``."""
        if self.inertia is None or self.quantity != "epsilon" or self.kind != "soft":
            return None
        return self.inertia * self.jump


@dataclass(frozen=True, slots=True)
class Peak:
    """Largest magnitude of an acceleration-level quantity over a run.

    Attributes
    ----------
    column, member, quantity, unit : str
    value : float
        Signed value at the peak (SI).
    time : float
        When [s].
    side : {"sample", "left", "right"}
        Whether the peak is at a (refined) sample or a one-sided limit at a breakpoint.
    inertia : float or None
        ``J`` [kg·m²] for a body with mass properties.
    """

    column: str
    member: str
    quantity: str
    unit: str
    value: float
    time: float
    side: str
    inertia: float | None = None

    @property
    def magnitude(self) -> float:
        """``|value|``."""
        return abs(self.value)

    @property
    def inertia_torque(self) -> float | None:
        """``J·|ε|`` [N·m] at the peak for a body with mass properties, else ``None``."""
        if self.inertia is None or self.quantity != "epsilon":
            return None
        return self.inertia * self.magnitude


@dataclass(frozen=True, slots=True)
class ShockReport:
    """Exact jumps at the drives' breakpoints and peaks over a run.

    Attributes
    ----------
    times : ndarray, shape (n_breakpoints,)
        Breakpoint times [s], sorted.
    causes : tuple of tuple of str
        Per breakpoint, which drives' breakpoints meet there.
    columns : tuple of Column
        The tracked quantities (see `tracked_columns`).
    before, after : ndarray, shape (n_breakpoints, n_columns)
        One-sided limits at each breakpoint (NaN where the solve failed).
    shocks : tuple of Shock
        In time order, then column order.
    peaks : tuple of Peak
        One per acceleration-level column.
    """

    times: FloatArray
    causes: tuple[tuple[str, ...], ...]
    columns: tuple[Column, ...]
    before: FloatArray
    after: FloatArray
    shocks: tuple[Shock, ...]
    peaks: tuple[Peak, ...]

    @property
    def soft(self) -> tuple[Shock, ...]:
        """Soft shocks (acceleration jumps)."""
        return tuple(s for s in self.shocks if s.kind == "soft")

    @property
    def hard(self) -> tuple[Shock, ...]:
        """Hard shocks (velocity jumps)."""
        return tuple(s for s in self.shocks if s.kind == "hard")

    def of(self, member: str, kind: ShockKind | None = None) -> tuple[Shock, ...]:
        """Shocks of one member (``"rocker"``, ``"cyl"``), optionally of one kind."""
        return tuple(
            s for s in self.shocks if s.member == member and (kind is None or s.kind == kind)
        )

    def _index(self, column: str) -> int:
        for k, c in enumerate(self.columns):
            if c.name == column:
                return k
        raise KeyError(
            f"no tracked quantity {column!r}; tracked: {', '.join(c.name for c in self.columns)}"
        )

    def limit(self, column: str, time: float, side: Literal["left", "right"]) -> float:
        """One-sided limit of ``column`` at the breakpoint nearest ``time``.

        Raises
        ------
        KeyError
            Unknown column, or no breakpoint within ``1e-9·max(1, |time|)`` of ``time``.
        """
        c = self._index(column)
        if self.times.size:
            k = int(np.argmin(np.abs(self.times - time)))
            if abs(self.times[k] - time) <= 1e-9 * max(1.0, abs(time)):
                return float((self.before if side == "left" else self.after)[k, c])
        raise KeyError(f"no breakpoint at t = {time!r} s; breakpoints: {self.times.tolist()}")

    def peak(self, column: str) -> Peak:
        """The peak of an acceleration-level column (``"rocker.epsilon"``)."""
        for p in self.peaks:
            if p.column == column:
                return p
        raise KeyError(f"no peak for {column!r}; peaks: {', '.join(p.column for p in self.peaks)}")

    def to_frame(self) -> pd.DataFrame:
        """One row per shock: ``t, column, kind, before, after, jump, unit, J*jump, causes``."""
        import pandas as pd

        rows = [
            {
                "t": s.time,
                "column": s.column,
                "kind": s.kind,
                "before": s.before,
                "after": s.after,
                "jump": s.jump,
                "unit": s.unit,
                "J*jump [N*m]": s.inertia_torque_jump,
                "causes": "; ".join(s.causes),
            }
            for s in self.shocks
        ]
        cols = ["t", "column", "kind", "before", "after", "jump", "unit", "J*jump [N*m]", "causes"]
        return pd.DataFrame(rows, columns=cols)

    def peaks_frame(self) -> pd.DataFrame:
        """One row per peak: ``column, peak, value, t, unit, J*|eps| [N*m]``."""
        import pandas as pd

        rows = [
            {
                "column": p.column,
                "peak": p.magnitude,
                "value": p.value,
                "t": p.time,
                "unit": p.unit,
                "J*|eps| [N*m]": p.inertia_torque,
            }
            for p in self.peaks
        ]
        return pd.DataFrame(rows, columns=["column", "peak", "value", "t", "unit", "J*|eps| [N*m]"])

    def format(self) -> str:
        """The report as plain text (SI units)."""
        n_soft, n_hard = len(self.soft), len(self.hard)
        lines = [
            f"shock report: {self.times.size} breakpoint(s), {n_hard} hard shock(s) "
            f"(velocity jumps), {n_soft} soft shock(s) (acceleration jumps)"
        ]
        for k, tb in enumerate(self.times):
            here = [s for s in self.shocks if s.time == tb]
            head = f"  t = {tb:.6g} s ({'; '.join(self.causes[k])})"
            if not here:
                lines.append(head + ": smooth, no jump")
                continue
            lines.append(head + ":")
            for s in here:
                extra = ""
                if (tj := s.inertia_torque_jump) is not None:
                    extra = f"; J·Δε = {tj:+.6g} N·m"
                lines.append(
                    f"    {s.kind:<4}  {s.column:<24} {s.before:+.6g} → {s.after:+.6g} "
                    f"{s.unit} (Δ = {s.jump:+.6g}{extra})"
                )
        if self.peaks:
            lines.append("  peaks:")
            for p in self.peaks:
                extra = ""
                if (tq := p.inertia_torque) is not None:
                    extra = f", J·|ε| = {tq:.6g} N·m"
                at = f"t = {p.time:.6g} s" + ("" if p.side == "sample" else f"{_SUP[p.side]}")
                lines.append(
                    f"    {p.column:<24} |max| = {p.magnitude:.6g} {p.unit} at {at}{extra}"
                )
        return "\n".join(lines)


_SUP = {"left": "⁻", "right": "⁺"}


def _finite_max(a: FloatArray) -> float:
    """Largest finite magnitude in ``a`` (0 if none)."""
    m = np.abs(a)
    return float(np.max(m, initial=0.0, where=np.isfinite(m)))


def _refine_peak(
    mech: Mechanism,
    drives: Mapping[str, Drive],
    column: str,
    lo: float,
    hi: float,
    centre: float,
    value: float,
    held: Mapping[str, float] | None,
) -> tuple[float, float]:
    """Maximise ``|column|`` on ``[lo, hi]`` by repeated local resampling (shrinking windows)."""
    t_best, v_best = centre, value
    for _ in range(_REFINE_ROUNDS):
        if not hi > lo:
            break
        t = np.linspace(lo, hi, _REFINE_POINTS)
        vals = np.asarray(simulate(mech, drives, t=t, held=held).column(column), dtype=np.float64)
        if not np.any(np.isfinite(vals)):
            break
        k = int(np.nanargmax(np.abs(vals)))
        if abs(vals[k]) >= abs(v_best):
            t_best, v_best = float(t[k]), float(vals[k])
        step = t[1] - t[0]
        lo, hi = max(lo, t_best - step), min(hi, t_best + step)
    return t_best, v_best


def shock_report(
    mech: Mechanism,
    drives: Mapping[str, Drive | DriveLaw],
    result: KinematicResult | None = None,
    *,
    samples: int = DEFAULT_SAMPLES,
    rtol: float = 1e-9,
    refine: bool = True,
    held: Mapping[str, float] | None = None,
) -> ShockReport:
    """Hard and soft shocks of every driver, element and body, with peaks of ε and J·ε.

    Parameters
    ----------
    mech : Mechanism
    drives : mapping of str to Drive or law
        As for [`simulate`][excavkin.simulation.timeline.simulate].
    result : KinematicResult, optional
        A run of the same drives with a time column (for the peaks); default
        ``simulate(mech, drives, samples=samples)``.
    samples : int
        Grid size when ``result`` is not given.
    rtol : float
        A jump is reported when ``|Δ| > rtol · scale`` (``scale``: largest magnitude of the
        quantity over the run and the one-sided limits, at least the largest point speed or
        acceleration, per unit length for angular quantities; see the module notes).
    refine : bool
        Refine peaks that fall on a sample by local resampling (exact to ~1e-12 relative).
    held : mapping of str to float, optional
        Undriven drivers' values, as for ``simulate``.

    Returns
    -------
    ShockReport

    Examples
    --------
    >>> import excavkin
    >>> from excavkin.motion import get_law
    >>> mech = excavkin.load(excavkin.example_path("pasika_module"))
    >>> rep = shock_report(mech, {"cyl": get_law("cubic", 0.5, 5.0)}, samples=101)
    >>> [(s.time, round(s.jump, 4)) for s in rep.of("rocker", "soft")]
    [(0.0, 0.1203), (5.0, 0.1362)]
    >>> shock_report(mech, {"cyl": get_law("345", 0.5, 5.0)}, samples=101).soft
    ()
    """
    dd = normalise_drives(mech, drives)
    if result is None:
        result = simulate(mech, dd, samples=samples, held=held)
    if result.time is None:
        raise InputError("shock_report needs a result solved in time (see simulate)")
    cols = tracked_columns(mech)
    bps = merge_breakpoints(dd)
    times = np.array([tb for tb, _ in bps], dtype=np.float64)
    causes = tuple(c for _, c in bps)
    runs = [result]
    if times.size:
        runs += [simulate(mech, dd, t=times, side=side, held=held) for side in ("left", "right")]
        before, after = _values(runs[1], cols), _values(runs[2], cols)
    else:
        before = after = np.empty((0, len(cols)))
    samp = _values(result, cols)
    t = np.asarray(result.time, dtype=np.float64)

    stacked = np.abs(np.concatenate([samp, before, after], axis=0))
    scale = np.max(stacked, axis=0, initial=0.0, where=np.isfinite(stacked))
    # Floor of the scale: a quantity that is zero in exact arithmetic (a rod's acceleration
    # under a constant-speed law, recomputed from point accelerations) must not have its
    # round-off reported as a jump. Use the largest point speed / acceleration of the run
    # (divided by the mechanism's size for angular quantities).
    pv = max(_finite_max(r.velocities) for r in runs)
    pa = max(_finite_max(r.accelerations) for r in runs)
    size = mech.plan.scale if mech.plan.scale > 0.0 else 1.0
    floor = np.array(
        [(pv if c.order == 1 else pa) / (size if c.unit.startswith("rad") else 1.0) for c in cols]
    )
    scale = np.maximum(scale, floor)
    shocks: list[Shock] = []
    for k in range(times.size):  # loop over breakpoints, not samples
        for c, col in enumerate(cols):
            b, a = float(before[k, c]), float(after[k, c])
            if scale[c] > 0.0 and abs(a - b) > rtol * scale[c]:
                shocks.append(
                    Shock(
                        float(times[k]),
                        col.name,
                        col.member,
                        col.quantity,
                        "hard" if col.order == 1 else "soft",
                        b,
                        a,
                        col.unit,
                        causes[k],
                        col.inertia,
                    )
                )

    peaks: list[Peak] = []
    for c, col in enumerate(cols):
        if col.order != 2:
            continue
        # one-sided limits first, so that a tie with a sample at a breakpoint names the side
        cand_v = np.concatenate([before[:, c], after[:, c], samp[:, c]])
        cand_t = np.concatenate([times, times, t])
        if not np.any(np.isfinite(cand_v)):
            continue
        i = int(np.nanargmax(np.abs(cand_v)))
        nb = times.size
        side = "left" if i < nb else ("right" if i < 2 * nb else "sample")
        tp, vp = float(cand_t[i]), float(cand_v[i])
        if side == "sample" and refine and t.size > 2:
            i -= 2 * nb
            lo, hi = float(t[max(i - 1, 0)]), float(t[min(i + 1, t.size - 1)])
            tp, vp = _refine_peak(mech, dd, col.name, lo, hi, tp, vp, held)
        peaks.append(Peak(col.name, col.member, col.quantity, col.unit, vp, tp, side, col.inertia))
    return ShockReport(times, causes, cols, before, after, tuple(shocks), tuple(peaks))
