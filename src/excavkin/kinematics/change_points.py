"""Change points between samples: where a dyad folds flat between two neighbouring samples.

A dyad keeps the side of its base A→B that the sketch shows. At a change point (a
parallelogram's crank passing its ground pivot, a kite folding flat) the triangle A, B, P
degenerates, and a mechanism moving on may come out on either side; the side rule then takes
the sketch's side, which — seen from the samples either side — is a jump to the folded (or
crossed) configuration. It is found from the samples alone: P at sample i + 1 lies much
farther from P at sample i than P's mirror image in the line A→B does.

Where the triangle folds *flat* with its base A→B still long (a parallelogram at 180°, the
MO-100 hammer's blow), the side rule keeps P on its side and its path bends back instead of
jumping: P's distance s from the line A→B runs down to zero and up again, a V. It is found
from the samples and their rates: between neighbours, ṡ turns from approach to retreat with
about the same speed, and s at the two samples adds up to the distance that speed covers in
the step (a smooth turn short of the line covers about half of it).

``continuation="smooth"`` instead keeps the motion continuous: after each change point the
dyad takes the other side, so a parallelogram stays a parallelogram.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.step_kinds import kind_of
from excavkin.structure.plan import Dyad, GroupDyad, SolvePlan

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
    shape : {"jump", "bend"}
        On the sketch's side, the configuration jumps (the base A→B vanishes, a parallelogram's
        crank passing its ground pivot) or P's path bends back (the triangle folds flat on a
        long base).
    """

    point: str
    partners: tuple[str, str]
    before: int
    after: int
    continued: str
    shape: str = "jump"

    def describe(self) -> str:
        """One sentence for a person."""
        kept = "a jump of the configuration" if self.shape == "jump" else "its path bends back"
        how = (
            f"kept the sketch's side of its base ({kept})"
            if self.continued == "side"
            else "continued the motion on the other side"
        )
        a, b = self.partners
        return (
            f"change point of dyad {self.point} (from {a} and {b}) between samples "
            f"{self.before} and {self.after}: the engine {how}"
        )


#: a dyad whose transmission angle keeps sin γ at least this over a sweep cannot fold in it
NEVER_FLAT = 0.3

#: neighbouring solved samples are compared across at most this many unsolved ones (a fold
#: exactly on a sample leaves that one undetermined)
MAX_GAP = 2


#: a dyad's place in a plan: its step, and its place among a Newton group's dyads (−1 for a
#: closed-form dyad step)
Unit = tuple[int, int]

#: what a change point is searched in: a closed-form dyad or a Newton group's
Folding = Dyad | GroupDyad


def dyads(plan: SolvePlan) -> list[tuple[Unit, Folding]]:
    """Every dyad of a plan, in the order they are solved: its dyad steps, and the dyads inside
    its Newton groups (`excavkin.structure.group_dyads`), which fold as those do."""
    out: list[tuple[Unit, Folding]] = []
    for k, st in enumerate(plan.steps):
        out += [((k, j), d) for j, d in kind_of(st).folding(st)]
    return out


def folds(x: F, st: Folding) -> np.ndarray:
    """Samples i (of pairs i, j, the next solved sample) between which the dyad ``st`` folds;
    x: (n_points, 2, n)."""
    p = x[st.point]
    i, j = _neighbours(np.isfinite(p).all(axis=0))
    if not np.arange(p.shape[-1])[i].size:
        return np.zeros((2, 0), dtype=np.int64)
    jump = np.hypot(*(p[:, j] - p[:, i]))
    # a fold needs a nearly degenerate triangle at one of the two samples: its base nearly
    # gone, or P nearly on it — so a coarse sweep's big step is not taken for one. That test
    # first, on every pair; the mirror image only for the few pairs that pass it.
    flat = _flatness(x, st)
    with np.errstate(invalid="ignore"):
        near = np.flatnonzero((jump > 0) & (np.minimum(flat[i], flat[j]) < 0.25 * jump))
    i, j, jump = _picked(i, near), _picked(j, near), jump[near]
    a, b = x[st.a][:, j], x[st.b][:, j]
    nxt, prev = p[:, j], p[:, i]
    e = b - a
    e2 = e[0] * e[0] + e[1] * e[1]
    r = nxt - a
    # the mirror image of P in the line A→B
    with np.errstate(invalid="ignore", divide="ignore"):
        t = (r[0] * e[0] + r[1] * e[1]) / np.where(e2 > 0, e2, np.nan)
        mirror = a + 2.0 * t * e - r
        back = np.hypot(*(mirror - prev))
        found = back < MIRROR_RATIO * jump
    return np.stack([i[found], j[found]])


def _flatness(x: F, st: Folding) -> F:
    """How far the dyad's triangle is from degenerate at every sample: the smaller of its base
    length |B − A| and the distance of P from the line A→B."""
    a, b, p = x[st.a], x[st.b], x[st.point]
    e, r = b - a, p - a
    base = np.hypot(*e)
    with np.errstate(invalid="ignore", divide="ignore"):
        off = np.abs(e[0] * r[1] - e[1] * r[0]) / base
    return np.asarray(np.minimum(base, np.where(np.isfinite(off), off, 0.0)), dtype=np.float64)


