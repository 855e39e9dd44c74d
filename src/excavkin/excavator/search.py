"""Vectorised pattern search over an excavator's cylinder strokes.

The working-range figures and the rated tool forces are optima over one, two or three strokes
of smooth (or piecewise smooth) objectives evaluated in batches by the engine: a coarse grid
over the free strokes, then a shrinking grid around the best few points, to ~1e-9 m of stroke.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.excavator.machine import Machine

#: ``evaluate(L)`` → (objective, lengths it scored), both batched over (problems, k).
Evaluate = Callable[[F], tuple[F, F]]


#: ``progress(done, total)``: an analysis's report of the work done so far
Progress = Callable[[int, int], None]


def part(progress: Progress | None, k: int, n: int) -> Progress | None:
    """The ``k``-th of ``n`` equal parts of a task reported to ``progress``: a part's own
    ``(done, total)`` becomes the task's ``(k·total + done, n·total)``."""
    if progress is None:
        return None
    return lambda done, total: progress(k * total + done, n * total)


def maximize_strokes(
    evaluate: Evaluate,
    machine: Machine,
    free: tuple[int, ...],
    problems: int = 1,
    *,
    coarse: int = 17,
    keep: int = 3,
    rounds: int = 32,
    m: int = 5,
    base: F | None = None,
    strokes: tuple[F, F] | None = None,
    progress: Progress | None = None,
) -> tuple[F, F]:
    """Maximise ``evaluate`` over the free strokes, for ``problems`` independent problems.

    ``evaluate(L)`` takes lengths of shape (problems, k, 3) (entries not in ``free`` at
    ``base``, mid-stroke by default) and returns the objective (problems, k) (−inf where
    infeasible) and the full lengths of the pose it scored (problems, k, 3). ``strokes``: each
    problem's shortest and longest lengths, shape (problems, 3) each (a family of designs);
    default the machine's. Returns the best objective (problems,) and lengths (problems, 3).
    ``progress(done, rounds + 1)`` is called after the coarse grid and after each round.
    """
    if strokes is None:
        lo = np.broadcast_to(machine.lengths_min, (problems, 3))
        hi = np.broadcast_to(machine.lengths_max, (problems, 3))
    else:
        lo, hi = (np.broadcast_to(np.asarray(a, dtype=np.float64), (problems, 3)) for a in strokes)
    mid = 0.5 * (lo + hi) if base is None else np.broadcast_to(base, (problems, 3))
    nf = len(free)
    fr = list(free)
    unit = np.stack(
        np.meshgrid(*[np.linspace(0.0, 1.0, coarse)] * nf, indexing="ij"), axis=-1
    ).reshape(-1, nf)
    L = np.broadcast_to(mid[:, None, :], (problems, len(unit), 3)).copy()
    L[:, :, fr] = lo[:, None, fr] + unit * (hi - lo)[:, None, fr]
    obj, full = evaluate(L)
    if progress is not None:
        progress(1, rounds + 1)
    full = np.where(np.isfinite(full), full, L)
    top = np.argsort(-obj, axis=1)[:, :keep]
    centre = np.take_along_axis(full, top[:, :, None], axis=1)  # (P, keep, 3)
    w = ((hi - lo)[:, fr] / (coarse - 1))[:, None, None, :]  # (P, 1, 1, nf)
    offs = np.stack(np.meshgrid(*[np.linspace(-1.0, 1.0, m)] * nf, indexing="ij"), axis=-1).reshape(
        -1, nf
    )  # (m^nf, nf)
    best_obj = np.take_along_axis(obj, top, axis=1)
    best_L = centre.copy()
    for r in range(rounds):
        trial = np.broadcast_to(best_L[:, :, None, :], (problems, keep, len(offs), 3)).copy()
        trial[..., fr] = np.clip(
            best_L[:, :, None, fr] + offs * w, lo[:, None, None, fr], hi[:, None, None, fr]
        )
        o, full = evaluate(trial.reshape(problems, -1, 3))
        o = o.reshape(problems, keep, -1)
        full = full.reshape(problems, keep, -1, 3)
        j = np.argmax(o, axis=2)
        oj = np.take_along_axis(o, j[:, :, None], axis=2)[:, :, 0]
        better = oj > best_obj
        best_obj = np.where(better, oj, best_obj)
        best_L = np.where(
            better[..., None],
            np.take_along_axis(full, j[:, :, None, None], axis=2)[:, :, 0],
            best_L,
        )
        best_L[..., free] = np.where(
            np.isfinite(best_L[..., free]), best_L[..., free], centre[..., free]
        )
        w = w / 2.0
        if progress is not None:
            progress(r + 2, rounds + 1)
    k = np.argmax(best_obj, axis=1)
    return best_obj[np.arange(problems), k], best_L[np.arange(problems), k]
