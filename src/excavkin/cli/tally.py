"""What the parts of a streamed solve said, told as the whole result would tell it.

A streamed solve decides only at its end whether the table may be written (failing samples,
statically singular ones); by then its parts are gone. The tally keeps what the messages need
— per reason, the count and the first samples with their inputs; which inputs vary over the
sweep; the change points — and words them as
[`KinematicResult.summary`][excavkin.kinematics.result.KinematicResult.summary] would for the
whole sweep.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from excavkin.kinematics import summary
from excavkin.kinematics.change_points import ChangePoint
from excavkin.kinematics.result import describe_inputs, sample_named
from excavkin.step_kinds import kind_of
from excavkin.structure.plan import SolvePlan


class Tally:
    """Failures, statically singular samples and change points over a streamed solve.

    Parameters
    ----------
    plan : SolvePlan
    limit : int
        Samples listed per reason.
    """

    def __init__(self, plan: SolvePlan, limit: int = 10) -> None:
        self.plan = plan
        self.limit = limit
        self.n = 0
        #: per reason: its count and its first samples (number, inputs, time, shortfall)
        self.groups: dict[str, list[Any]] = {}
        n_in = len(plan.inputs)
        self.low = np.full(n_in, np.nan)
        self.high = np.full(n_in, np.nan)
        self.singular: list[int] = []
        self.singular_count = 0
        #: samples where a rope would have to push: (rope names, first samples), count
        self.slack: list[int] = []
        self.slack_count = 0
        self.slack_ropes: dict[str, None] = {}
        self.change_points: list[ChangePoint] = []

    def add(self, start: int, result: Any) -> None:
        """Count a part's samples (``result``: its KinematicResult or ForceResult)."""
        kin = getattr(result, "kinematics", result)
        self.n += len(kin)
        q = kin.inputs
        if len(kin):
            self.low = np.fmin(self.low, np.fmin.reduce(q, axis=0))
            self.high = np.fmax(self.high, np.fmax.reduce(q, axis=0))
        self.change_points += kin.change_points
        code = kin.status.code
        bad = np.flatnonzero(code != 0)
        if bad.size:
            labels = kin.status.labels()[bad]
            for label in dict.fromkeys(labels):
                idx = bad[labels == label]
                group = self.groups.setdefault(str(label), [0, []])
                group[0] += idx.size
                room = self.limit - len(group[1])
                t = kin.time
                group[1] += [
                    (
                        start + int(i),
                        q[i].copy(),
                        None if t is None else float(t[i]),
                        kin.status.shortfall(int(i), "mm"),
                    )
                    for i in idx[: max(room, 0)]
                ]
        if kin is not result:
            singular = np.flatnonzero(result.singular & kin.status.ok)
            self.singular_count += singular.size
            room = self.limit - len(self.singular)
            self.singular += [start + int(i) for i in singular[: max(room, 0)]]
            self.add_slack(start, result)

    def add_slack(self, start: int, result: Any) -> None:
        """Count a force part's samples where a rope would have to push (not ok)."""
        kin = result.kinematics
        slack = np.flatnonzero(result.slack & kin.status.ok & ~result.singular)
        if not slack.size:
            return
        self.slack_count += slack.size
        room = self.limit - len(self.slack)
        self.slack += [start + int(i) for i in slack[: max(room, 0)]]
        for rope in kin.plan.model.ropes:
            if np.any(result.tension(rope.name)[slack] < 0.0):
                self.slack_ropes[rope.name] = None

    @property
    def all_ok(self) -> bool:
        """Whether every sample solved."""
        return not self.groups

    def summary(self) -> str:
        """The failing samples, grouped by reason, each named by its inputs: the whole
        result's [`summary`][excavkin.kinematics.result.KinematicResult.summary]."""
        held = (self.n > 1) & (self.low == self.high)
        groups = [
            (
                label,
                count,
                [
                    sample_named(i, describe_inputs(self.plan, q, held, t, i), short)
                    for i, q, t, short in shown
                ],
            )
            for label, (count, shown) in self.groups.items()
        ]
        return summary.failures(self.n, groups, self.limit)

    def singular_text(self) -> str | None:
        """The statically singular samples in a sentence, or None."""
        if not self.singular_count:
            return None
        listed = ", ".join(str(i) for i in self.singular)
        more = self.singular_count - len(self.singular)
        return (
            f"{self.singular_count} samples are statically singular (a redundant joint at "
            f"that position; their forces are NaN): samples {listed}"
            + (f" and {more} more" if more else "")
        )

    def slack_text(self) -> str | None:
        """The samples with a slack rope in a sentence, or None."""
        if not self.slack_count:
            return None
        listed = ", ".join(str(i) for i in self.slack)
        more = self.slack_count - len(self.slack)
        ropes = ", ".join(repr(r) for r in self.slack_ropes)
        return (
            f"{self.slack_count} samples have a slack rope ({ropes}: it would have to push, "
            f"and a rope pulls only, so their forces are not the mechanism's): samples {listed}"
            + (f" and {more} more" if more else "")
        )

    def sorted_change_points(self) -> list[ChangePoint]:
        """The change points as the whole result lists them: in plan order, each dyad's by
        sample."""
        order = {
            self.plan.points[d.point]: k
            for k, st in enumerate(self.plan.steps)
            for _, d in kind_of(st).folding(st)
        }
        return sorted(self.change_points, key=lambda cp: order[cp.point])
