"""The mechanism description: immutable records in SI units, validated."""

from excavkin.model.entities import (
    Body,
    CamFollower,
    GearPair,
    LinearDriver,
    Model,
    RackPinion,
    RotaryDriver,
    Slider,
)

__all__ = [
    "Body",
    "CamFollower",
    "GearPair",
    "LinearDriver",
    "Model",
    "RackPinion",
    "RotaryDriver",
    "Slider",
]
