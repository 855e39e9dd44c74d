"""A design study: a model, a box of design parameters sampled by a design of experiments, pose
sets, metrics and constraints — evaluated chunk by chunk of designs, each chunk one batch
solve, and written as a Parquet table with one row per design.

A study is streamed: each finished chunk is kept as a part file in a folder beside the output
(``.NAME.parts/``), so that an interrupted study resumes where it stopped (finished chunks are
skipped), and the table is assembled and moved into place only when every chunk is done. The
chunks may run here or on a Dask cluster; either way each is the same batch solve, so the
results are identical.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import os
import shutil
import sys
import threading
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from excavkin.errors import InputError
from excavkin.execution import Execution, current, settings, use
from excavkin.studies.design_space import METHODS, sample_designs
from excavkin.studies.metrics import (
    Constraint,
    Metric,
    Poses,
    check_pose_sets,
    needs_forces,
    pose_sets_of,
    probe_execution,
)

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.mechanism import Mechanism
    from excavkin.studies.plots import StudyPlot

#: samples (designs × poses) solved at once by the full solve (a study with loads, a model
#: with a Newton group, a machine's study): it holds every sample's whole state (a few hundred
#: bytes to a few kB a sample), so that a chunk's arrays stay within a few hundred MB
CHUNK_SAMPLES = 1 << 18
#: samples solved at once by a study whose metrics are fused
#: ([`evaluate_fused`][excavkin.studies.fused.evaluate_fused]): it keeps only the metrics'
#: series, the statuses and the inputs (about 34 B a sample for the four-bar's three
#: metrics; its solves' workspaces are per thread, not per chunk), so 2²¹ samples hold
#: ≈ 68 MB. A chunk carries serial work of its own, in Python and holding the GIL — its
#: designs' points, its precision check, its table and Parquet part, ≈ 3–5 ms whatever its
#: size — against ≈ 80 ms of its kernel for 2²¹ samples on one core: at 2¹⁸ that work held
#: the GIL a fifth of a study's wall time on two cores, at 2²⁰ 8–13 %, at 2²¹ 5–8 %
#: (`benchmarks/bench_study.py`)
FUSED_CHUNK_SAMPLES = 1 << 21
#: samples (designs × poses) below which a study run with ``backend="auto"`` in a process that
#: has not imported numba runs on NumPy: importing numba and loading a cached kernel takes about
#: half a second, which the compiled solve (≈ 0.15 µs a sample faster) repays only past
#: millions of samples
SMALL_STUDY = 1_000_000
#: the finished parts' tables kept in memory, at most (bytes), so that the table is assembled
#: without reading them back (the rest are read from their files)
KEEP_BYTES = 1 << 28


@dataclass(frozen=True)
class Study:
    """What a study evaluates (all values SI).

    Attributes
    ----------
    model : Path
        The model file.
    bounds : dict of str to (float, float)
        Design parameters (names of ``Mechanism.parameters``) and their bounds.
    poses : Poses
        The default pose set (the metrics that name no set read it).
    metrics : tuple of Metric
    constraints : tuple of Constraint
    method : {"sobol", "halton", "lhs", "grid"}
    samples : int
        Designs (for a grid: levels per parameter).
    seed : int
        Seed of the sampling (not used by a grid).
    loads : "model" or None
        Solve the kinetostatics under the model's loads (needed by force metrics).
    optimize : dict
        The file's ``[optimize]`` table (objective, sense, method, maxiter, popsize), the
        defaults of [`optimize_study`][excavkin.studies.optimize.optimize_study].
    units : dict of str to str
        The units to show results in (not part of what is computed): of each design parameter
        (``design.NAME``) and metric, as the study file writes them; SI where absent.
    pose_sets : dict of str to Poses
        Named pose sets besides the default one; every design is solved at every pose of
        every set (`excavkin.studies.metrics.pose_sets_of`).
    """

    model: Path
    bounds: dict[str, tuple[float, float]]
    poses: Poses
    metrics: tuple[Metric, ...]
    constraints: tuple[Constraint, ...] = ()
    method: str = "sobol"
    samples: int = 1024
    seed: int = 0
    loads: str | None = None
    units: dict[str, str] = field(default_factory=dict)
    optimize: dict[str, Any] = field(default_factory=dict)
    pose_sets: dict[str, Poses] = field(default_factory=dict)

    @property
    def designs(self) -> int:
        return self.samples ** len(self.bounds) if self.method == "grid" else self.samples

    @property
    def sets(self) -> dict[str | None, Poses]:
        """Every pose set solved, by name (None: the default set)."""
        return pose_sets_of(self.poses, self.pose_sets)

    @property
    def pose_count(self) -> int:
        """The poses each design is solved at, over every set."""
        return sum(p.count for p in self.sets.values())

    @property
    def motion_note(self) -> str:
        """What the force metrics are (``""`` without loads): static when the poses give no
        rates, the swept drivers given none taken at rest (``ForceResult.motion_note``)."""
        if self.loads is None:
            return ""
        from excavkin.kinetostatics.result import motion_note

        notes = []
        for name, poses in self.sets.items():
            unrated = [
                k for k, v in poses.values.items() if np.ndim(v) == 1 and k not in poses.rates
            ]
            given = [*poses.rates.values(), *poses.accels.values()]
            note = motion_note(not any(np.any(np.asarray(v) != 0.0) for v in given), unrated)
            notes.append(note if name is None else f"set {name!r}: {note}")
        return "; ".join(notes)

    def prepare(self) -> tuple[dict[str, str], str]:
        """Refuse, before any solve, unknown parameters, columns and metric names; return each
        column's kind and the model's name, for the table's metadata.

        Returns
        -------
        kinds : dict of str to str
            ``design.<parameter>`` and each metric → its physical kind (``"length"``,
            ``"angle"``, ``"dimensionless"`` …).
        name : str
            The model's name.

        Raises
        ------
        InputError
            An unknown parameter, column, metric or sampling method, or a force metric
            without loads.
        """
        mech = _check(self)
        return _kinds(self, mech), mech.name

    def evaluate_chunk(self, start: int, stop: int) -> pd.DataFrame:
        """The designs ``start:stop``: their rows, with their ``design`` index. A pure function
        of the study, so that it can run anywhere (a Dask worker).

        Parameters
        ----------
        start, stop : int
            The first design and one past the last, in the design of experiments' order.

        Returns
        -------
        pandas.DataFrame
            A first column ``design`` (their index), then ``design.<parameter>`` columns, one
            per metric, ``poses_failed``, ``feasible`` and ``status``, as
            `excavkin.studies.metrics.evaluate` gives them.
        """
        import pandas as pd

        return pd.DataFrame(self.chunk_columns(start, stop))

    def chunk_columns(self, start: int, stop: int) -> dict[str, Any]:
        """`evaluate_chunk`'s columns by name, in the table's order, without making the table
        where the metrics are fused
        ([`evaluate_fused_columns`][excavkin.studies.fused.evaluate_fused_columns]): a
        local run writes them as Arrow arrays (`part_table`).

        Parameters
        ----------
        start, stop : int
            The first design and one past the last.

        Returns
        -------
        dict of str to array
            ``design`` first, one value per design each.
        """
        from excavkin.studies.fused import evaluate_fused_columns, fusable
        from excavkin.studies.metrics import evaluate

        mech = _mechanism(self.model)
        part = sample_designs(self.bounds, self.samples, self.method, self.seed, (start, stop))
        args = (mech, part, self.poses, self.metrics, self.constraints)
        if fusable(mech, self.loads):
            columns = evaluate_fused_columns(*args, self.pose_sets)
        else:
            frame = evaluate(*args, self.loads, self.pose_sets)
            columns = {str(c): frame[c] for c in frame.columns}
        return {"design": np.arange(start, stop), **columns}

    def chunk_samples(self) -> int:
        """The samples (designs × poses) a chunk of the study solves by default: the fused
        evaluation's `FUSED_CHUNK_SAMPLES` where it applies
        ([`fusable`][excavkin.studies.fused.fusable]), else the full solve's
        `CHUNK_SAMPLES`. The same on every machine (the cores decide how many chunks run at
        once, and on how many threads each, never a chunk's designs): a chunk's results
        depend on where its blocks start (their precision check's scales), so a study's
        table is the same wherever it runs.

        Returns
        -------
        int
        """
        from excavkin.studies.fused import fusable

        mech = _mechanism(self.model)
        fused = fusable(mech, self.loads)
        return FUSED_CHUNK_SAMPLES if fused else CHUNK_SAMPLES

    def fingerprint(self) -> str:
        """A hash of everything that decides the results (the model file's text included), so
        that parts of another study are never mixed in.

        Returns
        -------
        str
            16 hexadecimal digits of a SHA-256.
        """
        from excavkin.io.toml_model import read_text_file

        def listed(poses: Poses) -> list[dict[str, Any]]:
            return [
                {k: np.asarray(v).tolist() for k, v in part.items()}
                for part in (poses.values, poses.rates, poses.accels)
            ]

        def metric(m: Metric) -> tuple[Any, ...]:
            # a metric of the default set, not a clearance, as before pose sets existed
            extra = () if m.poses is None and m.clearance is None else (m.poses, m.clearance)
            return (m.name, m.column, m.reduce, m.target, *extra)

        contents: dict[str, Any] = {
            "model": read_text_file(self.model),
            "bounds": self.bounds,
            "poses": listed(self.poses),
            "metrics": [metric(m) for m in self.metrics],
            "constraints": [(c.metric, c.low, c.high) for c in self.constraints],
            "sampling": (self.method, self.samples, self.seed),
            "loads": self.loads,
        }
        if self.pose_sets:
            contents["pose_sets"] = {k: listed(v) for k, v in self.pose_sets.items()}
        text = json.dumps(contents, sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


class Subject(Protocol):
    """What [`run_study`][excavkin.studies.study.run_study] runs: a
    [`Study`][excavkin.studies.study.Study] of a model, or a study of another
    subject (a machine) with the same sampling, chunks and table."""

    @property
    def designs(self) -> int: ...

    @property
    def pose_count(self) -> int: ...

    @property
    def motion_note(self) -> str:
        """What the study's force metrics are (static or with inertia), or ``""``."""
        ...

    def fingerprint(self) -> str: ...

    def prepare(self) -> tuple[dict[str, str], str]: ...

    def evaluate_chunk(self, start: int, stop: int) -> pd.DataFrame: ...


def chunks(study: Subject, chunk_samples: int | None = None) -> list[tuple[int, int]]:
    """The designs' index ranges, each solved as one batch: ``chunk_samples`` samples
    (designs × poses) each, default `default_chunk_samples`, a whole number of designs (one
    at least).

    Parameters
    ----------
    study : Study
    chunk_samples : int, optional

    Returns
    -------
    list of (int, int)
        ``(start, stop)`` of each chunk's designs, in order.
    """
    size = default_chunk_samples(study) if chunk_samples is None else chunk_samples
    per = max(1, size // study.pose_count)
    n = study.designs
    return [(s, min(s + per, n)) for s in range(0, n, per)]


def default_chunk_samples(study: Subject) -> int:
    """The samples a chunk of ``study`` solves unless told: a `Study`'s own
    (`Study.chunk_samples`: `FUSED_CHUNK_SAMPLES` for fused metrics, else `CHUNK_SAMPLES`),
    `CHUNK_SAMPLES` for another subject (a machine's study, solved whole).

    Parameters
    ----------
    study : Study

    Returns
    -------
    int
    """
    return study.chunk_samples() if isinstance(study, Study) else CHUNK_SAMPLES


def evaluate_chunk(
    study: Subject, start: int, stop: int, execution: Execution | None = None
) -> pd.DataFrame:
    """The designs ``start:stop`` of the study (module level, for a Dask task), solved with
    ``execution`` (default: the settings in use, `excavkin.execution.current`)."""
    with use(execution or current()):
        return study.evaluate_chunk(start, stop)


def evaluate_part(
    study: Subject, start: int, stop: int, execution: Execution | None = None
) -> pd.DataFrame | dict[str, Any]:
    """`evaluate_chunk`, or a `Study`'s columns alone (`Study.chunk_columns`: no table
    made, for `part_table`).

    Parameters
    ----------
    study : Study
    start, stop : int
    execution : Execution, optional

    Returns
    -------
    pandas.DataFrame or dict of str to array
    """
    if not isinstance(study, Study):
        return evaluate_chunk(study, start, stop, execution)
    with use(execution or current()):
        return study.chunk_columns(start, stop)


def run_study(
    study: Subject,
    out: str | Path,
    *,
    force: bool = False,
    resume: bool = True,
    progress: Callable[[int, int], None] | None = None,
    scheduler: str | None = None,
    chunk_samples: int | None = None,
    backend: str | None = None,
    execution: Execution | None = None,
) -> StudyResult:
    """Evaluate the study and write its table (Parquet) to ``out``.

    Parameters
    ----------
    study : Study
    out : path
        The ``.parquet`` table, one row per design.
    force : bool
        Replace ``out`` if it exists.
    resume : bool
        Keep the finished chunks of an interrupted run of the same study (else start anew).
    progress : callable, optional
        ``progress(designs_done, designs)`` after each chunk.
    scheduler : str, optional
        ``None`` to run here; ``"dask"`` for a local Dask cluster; ``"tcp://host:port"`` for an
        existing Dask scheduler (a scheme of `SCHEDULER_SCHEMES`), given up after
        `SCHEDULER_TIMEOUT` seconds (`SchedulerError`).
    chunk_samples : int, optional
        Designs × poses solved at once (default `default_chunk_samples`: the same on every
        machine, so that the table is; the chunk is also the unit of resuming).
    backend : {"auto", "numpy", "numba", "cuda"}, optional
        Where every solve runs, here or on the Dask workers, as for
        [`Mechanism.solve`][excavkin.mechanism.Mechanism.solve]; ``"auto"`` runs a study of
        fewer than `SMALL_STUDY` samples on NumPy where numba is not imported yet (its import
        would cost more than the compiled solve saves).
    execution : Execution, optional
        Backend, threads and chunk size of every solve as one object
        ([`Execution`][excavkin.execution.Execution]); ``backend`` replaces its own.

    Returns
    -------
    StudyResult
        The table written (its ``path``; a path-like object, so that ``open(result)`` and
        ``pd.read_parquet(result)`` read the file).
    """
    from excavkin.io.files import check_target

    if scheduler is not None:
        check_scheduler(scheduler)
    run = dataclasses.replace(settings(execution, backend=backend), progress=None)
    small = study.designs * study.pose_count < SMALL_STUDY
    if run.backend == "auto" and small and "numba" not in sys.modules:  # (see SMALL_STUDY)
        run = dataclasses.replace(run, backend="numpy")
    target = check_target(out, force=force, suffixes=(".parquet",))
    with use(run):  # (its probes too)
        kinds, name = study.prepare()
    parts = target.parent / f".{target.name}.parts"
    fingerprint = study.fingerprint()
    stamp = parts / "study.json"
    spans = chunks(study, chunk_samples)
    # the parts of a run with other chunks are not this run's (their designs overlap)
    mark = {"fingerprint": fingerprint, "designs_per_chunk": spans[0][1] - spans[0][0]}
    if parts.exists() and (not resume or _stamp(stamp) != mark):
        shutil.rmtree(parts)
    parts.mkdir(exist_ok=True)
    stamp.write_text(json.dumps(mark), encoding="utf-8")
    todo = [(s, e) for s, e in spans if not _part(parts, s).exists()]
    done = study.designs - sum(e - s for s, e in todo)
    if progress is not None:
        progress(done, study.designs)
    kept: dict[str, Any] = {}  # part file's name → its table, as written (`KEEP_BYTES`)
    for (s, e), frame in _run(study, todo, scheduler, run):
        table = _write_part(frame, _part(parts, s))
        if sum(t.nbytes for t in kept.values()) + table.nbytes <= KEEP_BYTES:
            kept[_part(parts, s).name] = table
        done += e - s
        if progress is not None:
            progress(done, study.designs)
    # the pose sets (name → poses; "" the default set) and each metric's set, where named
    sets = getattr(study, "sets", {})
    described = (
        {
            "sets": {k or "": v.count for k, v in sets.items()},
            "metrics": {m.name: m.poses or "" for m in getattr(study, "metrics", ())},
        }
        if set(sets) - {None}
        else None
    )
    _assemble(parts, target, fingerprint, kinds, name, study.motion_note, described, kept)
    shutil.rmtree(parts)
    return StudyResult(target, getattr(study, "units", {}))


@dataclass(frozen=True, repr=False)
class StudyResult:
    """A study's table, written: one row per design (``design``, ``design.NAME`` per parameter
    in SI, one column per metric, ``poses_failed``, ``feasible``, ``status``).

    It is path-like (``os.fspath(result)`` is the table's path), so that code that took the
    path [`run_study`][excavkin.studies.study.run_study] used to return keeps working.

    Attributes
    ----------
    path : Path
        The Parquet table.
    units : dict of str to str
        The units to show columns in (the study file's own); SI where absent.
    """

    path: Path
    units: dict[str, str] = field(default_factory=dict)

    def __fspath__(self) -> str:
        return str(self.path)

    def to_frame(self) -> pd.DataFrame:
        """The table, SI, with each column's kind (``frame.attrs["excavkin.kinds"]``), SI unit
        (``"excavkin.units"``) and the model's name (``"excavkin.model"``) in its ``attrs``, as
        a result's table.

        Returns
        -------
        pandas.DataFrame
        """
        import pandas as pd

        frame = pd.read_parquet(self.path)
        meta = self.metadata()
        frame.attrs["excavkin.model"] = meta["model"]
        frame.attrs["excavkin.kinds"] = meta["kinds"]
        frame.attrs["excavkin.units"] = {str(c): meta["units"].get(str(c), "") for c in frame}
        if meta["motion"]:
            frame.attrs["excavkin.motion"] = meta["motion"]
        return frame

    def metadata(self) -> dict[str, Any]:
        """The table's own metadata: ``model``, ``kinds`` and ``units`` (SI) of its columns,
        ``motion``: what its force metrics are (static unless the poses give rates), or ``""``,
        and ``pose_sets``: for a study with named pose sets, ``{"sets": {name: poses},
        "metrics": {metric: its set}}`` (``""``: the default set), else ``{}``.

        Returns
        -------
        dict
        """
        import pyarrow.parquet as pq

        meta = pq.read_schema(self.path).metadata or {}

        def read(key: bytes, default: Any) -> Any:
            return json.loads(meta[key]) if key in meta else default

        model = meta.get(b"excavkin.model", b"").decode()
        return {
            "model": model,
            "kinds": read(b"excavkin.kinds", {}),
            "units": read(b"excavkin.units", {}),
            "motion": meta.get(b"excavkin.motion", b"").decode(),
            "pose_sets": read(b"excavkin.pose_sets", {}),
        }

    def _shown(self, frame: pd.DataFrame, column: str) -> tuple[np.ndarray, str]:
        """A column's values in the study's unit, and that unit."""
        from excavkin.kinematics.columns import si_unit

        kind = frame.attrs["excavkin.kinds"].get(column, "dimensionless")
        values = frame[column].to_numpy(dtype=np.float64)
        unit = self.units.get(column, "")
        if not unit or kind == "dimensionless":
            return values, si_unit(kind)
        from excavkin.units import from_si

        return np.asarray(from_si(values, kind, unit)), unit

    def _metrics(self, frame: pd.DataFrame) -> list[str]:
        """The metrics' columns (those after the parameters, before the verdicts)."""
        fixed = {"design", "poses_failed", "feasible", "status"}
        return [c for c in frame.columns if c not in fixed and not c.startswith("design.")]

    def summary(self) -> str:
        """The study in a few lines: designs, feasible designs, and per metric its range over
        the feasible designs (over every design where none is) and the design where it is
        least and greatest, in the study's units.

        Returns
        -------
        str
        """
        frame = self.to_frame()
        ok = frame["feasible"].to_numpy(dtype=bool)
        n = len(frame)
        lines = [
            f"study of {frame.attrs['excavkin.model']!r}: {n:,} designs, {int(ok.sum()):,} "
            f"feasible — {self.path}"
        ]
        failed = frame.loc[~ok, "status"].astype(str).value_counts()
        for why, count in failed.items():
            lines.append(f"  not feasible, {why}: {count:,}")
        designs = frame["design"].to_numpy()
        over = ok
        if not ok.any():  # the ranges over every design then, said so
            lines.append("  no design is feasible; the metrics over every design:")
            over = np.ones_like(ok)
        for m in self._metrics(frame):
            v, unit = self._shown(frame, m)
            v = np.where(over, v, np.nan)
            if np.isnan(v).all():
                continue
            lo, hi = int(np.nanargmin(v)), int(np.nanargmax(v))
            lines.append(
                f"  {m:<20} {v[lo]:.6g} … {v[hi]:.6g} {unit}".rstrip()
                + f"  (least: design {designs[lo]}, greatest: design {designs[hi]})"
            )
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"StudyResult({str(self.path)!r})"

    def _repr_html_(self) -> str:
        import html

        from excavkin.kinematics.summary import html_table

        lines = self.summary().splitlines()
        rows = [[html.escape(line.strip())] for line in lines[1:]]
        return f"<p>{html.escape(lines[0])}</p>" + html_table(rows, [""])

    def plot(
        self, metric: str | None = None, x: str | None = None, *, ax: Axes | None = None
    ) -> StudyPlot:
        """A metric against a design variable, one point per design, the infeasible grey; in
        the study's units.

        Parameters
        ----------
        metric : str, optional
            A metric's name; default the first.
        x : str, optional
            A design parameter's name (or ``design.NAME``); default the first.
        ax : matplotlib.axes.Axes, optional

        Returns
        -------
        StudyPlot
        """
        from excavkin.errors import unknown_name
        from excavkin.studies.plots import plot_study

        frame = self.to_frame()
        metrics = self._metrics(frame)
        params = [c.removeprefix("design.") for c in frame.columns if c.startswith("design.")]
        metric = metric if metric is not None else metrics[0]
        if metric not in metrics:
            raise unknown_name("metric", metric, metrics)
        name = (x if x is not None else params[0]).removeprefix("design.")
        if name not in params:
            raise unknown_name("design parameter", name, params)
        xs, xu = self._shown(frame, f"design.{name}")
        ys, yu = self._shown(frame, metric)
        return plot_study(
            xs, ys, frame["feasible"].to_numpy(dtype=bool),
            xlabel=f"{name} [{xu}]" if xu else name, ylabel=f"{metric} [{yu}]" if yu else metric,
            ax=ax,
        )  # fmt: skip


#: the model last loaded by a study's chunk, with its file's text: the next chunk of the same
#: file takes it again (its plan, and the workspaces kept for that plan)
_loaded: dict[str, tuple[str, Mechanism]] = {}
_loaded_lock = threading.Lock()


def _mechanism(path: Path) -> Mechanism:
    """The model file's mechanism, loaded again only when its text has changed."""
    from excavkin import load
    from excavkin.io.toml_model import read_text_file

    key = str(path)
    text = read_text_file(path)
    with _loaded_lock:
        got = _loaded.get(key)
    if got is not None and got[0] == text:
        return got[1]
    mech = load(path)
    with _loaded_lock:
        _loaded.clear()
        _loaded[key] = (text, mech)
    return mech


def _check(study: Study) -> Mechanism:
    """Refuse, before any solve, unknown parameters, columns and metric names."""
    from excavkin import load
    from excavkin.errors import unknown_name

    # the chunks' own mechanism (loaded once for the study); a file that is not there: the
    # loader's message, with the nearest example
    mech = _mechanism(study.model) if Path(study.model).is_file() else load(study.model)
    for name in study.bounds:
        if name not in mech.parameters:
            raise unknown_name("parameter", name, list(mech.parameters))
    check_pose_sets(study.sets, study.metrics)
    forces = needs_forces(mech, study.metrics)
    if forces and study.loads is None:
        raise InputError(
            'a metric reads a force column: give the study loads = "model" (the model\'s '
            "own loads and gravity)"
        )
    names = {m.name for m in study.metrics}
    for c in study.constraints:
        if c.metric not in names:
            raise unknown_name("metric (in a constraint)", c.metric, sorted(names))
    if study.method not in METHODS:
        raise InputError(f"unknown sampling method {study.method!r} (known: {', '.join(METHODS)})")
    return mech


class SchedulerError(InputError):
    """A Dask scheduler's address is malformed, or the scheduler cannot be reached."""


#: the address schemes of a Dask scheduler that a study may name
SCHEDULER_SCHEMES = ("tcp", "tls", "ws", "wss", "ucx")
#: seconds to wait for a Dask scheduler before saying it cannot be reached
SCHEDULER_TIMEOUT = 10.0


def check_scheduler(address: str) -> None:
    """Check, before any work, that ``address`` is ``"dask"`` or a scheduler's address
    ``SCHEME://HOST:PORT`` (``tcp``, ``tls``, ``ws``, ``wss``, ``ucx``).

    Parameters
    ----------
    address : str

    Raises
    ------
    SchedulerError
        Saying what is wrong with it.
    """
    if address == "dask":
        return
    scheme, sep, rest = address.partition("://")
    if not sep:
        raise SchedulerError(
            "expected 'dask' (a local cluster) or a scheduler's address SCHEME://HOST:PORT, "
            "such as tcp://10.0.0.5:8786"
        )
    if scheme not in SCHEDULER_SCHEMES:
        raise SchedulerError(
            f"unsupported protocol {scheme!r} (a Dask scheduler speaks "
            f"{', '.join(SCHEDULER_SCHEMES)})"
        )
    host, colon, port = rest.rpartition(":")
    if not colon or not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise SchedulerError("expected HOST:PORT after the protocol, the port from 1 to 65535")


def _run(
    study: Subject, todo: list[tuple[int, int]], scheduler: str | None, execution: Execution
) -> Iterator[tuple[tuple[int, int], Rows]]:
    if scheduler is None:
        yield from _run_here(study, todo, execution)
        return
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise InputError(
            "a Dask scheduler needs dask.distributed: pip install 'excavkin[cluster]'"
        ) from None
    check_scheduler(scheduler)
    cluster = None
    if scheduler == "dask":  # a worker process per core, quiet, no dashboard
        import logging

        cluster = LocalCluster(
            processes=True, threads_per_worker=1, dashboard_address=None,
            silence_logs=logging.ERROR,
        )  # fmt: skip
    try:
        if cluster is not None:
            client = Client(cluster)
        else:
            try:
                client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
            except (OSError, TimeoutError, ValueError) as exc:
                raise SchedulerError(
                    f"the Dask scheduler cannot be reached within {SCHEDULER_TIMEOUT:g} s "
                    f"({exc}); nothing was computed"
                ) from None
        with client:
            # a bounded window of tasks in flight, each released once its rows are here: the
            # cluster's memory and the scheduler's queue stay bounded however many chunks
            window = max(8, 2 * sum(client.nthreads().values()))
            pending = iter(todo)
            futures = {}
            for s, e in itertools.islice(pending, window):
                futures[client.submit(evaluate_chunk, study, s, e, execution, pure=False)] = (s, e)
            running = as_completed(list(futures))
            for future in running:
                span = futures.pop(future)
                frame = future.result()
                future.release()
                for s, e in itertools.islice(pending, 1):
                    nxt = client.submit(evaluate_chunk, study, s, e, execution, pure=False)
                    futures[nxt] = (s, e)
                    running.add(nxt)
                yield span, frame
    finally:
        if cluster is not None:
            cluster.close()


def _run_here(
    study: Subject, todo: list[tuple[int, int]], execution: Execution
) -> Iterator[tuple[tuple[int, int], Rows]]:
    """The chunks here: several at once, one per thread (each solved on its share of the
    cores — one, where there are as many chunks as cores — so that one chunk's serial work,
    its designs and its table, overlaps the others' solves), a bounded window of them in
    flight, each yielded as it finishes; a single chunk, or one thread, solves its blocks on
    every thread instead (and so does another subject than a `Study`: a machine study's
    chunks, one after another, as before). A chunk's rows do not depend on the threads: they
    are those of a Dask worker's solve, to the bit."""
    cores = execution.workers or os.cpu_count() or 1
    threads = min(cores, len(todo))
    if threads <= 1 or not isinstance(study, Study):
        for s, e in todo:
            yield (s, e), evaluate_part(study, s, e, execution)
        return
    from concurrent.futures import FIRST_COMPLETED, Future, ThreadPoolExecutor, wait

    # fewer chunks than cores: each chunk's blocks on its share of them, no core idle
    alone = dataclasses.replace(execution, workers=max(1, cores // threads))
    pending = iter(todo)
    with ThreadPoolExecutor(threads) as pool:
        running: dict[Future[Rows], tuple[int, int]] = {}

        def submit(n: int) -> None:
            for s, e in itertools.islice(pending, n):
                running[pool.submit(evaluate_part, study, s, e, alone)] = (s, e)

        submit(2 * threads)
        try:
            while running:
                finished, _ = wait(running, return_when=FIRST_COMPLETED)
                for future in sorted(finished, key=lambda f: running[f]):
                    span = running.pop(future)
                    frame = future.result()
                    submit(1)
                    yield span, frame
        finally:
            for future in running:
                future.cancel()


def _part(parts: Path, start: int) -> Path:
    return parts / f"part-{start:012d}.parquet"


def _stamp(path: Path) -> Any:
    """What a parts folder's stamp says (its study's fingerprint and chunks), or None."""
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def _write_part(rows: Rows, path: Path) -> Any:
    """A chunk's rows, written whole or not at all; returns them as the Arrow table written
    (`part_table`).

    The parts' folder is the study's own: a temporary file that a killed run leaves in it is
    never read (the parts are ``part-*.parquet``) and goes with the folder, so that a write
    does not list the folder's thousands of parts for leftovers (`write_atomic` does)."""
    import pyarrow.parquet as pq

    table = part_table(rows)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        pq.write_table(table, tmp)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return table


def part_table(rows: Rows) -> Any:
    """A chunk's rows as the Arrow table ``pyarrow.Table.from_pandas`` makes of their frame
    (no index), on this thread (Arrow's pool of threads started for a few thousand rows
    cost 5–20× the conversion).

    A table's schema, pandas' metadata with it, depends on its columns' names and types
    alone: it is made from a frame once a study (≈ 1 ms of Python holding the GIL, and the
    frame's own), and every other chunk's columns are put under it as arrays.

    Parameters
    ----------
    rows : pandas.DataFrame or dict of str to array
        A chunk's frame (`Study.evaluate_chunk`) or its columns (`Study.chunk_columns`).

    Returns
    -------
    pyarrow.Table
        Equal to ``pa.Table.from_pandas(pd.DataFrame(rows), preserve_index=False)``, its
        metadata included.
    """
    import pandas as pd
    import pyarrow as pa

    if isinstance(rows, pd.DataFrame):
        return pa.Table.from_pandas(rows, preserve_index=False, nthreads=1)
    key = tuple((name, str(getattr(v, "dtype", type(v)))) for name, v in rows.items())
    with _loaded_lock:
        schema = _schemas.get(key)
    if schema is None:
        table = pa.Table.from_pandas(pd.DataFrame(rows), preserve_index=False, nthreads=1)
        with _loaded_lock:
            if len(_schemas) >= 16:
                _schemas.clear()
            _schemas[key] = table.schema
        return table
    arrays = [
        pa.array(v, type=f.type, from_pandas=True)  # (a float's NaN a null, as there)
        for v, f in zip(rows.values(), schema, strict=True)
    ]
    return pa.Table.from_arrays(arrays, schema=schema)


#: a chunk's rows: its frame, or its columns by name
Rows = Any
#: `part_table`'s schemas (pandas' metadata included), by the columns' names and types
_schemas: dict[tuple[tuple[str, str], ...], Any] = {}


def _assemble(
    parts: Path,
    target: Path,
    fingerprint: str,
    kinds: dict[str, str],
    name: str,
    motion: str,
    sets: dict[str, Any] | None = None,
    kept: Mapping[str, Any] | None = None,
) -> None:
    """The parts in design order, as one table with units (and the pose sets, where named) in
    its metadata, moved into place whole; one part read at a time, those ``kept`` (part
    file's name → its table, as written by this run) not read back."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from excavkin.io.files import write_atomic
    from excavkin.kinematics.columns import si_unit

    files = sorted(parts.glob("part-*.parquet"))
    kept = kept or {}
    first = kept.get(files[0].name)
    schema = first.schema if first is not None else pq.read_schema(files[0])
    meta = {
        b"excavkin.units": json.dumps({k: si_unit(v) for k, v in kinds.items()}).encode(),
        b"excavkin.kinds": json.dumps(kinds).encode(),
        b"excavkin.model": name.encode(),
        b"excavkin.study": fingerprint.encode(),
        **({b"excavkin.motion": motion.encode()} if motion else {}),
        **({b"excavkin.pose_sets": json.dumps(sets).encode()} if sets else {}),
    }
    schema = schema.with_metadata({**(schema.metadata or {}), **meta})

    def write(tmp: Path) -> None:
        with pq.ParquetWriter(tmp, schema) as writer:
            for f in files:
                table = kept.get(f.name)
                batches = (table if table is not None else pq.read_table(f)).to_batches()
                writer.write_table(pa.Table.from_batches(batches, schema))

    write_atomic(target, write)


def _kinds(study: Study, mech: Mechanism) -> dict[str, str]:
    """Each column's physical kind: parameters', and each metric's from its column."""
    from excavkin.structure.design import parameter_kind

    kinds = {f"design.{k}": parameter_kind(k, mech.model) for k in study.bounds}
    run = probe_execution()
    probe = (
        mech.solve({}, loads="model", execution=run)
        if study.loads
        else mech.solve({}, execution=run)
    )
    of = {c.name: c.kind for c in probe.columns}
    for m in study.metrics:
        kinds[m.name] = metric_kind(m, of)
    return kinds


def metric_kind(m: Metric, of: Mapping[str, str]) -> str:
    """A metric's kind, from its column's: a pose's index is dimensionless, a clearance a
    length.

    Parameters
    ----------
    m : Metric
    of : mapping of str to str
        Each column's kind.

    Returns
    -------
    str
        The metric's kind (``"length"``, ``"angle"``, ``"dimensionless"`` …).
    """
    if m.reduce in ("argmin", "argmax"):
        return "dimensionless"
    return "length" if m.clearance is not None else of.get(m.column, "dimensionless")
