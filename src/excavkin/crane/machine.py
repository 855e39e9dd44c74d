r"""A crane: its booms as a general mechanism, its cylinders, hoist, masses and support.

A [`Crane`][excavkin.crane.machine.Crane] is a general
[`Mechanism`][excavkin.mechanism.Mechanism] in the **slew plane**, a vertical plane through the
slew axis (x the radius from the axis at x = 0, y the height above the ground), driven by two
cylinders:

* ``luff`` raises the **boom**, the body pinned to the turntable (the ground of the model);
* ``knuckle`` folds the **jib** (a knuckle-boom crane's outer boom, pinned to the boom), or
  ``telescope`` pushes it out (a telescopic crane's fly section, a prismatic pair on the boom).

Every position and transfer function comes from the general engine. The hook hangs below the
jib's **tip** sheave on ``parts`` falls of the hoist rope: its radius is the tip's x. Where the
rope leaves the tip for a winch elsewhere (the ``lead`` point), it pulls the tip towards it
with the single-line tension W/parts. The turntable's masses slew with the booms; the carrier's
do not, and it stands on outriggers or crawlers (the machinery layer's
[`Support`][excavkin.machinery.base.Support]).

At a hook radius and a length of the second cylinder (the **configuration**), the luffing
cylinder's length that puts the tip at that radius is found on the engine by a bracketed
Newton iteration over the luffing stroke (`Crane.pose`): the root with the highest tip (the
boom raised), to 1e-12 m.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import BoolArray as B
from excavkin.arrays import FloatArray as F
from excavkin.machinery.base import Support
from excavkin.machinery.cylinder_machine import CylinderMachine
from excavkin.machinery.cylinders import Circuit, Cylinder
from excavkin.machinery.masses import MassPoints, mass_points
from excavkin.mechanism import Mechanism

if TYPE_CHECKING:
    from excavkin.kinematics import KinematicResult
    from excavkin.model.entities import Load

#: the second cylinder's role, by the kind of crane
SECOND = {"knuckle": "knuckle", "telescopic": "telescope"}
#: tolerance of the radius solve (m) and its most Newton steps
RADIUS_TOL, MAX_STEPS = 1e-12, 60
#: luffing lengths sampled over the stroke to bracket every root
GRID = 65
#: the largest stability factor a crane takes (a bound against typing errors, not a norm)
FACTOR_MAX = 10.0


@dataclass(frozen=True, slots=True)
class Linkage:
    """Names, in the general model, of the crane's booms and points.

    Attributes
    ----------
    boom : str
        The body pinned to the turntable and luffed by the luffing cylinder.
    jib : str
        The outer boom (pinned to the boom) or the fly section (sliding on it).
    tip : str
        The jib's tip sheave: the hook hangs below it.
    lead : str or None
        Where the hoist rope goes from the tip to its winch (a point of the model), or None
        where the winch sits on the jib.
    """

    boom: str
    jib: str
    tip: str
    lead: str | None = None


@dataclass(frozen=True, slots=True)
class Hoist:
    """The hoist: its winch's rated single-line pull and its reeving.

    Attributes
    ----------
    line_pull : float
        The winch's rated single-line pull (N).
    parts : int
        Parts of line (falls) to the hook block.
    hook_mass : float
        The hook block's mass (kg): part of the load (ASME B30.5 para. 5-1.1.1(b)(4)).
    """

    line_pull: float
    parts: int
    hook_mass: float


@dataclass(frozen=True, slots=True)
class StabilityFactors:
    """The factors of the stability criterion by factored loads, as the user takes them from
    the clause of the standard that rates the crane (ISO 4305, EN 13000 state their stability
    loads in this form; excavkin ships no values for them): the crane must stand under
    ``hook·P + jib·F`` at the tip, F the booms' weight reduced to the tip
    ([`factored_stability_loads`][excavkin.crane.limits.factored_stability_loads]).

    Attributes
    ----------
    hook : float
        γ_P, the factor on the hook load P (> 0).
    jib : float
        γ_F, the share of the booms' weight reduced to the tip that is added (≥ 0).

    Raises
    ------
    InputError
        A factor that is not a finite number in its range.
    """

    hook: float
    jib: float

    def __post_init__(self) -> None:
        from excavkin.errors import InputError

        for name, v, low in (("hook load", self.hook, 0.0), ("jib weight", self.jib, None)):
            number = isinstance(v, (int, float)) and not isinstance(v, bool)
            if not number or not math.isfinite(v):
                raise InputError(f"the {name} factor must be a finite number, not {v!r}")
            if not ((v > low) if low is not None else (v >= 0.0)) or v > FACTOR_MAX:
                side = "more than 0" if low is not None else "at least 0"
                raise InputError(
                    f"the {name} factor {v:g} must be {side} and at most {FACTOR_MAX:g}"
                )

    @property
    def label(self) -> str:
        """``"factors 1.3, 0.2"``: what a chart names the criterion by."""
        return f"factors {self.hook:g}, {self.jib:g}"


@dataclass(frozen=True, slots=True)
class CraneBase:
    """What a crane stands on: the machinery layer's support (turntable and carrier masses,
    outriggers or crawlers).

    Attributes
    ----------
    support : Support
    """

    support: Support


@dataclass(frozen=True, slots=True)
class Pose:
    """The crane at n poses found by radius (`Crane.pose`).

    Attributes
    ----------
    lengths : ndarray, shape (n, 2)
        Cylinder lengths in role order (m); NaN where out of reach.
    kinematics : KinematicResult
        The engine's solve at those lengths, at rest.
    reached : ndarray of bool, shape (n,)
    """

    lengths: F
    kinematics: KinematicResult
    reached: B


class Crane(CylinderMachine):
    """A crane: a general mechanism plus cylinders, circuits, hoist, masses and support.

    Parameters
    ----------
    mechanism : Mechanism
        Two driven linear drivers (the cylinders) and no other input.
    kind : {"knuckle", "telescopic"}
        Which cylinder moves the jib.
    linkage : Linkage
    cylinders : mapping of str to Cylinder
        Keys ``"luff"`` and ``"knuckle"`` or ``"telescope"``.
    circuits : mapping of str to Circuit
    hoist : Hoist
    support : Support
        The turntable's masses (they slew), the carrier's (they do not) and the contacts.
    gravity : float
        g (m/s²), along −y.
    name, source : str
        For messages.
    stability : StabilityFactors, optional
        The stability criterion by factored loads; None (the default) rates stability as a
        share of the tipping load (ASME B30.5 para. 5-1.1.1, `excavkin.crane.limits`).

    Raises
    ------
    ModelError
        Naming the table and entry of a name, topology or number that does not fit.
    """

    def __init__(
        self,
        mechanism: Mechanism,
        kind: str,
        linkage: Linkage,
        cylinders: Mapping[str, Cylinder],
        circuits: Mapping[str, Circuit],
        hoist: Hoist,
        support: Support,
        *,
        gravity: float = 9.80665,
        name: str = "",
        source: str | None = None,
        stability: StabilityFactors | None = None,
    ) -> None:
        self.mechanism = mechanism
        self.source = source
        self.stability = stability
        if kind not in SECOND:
            raise self._err(f"kind must be 'knuckle' or 'telescopic', not {kind!r}", "linkage")
        self.kind = kind
        self.linkage = linkage
        self.circuits = dict(circuits)
        self.hoist = hoist
        self.crane_base = CraneBase(support)
        self.gravity = float(gravity)
        self.name = name or mechanism.name
        self._roles = ("luff", SECOND[kind])
        for role in self._roles:
            if role not in cylinders:
                raise self._err(f"the {role} cylinder is missing", f"cylinders.{role}")
        self.cylinders = tuple(cylinders[r] for r in self._roles)
        for c in self.cylinders:
            self._check_cylinder(c)
        extra = [n for n in mechanism.plan.inputs if n not in self.drivers]
        if extra:
            raise self._err(
                f"the model has inputs besides the two cylinders: {', '.join(extra)}",
                "cylinders",
            )
        self.boom_pin, self.knuckle_pin = self._find_pins()
        drivers = {d.name: d for d in mechanism.model.linear}
        self.pins = _Ends(tuple(drivers[c.driver].between for c in self.cylinders))
        self._mass_points: MassPoints | None = None
        self._check_strokes()

    def with_stability(self, stability: StabilityFactors | None) -> Crane:
        """The same crane rated by another stability criterion.

        Parameters
        ----------
        stability : StabilityFactors or None
            Factored loads, or None for the share of the tipping load.

        Returns
        -------
        Crane
            A shallow copy (the model, cylinders and masses shared).
        """
        out = copy.copy(self)
        out.stability = stability
        return out

    # ---- construction checks
    def _find_pins(self) -> tuple[str, str | None]:
        model = self.mechanism.model
        lk = self.linkage
        bodies = {b.name: set(b.points) for b in model.bodies if not b.ground}
        for key in ("boom", "jib"):
            if getattr(lk, key) not in bodies:
                raise self._err(f"no moving body {getattr(lk, key)!r} in the model", "linkage", key)
        if lk.tip not in bodies[lk.jib]:
            raise self._err(f"{lk.tip!r} is not a point of the jib {lk.jib!r}", "linkage", "tip")
        if lk.lead is not None and lk.lead not in self.mechanism.plan.points:
            raise self._err(f"no point {lk.lead!r} in the model", "linkage", "lead")
        pin = sorted(set(model.ground.points) & bodies[lk.boom])
        if len(pin) != 1:
            raise self._err(
                f"the turntable and the boom must share exactly one pin, found {pin or 'none'}",
                "linkage",
                "boom",
            )
        shared = sorted(bodies[lk.boom] & bodies[lk.jib])
        if self.kind == "knuckle" and len(shared) != 1:
            raise self._err(
                f"a knuckle crane's boom and jib share exactly one pin, found {shared or 'none'}",
                "linkage",
                "jib",
            )
        return pin[0], (shared[0] if self.kind == "knuckle" else None)

    def _check_strokes(self) -> None:
        """Refuse strokes that never assemble (each swept with the other at the sketch)."""
        sketch = self.mechanism.sketch_values()
        for c in self.cylinders:
            values: dict[str, F | float] = dict(sketch)
            values[c.driver] = np.linspace(c.retracted, c.extended, 41)
            if not self.mechanism.solve(values).status.ok.all():
                raise self._err(
                    f"cylinder {c.driver!r} does not assemble the booms over its whole stroke "
                    f"({c.retracted * 1e3:.0f} to {c.extended * 1e3:.0f} mm) with the other at "
                    "the model's sketch; check its retracted length and stroke against the pins",
                    f"cylinders.{c.role}",
                    "stroke",
                )

    # ---- what the machinery layer reads
    @property
    def roles(self) -> tuple[str, ...]:
        """``("luff", "knuckle")`` or ``("luff", "telescope")``: the order of every ``(n, 2)``
        array of lengths."""
        return self._roles

    @property
    def base(self) -> CraneBase:
        """What it stands on (the machinery layer's equilibrium reads its ``support``)."""
        return self.crane_base

    @property
    def support(self) -> Support:
        """The support: turntable and carrier masses and the contacts."""
        return self.crane_base.support

    @property
    def swing_axis(self) -> float:
        """The slew axis: x = 0 in the slew plane (m)."""
        return 0.0

    @property
    def ground_line(self) -> float:
        """The ground: y = 0 (m)."""
        return 0.0

    @property
    def mass_points(self) -> MassPoints:
        """The booms' masses as points (each body's centre of mass, half of each cylinder's
        mass at either end pin)."""
        if self._mass_points is None:
            self._mass_points = mass_points(self.mechanism, self.cylinders, self.pins.cyl_ends)
        return self._mass_points

    @property
    def mass(self) -> float:
        """The whole crane's mass without the load (kg)."""
        return float(self.mass_points.mass.sum()) + self.support.mass

    @property
    def on_outriggers(self) -> bool:
        """Whether it stands on outriggers."""
        return any(c.kind == "outriggers" for c in self.support.contacts)

    @property
    def mounting(self) -> str:
        """``"outriggers"``, ``"tyres"`` or ``"crawlers"``: what it stands on."""
        if self.on_outriggers:
            return "outriggers"
        return "tyres" if any(c.kind == "tyres" for c in self.support.contacts) else "crawlers"

    @property
    def second(self) -> Cylinder:
        """The cylinder that moves the jib."""
        return self.cylinders[1]

    # ---- geometry from the engine
    def tip(self, kin: KinematicResult) -> F:
        """The tip sheave's position at every pose (n, 2) (m).

        Parameters
        ----------
        kin : KinematicResult

        Returns
        -------
        ndarray
        """
        return np.asarray(kin.positions[:, self.index(self.linkage.tip)])

    def configuration(self, kin: KinematicResult) -> F:
        """The boom configuration at every pose: the knuckle angle (rad, the jib from the
        boom's line, < 0 folded down) or the boom length (m, boom pin to tip).

        Parameters
        ----------
        kin : KinematicResult

        Returns
        -------
        ndarray, shape (n,)
        """
        p = kin.positions
        a = p[:, self.index(self.boom_pin)]
        t = p[:, self.index(self.linkage.tip)]
        if self.knuckle_pin is None:
            return np.asarray(np.hypot(*(t - a).T))
        k = p[:, self.index(self.knuckle_pin)]
        u, v = k - a, t - k
        return np.asarray(
            np.arctan2(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0], u[:, 0] * v[:, 0] + u[:, 1] * v[:, 1])
        )

    @property
    def configuration_name(self) -> str:
        """``"knuckle angle"`` or ``"boom length"``."""
        return "boom length" if self.knuckle_pin is None else "knuckle angle"

    def pose(self, radius: ArrayLike, second: ArrayLike) -> Pose:
        """The crane with the hook at a radius, the second cylinder at a length (broadcast).

        Parameters
        ----------
        radius : array_like
            The hook's distance from the slew axis (m).
        second : array_like
            The knuckle or telescoping cylinder's length (m).

        Returns
        -------
        Pose
            NaN lengths where no luffing length within its stroke reaches the radius.
        """
        r, s = np.broadcast_arrays(
            np.atleast_1d(np.asarray(radius, dtype=np.float64)),
            np.atleast_1d(np.asarray(second, dtype=np.float64)),
        )
        r, s = r.ravel(), s.ravel()
        n = r.size
        luff = self.cylinders[0]
        grid = np.linspace(luff.retracted, luff.extended, GRID)
        lg = np.column_stack([np.tile(grid, n), np.repeat(s, GRID)])
        tips = self.tip(self.solve(lg)).reshape(n, GRID, 2)
        f = tips[..., 0] - r[:, None]
        cross = (f[:, :-1] * f[:, 1:] <= 0.0) & np.isfinite(f[:, :-1] * f[:, 1:])
        height = np.where(cross, tips[:, :-1, 1] + tips[:, 1:, 1], -np.inf)
        j = np.argmax(height, axis=1)
        reached = cross[np.arange(n), j]
        lo, hi = grid[j], grid[j + 1]
        flo = f[np.arange(n), j]
        L = np.where(reached, 0.5 * (lo + hi), luff.retracted)
        one_hot = np.array([1.0, 0.0])
        for _ in range(MAX_STEPS):  # bracketed Newton, every pose at once
            kin = self.solve(np.column_stack([L, s]), one_hot)
            x = self.tip(kin)[:, 0]
            dx = np.asarray(kin.velocities[:, self.index(self.linkage.tip), 0])
            g = x - r
            if np.all(~reached | (np.abs(g) <= RADIUS_TOL)):
                break
            same = np.sign(g) == np.sign(flo)
            lo, flo = np.where(same, L, lo), np.where(same, g, flo)
            hi = np.where(same, hi, L)
            with np.errstate(divide="ignore", invalid="ignore"):
                step = L - g / dx
            inside = np.isfinite(step) & (step > np.minimum(lo, hi)) & (step < np.maximum(lo, hi))
            L = np.where(reached, np.where(inside, step, 0.5 * (lo + hi)), L)
        lengths = np.column_stack([np.where(reached, L, np.nan), s])
        return Pose(lengths, self.solve(lengths), reached)

    def hook_loads(self, kin: KinematicResult, load: float | F) -> list[Load]:
        """The hook load as loads of the general kinetostatics: the falls on the tip sheave
        and, where the rope leads off to a winch, its single-line pull towards the lead point
        (module docstring).

        Parameters
        ----------
        kin : KinematicResult
            The poses (the lead's direction changes with them).
        load : float or ndarray
            The hook load (N), hook block included.

        Returns
        -------
        list of PointForce
        """
        from excavkin.kinetostatics import PointForce

        lk = self.linkage
        w = np.broadcast_to(np.asarray(load, dtype=np.float64), (len(kin),))
        out: list[Load] = [PointForce("hook", lk.jib, lk.tip, np.column_stack([0.0 * w, -w]))]
        if lk.lead is None:
            return out
        p = kin.positions
        d = p[:, self.index(lk.lead)] - p[:, self.index(lk.tip)]
        u = d / np.hypot(d[:, 0], d[:, 1])[:, None]
        pull = (w / self.hoist.parts)[:, None] * u
        out.append(PointForce("lead", lk.jib, lk.tip, pull))
        owner = next(
            (b.name for b in self.mechanism.model.bodies if lk.lead in b.points and not b.ground),
            None,
        )
        if owner is not None:
            out.append(PointForce("lead reaction", owner, lk.lead, -pull))
        return out


@dataclass(frozen=True, slots=True)
class _Ends:
    """Each cylinder's two end pins, in role order (what `CylinderMachine` reads)."""

    cyl_ends: tuple[tuple[str, str], ...]
