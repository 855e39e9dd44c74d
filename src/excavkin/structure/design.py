"""Geometry as a batch axis: a model's dimensions as named parameters, and a plan whose
constants hold one value per design.

Every dimension of a model is a parameter with a name and a nominal SI value
([`parameters`][excavkin.structure.design.parameters]):

=========================  ==========================================================
``P.x``, ``P.y``           the sketch coordinates of every point
``"A-B"``                  every ``[lengths]`` entry, by its key
``BODY.mass``              a body's mass, kg
``BODY.inertia``           its moment of inertia about the centre of mass, kg·m²
``BODY.center_of_mass.x``  its centre of mass in sketch coordinates (and ``.y``), m
``LOAD.Fx``, ``LOAD.Fy``   a constant point force of the model's ``[loads]``, N
``LOAD.torque``            a constant couple of the model's ``[loads]``, N·m
``ROPE.drum_radius``       a winch rope's drum radius, m
``ROPE.gear_ratio``        its gear ratio (motor turns per drum turn)
``GEAR.ratio``             a gear pair's ratio r2/r1
``RACK.radius``            a rack's pinion pitch radius, m
``ROPE.radius.S``          the radius of a rope's sheave at its path point S, m
=========================  ==========================================================

[`design_plan`][excavkin.structure.design.design_plan] recomputes the plan's constants (ground
coordinates, radii, body
distances, attachment coefficients, locked lengths) for arrays of parameter values, with the
same arithmetic as the plan builder, through the same body shapes
(`local_frame`). The plan's structure and its branch rule (each
dyad keeps its nominal sketch side) are shared by every design. A design that cannot be built
(a body whose first two points coincide, distances that form no triangle) is marked, not
raised.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.errors import unknown_name
from excavkin.model.entities import Model
from excavkin.model.gears import train_angles
from excavkin.step_kinds import kind_of
from excavkin.step_kinds.rope_path import rope_path, sketch_wraps
from excavkin.structure.plan import SolvePlan, Step
from excavkin.structure.shapes import LocalFrame, com_coords, local_frame

Num = Any  # a float, or an array of one value per design

#: the kind of value of each parameter suffix (for units at the edges)
KIND_OF = {
    "x": "length",
    "y": "length",
    "mass": "mass",
    "inertia": "inertia",
    "Fx": "force",
    "Fy": "force",
    "torque": "torque",
    "drum_radius": "length",
    "gear_ratio": "dimensionless",
    "ratio": "dimensionless",
    "radius": "length",
}


def parameters(model: Model) -> dict[str, float]:
    """Every dimension of the model by name, at its nominal SI value; the file's design
    variables first (each sets every entry that refers to it).

    Parameters
    ----------
    model : Model
        The model whose dimensions are named.

    Returns
    -------
    dict of str to float
        ``NAME`` of each design variable; ``P.x``, ``P.y`` of each point (m); ``P-Q`` of each
        fixed length (m); ``LOAD.Fx``, ``LOAD.Fy`` (N) or ``LOAD.torque`` (N·m) of each
        constant load; ``BODY.mass`` (kg), ``BODY.inertia`` (kg·m²) and
        ``BODY.center_of_mass.x``, ``.y`` (m) where the body gives them; ``ROPE.drum_radius``
        (m) and ``ROPE.gear_ratio`` of each winch rope; ``GEAR.ratio`` of each gear pair;
        ``RACK.radius`` (m), the pinion pitch radius of each rack; ``ROPE.radius.S`` (m), the
        radius of each sheave S of a rope over sheaves; ``CAM.lift.K`` (m, or rad), the lift of
        row K of a cam's table.
    """
    out: dict[str, float] = {v.name: float(v.value) for v in model.design}
    for name, (x, y) in model.points.items():
        out[f"{name}.x"], out[f"{name}.y"] = float(x), float(y)
    for (p, q), value in model.lengths.items():
        out[f"{p}-{q}"] = float(value)
    for name, value in load_parameters(model).items():
        out[name] = value
    for rope in model.ropes:
        if rope.mode == "winch" and rope.drum_radius is not None:
            out[f"{rope.name}.drum_radius"] = float(rope.drum_radius)
            out[f"{rope.name}.gear_ratio"] = float(rope.gear_ratio)
    for g in model.gears:
        out[f"{g.name}.ratio"] = float(g.ratio)
    for rk in model.racks:
        out[f"{rk.name}.radius"] = float(rk.radius)
    for name, value in sheave_parameters(model).items():
        out[name] = value
    for name, value in lift_parameters(model).items():
        out[name] = value
    for b in model.bodies:
        if b.mass is not None:
            out[f"{b.name}.mass"] = float(b.mass)
        if b.inertia is not None:
            out[f"{b.name}.inertia"] = float(b.inertia)
        if b.center_of_mass is not None:
            out[f"{b.name}.center_of_mass.x"] = float(b.center_of_mass[0])
            out[f"{b.name}.center_of_mass.y"] = float(b.center_of_mass[1])
    return out


def lift_parameters(model: Model) -> dict[str, float]:
    """The lifts of the model's cams' tables: ``CAM.lift.K`` of row K (m, or rad for an
    oscillating follower), each row but the last (which repeats the first: row 0 sets both).

    Parameters
    ----------
    model : Model
        The model.

    Returns
    -------
    dict of str to float
        In each cam's table order; none for a law given as a function.
    """
    out: dict[str, float] = {}
    for cm in model.cams:
        if not callable(cm.lift):
            for k, (_, lift) in enumerate(cm.lift[:-1]):
                out[f"{cm.name}.lift.{k}"] = float(lift)
    return out


def sheave_parameters(model: Model) -> dict[str, float]:
    """The sheave radii of the model's ropes over sheaves: ``ROPE.radius.S`` of the sheave at
    path point S (m).

    Parameters
    ----------
    model : Model
        The model.

    Returns
    -------
    dict of str to float
        In each rope's path order.
    """
    out: dict[str, float] = {}
    for rope in model.ropes:
        if rope.over_sheaves:
            for p, r in zip(rope.path[1:-1], rope.radii, strict=True):
                out[f"{rope.name}.radius.{p}"] = float(r)
    return out


def load_parameters(model: Model) -> dict[str, float]:
    """The magnitudes of the model's own constant loads: ``LOAD.Fx``, ``LOAD.Fy`` of a point
    force, ``LOAD.torque`` of a couple (N, N·m)."""
    from excavkin.model.entities import PointForce

    out: dict[str, float] = {}
    for ld in model.loads:
        if callable(ld.value):
            continue
        value = np.asarray(ld.value, dtype=np.float64)
        if isinstance(ld, PointForce) and value.shape == (2,):
            out[f"{ld.name}.Fx"], out[f"{ld.name}.Fy"] = float(value[0]), float(value[1])
        elif not isinstance(ld, PointForce) and value.ndim == 0:
            out[f"{ld.name}.torque"] = float(value)
    return out


def joint_offsets(model: Model) -> dict[str, float]:
    """The pin offsets of every joint, for clearances: ``P@BODY.x`` and ``P@BODY.y`` move body
    BODY's pin at joint P by that much in the body's own frame (nominal 0). At a joint with
    the ground every moving body's pin moves; between moving bodies, every body's but the
    first's (which sets where the joint is).

    Parameters
    ----------
    model : Model
        The model whose joints are offset.

    Returns
    -------
    dict of str to float
        ``P@BODY.x`` and ``P@BODY.y`` of each offset pin, all 0.0 (m).
    """
    out: dict[str, float] = {}
    bodies_at = model.bodies_at()
    for p in model.points:
        owners = bodies_at.get(p, [])
        if len(owners) < 2:
            continue
        moving = [b for b in owners if not b.ground]
        if len(moving) == len(owners):
            moving = moving[1:]
        for b in moving:
            out[f"{p}@{b.name}.x"] = 0.0
            out[f"{p}@{b.name}.y"] = 0.0
    return out


def parameter_kind(name: str, model: Model | None = None) -> str:
    """``"length"``, ``"mass"`` or ``"inertia"``: what a parameter measures."""
    if model is not None:
        for var in model.design:
            if var.name == name:
                return var.kind
        for cm in model.cams:  # an oscillating follower's lift is an angle
            if cm.along is None and name.startswith(f"{cm.name}.lift."):
                return "angle"
    return KIND_OF.get(name.rsplit(".", 1)[-1], "length")


def expand(model: Model, values: Mapping[str, Any]) -> dict[str, Any]:
    """The values with each design variable's value given to every entry that refers to it.

    Raises
    ------
    InputError
        An entry given both itself and through its design variable.
    """
    out = dict(values)
    for var in model.design:
        if var.name not in out:
            continue
        value = out.pop(var.name)
        for target in var.targets:
            if target in values and hasattr(value, "tan") and hasattr(values[target], "tan"):
                # differentiating by both the variable and the entry (dual numbers at the
                # same value): the entry moves with either
                own = values[target]
                out[target] = type(own)(own.val, own.tan + value.tan)
            elif target in values:
                from excavkin.errors import InputError

                raise InputError(
                    f"parameter {target!r} is given both itself and through design variable "
                    f"{var.name!r}"
                )
            else:
                out[target] = value
    return out


@dataclasses.dataclass(frozen=True, slots=True)
class Designs:
    """A family of designs of one model.

    Attributes
    ----------
    plan : SolvePlan
        The model's plan with every constant that varies held as an array, shape (n,).
    input_sketch : ndarray, shape (n_inputs, n)
        Each design's driver values at its sketch (what a held driver keeps).
    unbuildable : ndarray of bool, shape (n,)
        Designs whose dimensions build no mechanism.
    values : dict
        The parameters given, as arrays of shape (n,).
    """

    plan: SolvePlan
    input_sketch: F
    unbuildable: NDArray[np.bool_]
    values: dict[str, F]


class _Geometry:
    """The model's sketch and overrides with the given parameters, and its body frames."""

    def __init__(self, model: Model, values: Mapping[str, Any], frames: bool = True) -> None:
        self.model = model
        values = expand(model, values)
        self.sketch: dict[str, tuple[Num, Num]] = {
            n: (values.get(f"{n}.x", x), values.get(f"{n}.y", y))
            for n, (x, y) in model.points.items()
        }
        self.lengths: dict[tuple[str, str], Num] = {
            (p, q): values.get(f"{p}-{q}", v) for (p, q), v in model.lengths.items()
        }
        #: each winch rope's length per motor angle, R/(i·parts), with the values given
        self.winch: dict[str, Num] = {
            r.name: values.get(f"{r.name}.drum_radius", r.drum_radius)
            / (values.get(f"{r.name}.gear_ratio", r.gear_ratio) * r.parts)
            for r in model.ropes
            if r.mode == "winch"
        }
        #: the gear pairs' ratios given (the others keep their own)
        self.ratios: dict[str, Num] = {
            g.name: values[f"{g.name}.ratio"] for g in model.gears if f"{g.name}.ratio" in values
        }
        self.angles: dict[str, dict[int, Num]] | None = None
        #: each rack's pinion pitch radius
        self.rack_radii: dict[str, Num] = {
            r.name: values.get(f"{r.name}.radius", r.radius) for r in model.racks
        }
        #: each rope's signed sheave radii (0 at its ends), where one of its radii is given
        self.sheaves: dict[str, tuple[Num, ...]] = {
            r.name: (
                0.0,
                *(
                    values.get(f"{r.name}.radius.{p}", rad) * (1.0 if w == "ccw" else -1.0)
                    for p, rad, w in zip(r.path[1:-1], r.radii, r.wraps, strict=True)
                ),
                0.0,
            )
            for r in model.ropes
            if r.over_sheaves and any(f"{r.name}.radius.{p}" in values for p in r.path[1:-1])
        }
        #: each cam's table lifts (all rows but the last), where one of its lifts is given
        self.lifts: dict[str, tuple[Num, ...]] = {
            cm.name: tuple(
                values.get(f"{cm.name}.lift.{k}", lift) for k, (_, lift) in enumerate(cm.lift[:-1])
            )
            for cm in model.cams
            if not callable(cm.lift)
            and any(f"{cm.name}.lift.{k}" in values for k in range(len(cm.lift) - 1))
        }
        self.frames: dict[str, LocalFrame] = {}
        self.bad: Num = False
        for b in model.bodies if frames else ():
            if len(b.points) >= 2:
                frame = local_frame(b, self.sketch, self.lengths)
                self.frames[b.name] = frame
                self.bad = self.bad | ~(frame.base > 0.0)
                for *_, bad in frame.triangles.values():
                    self.bad = self.bad | bad
        for name, value in values.items():
            # a value no design can have: not finite, a length or mass not positive, a
            # negative inertia (the plain model refuses these too)
            if hasattr(value, "tan"):  # a dual number: differentiating, not checking
                continue
            kind = parameter_kind(name)
            with np.errstate(invalid="ignore"):
                fine = np.isfinite(value)
                if kind == "inertia":
                    fine = fine & (value >= 0)
                elif (
                    kind == "mass"
                    or ("." not in name and "-" in name)  # a [lengths] entry
                    or name.endswith((".drum_radius", ".gear_ratio"))  # a winch's
                    or name in {f"{g.name}.ratio" for g in model.gears}
                    or name in {f"{r.name}.radius" for r in model.racks}
                    or name in sheave_parameters(model)
                ):
                    fine = fine & (value > 0)
            self.bad = self.bad | ~fine
        for name, value in values.items():  # pin offsets (clearances) in a body's frame
            if "@" in name and frames:
                pin, _, rest = name.partition("@")
                body, _, axis = rest.rpartition(".")
                x, y = self.frames[body].local[pin]
                self.frames[body].local[pin] = (x + value, y) if axis == "x" else (x, y + value)

    def distance(self, body: str, p: str, q: str) -> Num:
        (x1, y1), (x2, y2) = self.frames[body].local[p], self.frames[body].local[q]
        return np.hypot(x2 - x1, y2 - y1)

    def frame_coords(self, body: str, p: str, a: str, b: str) -> tuple[Num, Num]:
        loc = self.frames[body].local
        (ax, ay), (bx, by), (px, py) = loc[a], loc[b], loc[p]
        wx, wy = bx - ax, by - ay
        rx, ry = px - ax, py - ay
        w2 = wx * wx + wy * wy
        return (rx * wx + ry * wy) / w2, (wx * ry - wy * rx) / w2

    def override(self, p: str, q: str) -> Num | None:
        return self.lengths.get((p, q), self.lengths.get((q, p)))

    def winch_ratio(self, rope: str) -> Num:
        return self.winch[rope]

    def rope_signed(self, rope: str) -> tuple[Num, ...] | None:
        return self.sheaves.get(rope)

    def rack_radius(self, rack: str) -> Num:
        return self.rack_radii[rack]

    def cam_lifts(self, cam: str) -> tuple[Num, ...] | None:
        return self.lifts.get(cam)

    def train(self) -> dict[str, dict[int, Num]] | None:
        if not self.ratios:
            return None
        if self.angles is None:
            self.angles = train_angles(self.model, self.ratios)
        return self.angles

    def unit(self, p: str, q: str) -> tuple[Num, Num]:
        (px, py), (qx, qy) = self.sketch[p], self.sketch[q]
        dx, dy = px - qx, py - qy
        r = np.hypot(dx, dy)
        return dx / r, dy / r


