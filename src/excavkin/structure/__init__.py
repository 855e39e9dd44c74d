"""From a model's topology to an ordered plan of closed-form solve steps."""

from excavkin.structure.builder import compile_plan
from excavkin.structure.plan import SolvePlan

__all__ = ["SolvePlan", "compile_plan"]
