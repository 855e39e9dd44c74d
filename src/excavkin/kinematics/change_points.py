"""Change points between samples: where a dyad folds flat between two neighbouring samples.

A dyad keeps the side of its base A→B that the sketch shows. At a change point (a
parallelogram's crank passing its ground pivot, a kite folding flat) the triangle A, B, P
degenerates, and a mechanism moving on may come out on either side; the side rule then takes
the sketch's side, which — seen from the samples either side — is a jump to the folded (or
crossed) configuration. It is found from the samples alone: P at sample i + 1 lies much
farther from P at sample i than P's mirror image in the line A→B does.

``continuation="smooth"`` instead keeps the motion continuous: after each change point the
dyad takes the other side, so a parallelogram stays a parallelogram.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from excavkin.kinematics.kernels import F
from excavkin.structure.plan import Dyad, SolvePlan

#: the mirror image must be this much closer to the previous sample than the point itself
MIRROR_RATIO = 0.5


@dataclass(frozen=True, slots=True)
class ChangePoint:
    """A dyad that folds between two neighbouring samples.

    Attributes
    ----------
    point : str
        The dyad's point.
    partners : (str, str)
        Its two partners A and B.
    before, after : int
        The samples either side of the fold.
    continued : {"side", "smooth"}
        How the engine went on: on the sketch's side of A→B (``"side"``) or on the other side,
        continuing the motion (``"smooth"``).
    """

    point: str
    partners: tuple[str, str]
    before: int
    after: int
    continued: str

    def describe(self) -> str:
        """One sentence for a person."""
        how = (
            "kept the sketch's side of its base (a jump of the configuration)"
            if self.continued == "side"
            else "continued the motion on the other side"
        )
        a, b = self.partners
        return (
            f"change point of dyad {self.point} (from {a} and {b}) between samples "
            f"{self.before} and {self.after}: the engine {how}"
        )


#: neighbouring solved samples are compared across at most this many unsolved ones (a fold
#: exactly on a sample leaves that one undetermined)
MAX_GAP = 2


def folds(x: F, st: Dyad) -> np.ndarray:
    """Samples i (of pairs i, j, the next solved sample) between which the dyad ``st`` folds;
    x: (n_points, 2, n)."""
    p = x[st.point]
    solved = np.flatnonzero(np.isfinite(p).all(axis=0))
    pairs = np.diff(solved) <= MAX_GAP + 1
    i, j = solved[:-1][pairs], solved[1:][pairs]
    if not i.size:
        return np.zeros((2, 0), dtype=np.int64)
    a, b = x[st.a][:, j], x[st.b][:, j]
    nxt, prev = p[:, j], p[:, i]
    e = b - a
    e2 = e[0] * e[0] + e[1] * e[1]
    r = nxt - a
    # the mirror image of P in the line A→B
    t = (r[0] * e[0] + r[1] * e[1]) / np.where(e2 > 0, e2, np.nan)
    mirror = a + 2.0 * t * e - r
    jump = np.hypot(*(nxt - prev))
    back = np.hypot(*(mirror - prev))
    # a fold needs a nearly degenerate triangle at one of the two samples: its base nearly
    # gone, or P nearly on it — so a coarse sweep's big step is not taken for one
    flat = np.minimum(_flatness(x, st, i), _flatness(x, st, j))
    with np.errstate(invalid="ignore"):
        found = (back < MIRROR_RATIO * jump) & (jump > 0) & (flat < 0.25 * jump)
    return np.stack([i[found], j[found]])


def _flatness(x: F, st: Dyad, k: np.ndarray) -> F:
    """How far the dyad's triangle is from degenerate at samples ``k``: the smaller of its base
    length |B − A| and the distance of P from the line A→B."""
    a, b, p = x[st.a][:, k], x[st.b][:, k], x[st.point][:, k]
    e, r = b - a, p - a
    base = np.hypot(*e)
    with np.errstate(invalid="ignore", divide="ignore"):
        off = np.abs(e[0] * r[1] - e[1] * r[0]) / base
    return np.asarray(np.minimum(base, np.where(np.isfinite(off), off, 0.0)), dtype=np.float64)


def find_change_points(plan: SolvePlan, x: F, continued: str = "side") -> list[ChangePoint]:
    """Every dyad's change points between neighbouring samples, in plan order."""
    out = []
    names = plan.points
    for st in plan.steps:
        if isinstance(st, Dyad):
            for i, j in folds(x, st).T:
                partners = (names[st.a], names[st.b])
                out.append(ChangePoint(names[st.point], partners, int(i), int(j), continued))
    return out


def smooth_signs(x: F, st: Dyad, anchor: int) -> F | None:
    """Per-sample branch signs that continue the motion through the dyad's change points, or
    None when it has none. The sample ``anchor`` (the one nearest the sketch) keeps the
    sketch's side; every change point between a sample and the anchor flips it once more."""
    found = folds(x, st)
    if not found.size:
        return None
    n = x.shape[-1]
    up = np.zeros(n, dtype=np.int64)
    down = np.zeros(n, dtype=np.int64)
    ahead = found[0] >= anchor
    up[found[1][ahead]] = 1  # crossing it moving away from the anchor, forwards
    down[found[0][~ahead]] = 1  # … and backwards
    flips = np.cumsum(up) + np.cumsum(down[::-1])[::-1]
    return np.asarray(st.sign * (-1.0) ** flips, dtype=np.float64)
