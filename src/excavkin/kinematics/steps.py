"""One pass of a solve plan's steps over a chunk of samples, dispatching each step to its kernel."""

from __future__ import annotations

from excavkin.arrays import FloatArray as F
from excavkin.kinematics import kernels
from excavkin.kinematics.kernels import Chunk
from excavkin.kinematics.newton import newton_positions, newton_rates
from excavkin.structure.plan import Attach, Dyad, Fixed, NewtonGroup, Rotate, SliderStep, SolvePlan


def run_steps(plan: SolvePlan, c: Chunk, order: int, newton: bool = True) -> list[F]:
    """Run the plan's steps over one chunk, in order; returns each Newton group's determinant
    sign (when ``order`` is 2). ``newton=False`` leaves the Newton groups' positions as they
    are (already found) and solves only their rates."""
    signs: list[F] = []
    for k, st in enumerate(plan.steps):
        if isinstance(st, Dyad):
            kernels.dyad(c, st, order, k)
        elif isinstance(st, Attach):
            kernels.attach(c, st, order)
        elif isinstance(st, Rotate):
            kernels.rotate(c, st, order)
        elif isinstance(st, SliderStep):
            kernels.slider(c, st, order, k)
        elif isinstance(st, Fixed):
            kernels.fixed(c, st, order)
        elif isinstance(st, NewtonGroup):
            if newton:
                newton_positions(c, st, k, plan.scale)
            if order:
                signs.append(newton_rates(c, st, k))
        if c.nudge is not None and not isinstance(st, Fixed | NewtonGroup):
            # the step's output rounded, emulated
            for arr in (c.x, c.v, c.a) if order else (c.x,):
                arr[st.point] *= 1.0 + c.nudge
    return signs
