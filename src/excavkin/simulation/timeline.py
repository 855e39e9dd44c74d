"""Time-domain kinematics: drivers moved by motion laws, solved over a time grid.

A [`Drive`][excavkin.simulation.timeline.Drive] moves one driver of a
[`Mechanism`][excavkin.mechanism.Mechanism] from an initial
value (its sketch value unless given) by a law's displacement::

    q(t)   = q0 + σ·s(t)       q'(t) = σ·v(t)       q''(t) = σ·a(t)

with ``σ = +1`` for a [`MotionLaw`][excavkin.motion.MotionLaw], a `Profile`
and a `ConstantSpeedCrank`, and ``σ = −1`` for a
`RopeWinch` (hauling in shortens the rope: ``L = L0 − hauled``).
A law holds before its start and after its end, so a drive does too. Drivers without a drive
stay at their sketch values (rate and acceleration 0).

The solver receives the laws' exact values, rates and accelerations — never finite
differences — so the velocities and accelerations of every point and body are exact
(``DESIGN.md`` §4).

::

    q ^             ______ q0 + H           grid: [min start, max end] of the drives
      |          _-'                               (or start/duration), ``samples`` points
      |_______.-'
      +------+---------+---> t
        q0  start     end

One-sided limits
----------------
At a breakpoint of a law (its start, its end, the joins of its pieces) the acceleration may
jump (a *soft shock*) and in principle the velocity too (a *hard shock*).
[`Drive.state`][excavkin.simulation.timeline.Drive.state] with ``side="left"`` or ``"right"``
returns the exact one-sided limits
``q(t⁻), q'(t⁻), q''(t⁻)`` or ``q(t⁺), …``; `driver_inputs` passes them to the solver
for all drivers at once. `excavkin.simulation.shocks` builds its report on them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Literal

import numpy as np
import numpy.typing as npt

from excavkin.arrays import FloatArray
from excavkin.errors import InputError
from excavkin.kinematics import KinematicResult
from excavkin.mechanism import Mechanism
from excavkin.motion import ConstantSpeedCrank, MotionLaw, MotionState, Profile, RopeWinch

__all__ = [
    "Drive",
    "DriveLaw",
    "Side",
    "driver_inputs",
    "merge_breakpoints",
    "normalise_drives",
    "simulate",
    "time_grid",
]

DriveLaw = MotionLaw | Profile | ConstantSpeedCrank | RopeWinch
"""Anything that can move a driver in time."""
Side = Literal["left", "right"]

DEFAULT_SAMPLES = 501
_SNAP = 1e-12  # relative to the law's duration


def _law_one_sided(law: MotionLaw, t: FloatArray, side: Side | None) -> MotionState:
    """``law.evaluate(t)``, or its exact one-sided limits at ``t`` (shape (n,))."""
    if side is None:
        return law.evaluate(t)
    left = side == "left"
    h, T = law.stroke, law.duration
    if left:
        before, after = t <= law.start, t > law.end
    else:
        before, after = t < law.start, t >= law.end
    inside = ~(before | after)
    u = np.clip((t - law.start) / T, 0.0, 1.0)
    # A breakpoint time start + u_b·T need not map back to u_b exactly: snap to it, so the
    # limit is taken on the intended side of the breakpoint.
    for ub in law.breakpoints:
        u = np.where(np.abs(u - ub) <= _SNAP, ub, u)
    # The laws' pieces are evaluated with the same ``left`` flag their own
    # ``acceleration_jumps`` uses: left-open pieces for left limits, left-closed otherwise.
    f0, f1, f2, f3 = law._shape(u, left=left)
    zero = np.zeros_like(t)
    s = np.where(before, 0.0, np.where(after, h, h * f0))
    v = np.where(inside, (h / T) * f1, zero)
    a = np.where(inside, (h / T**2) * f2, zero)
    j = np.where(inside, (h / T**3) * f3, zero)
    return MotionState(s, v, a, j)


def _profile_one_sided(p: Profile, t: FloatArray, side: Side | None) -> MotionState:
    """Profile values; at a join ``side`` picks the earlier (left) or later (right) segment."""
    if side is None:
        return p.evaluate(t)
    starts = np.array([sg.law.start for sg in p.segments[1:]], dtype=np.float64)
    idx = np.searchsorted(starts, t, side="left" if side == "left" else "right")
    out = [np.empty_like(t) for _ in range(4)]
    for k, sg in enumerate(p.segments):  # loop over segments, not samples
        m = idx == k
        if not np.any(m):
            continue
        st = _law_one_sided(sg.law, t[m], side)
        out[0][m] = sg.offset + st.s
        for arr, val in zip(out[1:], (st.v, st.a, st.j), strict=True):
            arr[m] = val
    return MotionState(*out)


def _law_breakpoints(law: MotionLaw) -> list[tuple[float, str]]:
    out = []
    bps = law.breakpoints
    for k, u in enumerate(bps):
        if k == 0:
            what = f"start of {law.name}"
        elif k == len(bps) - 1:
            what = f"end of {law.name}"
        else:
            what = f"{law.name} at u = {u:.6g}"
        out.append((law.start + u * law.duration, what))
    return out


@dataclass(frozen=True, slots=True)
class Drive:
    """A driver moved by a law from an initial value.

    Parameters
    ----------
    law : MotionLaw, Profile, ConstantSpeedCrank or RopeWinch
        What moves the driver. Its displacement is added to ``initial`` (subtracted for a
        `RopeWinch`, whose displacement is the hauled-in length).
    initial : float or None
        Driver value the displacement starts from [m or rad]; ``None`` takes the driver's
        sketch value.

    Examples
    --------
    >>> from excavkin.motion import get_law
    >>> d = Drive(get_law("cubic", 0.5, 5.0), initial=0.8)
    >>> [round(float(x), 6) for x in d.state([0.0, 2.5, 9.0], 0.0).s]
    [0.8, 1.05, 1.3]
    """

    law: DriveLaw
    initial: float | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.law, MotionLaw | Profile | ConstantSpeedCrank | RopeWinch):
            raise TypeError(
                "Drive: law must be a MotionLaw, Profile, ConstantSpeedCrank or RopeWinch, got "
                f"{type(self.law).__name__}"
            )
        if self.initial is not None and not math.isfinite(self.initial):
            raise ValueError(f"Drive: initial must be finite, got {self.initial!r}")

    @property
    def sign(self) -> float:
        """``−1`` for a rope winch (hauling in shortens the rope), ``+1`` otherwise."""
        return -1.0 if isinstance(self.law, RopeWinch) else 1.0

    @property
    def interval(self) -> tuple[float, float] | None:
        """``(start, end)`` of the motion [s], or ``None`` for a drive that never stops."""
        law = self.law
        if isinstance(law, MotionLaw | Profile):
            return (law.start, law.end)
        if isinstance(law, RopeWinch) and law.motor_law is not None:
            return (law.motor_law.start, law.motor_law.end)
        return None

    def breakpoints(self) -> tuple[tuple[float, str], ...]:
        """Times where the law's pieces meet, with a label, in time order.

        Returns
        -------
        tuple of (float, str)
            Start, interior breakpoints and end of each law (joins of a profile once);
            empty for a constant-speed crank or winch, which are smooth.
        """
        law = self.law
        items: list[tuple[float, str]] = []
        if isinstance(law, MotionLaw):
            items = _law_breakpoints(law)
        elif isinstance(law, Profile):
            for k, sg in enumerate(law.segments):
                bps = _law_breakpoints(sg.law)
                if k > 0:  # the join is the previous segment's end
                    items[-1] = (items[-1][0], f"join {k} ({items[-1][1]} -> {bps[0][1]})")
                    bps = bps[1:]
                items += bps
        elif isinstance(law, RopeWinch) and law.motor_law is not None:
            items = [(t, f"winch motor: {w}") for t, w in _law_breakpoints(law.motor_law)]
        return tuple(items)

    def state(self, t: npt.ArrayLike, base: float, side: Side | None = None) -> MotionState:
        """Driver value, rate, acceleration and jerk at times ``t``.

        Parameters
        ----------
        t : array_like, shape (n,)
            Times [s].
        base : float
            Initial value used when ``initial`` is ``None`` (the sketch value).
        side : {"left", "right"} or None
            ``None``: the laws' own values (``law.evaluate``). ``"left"``/``"right"``: the exact
            one-sided limits ``t⁻``/``t⁺`` (they differ only at breakpoints).

        Returns
        -------
        MotionState
            ``s`` = driver value [m or rad], ``v`` = rate, ``a`` = acceleration, ``j`` = jerk;
            each shape (n,).
        """
        tt = np.atleast_1d(np.asarray(t, dtype=np.float64))
        law = self.law
        if isinstance(law, MotionLaw):
            st = _law_one_sided(law, tt, side)
        elif isinstance(law, Profile):
            st = _profile_one_sided(law, tt, side)
        elif isinstance(law, RopeWinch) and law.motor_law is not None:
            m = _law_one_sided(law.motor_law, tt, side)
            k = law.ratio
            st = MotionState(k * m.s, k * m.v, k * m.a, k * m.j)
        else:
            st = law.evaluate(tt)
        q0 = base if self.initial is None else self.initial
        sg = self.sign
        return MotionState(q0 + sg * st.s, sg * st.v, sg * st.a, sg * st.j)


def normalise_drives(mech: Mechanism, drives: Mapping[str, Drive | DriveLaw]) -> dict[str, Drive]:
    """Check drives against the mechanism's inputs and wrap bare laws in
    [`Drive`][excavkin.simulation.timeline.Drive].

    Parameters
    ----------
    mech : Mechanism
    drives : mapping of str to Drive or law
        Driver name → what moves it.

    Returns
    -------
    dict of str to Drive

    Raises
    ------
    InputError
        Unknown driver name, no drives, a crank on a linear driver or a winch on a rotary one.
    """
    if not drives:
        raise InputError("no drives: give at least one driver and its motion law")
    out: dict[str, Drive] = {}
    for name, d in drives.items():
        if name not in mech.inputs:
            raise InputError(
                f"unknown driver {name!r} for {mech.name!r}: its inputs are "
                f"{', '.join(mech.inputs) or 'none'}"
            )
        drive = d if isinstance(d, Drive) else Drive(d)
        kind = mech.input_kind(name)
        if isinstance(drive.law, ConstantSpeedCrank) and kind != "angle":
            raise InputError(f"driver {name!r} is linear (a length); a crank drives an angle")
        winches = {r.name for r in mech.model.ropes if r.mode == "winch"}
        if isinstance(drive.law, RopeWinch) and name in winches:
            raise InputError(
                f"driver {name!r} is a winch rope of the model, its input its motor's angle: "
                "drive the motor (a constant-speed crank at the motor's speed, or any law of "
                "its angle); the model's drum radius, gear ratio and parts give the rope's speed"
            )
        if isinstance(drive.law, RopeWinch) and kind != "length":
            raise InputError(f"driver {name!r} is rotary (an angle); a winch drives a length")
        out[name] = drive
    return out


def time_grid(
    drives: Mapping[str, Drive],
    *,
    samples: int = DEFAULT_SAMPLES,
    start: float | None = None,
    duration: float | None = None,
) -> FloatArray:
    """Evenly spaced times over the union of the drives' intervals.

    Parameters
    ----------
    drives : mapping of str to Drive
    samples : int
        Number of times, ``>= 2``.
    start : float, optional
        First time [s]; default the earliest start of a timed drive (0 if none).
    duration : float, optional
        Length of the grid [s]; default up to the latest end of a timed drive. Required when
        no drive has an end (only constant-speed winches), except that cranks alone default
        to one period of the slowest crank.

    Returns
    -------
    ndarray, shape (samples,)
        Times [s].
    """
    if samples < 2:
        raise InputError(f"samples must be at least 2, got {samples}")
    spans = [iv for d in drives.values() if (iv := d.interval) is not None]
    t0 = start if start is not None else (min(a for a, _ in spans) if spans else 0.0)
    if duration is not None:
        if not (math.isfinite(duration) and duration > 0.0):
            raise InputError(f"duration must be > 0, got {duration!r}")
        t1 = t0 + duration
    elif spans:
        t1 = max(b for _, b in spans)
    else:
        periods = [d.law.period for d in drives.values() if isinstance(d.law, ConstantSpeedCrank)]
        if not periods or len(periods) != len(drives) or not math.isfinite(max(periods)):
            raise InputError(
                "the drives never stop (constant-speed winch or crank): give a duration"
            )
        t1 = t0 + max(periods)
    if not t1 > t0:
        raise InputError(f"the time grid is empty: it would run from {t0!r} s to {t1!r} s")
    return np.linspace(t0, t1, samples)


def driver_inputs(
    mech: Mechanism,
    drives: Mapping[str, Drive | DriveLaw],
    t: npt.ArrayLike,
    side: Side | None = None,
    held: Mapping[str, float] | None = None,
) -> tuple[dict[str, FloatArray], dict[str, FloatArray], dict[str, FloatArray]]:
    """Values, rates and accelerations of the driven drivers at times ``t``.

    Parameters
    ----------
    mech : Mechanism
    drives : mapping of str to Drive or law
    t : array_like, shape (n,)
        Times [s].
    side : {"left", "right"} or None
        One-sided limits (see [`Drive.state`][excavkin.simulation.timeline.Drive.state]).
    held : mapping of str to float, optional
        Drivers without a drive held at these values (SI) instead of their sketch values.

    Returns
    -------
    values, rates, accels : dict of str to ndarray, each shape (n,)
        Ready for [`Mechanism.solve`][excavkin.mechanism.Mechanism.solve].
    """
    dd = normalise_drives(mech, drives)
    sketch = mech.sketch_values()
    tt = np.atleast_1d(np.asarray(t, dtype=np.float64))
    values, rates, accels = {}, {}, {}
    for name, d in dd.items():
        st = d.state(tt, sketch[name], side)
        values[name], rates[name], accels[name] = st.s, st.v, st.a
    for name, value in (held or {}).items():
        if name in dd:
            raise InputError(f"driver {name!r} is both driven and held")
        if name not in sketch:
            raise InputError(f"unknown driver {name!r} (drivers: {', '.join(sorted(sketch))})")
        if not np.isfinite(value):
            raise InputError(f"held value of {name!r} is not finite")
        values[name] = np.full(tt.shape, float(value))
        rates[name] = np.zeros(tt.shape)
        accels[name] = np.zeros(tt.shape)
    return values, rates, accels


def simulate(
    mech: Mechanism,
    drives: Mapping[str, Drive | DriveLaw],
    *,
    samples: int = DEFAULT_SAMPLES,
    t: npt.ArrayLike | None = None,
    start: float | None = None,
    duration: float | None = None,
    side: Side | None = None,
    strict: bool = False,
    held: Mapping[str, float] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> KinematicResult:
    """Solve a mechanism in time, its drivers moved by motion laws.

    Parameters
    ----------
    mech : Mechanism
    drives : mapping of str to Drive or law
        Driver name → [`Drive`][excavkin.simulation.timeline.Drive] (or a bare law, moved from the
        sketch value). Drivers
        not listed are held at their sketch values, or at ``held``.
    samples : int
        Number of times of the grid built by `time_grid` (ignored when ``t`` is given).
    t : array_like, shape (n,), optional
        Explicit sample times [s].
    start, duration : float, optional
        Grid start and length [s]; see `time_grid`.
    side : {"left", "right"} or None
        Solve at the one-sided limits of the inputs (see
        [`Drive.state`][excavkin.simulation.timeline.Drive.state]).
    strict : bool
        Raise [`SolveFailure`][excavkin.errors.SolveFailure] if a sample fails.
    held : mapping of str to float, optional
        Undriven drivers held at these values (SI) instead of their sketch values.
    progress : callable, optional
        ``progress(samples_done, samples)`` after each chunk of the solve
        ([`Mechanism.solve`][excavkin.mechanism.Mechanism.solve]'s).

    Returns
    -------
    KinematicResult
        With ``time`` of shape (n,): the ``t`` column of ``to_frame()``.

    Examples
    --------
    >>> import excavkin
    >>> from excavkin.motion import get_law
    >>> mech = excavkin.load(excavkin.example_path("pasika_module"))
    >>> res = simulate(mech, {"cyl": get_law("cubic", 0.5, 5.0)}, samples=11)
    >>> round(float(res.column("rocker.epsilon")[0]), 5)
    0.12031
    """
    dd = normalise_drives(mech, drives)
    if t is None:
        tt = time_grid(dd, samples=samples, start=start, duration=duration)
    else:
        tt = np.asarray(t, dtype=np.float64)
        if tt.ndim != 1 or tt.size == 0:
            raise InputError(f"t must have shape (n,) with n >= 1, got shape {tt.shape}")
    values, rates, accels = driver_inputs(mech, dd, tt, side, held)
    return mech.solve(values, rates, accels, time=tt, strict=strict, progress=progress)


def merge_breakpoints(
    drives: Mapping[str, Drive], *, rtol: float = 1e-12
) -> list[tuple[float, tuple[str, ...]]]:
    """All drives' breakpoints, merged where they coincide, in time order.

    Parameters
    ----------
    drives : mapping of str to Drive
    rtol : float
        Times closer than ``rtol · max(1, |t|)`` are one breakpoint.

    Returns
    -------
    list of (float, tuple of str)
        Time [s] and the causes (``"<driver>: <what>"``).
    """
    items: list[tuple[float, str]] = sorted(
        (tb, f"{name}: {what}") for name, d in drives.items() for tb, what in d.breakpoints()
    )
    merged: list[tuple[float, list[str]]] = []
    for tb, cause in items:
        if merged and abs(tb - merged[-1][0]) <= rtol * max(1.0, abs(tb)):
            merged[-1][1].append(cause)
        else:
            merged.append((tb, [cause]))
    return [(tb, tuple(c)) for tb, c in merged]
