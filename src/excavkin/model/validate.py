"""Checks on a [`Model`][excavkin.model.entities.Model] that need no geometry solving.

Each problem raises [`ModelError`][excavkin.errors.ModelError] naming the table and entry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.errors import MobilityError, ModelError, did_you_mean
from excavkin.model.entities import Model, Rope
from excavkin.model.gears import gear_pivots, gear_train, pivot_on, rack_side


def validate(model: Model) -> None:
    """Check names, references, counts and values of ``model``; raise on the first problem.

    One check per table, in the order a file's tables are read, then the checks across the
    whole model (its mobility, and where each driver and slider leaves it)."""
    _check_points(model)
    _check_names(model)
    _check_bodies(model)
    _check_rotary(model)
    _check_ropes(model)
    _check_linear(model)
    _check_sliders(model)
    _check_lengths(model)
    _check_gears(model)
    _check_racks(model)
    _check_cams(model)
    mobility_check(model)
    gear_train(model)


def _check_points(model: Model) -> None:
    """``[points]``: at least one, each with two finite coordinates."""
    src = model.source
    if not model.points:
        raise ModelError("the model has no points", table="points", source=src)
    for name, xy in model.points.items():
        if len(xy) != 2 or not all(math.isfinite(c) for c in xy):
            raise ModelError(
                "a point needs two finite coordinates [x, y]",
                table="points",
                entry=name,
                source=src,
            )


def _check_names(model: Model) -> None:
    """No name twice among the bodies, the drivers or the sliders."""
    src = model.source
    _unique([b.name for b in model.bodies], "bodies", src)
    _unique([d.name for d in model.rotary] + [d.name for d in model.linear], "drivers", src)
    _unique([s.name for s in model.sliders], "sliders", src)
    _unique([g.name for g in model.gears], "gears", src)
    _unique([r.name for r in model.racks], "racks", src)
    _unique([c.name for c in model.cams], "cams", src)


def _check_bodies(model: Model) -> None:
    """``[bodies]``: one ground; each body's points known, distinct and enough, its first two
    apart, its mass properties sound; every point on some body."""
    src = model.source
    grounds = [b.name for b in model.bodies if b.ground]
    if len(grounds) != 1:
        raise ModelError(
            "exactly one body must have ground = true"
            + (f" (found {len(grounds)}: {', '.join(grounds)})" if grounds else " (found none)"),
            table="bodies",
            source=src,
        )
    in_some_body: set[str] = set()
    for b in model.bodies:
        need = 1 if b.ground else 2
        if len(b.points) < need:
            raise ModelError(
                f"a body needs at least {need} point{'s' if need > 1 else ''}, it has "
                f"{len(b.points)}",
                table="bodies",
                entry=b.name,
                source=src,
            )
        _known_points(model, b.points, "bodies", b.name)
        if len(set(b.points)) != len(b.points):
            raise ModelError("a point is listed twice", table="bodies", entry=b.name, source=src)
        in_some_body.update(b.points)
        if not b.ground and len(b.points) >= 2:
            first, second = (model.points[n] for n in b.points[:2])
            if math.dist(first, second) == 0.0:
                raise ModelError(
                    f"its first two points {b.points[0]} and {b.points[1]} coincide in the "
                    "sketch, so the body has no orientation",
                    table="bodies",
                    entry=b.name,
                    source=src,
                )
        if b.mass is not None and not b.mass > 0:
            raise ModelError(
                f"mass must be positive, got {b.mass} kg", table="bodies", entry=b.name, source=src
            )
        if b.inertia is not None and not b.inertia >= 0:
            raise ModelError(
                f"inertia must not be negative, got {b.inertia} kg*m^2",
                table="bodies",
                entry=b.name,
                source=src,
            )
        if (b.inertia is not None or b.center_of_mass is not None) and b.mass is None:
            raise ModelError(
                "inertia or center_of_mass is given without a mass",
                table="bodies",
                entry=b.name,
                source=src,
            )
    orphans = [p for p in model.points if p not in in_some_body]
    if orphans:
        raise ModelError(
            f"{', '.join(orphans)}: "
            + ("these points belong" if len(orphans) > 1 else "point belongs")
            + " to no body (add it to a body's points list)",
            table="points",
            source=src,
        )


def _check_rotary(model: Model) -> None:
    """The rotary ``[drivers]``: a known moving body, a known other reference, a pivot on the
    body."""
    src = model.source
    body_names = {b.name for b in model.bodies}
    body_named = {b.name: b for b in model.bodies}
    for d in model.rotary:
        if d.body not in body_names:
            raise ModelError(
                f"unknown body {d.body!r}{did_you_mean(d.body, body_names)}",
                table=f"drivers.{d.name}",
                entry="body",
                source=src,
            )
        if d.reference not in body_names:
            raise ModelError(
                f"unknown body {d.reference!r}{did_you_mean(d.reference, body_names)}",
                table=f"drivers.{d.name}",
                entry="reference",
                source=src,
            )
        body = body_named[d.body]
        if body.ground:
            raise ModelError(
                "the ground cannot be driven", table=f"drivers.{d.name}", entry="body", source=src
            )
        if d.reference == d.body:
            raise ModelError(
                "a body cannot be its own reference",
                table=f"drivers.{d.name}",
                entry="reference",
                source=src,
            )
        if d.pivot not in body.points:
            raise ModelError(
                f"pivot {d.pivot!r} is not a point of body {d.body!r}",
                table=f"drivers.{d.name}",
                entry="pivot",
                source=src,
            )


def _check_linear(model: Model) -> None:
    """The linear ``[drivers]``: two known, distinct points not on one body (unless free)."""
    src = model.source
    bodies_at = model.bodies_at()
    for ld in model.linear:
        _known_points(model, ld.between, f"drivers.{ld.name}", "between")
        p, q = ld.between
        if p == q:
            raise ModelError(
                "its two points are the same",
                table=f"drivers.{ld.name}",
                entry="between",
                source=src,
            )
        common = [b.name for b in bodies_at.get(p, ()) if q in b.points]
        if common and ld.mode != "free":
            raise ModelError(
                f"{p} and {q} are both points of body {common[0]!r}, so their distance cannot "
                "change",
                table=f"drivers.{ld.name}",
                entry="between",
                source=src,
            )


def _check_ropes(model: Model) -> None:
    """``[ropes]``: two known, distinct blocks not on one body, a whole number of parts, a
    winch's drum radius and gear ratio positive, and the element of its name its own."""
    src = model.source
    bodies_at = model.bodies_at()
    _unique([r.name for r in model.ropes], "ropes", src)
    elements = {d.name: d for d in model.linear}
    drivers = {d.name for d in model.rotary} | set(elements)
    for rope in model.ropes:
        table = f"ropes.{rope.name}"
        if len(rope.path) < 2:
            raise ModelError(
                f"path must list the rope's two blocks (got {len(rope.path)} points)",
                table=table,
                entry="path",
                source=src,
            )
        _known_points(model, rope.path, table, "path")
        if rope.over_sheaves:
            _check_sheaves(model, rope, drivers)
            continue
        if rope.radii or rope.wraps:
            raise ModelError(
                "radii and wraps belong to sheaves: a rope between two blocks has none",
                table=table,
                entry="radii" if rope.radii else "wraps",
                source=src,
            )
        p, q = rope.path
        if p == q:
            raise ModelError(
                "its two blocks are the same point", table=table, entry="path", source=src
            )
        common = [b.name for b in bodies_at.get(p, ()) if q in b.points]
        if common:
            raise ModelError(
                f"{p} and {q} are both points of body {common[0]!r}, so the rope between "
                "them cannot move",
                table=table,
                entry="path",
                source=src,
            )
        if isinstance(rope.parts, bool) or not isinstance(rope.parts, int) or rope.parts < 1:
            raise ModelError(
                f"parts must be a whole number ≥ 1, not {rope.parts!r}",
                table=table,
                entry="parts",
                source=src,
            )
        if rope.mode not in ("winch", "locked"):
            raise ModelError(
                f"mode must be 'winch' or 'locked', not {rope.mode!r}",
                table=table,
                entry="mode",
                source=src,
            )
        if rope.mode == "winch":
            for key, value in (("drum_radius", rope.drum_radius), ("gear_ratio", rope.gear_ratio)):
                if value is None or not (math.isfinite(value) and value > 0.0):
                    raise ModelError(
                        f"a winch needs a finite {key} > 0 (got {value!r})",
                        table=table,
                        entry=key,
                        source=src,
                    )
        el = elements.get(rope.name)
        if el is not None and el != rope.element():
            raise ModelError(
                f"a driver is also called {rope.name!r}: the rope is the linear element of its "
                "name between its blocks; rename one",
                table=table,
                source=src,
            )


