"""Batched Newton–Raphson for the points no closed-form step reaches, where the kinematics has
always imported it from: it lives with the Newton group's kind, in
`excavkin.step_kinds.newton_solve`."""

from __future__ import annotations

from excavkin.step_kinds.newton_solve import (
    CHORD_FROM,
    CHORD_RATE,
    SHRINK,
    keep_sides,
    newton_positions,
    newton_rates,
    rotary_branch_ok,
    side,
    tangents,
    wrong_side,
)

__all__ = [
    "CHORD_FROM",
    "CHORD_RATE",
    "SHRINK",
    "keep_sides",
    "newton_positions",
    "newton_rates",
    "rotary_branch_ok",
    "side",
    "tangents",
    "wrong_side",
]
