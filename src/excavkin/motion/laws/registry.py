"""The laws by name: `LAW_NAMES` and [`get_law`][excavkin.motion.laws.registry.get_law], what files
and the command line use."""

from __future__ import annotations

from dataclasses import fields

from excavkin.motion.laws.base import MotionLaw
from excavkin.motion.laws.limited import SCurveLaw, TrapezoidalLaw
from excavkin.motion.laws.modified import ModifiedSineLaw, ModifiedTrapezoidLaw
from excavkin.motion.laws.polynomial import CubicLaw, Poly345Law, Poly4567Law
from excavkin.motion.laws.trigonometric import CycloidalLaw, HarmonicLaw

_LAWS: dict[str, type[MotionLaw]] = {
    "cubic": CubicLaw,
    "345": Poly345Law,
    "4567": Poly4567Law,
    "cycloidal": CycloidalLaw,
    "harmonic": HarmonicLaw,
    "modified-trapezoid": ModifiedTrapezoidLaw,
    "modified-sine": ModifiedSineLaw,
    "trapezoidal": TrapezoidalLaw,
    "s-curve": SCurveLaw,
}

LAW_NAMES: tuple[str, ...] = tuple(_LAWS)
"""Names accepted by [`get_law`][excavkin.motion.laws.registry.get_law]."""


def _shape_params(cls: type[MotionLaw]) -> set[str]:
    return {f.name for f in fields(cls)} - {"stroke", "duration"}


def get_law(name: str, stroke: float, duration: float | None, **params: float) -> MotionLaw:
    """Build a motion law by name.

    Parameters
    ----------
    name : str
        One of `LAW_NAMES`: ``"cubic"``, ``"345"``, ``"4567"``, ``"cycloidal"``,
        ``"harmonic"``, ``"modified-trapezoid"``, ``"modified-sine"``, ``"trapezoidal"``,
        ``"s-curve"``.
    stroke : float
        Signed stroke ``H`` [m or rad].
    duration : float or None
        Duration ``T`` [s]. Must be ``None`` for ``"s-curve"`` built from limits (``T`` is
        then an output) and a number otherwise.
    **params : float
        ``start`` for every law; ``accel_fraction`` or ``v_max`` for ``"trapezoidal"``;
        ``accel_fraction`` and ``jerk_fraction``, or ``v_max``, ``a_max`` and ``j_max``
        (all three) for ``"s-curve"``.

    Returns
    -------
    MotionLaw

    Raises
    ------
    ValueError
        Unknown ``name`` (the message lists the known names), a missing or superfluous
        ``duration``, or invalid values.
    TypeError
        Unknown or conflicting parameters.

    Examples
    --------
    >>> get_law("cycloidal", 0.8, 2.0, start=1.0).peak_velocity
    0.8
    """
    try:
        cls = _LAWS[name]
    except KeyError:
        raise ValueError(
            f"unknown motion law {name!r}; known laws: {', '.join(LAW_NAMES)}"
        ) from None
    allowed = _shape_params(cls)
    alt: set[str] = set()
    if cls is TrapezoidalLaw:
        alt = {"v_max"}
    elif cls is SCurveLaw:
        alt = {"v_max", "a_max", "j_max"}
    unknown = set(params) - allowed - alt
    if unknown:
        raise TypeError(
            f"motion law {name!r} got unknown parameter(s) {sorted(unknown)}; "
            f"allowed: {sorted(allowed | alt)}"
        )
    start = float(params.get("start", 0.0))
    used_alt = set(params) & alt
    if used_alt and set(params) & (allowed - {"start"}):
        raise TypeError(
            f"motion law {name!r}: give either {sorted(allowed - {'start'})} or "
            f"{sorted(alt)}, not both"
        )
    if cls is SCurveLaw and used_alt:
        if used_alt != alt:
            raise TypeError(
                f"motion law 's-curve' needs all of {sorted(alt)}, got {sorted(used_alt)}"
            )
        if duration is not None:
            raise ValueError(
                "motion law 's-curve' with limits v_max, a_max, j_max: the duration is an "
                "output, pass duration=None"
            )
        return SCurveLaw.from_limits(
            stroke, params["v_max"], params["a_max"], params["j_max"], start=start
        )
    if duration is None:
        raise ValueError(f"motion law {name!r} needs a duration")
    if cls is TrapezoidalLaw and used_alt:
        return TrapezoidalLaw.from_max_velocity(stroke, duration, params["v_max"], start=start)
    return cls(stroke, duration, **params)
