"""The state a step kernel works on: a chunk of samples' arrays, and per-sample status codes.

State lives in struct-of-arrays form: ``x[i, 0]`` is the x coordinate of point i over the chunk
(a contiguous row), likewise velocities ``v`` and accelerations ``a``. Each kernel computes its
point's position and, when ``order == 2``, its velocity and acceleration by solving the
*differentiated* constraints — never by finite differences.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.step_kinds.dist import Dist


class Code(IntEnum):
    """Per-sample status codes."""

    OK = 0
    NO_CLOSURE = 1
    SINGULAR = 2
    NO_CONVERGENCE = 3
    BRANCH_CHANGED = 4
    BAD_INPUT = 5
    BAD_LENGTH = 6
    NOT_FINITE = 7
    UNDETERMINED = 8
    IMPRECISE = 9
    BAD_DESIGN = 10
    OUT_OF_REACH = 11
    ROPE_OFF_SHEAVE = 12


@dataclass(slots=True)
class Chunk:
    """Views of the solve arrays for one chunk of samples."""

    x: F  # (n_points, 2, c)
    v: F
    a: F
    q: F  # (n_inputs, c)
    qd: F
    qdd: F
    trans: F  # (n_trans, c)
    status: NDArray[np.int8]  # (c,)
    failed: NDArray[np.int16]  # (c,)
    close_tol: float
    singular_tol: float
    #: how far each sample is from a dead position of a Newton group (the Jacobian's
    #: determinant over its rows' norms), where the solve keeps it
    near: F | None = None
    #: the precision check's emulated rounding: per-sample ±units by which each step's
    #: cancelling quantity (a dyad's or slider's squared half-chord) and its output are moved
    nudge: F | None = None


def flag(c: Chunk, mask: NDArray[np.bool_], code: Code, step: int) -> None:
    """Give ``code`` to the samples in ``mask`` that are still OK (the first failure wins).

    Parameters
    ----------
    c : Chunk
        The chunk whose ``status`` and ``failed`` are written.
    mask : ndarray of bool, shape (c,)
        The samples that fail.
    code : Code
        Why.
    step : int
        The plan step that fails them.
    """
    hit = mask & (c.status == 0)
    if hit.any():
        c.status[hit] = code
        c.failed[hit] = step


def dist(c: Chunk, d: Dist) -> tuple[F | float, F | float, F | float]:
    """A distance and its first and second time derivatives.

    Parameters
    ----------
    c : Chunk
        The chunk (its inputs, for an input's distance).
    d : Dist
        The distance.

    Returns
    -------
    tuple of (float or ndarray, shape (c,))
        The value, its rate and its acceleration.
    """
    if d.kind == "fixed":
        if c.x.dtype != np.float64:  # a wider solve: products of lengths in its own precision
            return c.x.dtype.type(d.value), 0.0, 0.0
        return d.value, 0.0, 0.0
    if d.winch:  # a winch: the blocks' distance from its motor's angle
        k = d.scale
        return k * c.q[d.input], k * c.qd[d.input], k * c.qdd[d.input]
    return c.q[d.input], c.qd[d.input], c.qdd[d.input]


def round_output(c: Chunk, point: int, order: int) -> None:
    """The precision check's emulated rounding of a step's output point: its position (and
    rates, at order 2) moved by ``c.nudge`` units, in place (nothing without a nudge).

    Parameters
    ----------
    c : Chunk
        The chunk.
    point : int
        The step's point.
    order : int
        0: positions only; 2: velocities and accelerations too.
    """
    if c.nudge is None:
        return
    for arr in (c.x, c.v, c.a) if order else (c.x,):
        arr[point] *= 1.0 + c.nudge