def _check_sheaves(model: Model, rope: Rope, drivers: set[str]) -> None:
    """A rope over sheaves: one part, a radius > 0 and a wrap per sheave, no point twice in a
    row, a winch's drum, and a name no driver has."""
    src = model.source
    table = f"ropes.{rope.name}"

    def bad(problem: str, entry: str) -> ModelError:
        return ModelError(problem, table=table, entry=entry, source=src)

    if rope.name in drivers:
        raise bad(f"a driver is also called {rope.name!r}: rename one", "path")
    if rope.parts != 1:
        raise bad(
            f"a rope over sheaves has one part (got parts = {rope.parts!r}); a block of n parts "
            "is a rope between two blocks, or reeved over sheaves by a path that visits its "
            "two blocks in turn (path = [..., M, T, M, T])",
            "parts",
        )
    for a, b in zip(rope.path, rope.path[1:], strict=False):
        if a == b:
            raise bad(f"point {a} follows itself in the path", "path")
    inner = len(rope.path) - 2
    for key, given in (("radii", rope.radii), ("wraps", rope.wraps)):
        if len(given) != inner:
            raise bad(
                f"{key} must give one value per sheave ({inner}: the inner points of path), "
                f"got {len(given)}",
                key,
            )
    for k, r in enumerate(rope.radii):
        if not (math.isfinite(r) and r > 0.0):
            raise bad(f"sheave {rope.path[k + 1]}: its radius must be finite and > 0", "radii")
    for k, w in enumerate(rope.wraps):
        if w not in ("ccw", "cw"):
            raise bad(f"sheave {rope.path[k + 1]}: wrap must be 'ccw' or 'cw', not {w!r}", "wraps")
    first: dict[str, float] = {}  # a block's sheaves (a point the path visits again): one radius
    for p, r in zip(rope.path[1:-1], rope.radii, strict=True):
        if first.setdefault(p, r) != r:
            raise bad(
                f"sheave {p}: the rope runs over it again with radius {r:g} m, not "
                f"{first[p]:g} m; a block's sheaves (the path's visits of one point) share one "
                "radius",
                "radii",
            )
    if rope.mode not in ("winch", "locked"):
        raise bad(f"mode must be 'winch' or 'locked', not {rope.mode!r}", "mode")
    if rope.mode == "winch":
        for key, value in (("drum_radius", rope.drum_radius), ("gear_ratio", rope.gear_ratio)):
            if value is None or not (math.isfinite(value) and value > 0.0):
                raise bad(f"a winch needs a finite {key} > 0 (got {value!r})", key)


