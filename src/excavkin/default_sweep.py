"""A sensible sweep of every input of a mechanism: what ``excavkin report`` and ``excavkin demo``
solve when no sweep is given.

A rotary input turns fully if the mechanism closes all the way round, else over the range
around its sketch value where it closes; a linear input sweeps its stroke (or 0.8 to 1.25 times
its sketch length) cut to where the mechanism closes. The range is found by solving probes, so
the caller solves here, once, before handing the result to an output.

>>> import excavkin
>>> from excavkin.default_sweep import default_sweep
>>> mech = excavkin.load(excavkin.example_path("fourbar"))
>>> sweep = default_sweep(mech)
>>> round(float(sweep["crank"][-1] - sweep["crank"][0]), 4)   # a full turn of the crank
6.2832
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from excavkin.mechanism import Mechanism

__all__ = ["N_LINEAR", "N_ROTARY", "STROKE", "default_sweep", "solve_default"]

#: samples in a default sweep of a rotary input (a full turn in 2° steps)
N_ROTARY = 181
#: samples in a default sweep of a linear input
N_LINEAR = 121
#: a linear input's default stroke, as fractions of its sketch length (a ratio of about 1.56,
#: a usual extended/retracted ratio of hydraulic cylinders)
STROKE = (0.8, 1.25)


def _run_containing(ok: np.ndarray, i0: int, circular: bool) -> tuple[int, int] | None:
    """Inclusive (start, stop) of the run of True containing ``i0``; stop < start if it wraps."""
    n = ok.size
    if not ok[i0]:
        return None
    if circular and ok.all():
        return 0, n - 1
    lo = i0
    while True:
        nxt = lo - 1
        if nxt < 0:
            if not circular:
                break
            nxt += n
        if not ok[nxt] or nxt == i0:
            break
        lo = nxt
    hi = i0
    while True:
        nxt = hi + 1
        if nxt >= n:
            if not circular:
                break
            nxt -= n
        if not ok[nxt] or nxt == i0:
            break
        hi = nxt
    return lo, hi


def _passable(code: np.ndarray) -> np.ndarray:
    """Samples a sweep may pass: solved, or exactly at a dead position it can go through."""
    from excavkin.kinematics.kernels import Code

    return np.asarray((code == Code.OK) | (code == Code.SINGULAR) | (code == Code.IMPRECISE))


def default_sweep(mech: Mechanism, n: int | None = None) -> dict[str, np.ndarray]:
    """A sensible sweep of every input of a mechanism, all moving together.

    * A rotary input turns a full turn, 0 to 2π (from the sketch value instead if 0 is a dead
      position), if the mechanism closes all the way round;
      otherwise it sweeps the range around the sketch over which it closes (found by probing
      720 positions), from one dead position to the other.
    * A linear input (a cylinder, a rope) sweeps its ``stroke`` when the model gives one,
      else from 0.8 to 1.25 times its sketch length (`STROKE`), cut to the range around
      the sketch over which the mechanism closes. A winch rope's motor angle sweeps so that
      its blocks' distance does that (its angle is proportional to that distance).

    Each input's range is found with the others held at their sketch values.

    Parameters
    ----------
    mech : Mechanism
    n : int, optional
        Samples; default 181 when any input is rotary, else 121.

    Returns
    -------
    dict of str to ndarray, shape (n,)
        Input values, SI, for [`Mechanism.solve`][excavkin.mechanism.Mechanism.solve]. Empty for a
        mechanism without inputs.
    """
    names = list(mech.inputs)
    if not names:
        return {}
    kinds = {name: mech.input_kind(name) for name in names}
    if n is None:
        n = N_ROTARY if "angle" in kinds.values() else N_LINEAR
    if n < 2:
        raise ValueError(f"n: a sweep needs at least 2 samples, got {n}")
    sketch = mech.sketch_values()
    out: dict[str, np.ndarray] = {}
    winches = {r.name for r in mech.model.ropes if r.mode == "winch"}
    for name in names:
        q0 = sketch[name]
        if kinds[name] == "angle" and name not in winches:
            m = 720
            probe = q0 + np.linspace(0.0, 2 * np.pi, m, endpoint=False)
            ok = _passable(mech.solve({name: probe}).status.code)
            run = _run_containing(ok, 0, circular=True)
            if run is None or run == (0, m - 1):
                # a full turn: from the reference orientation, or from the sketch if the
                # reference orientation is a dead position
                start = 0.0 if mech.solve({name: [0.0]}).status.all_ok else q0
                out[name] = start + np.linspace(0.0, 2 * np.pi, n)
                continue
            lo, hi = run
            # the run starts at or before the sketch (index 0: lo > 0 wraps round) and ends after
            start = probe[lo] - (2 * np.pi if lo > 0 else 0.0)
            out[name] = np.linspace(start, probe[hi], n)
        else:
            m = 401
            stroke = next((d.stroke for d in mech.model.linear if d.name == name), None)
            if stroke is not None:  # the cylinder's own stroke, pin to pin
                probe = np.linspace(stroke[0], stroke[1], m)
            else:
                probe = q0 * np.linspace(STROKE[0], STROKE[1], m)
            i0 = int(np.argmin(np.abs(probe - q0)))
            ok = _passable(mech.solve({name: probe}).status.code)
            run = _run_containing(ok, i0, circular=False)
            lo, hi = run if run is not None else (0, m - 1)
            out[name] = np.linspace(probe[lo], probe[hi], n)
    return out


def solve_default(mech: Mechanism, n: int | None = None) -> Any:
    """``mech.solve(default_sweep(mech, n))``: the result ``excavkin demo`` reports."""
    return mech.solve(default_sweep(mech, n))
