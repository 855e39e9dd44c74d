"""Tolerance and pin-clearance analysis: how far each result column can move when the
dimensions are made within their tolerances and the pins sit anywhere in their clearances.

Three bands per column and sample, each about the nominal value:

* **worst case** (linear): ``Σ |∂c/∂p|·tol_p + Σ_joints c_j·|∇_j c|`` from the exact
  sensitivities — every dimension at the end of its tolerance that hurts most, and every pin
  pushed across its clearance the way that hurts most;
* **root-sum-square** (linear): ``√(Σ (∂c/∂p·tol_p)² + Σ (c_j·|∇_j c|)²)``;
* **Monte Carlo**: the smallest and largest value, mean and standard deviation over ``draws``
  designs, solved as one batch over the geometry axis (in chunks of draws). Each dimension is
  drawn normal with σ = tol/3, cut at ±tol (the root-sum-square convention: a tolerance is
  three standard deviations), or uniform within ±tol (``distribution="uniform"``); each pin
  offset uniform in the disc of its clearance.

A pin clearance c at joint P lets each body's pin there sit anywhere within c of the joint's
centre: a radial offset of any direction
([`joint_offsets`][excavkin.structure.design.joint_offsets]). Its gradient ``∇_j c`` is the pair of
sensitivities to that offset's two components.

For small tolerances the three agree as theory says: the Monte Carlo range lies within the
worst case, and its standard deviation is ``√(Σ (∂c/∂p)²·σ_p² + Σ |∇_j c|²·c_j²/4)``, with σ_p
that of the drawn distribution (tol/3 cut at ±3σ: 0.9866·tol/3; uniform: tol/√3) and c²/4 the
variance of each component of an offset uniform in a disc of radius c.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.execution import Execution, settings
from excavkin.mechanism import Mechanism, as_si
from excavkin.structure.design import joint_offsets, parameter_kind

#: Monte Carlo samples solved in one batch (draws × poses)
BATCH = 200_000


@dataclasses.dataclass(frozen=True, slots=True)
class ToleranceBands:
    """Bands of every column over the samples of a sweep.

    Attributes
    ----------
    columns : tuple of str
        The columns, in table order.
    nominal : ndarray, shape (n, k)
        Values of the nominal design.
    worst, rss : ndarray, shape (n, k)
        Half-widths of the linear worst-case and root-sum-square bands.
    mc_min, mc_max, mc_mean, mc_std : ndarray, shape (n, k)
        Over the Monte Carlo draws (NaN where no draw was given).
    contributions : dict
        Per toleranced dimension or clearance (``"clearance P"``), the largest worst-case
        contribution ``|∂c/∂p|·tol_p`` over the samples, shape (k,).
    draws : int
        Monte Carlo draws per sample.
    failed : ndarray of int, shape (n,)
        Draws per sample that did not solve (a design that does not close there).
    motion : str
        What the nominal velocities or forces are (``ForceResult.motion_note``: static forces
        when no rate is given), or ``""`` for a plain motion.
    """

    columns: tuple[str, ...]
    nominal: F
    worst: F
    rss: F
    mc_min: F
    mc_max: F
    mc_mean: F
    mc_std: F
    contributions: dict[str, F]
    draws: int
    failed: NDArray[np.int64]
    motion: str = ""

    def index(self, column: str) -> int:
        """The position of a column (with the nearest names when unknown).

        Parameters
        ----------
        column : str
            A column name, as in `columns`.

        Returns
        -------
        int
            Its index along the last axis of the band arrays.

        Raises
        ------
        InputError
            An unknown column, with the nearest names.
        """
        if column not in self.columns:
            from excavkin.errors import unknown_name

            raise unknown_name("column", column, self.columns)
        return self.columns.index(column)

    def ranking(self, column: str) -> list[tuple[str, float]]:
        """The dimensions and clearances that matter most for ``column``, largest worst-case
        contribution first.

        Parameters
        ----------
        column : str
            A column name, as in `columns`.

        Returns
        -------
        list of (str, float)
            (name, largest contribution over the samples in the column's SI unit), one per
            toleranced dimension or clearance.
        """
        j = self.index(column)
        pairs = [(name, float(c[j])) for name, c in self.contributions.items()]
        return sorted(pairs, key=lambda nc: -nc[1])

    def to_frame(self) -> Any:
        """A long table: one row per sample and column, with every band's ends.

        Returns
        -------
        pandas.DataFrame
            Columns ``sample``, ``column``, ``nominal``, ``worst_low``, ``worst_high``,
            ``rss_low``, ``rss_high``, ``mc_min``, ``mc_max``, ``mc_mean``, ``mc_std``, in each
            column's SI unit; ``attrs`` hold the draws and, where given, the motion note.
        """
        import pandas as pd

        n, k = self.nominal.shape
        frame = pd.DataFrame(
            {
                "sample": np.repeat(np.arange(n), k),
                "column": np.tile(np.array(self.columns, dtype=object), n),
                "nominal": self.nominal.ravel(),
                "worst_low": (self.nominal - self.worst).ravel(),
                "worst_high": (self.nominal + self.worst).ravel(),
                "rss_low": (self.nominal - self.rss).ravel(),
                "rss_high": (self.nominal + self.rss).ravel(),
                "mc_min": self.mc_min.ravel(),
                "mc_max": self.mc_max.ravel(),
                "mc_mean": self.mc_mean.ravel(),
                "mc_std": self.mc_std.ravel(),
            }
        )
        frame.attrs["excavkin.draws"] = self.draws
        if self.motion:
            frame.attrs["excavkin.motion"] = self.motion
        return frame


def parse_tolerance(text: Any, kind: str, what: str) -> float:
    """A tolerance ``±0.1 mm`` (also ``+-0.1mm``, ``+/-0.1 mm``, ``0.1 mm``, a quantity or a
    number in SI) as a non-negative SI half-width."""
    if isinstance(text, str):
        text = text.strip()
        for sign in ("±", "+/-", "+-"):
            if text.startswith(sign):
                text = text[len(sign) :].strip()
                break
    value = float(as_si(text, kind, what))
    if not (np.isfinite(value) and value >= 0.0):
        raise InputError(f"{what}: a tolerance is a half-width of zero or more, got {value:g}")
    return value


def tolerance_bands(
    mech: Mechanism,
    values: Mapping[str, Any],
    rates: Mapping[str, Any] | None = None,
    accels: Mapping[str, Any] | None = None,
    *,
    tolerances: Mapping[str, Any] | None = None,
    clearance: Any = 0.0,
    columns: Sequence[str] | None = None,
    draws: int = 1_000_000,
    seed: int = 0,
    distribution: str = "normal",
    loads: Any = None,
    progress: Callable[[int, int], None] | None = None,
    backend: str | None = None,
    execution: Execution | None = None,
) -> ToleranceBands:
    """Worst-case, root-sum-square and Monte Carlo bands of every kinematic column.

    Parameters
    ----------
    mech : Mechanism
    values, rates, accels : mapping
        The sweep, as for [`Mechanism.solve`][excavkin.mechanism.Mechanism.solve].
    tolerances : mapping of str to float or str
        Half-width per parameter
        ([`Mechanism.parameters`][excavkin.mechanism.Mechanism.parameters]): ``{"A-B": "±0.1 mm"}``.
    clearance : float, str or mapping
        Radial pin clearance: one for every joint, or ``{point: clearance}`` per joint.
    columns : sequence of str, optional
        The columns to band (default: every kinematic column).
    draws : int
        Monte Carlo designs per sample (0 for the linear bands alone).
    seed : int
        Seed of the random draws (the same seed, the same bands).
    distribution : {"normal", "uniform"}
        How a dimension is drawn within its tolerance: normal with σ = tol/3 cut at ±tol, or
        uniform.
    loads : iterable of loads or "model", optional
        Also band the forces (joint, cylinder, driver) under these loads, as for
        [`Mechanism.solve`][excavkin.mechanism.Mechanism.solve].
    progress : callable, optional
        ``progress(draws_done, draws)`` after each batch of Monte Carlo designs.
    backend : {"auto", "numpy", "numba", "cuda"}, optional
        Where the solves run, as for
        [`Mechanism.solve`][excavkin.mechanism.Mechanism.solve].
    execution : Execution, optional
        The solves' backend, threads and chunk size as one object
        ([`Execution`][excavkin.execution.Execution]); ``backend`` replaces its own.

    Returns
    -------
    ToleranceBands
    """
    run = settings(execution, backend=backend)
    tols = {
        name: parse_tolerance(t, _kind(mech, name), f"tolerance of {name!r}")
        for name, t in (tolerances or {}).items()
    }
    pins = _pins(mech, clearance)
    names = list(tols) + [p for _, axes in pins for p in axes]
    if not names:
        raise InputError("nothing is toleranced: give tolerances or a clearance")
    nominal: Any = mech.solve(
        values, rates, accels, sensitivities=names, loads=loads, execution=run
    )
    table = nominal.to_frame()
    every = [c.name for c in nominal.columns if c.owner_kind != "time"]
    every = [c for c in every if not c.startswith(("d(", "design."))]
    for name in columns or ():
        if name not in every:
            from excavkin.errors import unknown_name

            raise unknown_name("column", name, every)
    cols = list(columns) if columns else every
    nom = np.column_stack([table[name].to_numpy() for name in cols])
    grad = {p: np.column_stack([nominal.sensitivity(col, p) for col in cols]) for p in names}
    parts: dict[str, F] = {p: np.abs(grad[p]) * tols[p] for p in tols}
    for (point, radius), axes in pins:
        gx, gy = (grad[a] for a in axes)
        key = f"clearance {point}"
        parts[key] = parts.get(key, np.zeros_like(nom)) + radius * np.hypot(gx, gy)
    worst = np.sum(list(parts.values()), axis=0)
    rss = np.sqrt(np.sum([v * v for v in parts.values()], axis=0))
    contributions = {k: np.nanmax(v, axis=0) for k, v in parts.items()}
    n = len(nominal)
    if distribution not in ("normal", "uniform"):
        raise InputError(f"distribution must be 'normal' or 'uniform', got {distribution!r}")
    low, high, mean, std, failed = _monte_carlo(
        mech, values, rates, accels, tols, pins, cols, n, draws, seed, distribution, loads,
        progress, run,
    )  # fmt: skip
    motion = nominal.motion_note if loads is not None or nominal.unit_rates else ""
    return ToleranceBands(
        tuple(cols), nom, worst, rss, low, high, mean, std, contributions, draws, failed, motion
    )


def _kind(mech: Mechanism, name: str) -> str:
    if name not in mech.parameters:
        from excavkin.errors import unknown_name

        raise unknown_name("parameter", name, list(mech.parameters))
    return parameter_kind(name, mech.model)


def _pins(mech: Mechanism, clearance: Any) -> list[tuple[tuple[str, float], tuple[str, str]]]:
    """((joint, clearance), (offset x name, offset y name)) for every pin with a clearance."""
    offsets = joint_offsets(mech.model)
    joints = sorted({name.partition("@")[0] for name in offsets})
    if isinstance(clearance, Mapping):
        given = dict(clearance)
        for point in given:
            if point not in joints:
                from excavkin.errors import unknown_name

                raise unknown_name("joint", point, joints)
    else:
        given = dict.fromkeys(joints, clearance)
    out = []
    for point, c in given.items():
        value = parse_tolerance(c, "length", f"clearance of joint {point!r}")
        if value == 0.0:
            continue
        for name in offsets:
            if name.startswith(f"{point}@") and name.endswith(".x"):
                out.append(((point, value), (name, name[:-2] + ".y")))
    return out


def _monte_carlo(
    mech: Mechanism,
    values: Mapping[str, Any],
    rates: Mapping[str, Any] | None,
    accels: Mapping[str, Any] | None,
    tols: dict[str, float],
    pins: list[tuple[tuple[str, float], tuple[str, str]]],
    cols: list[str],
    n: int,
    draws: int,
    seed: int,
    distribution: str,
    loads: Any,
    progress: Callable[[int, int], None] | None = None,
    execution: Execution | None = None,
) -> tuple[F, F, F, F, NDArray[np.int64]]:
    """Min, max, mean and standard deviation of every column over the draws, per sample, and
    the draws per sample that failed; the designs are solved ``BATCH`` samples at a time."""
    k = len(cols)
    low = np.full((n, k), np.inf)
    high = np.full((n, k), -np.inf)
    total = np.zeros((n, k))
    square = np.zeros((n, k))
    count = np.zeros(n, dtype=np.int64)
    failed = np.zeros(n, dtype=np.int64)
    if draws <= 0:
        nan = np.full((n, k), np.nan)
        return nan, nan.copy(), nan.copy(), nan.copy(), failed
    rng = np.random.default_rng(seed)
    nominal = mech.parameters
    per = max(BATCH // n, 1)
    shift = None
    for start in range(0, draws, per):
        d = min(per, draws - start)
        params: dict[str, F] = {}
        for name, tol in tols.items():
            params[name] = np.repeat(nominal[name] + _draw(rng, tol, d, distribution), n)
        for (_, c), (ax, ay) in pins:
            r = c * np.sqrt(rng.uniform(0.0, 1.0, d))
            th = rng.uniform(0.0, 2 * np.pi, d)
            params[ax], params[ay] = np.repeat(r * np.cos(th), n), np.repeat(r * np.sin(th), n)
        res: Any = mech.solve(
            _tiled(mech, values, n, d, 0),
            _tiled(mech, rates, n, d, 1),
            _tiled(mech, accels, n, d, 2),
            params=params,
            loads=loads,
            execution=execution,
        )
        if loads is None:
            ok = res.status.ok.reshape(d, n)
            by_name = {c.name: arr for c, arr in res._columns()}
        else:
            ok = res.ok.reshape(d, n)
            ground = res.system.bodies[res.system.ground]
            by_name = {c.name: arr for c, arr in res.kinematics._columns()}
            by_name.update({c.name: arr for c, arr in res._columns((ground,))})
        block = np.stack([by_name[c] for c in cols], axis=-1).reshape(d, n, k)
        if shift is None:  # sums about the first draw's values: no cancellation in the variance
            shift = np.where(np.isfinite(block[0]), block[0], 0.0)
        block = np.where(ok[..., None], block, np.nan)
        low = np.fmin(low, np.nanmin(block, axis=0, initial=np.inf))
        high = np.fmax(high, np.nanmax(block, axis=0, initial=-np.inf))
        centred = np.where(ok[..., None], block - shift, 0.0)
        total += centred.sum(axis=0)
        square += (centred * centred).sum(axis=0)
        count += ok.sum(axis=0)
        failed += (~ok).sum(axis=0)
        if progress is not None:
            progress(start + d, draws)
    with np.errstate(invalid="ignore", divide="ignore"):
        many = count[:, None]
        m = total / many
        var = np.maximum(square / many - m * m, 0.0) * many / (many - 1)
        mean = m + (shift if shift is not None else 0.0)
    none = count == 0
    low[none], high[none] = np.nan, np.nan
    return low, high, mean, np.sqrt(var), failed


def _draw(rng: np.random.Generator, tol: float, d: int, distribution: str) -> F:
    """``d`` deviations within ±tol: uniform, or normal with σ = tol/3 cut at ±tol (a draw
    beyond is drawn again)."""
    if distribution == "uniform":
        return rng.uniform(-tol, tol, d)
    out = rng.normal(0.0, tol / 3.0, d)
    while True:
        beyond = np.flatnonzero(np.abs(out) > tol)
        if not beyond.size:
            return out
        out[beyond] = rng.normal(0.0, tol / 3.0, beyond.size)


def _tiled(
    mech: Mechanism, given: Mapping[str, Any] | None, n: int, d: int, order: int
) -> dict[str, F]:
    """The sweep's inputs repeated for ``d`` draws (sample i of draw r at r·n + i)."""
    si = mech._in_si(given, order)
    return {k: np.tile(np.broadcast_to(np.asarray(v, dtype=float), (n,)), d) for k, v in si.items()}


def summary_rows(bands: ToleranceBands, columns: Sequence[str]) -> list[list[str]]:
    """Rows for a printed summary: column, nominal range, and the largest half-width of each
    band over the samples, with the dimension that matters most."""
    rows = []
    for col in columns:
        j = bands.index(col)
        ranked = bands.ranking(col)
        top = ranked[0][0] if ranked and ranked[0][1] > 0 else "—"
        nom = bands.nominal[:, j]
        spread = np.maximum(bands.mc_max[:, j] - nom, nom - bands.mc_min[:, j])
        rows.append(
            [
                col,
                f"{np.nanmax(bands.worst[:, j]):.4g}",
                f"{np.nanmax(bands.rss[:, j]):.4g}",
                f"{np.nanmax(spread):.4g}" if np.isfinite(spread).any() else "—",
                top,
            ]
        )
    return rows