def _check_sliders(model: Model) -> None:
    """``[sliders]``: a line through two distinct points of one body, a point off that body."""
    src = model.source
    bodies_at = model.bodies_at()
    for s in model.sliders:
        _known_points(model, (s.point, *s.along), f"sliders.{s.name}", "point/along")
        if s.along[0] == s.along[1]:
            raise ModelError(
                "the line needs two different points",
                table=f"sliders.{s.name}",
                entry="along",
                source=src,
            )
        if math.dist(model.points[s.along[0]], model.points[s.along[1]]) == 0.0:
            raise ModelError(
                f"the line's points {s.along[0]} and {s.along[1]} coincide in the sketch, so "
                "they set no direction",
                table=f"sliders.{s.name}",
                entry="along",
                source=src,
            )
        carriers = [b for b in bodies_at.get(s.along[0], ()) if s.along[1] in b.points]
        if not carriers:
            raise ModelError(
                f"{s.along[0]} and {s.along[1]} are not points of one body",
                table=f"sliders.{s.name}",
                entry="along",
                source=src,
            )
        if any(s.point in b.points for b in carriers):
            raise ModelError(
                f"{s.point} is a point of the body that carries the line",
                table=f"sliders.{s.name}",
                entry="point",
                source=src,
            )


def _check_lengths(model: Model) -> None:
    """``[lengths]``: known points, positive values."""
    src = model.source
    for (p, q), value in model.lengths.items():
        key = f"{p}-{q}"
        if p not in model.points or q not in model.points:
            missing = p if p not in model.points else q
            raise ModelError(
                f"unknown point {missing!r}{did_you_mean(missing, model.points)}",
                table="lengths",
                entry=key,
                source=src,
            )
        if not value > 0:
            raise ModelError(
                f"a length must be positive, got {value} m", table="lengths", entry=key, source=src
            )