def design_plan(plan: SolvePlan, values: Mapping[str, Any], n: int) -> Designs:
    """The plan's constants for ``n`` designs.

    Parameters
    ----------
    plan : SolvePlan
        The nominal model's plan.
    values : mapping
        Parameter name → SI value: a scalar (every design) or an array of shape (n,).
    n : int
        The number of designs (samples).

    Returns
    -------
    Designs
        The plan with the varied constants as arrays of shape (n,), each design's driver
        values at its sketch, and which designs build no mechanism.

    Raises
    ------
    InputError
        An unknown parameter (with the nearest names), or an array of another length.
    """
    model = plan.model
    known = {**parameters(model), **joint_offsets(model)}
    arrays: dict[str, F] = {}
    for name, value in values.items():
        if name not in known:
            raise unknown_name("parameter", name, list(known))
        arr = np.asarray(value, dtype=np.float64)
        arrays[name] = np.broadcast_to(arr, (n,)).copy() if arr.ndim == 0 else arr
        if arrays[name].shape != (n,):
            from excavkin.errors import InputError

            raise InputError(
                f"parameter {name!r} has {arrays[name].shape} values for {n} samples; give a "
                "scalar or one value per sample"
            )
    varied, held, bad = vary(plan, arrays)
    sketch = np.empty((len(plan.inputs), n))
    for i, value in enumerate(held):
        sketch[i] = value
    bad = np.broadcast_to(np.asarray(bad | ~np.isfinite(sketch).all(axis=0)), (n,)).copy()
    return Designs(varied, sketch, bad, arrays)


