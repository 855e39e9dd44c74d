r"""The radial part of each gear pair's tooth force, added to its pivots' pin forces.

The tooth force acts along the line of action, at the pressure angle φ to the common tangent
of the pitch circles: its tangential part ``W`` (an unknown of the equilibrium,
`excavkin.kinetostatics.equilibrium`) and its radial part ``|W|·tan φ``, which presses each gear
towards its own centre — the pinion's, in an internal pair, while the ring is pushed outwards::

               gear 1            P            gear 2
        O1 o--------------------->*<---------------------o O2      (external)
                       −R on gear 1   +R on gear 2,  R = σ·|W|·tan φ·u,  u = (O2 − O1)/|O2 − O1|

The radial part changes sign with nothing but the line of centres (whichever flank carries the
load, the teeth push the gears apart), so it is not linear in ``W``; but it does no work and
passes through both pivots, which the carrier holds: each gear's pin takes it and hands it to
the carrier, where the two cancel along the line of centres. So the linear equilibrium is solved
with the tangential part alone and the radial part is added afterwards, exactly, to the pin
forces at the two pivots: on gear g the pin pushes ``−R_g``, on the carrier ``+R_g``. No
other unknown changes (the pin equations, both gears' and the carrier's equilibrium still
hold), and the power balance is untouched.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.kinetostatics.equilibrium import StaticsSystem
from excavkin.model.cams import LiftLaw, lift_law, with_lifts
from excavkin.model.entities import Model

__all__ = [
    "CAM_COLUMNS",
    "RACK_COLUMNS",
    "RACK_KINDS",
    "mesh_forces",
    "add_radial",
    "pin_updates",
    "tooth_forces",
]

#: a rack's force columns: its tooth force (N, along the guide, on the rack), its guide's
#: normal force (N, along perp of the guide, on the rack, at the pitch point) and couple (N·m)
RACK_COLUMNS = ("tooth", "guide", "couple")
#: their kinds
RACK_KINDS = ("force", "force", "torque")
#: a cam's force columns: its contact force, its follower's guide force and couple
CAM_COLUMNS = ("contact", "guide", "couple")


def pin_updates(sy: StaticsSystem, x: Any, tooth: Sequence[Any]) -> list[tuple[int, Any]]:
    """What each gear pair's radial tooth force adds to the pin-force unknowns.

    Written in operations the dual numbers carry (`excavkin.kinematics.dual`), so that the
    forces' sensitivities take the same path.

    Parameters
    ----------
    sy : StaticsSystem
        The equilibrium system (its ``gears``, ``carriers`` and ``slots``).
    x : ndarray or Dual, shape (n_points, 2, n)
        Point positions.
    tooth : sequence of ndarray or Dual, shape (n,)
        Each gear pair's tangential tooth force ``W``, then each rack's.

    Returns
    -------
    list of (int, ndarray or Dual)
        (column of an unknown, the amount added to it): four per gear pivot; a rack's guide
        force and four at its pinion's pivot.
    """
    slot = {s: k for k, s in enumerate(sy.slots)}
    out: list[tuple[int, Any]] = []
    for k, (_, b1, b2, o1, o2, _, tan_phi, sense) in enumerate(sy.gears):
        ex, ey = x[o2, 0] - x[o1, 0], x[o2, 1] - x[o1, 1]
        mag = (sense * tan_phi) * abs(tooth[k]) / np.hypot(ex, ey)
        rx, ry = mag * ex, mag * ey  # on gear 2
        carrier = sy.carriers[k]
        for body, pivot, sign in ((b1, o1, -1.0), (b2, o2, 1.0)):
            gs, cs = slot[(pivot, body)], slot[(pivot, carrier)]
            fx, fy = sign * rx, sign * ry  # on the gear: its pin pushes back, the carrier's on
            out += [(2 * gs, -fx), (2 * gs + 1, -fy), (2 * cs, fx), (2 * cs + 1, fy)]
    col = sy.rack_col0
    for k, (_, _, pinion, carrier, o, l1, l2, side, _, tan_phi) in enumerate(sy.racks):
        # on the rack σ·|W|·tan φ·n̂ (away from the pinion), which its guide takes (N changes
        # by −σ|W| tan φ at the same point); on the pinion the opposite, which its pin takes
        radial = side * tan_phi * abs(tooth[len(sy.gears) + k])
        ex, ey = x[l2, 0] - x[l1, 0], x[l2, 1] - x[l1, 1]
        inv = 1.0 / np.hypot(ex, ey)
        rx, ry = -ey * inv * radial, ex * inv * radial  # on the rack
        gs, cs = slot[(o, pinion)], slot[(o, carrier)]
        out += [(col + 3 * k + 1, -radial)]
        out += [(2 * gs, rx), (2 * gs + 1, ry), (2 * cs, -rx), (2 * cs + 1, -ry)]
    return out


def add_radial(sy: StaticsSystem, x: F, out: F) -> None:
    """Add each gear pair's radial tooth force to the pin forces at its pivots, in place.

    Parameters
    ----------
    sy : StaticsSystem
        The equilibrium system.
    x : ndarray, shape (n_points, 2, n)
        Point positions.
    out : ndarray, shape (n_unknowns, n)
        The solved unknowns: the pin-force rows at the gears' pivots are updated.
    """
    for col, value in pin_updates(sy, x, tooth_forces(sy, list(out))):
        out[col] += value


def tooth_forces(sy: StaticsSystem, solution: Sequence[Any]) -> list[Any]:
    """Each gear pair's tangential tooth force, then each rack's, from the solved unknowns.

    Parameters
    ----------
    sy : StaticsSystem
        The equilibrium system.
    solution : sequence
        One entry per unknown.

    Returns
    -------
    list
        ``W`` of each gear pair, then of each rack.
    """
    g0, r0 = sy.gear_col0, sy.rack_col0
    return [
        *solution[g0 : g0 + len(sy.gears)],
        *(solution[r0 + 3 * k] for k in range(len(sy.racks))),
    ]


def mesh_forces(sy: StaticsSystem, out: F) -> tuple[F, F, F]:
    """The gear pairs', racks' and cams' forces of a `ForceResult`, from the solved unknowns.

    Parameters
    ----------
    sy : StaticsSystem
        The equilibrium system.
    out : ndarray, shape (n_unknowns, n)
        The solved unknowns.

    Returns
    -------
    gear_force : ndarray, shape (n, n_gears)
    rack_force : ndarray, shape (n, n_racks, 3)
    cam_force : ndarray, shape (n, n_cams, 3)
        (an oscillating follower's guide force and couple are 0: it has none)
    """
    n = out.shape[1]
    g0, r0, c0 = sy.gear_col0, sy.rack_col0, sy.cam_col0
    cams = np.zeros((n, len(sy.cams), 3))  # an oscillating follower has no guide: zeros
    for k, (cm, col) in enumerate(zip(sy.cams, sy.cam_cols, strict=True)):
        cams[:, k, : cm.unknowns] = out[col : col + cm.unknowns].T
    return (
        out[g0:r0].T,
        np.moveaxis(out[r0:c0].reshape(len(sy.racks), 3, n), -1, 0),
        cams,
    )


def pitch_fractions(model: Model, values: Mapping[str, Any]) -> dict[tuple[str, int], Any]:
    """Each gear pair's pitch fraction λ (`GearPair.pitch_fraction`), each rack's pitch
    radius and each rope's signed sheave radii with the values that ``values`` give
    (``GEAR.ratio``, ``RACK.radius``, ``ROPE.radius.S``: arrays of one value per design, or
    dual numbers).

    Parameters
    ----------
    model : Model
        The model.
    values : mapping
        Parameter name → value, design variables expanded.

    Returns
    -------
    dict
        ``("gear", k)`` → λ of gear pair k, ``("rack", k)`` → r of rack k, ``("rope", k)`` →
        the signed radii (0 at the ends) of the k-th rope over sheaves, ``("cam", k)`` → the
        lift law of cam k with its lifts (``CAM.lift.K``), for those given.
    """
    out: dict[tuple[str, int], Any] = {}
    for k, g in enumerate(model.gears):
        ratio = values.get(f"{g.name}.ratio")
        if ratio is not None:
            out["gear", k] = 1.0 / (1.0 - ratio if g.internal else 1.0 + ratio)
    for k, rk in enumerate(model.racks):
        radius = values.get(f"{rk.name}.radius")
        if radius is not None:
            out["rack", k] = radius
    sheaved = [r for r in model.ropes if r.over_sheaves]
    for k, rope in enumerate(sheaved):
        names = [f"{rope.name}.radius.{p}" for p in rope.path[1:-1]]
        if any(n in values for n in names):
            signed = (
                values.get(n, r) * (1.0 if w == "ccw" else -1.0)
                for n, r, w in zip(names, rope.radii, rope.wraps, strict=True)
            )
            out["rope", k] = (0.0, *signed, 0.0)
    for k, cm in enumerate(model.cams):
        if callable(cm.lift):
            continue
        names = [f"{cm.name}.lift.{i}" for i in range(len(cm.lift) - 1)]
        if any(n in values for n in names):
            lifts = tuple(values.get(n, row[1]) for n, row in zip(names, cm.lift, strict=False))
            law = lift_law(cm.lift)
            assert isinstance(law, LiftLaw)
            out["cam", k] = with_lifts(law, lifts)
    return out


def with_pitch(
    sy: StaticsSystem, given: Mapping[tuple[str, int], Any], part: slice
) -> StaticsSystem:
    """The system with the pitch fractions and radii ``given`` (`pitch_fractions`) of the
    samples ``part`` in its gear pairs', racks' and ropes' entries.

    Parameters
    ----------
    sy : StaticsSystem
        The model's equilibrium system.
    given : mapping
        ``("gear", k)`` → λ, ``("rack", k)`` → r, ``("rope", k)`` → signed radii,
        ``("cam", k)`` → a lift law, per sample.
    part : slice
        The samples.

    Returns
    -------
    StaticsSystem
        ``sy`` itself where ``given`` is empty.
    """
    if not given:
        return sy

    def cut(v: Any) -> Any:
        return v[part] if np.ndim(v) else v

    gears = tuple(
        (*e[:5], cut(given["gear", k]), *e[6:]) if ("gear", k) in given else e
        for k, e in enumerate(sy.gears)
    )
    racks = tuple(
        (*e[:8], cut(given["rack", k]), *e[9:]) if ("rack", k) in given else e
        for k, e in enumerate(sy.racks)
    )
    ropes = tuple(
        (e[0], e[1], tuple(cut(v) for v in given["rope", k])) if ("rope", k) in given else e
        for k, e in enumerate(sy.ropes)
    )
    cams = tuple(
        dataclasses.replace(e, law=given["cam", k].take(part)) if ("cam", k) in given else e
        for k, e in enumerate(sy.cams)
    )
    return dataclasses.replace(sy, gears=gears, racks=racks, ropes=ropes, cams=cams)  # type: ignore[arg-type]
