r"""Hydraulic excavator working equipment: the machine, forward and inverse kinematics.

A [`Machine`][excavkin.excavator.machine.Machine] is a general
[`Mechanism`][excavkin.mechanism.Mechanism] (any model whose bodies
and pins form a backhoe front) plus what an excavator designer adds: which bodies are the boom,
stick, bucket and the bucket's two links, the three cylinders (stroke limits, bore, rod, count),
the pressures of their circuits, and the tooth-tip and lip points. Every position, velocity and
transfer function comes from the general engine
([`Mechanism.solve`][excavkin.mechanism.Mechanism.solve], vectorised over
samples); this module only arranges its inputs and reads its outputs.

Conventions (SI; side view, x forward, y up, angles CCW from +x)::

                      E ─────── arm cylinder ─────── G      (stick tail)
                 ____/ boom                         F|\      F: stick pivot (boom nose)
            D___/                                   |  H     H: bucket-cylinder base
     boom  /                                   stick|   \    bucket cylinder H→K
     cyl  /                                         N────K   N–K side link, K–L H-link
      C──A (boom foot)                              Q───L    Q: bucket pin
                                                     \_T     T: tooth tip, W: lip

* Cylinder lengths are pin-to-pin and come in the fixed order ``("boom", "arm", "bucket")``:
  arrays of them have shape ``(n, 3)``.
* The **bucket angle** β is the direction of the vector bucket pin Q → tip, CCW from +x;
  ``β = −π/2`` is a bucket hanging straight down.
* The **Jacobian** is ``J[i, r, c] = ∂(x_T, y_T, β)_r / ∂L_c`` at sample i; its condition
  number is taken with the β row multiplied by |QT| so that all entries are lengths over lengths.

>>> import excavkin
>>> from excavkin.excavator.machine import forward
>>> from excavkin.excavator.machine_file import load_machine
>>> m = load_machine(excavkin.example_path("excavator_machine"))
>>> pose = forward(m, m.lengths_min[None, :])
>>> bool(pose.ok[0])
True
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from excavkin.arrays import BoolArray as B
from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError, ModelError
from excavkin.kinematics import KinematicResult
from excavkin.kinematics.summary import batch_repr
from excavkin.machinery.base import BaseMachine
from excavkin.machinery.cylinder_machine import CylinderMachine
from excavkin.machinery.cylinders import Circuit, Cylinder, cylinder_lengths
from excavkin.machinery.masses import MassPoints, mass_points
from excavkin.mechanism import Mechanism
from excavkin.step_kinds import Dyad, of_kind

if TYPE_CHECKING:
    from excavkin.machinery.pumps import Hydraulics


#: The three cylinders of a backhoe front, in the order of every ``(n, 3)`` array.
ROLES: tuple[str, str, str] = ("boom", "arm", "bucket")

__all__ = [
    "mm_field",
    "BRANCHES",
    "ROLES",
    "Circuit",
    "Cylinder",
    "Front",
    "FrontJacobian",
    "FrontPose",
    "InverseSolution",
    "Machine",
    "MassPoints",
    "Pins",
    "Transfer",
    "as_lengths",
    "circle_point",
    "direction_angle",
    "forward",
    "inverse",
    "jacobian",
    "length_columns",
    "pose_of",
    "transfer",
    "transmission_angles",
    "wrap_angle",
]


@dataclass(frozen=True, slots=True)
class Front:
    """Names, in the general model, of the front's bodies and tool points.

    ``tip`` may be ``lip`` (a bucket without teeth). ``floor``, optional, is a point of the
    bucket's floor behind the lip: floor → lip gives a toothless bucket's cutting direction
    for the vertical-wall digging depth.
    """

    boom: str
    stick: str
    bucket: str
    side_link: str
    h_link: str
    tip: str
    lip: str
    floor: str | None = None


@dataclass(frozen=True, slots=True)
class Pins:
    """Point names of the pins, found from the model's topology (see
    [`Machine`][excavkin.excavator.machine.Machine])."""

    foot: str  # ground–boom
    stick_pivot: str  # boom–stick
    bucket_pin: str  # stick–bucket
    link_pivot: str  # stick–side link
    junction: str  # side link–H-link
    link_pin: str  # H-link–bucket
    cyl_ends: tuple[tuple[str, str], ...]  # per role: (base, rod end)


class Machine(CylinderMachine):
    """An excavator front: a general mechanism plus cylinders, circuits and tool points.

    Parameters
    ----------
    mechanism : Mechanism
        Whose bodies include the boom, stick, bucket, side link and H-link named in ``front``,
        pinned as a backhoe: ground–boom–stick–bucket in a chain, the side link on the stick,
        the H-link from the side link to the bucket; the boom cylinder between the ground and
        the boom, the arm cylinder between the boom and the stick, the bucket cylinder between
        the stick and the side link.
    front : Front
    cylinders : mapping of str to Cylinder
        Keys ``"boom"``, ``"arm"``, ``"bucket"``; each ``driver`` a driven linear driver.
    circuits : mapping of str to Circuit
    ground_line, swing_axis : float
        Height of the ground line and abscissa of the swing axis (m).
    level_bottom : float
        Length of the level-bottom cut for that working-range figure (m; 2.44 m = 8 ft).
    gravity : float
        g (m/s²), acting along −y on the bodies' masses.
    base : BaseMachine, optional
        Upper structure, counterweight, undercarriage and ground support, for tipping,
        slipping and lift capacity (`excavkin.excavator.stability`).
    lift_point : str, optional
        The load point of lift capacity (ISO 10567): a point of the stick, the bucket or a
        bucket link, such as a lifting hook; default the bucket pin.
    hydraulics : Hydraulics, optional
        Pump flows, swing and rod material, for speeds, cycle time and buckling
        (`excavkin.excavator.hydraulics`).
    name, source : str
        For messages.

    Raises
    ------
    ModelError
        If the topology is not a backhoe front, a name is unknown or a number is impossible.
    """

    ROLES = ROLES

    def __init__(
        self,
        mechanism: Mechanism,
        front: Front,
        cylinders: Mapping[str, Cylinder],
        circuits: Mapping[str, Circuit],
        *,
        ground_line: float = 0.0,
        swing_axis: float = 0.0,
        level_bottom: float = 2.44,
        gravity: float = 9.80665,
        base: BaseMachine | None = None,
        lift_point: str | None = None,
        hydraulics: Hydraulics | None = None,
        name: str = "",
        source: str | None = None,
    ) -> None:
        self.mechanism = mechanism
        self.front = front
        self.circuits = dict(circuits)
        self.ground_line = float(ground_line)
        self.swing_axis = float(swing_axis)
        self.level_bottom = float(level_bottom)
        self.gravity = float(gravity)
        self.base = base
        self.hydraulics = hydraulics
        self._mass_points: MassPoints | None = None
        self.name = name or mechanism.name
        self.source = source
        missing = [r for r in ROLES if r not in cylinders]
        if missing:
            raise self._err(
                f"missing cylinder{'s' if len(missing) > 1 else ''} "
                f"{', '.join(missing)} (needs boom, arm and bucket)",
                "cylinders",
            )
        for role in ROLES:
            if cylinders[role].role != role:
                raise self._err(
                    f"the {role} cylinder says its role is {cylinders[role].role!r}",
                    f"cylinders.{role}",
                )
        self.cylinders: tuple[Cylinder, Cylinder, Cylinder] = (
            cylinders["boom"],
            cylinders["arm"],
            cylinders["bucket"],
        )
        for c in self.cylinders:
            self._check_cylinder(c)
        self.pins = self._find_pins()
        plan = mechanism.plan
        self._col = tuple(plan.inputs.index(c.driver) for c in self.cylinders)
        self._free = [n for n in plan.inputs if n not in {c.driver for c in self.cylinders}]
        if self._free:
            raise self._err(
                f"the model has inputs besides the three cylinders: {', '.join(self._free)}",
                "cylinders",
            )
        shapes = plan.shapes
        self._r_tip = shapes[front.bucket].distance(self.pins.bucket_pin, front.tip)
        self._r_lip = shapes[front.bucket].distance(self.pins.bucket_pin, front.lip)
        pos = mechanism.assembly.positions
        self._ground_xy = {n: pos[plan.points.index(n)] for n in mechanism.model.ground.points}
        q, t, w = (pos[plan.points.index(n)] for n in (self.pins.bucket_pin, front.tip, front.lip))
        # the cutting direction for the vertical-wall depth: the teeth (lip → tip), or for a
        # bucket without teeth its floor (floor → lip); None where neither is known
        self._teeth_offset: float | None = None
        if np.hypot(*(t - w)) >= 1e-6:
            self._teeth_offset = float(wrap_angle(direction_angle(t - q) - direction_angle(t - w)))
        elif front.floor is not None:
            f = pos[plan.points.index(front.floor)]
            if np.hypot(*(w - f)) < 1e-6:
                raise self._err("the floor point coincides with the lip", "front", "floor")
            self._teeth_offset = float(wrap_angle(direction_angle(t - q) - direction_angle(w - f)))
        self.lift_point = self.pins.bucket_pin if lift_point is None else lift_point
        self._check_lift_point()
        for c in self.cylinders:
            if not (math.isfinite(c.mass) and c.mass >= 0.0):
                raise self._err("mass must be zero or positive", f"cylinders.{c.role}", "mass")
        self._check_strokes()

    def _check_lift_point(self) -> None:
        f = self.front
        carriers = (f.stick, f.bucket, f.side_link, f.h_link)
        bodies = {b.name: b.points for b in self.mechanism.model.bodies}
        if not any(self.lift_point in bodies[b] for b in carriers):
            raise self._err(
                f"the lift point {self.lift_point!r} is not a point of the stick, the bucket or "
                "a bucket link",
                "lift",
                "point",
            )

    def _check_strokes(self) -> None:
        """Refuse strokes that never assemble the front (a typo in a retracted length would
        otherwise give ranges and forces of nothing).

        Each cylinder is swept over its stroke with the others at the model's sketch lengths
        (which assemble); one that closes nowhere is named.
        """
        n = 41
        sketch = self.mechanism.sketch_values()
        for c in self.cylinders:
            values: dict[str, np.ndarray | float] = dict(sketch)
            values[c.driver] = np.linspace(c.retracted, c.retracted + c.stroke, n)
            if not self.mechanism.solve(values).status.ok.any():
                raise self._err(
                    f"no length of cylinder {c.driver!r} within its stroke "
                    f"({c.retracted * 1e3:.0f} to {(c.retracted + c.stroke) * 1e3:.0f} mm) "
                    "assembles the front with the other cylinders at the model's sketch; check its "
                    "retracted length and stroke against the model's pins",
                    f"cylinders.{c.role}",
                    "retracted",
                )

    # ---- construction helpers
    def _find_pins(self) -> Pins:
        model = self.mechanism.model
        f = self.front
        names = {b.name: set(b.points) for b in model.bodies}
        for key in ("boom", "stick", "bucket", "side_link", "h_link"):
            if getattr(f, key) not in names:
                raise self._err(f"no body {getattr(f, key)!r} in the model", "front", key)
        for key in ("tip", "lip", "floor"):
            if getattr(f, key) is not None and getattr(f, key) not in names[f.bucket]:
                raise self._err(
                    f"{getattr(f, key)!r} is not a point of the bucket {f.bucket!r}", "front", key
                )
        ground = set(model.ground.points)

        def common(a: set[str], b: set[str], what: str) -> str:
            both = sorted(a & b)
            if len(both) != 1:
                raise self._err(
                    f"the {what} must be exactly one shared point (found "
                    f"{', '.join(both) or 'none'})",
                    "front",
                )
            return both[0]

        foot = common(ground, names[f.boom], "boom foot (ground–boom pin)")
        spiv = common(names[f.boom], names[f.stick], "stick pivot (boom–stick pin)")
        bpin = common(names[f.stick], names[f.bucket], "bucket pin (stick–bucket pin)")
        lpiv = common(names[f.stick], names[f.side_link], "side-link pivot (stick–side link)")
        junc = common(names[f.side_link], names[f.h_link], "link junction (side link–H-link)")
        lpin = common(names[f.h_link], names[f.bucket], "H-link pin (H-link–bucket)")
        drivers = {d.name: d for d in model.linear}
        carriers = (
            (ground, names[f.boom]),
            (names[f.boom], names[f.stick]),
            (names[f.stick], names[f.side_link]),
        )
        what = ("the ground and the boom", "the boom and the stick", "the stick and the side link")
        ends: list[tuple[str, str]] = []
        for c, (base_set, rod_set), text in zip(self.cylinders, carriers, what, strict=True):
            p, q = drivers[c.driver].between
            if p in base_set and q in rod_set:
                ends.append((p, q))
            elif q in base_set and p in rod_set:
                ends.append((q, p))
            else:
                raise self._err(
                    f"the {c.role} cylinder {c.driver!r} ({p}–{q}) must join {text}",
                    f"cylinders.{c.role}",
                    "driver",
                )
        return Pins(foot, spiv, bpin, lpiv, junc, lpin, tuple(ends))

    # ---- simple properties
    @property
    def parameters(self) -> dict[str, float]:
        """Every parameter of the machine and its nominal value (SI): the mechanism's and its
        cylinders' and circuits' ([`excavkin.excavator.designs.machine_parameters`][])."""
        from excavkin.excavator.designs import machine_parameters

        return machine_parameters(self)

    @property
    def tip_radius(self) -> float:
        """|bucket pin → tooth tip| (m)."""
        return self._r_tip

    @property
    def lip_radius(self) -> float:
        """|bucket pin → lip| (m)."""
        return self._r_lip

    @property
    def has_cutting_direction(self) -> bool:
        """Whether the teeth (tip ≠ lip) or a floor point give the bucket's cutting direction."""
        return self._teeth_offset is not None

    @property
    def wall_bucket_angle(self) -> float:
        """Bucket angle (direction of pin → tip, rad) at which the teeth (lip → tip) point
        straight down, so that the bucket shaves a vertical wall; for a bucket without teeth,
        its floor (floor → lip).

        Raises
        ------
        ModelError
            A bucket without teeth and without a ``floor`` point.
        """
        if self._teeth_offset is None:
            raise self._err(
                "the tooth tip is the lip and no floor point is named: the cutting direction of "
                "the vertical-wall digging depth is unknown",
                "front",
                "floor",
            )
        return float(wrap_angle(np.asarray(-0.5 * np.pi + self._teeth_offset)))

    @property
    def mass_points(self) -> MassPoints:
        """The front's masses as points: each body's centre of mass (the engine's own, from
        `MassProperties`) and each cylinder's mass,
        half at either end pin."""
        if self._mass_points is None:
            self._mass_points = _mass_points(self)
        return self._mass_points

    @property
    def front_mass(self) -> float:
        """Mass of the front: the model's moving bodies and the cylinders (kg)."""
        return float(self.mass_points.mass.sum())

    def __repr__(self) -> str:
        return f"Machine({self.name!r}, cylinders={list(self.drivers)})"

    def _repr_html_(self) -> str:
        """The machine's cylinders and circuits as a small table, for notebooks."""
        import html

        rows = "".join(
            f"<tr><td>{html.escape(c.role)}</td><td>{html.escape(c.driver)}</td>"
            f"<td>{c.count}</td><td>{c.bore * 1e3:.0f}/{c.rod * 1e3:.0f}</td>"
            f"<td>{c.retracted * 1e3:.0f}–{(c.retracted + c.stroke) * 1e3:.0f}</td>"
            f"<td>{self.circuits[c.circuit].working / 1e6:.1f} / "
            f"{self.circuits[c.circuit].relief / 1e6:.1f}</td></tr>"
            for c in self.cylinders
        )
        return (
            f"<div><b>{html.escape(self.name)}</b> — excavator front on model "
            f"{html.escape(self.mechanism.name)!s}<table><thead><tr><th>cylinder</th>"
            "<th>driver</th><th>count</th><th>bore/rod mm</th><th>pin to pin mm</th>"
            f"<th>working / relief MPa</th></tr></thead><tbody>{rows}</tbody></table></div>"
        )


