"""External loads: point forces, couples and gravity, evaluated over a batch of samples.

The records themselves live with the model (`excavkin.model.entities`, so that a
[`Model`][excavkin.model.entities.Model] can carry them) and are re-exported here::

    PointForce(name, body, point, value)      value: (Fx, Fy), shape (n, 2), or f(result)
    Torque(name, body, value, reaction=None)  value: scalar, shape (n,), or f(result)
    Gravity(g=9.80665, direction=(0, -1))     m·g·direction at every centre of mass

Signs, in global axes::

        y ^          F = (Fx, Fy) acts on `body` at `point`
          |   F        the couple τ is counter-clockwise positive;
          |  ↗         `reaction` (if any) receives −τ
          | P
          +------> x

A value that is a function is called once with the whole
[`KinematicResult`][excavkin.kinematics.result.KinematicResult]; it returns a constant or one row
per sample.
A digging resistance of 5 kN opposing the bucket tip's velocity::

    def resistance(res):
        _, v, _ = res.point("tip")                       # shape (n, 2)
        speed = np.hypot(v[:, 0], v[:, 1])[:, None]
        return -5e3 * v / np.where(speed > 0, speed, 1.0)

    PointForce("dig", "bucket", "tip", resistance)
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError, ModelError
from excavkin.kinematics.result import KinematicResult
from excavkin.model.entities import (
    STANDARD_GRAVITY,
    Gravity,
    Load,
    LoadValue,
    Model,
    PointForce,
    Torque,
)

__all__ = [
    "STANDARD_GRAVITY",
    "EvaluatedLoads",
    "Gravity",
    "Load",
    "LoadValue",
    "PointForce",
    "Torque",
    "check_loads",
    "evaluate_loads",
    "model_loads",
]


def model_loads(model: Model, *, gravity: bool | None = None) -> tuple[Load, ...]:
    """The loads a model declares: its ``[loads]`` and, if enabled, its gravity.

    Parameters
    ----------
    model : Model
    gravity : bool or None
        ``None``: as the model says. ``True``: the model's gravity, or standard gravity along
        −y if it declares none. ``False``: without gravity.

    Returns
    -------
    tuple of PointForce, Torque and Gravity
    """
    out: list[Load] = list(model.loads)
    if gravity is None:
        if model.gravity is not None:
            out.append(model.gravity)
    elif gravity:
        out.append(model.gravity if model.gravity is not None else Gravity())
    return tuple(out)


def check_loads(model: Model, loads: Iterable[object]) -> tuple[Load, ...]:
    """Check load records against the model's names and return them as a tuple.

    Raises
    ------
    ModelError
        A load names an unknown body or point, a point that is not on its body, a
        non-finite or zero gravity direction, or there is more than one
        [`Gravity`][excavkin.kinetostatics.loads.Gravity].
    InputError
        Something that is not a load record.
    """
    out: list[Load] = []
    bodies = {b.name: b for b in model.bodies}
    names: set[str] = set()
    n_grav = 0
    src = model.source
    for ld in loads:
        if isinstance(ld, Gravity):
            n_grav += 1
            dx, dy = ld.direction
            if not (np.isfinite(ld.g) and np.isfinite(dx) and np.isfinite(dy)) or dx == dy == 0:
                raise ModelError(
                    "gravity needs a finite g and a non-zero direction", table="gravity", source=src
                )
            if n_grav > 1:
                raise ModelError("gravity is given more than once", table="gravity", source=src)
            out.append(ld)
            continue
        if not isinstance(ld, PointForce | Torque):
            raise InputError(f"not a load record: {ld!r} (use PointForce, Torque or Gravity)")
        table = f"loads.{ld.name}"
        if ld.name in names:
            raise ModelError("duplicate load name", table="loads", entry=ld.name, source=src)
        names.add(ld.name)
        if ld.body not in bodies:
            raise ModelError(f"unknown body {ld.body!r}", table=table, entry="body", source=src)
        if isinstance(ld, PointForce):
            if ld.point not in bodies[ld.body].points:
                raise ModelError(
                    f"point {ld.point!r} is not a point of body {ld.body!r} (its points: "
                    f"{', '.join(bodies[ld.body].points)}); add it to the body to load it there",
                    table=table,
                    entry="point",
                    source=src,
                )
        elif ld.reaction is not None:
            if ld.reaction not in bodies:
                raise ModelError(
                    f"unknown body {ld.reaction!r}", table=table, entry="reaction", source=src
                )
            if ld.reaction == ld.body:
                raise ModelError(
                    "a couple's reaction must be on another body",
                    table=table,
                    entry="reaction",
                    source=src,
                )
        out.append(ld)
    return tuple(out)


@dataclass(frozen=True, slots=True)
class EvaluatedLoads:
    """Loads resolved to indices and evaluated over the samples.

    Each value is either a Python float (a constant: cheap to apply) or an array of shape (n,).

    Attributes
    ----------
    forces : tuple of (body, point, fx, fy)
        Body and point indices and the force components.
    torques : tuple of (body, reaction, tau)
        Body index, reaction body index (−1: none) and the couple.
    gravity : tuple of float or None
        ``(gx, gy)``, the gravitational acceleration vector in m/s², if on.
    """

    forces: tuple[tuple[int, int, float | F, float | F], ...]
    torques: tuple[tuple[int, int, float | F], ...]
    gravity: tuple[float, float] | None


def _value(ld: PointForce | Torque, result: KinematicResult) -> object:
    v = ld.value
    if callable(v):
        try:
            return v(result)
        except Exception as exc:  # the user's function: say whose it was
            raise InputError(
                f"load {ld.name!r}: its value function raised {type(exc).__name__}: {exc}"
            ) from exc
    return v


def _scalar_or_column(a: F, n: int, what: str) -> float | F:
    if a.ndim == 0:
        return float(a)
    if a.shape == (n,):
        return np.ascontiguousarray(a)
    raise InputError(f"{what}: expected a scalar or shape ({n},), got shape {a.shape}")


def evaluate_loads(model: Model, loads: Sequence[Load], result: KinematicResult) -> EvaluatedLoads:
    """Evaluate ``loads`` (already checked) for the samples of ``result``.

    Parameters
    ----------
    model : Model
    loads : sequence of PointForce, Torque, Gravity
    result : KinematicResult
        n samples.

    Returns
    -------
    EvaluatedLoads

    Raises
    ------
    InputError
        A value of the wrong shape, or not finite where the kinematics is.
    """
    n = len(result)
    bidx = {b.name: i for i, b in enumerate(model.bodies)}
    pidx = {p: i for i, p in enumerate(model.points)}
    forces: list[tuple[int, int, float | F, float | F]] = []
    torques: list[tuple[int, int, float | F]] = []
    gravity: tuple[float, float] | None = None
    for ld in loads:
        if isinstance(ld, Gravity):
            dx, dy = ld.direction
            r = float(np.hypot(dx, dy))
            gravity = (ld.g * dx / r, ld.g * dy / r)
        elif isinstance(ld, PointForce):
            try:
                a = np.asarray(_value(ld, result), dtype=np.float64)
            except (TypeError, ValueError) as exc:
                raise InputError(f"load {ld.name!r}: the value is not numeric ({exc})") from None
            if a.shape == (2,):
                fx: float | F = float(a[0])
                fy: float | F = float(a[1])
            elif a.shape == (n, 2):
                fx, fy = np.ascontiguousarray(a[:, 0]), np.ascontiguousarray(a[:, 1])
            else:
                raise InputError(
                    f"load {ld.name!r}: a force is (Fx, Fy) or shape ({n}, 2), got shape {a.shape}"
                )
            forces.append((bidx[ld.body], pidx[ld.point], fx, fy))
        else:
            try:
                a = np.asarray(_value(ld, result), dtype=np.float64)
            except (TypeError, ValueError) as exc:
                raise InputError(f"load {ld.name!r}: the value is not numeric ({exc})") from None
            tau = _scalar_or_column(a, n, f"load {ld.name!r}")
            torques.append((bidx[ld.body], -1 if ld.reaction is None else bidx[ld.reaction], tau))
    return EvaluatedLoads(tuple(forces), tuple(torques), gravity)
