r"""A family of machine designs in one batch: the machine's parameters, and its tool forces
with each design's own geometry, cylinders and pressures.

The parameters of a machine are its mechanism's
([`Mechanism.parameters`][excavkin.mechanism.Mechanism.parameters]: every point's
``P.x``, ``P.y``, the bodies' masses, …) and, named after the machine file's tables,

=================================  ============================================
``cylinders.ROLE.bore``            piston diameter (m), ROLE boom, arm, bucket
``cylinders.ROLE.rod``             rod diameter (m)
``cylinders.ROLE.retracted``       pin-to-pin length fully retracted (m)
``cylinders.ROLE.stroke``          stroke (m)
``circuits.NAME.working``          working (main relief) pressure (Pa)
``circuits.NAME.relief``           port relief pressure (Pa)
=================================  ============================================

[`design_tool_forces`][excavkin.excavator.designs.design_tool_forces] is
[`tool_forces`][excavkin.excavator.forces.tool_forces] for one design
per sample: the transfer functions come from the general engine's solve with ``params=`` (one
solve per cylinder with unit rate), the cylinder areas and pressures are arrays, and the
gravity terms use each design's mass properties. What a moved pin carries with it follows the
engine's convention for designs (`excavkin.structure.design`): a body's centre of mass
stays at its sketch coordinates (``BODY.center_of_mass.x``/``.y``, parameters themselves) and
its other points stay where the sketch puts them, so moving the H-link pin of the bucket moves
neither the tooth tip nor the bucket's centre of mass; half of each cylinder's mass sits at
each of its end pins and moves with them. The cylinders' masses and counts are not parameters.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from excavkin.arrays import BoolArray as B
from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.excavator.forces import At, Working
from excavkin.excavator.machine import ROLES, Machine, as_lengths, direction_angle, wrap_angle
from excavkin.kinematics import KinematicResult
from excavkin.machinery.capped_force import capped_force
from excavkin.machinery.designs import (
    CIRCUIT_KEYS,
    CYLINDER_KEYS,
    cylinder_parameters,
    design_cylinders,
)


def machine_parameters(machine: Machine) -> dict[str, float]:
    """Every parameter of the machine and its nominal value (SI): the mechanism's, then
    ``cylinders.ROLE.KEY`` and ``circuits.NAME.KEY``.

    Parameters
    ----------
    machine : Machine
        The excavator.

    Returns
    -------
    dict of str to float
        The mechanism's parameters (points, lengths, loads, masses); each cylinder's
        ``bore``, ``rod``, ``retracted`` and ``stroke`` (m); each circuit's ``working`` and
        ``relief`` pressure (Pa).
    """
    out = dict(machine.mechanism.parameters)
    out.update(cylinder_parameters(machine.cylinders, machine.circuits))
    return out


def machine_parameter_kind(name: str, machine: Machine) -> str:
    """The physical kind of a machine parameter (for units at the edges)."""
    from excavkin.structure.design import parameter_kind

    head = name.rpartition(".")[0]
    if head.startswith("cylinders."):
        return "length"
    if head.startswith("circuits."):
        return "pressure"
    return parameter_kind(name, machine.mechanism.model)


def check_parameters(machine: Machine, names: Any) -> None:
    """Refuse a name that is not a parameter of the machine, with the closest known names."""
    from excavkin.errors import unknown_name

    known = machine_parameters(machine)
    for name in names:
        if name not in known:
            raise unknown_name("parameter", name, list(known))


@dataclass(frozen=True, slots=True)
class DesignTransfer:
    """Positions and transfer functions ∂(point)/∂L of n samples, each its own design.

    Attributes
    ----------
    positions : ndarray, shape (n, n_points, 2)
    d : ndarray, shape (n, n_points, 2, 3)
    result : KinematicResult
        The solve with unit boom rate (its parameters are the designs').
    """

    positions: F
    d: F
    result: KinematicResult

    def point(self, machine: Machine, name: str) -> tuple[F, F]:
        """Position (n, 2) and Jacobian (n, 2, 3) of a point."""
        i = machine.mechanism.plan.points.index(name)
        return self.positions[:, i], self.d[:, i]


def design_transfer(
    machine: Machine, lengths: ArrayLike, params: Mapping[str, ArrayLike] | None = None
) -> DesignTransfer:
    """The engine's exact transfer functions at ``lengths`` (shape (n, 3)), sample i solved
    with the mechanism parameters ``params[name][i]`` (scalars or arrays broadcasting to (n,);
    machine-only parameters are ignored here)."""
    L = as_lengths(lengths)
    n = len(L)
    mech = machine.mechanism
    geometry = {
        k: np.broadcast_to(np.asarray(v, dtype=np.float64), (n,))
        for k, v in (params or {}).items()
        if k in mech.parameters
    }
    values = {d: L[:, i] for i, d in enumerate(machine.drivers)}
    cols = []
    first: KinematicResult | None = None
    for c in range(3):
        rates = {d: np.full(n, 1.0 if i == c else 0.0) for i, d in enumerate(machine.drivers)}
        res = mech.solve(values, rates, params=geometry or None)
        first = first or res
        cols.append(res.velocities)
    assert first is not None
    return DesignTransfer(first.positions, np.stack(cols, axis=-1), first)


def design_gravity_terms(machine: Machine, tr: DesignTransfer) -> F:
    """G_c = g·Σ m_k ∂y_k/∂L_c per sample, shape (n, 3): the bodies' masses at each design's
    centres of mass, and half of each cylinder's mass at each of its end pins."""
    from excavkin.kinetostatics.inertia import MassProperties

    props = MassProperties.of(tr.result)
    n = len(tr.positions)
    mass = np.broadcast_to(props.mass.reshape(len(props.mass), -1), (len(props.mass), n))
    com = np.broadcast_to(props.com.reshape(len(props.com), 2, -1), (len(props.com), 2, n))
    dy = np.zeros((n, 3))
    for j, (p0, p1) in enumerate(props.base):
        if not np.any(mass[j] > 0.0):
            continue
        d0, d1 = tr.d[:, int(p0)], tr.d[:, int(p1)]  # (n, 2, 3)
        s, t = com[j, 0][:, None], com[j, 1][:, None]
        # y of S = p0 + s·(p1 − p0) + t·perp(p1 − p0), perp(w) = (−w_y, w_x)
        dys = d0[:, 1] + s * (d1[:, 1] - d0[:, 1]) + t * (d1[:, 0] - d0[:, 0])
        dy += mass[j][:, None] * dys
    points = machine.mechanism.plan.points
    for cyl, ends in zip(machine.cylinders, machine.pins.cyl_ends, strict=True):
        for pin in ends:
            dy += 0.5 * cyl.mass * tr.d[:, points.index(pin), 1]
    return np.asarray(machine.gravity * dy)


def _value(params: Mapping[str, ArrayLike], name: str, nominal: float, n: int) -> F:
    v = np.asarray(params.get(name, nominal), dtype=np.float64)
    return np.broadcast_to(v, (n,))


def cylinder_arrays(
    machine: Machine, params: Mapping[str, ArrayLike], n: int
) -> dict[str, dict[str, F]]:
    """Per role, each cylinder's bore, rod, retracted, stroke (m), its ``bore_area`` and
    ``annulus_area`` (all ``count`` cylinders, m²) and its circuit's ``working`` and ``relief``
    pressures (Pa), as arrays of shape (n,)."""
    out: dict[str, dict[str, F]] = {}
    for c in machine.cylinders:
        v = {k: _value(params, f"cylinders.{c.role}.{k}", getattr(c, k), n) for k in CYLINDER_KEYS}
        circ = machine.circuits[c.circuit]
        for k in CIRCUIT_KEYS:
            v[k] = _value(params, f"circuits.{c.circuit}.{k}", getattr(circ, k), n)
        v["bore_area"] = c.count * np.pi / 4.0 * v["bore"] ** 2
        v["annulus_area"] = c.count * np.pi / 4.0 * (v["bore"] ** 2 - v["rod"] ** 2)
        out[c.role] = v
    return out


def check_designs(machine: Machine, params: Mapping[str, ArrayLike], n: int) -> B:
    """Whether each sample's cylinders and circuits are possible (positive sizes, rod within
    the bore, 0 < working ≤ relief), shape (n,)."""
    ok = np.ones(n, dtype=bool)
    for v in cylinder_arrays(machine, params, n).values():
        ok &= (v["bore"] > 0.0) & (v["rod"] >= 0.0) & (v["rod"] < v["bore"])
        ok &= (v["retracted"] > 0.0) & (v["stroke"] > 0.0)
        ok &= (v["working"] > 0.0) & (v["working"] <= v["relief"])
    return ok


def within_strokes(machine: Machine, lengths: F, params: Mapping[str, ArrayLike]) -> B:
    """Whether each row of ``lengths`` (shape (n, 3)) lies within its design's three strokes
    (to 1e-9 m), shape (n,)."""
    cyl = cylinder_arrays(machine, params, len(lengths))
    lo = np.stack([cyl[r]["retracted"] for r in ROLES], axis=-1)
    hi = lo + np.stack([cyl[r]["stroke"] for r in ROLES], axis=-1)
    return np.asarray(np.all((lo - 1e-9 <= lengths) & (hi + 1e-9 >= lengths), axis=-1))


@dataclass(frozen=True, slots=True)
class DesignForces:
    """Tool forces of one working cylinder, each sample its own design.

    Attributes
    ----------
    force, uncapped : ndarray, shape (n,)
        As `ToolForces` (N).
    limiting : ndarray of str, shape (n,)
    cylinder_force : ndarray, shape (n, 3)
    within_stroke : ndarray of bool, shape (n,)
        The lengths lie within each sample's own strokes.
    """

    force: F
    uncapped: F
    limiting: NDArray[np.str_]
    cylinder_force: F
    within_stroke: B


def design_tool_forces(
    machine: Machine,
    lengths: ArrayLike,
    params: Mapping[str, ArrayLike] | None = None,
    working: Working = "bucket",
    *,
    at: At = "lip",
    gravity: bool = True,
    transfer: DesignTransfer | None = None,
) -> DesignForces:
    """ISO 6015 (``at="lip"``) or SAE J1179 (``at="tip"``) tool force of the arm or bucket
    cylinder at cylinder ``lengths`` (shape (n, 3)), sample i being the design
    ``params[name][i]`` (names of
    [`machine_parameters`][excavkin.excavator.designs.machine_parameters]; scalars or arrays
    broadcasting to
    (n,); the others nominal). ``transfer``, if given, is `design_transfer` of the same
    lengths and parameters (to share it between forces).

    Parameters
    ----------
    machine : Machine
        The nominal excavator.
    lengths : array_like, shape (n, 3)
        Boom, arm and bucket cylinder lengths (m).
    params : mapping of str to array_like, optional
        Parameter name → SI value, a scalar or shape (n,); unnamed parameters are nominal.
    working : {"arm", "bucket"}, default "bucket"
        The working cylinder, at its circuit's working pressure; the others hold at their
        relief pressure.
    at : {"lip", "tip"}, default "lip"
        The bucket lip (ISO 6015) or the tooth tip (SAE J1179).
    gravity : bool, default True
        Include the weight of each design's front.
    transfer : DesignTransfer, optional
        The transfer functions of these lengths and designs, when already computed.

    Returns
    -------
    DesignForces
        The capped and uncapped tool forces (N), what limits each, the cylinder forces and
        whether each sample lies within its design's strokes.

    Raises
    ------
    InputError
        A bad ``working`` or ``at``, an unknown parameter, or lengths not of shape (n, 3).
    """
    if working not in ("arm", "bucket"):
        raise InputError(f"working must be 'arm' or 'bucket', not {working!r}")
    if at not in ("lip", "tip"):
        raise InputError(f"at must be 'lip' or 'tip', not {at!r}")
    given = dict(params or {})
    check_parameters(machine, given)
    L = as_lengths(lengths)
    n = len(L)
    tr = transfer if transfer is not None else design_transfer(machine, L, given)
    _, J = tr.point(machine, machine.front.lip if at == "lip" else machine.front.tip)
    G = design_gravity_terms(machine, tr) if gravity else np.zeros((n, 3))
    cyl = cylinder_arrays(machine, given, n)
    w = ROLES.index(working)
    limits = []
    for h, c in enumerate(machine.cylinders):
        v = cyl[c.role]
        p = v["working"] if h == w else v["relief"]
        limits.append((-p * v["annulus_area"], p * v["bore_area"]))
    dig = 1.0 if machine.cylinders[w].dig == "extend" else -1.0
    force, uncapped, limiting, cyl_force, _ = capped_force(J, G, w, dig, limits, ROLES)
    within = within_strokes(machine, L, given)
    return DesignForces(force, uncapped, limiting, cyl_force, within)


def bucket_angle_to_stick(machine: Machine, tr: DesignTransfer) -> F:
    """The bucket's angle relative to the stick (rad): the direction of bucket pin → tooth
    tip less that of stick pivot → bucket pin, wrapped into [−π, π). With the boom and the
    stick as they are, it alone places the tip, so the working ranges depend on the bucket
    linkage only through its values at the two ends of the bucket cylinder's stroke."""
    tip, _ = tr.point(machine, machine.front.tip)
    q, _ = tr.point(machine, machine.pins.bucket_pin)
    f, _ = tr.point(machine, machine.pins.stick_pivot)
    return np.asarray(wrap_angle(direction_angle(tip - q) - direction_angle(q - f)))


def design_machine(machine: Machine, params: Mapping[str, float]) -> Machine:
    """One design as a machine of its own: the model rebuilt with the points, bodies' masses
    and centres of mass, cylinders and circuits of ``params`` (names of
    [`machine_parameters`][excavkin.excavator.designs.machine_parameters]; others nominal). For
    checking a design with the machine's own
    functions (working ranges, rated forces).

    Parameters
    ----------
    machine : Machine
        The nominal excavator.
    params : mapping of str to float
        Parameter name → SI value: point coordinates, bodies' masses, inertias and centres of
        mass, cylinders' and circuits' values.

    Returns
    -------
    Machine
        The design, with the nominal machine's tool points, base, hydraulics and name.

    Raises
    ------
    InputError
        An unknown parameter, or one of another kind (a design variable, a fixed length, a
        load).
    ModelError
        A design that does not assemble, or whose cylinders or circuits are impossible.
    """
    import dataclasses

    from excavkin.mechanism import Mechanism

    check_parameters(machine, params)
    model = machine.mechanism.model
    points = dict(model.points)
    bodies = {b.name: b for b in model.bodies}
    for name, value in params.items():
        head, _, key = name.rpartition(".")
        if head in points and key in ("x", "y"):
            x, y = points[head]
            points[head] = (float(value), y) if key == "x" else (x, float(value))
        elif head in bodies and key == "mass":
            bodies[head] = dataclasses.replace(bodies[head], mass=float(value))
        elif head in bodies and key == "inertia":
            bodies[head] = dataclasses.replace(bodies[head], inertia=float(value))
        elif head.endswith(".center_of_mass") and head[: -len(".center_of_mass")] in bodies:
            b = bodies[head[: -len(".center_of_mass")]]
            cx, cy = b.center_of_mass or (0.0, 0.0)
            com = (float(value), cy) if key == "x" else (cx, float(value))
            bodies[b.name] = dataclasses.replace(b, center_of_mass=com)
        elif not head.startswith(("cylinders.", "circuits.")):
            raise InputError(f"parameter {name!r}: a single design is built from points, "
                             "masses, cylinders and circuits only")  # fmt: skip
    rebuilt = dataclasses.replace(
        model, points=points, bodies=tuple(bodies[b.name] for b in model.bodies)
    )

    cylinders, circuits = design_cylinders(machine.cylinders, machine.circuits, params)
    return Machine(
        Mechanism(rebuilt), machine.front, cylinders, circuits,
        ground_line=machine.ground_line, swing_axis=machine.swing_axis,
        level_bottom=machine.level_bottom, gravity=machine.gravity, base=machine.base,
        lift_point=machine.lift_point, hydraulics=machine.hydraulics, name=machine.name,
        source=machine.source,
    )  # fmt: skip