def _mass_points(machine: Machine) -> MassPoints:
    return mass_points(machine.mechanism, machine.cylinders, machine.pins.cyl_ends)


def as_lengths(lengths: ArrayLike) -> F:
    """Cylinder lengths as an array of shape (n, 3), boom, arm, bucket; refuses other shapes."""
    return cylinder_lengths(lengths, ROLES)


def mm_field(v: float) -> str:
    """A length in metres as whole millimetres in a field of 8, as the printed sheets show it
    (``-0`` printed as ``0``).

    Parameters
    ----------
    v : float
        Length (m).

    Returns
    -------
    str
    """
    return f"{round(v * 1000) + 0.0:8.0f}"


def length_columns(lengths: Sequence[float] | F) -> dict[str, Any]:
    """A table row's cylinder lengths: ``boom``, ``arm``, ``bucket`` (m).

    Parameters
    ----------
    lengths : sequence of float, shape (3,)
        Boom, arm and bucket lengths.

    Returns
    -------
    dict of str to float
    """
    return dict(zip(ROLES, (lengths[0], lengths[1], lengths[2]), strict=True))


def direction_angle(v: F) -> F:
    """Direction of vectors ``v[..., :2]``, CCW from +x, in (−π, π]."""
    return np.asarray(np.arctan2(v[..., 1], v[..., 0]))


