"""The mechanism description: immutable records in SI units, validated."""

from excavkin.model.entities import Body, LinearDriver, Model, RotaryDriver, Slider

__all__ = ["Body", "LinearDriver", "Model", "RotaryDriver", "Slider"]
