"""A dwell: the driver holds still for a time (a law of zero stroke, for profiles)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from excavkin.arrays import FloatArray
from excavkin.motion.laws.base import MotionLaw, PeakCoefficients, ShapeValues


@dataclass(frozen=True, slots=True)
class Dwell(MotionLaw):
    """A dwell: ``s = 0`` over ``[t0, t0 + T]``; ``stroke`` must be 0 (see `dwell`)."""

    name: ClassVar[str] = "dwell"

    def _validate(self) -> None:
        if self.stroke != 0.0:
            raise ValueError(f"Dwell: stroke must be 0, got {self.stroke!r}")

    def _shape(self, u: FloatArray, left: bool = False) -> ShapeValues:
        z = np.zeros_like(u)
        return z, z.copy(), z.copy(), z.copy()

    @property
    def coefficients(self) -> PeakCoefficients:
        return PeakCoefficients(0.0, 0.0, 0.0)


def dwell(duration: float, *, start: float = 0.0) -> Dwell:
    """A `Dwell` of the given ``duration`` [s] starting at ``start`` [s]."""
    return Dwell(0.0, duration, start=start)