def wrap_angle(a: F) -> F:
    """Angles wrapped into [−π, π)."""
    return np.asarray((a + np.pi) % (2.0 * np.pi) - np.pi)


# ------------------------------------------------------------------------ forward kinematics
@dataclass(frozen=True, slots=True)
class FrontPose:
    """The tool's pose at n sets of cylinder lengths.

    Attributes
    ----------
    lengths : ndarray, shape (n, 3)
    tip, lip : ndarray, shape (n, 2)
        Tooth tip and lip positions (m).
    bucket_angle : ndarray, shape (n,)
        Direction of bucket pin → tip (rad).
    ok : ndarray of bool, shape (n,)
        Assembled (the engine's status).
    within_stroke : ndarray of bool, shape (n,)
    result : KinematicResult
        Everything else (all points, body angles, transmission angles).
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    lengths: F
    tip: F
    lip: F
    bucket_angle: F
    ok: B
    within_stroke: B
    result: KinematicResult


def forward(machine: Machine, lengths: ArrayLike) -> FrontPose:
    """Cylinder lengths → tip, lip and bucket angle, through the general engine.

    Parameters
    ----------
    machine : Machine
    lengths : array_like, shape (n, 3)
        Boom, arm and bucket cylinder lengths (m).

    Returns
    -------
    FrontPose
    """
    L = as_lengths(lengths)
    return pose_of(machine, L, machine.solve(L))


def pose_of(machine: Machine, lengths: F, result: KinematicResult) -> FrontPose:
    """The tool's pose read from a solve of ``machine`` at ``lengths`` (shape (n, 3))."""
    tip = result.point(machine.front.tip)[0]
    lip = result.point(machine.front.lip)[0]
    q = result.point(machine.pins.bucket_pin)[0]
    ok, within = result.status.ok, machine.within_stroke(lengths)
    return FrontPose(lengths, tip, lip, direction_angle(tip - q), ok, within, result)


