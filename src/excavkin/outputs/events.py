"""What an engineer must be warned of in a result: non-closure, dead positions, shocks.

Every warning is exact, taken from what the solver and the motion laws know, never guessed from
differences of samples:

* **does not close** — runs of samples the solver could not assemble (their status codes);
* **dead position** — samples the solver flagged as singular (status code), and samples where a
  transmission angle comes within ``dead_tol`` (3°) of 0 or π (a local minimum of its distance
  to them, read from the transmission columns);
* **change point** — a dyad folding flat between two neighbouring samples
  (``result.change_points``), and how the engine went on;
* **low transmission** — the worst transmission angle of each dyad and slider, when it drops below
  ``transmission_limit``;
* **shock** — for runs in time, the jumps of velocity (hard) and acceleration (soft) that the
  exact shock report ([`excavkin.simulation.shocks.shock_report`][]) found at the motion
  laws' breakpoints, when it is given.

All functions take a [`KinematicResult`][excavkin.kinematics.KinematicResult], a
[`ForceResult`][excavkin.kinetostatics.ForceResult] or a DataFrame with the same columns.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
import numpy.typing as npt

from excavkin.kinematics.columns import Column, columns_from_names
from excavkin.kinematics.kernels import Code

if TYPE_CHECKING:
    import pandas as pd

    from excavkin.outputs.protocols import SampleNamer, TableData


class ShockLike(Protocol):
    """One exact shock of a run in time (`excavkin.simulation.shocks.Shock`)."""

    @property
    def time(self) -> float: ...

    @property
    def column(self) -> str: ...

    @property
    def kind(self) -> str: ...

    @property
    def before(self) -> float: ...

    @property
    def after(self) -> float: ...


#: status labels' openings → codes, for tables read back from files (the one fallback)
_LABEL_CODES = (
    ("dead position", Code.SINGULAR),
    ("cannot close", Code.NO_CLOSURE),
    ("newton did not converge", Code.NO_CONVERGENCE),
    ("out of reach", Code.OUT_OF_REACH),
    ("assembly branch changed", Code.BRANCH_CHANGED),
    ("undetermined", Code.UNDETERMINED),
    ("a result overflows", Code.NOT_FINITE),
    ("rates lose precision", Code.IMPRECISE),
)


def codes_from_labels(labels: np.ndarray) -> np.ndarray:
    """Status codes from status labels: for a table without its result, shape (n,)."""
    text = np.char.lower(labels.astype(str))
    codes = np.where(text == "ok", int(Code.OK), int(Code.BAD_INPUT)).astype(np.int8)
    for opening, code in _LABEL_CODES:
        codes[np.char.startswith(text, opening)] = code
    return codes


@dataclass(frozen=True, slots=True)
class Table:
    """A result as a table, with what each column is and each sample's status code.

    Attributes
    ----------
    frame : pandas.DataFrame
        One row per sample, SI.
    columns : dict of str to Column
        Every column's description, by name.
    codes : ndarray of int8, shape (n,)
        Status codes (`Code`).
    plan : SolvePlan or None
    result : object or None
        The result the table came from, if any.
    """

    frame: pd.DataFrame
    columns: dict[str, Column] = field(default_factory=dict)
    codes: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int8))
    plan: Any = None
    result: Any = None

    @property
    def kinds(self) -> dict[str, str]:
        """Every column's kind, by name."""
        return {name: c.kind for name, c in self.columns.items()}

    @property
    def ok(self) -> np.ndarray:
        """Boolean mask of solved samples, shape (n,)."""
        return np.asarray(self.codes == Code.OK)

    @property
    def labels(self) -> np.ndarray:
        """Per-sample status label, shape (n,)."""
        if "status" not in self.frame:
            return np.full(len(self.frame), "ok", dtype=object)
        return np.asarray(self.frame["status"].astype(str), dtype=object)

    def describe(self, name: str) -> Column:
        """The description of a column (of any name: ``t``, ``sample`` and unknown ones too)."""
        return self.columns.get(name) or columns_from_names([name])[0]

    def of_quantity(self, quantity: str, owner_kind: str | None = None) -> list[str]:
        """Names of the columns of this quantity (and owner kind), in table order."""
        return [
            n
            for n, c in self.columns.items()
            if c.quantity == quantity and (owner_kind is None or c.owner_kind == owner_kind)
        ]

    def of_kind(self, *kinds: str, quantity: str | None = None) -> list[str]:
        """Names of the columns of these kinds (and this quantity, if given), in table order."""
        return [
            n
            for n, c in self.columns.items()
            if c.kind in kinds and (quantity is None or c.quantity == quantity)
        ]


def as_table(data: TableData, kinds: Mapping[str, str] | None = None) -> Table:
    """Wrap a result or a DataFrame as a `Table`.

    Parameters
    ----------
    data : KinematicResult, ForceResult, Table or pandas.DataFrame
        A result describes its own columns and gives its status codes; a DataFrame's columns
        are described by [`columns_from_names`][excavkin.kinematics.columns.columns_from_names]
        (with the
        kinds its ``attrs`` keep) and its codes read from its status labels.
    kinds : mapping, optional
        Column kinds that win over the description.
    """
    import pandas as pd

    if isinstance(data, Table):
        frame, described, codes, plan, result = (
            data.frame,
            list(data.columns.values()),
            data.codes,
            data.plan,
            data.result,
        )
    elif isinstance(data, pd.DataFrame):
        frame, plan, result = data, None, None
        described = columns_from_names(frame.columns, frame.attrs.get("excavkin.kinds", {}))
        labels = frame["status"] if "status" in frame else pd.Series(["ok"] * len(frame))
        codes = codes_from_labels(np.asarray(labels.astype(str)))
    elif hasattr(data, "to_frame") and hasattr(data, "columns"):
        frame, result = data.to_frame(), data
        kin: Any = getattr(data, "kinematics", data)  # a ForceResult's own kinematics
        plan = kin.plan
        described = list(data.columns)
        codes = np.asarray(kin.status.code, dtype=np.int8)
    else:
        raise TypeError(f"expected a result or a pandas DataFrame, got {type(data).__name__}")
    cols = {c.name: c for c in described if c.name in frame}
    for name, kind in (kinds or {}).items():
        if name in cols:
            c = cols[name]
            cols[name] = Column(c.name, c.owner, c.owner_kind, c.quantity, kind)
    return Table(frame, cols, codes, plan, result)


