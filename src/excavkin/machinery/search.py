"""Vectorised pattern search over a machine's cylinder strokes.

An excavator's working-range figures and rated tool forces are optima over one, two or three strokes
of smooth (or piecewise smooth) objectives evaluated in batches by the engine: a coarse grid
over the free strokes, then a shrinking grid around the best few points, to ~1e-9 m of stroke.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.machinery.machine import Strokes

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
    machine: Strokes,
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

    A coarse grid over the free strokes, then ``rounds`` of a shrinking grid around the best
    ``keep`` points; c below is the machine's number of cylinders.

    Parameters
    ----------
    evaluate : callable
        ``evaluate(L)`` takes lengths of shape (problems, k, c) (entries not in ``free`` at
        ``base``) and returns the objective (problems, k) (−inf where infeasible) and the full
        lengths of the pose it scored (problems, k, c).
    machine : Strokes
        Its ``lengths_min`` and ``lengths_max`` (shape (c,)) bound the search unless
        ``strokes`` is given.
    free : tuple of int
        The cylinders searched over (columns of the lengths).
    problems : int
        Independent problems solved together.
    coarse, keep, rounds, m : int
        Points per free stroke of the coarse grid; best points kept; refining rounds; points
        per free stroke of each refining grid.
    base : ndarray, shape (problems, c), optional
        Lengths of the cylinders not searched over; default mid-stroke.
    strokes : (ndarray, ndarray), optional
        Each problem's shortest and longest lengths, shape (problems, c) each (a family of
        designs); default the machine's.
    progress : callable, optional
        ``progress(done, rounds + 1)`` after the coarse grid and after each round.

    Returns
    -------
    objective : ndarray, shape (problems,)
        The best objective of each problem.
    lengths : ndarray, shape (problems, c)
        The lengths where it is reached.
    """
    nc = len(machine.lengths_min)
    if strokes is None:
        lo = np.broadcast_to(machine.lengths_min, (problems, nc))
        hi = np.broadcast_to(machine.lengths_max, (problems, nc))
    else:
        lo, hi = (np.broadcast_to(np.asarray(a, dtype=np.float64), (problems, nc)) for a in strokes)
    mid = 0.5 * (lo + hi) if base is None else np.broadcast_to(base, (problems, nc))
    nf = len(free)
    fr = list(free)
    unit = np.stack(
        np.meshgrid(*[np.linspace(0.0, 1.0, coarse)] * nf, indexing="ij"), axis=-1
    ).reshape(-1, nf)
    L = np.broadcast_to(mid[:, None, :], (problems, len(unit), nc)).copy()
    L[:, :, fr] = lo[:, None, fr] + unit * (hi - lo)[:, None, fr]
    obj, full = evaluate(L)
    if progress is not None:
        progress(1, rounds + 1)
    full = np.where(np.isfinite(full), full, L)
    top = np.argsort(-obj, axis=1)[:, :keep]
    centre = np.take_along_axis(full, top[:, :, None], axis=1)  # (P, keep, nc)
    w = ((hi - lo)[:, fr] / (coarse - 1))[:, None, None, :]  # (P, 1, 1, nf)
    offs = np.stack(np.meshgrid(*[np.linspace(-1.0, 1.0, m)] * nf, indexing="ij"), axis=-1).reshape(
        -1, nf
    )  # (m^nf, nf)
    best_obj = np.take_along_axis(obj, top, axis=1)
    best_L = centre.copy()
    for r in range(rounds):
        trial = np.broadcast_to(best_L[:, :, None, :], (problems, keep, len(offs), nc)).copy()
        trial[..., fr] = np.clip(
            best_L[:, :, None, fr] + offs * w, lo[:, None, None, fr], hi[:, None, None, fr]
        )
        o, full = evaluate(trial.reshape(problems, -1, nc))
        o = o.reshape(problems, keep, -1)
        full = full.reshape(problems, keep, -1, nc)
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