Pairs = tuple["np.ndarray | slice", "np.ndarray | slice"]


def _neighbours(solved: np.ndarray) -> Pairs:
    """Pairs (i, j) of neighbouring solved samples, across at most MAX_GAP unsolved ones: as
    two slices when every sample solved (views, no gathering), else as index arrays."""
    n = solved.size
    if solved.all():
        return slice(0, max(n - 1, 0)), slice(1, n)
    idx = np.flatnonzero(solved)
    pairs = np.diff(idx) <= MAX_GAP + 1
    return idx[:-1][pairs], idx[1:][pairs]


def _picked(ix: np.ndarray | slice, sel: np.ndarray) -> np.ndarray:
    """The samples of a pair side at the positions ``sel``."""
    if isinstance(ix, slice):
        return np.asarray(np.arange(ix.start, ix.stop)[sel])
    return np.asarray(ix[sel])


def bends(x: F, v: F, q: F, qd: F, st: Folding) -> np.ndarray:
    """Samples (i, j) between which the dyad ``st`` folds flat on a long base and P's path bends
    back; x, v: (n_points, 2, n), q, qd: (n_inputs, n)."""
    i, j = _neighbours(np.isfinite(x[st.point]).all(axis=0) & np.isfinite(v[st.point]).all(axis=0))
    if not np.arange(x.shape[-1])[i].size:
        return np.zeros((2, 0), dtype=np.int64)
    e = x[st.b] - x[st.a]
    r = x[st.point] - x[st.a]
    de = v[st.b] - v[st.a]
    dr = v[st.point] - v[st.a]
    with np.errstate(divide="ignore", invalid="ignore"):
        base = np.hypot(*e)
        cross = e[0] * r[1] - e[1] * r[0]
        side = np.sign(cross)
        s = np.abs(cross) / base  # P's distance from the line A→B
        sd = side * (
            (de[0] * r[1] - de[1] * r[0] + e[0] * dr[1] - e[1] * dr[0]) / base
            - cross * (e[0] * de[0] + e[1] * de[1]) / base**3
        )
        # only where ṡ turns round between the two samples
        turn = np.flatnonzero(np.sign(sd[i]) * np.sign(sd[j]) < 0)
        i, j = _picked(i, turn), _picked(j, turn)
        # the step's duration, from the input that moves most in it at a known rate
        rate = 0.5 * (qd[:, i] + qd[:, j])
        steps = np.where(rate != 0, (q[:, j] - q[:, i]) / rate, np.nan)
        moved = np.where(np.isfinite(steps), np.abs(q[:, j] - q[:, i]), -1.0)
        dt = np.take_along_axis(steps, np.argmax(moved, axis=0)[None], axis=0)[0]
        speed = 0.5 * (np.abs(sd[i]) + np.abs(sd[j]))
        covered = speed * np.abs(dt)
        ratio = np.abs(sd[i]) / np.abs(sd[j])
        found = (
            (np.sign(dt) * sd[i] < 0)  # approaching the line along the sweep
            & (np.sign(dt) * sd[j] > 0)  # … and leaving it on the same side
            & (ratio > 1 / 3)
            & (ratio < 3)
            & (np.abs(s[i] + s[j] - covered) <= 0.25 * covered)
            & (covered < 0.5 * base[i])  # a long base: a flat fold, not a vanishing one
        )
    return np.stack([i[found], j[found]])


def _changes(
    x: F, v: F | None, q: F | None, qd: F | None, st: Folding
) -> list[tuple[int, int, str]]:
    """The dyad's change points as (before, after, shape), in sample order."""
    out = [(int(i), int(j), "jump") for i, j in folds(x, st).T]
    if v is not None and q is not None and qd is not None:
        jumps = {(i, j) for i, j, _ in out}
        out += [
            (int(i), int(j), "bend") for i, j in bends(x, v, q, qd, st).T if (i, j) not in jumps
        ]
    return sorted(out)


def find_change_points(
    plan: SolvePlan,
    x: F,
    continued: str = "side",
    v: F | None = None,
    q: F | None = None,
    qd: F | None = None,
    trans: F | None = None,
    *,
    offset: int = 0,
    tail: Tail | None = None,
    only: Unit | None = None,
) -> list[ChangePoint]:
    """Every dyad's change points between neighbouring samples, in plan order (bends too when
    the velocities and inputs are given); the dyads inside Newton groups count as dyads
    (`dyads`); ``only``: that one dyad's.

    With the transmission angles ``trans`` (n_transmissions, n), a dyad whose triangle never
    comes nearer flat than sin γ = `NEVER_FLAT` is passed over: its triangle's height
    and base then stay above about a sixth of its shorter side, so a fold between two samples
    would need P to move more than half a link in one step — no sweep that can be read. (A
    Newton group's dyad has no transmission angle of the plan's: its angle is measured from
    the positions, as a closed-form dyad's is.)

    The samples are numbered from ``offset``. With the ``tail`` of the samples just before
    them (`Tail.of`), the change points between the two stretches are found too, so
    that a sweep searched stretch by stretch finds what a search of the whole would (pairs
    are neighbours across at most `MAX_GAP` unsolved samples; ``trans`` then covers the
    tail as well).
    """
    out = []
    names = plan.points
    for unit, st in searched(plan, x, trans, tail):
        if only is not None and unit != only:
            continue
        found = [] if tail is None else _across(tail, x, v, q, qd, st, offset)
        found += [(i + offset, j + offset, shape) for i, j, shape in _changes(x, v, q, qd, st)]
        for i, j, shape in found:
            partners = (names[st.a], names[st.b])
            out.append(ChangePoint(names[st.point], partners, i, j, continued, shape))
    return out