def _check_gears(model: Model) -> None:
    """``[gears]``: two distinct known bodies on a known carrier, each sharing one point (its
    pivot) with it, pivots apart; a positive ratio (not 1 for an internal pair), a pressure
    angle in [0, 90°), and pitch radii, where given, that fit the pivots' distance."""
    src = model.source
    names = {b.name for b in model.bodies}
    for g in model.gears:
        table = f"gears.{g.name}"
        for body in (*g.gears, g.carrier):
            if body not in names:
                raise ModelError(
                    f"unknown body {body!r}{did_you_mean(body, names)}",
                    table=table,
                    entry="carrier" if body == g.carrier else "gears",
                    source=src,
                )
        if len({*g.gears, g.carrier}) != 3:
            raise ModelError(
                "the two gears and the carrier must be three different bodies",
                table=table,
                entry="gears",
                source=src,
            )
        if not (math.isfinite(g.ratio) and g.ratio > 0):
            raise ModelError(
                f"the ratio must be positive, got {g.ratio}", table=table, entry="ratio", source=src
            )
        if g.internal and g.ratio == 1.0:
            raise ModelError(
                "an internal pair needs a ring larger than its pinion (ratio ≠ 1)",
                table=table,
                entry="ratio",
                source=src,
            )
        if not 0.0 <= g.pressure_angle < math.pi / 2:
            raise ModelError(
                f"the pressure angle must be in [0, 90) deg, got {math.degrees(g.pressure_angle)}",
                table=table,
                entry="pressure_angle",
                source=src,
            )
        p1, p2 = gear_pivots(model, g)
        d = model.lengths.get((p1, p2), model.lengths.get((p2, p1)))
        d = math.dist(model.points[p1], model.points[p2]) if d is None else d
        if not d > 0:
            raise ModelError(
                f"the pivots {p1} and {p2} coincide, so the gears have no centre distance",
                table=table,
                entry="gears",
                source=src,
            )
        if g.radii is not None:
            r1, r2 = g.radii
            want = abs(r1 - r2) if g.internal else r1 + r2
            if not math.isclose(d, want, rel_tol=1e-6):
                raise ModelError(
                    f"the pitch radii {r1:.6g} m and {r2:.6g} m need a centre distance of "
                    f"{want:.6g} m, but the pivots {p1} and {p2} are {d:.6g} m apart",
                    table=table,
                    entry="radii",
                    source=src,
                )


def _check_racks(model: Model) -> None:
    """``[racks]``: a rack, a pinion and a carrier, three different known bodies, the rack and
    the pinion not the ground; the guide two carrier points apart; the pinion pivoted on the
    carrier, the rack sharing no point with it and drawn to one side of the pinion; a positive
    pitch radius and a pressure angle in [0, 90°)."""
    src = model.source
    names = {b.name for b in model.bodies}
    for rk in model.racks:
        table = f"racks.{rk.name}"
        for key, body in (("rack", rk.rack), ("pinion", rk.pinion), ("carrier", rk.carrier)):
            if body not in names:
                raise ModelError(
                    f"unknown body {body!r}{did_you_mean(body, names)}",
                    table=table,
                    entry=key,
                    source=src,
                )
        if len({rk.rack, rk.pinion, rk.carrier}) != 3:
            raise ModelError(
                "the rack, the pinion and the carrier must be three different bodies",
                table=table,
                entry="rack",
                source=src,
            )
        if model.body(rk.rack).ground or model.body(rk.pinion).ground:
            raise ModelError(
                "the rack and the pinion move: neither can be the ground (make the frame the "
                "carrier)",
                table=table,
                entry="rack",
                source=src,
            )
        carrier = model.body(rk.carrier)
        if not all(p in carrier.points for p in rk.along) or rk.along[0] == rk.along[1]:
            raise ModelError(
                f"along must name two different points of the carrier {rk.carrier!r}",
                table=table,
                entry="along",
                source=src,
            )
        if math.dist(model.points[rk.along[0]], model.points[rk.along[1]]) == 0.0:
            raise ModelError(
                "the guide's two points coincide in the sketch, so they set no direction",
                table=table,
                entry="along",
                source=src,
            )
        shared = [p for p in model.body(rk.rack).points if p in carrier.points]
        if shared:
            raise ModelError(
                f"the rack shares {', '.join(shared)} with its carrier; it slides in its guide "
                "and is joined to the carrier by nothing else",
                table=table,
                entry="rack",
                source=src,
            )
        if not (math.isfinite(rk.radius) and rk.radius > 0):
            raise ModelError(
                f"the pitch radius must be positive, got {rk.radius} m",
                table=table,
                entry="radius",
                source=src,
            )
        if not 0.0 <= rk.pressure_angle < math.pi / 2:
            raise ModelError(
                f"the pressure angle must be in [0, 90) deg, got {math.degrees(rk.pressure_angle)}",
                table=table,
                entry="pressure_angle",
                source=src,
            )
        pivot_on(model, rk.pinion, rk.carrier, table, "pinion")
        rack_side(model, rk)