@dataclasses.dataclass(frozen=True, slots=True)
class DesignBatch:
    """A family of designs whose plan constants are made chunk by chunk, where they are used
    (in cache, on the chunk's thread), rather than for the whole batch at once.

    Attributes
    ----------
    plan : SolvePlan
        The nominal model's plan.
    values : dict
        Parameter name → SI values, shape (n,).
    """

    plan: SolvePlan
    values: dict[str, F]

    def at(self, index: slice | NDArray[np.intp]) -> tuple[SolvePlan, NDArray[np.bool_]]:
        """The plan for the samples ``index``, and which of them build no mechanism."""
        part = {k: v[index] for k, v in self.values.items()}
        varied, _, bad = vary(self.plan, part)
        n = len(next(iter(part.values())))
        return varied, np.broadcast_to(np.asarray(bad, dtype=bool), (n,))

    def held(self, n: int) -> F:
        """Each design's driver values at its sketch, shape (n_inputs, n): what a driver not
        given keeps (sketch coordinates and overrides only; no body shapes are needed)."""
        geo = _Geometry(self.plan.model, self.values, frames=False)
        out = np.empty((len(self.plan.inputs), n))
        for i, value in enumerate(_input_sketch(self.plan, geo)):
            out[i] = value
        return out


def vary(plan: SolvePlan, values: Mapping[str, Any]) -> tuple[SolvePlan, list[Any], Any]:
    """The plan with its constants recomputed from the parameter ``values`` (arrays, or any
    array-like number type such as dual numbers), each input's sketch value, and which
    designs build no mechanism."""
    geo = _Geometry(plan.model, values)
    names = plan.points
    steps = [kind_of(st).vary(st, geo, names, plan.model) for st in plan.steps]
    return dataclasses.replace(plan, steps=tuple(steps)), _input_sketch(plan, geo), geo.bad


