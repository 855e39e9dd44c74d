r"""Hydraulic power along the dig–swing–dump cycle of
[`cycle_time`][excavkin.excavator.hydraulics.cycle_time].

The cycle is played one motion at a time, each cylinder over its full stroke at its no-load,
full-flow speed ([`strokes`][excavkin.excavator.hydraulics.strokes]), from a start with the boom
down and the arm and bucket at the ends they dig from::

    dig: arm → dig: bucket → boom up → swing → dump: arm → dump: bucket → swing back → boom down

so that its duration is the ``sequential`` cycle time. Along it the power of each function
comes from [`motion_power`][excavkin.excavator.hydraulics.motion_power]: the front's weight and the
inertia of the motion (a cylinder at constant speed still swings its links at varying speeds),
no soil force. Speed steps between phases are taken as instantaneous. The swing motor is not
modelled: its phases carry no cylinder power.

Over a phase the cylinders' work ∫ f·L̇ dt equals the rise of the front's potential energy plus
that of its kinetic energy (the tests check it): positive when it lifts, negative when the
weight overruns the cylinder (the meter-out throttle then carries the load). A phase whose
inlet pressure would exceed the circuit's working pressure cannot run at full flow there: the
relief valve opens and the function slows or stalls. It is named, not hidden.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.excavator.hydraulics import (
    Hydraulics,
    Power,
    hydraulics_of,
    motion_power,
    strokes,
)
from excavkin.excavator.machine import ROLES, Machine

#: the cycle's phases in order: (label, cylinder role or None for a swing, dig direction?)
PHASES: tuple[tuple[str, str | None, bool], ...] = (
    ("dig: arm", "arm", True),
    ("dig: bucket", "bucket", True),
    ("boom up", "boom", True),
    ("swing", None, True),
    ("dump: arm", "arm", False),
    ("dump: bucket", "bucket", False),
    ("swing back", None, False),
    ("boom down", "boom", False),
)


@dataclass(frozen=True, slots=True)
class CyclePower:
    """Power along the cycle, sampled (SI).

    Attributes
    ----------
    time : ndarray, shape (n,)
        From the start of the cycle (s). A phase's last sample and the next one's first share
        a time.
    phase : ndarray of str, shape (n,)
    lengths, rates : ndarray, shape (n, 3)
        Cylinder lengths (m) and rates (m/s).
    power : Power
        Forces, pressures, flows and powers at each sample.
    phases : tuple of PhasePower
        Each phase's duration, peak power and work.
    supply : float
        The pumps' hydraulic power at full flow and the highest working pressure, Σ Q·p (W):
        a bound on what they can deliver.
    """

    time: F
    phase: np.ndarray
    lengths: F
    rates: F
    power: Power
    phases: tuple[PhasePower, ...]
    supply: float


@dataclass(frozen=True, slots=True)
class PhasePower:
    """One phase of the cycle (SI).

    Attributes
    ----------
    name : str
    role : str or None
        The moving cylinder (None for a swing).
    duration : float
    peak : float
        Largest total cylinder power over the phase (W).
    peak_pressure : float
        Largest inlet pressure of the moving cylinder (Pa).
    working_pressure : float
        Its circuit's working pressure (Pa); NaN for a swing.
    over_pressure : float
        Fraction of the phase's samples whose inlet pressure exceeds the working pressure:
        there the function cannot move at full flow.
    work : float
        ∫ total power dt over the phase (J), by Simpson's rule on the phase's samples.
    """

    name: str
    role: str | None
    duration: float
    peak: float
    peak_pressure: float
    working_pressure: float
    over_pressure: float
    work: float


def cycle_power(
    machine: Machine, hydraulics: Hydraulics | None = None, *, samples: int = 101
) -> CyclePower:
    """Power along the dig–swing–dump cycle (see the module's docstring).

    Parameters
    ----------
    machine : Machine
    hydraulics : Hydraulics, optional
        Default the machine's own.
    samples : int
        Samples per phase (odd, ≥ 3, for Simpson's rule).

    Returns
    -------
    CyclePower
    """
    from scipy.integrate import simpson

    from excavkin.errors import InputError

    if samples < 3 or samples % 2 == 0:
        raise InputError(f"samples per phase must be odd and at least 3, not {samples}")
    h = hydraulics_of(machine, hydraulics)
    st = {s.role: s for s in strokes(machine, h)}
    cyl = {c.role: c for c in machine.cylinders}
    lo, hi = machine.lengths_min, machine.lengths_max
    # the start: boom down, arm and bucket at the ends they dig from
    state = np.array(
        [lo[i] if (r == "boom" or cyl[r].dig == "extend") else hi[i] for i, r in enumerate(ROLES)]
    )
    t0 = 0.0
    times: list[F] = []
    labels: list[np.ndarray] = []
    lengths: list[F] = []
    rates: list[F] = []
    spans: list[tuple[str, str | None, float, slice]] = []
    for name, role, dig in PHASES:
        if role is None:
            duration = h.swing_angle / h.swing_speed
            L = np.broadcast_to(state, (samples, 3)).copy()
            R = np.zeros((samples, 3))
        else:
            i = ROLES.index(role)
            extend = (cyl[role].dig == "extend") == dig if role != "boom" else dig
            speed = st[role].extend_speed if extend else -st[role].retract_speed
            end = hi[i] if extend else lo[i]
            duration = abs(end - state[i]) / abs(speed)
            L = np.broadcast_to(state, (samples, 3)).copy()
            L[:, i] = np.linspace(state[i], end, samples)
            R = np.zeros((samples, 3))
            R[:, i] = speed
            state = L[-1].copy()
        start = len(times) * samples
        times.append(t0 + np.linspace(0.0, duration, samples))
        labels.append(np.full(samples, name))
        lengths.append(L)
        rates.append(R)
        spans.append((name, role, duration, slice(start, start + samples)))
        t0 += duration
    time = np.concatenate(times)
    L, R = np.concatenate(lengths), np.concatenate(rates)
    power = motion_power(machine, L, R)
    phases = []
    for name, role, duration, sl in spans:
        total = power.total[sl]
        pressure = power.pressure[sl, ROLES.index(role)] if role else np.zeros(1)
        working = machine.circuit(role).working if role else float("nan")
        work = float(simpson(total, x=time[sl])) if duration > 0.0 else 0.0
        over = float(np.mean(pressure > working)) if role else 0.0
        phases.append(
            PhasePower(
                name,
                role,
                float(duration),
                float(total.max()),
                float(pressure.max()),
                working,
                over,
                work,
            )  # fmt: skip
        )
    highest = max(c.working for c in machine.circuits.values())
    supply = float(sum(p.flow for p in h.pumps) * highest)
    return CyclePower(time, np.concatenate(labels), L, R, power, tuple(phases), supply)