@dataclass(frozen=True, slots=True)
class Event:
    """One warning about a result.

    Attributes
    ----------
    kind : {"does not close", "dead position", "change point", "low transmission", "shock"}
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


def varies(values: npt.ArrayLike) -> bool:
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


def failed_runs(data: TableData) -> list[tuple[int, int, str]]:
    """Runs of samples that did not solve for one reason (one status code), dead positions
    aside.

    Returns
    -------
    list of (start, stop, label)
        Inclusive sample indices and the first sample's status label.
    """
    t = as_table(data)
    bad = (t.codes != Code.OK) & (t.codes != Code.SINGULAR)
    labels = t.labels
    out = []
    for a, b in _runs(bad):
        cuts = [a, *(a + 1 + np.flatnonzero(np.diff(t.codes[a : b + 1]))).tolist(), b + 1]
        out += [
            (int(lo), int(hi) - 1, str(labels[lo])) for lo, hi in zip(cuts, cuts[1:], strict=False)
        ]
    return out


def _worst(kin: Any, a: int, b: int) -> str:
    """For a run of samples out of reach (a, b inclusive), how far at worst its first
    sample's constraint is missed over the samples that name it: ``", by up to 35.9 mm too
    long"``; ``""`` for a run that is not, or a table without its result."""
    status = getattr(kin, "status", None)
    miss = getattr(status, "miss", None)
    if miss is None or status is None or status.code[a] != Code.OUT_OF_REACH:
        return ""
    run = np.where(status.unmet[a : b + 1] == status.unmet[a], np.abs(miss[a : b + 1]), np.nan)
    if not np.isfinite(run).any():
        return ""
    return f", by up to {status.shortfall(a + int(np.nanargmax(run)), 'mm')}"


def dead_samples(data: TableData, dead_tol: float = np.radians(3.0)) -> np.ndarray:
    """Samples at or next to a dead position, sorted, shape (k,).

    Parameters
    ----------
    data : result or DataFrame
    dead_tol : float
        rad; a local minimum of a transmission angle's distance to 0 or π below this counts.
    """
    t = as_table(data)
    found = set(np.flatnonzero(t.codes == Code.SINGULAR).tolist())
    for col in t.of_kind("angle", quantity="transmission"):
        mu = np.asarray(t.frame[col], dtype=np.float64)
        dist = np.minimum(np.abs(mu), np.abs(np.pi - mu))
        d = np.where(np.isfinite(dist), dist, np.inf)
        left = np.concatenate([[np.inf], d[:-1]])
        right = np.concatenate([d[1:], [np.inf]])
        found |= set(np.flatnonzero((d < dead_tol) & (d <= left) & (d <= right)).tolist())
    return np.array(sorted(found), dtype=np.int64)


def find_events(
    data: TableData,
    *,
    dead_tol: float = np.radians(3.0),
    transmission_limit: float = np.radians(30.0),
    describe_sample: SampleNamer | None = None,
    shocks: Sequence[ShockLike] = (),
) -> list[Event]:
    """Every warning about a result, most serious first.

    Parameters
    ----------
    data : result or DataFrame
    dead_tol : float
        rad, see `dead_samples`.
    transmission_limit : float
        rad; a transmission angle closer than this to 0 or π is reported as a note.
    describe_sample : callable, optional
        ``describe_sample(i) -> str`` names sample ``i`` in messages (e.g. ``"crank = 35°"``);
        the default is ``"sample i"``.
    shocks : sequence of Shock, optional
        For a run in time: the exact shock report's shocks (``report.shocks`` of
        [`excavkin.simulation.shocks.shock_report`][]), listed as warnings.

    Returns
    -------
    list of Event
    """
    t = as_table(data)
    name = describe_sample or (lambda i: f"sample {i}")
    events: list[Event] = []
    kin = getattr(t.result, "kinematics", t.result)
    for a, b, label in failed_runs(t):
        where = (
            f"sample {a} ({name(a)})" if a == b else (f"samples {a}–{b} ({name(a)} … {name(b)})")
        )
        message = f"{label}: {where}{_worst(kin, a, b)}"
        events.append(Event("does not close", np.arange(a, b + 1), message, "error"))
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
    for cp in getattr(kin, "change_points", ()):
        where = f"{name(cp.before)} … {name(cp.after)}"
        events.append(
            Event(
                "change point",
                np.array([cp.before, cp.after]),
                f"{cp.describe()} ({where})",
                "warning",
            )
        )
    for sh in shocks:
        message = (
            f"{sh.kind} shock: {sh.column} jumps from {sh.before:.6g} to {sh.after:.6g} "
            f"at t = {sh.time:.6g} s"
        )
        events.append(Event("shock", np.array([], dtype=np.int64), message, "warning"))
    for col in t.of_kind("angle", quantity="transmission"):
        mu = np.asarray(t.frame[col], dtype=np.float64)
        dist = np.minimum(np.abs(mu), np.abs(np.pi - mu))
        if not np.isfinite(dist).any():
            continue
        i = int(np.nanargmin(dist))
        if dist[i] < transmission_limit:
            point = t.columns[col].owner
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
