"""A distance a step uses, and the helpers every kind shares for per-sample constants.

A `Dist` is fixed (a body's distance, or a locked element's length) or an input's value (a
driven element). Its value may be one number or an array of one value per sample (a family of
designs); `vary_dist` recomputes it from a design's geometry, `take_dist` takes it at a subset
of samples.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from excavkin.step_kinds.base import Geometry

Num = Any  # a float, or an array of one value per design
Index = slice | NDArray[np.intp]


@dataclass(frozen=True, slots=True)
class Dist:
    """A distance used by a step: fixed (a body or a locked element) or an input's value
    (``scale·q``: the input itself for a cylinder; for a winch rope, its motor's angle times
    the blocks' distance per motor angle)."""

    kind: Literal["fixed", "input"]
    value: float
    input: int = -1
    label: str = ""
    #: where a fixed distance comes from, so that a design of other dimensions can recompute
    #: it: the two points (plan indices), and the body they are on ("" for a locked element)
    pair: tuple[int, int] = (-1, -1)
    body: str = ""
    #: an input's distance is ``scale·q`` (m per input unit; one value per design where a
    #: winch's drum radius or gear ratio varies)
    scale: Any = 1.0
    #: the winch rope whose motor's angle the input is ("" for a cylinder's length)
    winch: str = ""


def varies(value: Num) -> bool:
    """Whether a constant holds one value per sample.

    Parameters
    ----------
    value : float or ndarray
        The constant.

    Returns
    -------
    bool
        True for an array (of any number type) with at least one axis.
    """
    return bool(np.ndim(value))


def at(value: Num, index: Index) -> Num:
    """A per-sample constant taken at ``index`` (a single number is left as it is).

    Parameters
    ----------
    value : float or ndarray, shape (n,)
        The constant.
    index : slice or ndarray of int
        The samples taken.

    Returns
    -------
    float or ndarray
        ``value[index]``, or ``value`` when it is one number.
    """
    return value[index] if np.ndim(value) else value


def vary_dist(d: Dist, geo: Geometry, names: tuple[str, ...]) -> Dist:
    """A fixed distance recomputed from a design's geometry (an input's is left as it is).

    Parameters
    ----------
    d : Dist
        The plan's distance.
    geo : Geometry
        The designs' sketch, lengths and body frames.
    names : tuple of str
        The plan's point names.

    Returns
    -------
    Dist
        ``d`` with its value for the designs where it varies, else ``d`` itself.
    """
    if d.winch:  # a winch: its distance per motor angle, R/(i·n) of each design
        scale = geo.winch_ratio(d.winch)
        if not varies(scale):
            return d
        # (its value varies alongside, so that a step takes the designs' scales with it)
        return dataclasses.replace(d, scale=scale, value=d.value + 0.0 * scale)
    if d.kind != "fixed" or d.pair == (-1, -1):
        return d
    p, q = names[d.pair[0]], names[d.pair[1]]
    if d.body:
        value = geo.distance(d.body, p, q)
    else:  # a locked element: its [lengths] entry, or its sketch length
        given = geo.override(p, q)
        (px, py), (qx, qy) = geo.sketch[p], geo.sketch[q]
        value = given if given is not None else np.hypot(px - qx, py - qy)
    return dataclasses.replace(d, value=value) if varies(value) else d


def take_dist(d: Dist, index: Index) -> Dist:
    """A distance's per-sample value taken at ``index``.

    Parameters
    ----------
    d : Dist
        The distance.
    index : slice or ndarray of int
        The samples taken.

    Returns
    -------
    Dist
        ``d`` with ``value[index]``, or ``d`` itself when its value is one number.
    """
    if not np.ndim(d.value):
        return d
    return dataclasses.replace(d, value=at(d.value, index), scale=at(d.scale, index))


def compiled_value(d: Dist) -> Any:
    """What the compiled plan's constants table holds for a distance: its value when fixed,
    0.0 for an input's (read from the inputs instead).

    Parameters
    ----------
    d : Dist
        The distance.

    Returns
    -------
    float or ndarray
        The table's entry (a winch's: its distance per motor angle).
    """
    if d.winch:
        return d.scale
    return d.value if d.kind == "fixed" else 0.0


def describe_dist(d: Dist) -> str:
    """A distance as the plan's description writes it.

    Parameters
    ----------
    d : Dist
        The distance.

    Returns
    -------
    str
        ``"driver 'NAME'"`` or ``"LABEL VALUE m"``.
    """
    if d.kind == "input":
        return f"driver {d.label!r}"
    return f"{d.label} {d.value:.6g} m"


def dist_inputs(*dists: Dist) -> tuple[int, ...]:
    """The inputs among some distances (a driven element's length).

    Parameters
    ----------
    *dists : Dist
        The distances.

    Returns
    -------
    tuple of int
        The input index of each that is an input's value, in order.
    """
    return tuple(d.input for d in dists if d.kind == "input")
