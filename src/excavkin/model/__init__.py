"""The mechanism description: immutable records in SI units, validated."""

from excavkin.model.entities import (
    Body,
    GearPair,
    LinearDriver,
    Model,
    RackPinion,
    RotaryDriver,
    Slider,
)

__all__ = ["Body", "GearPair", "LinearDriver", "Model", "RackPinion", "RotaryDriver", "Slider"]
