"""Profiles: motion laws (and dwells) one after the other, as one driver's motion."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import numpy.typing as npt

from excavkin.motion.laws.base import AccelerationJump, MotionLaw, MotionState


@dataclass(frozen=True, slots=True)
class Segment:
    """One segment of a `Profile`.

    Parameters
    ----------
    law : MotionLaw
        The law; its ``start`` is the absolute start time of the segment [s].
    offset : float
        Position of the driver at the start of the segment [m or rad]; the segment moves
        from ``offset`` to ``offset + law.stroke``.
    """

    law: MotionLaw
    offset: float = 0.0


@dataclass(frozen=True, slots=True)
class Profile:
    """A motion profile: consecutive segments (rise, dwell, return, ...).

    Parameters
    ----------
    segments : tuple of Segment
        Time-ordered, contiguous segments (segment ``k`` starts where ``k − 1`` ends).
    rtol : float
        Relative tolerance of the join checks (see Notes). Default 1e-9.

    Raises
    ------
    ValueError
        If there are no segments, if segments overlap or leave a gap in time, or if ``s`` or
        ``v`` jump at a join. The message names the join, the quantity and the jump.

    Notes
    -----
    At join ``k`` (end of segment ``k − 1`` = start of segment ``k``) the one-sided values
    are ``s⁻ = offset[k−1] + s_{k−1}(end)``, ``s⁺ = offset[k] + s_k(start)``, and likewise
    for ``v``. Continuity requires ``|s⁺ − s⁻| <= rtol · max(|offset|, |H|)`` and
    ``|v⁺ − v⁻| <= rtol · max(|H|/T)`` over the segments. Jumps of ``a`` (soft shocks) are
    allowed and listed by `acceleration_jumps`. Before the first segment the profile
    holds its initial position, after the last its final one (``v = a = j = 0``). At a join
    the values of the later segment are returned.

    Examples
    --------
    >>> from excavkin.motion import CycloidalLaw, Profile, dwell
    >>> p = Profile.from_laws([CycloidalLaw(0.5, 2.0), dwell(1.0), CycloidalLaw(-0.5, 2.0)])
    >>> float(p.evaluate([3.0]).s[0])
    0.5
    """

    segments: tuple[Segment, ...]
    rtol: float = 1e-9

    def __post_init__(self) -> None:
        segs = tuple(self.segments)
        object.__setattr__(self, "segments", segs)
        if not segs:
            raise ValueError("Profile: at least one segment is required")
        scale_s = max(max(abs(sg.offset), abs(sg.law.stroke)) for sg in segs)
        scale_v = max(abs(sg.law.stroke) / sg.law.duration for sg in segs)
        scale_t = max(max(abs(sg.law.start), abs(sg.law.end)) for sg in segs)
        for k in range(1, len(segs)):
            prev, cur = segs[k - 1], segs[k]
            label = self._join_label(k)
            dt = cur.law.start - prev.law.end
            if abs(dt) > self.rtol * scale_t:
                kind = "gap" if dt > 0 else "overlap"
                raise ValueError(
                    f"Profile {label}: segment {k} starts at t = {cur.law.start!r} s but segment "
                    f"{k - 1} ends at t = {prev.law.end!r} s ({kind} of {abs(dt)!r} s); "
                    "insert a dwell or fix the start times"
                )
            left = prev.law.evaluate(np.array([prev.law.end]))
            right = cur.law.evaluate(np.array([cur.law.start]))
            s_l = prev.offset + float(left.s[0])
            s_r = cur.offset + float(right.s[0])
            if abs(s_r - s_l) > self.rtol * scale_s:
                raise ValueError(
                    f"Profile {label} at t = {cur.law.start!r} s: displacement s jumps by "
                    f"{s_r - s_l:.6g} (from {s_l:.9g} to {s_r:.9g})"
                )
            v_l, v_r = float(left.v[0]), float(right.v[0])
            if abs(v_r - v_l) > self.rtol * scale_v:
                raise ValueError(
                    f"Profile {label} at t = {cur.law.start!r} s: velocity v jumps by "
                    f"{v_r - v_l:.6g} (from {v_l:.9g} to {v_r:.9g}); a hard shock"
                )

    def _join_label(self, k: int) -> str:
        a, b = self.segments[k - 1].law, self.segments[k].law
        return f"join {k} (segment {k - 1} '{a.name}' -> segment {k} '{b.name}')"

    @classmethod
    def from_laws(
        cls,
        laws: Sequence[MotionLaw],
        *,
        s0: float = 0.0,
        t0: float = 0.0,
        rtol: float = 1e-9,
    ) -> Profile:
        """Chain laws one after the other, each starting where the previous one ended.

        The laws' own ``start`` is replaced; positions accumulate from ``s0``, so a return
        is simply a law with a negative stroke.

        Parameters
        ----------
        laws : sequence of MotionLaw
            In time order.
        s0 : float
            Initial position [m or rad].
        t0 : float
            Start time of the first segment [s].
        rtol : float
            See `Profile`.
        """
        segs: list[Segment] = []
        t, s = t0, s0
        for law in laws:
            moved = replace(law, start=t)
            segs.append(Segment(moved, s))
            t = moved.end
            s = s + law.stroke
        return cls(tuple(segs), rtol=rtol)

    @property
    def start(self) -> float:
        """Start time of the first segment [s]."""
        return self.segments[0].law.start

    @property
    def end(self) -> float:
        """End time of the last segment [s]."""
        return self.segments[-1].law.end

    @property
    def duration(self) -> float:
        """``end − start`` [s]."""
        return self.end - self.start

    @property
    def joins(self) -> tuple[float, ...]:
        """Times of the joins between segments [s], shape (n_segments − 1,)."""
        return tuple(sg.law.start for sg in self.segments[1:])

    def evaluate(self, t: npt.ArrayLike) -> MotionState:
        """Displacement, velocity, acceleration and jerk of the profile at times ``t``.

        Parameters
        ----------
        t : array_like, shape (n,)
            Times [s]. Any shape is accepted and preserved.

        Returns
        -------
        MotionState
            ``s, v, a, j``, each of shape (n,).
        """
        tt = np.asarray(t, dtype=np.float64)
        starts = np.array([sg.law.start for sg in self.segments[1:]], dtype=np.float64)
        idx = np.searchsorted(starts, tt, side="right")
        s = np.empty_like(tt)
        v = np.empty_like(tt)
        a = np.empty_like(tt)
        j = np.empty_like(tt)
        for k, sg in enumerate(self.segments):  # loop over segments, not samples
            m = idx == k
            if not np.any(m):
                continue
            st = sg.law.evaluate(tt[m])
            s[m] = sg.offset + st.s
            v[m] = st.v
            a[m] = st.a
            j[m] = st.j
        return MotionState(s, v, a, j)

    def acceleration_jumps(self, rtol: float | None = None) -> tuple[AccelerationJump, ...]:
        """Jumps of acceleration at the joins, at the start and at the end (rest outside).

        Jumps inside a segment (e.g. the corners of a trapezoidal law) are listed by that
        law's
        [`MotionLaw.acceleration_jumps`][excavkin.motion.laws.base.MotionLaw.acceleration_jumps],
        not here.

        Parameters
        ----------
        rtol : float, optional
            A jump is reported when ``|Δa| > rtol · max(|H|/T²)`` over the segments.
            Defaults to the profile's ``rtol``.

        Returns
        -------
        tuple of AccelerationJump
            In time order.
        """
        tol = (self.rtol if rtol is None else rtol) * max(
            abs(sg.law.stroke) / sg.law.duration**2 for sg in self.segments
        )
        a_end = [float(sg.law.evaluate(np.array([sg.law.end])).a[0]) for sg in self.segments]
        a_start = [float(sg.law.evaluate(np.array([sg.law.start])).a[0]) for sg in self.segments]
        cand = [AccelerationJump(self.start, "start", 0.0, a_start[0])]
        for k in range(1, len(self.segments)):
            cand.append(
                AccelerationJump(
                    self.segments[k].law.start, self._join_label(k), a_end[k - 1], a_start[k]
                )
            )
        cand.append(AccelerationJump(self.end, "end", a_end[-1], 0.0))
        return tuple(c for c in cand if abs(c.jump) > tol)
