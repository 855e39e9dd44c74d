"""The state the step kernels work on, where the kinematics has always imported it from.

Each step kind's NumPy kernel lives in its own module of `excavkin.step_kinds` (its ``solve``);
the chunk of arrays they work on, the per-sample status codes and the helpers they share live
in `excavkin.step_kinds.state` and are named here too.
"""

from __future__ import annotations

from excavkin.step_kinds.state import Chunk, Code, dist, flag

__all__ = ["Chunk", "Code", "dist", "flag"]