def searched(
    plan: SolvePlan, x: F, trans: F | None, tail: Tail | None = None
) -> list[tuple[Unit, Folding]]:
    """The dyads that `find_change_points` searches: every one without ``trans``, else those
    whose triangle comes nearer flat than sin γ = `NEVER_FLAT` in these samples or the
    ``tail`` (a Newton group's dyad's angle measured from the positions ``x``; a closed-form
    dyad's read from ``trans`` alone).

    Parameters
    ----------
    plan : SolvePlan
    x : ndarray, shape (n_points, 2, n)
        The positions (read for a Newton group's dyads only).
    trans : ndarray, shape (n_transmissions, n), optional
    tail : Tail, optional

    Returns
    -------
    list of (Unit, Folding)
        In plan order.
    """
    out: list[tuple[Unit, Folding]] = []
    for unit, st in dyads(plan):
        if trans is not None:
            if not isinstance(st, GroupDyad):  # a closed-form dyad: its own angle
                angles = [trans[st.index]] + ([] if tail is None else [tail.trans[st.index]])
            else:
                angles = [_angles(x, st)] + ([] if tail is None else [_angles(tail.x, st)])
            if min(_flattest(t) for t in angles) >= NEVER_FLAT:
                continue
        out.append((unit, st))
    return out


def _angles(x: F, st: GroupDyad) -> F:
    """A Newton group's dyad's transmission angle at every sample, as the dyad kernel's."""
    r1, r2 = x[st.point] - x[st.a], x[st.point] - x[st.b]
    det = r1[0] * r2[1] - r1[1] * r2[0]
    return np.arctan2(np.abs(det), r1[0] * r2[0] + r1[1] * r2[1])  # type: ignore[no-any-return]


def _flattest(trans: F) -> float:
    """The least |sin γ| of transmission angles γ (NaN passed over; 1 if none): from their
    least and greatest, as |sin| grows with the distance from 0 and π — two passes over the
    samples where a sine of each would cost ten times as much."""
    if not trans.size:
        return 1.0
    lo = float(np.nanmin(trans, initial=np.inf))
    hi = float(np.nanmax(trans, initial=-np.inf))
    if lo > hi:  # all NaN
        return 1.0
    if lo >= 0.0 and hi <= np.pi:
        return min(float(np.sin(min(lo, np.pi - hi))), 1.0)
    with np.errstate(invalid="ignore"):
        return float(np.nanmin(np.abs(np.sin(trans)), initial=1.0))


@dataclass(frozen=True, slots=True)
class Tail:
    """The last samples of a stretch of a sweep, as many as a change point can reach back
    across (`MAX_GAP` unsolved samples and one solved): x, v (n_points, 2, k), q, qd
    (n_inputs, k) and the transmission angles (n_transmissions, k), copied."""

    x: F
    v: F
    q: F
    qd: F
    trans: F

    @classmethod
    def of(cls, x: F, v: F, q: F, qd: F, trans: F, before: Tail | None = None) -> Tail:
        """The tail of a stretch (``before``: the tail of the stretch before it, for a stretch
        shorter than a tail)."""
        k = MAX_GAP + 1
        if before is not None and x.shape[-1] < k:
            x, v, q, qd, trans = (
                np.concatenate([old, new], axis=-1)
                for old, new in zip(
                    (before.x, before.v, before.q, before.qd, before.trans),
                    (x, v, q, qd, trans),
                    strict=True,
                )
            )
        return cls(*(arr[..., -k:].copy() for arr in (x, v, q, qd, trans)))


def _across(
    tail: Tail, x: F, v: F | None, q: F | None, qd: F | None, st: Folding, offset: int
) -> list[tuple[int, int, str]]:
    """The dyad's change points between a tail and the samples after it (numbered from
    ``offset``)."""
    k = tail.x.shape[-1]
    head = MAX_GAP + 1

    def joined(before: F, after: F | None) -> F | None:
        return None if after is None else np.concatenate([before, after[..., :head]], axis=-1)

    found = _changes(
        joined(tail.x, x),  # type: ignore[arg-type]
        joined(tail.v, v),
        joined(tail.q, q),
        joined(tail.qd, qd),
        st,
    )
    return [(i - k + offset, j - k + offset, shape) for i, j, shape in found if i < k <= j]