def _input_sketch(plan: SolvePlan, geo: _Geometry) -> list[Num]:
    """Each design's driver values at its sketch, as the plan builder reads them."""
    model = geo.model
    out: list[Num] = list(plan.input_sketch)
    sk = geo.sketch
    body_named = {b.name: b for b in model.bodies}
    input_index = {name: i for i, name in enumerate(plan.inputs)}
    for d in model.rotary:
        p = next(x for x in body_named[d.body].points if x != d.pivot)
        ref = body_named[d.reference]
        ex, ey = (1.0, 0.0) if ref.ground else geo.unit(ref.points[1], ref.points[0])
        dx, dy = sk[p][0] - sk[d.pivot][0], sk[p][1] - sk[d.pivot][1]
        out[input_index[d.name]] = np.arctan2(ex * dy - ey * dx, ex * dx + ey * dy)
    for ld in model.linear:
        if ld.mode == "driven":
            p, q = ld.between
            given = geo.override(p, q)
            (px, py), (qx, qy) = sk[p], sk[q]
            out[input_index[ld.name]] = given if given is not None else np.hypot(px - qx, py - qy)
    for rope in model.ropes:  # a winch's input is its motor's angle: the length over R/(i·n)
        if rope.mode != "winch":
            continue
        i = input_index[rope.name]
        if rope.over_sheaves:
            signed = (
                0.0,
                *(r if w == "ccw" else -r for r, w in zip(rope.radii, rope.wraps, strict=True)),
                0.0,
            )
            wraps0 = sketch_wraps([model.points[p] for p in rope.path], signed)
            own = geo.rope_signed(rope.name) or signed
            out[i] = rope_path([sk[p] for p in rope.path], own, wraps0).length
        out[i] = out[i] / geo.winch[rope.name]
    return out


