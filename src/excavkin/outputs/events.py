"""What an engineer must be warned of in a result: dead positions, non-closure, shocks.

Found from the per-sample status (the solver's verdict) and the result's columns:

* **does not close** — runs of samples the solver could not assemble (``status`` not ``"ok"``);
* **dead position** — samples the solver flagged as singular, and samples where a transmission
  angle comes within ``dead_tol`` (3°) of 0 or π (a local minimum of its distance to them);
* **low transmission** — the worst transmission angle of each dyad and slider, when it drops below
  ``transmission_limit``;
* **shock** — a jump of a velocity (rigid shock) or acceleration (soft shock) column between two
  samples, much larger than its neighbours' steps.

All functions take a :class:`~excavkin.kinematics.KinematicResult`, any object with
``to_frame()``, or a DataFrame with the same columns.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import pandas as pd

_VELOCITY_KINDS = ("velocity", "angular_velocity")
_ACCEL_KINDS = ("acceleration", "angular_acceleration")


@dataclass(frozen=True, slots=True)
class Table:
    """A result as a table plus what its plan says about its columns.

    Attributes
    ----------
    frame : pandas.DataFrame
        One row per sample, SI.
    kinds : dict
        Column kinds known from the plan (driver values), see
        :func:`~excavkin.outputs.display_units.column_kinds`.
    plan : SolvePlan or None
    result : object or None
        The result the table came from, if any.
    """

    frame: pd.DataFrame
    kinds: dict[str, str] = field(default_factory=dict)
    plan: Any = None
    result: Any = None

    @property
    def ok(self) -> np.ndarray:
        """Boolean mask of solved samples, shape (n,)."""
        if "status" not in self.frame:
            return np.ones(len(self.frame), dtype=bool)
        return np.asarray(self.frame["status"].astype(str) == "ok")

    @property
    def labels(self) -> np.ndarray:
        """Per-sample status label, shape (n,)."""
        if "status" not in self.frame:
            return np.full(len(self.frame), "ok", dtype=object)
        return np.asarray(self.frame["status"].astype(str), dtype=object)


def as_table(data: Any, kinds: Mapping[str, str] | None = None) -> Table:
    """Wrap a result or a DataFrame as a :class:`Table`.

    Parameters
    ----------
    data : KinematicResult, object with ``to_frame()``, or pandas.DataFrame
        A result with a ``plan`` (or a ``kinematics`` result with one) gives the kinds of the
        driver columns.
    kinds : mapping, optional
        Further column kinds, which win.
    """
    import pandas as pd

    from excavkin.outputs.display_units import column_kinds

    if isinstance(data, Table):
        return Table(data.frame, {**data.kinds, **(kinds or {})}, data.plan, data.result)
    if isinstance(data, pd.DataFrame):
        frame, plan, result = data, None, None
        known = dict(frame.attrs.get("excavkin.kinds", {}))
    elif hasattr(data, "to_frame"):
        frame, result = data.to_frame(), data
        plan = getattr(data, "plan", None)
        if plan is None:
            plan = getattr(getattr(data, "kinematics", None), "plan", None)
        known = {}
    else:
        raise TypeError(f"expected a result or a pandas DataFrame, got {type(data).__name__}")
    if plan is not None:
        known.update(column_kinds(plan))
    known.update(kinds or {})
    return Table(frame, known, plan, result)


@dataclass(frozen=True, slots=True)
class Event:
    """One warning about a result.

    Attributes
    ----------
    kind : {"does not close", "dead position", "low transmission", "shock"}
    samples : ndarray of int
        The samples concerned (for a shock: the sample after the jump).
    message : str
        One sentence for a person.
    severity : {"error", "warning", "note"}
    """

    kind: str
    samples: np.ndarray
    message: str
    severity: str = "warning"


def varies(values: Any) -> bool:
    """Whether a column changes over its finite samples (beyond rounding), shape (n,) in."""
    v = np.asarray(values, dtype=np.float64)
    v = v[np.isfinite(v)]
    if v.size < 2:
        return False
    lo, hi = float(v.min()), float(v.max())
    return hi - lo > 1e-9 * max(abs(lo), abs(hi), 1e-300)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Inclusive (start, stop) of each run of True."""
    m = np.concatenate([[False], np.asarray(mask, dtype=bool), [False]])
    edges = np.flatnonzero(np.diff(m.astype(np.int8)))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def failed_runs(data: Any) -> list[tuple[int, int, str]]:
    """Runs of samples that did not solve, except lone dead positions.

    Returns
    -------
    list of (start, stop, label)
        Inclusive sample indices and the first sample's status label.
    """
    t = as_table(data)
    labels = t.labels
    bad = ~t.ok & ~np.char.startswith(labels.astype(str), "dead position")
    return [(a, b, str(labels[a])) for a, b in _runs(bad)]


