"""Gear pairs and trains: each gear's pivot, and the angles a train's drivers set.

A gear pair keeps ``Δ(θ2 − θc) = e·Δ(θ1 − θc)`` (`GearPair.train_value`), a rotary driver
``Δθ_body − Δθ_reference = Δq``, and the ground does not turn. Together, over the bodies the
meshes and the drivers between them join (a *train*, the ground with them), these are linear
equations in the bodies' angle changes with constant coefficients, one per body: solved once,
each body's angle is ``θ = θ_sketch + Σ_i c_i (q_i − q_i,sketch)`` — the tabular method of
planetary trains, done by a linear solve. The angles follow the inputs themselves, not the
points' positions, so a gear that turns many times is followed exactly at every turn.

A train whose angles its drivers and meshes do not fix (a gear on an arm that a cylinder moves)
or fix twice is refused, naming its bodies.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.errors import MobilityError, ModelError
from excavkin.model.entities import GearPair, Model, RackPinion

__all__ = [
    "GearTrain",
    "describe_meshes",
    "gear_pivots",
    "gear_train",
    "pivot_on",
    "rack_side",
    "train_angles",
]


def describe_meshes(model: Model) -> list[str]:
    """One line per gear pair and rack, as ``check`` lists a model's parts.

    Parameters
    ----------
    model : Model
        A validated model.

    Returns
    -------
    list of str
        ``"  gears   : NAME external 1:3 — G1 (about O1) with G2 (about O2) on CARRIER, φ = 20°"``
        , ``"  rack    : NAME — RACK along L1→L2 on CARRIER by PINION (r = … m), φ = 20°"`` and
        ``"  cam     : NAME — CAM lifts FOLLOWER (roller) along L1→L2 on CARRIER, …"``.
    """
    out = []
    for g in model.gears:
        p1, p2 = gear_pivots(model, g)
        kind = "internal" if g.internal else "external"
        out.append(
            f"  gears   : {g.name} {kind} 1:{g.ratio:.6g} — {g.gears[0]} (about {p1}) with "
            f"{g.gears[1]} (about {p2}) on {g.carrier}, φ = {np.degrees(g.pressure_angle):.6g}°"
        )
    for rk in model.racks:
        out.append(
            f"  rack    : {rk.name} — {rk.rack} along {rk.along[0]}→{rk.along[1]} on "
            f"{rk.carrier} by {rk.pinion} (r = {rk.radius:.6g} m), "
            f"φ = {np.degrees(rk.pressure_angle):.6g}°"
        )
    for cm in model.cams:
        if callable(cm.lift):
            law = "by a function"
        else:
            lifts = [s for _, s in cm.lift]
            law = f"lift {min(lifts):.6g}…{max(lifts):.6g} m over {len(cm.lift) - 1} rows"
        if cm.along is not None:
            how = f"along {cm.along[0]}→{cm.along[1]}"
        else:
            how = f"about {pivot_on(model, cm.follower, cm.carrier, f'cams.{cm.name}', 'follower')}"
        out.append(
            f"  cam     : {cm.name} — {cm.cam} moves {cm.follower} ({cm.face}) {how} on "
            f"{cm.carrier}, {law}"
        )
    return out


def pivot_on(model: Model, body: str, carrier: str, table: str, entry: str) -> str:
    """The one point ``body`` shares with ``carrier``: its pivot.

    Parameters
    ----------
    model : Model
        The model.
    body, carrier : str
        Two bodies of it.
    table, entry : str
        Where a problem is reported.

    Returns
    -------
    str
        The shared point.

    Raises
    ------
    ModelError
        They share no point, or more than one.
    """
    shared = [p for p in model.body(body).points if p in model.body(carrier).points]
    if len(shared) != 1:
        raise ModelError(
            f"gear {body!r} shares {len(shared)} points with its carrier {carrier!r} "
            f"({', '.join(shared) or 'none'}); it needs exactly one, its pivot",
            table=table,
            entry=entry,
            source=model.source,
        )
    return shared[0]


def rack_side(model: Model, rack: RackPinion) -> float:
    """σ: +1 where the rack's first point lies to the left of the guide's direction through
    the pinion's pivot in the sketch, −1 to the right.

    Parameters
    ----------
    model : Model
        The model.
    rack : RackPinion
        The rack and pinion.

    Returns
    -------
    float
        ±1.

    Raises
    ------
    ModelError
        The rack's first point lies on that line (no side).
    """
    pts = model.points
    o = pts[pivot_on(model, rack.pinion, rack.carrier, f"racks.{rack.name}", "pinion")]
    (ax, ay), (bx, by) = pts[rack.along[0]], pts[rack.along[1]]
    first = model.body(rack.rack).points[0]
    px, py = pts[first]
    cross = (bx - ax) * (py - o[1]) - (by - ay) * (px - o[0])
    if cross == 0.0:
        raise ModelError(
            f"the rack's point {first} lies on the line through the pinion's pivot along the "
            "guide, so the sketch does not show on which side of the pinion the rack runs",
            table=f"racks.{rack.name}",
            entry="rack",
            source=model.source,
        )
    return 1.0 if cross > 0 else -1.0


def gear_pivots(model: Model, pair: GearPair) -> tuple[str, str]:
    """The pivot of each gear of a pair: the one point it shares with the carrier.

    Parameters
    ----------
    model : Model
        The model the pair belongs to (its bodies are known: see `validate`).
    pair : GearPair
        The gear pair.

    Returns
    -------
    (str, str)
        The pivots of ``pair.gears[0]`` and ``pair.gears[1]``.

    Raises
    ------
    ModelError
        A gear shares no point, or more than one, with the carrier.
    """
    table = f"gears.{pair.name}"
    return (
        pivot_on(model, pair.gears[0], pair.carrier, table, "gears"),
        pivot_on(model, pair.gears[1], pair.carrier, table, "gears"),
    )


@dataclass(frozen=True, slots=True)
class GearTrain:
    """The angles a model's gear trains set.

    Attributes
    ----------
    placed : dict
        Body name → ``((rotary driver index, coefficient), ...)``: each body whose angle its
        train sets and no rotary driver of its own does, with ``Δθ = Σ c·Δq``.
    meshes : dict
        Body name → the names of the gear pairs of its train (for messages).
    angles : dict
        Body name → ``((rotary driver index, coefficient), ...)`` of every body of a train,
        the ground (no terms) and the driven ones included.
    """

    placed: dict[str, tuple[tuple[int, float], ...]]
    meshes: dict[str, tuple[str, ...]]
    angles: dict[str, tuple[tuple[int, float], ...]]

    def travel(self, model: Model, rack: RackPinion) -> tuple[tuple[int, float], ...]:
        """A rack's travel along its guide: ``Δs = Σ c·Δq`` over the rotary drivers, with
        ``Δs = −σ·r·Δ(θp − θc)``.

        Parameters
        ----------
        model : Model
            The model.
        rack : RackPinion
            One of its racks.

        Returns
        -------
        tuple of (int, float)
            (rotary driver index, coefficient) pairs.
        """
        k = -rack_side(model, rack) * rack.radius
        pin = dict(self.angles[rack.pinion])
        car = dict(self.angles[rack.carrier])
        return tuple((ri, k * (pin.get(ri, 0.0) - car.get(ri, 0.0))) for ri in sorted(pin | car))

    def turn(self, body: str, carrier: str) -> tuple[tuple[int, float], ...]:
        """A body's turn relative to a carrier, ``Δ(θb − θc) = Σ c·Δq``.

        Parameters
        ----------
        body, carrier : str
            Two bodies of a train.

        Returns
        -------
        tuple of (int, float)
            (rotary driver index, coefficient) pairs.
        """
        b, c = dict(self.angles[body]), dict(self.angles[carrier])
        return tuple((ri, b.get(ri, 0.0) - c.get(ri, 0.0)) for ri in sorted(b | c))


def gear_train(model: Model) -> GearTrain:
    """Solve the angle relations of every gear train of ``model`` (see the module's text).

    Parameters
    ----------
    model : Model
        A model whose gear pairs name known bodies.

    Returns
    -------
    GearTrain
        Empty when the model has no gears.

    Raises
    ------
    MobilityError
        The drivers and meshes of a train do not fix its bodies' angles, or fix them twice.
    """
    if not (model.gears or model.racks or model.cams):
        return GearTrain({}, {}, {})
    ground = model.ground.name
    members = {ground}
    for g in model.gears:
        members.update((*g.gears, g.carrier))
    for rk in model.racks:
        members.update((rk.pinion, rk.carrier))
    for cm in model.cams:
        members.update((cm.cam, cm.carrier))
    drivers: list[int] = []
    grown = True
    while grown:
        grown = False
        for ri, d in enumerate(model.rotary):
            if ri not in drivers and (d.body in members or d.reference in members):
                drivers.append(ri)
                members.update((d.body, d.reference))
                grown = True
    order = [b.name for b in model.bodies if b.name in members and b.name != ground]
    col = {b: k for k, b in enumerate(order)}
    names = tuple(g.name for g in model.gears) + tuple(rk.name for rk in model.racks)
    names += tuple(cm.name for cm in model.cams)
    n_eq = len(drivers) + len(model.gears)
    if n_eq != len(order):
        what = "fewer" if n_eq < len(order) else "more"
        raise MobilityError(
            f"the gear train of {', '.join(names)} has {n_eq} driver and mesh relations for "
            f"the angles of {len(order)} bodies ({', '.join(order)}): {what} than its bodies "
            "(each body of a train turns by its rotary driver or by its gears; a gear on a "
            "body that something else moves is not supported)",
            table="gears",
            source=model.source,
        )
    a = np.zeros((n_eq, len(order)))
    b = np.zeros((n_eq, len(model.rotary)))

    def put(row: int, body: str, value: float) -> None:
        if body != ground:
            a[row, col[body]] += value

    for row, ri in enumerate(drivers):
        d = model.rotary[ri]
        put(row, d.body, 1.0)
        put(row, d.reference, -1.0)
        b[row, ri] = 1.0
    for k, g in enumerate(model.gears):
        row = len(drivers) + k
        e = g.train_value
        put(row, g.gears[1], 1.0)
        put(row, g.gears[0], -e)
        put(row, g.carrier, e - 1.0)
    sv = np.linalg.svd(a, compute_uv=False) if n_eq else np.ones(1)
    if sv.size and sv[-1] <= 1e-12 * max(sv[0], 1.0):
        raise MobilityError(
            f"the gear train of {', '.join(names)} does not fix the angles of its bodies "
            f"({', '.join(order)}): its driver and mesh relations are dependent (a redundant "
            "mesh, or a freedom without a driver)",
            table="gears",
            source=model.source,
        )
    c = np.linalg.solve(a, b) if n_eq else np.zeros((0, len(model.rotary)))
    driven = {model.rotary[ri].body for ri in drivers}
    placed = {
        body: tuple((ri, float(c[col[body], ri])) for ri in drivers)
        for body in order
        if body not in driven
    }
    meshes = {
        body: tuple(g.name for g in model.gears if body in (*g.gears, g.carrier)) for body in order
    }
    angles = {body: tuple((ri, float(c[col[body], ri])) for ri in drivers) for body in order}
    angles[ground] = ()
    return GearTrain(placed, meshes, angles)


def train_angles(model: Model, ratios: Mapping[str, Any]) -> dict[str, dict[int, Any]]:
    """Every train body's angle coefficients with the gear pairs' ratios ``ratios`` (floats,
    arrays of one value per design, or dual numbers): the linear system of `gear_train`
    solved by elimination in the arithmetic of the values given, its pivots chosen on the
    nominal ratios (so a family of designs and the derivatives follow one elimination).

    Parameters
    ----------
    model : Model
        A model with gears (its train builds: see `gear_train`).
    ratios : mapping
        Gear pair name → its ratio; a pair not named keeps its own.

    Returns
    -------
    dict
        Body name → {rotary driver index: coefficient}, ``Δθ = Σ c·Δq``, for every body of a
        train (the ground has none).
    """
    nominal = gear_train(model)
    ground = model.ground.name
    order = [b for b in nominal.angles if b != ground]
    col = {b: k for k, b in enumerate(order)}
    drivers = sorted({ri for terms in nominal.angles.values() for ri, _ in terms})
    n = len(order)
    a: list[list[Any]] = [[0.0] * n for _ in range(n)]
    a0 = np.zeros((n, n))
    b: list[list[Any]] = [[0.0] * len(drivers) for _ in range(n)]

    def put(row: int, body: str, value: Any, value0: float) -> None:
        if body != ground:
            a[row][col[body]] = a[row][col[body]] + value
            a0[row, col[body]] += value0

    for row, ri in enumerate(drivers):
        d = model.rotary[ri]
        put(row, d.body, 1.0, 1.0)
        put(row, d.reference, -1.0, -1.0)
        b[row][drivers.index(ri)] = 1.0
    for k, g in enumerate(model.gears):
        row = len(drivers) + k
        sign = 1.0 if g.internal else -1.0
        e = sign / ratios.get(g.name, g.ratio)
        e0 = g.train_value
        put(row, g.gears[1], 1.0, 1.0)
        put(row, g.gears[0], -e, -e0)
        put(row, g.carrier, e - 1.0, e0 - 1.0)
    # Gaussian elimination with the nominal system's partial pivoting
    for k in range(n):
        p = k + int(np.argmax(np.abs(a0[k:, k])))
        a[k], a[p] = a[p], a[k]
        b[k], b[p] = b[p], b[k]
        a0[[k, p]] = a0[[p, k]]
        for r in range(k + 1, n):
            if isinstance(a[r][k], float) and a[r][k] == 0.0:
                continue
            f = a[r][k] / a[k][k]
            f0 = a0[r, k] / a0[k, k]
            for j in range(k, n):
                a[r][j] = a[r][j] - f * a[k][j]
            a0[r, k:] -= f0 * a0[k, k:]
            b[r] = [br - f * bk for br, bk in zip(b[r], b[k], strict=True)]
    x: list[list[Any]] = [[0.0] * len(drivers) for _ in range(n)]
    for k in reversed(range(n)):
        rhs = list(b[k])
        for j in range(k + 1, n):
            rhs = [v - a[k][j] * xj for v, xj in zip(rhs, x[j], strict=True)]
        x[k] = [v / a[k][k] for v in rhs]
    out: dict[str, dict[int, Any]] = {
        body: {ri: x[col[body]][m] for m, ri in enumerate(drivers)} for body in order
    }
    out[ground] = {}
    return out
