"""From a model's topology to an ordered plan of closed-form solve steps."""

from excavkin.structure.plan import SolvePlan, compile_plan

__all__ = ["SolvePlan", "compile_plan"]
