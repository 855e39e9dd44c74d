"""Designs spread over a box of parameter bounds: quasi-random (Sobol, Halton), Latin
hypercube, or a full grid."""

from __future__ import annotations

import os
import threading
from collections.abc import Mapping
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError

METHODS = ("sobol", "halton", "lhs", "grid")


def sample_designs(
    bounds: Mapping[str, tuple[float, float]],
    n: int,
    method: str = "sobol",
    seed: int = 0,
    part: tuple[int, int] | None = None,
) -> dict[str, F]:
    """``n`` designs in the box ``bounds`` (name → (low, high), SI), or the designs
    ``part = (start, stop)`` of them (made without the others where the method allows).

    Parameters
    ----------
    bounds : mapping of str to (float, float)
        Parameter name → (low, high), SI, low < high.
    n : int
        Designs; for ``"grid"``, the levels of each parameter (``n ** len(bounds)`` designs,
        the first parameter varying slowest).
    method : {"sobol", "halton", "lhs", "grid"}
        Scrambled Sobol' and Halton sequences and Latin hypercubes come from
        `scipy.stats.qmc`, seeded: the same arguments give the same designs. A Sobol'
        count that is a power of two keeps the sequence's balance.
    seed : int
        Seed of the scrambling (Sobol', Halton) or of the hypercube; the grid has none.
    part : (int, int), optional
        ``(start, stop)``: only those designs, in the order of the whole set (default all).

    Returns
    -------
    dict of str to ndarray
        Each parameter's values, shape (designs,).
    """
    names = list(bounds)
    if not names:
        raise InputError("a design space needs at least one parameter with bounds")
    if n < 1:
        raise InputError(f"the number of designs must be at least 1, got {n}")
    lo = np.array([bounds[k][0] for k in names], dtype=np.float64)
    hi = np.array([bounds[k][1] for k in names], dtype=np.float64)
    bad = [k for k, a, b in zip(names, lo, hi, strict=True) if not (np.isfinite(a) and a < b)]
    if bad:
        raise InputError(f"parameter {bad[0]!r}: its bounds must be finite with low < high")
    d = len(names)
    total = n**d if method == "grid" else n
    start, stop = part if part is not None else (0, total)
    if not 0 <= start <= stop <= total:
        raise InputError(f"designs {start}:{stop} are not within the {total} designs")
    if method == "grid":
        index = np.unravel_index(np.arange(start, stop), (n,) * d)
        return {
            k: a + (b - a) * (i / max(n - 1, 1)) if n > 1 else np.full(stop - start, (a + b) / 2)
            for k, a, b, i in zip(names, lo, hi, index, strict=True)
        }
    from scipy.stats import qmc

    if method == "sobol":
        engine: qmc.QMCEngine = _sobol(d, seed, start)
    elif method == "halton":
        engine = qmc.Halton(d, scramble=True, seed=seed)
    elif method == "lhs":
        engine = qmc.LatinHypercube(d, seed=seed)
    else:
        raise InputError(f"unknown sampling method {method!r} (known: {', '.join(METHODS)})")
    import warnings

    with warnings.catch_warnings():  # Sobol' balance: said in the docstring
        warnings.simplefilter("ignore", UserWarning)
        if method == "lhs":  # a Latin hypercube is one permutation of all its designs
            unit = engine.random(n)[start:stop]
        else:  # a sequence: skip to the part (a kept Sobol' engine is there already, or near)
            if start > engine.num_generated:
                engine.fast_forward(start - engine.num_generated)
            unit = engine.random(stop - start)
    if method == "sobol":
        _give_back(d, seed, engine)
    values = qmc.scale(unit, lo, hi)
    return {k: np.ascontiguousarray(values[:, j]) for j, k in enumerate(names)}


#: scrambled Sobol' engines made before, by dimension and seed, each where it stopped in the
#: sequence: a study's chunks, drawn mostly in order, each take the one nearest before their
#: first design (skipping to a design costs one step a design skipped, in Python's thread:
#: skipping from the start would make a study's draws grow as its designs squared; the
#: scrambling, made once, is a third of a chunk's points' time), and give it back
_engines: dict[tuple[int, int], list[Any]] = {}
_lock = threading.Lock()


def _sobol(d: int, seed: int, start: int) -> Any:
    """A scrambled Sobol' engine of ``d`` dimensions and ``seed`` at most at design ``start``:
    the one given back before nearest before it, reset to the sequence's start where all are
    past it (the same points as a new one: tested), or a new one."""
    from scipy.stats import qmc

    with _lock:
        spare = _engines.get((d, seed), [])
        before = [e for e in spare if e.num_generated <= start]
        engine = max(before, key=lambda e: e.num_generated) if before else None
        if engine is None and spare:
            engine = spare[0]
        if engine is not None:
            spare.remove(engine)
    if engine is None:
        return qmc.Sobol(d, scramble=True, seed=seed)
    return engine if engine.num_generated <= start else engine.reset()


def _give_back(d: int, seed: int, engine: Any) -> None:
    """Keep an engine for the next chunk: two per core of a kind, eight kinds, at most (the
    one furthest behind in the sequence given up first)."""
    with _lock:
        if (d, seed) not in _engines and len(_engines) >= 8:
            _engines.clear()
        spare = _engines.setdefault((d, seed), [])
        spare.append(engine)
        if len(spare) > 2 * (os.cpu_count() or 1):
            spare.remove(min(spare, key=lambda e: e.num_generated))
