"""A point of a body that gears turn, about a known point of it: ``θ = θ0 + Σ c_i q_i``.

A gear train (`excavkin.model.gears`) sets the angle of each body it turns as a linear
function of the rotary inputs with constant coefficients; once one point of the body (its
``anchor``, a pivot) is known, another is ``anchor + radius·(cos θ, sin θ)``, where θ is the
direction anchor → point. Its rates are ``θ̇ = Σ c_i q̇_i`` and ``θ̈ = Σ c_i q̈_i``, so
positions, velocities and accelerations are closed forms, exact at every order and at every
turn (the angle follows the inputs, not an arctangent).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.model.entities import Model
from excavkin.step_kinds.base import Emitter, Geometry, Primitive, Role, StepKind, register
from excavkin.step_kinds.dist import Index, at, varies
from excavkin.step_kinds.state import Chunk, round_output


@dataclass(frozen=True, slots=True)
class GearStep:
    """``point = anchor + radius·(cos θ, sin θ)``, ``θ = offset + Σ coef[k]·q[inputs[k]]``.

    ``offset`` is the sketch's direction anchor → point less ``Σ coef·q_sketch``; ``body``
    names the body and ``meshes`` the gear pairs of its train (for messages).
    """

    point: int
    anchor: int
    radius: float
    offset: float
    inputs: tuple[int, ...]
    coef: tuple[Any, ...]
    body: str
    meshes: tuple[str, ...]


def sketch_input_angle(geo_sketch: Any, model: Model, ri: int) -> Any:
    """A rotary driver's value in a sketch: the angle from its reference body's orientation to
    pivot → the first other point of its body (floats, or arrays of one per design).

    Parameters
    ----------
    geo_sketch : dict
        Point name → (x, y).
    model : Model
        The model.
    ri : int
        The rotary driver's index.

    Returns
    -------
    float or ndarray
        rad, in (−π, π].
    """
    d = model.rotary[ri]
    p = next(n for n in model.body(d.body).points if n != d.pivot)
    ref = model.body(d.reference)
    if ref.ground:
        ex, ey = 1.0, 0.0
    else:
        (ax, ay), (bx, by) = geo_sketch[ref.points[0]], geo_sketch[ref.points[1]]
        ex, ey = bx - ax, by - ay
    dx = geo_sketch[p][0] - geo_sketch[d.pivot][0]
    dy = geo_sketch[p][1] - geo_sketch[d.pivot][1]
    return np.arctan2(ex * dy - ey * dx, ex * dx + ey * dy)


def train_coefficients(
    geo: Geometry,
    model: Model,
    body: str,
    carrier: str | None,
    inputs: tuple[int, ...],
    coef: tuple[Any, ...],
    scale: Any = 1.0,
) -> tuple[Any, ...]:
    """A step's coefficients of its inputs with the gear ratios of ``geo``: ``scale`` times
    the turn of ``body`` (less that of ``carrier``, when given) per input, or ``coef`` where
    no ratio is given.

    Parameters
    ----------
    geo : Geometry
        The designs' geometry (`Geometry.train`).
    model : Model
        The model.
    body, carrier : str
        The body whose turn sets the step, and the body it is counted from (None: the
        ground).
    inputs : tuple of int
        The step's inputs (indices among the model's inputs).
    coef : tuple
        The plan's own coefficients.
    scale : float or ndarray
        A factor of each coefficient (a rack's −σ·r).

    Returns
    -------
    tuple
        One coefficient per input: floats, arrays of one per design, or dual numbers.
    """
    angles = geo.train()
    if angles is None:
        return coef
    rotary = {d.name: k for k, d in enumerate(model.rotary)}
    out = []
    for i in inputs:
        ri = rotary[model.inputs[i]]
        c = angles[body].get(ri, 0.0)
        if carrier is not None:
            c = c - angles[carrier].get(ri, 0.0)
        out.append(scale * c)
    return tuple(out)


def refuse_ratios(geo: Geometry, cam: str) -> None:
    """Refuse a gear ratio given as a design parameter of a model with a cam (its follower's
    turn is the plan's own).

    Parameters
    ----------
    geo : Geometry
        The designs' geometry.
    cam : str
        The cam's name, for the message.

    Returns
    -------
    None

    Raises
    ------
    InputError
        A gear ratio is given.
    """
    if geo.ratios:
        from excavkin.errors import InputError

        names = ", ".join(f"{g}.ratio" for g in geo.ratios)
        raise InputError(
            f"parameter {names}: a gear ratio is not a design parameter of a model with a cam "
            f"({cam!r}); vary it in a model without cams, or solve each ratio as its own model"
        )


@register
class GearKind(StepKind[GearStep]):
    """A body turned by its gear train."""

    name = "gear"
    record = GearStep
    compiles = True
    iterative = False

    def build(
        self,
        point: int,
        anchor: int,
        radius: float,
        offset: float,
        inputs: tuple[int, ...],
        coef: tuple[float, ...],
        body: str,
        meshes: tuple[str, ...],
    ) -> GearStep:
        return GearStep(point, anchor, radius, offset, inputs, coef, body, meshes)

    def vary(self, st: GearStep, geo: Geometry, names: tuple[str, ...], model: Model) -> GearStep:
        p, o = names[st.point], names[st.anchor]
        radius = geo.distance(st.body, p, o)
        sk = geo.sketch
        offset = np.arctan2(sk[p][1] - sk[o][1], sk[p][0] - sk[o][0])
        coef = train_coefficients(geo, model, st.body, None, st.inputs, st.coef)
        rotary = {d.name: k for k, d in enumerate(model.rotary)}
        for i, c in zip(st.inputs, coef, strict=True):
            ri = rotary[model.inputs[i]]
            offset = offset - c * sketch_input_angle(sk, model, ri)
        if not (varies(radius) or varies(offset) or any(varies(c) for c in coef)):
            return st
        return dataclasses.replace(st, radius=radius, offset=offset, coef=coef)

    def take(self, st: GearStep, index: Index) -> GearStep:
        if not (np.ndim(st.radius) or np.ndim(st.offset) or any(np.ndim(c) for c in st.coef)):
            return st
        return dataclasses.replace(
            st,
            radius=at(st.radius, index) if np.ndim(st.radius) else st.radius,
            offset=at(st.offset, index) if np.ndim(st.offset) else st.offset,
            coef=tuple(at(c, index) if np.ndim(c) else c for c in st.coef),
        )

    def solve(
        self, c: Chunk, st: GearStep, k: int, order: int, scale: float, newton: bool = True
    ) -> F | None:
        """A point of a geared body about a known point: θ = θ0 + Σ c_i q_i."""
        x, v, a = c.x, c.v, c.a
        th: Any = st.offset
        for i, co in zip(st.inputs, st.coef, strict=True):
            th = th + co * c.q[i]
        r = st.radius
        cs, sn = np.cos(th), np.sin(th)
        x[st.point, 0] = x[st.anchor, 0] + r * cs
        x[st.point, 1] = x[st.anchor, 1] + r * sn
        if not order:
            return None
        thd: Any = 0.0
        thdd: Any = 0.0
        for i, co in zip(st.inputs, st.coef, strict=True):
            thd = thd + co * c.qd[i]
            thdd = thdd + co * c.qdd[i]
        v[st.point, 0] = v[st.anchor, 0] - r * thd * sn
        v[st.point, 1] = v[st.anchor, 1] + r * thd * cs
        a[st.point, 0] = a[st.anchor, 0] - r * (thdd * sn + thd * thd * cs)
        a[st.point, 1] = a[st.anchor, 1] + r * (thdd * cs - thd * thd * sn)
        return None

    def nudge(self, c: Chunk, st: GearStep, order: int) -> None:
        round_output(c, st.point, order)

    def transmission(self, st: GearStep) -> int | None:
        return None

    def constants(self, st: GearStep) -> list[Any]:
        return [st.radius, st.offset, *st.coef]

    def emit(self, g: Emitter, st: GearStep, k: int) -> None:
        p, o = st.point, st.anchor
        g.emit(f"r = {g.const()}", f"th = {g.const()}", "thd = 0.0", "thdd = 0.0")
        for i in st.inputs:
            g.emit(
                f"mesh_c = {g.const()}",
                f"th = th + mesh_c * q[{i}, i]",
                f"thd = thd + mesh_c * qd[{i}, i]",
                f"thdd = thdd + mesh_c * qdd[{i}, i]",
            )
        g.emit(
            "cs = math.cos(th)", "sn = math.sin(th)",
            f"X{p} = X{o} + r * cs", f"Y{p} = Y{o} + r * sn",
            f"VX{p} = VX{o} - r * thd * sn", f"VY{p} = VY{o} + r * thd * cs",
            f"AX{p} = AX{o} - r * (thdd * sn + thd * thd * cs)",
            f"AY{p} = AY{o} + r * (thdd * cs - thd * thd * sn)",
        )  # fmt: skip

    def describe(self, st: GearStep, names: tuple[str, ...]) -> str:
        terms = " ".join(
            f"{'+' if co >= 0 else '−'} {abs(co):.6g}·q{i}"
            for i, co in zip(st.inputs, (float(np.max(c)) for c in st.coef), strict=True)
        )
        return (
            f"gear     {names[st.point]} about {names[st.anchor]}: body {st.body!r} turned by "
            f"{', '.join(st.meshes)} (θ = θ0 {terms}, r = {float(np.max(st.radius)):.6g} m)"
        )

    def label(self, st: GearStep, names: tuple[str, ...], k: int) -> str:
        return f"step {k + 1} (gears {', '.join(st.meshes)})"

    def folding(self, st: GearStep) -> list[tuple[int, Any]]:
        return []

    def turn(self, st: GearStep, place: int, turn: Any) -> GearStep:
        raise TypeError("a geared body's step has no dyad to turn")

    def role(self, st: GearStep) -> Role:
        return Role(places=(st.point,), efforts=())

    def drawing(self, st: GearStep) -> tuple[Primitive, ...]:
        return (Primitive("arc", (st.anchor, st.point)),)
