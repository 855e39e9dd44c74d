r"""The length of a rope over sheaves, with its exact derivatives.

The rope runs from its first point over a sheave centred at each inner point of its path to its
last point. A sheave's signed radius ``s = σ·r`` has σ = +1 where the rope turns
counter-clockwise around it (the sheave on the rope's left), −1 clockwise; the ends have s = 0.
Between path points k and k+1 the free segment leaves sheave k at ``P_k = c_k − s_k·n`` and
reaches sheave k+1 at ``P_{k+1} = c_{k+1} − s_{k+1}·n``, n = perp(u) the segment's left
normal, u its direction::

    ℓ·u = D + ρ·n,   D = c_{k+1} − c_k,   ρ = s_k − s_{k+1}
    ℓ = sqrt(|D|² − ρ²),   u = (ℓ·D + ρ·perp(D)) / |D|²

On sheave k the rope wraps ``φ_k = σ_k·(angle of u_k − angle of u_{k−1})`` (taken on the branch
nearest the sketch's), and its length is ``L = Σ ℓ_k + Σ r_k·φ_k``.

Derivatives: a segment turns at ``ω_k = n_k·Ḋ_k/ℓ_k``, and its length changes at
``u_k·Ḋ_k − ρ_k·ω_k``; the arcs change at ``Σ r_k·φ̇_k = Σ ρ_k·ω_k``, which cancels, so::

    L̇ = Σ u_k·Ḋ_k          ∂L/∂c_k = u_{k−1} − u_k
    L̈ = Σ u_k·D̈_k + Σ (n_k·Ḋ_k)² / ℓ_k

exact at every order, the tension acting along each free segment: the rope pulls sheave k's pin
with ``T·(u_k − u_{k−1})``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["RopePath", "rope_path", "segment_directions", "sketch_wraps"]

TWO_PI = 2.0 * math.pi


class RopePath:
    """A rope's free segments and length over a batch (values may be dual numbers).

    Attributes
    ----------
    ux, uy : list
        Each free segment's unit direction, from path point k to k+1.
    ell : list
        Each free segment's length (m).
    wraps : list
        The wrap angle on each sheave (rad), one per inner point.
    length : array_like
        The rope's length (m): the segments and the arcs.
    """

    __slots__ = ("ell", "length", "ux", "uy", "wraps")

    def __init__(self, ux: list[Any], uy: list[Any], ell: list[Any], wraps: list[Any], length: Any):
        self.ux, self.uy, self.ell, self.wraps, self.length = ux, uy, ell, wraps, length

    def rate(self, vel: Sequence[tuple[Any, Any]]) -> Any:
        """``L̇ = Σ u_k·(v_{k+1} − v_k)`` for the path points' velocities.

        Parameters
        ----------
        vel : sequence of (vx, vy)
            Each path point's velocity.

        Returns
        -------
        array_like
            The length's rate (m/s).
        """
        out: Any = 0.0
        for k in range(len(self.ux)):
            dx, dy = vel[k + 1][0] - vel[k][0], vel[k + 1][1] - vel[k][1]
            out = out + self.ux[k] * dx + self.uy[k] * dy
        return out

    def curvature(self, vel: Sequence[tuple[Any, Any]]) -> Any:
        """``Σ (n_k·Ḋ_k)²/ℓ_k``: what the segments' turning adds to L̈ beyond Σ u_k·D̈_k.

        Parameters
        ----------
        vel : sequence of (vx, vy)
            Each path point's velocity.

        Returns
        -------
        array_like
            m/s².
        """
        out: Any = 0.0
        for k in range(len(self.ux)):
            dx, dy = vel[k + 1][0] - vel[k][0], vel[k + 1][1] - vel[k][1]
            w = -self.uy[k] * dx + self.ux[k] * dy
            out = out + w * w / self.ell[k]
        return out


def segment_directions(
    pts: Sequence[tuple[Any, Any]], signed: Sequence[float]
) -> tuple[list[Any], list[Any]]:
    """Each free segment's unit direction ``u = (ℓ·D + ρ·perp(D))/|D|²``, by arithmetic and one
    square root a segment (so that the compiled equilibrium can trace it).

    Parameters
    ----------
    pts : sequence of (x, y)
        Each path point's coordinates (m).
    signed : sequence of float
        Each path point's signed sheave radius (m), 0 at the ends.

    Returns
    -------
    ux, uy : list
        One per segment, from path point k to k+1.
    """
    ux: list[Any] = []
    uy: list[Any] = []
    for k in range(len(pts) - 1):
        dx, dy = pts[k + 1][0] - pts[k][0], pts[k + 1][1] - pts[k][1]
        rho = signed[k] - signed[k + 1]
        d2 = dx * dx + dy * dy
        inv = 1.0 / d2
        if isinstance(rho, float) and rho == 0.0:
            length = np.sqrt(d2)
            ux.append(length * dx * inv)
            uy.append(length * dy * inv)
            continue
        length = np.sqrt(d2 - rho * rho)
        ux.append((length * dx - rho * dy) * inv)
        uy.append((length * dy + rho * dx) * inv)
    return ux, uy


def rope_path(
    pts: Sequence[tuple[Any, Any]], signed: Sequence[float], wraps0: Sequence[float]
) -> RopePath:
    """The free segments, the wraps and the length of a rope over sheaves.

    Parameters
    ----------
    pts : sequence of (x, y)
        Each path point's coordinates (m): arrays of one value per sample, or dual numbers.
    signed : sequence of float
        Each path point's signed sheave radius σ·r (m), 0 at the two ends.
    wraps0 : sequence of float
        Each path point's wrap angle at the sketch (rad; 0 at the ends): the branch of each
        wrap is the one nearest it.

    Returns
    -------
    RopePath
        NaN where a segment has no tangent (two sheaves overlapping across it).
    """
    ux: list[Any] = []
    uy: list[Any] = []
    ell: list[Any] = []
    for k in range(len(pts) - 1):
        dx, dy = pts[k + 1][0] - pts[k][0], pts[k + 1][1] - pts[k][1]
        rho = signed[k] - signed[k + 1]
        d2 = dx * dx + dy * dy
        with np.errstate(invalid="ignore"):
            length = np.sqrt(d2 - rho * rho)
        ell.append(length)
        ux.append((length * dx - rho * dy) / d2)
        uy.append((length * dy + rho * dx) / d2)
    total: Any = 0.0
    for length in ell:
        total = total + length
    wraps: list[Any] = []
    for k in range(1, len(pts) - 1):
        cross = ux[k - 1] * uy[k] - uy[k - 1] * ux[k]
        dot = ux[k - 1] * ux[k] + uy[k - 1] * uy[k]
        own = np.asarray(getattr(signed[k], "val", signed[k]), dtype=np.float64)
        sigma = np.where(own > 0, 1.0, -1.0)  # (per design where the radii are)
        phi = sigma * np.arctan2(cross, dot)
        plain = np.asarray(getattr(phi, "val", phi), dtype=np.float64)
        with np.errstate(invalid="ignore"):
            turns = np.round((wraps0[k] - plain) / TWO_PI)
        phi = phi + TWO_PI * np.where(np.isfinite(turns), turns, 0.0)
        wraps.append(phi)
        total = total + abs(signed[k]) * phi
    return RopePath(ux, uy, ell, wraps, total)


def sketch_wraps(pts: Sequence[tuple[float, float]], signed: Sequence[float]) -> tuple[float, ...]:
    """Each path point's wrap angle at the sketch, in [0, 2π) (0 at the ends).

    Parameters
    ----------
    pts : sequence of (float, float)
        The path points' sketch coordinates (m).
    signed : sequence of float
        Their signed sheave radii (m), 0 at the ends.

    Returns
    -------
    tuple of float
        rad; NaN where a segment has no tangent.
    """
    geo = rope_path([(np.float64(x), np.float64(y)) for x, y in pts], signed, [math.pi] * len(pts))
    inner = [float(np.mod(w, TWO_PI)) for w in geo.wraps]
    return (0.0, *inner, 0.0)