@dataclass(frozen=True, slots=True)
class Transfer:
    """Positions and first-order transfer functions ∂(point)/∂L of every point.

    Attributes
    ----------
    positions : ndarray, shape (n, n_points, 2)
    d : ndarray, shape (n, n_points, 2, 3)
        ``d[i, p, :, c]`` = ∂(position of point p)/∂L_c.
    ok : ndarray of bool, shape (n,)
    result : KinematicResult
        The solve with unit boom rate (its positions are ``positions``).
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    positions: F
    d: F
    ok: B
    result: KinematicResult

    def point(self, machine: Machine, name: str) -> tuple[F, F]:
        """Position (n, 2) and Jacobian (n, 2, 3) of a point."""
        i = machine.mechanism.plan.points.index(name)
        return self.positions[:, i], self.d[:, i]


def transfer(machine: Machine, lengths: ArrayLike) -> Transfer:
    """The engine's exact transfer functions: one solve per cylinder with unit rate.

    With the rates of the other two cylinders zero, the engine's velocities are the partial
    derivatives ∂(x, y)/∂L_c (DESIGN.md §4), exact to rounding.

    Parameters
    ----------
    machine : Machine
    lengths : array_like, shape (n, 3)

    Returns
    -------
    Transfer
    """
    L = as_lengths(lengths)
    cols = []
    first: KinematicResult | None = None
    for c in range(3):
        res = machine.solve(L, np.eye(3)[c])
        first = first or res
        cols.append(res.velocities)
    assert first is not None
    return Transfer(first.positions, np.stack(cols, axis=-1), first.status.ok, first)


@dataclass(frozen=True, slots=True)
class FrontJacobian:
    """The cylinder-space Jacobian of the tool.

    Attributes
    ----------
    matrix : ndarray, shape (n, 3, 3)
        ``∂(x_T, y_T, β)/∂(L_boom, L_arm, L_bucket)`` (rows: m/m, m/m, rad/m).
    condition : ndarray, shape (n,)
        2-norm condition number of ``matrix`` with its β row scaled by |QT| (dimensionless);
        inf at a singular pose.
    pose : FrontPose
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    matrix: F
    condition: F
    pose: FrontPose


