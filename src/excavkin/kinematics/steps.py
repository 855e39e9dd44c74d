"""One pass of a solve plan's steps over a chunk of samples, each step run by its kind."""

from __future__ import annotations

from excavkin.arrays import FloatArray as F
from excavkin.kinematics.kernels import Chunk
from excavkin.step_kinds import kind_of
from excavkin.structure.plan import SolvePlan


def run_steps(plan: SolvePlan, c: Chunk, order: int, newton: bool = True) -> list[F]:
    """Run the plan's steps over one chunk, in order; returns each Newton group's determinant
    sign (when ``order`` is 2). ``newton=False`` leaves the Newton groups' positions as they
    are (already found) and solves only their rates."""
    signs: list[F] = []
    for k, st in enumerate(plan.steps):
        kind = kind_of(st)
        sign = kind.solve(c, st, k, order, plan.scale, newton)
        if sign is not None:
            signs.append(sign)
        kind.nudge(c, st, order)  # the step's output rounded, emulated (with c.nudge)
    return signs
