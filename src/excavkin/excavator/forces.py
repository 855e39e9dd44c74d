r"""Tool forces of an excavator front (ISO 6015, SAE J1179) by virtual work on the engine.

The tool force of the **working** cylinder (arm: ISO 6015 arm-cylinder tool force; bucket:
bucket-cylinder tool force) acts along the direction the tool point moves when that cylinder
digs, at its circuit's working pressure; each **holding** cylinder's port relief caps it, and
the cylinder that caps it is named as the limit (ISO 6015 "hydraulic limit"). The virtual-work
derivation, shared by every machine family, is written in
[`excavkin.machinery.capped_force`][]; here J is ∂(tool point)/∂L from the engine's transfer
functions and G_c = g·Σ_b m_b·∂y_Sb/∂L_c the gravity terms over the front's mass points. The
tipping and slipping limits of the base machine cap these forces in
`excavkin.excavator.stability`. With ``gravity=False`` every G term is zero (the front
weightless); the masses are the model's bodies and the cylinders' (``Cylinder.mass``, half at
each end pin).

The ISO 6015 tool point is the bucket lip (cutting edge); SAE J1179 uses the tooth tip.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.excavator.machine import (
    ROLES,
    FrontPose,
    Machine,
    as_lengths,
    pose_of,
    transfer,
)
from excavkin.kinematics.summary import batch_repr
from excavkin.machinery.capped_force import capped_force, loaded_pressure, pressure_limits
from excavkin.machinery.capped_force import gravity_terms as gravity_terms
from excavkin.machinery.search import Evaluate, Progress, maximize_strokes, part

Working = Literal["arm", "bucket"]
At = Literal["lip", "tip"]
#: further limits of a tool force (the base machine's): ``limits(tf)`` → a list of
#: (name per sample, cap per sample (N)), both shape (n,)
Limits = Callable[["ToolForces"], Sequence[tuple[NDArray[np.str_], NDArray[np.float64]]]]


@dataclass(frozen=True, slots=True)
class ToolForces:
    """Tool forces of one working cylinder at n poses.

    Attributes
    ----------
    working : {"arm", "bucket"}
    at : {"lip", "tip"}
    gravity : bool
    force : ndarray, shape (n,)
        Tool force (N), capped by the holding cylinders' reliefs; 0 where the front cannot
        even hold itself, NaN where the pose does not assemble.
    uncapped : ndarray, shape (n,)
        The working cylinder's own limit, before capping (N).
    direction : ndarray, shape (n, 2)
        Unit vector of the force the tool exerts on the soil (the tool point's motion).
    limiting : ndarray of str, shape (n,)
        ``"arm"``/``"bucket"`` where the working cylinder limits, else the holding cylinder
        whose relief limits (``"boom"``, …); ``""`` where not assembled.
    cylinder_force : ndarray, shape (n, 3)
        Boom, arm, bucket cylinder forces at that tool force (N, > 0 pushing).
    cylinder_pressure : ndarray, shape (n, 3)
        The pressure of the loaded side of each cylinder (Pa): bore side when pushing,
        rod side when pulling.
    pose : FrontPose
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    working: str
    at: str
    gravity: bool
    force: F
    uncapped: F
    direction: F
    limiting: NDArray[np.str_]
    cylinder_force: F
    cylinder_pressure: F
    pose: FrontPose


def tool_forces(
    machine: Machine,
    lengths: ArrayLike,
    working: Working = "bucket",
    *,
    at: At = "lip",
    gravity: bool = True,
) -> ToolForces:
    """Tool force of the arm or bucket cylinder at each pose, the others holding.

    Parameters
    ----------
    machine : Machine
    lengths : array_like, shape (n, 3)
        Boom, arm, bucket cylinder lengths (m).
    working : {"arm", "bucket"}
        ISO 6015 arm-cylinder or bucket-cylinder tool force.
    at : {"lip", "tip"}
        The bucket lip (ISO 6015) or the tooth tip (SAE J1179).
    gravity : bool
        Include the weight of the front (the model's masses); it helps or hinders.

    Returns
    -------
    ToolForces
    """
    if working not in ("arm", "bucket"):
        raise InputError(f"working must be 'arm' or 'bucket', not {working!r}")
    if at not in ("lip", "tip"):
        raise InputError(f"at must be 'lip' or 'tip', not {at!r}")
    L = as_lengths(lengths)
    tr = transfer(machine, L)
    point = machine.front.lip if at == "lip" else machine.front.tip
    _, J = tr.point(machine, point)  # (n, 2, 3)
    G = gravity_terms(machine, tr.d) if gravity else np.zeros((len(L), 3))
    w = ROLES.index(working)
    limits = pressure_limits(machine.cylinders, machine.circuits, w)
    sgn = 1.0 if machine.cylinders[w].dig == "extend" else -1.0
    force, F_work, limiting, cyl_force, u = capped_force(J, G, w, sgn, limits, ROLES)
    pressure = loaded_pressure(machine.cylinders, cyl_force)
    pose = pose_of(machine, L, tr.result)
    return ToolForces(working, at, gravity, force, F_work, u, limiting, cyl_force, pressure, pose)


@dataclass(frozen=True, slots=True)
class ForceMaximum:
    """The largest tool force over a sweep and where it occurs.

    Attributes
    ----------
    working, at : str
    gravity : bool
    force : float
        N.
    uncapped : float
        The working cylinder's own limit there (N).
    lengths : ndarray, shape (3,)
    point : ndarray, shape (2,)
        Position of the tool point (m).
    limiting : str
    """

    working: str
    at: str
    gravity: bool
    force: float
    uncapped: float
    lengths: F
    point: F
    limiting: str


def force_maximum(tf: ToolForces) -> ForceMaximum:
    """The sample of ``tf`` with the largest tool force."""
    f = np.where(np.isfinite(tf.force), tf.force, -np.inf)
    k = int(np.argmax(f))
    pt = tf.pose.lip if tf.at == "lip" else tf.pose.tip
    return ForceMaximum(
        tf.working,
        tf.at,
        tf.gravity,
        float(tf.force[k]),
        float(tf.uncapped[k]),
        tf.pose.lengths[k],
        pt[k],
        str(tf.limiting[k]),
    )


def handbook_forces(machine: Machine, lengths: ArrayLike, *, at: At = "lip") -> tuple[F, F]:
    """The handbook lever formulas, from pin positions (no gravity, no capping).

    ``F_arm = F_cyl·a/b`` — a: distance from the stick pivot to the arm cylinder's line,
    b: stick pivot to tool point. ``F_bucket = F_cyl·c·e/(d·r)`` — c: side-link pivot to the
    bucket cylinder's line, d: side-link pivot to the H-link's line, e: bucket pin to the
    H-link's line, r: bucket pin to tool point. ``F_cyl`` at working pressure on the bore.

    Parameters
    ----------
    machine : Machine
    lengths : array_like, shape (n, 3)
    at : {"lip", "tip"}

    Returns
    -------
    arm, bucket : ndarray, shape (n,)
        N.
    """
    L = as_lengths(lengths)
    res = machine.solve(L)
    p = machine.pins

    def pt(n: str) -> F:
        return res.point(n)[0]

    def dist_to_line(o: F, a: F, b: F) -> F:
        d = b - a
        return np.abs(d[:, 0] * (o[:, 1] - a[:, 1]) - d[:, 1] * (o[:, 0] - a[:, 0])) / np.hypot(
            d[:, 0], d[:, 1]
        )

    tool = pt(machine.front.lip if at == "lip" else machine.front.tip)
    (eb, er), (hb, hr) = p.cyl_ends[1], p.cyl_ends[2]
    f_arm = machine.cylinders[1].force_limits(machine.circuit("arm").working)[1]
    f_bkt = machine.cylinders[2].force_limits(machine.circuit("bucket").working)[1]
    a = dist_to_line(pt(p.stick_pivot), pt(eb), pt(er))
    b = np.hypot(*(tool - pt(p.stick_pivot)).T)
    c = dist_to_line(pt(p.link_pivot), pt(hb), pt(hr))
    d = dist_to_line(pt(p.link_pivot), pt(p.junction), pt(p.link_pin))
    e = dist_to_line(pt(p.bucket_pin), pt(p.junction), pt(p.link_pin))
    r = np.hypot(*(tool - pt(p.bucket_pin)).T)
    return f_arm * a / b, f_bkt * c * e / (d * r)


@dataclass(frozen=True, slots=True)
class RatedForce:
    """A rated tool force: the standards' positions, working pressure, no gravity.

    Attributes
    ----------
    working, at : str
    force : float
        The tool force (N), capped where a holding cylinder would exceed its relief.
    uncapped : float
        The working cylinder's own limit there (N): ``moment / radius``.
    moment : float
        The working cylinder's largest output moment (N·m) about its pivot (the stick pivot
        for the arm, the bucket pin for the bucket), at working pressure.
    radius : float
        From that pivot to the tool point (m).
    lengths : ndarray, shape (3,)
        Boom, arm, bucket cylinder lengths of the rated pose (m).
    point : ndarray, shape (2,)
        The tool point there (m).
    limiting : str
        The working cylinder, or the holding cylinders whose relief caps the force (joined by
        ``+`` where two reach it together).
    """

    working: str
    at: str
    force: float
    uncapped: float
    moment: float
    radius: float
    lengths: F
    point: F
    limiting: str


def rated_force(
    machine: Machine,
    working: Working = "bucket",
    *,
    at: At = "lip",
    limits: Limits | None = None,
    progress: Progress | None = None,
) -> RatedForce:
    """The rated arm- or bucket-cylinder tool force (ISO 6015 §5.2, SAE J1179 §3.3).

    The bucket is turned to where the bucket cylinder and its linkage give their largest
    output moment about the bucket pin; for the arm force the stick is turned to where the arm
    cylinder gives its largest moment about the stick pivot, the bucket held as for the bucket
    force. The working cylinder is at working pressure, the others may not exceed their relief
    pressure, and the weight of the front is left out. The standards do not place the boom (nor,
    for the bucket force, the stick): they are put where the capped force is largest, so a
    holding limit is reported only where no such position avoids it.

    Parameters
    ----------
    machine : Machine
    working : {"arm", "bucket"}
        The arm-cylinder or the bucket-cylinder force.
    at : {"lip", "tip"}
        The bucket lip (ISO 6015) or the tooth tip (SAE J1179).
    limits : callable, optional
        Further caps of the force beyond the cylinders' (the base machine's tipping and
        slipping, [`excavkin.excavator.stability.base_rated_force`][]): the free strokes are
        then put where the force capped by them too is largest, and a cap reached there is
        named.
    progress : callable, optional
        ``progress(done, total)`` as the searches go on.

    Returns
    -------
    RatedForce
    """
    if working not in ("arm", "bucket"):
        raise InputError(f"working must be 'arm' or 'bucket', not {working!r}")
    point = machine.front.lip if at == "lip" else machine.front.tip

    def objective(role: Working, capped: bool) -> Evaluate:
        def evaluate(L: F) -> tuple[F, F]:
            tf = tool_forces(machine, L.reshape(-1, 3), role, at=at, gravity=False)
            f = tf.force if capped else tf.uncapped
            if capped and limits is not None:
                for _, cap in limits(tf):
                    f = np.minimum(f, cap)
            o = np.where(np.isfinite(f) & tf.pose.ok & tf.pose.within_stroke, f, -np.inf)
            return o.reshape(L.shape[:2]), L

        return evaluate

    # the working cylinder's own force depends on its own stroke alone (and, for the arm, on
    # the bucket's through the radius), so its largest moment is a 1-D search
    n = 3 if working == "arm" else 2
    _, pose = maximize_strokes(
        objective("bucket", False), machine, (2,), coarse=65, progress=part(progress, 0, n)
    )
    pivot = machine.pins.bucket_pin
    if working == "arm":
        _, pose = maximize_strokes(
            objective("arm", False), machine, (1,), coarse=65, base=pose[0],
            progress=part(progress, 1, n),
        )  # fmt: skip
        pivot = machine.pins.stick_pivot
    free = (0,) if working == "arm" else (0, 1)
    _, pose = maximize_strokes(
        objective(working, True), machine, free, base=pose[0], progress=part(progress, n - 1, n)
    )
    tf = tool_forces(machine, pose, working, at=at, gravity=False)
    force = float(tf.force[0])
    extra = [(str(names[0]), float(cap[0])) for names, cap in limits(tf)] if limits else []
    for _, cap in extra:
        force = min(force, cap)
    # the search ends where caps cross: name every holding cylinder at its relief, and every
    # further cap reached
    named = [str(tf.limiting[0])] if tf.limiting[0] == working else []
    for h, cyl in enumerate(machine.cylinders):
        if ROLES[h] == working:
            continue
        lo, hi = cyl.force_limits(machine.circuits[cyl.circuit].relief)
        f_h = float(tf.cylinder_force[0, h])
        if np.isclose(f_h, hi, rtol=1e-6) or np.isclose(f_h, lo, rtol=1e-6):
            named.append(ROLES[h])
    if force < float(tf.force[0]) * (1.0 - 1e-6):  # a further cap binds: no cylinder does
        named = []
    named += [name for name, cap in extra if np.isclose(cap, force, rtol=1e-6)]
    res = tf.pose.result
    tool = res.point(point)[0][0]
    radius = float(np.hypot(*(tool - res.point(pivot)[0][0])))
    return RatedForce(
        working,
        at,
        force,
        float(tf.uncapped[0]),
        float(tf.uncapped[0]) * radius,
        radius,
        pose[0],
        tool,
        "+".join(named) or str(tf.limiting[0]),
    )


@dataclass(frozen=True, slots=True)
class DirectedForce:
    """The largest force the tool can exert along given directions, the cylinders capping it.

    Attributes
    ----------
    force : ndarray, shape (n,)
        N; 0 where the front cannot even hold itself, NaN where the pose does not assemble.
    limiting : ndarray of str, shape (n,)
        The cylinder whose limit binds (``"boom"``, ``"arm"``, ``"bucket"``).
    driving : ndarray of bool, shape (n, 3)
        Cylinders doing work against the load (capped at the working pressure; the others at
        their port relief).
    cylinder_force : ndarray, shape (n, 3)
        Boom, arm, bucket cylinder forces at that force (N, > 0 pushing).
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    force: F
    limiting: NDArray[np.str_]
    driving: NDArray[np.bool_]
    cylinder_force: F


def directed_force(
    machine: Machine,
    lengths: ArrayLike,
    direction: ArrayLike,
    rates: ArrayLike,
    *,
    at: At = "lip",
    gravity: bool = True,
) -> DirectedForce:
    """Largest force F the tool exerts along ``direction`` while the cylinders move at ``rates``.

    The soil's force on the tool is −F·e (e the unit direction), so cylinder c carries
    ``f_c = F·(e·J_c) + G_c`` (virtual work, as
    [`tool_forces`][excavkin.excavator.forces.tool_forces]). A cylinder moving so
    that it does work against the load (``(e·J_c)·rate_c > 0``) is limited by its circuit's
    working pressure; the others, held or pushed back, by their port relief. F is the least of
    those caps. With e along the working cylinder's own motion and only that cylinder moving,
    this is [`tool_forces`][excavkin.excavator.forces.tool_forces].

    Parameters
    ----------
    machine : Machine
    lengths : array_like, shape (n, 3)
        Boom, arm, bucket cylinder lengths (m).
    direction : array_like, shape (n, 2)
        The force the tool exerts on the soil (unit vectors, or any length > 0).
    rates : array_like, shape (n, 3)
        Cylinder length rates, or any vectors of the same directions (m/s or m).
    at : {"lip", "tip"}
        The bucket lip (ISO 6015) or the tooth tip (SAE J1179).
    gravity : bool
        Include the front's weight.

    Returns
    -------
    DirectedForce
    """
    if at not in ("lip", "tip"):
        raise InputError(f"at must be 'lip' or 'tip', not {at!r}")
    L = as_lengths(lengths)
    e = np.broadcast_to(np.asarray(direction, dtype=np.float64), (len(L), 2))
    with np.errstate(divide="ignore", invalid="ignore"):
        e = e / np.hypot(e[:, 0], e[:, 1])[:, None]
    R = np.broadcast_to(np.asarray(rates, dtype=np.float64), L.shape)
    tr = transfer(machine, L)
    _, J = tr.point(machine, machine.front.lip if at == "lip" else machine.front.tip)
    G = gravity_terms(machine, tr.d) if gravity else np.zeros((len(L), 3))
    a = np.einsum("ni,nic->nc", e, J)  # e·J_c
    driving = a * R > 0.0
    force = np.full(len(L), np.inf)
    limiting = np.full(len(L), "", dtype="<U8")
    for c, cyl in enumerate(machine.cylinders):
        circ = machine.circuits[cyl.circuit]
        lo, hi = cyl.force_limits(np.where(driving[:, c], circ.working, circ.relief))
        with np.errstate(divide="ignore", invalid="ignore"):
            cap = np.where(
                a[:, c] > 0.0,
                (hi - G[:, c]) / a[:, c],
                np.where(a[:, c] < 0.0, (lo - G[:, c]) / a[:, c], np.inf),
            )
        lower = cap < force
        force = np.where(lower, cap, force)
        limiting = np.where(lower, ROLES[c], limiting)
    force = np.where(np.isfinite(force), np.maximum(force, 0.0), np.nan)
    return DirectedForce(force, limiting, driving, force[:, None] * a + G)