def jacobian(machine: Machine, lengths: ArrayLike) -> FrontJacobian:
    """∂(tip x, tip y, bucket angle)/∂(cylinder lengths) and its conditioning.

    Parameters
    ----------
    machine : Machine
    lengths : array_like, shape (n, 3)

    Returns
    -------
    FrontJacobian
    """
    L = as_lengths(lengths)
    tr = transfer(machine, L)
    tip, dtip = tr.point(machine, machine.front.tip)
    q, dq = tr.point(machine, machine.pins.bucket_pin)
    r = tip - q
    dr = dtip - dq
    dbeta = (r[:, 0, None] * dr[:, 1] - r[:, 1, None] * dr[:, 0]) / np.sum(r * r, axis=1)[:, None]
    J = np.concatenate([dtip, dbeta[:, None, :]], axis=1)
    scaled = J.copy()
    scaled[:, 2] *= machine.tip_radius
    cond = np.full(len(L), np.inf)
    good = np.all(np.isfinite(scaled), axis=(1, 2))
    if good.any():
        s = np.linalg.svd(scaled[good], compute_uv=False)
        with np.errstate(divide="ignore"):
            cond[good] = s[:, 0] / s[:, -1]
    return FrontJacobian(J, cond, pose_of(machine, L, tr.result))


