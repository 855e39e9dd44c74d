"""A point of an oscillating cam follower about its pivot: ``φ = φ0 + Σ a_i q_i + ψ(θ)``.

The follower turns about its pivot on the carrier by the lift law ``ψ(θ)`` of the cam's turn θ
relative to the carrier (`excavkin.model.cams`), on top of the carrier's own turn; both the
carrier's angle and the cam's turn are linear functions of the rotary inputs
(`excavkin.model.gears`), ``Σ a_i q_i`` and ``θ = θ0 + Σ c_i q_i``. A point of the follower is
``pivot + r·(cos φ, sin φ)``, with::

    φ̇ = Σ a_i q̇_i + ψ'·θ̇,    φ̈ = Σ a_i q̈_i + ψ''·θ̇² + ψ'·θ̈

A table's law compiles as a translating follower's does (`excavkin.step_kinds.cam.emit_law`);
a law given as a function runs in NumPy.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.model.cams import Law, LiftLaw, evaluate
from excavkin.model.entities import Model
from excavkin.step_kinds.base import Emitter, Geometry, Primitive, Role, StepKind, register
from excavkin.step_kinds.cam import emit_law, law_constants, law_uncompiled, varied_law
from excavkin.step_kinds.dist import Index, at, varies
from excavkin.step_kinds.gear import refuse_ratios, sketch_input_angle
from excavkin.step_kinds.state import Chunk, round_output


@dataclass(frozen=True, slots=True, eq=False)
class CamRockerStep:
    """``point = pivot + radius·(cos φ, sin φ)``, ``φ = offset + Σ carrier[k]·q + ψ(θ)``,
    ``θ = turn0 + Σ turn[k]·q`` over ``q = q[inputs[k]]``; ``cam`` names the pair, ``body``
    the follower."""

    point: int
    pivot: int
    radius: float
    offset: float
    turn0: float
    inputs: tuple[int, ...]
    carrier: tuple[float, ...]
    turn: tuple[float, ...]
    law: Law
    cam: str
    body: str


@register
class CamRockerKind(StepKind[CamRockerStep]):
    """An oscillating follower moved by its cam about its pivot."""

    name = "cam rocker"
    record = CamRockerStep
    compiles = True
    iterative = False

    def build(
        self,
        point: int,
        pivot: int,
        radius: float,
        offset: float,
        turn0: float,
        inputs: tuple[int, ...],
        carrier: tuple[float, ...],
        turn: tuple[float, ...],
        law: Law,
        cam: str,
        body: str,
    ) -> CamRockerStep:
        return CamRockerStep(
            point, pivot, radius, offset, turn0, inputs, carrier, turn, law, cam, body
        )

    def vary(
        self, st: CamRockerStep, geo: Geometry, names: tuple[str, ...], model: Model
    ) -> CamRockerStep:
        refuse_ratios(geo, st.cam)
        law = varied_law(st.law, geo, st.cam)
        p, o = names[st.point], names[st.pivot]
        radius = geo.distance(st.body, p, o)
        sk = geo.sketch
        offset: Any = np.arctan2(sk[p][1] - sk[o][1], sk[p][0] - sk[o][0])
        offset = offset - evaluate(law, 0.0, st.cam)[0]
        turn0: Any = 0.0
        rotary = {d.name: k for k, d in enumerate(model.rotary)}
        for i, a, c in zip(st.inputs, st.carrier, st.turn, strict=True):
            q0 = sketch_input_angle(sk, model, rotary[model.inputs[i]])
            offset = offset - a * q0
            turn0 = turn0 - c * q0
        if not (varies(radius) or varies(offset) or varies(turn0) or law is not st.law):
            return st
        return dataclasses.replace(st, radius=radius, offset=offset, turn0=turn0, law=law)

    def take(self, st: CamRockerStep, index: Index) -> CamRockerStep:
        law = st.law.take(index) if isinstance(st.law, LiftLaw) else st.law
        if not (np.ndim(st.radius) or np.ndim(st.offset) or np.ndim(st.turn0)):
            return st if law is st.law else dataclasses.replace(st, law=law)
        return dataclasses.replace(
            st,
            radius=at(st.radius, index),
            offset=at(st.offset, index),
            turn0=at(st.turn0, index),
            law=law,
        )

    def solve(
        self, c: Chunk, st: CamRockerStep, k: int, order: int, scale: float, newton: bool = True
    ) -> F | None:
        """A point of an oscillating follower about its pivot: φ = φ0 + Σ a q + ψ(θ)."""
        x, v, a = c.x, c.v, c.a
        phi: Any = st.offset
        th: Any = st.turn0
        for i, ca, ct in zip(st.inputs, st.carrier, st.turn, strict=True):
            phi = phi + ca * c.q[i]
            th = th + ct * c.q[i]
        psi, p1, p2 = evaluate(st.law, th, st.cam)
        phi = phi + psi
        r = st.radius
        cs, sn = np.cos(phi), np.sin(phi)
        x[st.point, 0] = x[st.pivot, 0] + r * cs
        x[st.point, 1] = x[st.pivot, 1] + r * sn
        if not order:
            return None
        w: Any = 0.0
        e: Any = 0.0
        thd: Any = 0.0
        thdd: Any = 0.0
        for i, ca, ct in zip(st.inputs, st.carrier, st.turn, strict=True):
            w = w + ca * c.qd[i]
            e = e + ca * c.qdd[i]
            thd = thd + ct * c.qd[i]
            thdd = thdd + ct * c.qdd[i]
        w = w + p1 * thd
        e = e + p2 * thd * thd + p1 * thdd
        v[st.point, 0] = v[st.pivot, 0] - r * w * sn
        v[st.point, 1] = v[st.pivot, 1] + r * w * cs
        a[st.point, 0] = a[st.pivot, 0] - r * (e * sn + w * w * cs)
        a[st.point, 1] = a[st.pivot, 1] + r * (e * cs - w * w * sn)
        return None

    def nudge(self, c: Chunk, st: CamRockerStep, order: int) -> None:
        round_output(c, st.point, order)

    def transmission(self, st: CamRockerStep) -> int | None:
        return None

    def uncompiled(self, st: CamRockerStep) -> str | None:
        return law_uncompiled(st.law, st.cam)

    def constants(self, st: CamRockerStep) -> list[Any]:
        if not isinstance(st.law, LiftLaw):
            return []
        pairs = [c for ca, ct in zip(st.carrier, st.turn, strict=True) for c in (ca, ct)]
        return [st.radius, st.offset, st.turn0, *pairs, *law_constants(st.law)]

    def emit(self, g: Emitter, st: CamRockerStep, k: int) -> None:
        if not isinstance(st.law, LiftLaw):
            raise TypeError(f"step {k} ({type(st).__name__}) cannot be compiled: {st.cam!r}")
        p, o = st.point, st.pivot
        g.emit(f"r = {g.const()}", f"phi = {g.const()}", f"th = {g.const()}")
        g.emit("w = 0.0", "e = 0.0", "thd = 0.0", "thdd = 0.0")
        for i in st.inputs:
            g.emit(
                f"cam_a = {g.const()}", f"cam_c = {g.const()}",
                f"phi = phi + cam_a * q[{i}, i]", f"th = th + cam_c * q[{i}, i]",
                f"w = w + cam_a * qd[{i}, i]", f"e = e + cam_a * qdd[{i}, i]",
                f"thd = thd + cam_c * qd[{i}, i]", f"thdd = thdd + cam_c * qdd[{i}, i]",
            )  # fmt: skip
        emit_law(g, st.law, "th")
        g.emit(
            "phi = phi + lift",
            "cs = math.cos(phi)", "sn = math.sin(phi)",
            f"X{p} = X{o} + r * cs", f"Y{p} = Y{o} + r * sn",
            "w = w + lift1 * thd",
            "e = e + lift2 * thd * thd + lift1 * thdd",
            f"VX{p} = VX{o} - r * w * sn", f"VY{p} = VY{o} + r * w * cs",
            f"AX{p} = AX{o} - r * (e * sn + w * w * cs)",
            f"AY{p} = AY{o} + r * (e * cs - w * w * sn)",
        )  # fmt: skip

    def describe(self, st: CamRockerStep, names: tuple[str, ...]) -> str:
        law = (
            f"{st.law.coef.shape[1]} spline pieces" if isinstance(st.law, LiftLaw) else "a function"
        )
        return (
            f"cam      {names[st.point]} about {names[st.pivot]}: body {st.body!r} swung by "
            f"{st.cam!r} (φ = φ0 + ψ(θ), {law}, r = {float(np.max(st.radius)):.6g} m)"
        )

    def label(self, st: CamRockerStep, names: tuple[str, ...], k: int) -> str:
        return f"step {k + 1} (cam {st.cam})"

    def folding(self, st: CamRockerStep) -> list[tuple[int, Any]]:
        return []

    def turn(self, st: CamRockerStep, place: int, turn: Any) -> CamRockerStep:
        raise TypeError("a cam's step has no dyad to turn")

    def role(self, st: CamRockerStep) -> Role:
        return Role(places=(st.point,), efforts=())

    def drawing(self, st: CamRockerStep) -> tuple[Primitive, ...]:
        return (Primitive("arc", (st.pivot, st.point)),)
