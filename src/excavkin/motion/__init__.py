"""Motion laws of drivers and the drives of the seed papers (kernel layer: numpy only).

See ``docs/motion-laws.md`` for the formulas, peak coefficients and shock behaviour.
"""

from excavkin.motion.drives import ConstantSpeedCrank, RopeWinch, rope_speed
from excavkin.motion.laws import (
    LAW_NAMES,
    AccelerationJump,
    CubicLaw,
    CycloidalLaw,
    Dwell,
    HarmonicLaw,
    ModifiedSineLaw,
    ModifiedTrapezoidLaw,
    MotionLaw,
    MotionState,
    PeakCoefficients,
    Poly345Law,
    Poly4567Law,
    Profile,
    SCurveLaw,
    Segment,
    TrapezoidalLaw,
    dwell,
    get_law,
)

__all__ = [
    "LAW_NAMES",
    "AccelerationJump",
    "ConstantSpeedCrank",
    "CubicLaw",
    "CycloidalLaw",
    "Dwell",
    "HarmonicLaw",
    "ModifiedSineLaw",
    "ModifiedTrapezoidLaw",
    "MotionLaw",
    "MotionState",
    "PeakCoefficients",
    "Poly345Law",
    "Poly4567Law",
    "Profile",
    "RopeWinch",
    "SCurveLaw",
    "Segment",
    "TrapezoidalLaw",
    "dwell",
    "get_law",
    "rope_speed",
]