def transmission_angles(machine: Machine, result: KinematicResult) -> dict[str, F]:
    """Transmission angles of the three cylinders and of the bucket linkage (rad).

    Each cylinder's is the angle, at its rod end, between the cylinder and the link it drives
    (π/2 best, 0 or π dead); the bucket linkage's is the angle at the H-link pin between the
    H-link and the bucket (its four-bar's output). All come from the engine's dyads.

    Parameters
    ----------
    machine : Machine
    result : KinematicResult

    Returns
    -------
    dict of str to ndarray, shape (n,)
        Keys ``"boom"``, ``"arm"``, ``"bucket"``, ``"bucket_linkage"``.
    """
    plan = machine.mechanism.plan
    out: dict[str, F] = {}
    link_pin = plan.points.index(machine.pins.link_pin)
    for _, st in of_kind(plan.steps, Dyad):
        for role, cyl in zip(ROLES, machine.cylinders, strict=True):
            if cyl.driver in (st.da.label, st.db.label) and "input" in (st.da.kind, st.db.kind):
                out[role] = result.transmission[:, st.index]
        if st.point == link_pin:
            out["bucket_linkage"] = result.transmission[:, st.index]
    missing = [k for k in (*ROLES, "bucket_linkage") if k not in out]
    if missing:
        raise ModelError(
            f"the solve plan has no closed-form dyad for {', '.join(missing)}, "
            "so no transmission angle",
            table="front",
            source=machine.source,
        )
    return out