def dead_samples(data: Any, dead_tol: float = np.radians(3.0)) -> np.ndarray:
    """Samples at or next to a dead position, sorted, shape (k,).

    Parameters
    ----------
    data : result or DataFrame
    dead_tol : float
        rad; a local minimum of a transmission angle's distance to 0 or π below this counts.
    """
    t = as_table(data)
    labels = t.labels.astype(str)
    found = set(np.flatnonzero(np.char.startswith(labels, "dead position")).tolist())
    for col in t.frame.columns:
        if not str(col).endswith(".transmission"):
            continue
        mu = np.asarray(t.frame[col], dtype=np.float64)
        dist = np.minimum(np.abs(mu), np.abs(np.pi - mu))
        d = np.where(np.isfinite(dist), dist, np.inf)
        left = np.concatenate([[np.inf], d[:-1]])
        right = np.concatenate([d[1:], [np.inf]])
        found |= set(np.flatnonzero((d < dead_tol) & (d <= left) & (d <= right)).tolist())
    return np.array(sorted(found), dtype=np.int64)


def shock_samples(data: Any, *, ratio: float = 25.0, floor: float = 0.05) -> dict[str, np.ndarray]:
    """Jumps in velocity and acceleration columns.

    A step between consecutive samples is a jump when it exceeds ``ratio`` times the median step
    of its column and ``floor`` times the column's range. Steps into or out of unsolved samples
    are ignored.

    Returns
    -------
    dict
        ``{column: sample indices after each jump}``, only columns with jumps.
    """
    from excavkin.outputs.display_units import kind_of

    t = as_table(data)
    out: dict[str, np.ndarray] = {}
    if len(t.frame) < 5:
        return out
    for col in t.frame.columns:
        kind = kind_of(str(col), t.kinds)
        if kind not in _VELOCITY_KINDS + _ACCEL_KINDS:
            continue
        y = np.asarray(t.frame[col], dtype=np.float64)
        step = np.abs(np.diff(y))
        finite = np.isfinite(step)
        if finite.sum() < 4:
            continue
        span = float(np.nanmax(y) - np.nanmin(y))
        if span <= 0.0:
            continue
        typical = float(np.median(step[finite]))
        jump = finite & (step > ratio * typical) & (step > floor * span)
        if jump.any():
            out[str(col)] = np.flatnonzero(jump) + 1
    return out


def find_events(
    data: Any,
    *,
    dead_tol: float = np.radians(3.0),
    transmission_limit: float = np.radians(30.0),
    describe_sample: Any = None,
) -> list[Event]:
    """Every warning about a result, most serious first.

    Parameters
    ----------
    data : result or DataFrame
    dead_tol : float
        rad, see :func:`dead_samples`.
    transmission_limit : float
        rad; a transmission angle closer than this to 0 or π is reported as a note.
    describe_sample : callable, optional
        ``describe_sample(i) -> str`` names sample ``i`` in messages (e.g. ``"crank = 35°"``);
        the default is ``"sample i"``.

    Returns
    -------
    list of Event
    """
    t = as_table(data)
    name = describe_sample or (lambda i: f"sample {i}")
    events: list[Event] = []
    for a, b, label in failed_runs(t):
        where = (
            f"sample {a} ({name(a)})" if a == b else (f"samples {a}–{b} ({name(a)} … {name(b)})")
        )
        events.append(Event("does not close", np.arange(a, b + 1), f"{label}: {where}", "error"))
    dead = dead_samples(t, dead_tol)
    if dead.size:
        shown = "; ".join(f"{int(i)} ({name(int(i))})" for i in dead[:8])
        more = f" and {dead.size - 8} more" if dead.size > 8 else ""
        events.append(
            Event(
                "dead position",
                dead,
                f"at or within {np.degrees(dead_tol):.0f}° of a dead position: "
                f"sample{'s' if dead.size > 1 else ''} {shown}{more}",
                "warning",
            )
        )
    for col, idx in shock_samples(t).items():
        kind = "rigid" if col.rsplit(".", 1)[-1] in ("vx", "vy", "omega", "rate") else "soft"
        shown = ", ".join(f"{int(i)} ({name(int(i))})" for i in idx[:5])
        more = f" and {idx.size - 5} more" if idx.size > 5 else ""
        events.append(
            Event(
                "shock",
                idx,
                f"{kind} shock: {col} jumps at sample{'s' if idx.size > 1 else ''} {shown}{more}",
                "warning",
            )
        )
    for col in t.frame.columns:
        if not str(col).endswith(".transmission"):
            continue
        mu = np.asarray(t.frame[col], dtype=np.float64)
        dist = np.minimum(np.abs(mu), np.abs(np.pi - mu))
        if not np.isfinite(dist).any():
            continue
        i = int(np.nanargmin(dist))
        if dist[i] < transmission_limit:
            point = str(col).rsplit(".", 1)[0]
            events.append(
                Event(
                    "low transmission",
                    np.array([i]),
                    f"transmission angle at {point} reaches {np.degrees(mu[i]):.1f}° "
                    f"(limit {np.degrees(transmission_limit):.0f}° from 0° or 180°) at sample {i} "
                    f"({name(i)})",
                    "note",
                )
            )
    return events
