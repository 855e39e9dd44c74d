"""Many small dense linear systems at once, where the kinematics has always imported them
from: they live with the Newton group's kind, in `excavkin.step_kinds.small_systems`."""

from __future__ import annotations

from excavkin.step_kinds.small_systems import Factors

__all__ = ["Factors"]