# ------------------------------------------------------------------------ inverse kinematics
#: The four inverse-kinematics solutions: (stick-pivot side, link-junction side).
BRANCHES: tuple[tuple[int, int], ...] = ((1, 1), (1, -1), (-1, 1), (-1, -1))


@dataclass(frozen=True, slots=True)
class InverseSolution:
    """All cylinder-length solutions for n target poses.

    Attributes
    ----------
    lengths : ndarray, shape (n, 4, 3)
        Per target, one row per `BRANCHES` entry; NaN where that branch does not close.
    reachable : ndarray of bool, shape (n, 4)
        The geometry closes (the stick pivot and the link junction exist).
    within_stroke : ndarray of bool, shape (n, 4)
    model_branch : ndarray of bool, shape (n, 4)
        Every dyad of the model is on its sketch branch, so the forward kinematics of these
        lengths reproduces the target (other solutions need the machine re-assembled).
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    lengths: F
    reachable: B
    within_stroke: B
    model_branch: B

    @property
    def valid(self) -> B:
        """Reachable, within the strokes and on the model's branches, shape (n, 4)."""
        return np.asarray(self.reachable & self.within_stroke & self.model_branch)

    @property
    def n_valid(self) -> NDArray[np.int64]:
        """Number of valid solutions per target, shape (n,)."""
        return np.asarray(self.valid.sum(axis=1), dtype=np.int64)

    def first_valid(self) -> tuple[F, B]:
        """The first valid solution of each target (NaN where none), shape (n, 3), and a mask."""
        v = self.valid
        k = np.argmax(v, axis=1)
        out = self.lengths[np.arange(len(k)), k].copy()
        has = v.any(axis=1)
        out[~has] = np.nan
        return out, np.asarray(has)


def circle_point(a: F, ra: float, b: F, rb: float, side: float) -> tuple[F, B]:
    """Point P with |PA| = ra, |PB| = rb, on side ``side`` = sign cross(B − A, P − A).

    Parameters
    ----------
    a, b : ndarray, shape (..., 2)
        The two centres.
    ra, rb : float
        The distances from a and from b.
    side : float
        +1 or −1: which of the two intersections.

    Returns
    -------
    p : ndarray, shape (..., 2)
        The point (NaN where the circles do not meet).
    ok : ndarray of bool, shape (...)
        Where they meet.
    """
    d = b - a
    dd = np.sqrt(np.sum(d * d, axis=-1))
    x = (ra * ra - rb * rb + dd * dd) / (2.0 * dd)
    h2 = ra * ra - x * x
    ok = np.asarray(h2 >= 0.0)
    h = np.sqrt(np.where(ok, h2, np.nan))
    e = d / dd[..., None]
    perp = np.stack([-e[..., 1], e[..., 0]], axis=-1)
    return a + x[..., None] * e + (side * h)[..., None] * perp, ok


def _frame(machine: Machine, body: str, p0: str, p1: str, x0: F, x1: F, out: dict[str, F]) -> None:
    """World positions of every point of ``body`` from two of its points."""
    sh = machine.mechanism.plan.shapes[body]
    w = x1 - x0
    perp = np.stack([-w[..., 1], w[..., 0]], axis=-1)
    for n in sh.local:
        if n in out:
            continue
        s, t = sh.frame_coords(n, p0, p1)
        out[n] = x0 + s * w + t * perp