def _check_cams(model: Model) -> None:
    """``[cams]``: a cam, a follower and a carrier, three different known bodies, neither the
    cam nor the follower the ground; the guide two carrier points apart; the cam pivoted on the
    carrier, the follower sharing no point with it; a lift table from 0 to 360° (at least four
    rows, turns strictly increasing, the same lift at both ends, finite)."""
    src = model.source
    names = {b.name for b in model.bodies}
    for cm in model.cams:
        table = f"cams.{cm.name}"

        def bad(problem: str, entry: str, table: str = table) -> ModelError:
            return ModelError(problem, table=table, entry=entry, source=src)

        for key, body in (("cam", cm.cam), ("follower", cm.follower), ("carrier", cm.carrier)):
            if body not in names:
                raise bad(f"unknown body {body!r}{did_you_mean(body, names)}", key)
        if len({cm.cam, cm.follower, cm.carrier}) != 3:
            raise bad("the cam, the follower and the carrier must be three different bodies", "cam")
        if model.body(cm.cam).ground or model.body(cm.follower).ground:
            raise bad("the cam and the follower move: neither can be the ground", "cam")
        carrier = model.body(cm.carrier)
        if cm.face not in ("roller", "flat"):
            raise bad(f"face must be 'roller' or 'flat', not {cm.face!r}", "face")
        if cm.along is None:
            pivot_on(model, cm.follower, cm.carrier, table, "follower")
            if cm.face != "roller":
                raise bad("an oscillating follower is a roller (face = 'roller')", "face")
        else:
            if not all(p in carrier.points for p in cm.along) or cm.along[0] == cm.along[1]:
                raise bad(
                    f"along must name two different points of the carrier {cm.carrier!r}",
                    "along",
                )
            if math.dist(model.points[cm.along[0]], model.points[cm.along[1]]) == 0.0:
                raise bad("the guide's two points coincide in the sketch", "along")
            shared = [p for p in model.body(cm.follower).points if p in carrier.points]
            if shared:
                raise bad(
                    f"the follower shares {', '.join(shared)} with its carrier; a translating "
                    "follower slides in its guide (leave out along for one pivoted there)",
                    "follower",
                )
        pivot_on(model, cm.cam, cm.carrier, table, "cam")
        if callable(cm.lift):
            _check_lift_function(cm.lift, bad)
            continue
        lift = cm.lift
        if len(lift) < 4 or not all(
            len(row) == 2 and all(math.isfinite(v) for v in row) for row in lift
        ):
            raise bad("the lift table needs at least four finite rows [turn, lift]", "lift")
        turns = [a for a, _ in lift]
        if turns[0] != 0.0 or not math.isclose(turns[-1], 2 * math.pi, abs_tol=1e-12):
            raise bad("the lift table runs from 0 to 360 deg", "lift")
        if any(b <= a for a, b in zip(turns, turns[1:], strict=False)):
            raise bad("the lift table's turns must increase strictly", "lift")
        if lift[-1][1] != lift[0][1]:
            raise bad(
                f"the lift at 360 deg ({lift[-1][1]:.6g} m) must equal the lift at 0 "
                f"({lift[0][1]:.6g} m): the cam turns round",
                "lift",
            )


def _check_lift_function(law: Any, bad: Any) -> None:
    """A lift function returns three finite values, the same at 0 and 2π (periodic)."""
    try:
        at = [[float(np.asarray(v)) for v in law(np.float64(t))] for t in (0.0, 2 * math.pi)]
    except Exception as exc:  # a user's function: any failure is reported, named
        problem = f"the lift function failed at the turn 0: {type(exc).__name__}: {exc}"
        raise bad(problem, "lift") from None
    if not all(len(row) == 3 and all(math.isfinite(v) for v in row) for row in at):
        raise bad("the lift function must return three finite values (s, ds/dθ, d²s/dθ²)", "lift")
    scale = max(abs(at[0][0]), 1e-3)
    if any(abs(a - b) > 1e-9 * scale for a, b in zip(at[0], at[1], strict=True)):
        raise bad(
            "the lift function must be periodic: the same (s, s', s'') at 0 and 360 deg", "lift"
        )


