"""Random sketches for the property tests: accept only well-spread, non-degenerate ones."""

from __future__ import annotations

import numpy as np

WATT_NAMES = ("O2", "A", "B", "O4", "C", "D", "O6")


def spread(pts: list[tuple[float, float]], min_dist: float = 0.05) -> bool:
    """Every pair of points at least ``min_dist`` apart."""
    arr = np.array(pts)
    d = np.hypot(*(arr[:, None, :] - arr[None, :, :]).transpose(2, 0, 1))
    return bool(np.all(d[np.triu_indices(len(pts), 1)] > min_dist))


def not_collinear(a: tuple, b: tuple, p: tuple, tol: float = 0.02) -> bool:  # type: ignore[type-arg]
    """``p`` is clearly off the line through ``a`` and ``b`` (the sketch shows a branch)."""
    return abs((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) > tol


def watt_sketch(pts: list[tuple[float, float]]) -> dict[str, tuple[float, float]] | None:
    """Named points of a Watt II six-bar sketch, or None when the draw is degenerate."""
    if not spread(pts):
        return None
    p = dict(zip(WATT_NAMES, pts, strict=True))
    ok = (
        not_collinear(p["A"], p["O4"], p["B"])
        and not_collinear(p["C"], p["O6"], p["D"])
        and not_collinear(p["O4"], p["B"], p["C"])
    )
    return p if ok else None