def inverse(machine: Machine, tip: ArrayLike, bucket_angle: ArrayLike) -> InverseSolution:
    """Tip position and bucket angle → every set of cylinder lengths that reaches it.

    Closed form: the bucket pin Q is ``tip − |QT|·(cos β, sin β)``; the stick pivot is where
    the circles about the boom foot (radius boom length) and about Q (stick length) meet —
    two sides; the link junction is where the circles about the side-link pivot and the
    H-link pin meet — two sides. Each cylinder's length is then the distance of its pins.

    Parameters
    ----------
    machine : Machine
    tip : array_like, shape (n, 2) or (2,)
        Tooth-tip positions (m); a single pose may be given as one (x, y) pair.
    bucket_angle : array_like, shape (n,) or scalar
        Direction of bucket pin → tip (rad).

    Returns
    -------
    InverseSolution
        With n = 1 for a single pose.
    """
    T = np.asarray(tip, dtype=np.float64)
    if T.shape == (2,):  # one pose
        T = T[None, :]
    beta = np.broadcast_to(np.asarray(bucket_angle, dtype=np.float64), T.shape[:1])
    if T.ndim != 2 or T.shape[1] != 2:
        raise InputError(f"tip positions must have shape (n, 2), got {T.shape}")
    f, p = machine.front, machine.pins
    plan = machine.mechanism.plan
    shapes = plan.shapes
    n = len(T)
    q = T - machine.tip_radius * np.stack([np.cos(beta), np.sin(beta)], axis=-1)
    a = np.broadcast_to(machine._ground_xy[p.foot], (n, 2))
    l_boom = shapes[f.boom].distance(p.foot, p.stick_pivot)
    l_stick = shapes[f.stick].distance(p.stick_pivot, p.bucket_pin)
    l_side = shapes[f.side_link].distance(p.link_pivot, p.junction)
    l_h = shapes[f.h_link].distance(p.junction, p.link_pin)
    lengths = np.full((n, 4, 3), np.nan)
    reach = np.zeros((n, 4), dtype=bool)
    branch = np.zeros((n, 4), dtype=bool)
    dyads = [st for _, st in of_kind(plan.steps, Dyad)]
    for k, (s1, s2) in enumerate(BRANCHES):
        pts: dict[str, F] = {g: np.broadcast_to(xy, (n, 2)) for g, xy in machine._ground_xy.items()}
        pts[p.bucket_pin] = q
        pts[f.tip] = T
        _frame(machine, f.bucket, p.bucket_pin, f.tip, q, T, pts)
        fp, ok1 = circle_point(a, l_boom, q, l_stick, s1)
        pts[p.stick_pivot] = fp
        _frame(machine, f.boom, p.foot, p.stick_pivot, a, fp, pts)
        _frame(machine, f.stick, p.stick_pivot, p.bucket_pin, fp, q, pts)
        kp, ok2 = circle_point(pts[p.link_pivot], l_side, pts[p.link_pin], l_h, s2)
        pts[p.junction] = kp
        _frame(machine, f.side_link, p.link_pivot, p.junction, pts[p.link_pivot], kp, pts)
        _frame(machine, f.h_link, p.junction, p.link_pin, kp, pts[p.link_pin], pts)
        for c, (base, rod) in enumerate(p.cyl_ends):
            d = pts[rod] - pts[base]
            lengths[:, k, c] = np.sqrt(np.sum(d * d, axis=-1))
        reach[:, k] = ok1 & ok2
        good = np.ones(n, dtype=bool)
        for st in dyads:
            pa, pb, pp = (pts[plan.points[i]] for i in (st.a, st.b, st.point))
            cr = (pb[:, 0] - pa[:, 0]) * (pp[:, 1] - pa[:, 1]) - (pb[:, 1] - pa[:, 1]) * (
                pp[:, 0] - pa[:, 0]
            )
            good &= np.sign(cr) == st.sign
        branch[:, k] = good
    within = machine.within_stroke(lengths) & reach
    return InverseSolution(lengths, reach, np.asarray(within), branch & reach)