def mass_items(model: Model, values: Mapping[str, Any]) -> list[tuple[Num, Num, Num, Num]]:
    """Per body: mass, moment of inertia and centre of mass (s, t) on its base vector p0→p1,
    from the parameter ``values`` (arrays, or any array-like number type such as dual
    numbers). A body with a mass but no centre of mass takes the centroid of its points; the
    ground and massless bodies carry zeros."""
    geo = _Geometry(model, values)
    values = expand(model, values)
    out: list[tuple[Num, Num, Num, Num]] = []
    for b in model.bodies:
        if b.ground or b.mass is None:
            out.append((0.0, 0.0, 0.0, 0.0))
            continue
        mass = values.get(f"{b.name}.mass", b.mass)
        inertia = values.get(f"{b.name}.inertia", b.inertia or 0.0)
        if b.center_of_mass is not None:
            cx = values.get(f"{b.name}.center_of_mass.x", b.center_of_mass[0])
            cy = values.get(f"{b.name}.center_of_mass.y", b.center_of_mass[1])
            s, t = com_coords(geo.sketch[b.points[0]], geo.sketch[b.points[1]], (cx, cy))
        else:  # centroid of the body's points, in units of the base vector
            local = geo.frames[b.name].local
            d01 = geo.distance(b.name, b.points[0], b.points[1])
            s = sum(local[p][0] for p in b.points) / len(b.points) / d01
            t = sum(local[p][1] for p in b.points) / len(b.points) / d01
        out.append((mass, inertia, s, t))
    return out


