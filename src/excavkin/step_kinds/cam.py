"""A point of a cam's follower along its guide: ``s = s(θ)``, θ the cam's turn.

The follower translates in a guide on its carrier (points ``l1 → l2``, ``D = l2 − l1``, of
constant length ``d``) and the cam turns on the carrier about ``o``; the cam's turn relative to
the carrier is a linear function of the rotary inputs, ``θ = θ0 + Σ c_i q_i``
(`excavkin.model.gears.GearTrain.turn`), and the lift law ``s(θ)`` (`excavkin.model.cams`)
gives the follower's travel. A point of the follower is, in the guide's frame at ``o``::

    X = o + ((a + s(θ))·D + b·perp(D)) / d

and, with ``ṡ = s'·θ̇`` and ``s̈ = s''·θ̇² + s'·θ̈``, its rates are those of a rack
(`excavkin.step_kinds.rack`).

A table's law compiles (`emit_law`): its knots and its pieces' coefficients are constants
of the plan, and the generated source picks a sample's piece by weights of 1 and 0 from its
turn's test against each knot (arithmetic, no branch and no loop: the vectorised and the
differentiated sources take it as it is), then evaluates the piece's cubic as
`excavkin.model.cams.LiftLaw` does, operation for operation. A law given as a function does
not compile: a plan with it runs in NumPy.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.model.cams import Law, LiftLaw, evaluate, with_lifts
from excavkin.model.entities import Model
from excavkin.step_kinds.base import Emitter, Geometry, Primitive, Role, StepKind, register
from excavkin.step_kinds.dist import Index, at, varies
from excavkin.step_kinds.gear import refuse_ratios, sketch_input_angle
from excavkin.step_kinds.state import Chunk, round_output

#: 2π as the generated source writes it (`excavkin.model.cams.TWO_PI`)
TWO_PI = repr(2.0 * np.pi)


def law_constants(law: Law) -> list[Any]:
    """A table's lift law as constants of the compiled plan, in the order `emit_law` reads
    them: its m knots, then the pieces' coefficients of ``t³`` (one per piece), of ``t²``,
    of ``t`` and of 1.

    Parameters
    ----------
    law : LiftLaw
        A table's law (`excavkin.model.cams.lift_law`), or one with its lifts given
        (`excavkin.model.cams.with_lifts`).

    Returns
    -------
    list
        5·m entries for a law of m pieces (floats, or one value per sample).
    """
    assert isinstance(law, LiftLaw)
    m = law.coef.shape[1]
    pieces = law.pieces if law.pieces is not None else [law.coef[:, k] for k in range(m)]
    out: list[Any] = list(law.knots[:m])
    for j in range(4):
        out += [piece[j] for piece in pieces]
    return out


def varied_law(law: Law, geo: Geometry, cam: str) -> Law:
    """A cam's law with the lifts a family of designs gives (`excavkin.model.cams.with_lifts`),
    or ``law`` itself where none is given.

    Parameters
    ----------
    law : callable
        The cam's lift law.
    geo : Geometry
        The designs' geometry.
    cam : str
        The cam's name.

    Returns
    -------
    callable
    """
    lifts = geo.cam_lifts(cam)
    if lifts is None or not isinstance(law, LiftLaw):
        return law
    return with_lifts(law, lifts)


def law_uncompiled(law: Law, cam: str) -> str | None:
    """Why a cam's step cannot be compiled (None: its law is a table's, which can).

    Parameters
    ----------
    law : callable
        The cam's lift law.
    cam : str
        The cam's name.

    Returns
    -------
    str or None
    """
    if isinstance(law, LiftLaw):
        return None
    return f"cam {cam!r}, whose lift law is a function"


def emit_law(g: Emitter, law: Law, theta: str) -> None:
    """Write the evaluation of a table's lift law at the turn named ``theta``: the names
    ``lift``, ``lift1`` and ``lift2`` get ``s``, ``ds/dθ`` and ``d²s/dθ²``.

    The turn is brought into one turn as `excavkin.model.cams.LiftLaw` does
    (``u = θ − 2π·⌊θ/2π⌋``); the piece is the last whose knot is at most ``u`` (the first
    where none is: numpy's ``searchsorted``, clipped). With ``g_k = [u ≥ knot_k]`` (1 or 0,
    ``g_0 = 1``), which falls with k, piece k's weight ``g_k − g_{k+1}`` is 1 for that piece
    and 0 for every other, and each of its values is ``Σ_k w_k·v_k``: exactly the piece's
    (adding zeros), by arithmetic alone — no branch, which a table of hundreds of rows would
    multiply past what the compiler takes.

    Parameters
    ----------
    g : Emitter
        The source being written.
    law : LiftLaw
        A table's law (its constants: `law_constants`).
    theta : str
        The name of the turn in the source.
    """
    assert isinstance(law, LiftLaw)
    m = law.coef.shape[1]
    g.emit(f"turns = math.floor({theta} / {TWO_PI})", f"u = {theta} - {TWO_PI} * turns")
    g.emit(*(f"kn{k} = {g.const()}" for k in range(m)))
    g.emit(*(f"ge{k} = 1.0 * (u >= kn{k})" for k in range(1, m)))
    weights = ["(1.0 - ge1)" if m > 1 else "1.0"]
    weights += [f"(ge{k} - ge{k + 1})" for k in range(1, m - 1)]
    weights += [f"ge{m - 1}"] if m > 1 else []
    g.emit(*(f"w{k} = {w}" for k, w in enumerate(weights)))
    g.emit("kt = w0 * kn0", *(f"kt = kt + w{k} * kn{k}" for k in range(1, m)))
    for j in (3, 2, 1, 0):
        g.emit(f"c{j} = w0 * {g.const()}")
        g.emit(*(f"c{j} = c{j} + w{k} * {g.const()}" for k in range(1, m)))
    g.emit(
        "t = u - kt",
        "lift = ((c3 * t + c2) * t + c1) * t + c0",
        "lift1 = (3.0 * c3 * t + 2.0 * c2) * t + c1",
        "lift2 = 6.0 * c3 * t + 2.0 * c2",
    )


@dataclass(frozen=True, slots=True, eq=False)
class CamStep:
    """``X = o + ((a + s(θ))·D + b·perp(D))/d``, ``θ = offset + Σ coef[k]·q[inputs[k]]``.

    ``along`` is ``a`` (the sketch's along-guide coordinate less ``s(0)``), ``across`` is
    ``b``; ``cam`` names the pair, ``body`` the follower."""

    point: int
    origin: int
    l1: int
    l2: int
    along: float
    across: float
    offset: float
    inputs: tuple[int, ...]
    coef: tuple[float, ...]
    law: Law
    cam: str
    body: str


@register
class CamKind(StepKind[CamStep]):
    """A follower moved by its cam along its guide."""

    name = "cam"
    record = CamStep
    compiles = True
    iterative = False

    def build(
        self,
        point: int,
        origin: int,
        l1: int,
        l2: int,
        along: float,
        across: float,
        offset: float,
        inputs: tuple[int, ...],
        coef: tuple[float, ...],
        law: Law,
        cam: str,
        body: str,
    ) -> CamStep:
        return CamStep(point, origin, l1, l2, along, across, offset, inputs, coef, law, cam, body)

    def vary(self, st: CamStep, geo: Geometry, names: tuple[str, ...], model: Model) -> CamStep:
        refuse_ratios(geo, st.cam)
        law = varied_law(st.law, geo, st.cam)
        sk = geo.sketch
        (ax, ay), (bx, by) = sk[names[st.l1]], sk[names[st.l2]]
        dx, dy = bx - ax, by - ay
        d = np.hypot(dx, dy)
        px = sk[names[st.point]][0] - sk[names[st.origin]][0]
        py = sk[names[st.point]][1] - sk[names[st.origin]][1]
        along = (px * dx + py * dy) / d - evaluate(law, 0.0, st.cam)[0]
        across = (dx * py - dy * px) / d
        offset: Any = 0.0
        rotary = {dr.name: k for k, dr in enumerate(model.rotary)}
        for i, c in zip(st.inputs, st.coef, strict=True):
            offset = offset - c * sketch_input_angle(sk, model, rotary[model.inputs[i]])
        if not (varies(along) or varies(across) or varies(offset) or law is not st.law):
            return st
        return dataclasses.replace(st, along=along, across=across, offset=offset, law=law)

    def take(self, st: CamStep, index: Index) -> CamStep:
        law = st.law.take(index) if isinstance(st.law, LiftLaw) else st.law
        if not (np.ndim(st.along) or np.ndim(st.across) or np.ndim(st.offset)):
            return st if law is st.law else dataclasses.replace(st, law=law)
        return dataclasses.replace(
            st,
            along=at(st.along, index),
            across=at(st.across, index),
            offset=at(st.offset, index),
            law=law,
        )

    def solve(
        self, c: Chunk, st: CamStep, k: int, order: int, scale: float, newton: bool = True
    ) -> F | None:
        """A point of a cam's follower along its guide: s = s(θ)."""
        x, v, a = c.x, c.v, c.a
        th: Any = st.offset
        for i, co in zip(st.inputs, st.coef, strict=True):
            th = th + co * c.q[i]
        lift, s1, s2 = evaluate(st.law, th, st.cam)
        s = st.along + lift
        b = st.across
        dx, dy = x[st.l2, 0] - x[st.l1, 0], x[st.l2, 1] - x[st.l1, 1]
        inv = 1.0 / np.hypot(dx, dy)
        o = st.origin
        x[st.point, 0] = x[o, 0] + (s * dx - b * dy) * inv
        x[st.point, 1] = x[o, 1] + (s * dy + b * dx) * inv
        if not order:
            return None
        thd: Any = 0.0
        thdd: Any = 0.0
        for i, co in zip(st.inputs, st.coef, strict=True):
            thd = thd + co * c.qd[i]
            thdd = thdd + co * c.qdd[i]
        sd = s1 * thd
        sdd = s2 * thd * thd + s1 * thdd
        vx, vy = v[st.l2, 0] - v[st.l1, 0], v[st.l2, 1] - v[st.l1, 1]
        ax, ay = a[st.l2, 0] - a[st.l1, 0], a[st.l2, 1] - a[st.l1, 1]
        v[st.point, 0] = v[o, 0] + (sd * dx + s * vx - b * vy) * inv
        v[st.point, 1] = v[o, 1] + (sd * dy + s * vy + b * vx) * inv
        a[st.point, 0] = a[o, 0] + (sdd * dx + 2.0 * sd * vx + s * ax - b * ay) * inv
        a[st.point, 1] = a[o, 1] + (sdd * dy + 2.0 * sd * vy + s * ay + b * ax) * inv
        return None

    def nudge(self, c: Chunk, st: CamStep, order: int) -> None:
        round_output(c, st.point, order)

    def transmission(self, st: CamStep) -> int | None:
        return None

    def uncompiled(self, st: CamStep) -> str | None:
        return law_uncompiled(st.law, st.cam)

    def constants(self, st: CamStep) -> list[Any]:
        if not isinstance(st.law, LiftLaw):
            return []
        return [st.along, st.across, st.offset, *st.coef, *law_constants(st.law)]

    def emit(self, g: Emitter, st: CamStep, k: int) -> None:
        if not isinstance(st.law, LiftLaw):
            raise TypeError(f"step {k} ({type(st).__name__}) cannot be compiled: {st.cam!r}")
        p, o, l1, l2 = st.point, st.origin, st.l1, st.l2
        g.emit(f"s = {g.const()}", f"b = {g.const()}", f"th = {g.const()}")
        g.emit("thd = 0.0", "thdd = 0.0")
        for i in st.inputs:
            g.emit(
                f"cam_c = {g.const()}",
                f"th = th + cam_c * q[{i}, i]",
                f"thd = thd + cam_c * qd[{i}, i]",
                f"thdd = thdd + cam_c * qdd[{i}, i]",
            )
        emit_law(g, st.law, "th")
        g.emit(
            "s = s + lift",
            f"dx = X{l2} - X{l1}", f"dy = Y{l2} - Y{l1}",
            "inv = 1.0 / math.sqrt(dx * dx + dy * dy)",
            f"X{p} = X{o} + (s * dx - b * dy) * inv",
            f"Y{p} = Y{o} + (s * dy + b * dx) * inv",
            "sd = lift1 * thd",
            "sdd = lift2 * thd * thd + lift1 * thdd",
            f"rvx = VX{l2} - VX{l1}", f"rvy = VY{l2} - VY{l1}",
            f"rax = AX{l2} - AX{l1}", f"ray = AY{l2} - AY{l1}",
            f"VX{p} = VX{o} + (sd * dx + s * rvx - b * rvy) * inv",
            f"VY{p} = VY{o} + (sd * dy + s * rvy + b * rvx) * inv",
            f"AX{p} = AX{o} + (sdd * dx + 2.0 * sd * rvx + s * rax - b * ray) * inv",
            f"AY{p} = AY{o} + (sdd * dy + 2.0 * sd * rvy + s * ray + b * rax) * inv",
        )  # fmt: skip

    def describe(self, st: CamStep, names: tuple[str, ...]) -> str:
        terms = " ".join(
            f"{'+' if co >= 0 else '−'} {abs(co):.6g}·q{i}"
            for i, co in zip(st.inputs, st.coef, strict=True)
        )
        return (
            f"cam      {names[st.point]} along {names[st.l1]}→{names[st.l2]} from "
            f"{names[st.origin]}: body {st.body!r} lifted by {st.cam!r} "
            f"(s = s(θ), θ = θ0 {terms}, "
            + (
                f"{st.law.coef.shape[1]} spline pieces)"
                if isinstance(st.law, LiftLaw)
                else "a function)"
            )
        )

    def label(self, st: CamStep, names: tuple[str, ...], k: int) -> str:
        return f"step {k + 1} (cam {st.cam})"

    def folding(self, st: CamStep) -> list[tuple[int, Any]]:
        return []

    def turn(self, st: CamStep, place: int, turn: Any) -> CamStep:
        raise TypeError("a cam's step has no dyad to turn")

    def role(self, st: CamStep) -> Role:
        return Role(places=(st.point,), efforts=())

    def drawing(self, st: CamStep) -> tuple[Primitive, ...]:
        return (
            Primitive("slide", (st.point, st.l1, st.l2)),
            Primitive("profile", (st.origin, st.point)),
        )