def _unique(names: list[str], table: str, src: str | None) -> None:
    seen: set[str] = set()
    for n in names:
        if n in seen:
            raise ModelError("duplicate name", table=table, entry=n, source=src)
        seen.add(n)


def _known_points(model: Model, names: tuple[str, ...], table: str, entry: str) -> None:
    for n in names:
        if n not in model.points:
            raise ModelError(
                f"unknown point {n!r}{did_you_mean(n, model.points)} "
                f"(known: {', '.join(model.points)})",
                table=table,
                entry=entry,
                source=model.source,
            )


@dataclass(frozen=True, slots=True)
class Mobility:
    """The Chebyshev–Grübler count of a model.

    ``M = 3 (n − 1) − 2 p1 − p2`` with n links (each cylinder or rope counted as two links,
    barrel and rod, joined by a prismatic pair), p1 lower pairs (revolute and prismatic) and p2
    two-freedom pairs (a point sliding in a slot, a gear or rack mesh: ``gear_pairs``); a rack's
    guide is a prismatic pair; locked cylinders then take one freedom each.
    """

    links: int
    lower_pairs: int
    slot_pairs: int
    locked: int
    inputs: int
    gear_pairs: int = 0

    @property
    def mobility(self) -> int:
        """Freedoms of the mechanism with its locked elements locked."""
        return (
            3 * (self.links - 1)
            - 2 * self.lower_pairs
            - self.slot_pairs
            - self.gear_pairs
            - self.locked
        )

    def describe(self) -> str:
        """The count written out."""
        n, p1, p2 = self.links, self.lower_pairs, self.slot_pairs
        text = f"M = 3·({n} − 1) − 2·{p1} − {p2}"
        if self.gear_pairs:
            text += f" − {self.gear_pairs} higher pair{'s' if self.gear_pairs > 1 else ''}"
        if self.locked:
            text += f" − {self.locked} locked"
        return f"{text} = {self.mobility}"


def mobility(model: Model) -> Mobility:
    """Count links and pairs (Chebyshev–Grübler) for ``model``."""
    links = len(model.bodies)
    lower = 0
    bodies_at = model.bodies_at()
    for p in model.points:
        lower += max(len(bodies_at.get(p, ())) - 1, 0)
    # each cylinder/rope: barrel + rod (2 links), a revolute at each end and a prismatic pair
    links += 2 * len(model.linear)
    lower += 3 * len(model.linear)
    locked = sum(1 for d in model.linear if d.mode == "locked")
    # a rope over sheaves counts as a linear element: its own length a freedom (its winch's
    # input), locked or not
    sheaved = [r for r in model.ropes if r.over_sheaves]
    links += 2 * len(sheaved)
    lower += 3 * len(sheaved)
    locked += sum(1 for r in sheaved if r.mode == "locked")
    # a rack (a cam's follower): a prismatic pair with its carrier and a mesh (a contact)
    lower += len(model.racks) + sum(1 for cm in model.cams if cm.along is not None)
    higher = len(model.gears) + len(model.racks) + len(model.cams)
    return Mobility(links, lower, len(model.sliders), locked, len(model.inputs), higher)


def mobility_check(model: Model) -> None:
    """Raise [`MobilityError`][excavkin.MobilityError] unless the number of inputs equals the
    mobility."""
    m = mobility(model)
    if m.mobility == m.inputs:
        return
    inputs = ", ".join(model.inputs) or "none"
    if m.inputs < m.mobility:
        missing = m.mobility - m.inputs
        msg = (
            f"the mechanism has mobility {m.mobility} ({m.describe()}) but "
            f"{m.inputs} driver{'s' if m.inputs != 1 else ''} ({inputs}): {missing} driver"
            f"{'s are' if missing > 1 else ' is'} missing — add a rotary driver or make a "
            "cylinder 'driven'"
        )
    else:
        extra = m.inputs - m.mobility
        msg = (
            f"the mechanism has mobility {m.mobility} ({m.describe()}) but "
            f"{m.inputs} drivers ({inputs}): {extra} "
            f"{'are' if extra > 1 else 'is'} redundant — remove one or set a cylinder's mode "
            "to 'free'"
        )
    raise MobilityError(msg, table="drivers", source=model.source)