def design_masses(model: Model, values: Mapping[str, Any], n: int) -> tuple[F, F, F]:
    """Each body's mass, moment of inertia and centre of mass (as (s, t) on its base vector
    p0→p1) for ``n`` designs: shapes (n_bodies, n), (n_bodies, n) and (n_bodies, 2, n)."""
    arrays = {k: np.asarray(v, dtype=np.float64) for k, v in values.items()}
    nb = len(model.bodies)
    mass, inertia, com = np.zeros((nb, n)), np.zeros((nb, n)), np.zeros((nb, 2, n))
    for j, (m, i, s, t) in enumerate(mass_items(model, arrays)):
        mass[j], inertia[j], com[j, 0], com[j, 1] = m, i, s, t
    return mass, inertia, com


def take(plan: SolvePlan, index: slice | NDArray[np.intp]) -> SolvePlan:
    """The plan for a subset of samples: every per-sample constant (a design's dimensions, a
    smooth continuation's branch signs) taken at ``index``."""
    steps = [take_step(st, index) for st in plan.steps]
    if all(a is b for a, b in zip(steps, plan.steps, strict=True)):
        return plan
    return dataclasses.replace(plan, steps=tuple(steps))


def take_step(st: Step, index: slice | NDArray[np.intp]) -> Step:
    """One step's per-sample constants taken at ``index`` (its kind's ``take``)."""
    out: Step = kind_of(st).take(st, index)
    return out
