"""Batched Newton–Raphson for the points no closed-form step reaches.

Unknowns are the group's point coordinates; equations are the constraints of
`excavkin.step_kinds.constraints` (distances, rigid frames, point-on-line, driver angles). Each
iteration solves ``J·Δ = −Φ`` for every sample at once. Velocities and accelerations solve the
same Jacobian with the differentiated constraints (DESIGN.md §4)::

    J·ẋ = −Φ̇|ẋ_group=0          J·ẍ = −Φ̈|ẍ_group=0

where ``Φ̇|ẋ_group=0`` is the time derivative of Φ with the group's own velocities set to zero
(the contribution of known points and driver rates), and likewise for Φ̈.

Arrays keep the batch axis last, as the rest of the solve does: the residual is (m, n), the
Jacobian (m, m, n), and every linear solve goes through
`Factors` (one factorisation gives the solution and
the distance from singular; the rates solve both orders with it).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.step_kinds.base import kind_of
from excavkin.step_kinds.constraints import (
    CAngle,
    CDist,
    CFrame,
    CLine,
    Constraint,
    CRope,
    GroupDyad,
)
from excavkin.step_kinds.rope_path import rope_path
from excavkin.step_kinds.small_systems import Factors
from excavkin.step_kinds.state import Chunk, Code, dist, flag

if TYPE_CHECKING:
    from excavkin.step_kinds.newton_group import NewtonGroup

Grad = list[tuple[int, F | float, F | float]]


def _cross(ax: F, ay: F, bx: F, by: F) -> F:
    return ax * by - ay * bx


def _equations(
    c: Chunk, g: NewtonGroup, x: F, v: F | None, a: F | None, want: frozenset[int] = frozenset()
) -> Iterator[tuple[F, Grad, F | None, F | None]]:
    """Yield, per equation: residual, gradient per point of ``want`` (the others are not
    computed), Φ̇ and Φ̈ (when v, a given)."""
    zero = np.zeros(x.shape[-1], dtype=x.dtype)
    for con in g.constraints:
        if isinstance(con, CDist):
            d, dd, ddd = dist(c, con.dist)
            rx, ry = x[con.p, 0] - x[con.q, 0], x[con.p, 1] - x[con.q, 1]
            r2 = rx * rx + ry * ry
            f = r2 - d * d
            if c.nudge is not None:  # the rounding of the difference, emulated
                f = f + c.nudge * (r2 + d * d)
            grad: Grad = []
            if want:
                tx, ty = 2 * rx, 2 * ry
                if con.p in want:
                    grad.append((con.p, tx, ty))
                if con.q in want:
                    grad.append((con.q, -tx, -ty))
            f1 = f2 = None
            if v is not None:
                wx, wy = v[con.p, 0] - v[con.q, 0], v[con.p, 1] - v[con.q, 1]
                f1 = 2 * (rx * wx + ry * wy) - 2 * d * dd + zero
                if a is not None:
                    ax_, ay_ = a[con.p, 0] - a[con.q, 0], a[con.p, 1] - a[con.q, 1]
                    f2 = (
                        2 * (rx * ax_ + ry * ay_)
                        + 2 * (wx * wx + wy * wy)
                        - 2 * (dd * dd + d * ddd)
                        + zero
                    )
            yield f, grad, f1, f2
        elif isinstance(con, CFrame):
            s, t = con.s, con.t
            gx: Grad = [(con.p, 1.0, 0.0), (con.a, s - 1.0, -t), (con.b, -s, t)]
            gy: Grad = [(con.p, 0.0, 1.0), (con.a, t, s - 1.0), (con.b, -t, -s)]
            for comp, gr in ((0, gx), (1, gy)):
                yield (
                    _frame(x, con, comp),
                    [e for e in gr if e[0] in want],
                    None if v is None else _frame(v, con, comp),
                    None if a is None else _frame(a, con, comp),
                )
        elif isinstance(con, CLine):
            ux = x[con.l2, 0] - x[con.l1, 0]
            uy = x[con.l2, 1] - x[con.l1, 1]
            gx_, gy_ = x[con.p, 0] - x[con.l1, 0], x[con.p, 1] - x[con.l1, 1]
            f = _cross(ux, uy, gx_, gy_)
            grad = []
            if con.p in want:
                grad.append((con.p, -uy, ux))
            if con.l2 in want:
                grad.append((con.l2, gy_, -gx_))
            if con.l1 in want:
                grad.append((con.l1, uy - gy_, gx_ - ux))
            f1 = f2 = None
            if v is not None:
                udx, udy = v[con.l2, 0] - v[con.l1, 0], v[con.l2, 1] - v[con.l1, 1]
                gdx, gdy = v[con.p, 0] - v[con.l1, 0], v[con.p, 1] - v[con.l1, 1]
                f1 = _cross(udx, udy, gx_, gy_) + _cross(ux, uy, gdx, gdy)
                if a is not None:
                    uax, uay = a[con.l2, 0] - a[con.l1, 0], a[con.l2, 1] - a[con.l1, 1]
                    gax, gay = a[con.p, 0] - a[con.l1, 0], a[con.p, 1] - a[con.l1, 1]
                    f2 = (
                        _cross(uax, uay, gx_, gy_)
                        + 2 * _cross(udx, udy, gdx, gdy)
                        + _cross(ux, uy, gax, gay)
                    )
            yield f, grad, f1, f2
        elif isinstance(con, CRope):
            yield _rope(c, con, x, v, a, want)
        else:
            yield _angle(c, con, x, v, a, want)


def _rope(
    c: Chunk, con: CRope, x: F, v: F | None, a: F | None, want: frozenset[int]
) -> tuple[F, Grad, F | None, F | None]:
    """``L² − d²`` of a rope over sheaves (`excavkin.step_kinds.rope_path`), its gradient
    ``2L·(u_{k−1} − u_k)`` per path point, and its rates ``2L·L̇ − 2d·ḋ`` and
    ``2L̇² + 2L·L̈ − 2(ḋ² + d·d̈)``, L̈ = Σ u_k·D̈_k + Σ (n_k·Ḋ_k)²/ℓ_k."""
    d, dd, ddd = dist(c, con.dist)
    pts = con.points
    geo = rope_path([(x[p, 0], x[p, 1]) for p in pts], con.signed, con.wraps0)
    length = geo.length
    zero = np.zeros(x.shape[-1], dtype=x.dtype)
    f = length * length - d * d + zero
    if c.nudge is not None:  # the rounding of the difference, emulated
        f = f + c.nudge * (length * length + d * d)
    grad: Grad = []
    if want:
        acc: dict[int, tuple[Any, Any]] = {}
        last = len(pts) - 1
        for k, p in enumerate(pts):
            if p not in want:
                continue
            gx = (geo.ux[k - 1] if k else 0.0) - (geo.ux[k] if k < last else 0.0)
            gy = (geo.uy[k - 1] if k else 0.0) - (geo.uy[k] if k < last else 0.0)
            ox, oy = acc.get(p, (0.0, 0.0))
            acc[p] = (ox + 2 * length * gx, oy + 2 * length * gy)
        grad = [(p, gx, gy) for p, (gx, gy) in acc.items()]
    f1 = f2 = None
    if v is not None:
        vel = [(v[p, 0], v[p, 1]) for p in pts]
        rate = geo.rate(vel)
        f1 = 2 * length * rate - 2 * d * dd + zero
        if a is not None:
            accel = geo.rate([(a[p, 0], a[p, 1]) for p in pts]) + geo.curvature(vel)
            f2 = 2 * rate * rate + 2 * length * accel - 2 * (dd * dd + d * ddd) + zero
    return f, grad, f1, f2


def _frame(arr: F, con: CFrame, comp: int) -> F:
    """Residual of ``p = a + s·(b − a) + t·perp(b − a)``; linear, so any order alike."""
    wx = arr[con.b, 0] - arr[con.a, 0]
    wy = arr[con.b, 1] - arr[con.a, 1]
    if comp == 0:
        out = arr[con.p, 0] - arr[con.a, 0] - con.s * wx + con.t * wy
    else:
        out = arr[con.p, 1] - arr[con.a, 1] - con.s * wy - con.t * wx
    return out  # type: ignore[no-any-return]


def _angle(
    c: Chunk, con: CAngle, x: F, v: F | None, a: F | None, want: frozenset[int]
) -> tuple[F, Grad, F | None, F | None]:
    q, qd, qdd = c.q[con.input], c.qd[con.input], c.qdd[con.input]
    cs, sn = np.cos(q), np.sin(q)
    zero = np.zeros(q.shape)
    if con.ref is None:
        vx, vy = 1.0 + zero, zero
    else:
        vx = x[con.ref[1], 0] - x[con.ref[0], 0]
        vy = x[con.ref[1], 1] - x[con.ref[0], 1]
    ex, ey = cs * vx - sn * vy, sn * vx + cs * vy
    dpx, dpy = x[con.p, 0] - x[con.pivot, 0], x[con.p, 1] - x[con.pivot, 1]
    f = _cross(ex, ey, dpx, dpy)
    grad: Grad = []
    if con.p in want:
        grad.append((con.p, -ey, ex))
    if con.pivot in want:
        grad.append((con.pivot, ey, -ex))
    if con.ref is not None and (con.ref[0] in want or con.ref[1] in want):
        gvx, gvy = cs * dpy - sn * dpx, -sn * dpy - cs * dpx
        if con.ref[1] in want:
            grad.append((con.ref[1], gvx, gvy))
        if con.ref[0] in want:
            grad.append((con.ref[0], -gvx, -gvy))
    f1 = f2 = None
    if v is not None:
        if con.ref is None:
            vdx = vdy = zero
        else:
            vdx = v[con.ref[1], 0] - v[con.ref[0], 0]
            vdy = v[con.ref[1], 1] - v[con.ref[0], 1]
        rvdx, rvdy = cs * vdx - sn * vdy, sn * vdx + cs * vdy
        edx, edy = rvdx - qd * ey, rvdy + qd * ex
        ddx, ddy = v[con.p, 0] - v[con.pivot, 0], v[con.p, 1] - v[con.pivot, 1]
        f1 = _cross(edx, edy, dpx, dpy) + _cross(ex, ey, ddx, ddy)
        if a is not None:
            if con.ref is None:
                vax = vay = zero
            else:
                vax = a[con.ref[1], 0] - a[con.ref[0], 0]
                vay = a[con.ref[1], 1] - a[con.ref[0], 1]
            eax = cs * vax - sn * vay - 2 * qd * rvdy - qdd * ey - qd * qd * ex
            eay = sn * vax + cs * vay + 2 * qd * rvdx + qdd * ex - qd * qd * ey
            dax, day = a[con.p, 0] - a[con.pivot, 0], a[con.p, 1] - a[con.pivot, 1]
            f2 = (
                _cross(eax, eay, dpx, dpy)
                + 2 * _cross(edx, edy, ddx, ddy)
                + _cross(ex, ey, dax, day)
            )
    return f, grad, f1, f2


def tangents(c: Chunk, g: NewtonGroup, values: tuple[F, F, F]) -> None:
    """The group's derivatives with respect to the parameters, by the implicit function
    theorem, for a chunk of dual numbers (`excavkin.kinematics.dual`) whose known points
    already carry theirs.

    With the group's values (``values``: x, v, a of every point, plain arrays) and zero
    tangents, the tangent of each constraint level is what the group's own tangent must cancel:
    J·dx = −dΦ, then J·dv = −dΦ̇, then J·da = −dΦ̈, one Jacobian for all three.
    """
    pts = list(g.points)
    xv, vv, av = values
    for arr, solved in ((c.x, xv), (c.v, vv), (c.a, av)):
        for p in pts:
            arr[p] = solved[p]  # the solution's values, no tangent yet

    def val(v: Any) -> Any:
        return getattr(v, "val", v)

    plain = Chunk(
        xv, vv, av, val(c.q), c.qd, c.qdd, val(c.trans), c.status, c.failed,
        c.close_tol, c.singular_tol,
    )  # fmt: skip
    # the group's own constants at their values: its Jacobian is a plain one
    cons: list[Any] = []
    for con in g.constraints:
        if isinstance(con, CDist | CRope):
            d = con.dist
            con = replace(con, dist=replace(d, value=val(d.value), scale=val(d.scale)))
            if isinstance(con, CRope):  # its sheave radii, where they are parameters
                con = replace(con, signed=tuple(val(r) for r in con.signed))
        elif isinstance(con, CFrame):
            con = replace(con, s=val(con.s), t=val(con.t))
        cons.append(con)
    _, jac, _, _ = _system(plain, replace(g, constraints=tuple(cons)))
    assert jac is not None
    lu = Factors(jac, overwrite=True)
    sing = ~(np.abs(lu.ratio) >= c.singular_tol**2)
    m = c.x.tan.shape[0]  # type: ignore[attr-defined]
    for level, arr in enumerate((c.x, c.v, c.a)):
        rows = [
            eq[0] if level == 0 else eq[level + 1]
            for eq in _equations(c, g, c.x, c.v if level else None, c.a if level == 2 else None)
        ]
        n = c.x.shape[-1]
        rhs = np.zeros((len(rows), m, n))
        for r, f in enumerate(rows):
            tan = getattr(f, "tan", None)
            if tan is not None and np.ndim(tan):
                rhs[r] = np.broadcast_to(tan, (m, n))
        step = -lu.solve(rhs)  # (2·points, m, n)
        step[..., sing] = np.nan
        for j, p in enumerate(pts):
            arr.tan[:, p, 0] = step[2 * j]  # type: ignore[attr-defined]
            arr.tan[:, p, 1] = step[2 * j + 1]  # type: ignore[attr-defined]


def _system(
    c: Chunk, g: NewtonGroup, *, jacobian: bool = True, rates: int = 0
) -> tuple[F, F | None, F | None, F | None]:
    """Residual (m, n), Jacobian (m, m, n) when ``jacobian``, and with ``rates`` ≥ 1 the
    right-hand side of the velocities (Φ̇ with the group's own rates zeroed), with 2 also that
    of the accelerations; m is twice the group's point count, batch axis last."""
    n = c.x.shape[-1]
    col = {p: 2 * k for k, p in enumerate(g.points)}
    m = 2 * len(g.points)
    dt = c.x.dtype
    jac = np.zeros((m, m, n), dtype=dt) if jacobian else None
    res = np.empty((m, n), dtype=dt)
    r1 = np.empty((m, n), dtype=dt) if rates else None
    r2 = np.empty((m, n), dtype=dt) if rates == 2 else None
    want = frozenset(col) if jacobian else frozenset()
    eqs = _equations(c, g, c.x, c.v if rates else None, c.a if rates == 2 else None, want)
    for row, (f, grad, f1, f2) in enumerate(eqs):
        res[row] = f
        if jac is not None:
            for p, gx, gy in grad:
                jac[row, col[p]] += gx
                jac[row, col[p] + 1] += gy
        if r1 is not None:
            r1[row] = f1  # type: ignore[assignment]
        if r2 is not None:
            r2[row] = f2  # type: ignore[assignment]
    return res, jac, r1, r2


#: once every sample's last Newton step is below this fraction of the size, later steps reuse
#: the last factorisation (chord steps), as long as each shrinks by `CHORD_RATE` or more
CHORD_FROM = 1e-4
CHORD_RATE = 0.1
#: the samples still moving are copied out (the others leave the iteration) once they are
#: fewer than this fraction of those iterated; until then the converged ones are held still
SHRINK = 0.75


def newton_positions(c: Chunk, g: NewtonGroup, k: int, scale: float, max_iter: int = 50) -> None:
    """Newton iterations from the current ``c.x`` of the group's points, each of the group's
    dyads then kept on its side (`keep_sides`); samples whose residual stays above
    1e-10·scale² are marked as not converging and their points set to NaN.

    Converged (and singular) samples leave the iteration: each pass works on the samples still
    moving, so a batch costs what its slowest samples need, not every sample that many passes.
    Close to the solution, where a step's error is far below the step itself, the Jacobian
    factored last serves again (a chord step: a residual and a solve, no factorisation); a
    chord step that does not shrink fast is not taken, and the next pass factors afresh. The
    root and the test of convergence are Newton's own.
    """
    _iterate(c, g, scale, max_iter)
    keep_sides(c, g, scale, max_iter)
    res, _, _, _ = _system(c, g, jacobian=False)
    bad = ~(np.max(np.abs(res), axis=0) <= 1e-10 * scale * scale)
    flag(c, bad, Code.NO_CONVERGENCE, k)
    for p in g.points:
        c.x[p][:, bad] = np.nan


def side(x: F, d: GroupDyad) -> F:
    """cross(B − A, P − A) of a group's dyad: positive with P left of A→B; x (n_points, 2, n)."""
    ex, ey = x[d.b, 0] - x[d.a, 0], x[d.b, 1] - x[d.a, 1]
    return _cross(ex, ey, x[d.point, 0] - x[d.a, 0], x[d.point, 1] - x[d.a, 1])


def wrong_side(x: F, d: GroupDyad) -> NDArray[np.bool_]:
    """Where a group's dyad lies strictly on the other side of A→B than its ``sign`` keeps (a
    flat one, or a sign of 0, is on neither)."""
    return side(x, d) * d.sign < 0  # type: ignore[no-any-return]


def keep_sides(c: Chunk, g: NewtonGroup, scale: float, max_iter: int = 50) -> None:
    """Each of the group's dyads on the side of its base its ``sign`` keeps (the sketch's, or
    per sample the smooth continuation's), as a closed-form dyad is.

    Where the first dyad (in solve order) on the wrong side is found, P moves to its mirror
    image in the line A→B — another solution of the dyad's two distances, the rest of the group
    unmoved — and the samples so moved are iterated again by Newton: a dyad built on P then
    settles from where it was, and is looked at in the next pass. A group whose dyads hang on
    one another takes a pass per dyad at most; a sample still on a wrong side after them is
    left so, and the branch check reports it.
    """
    for _ in range(len(g.dyads)):
        moved = np.zeros(c.x.shape[-1], dtype=bool)
        for d in g.dyads:
            here = wrong_side(c.x, d) & ~moved
            if not here.any():
                continue
            p, a, b = c.x[d.point][:, here], c.x[d.a][:, here], c.x[d.b][:, here]
            e, r = b - a, p - a
            e2 = e[0] * e[0] + e[1] * e[1]
            t = (r[0] * e[0] + r[1] * e[1]) / np.where(e2 > 0, e2, np.nan)
            mirror = a + 2.0 * t * e - r
            c.x[d.point][:, here] = np.where(np.isfinite(mirror), mirror, p)
            moved |= here
        idx = np.flatnonzero(moved)
        if not idx.size:
            return
        sub = _positions_at(c, idx)
        _iterate(sub, kind_of(g).take(g, idx), scale, max_iter)  # type: ignore[arg-type]
        for p in g.points:
            c.x[p][:, idx] = sub.x[p]


def _iterate(c: Chunk, g: NewtonGroup, scale: float, max_iter: int) -> None:
    """The Newton iterations of `newton_positions`, in place in ``c.x``."""
    pts = list(g.points)
    n = c.x.shape[-1]
    live = np.arange(n)  # the samples in ``sub``, as indices of ``c``
    sub = c
    # converged at 1e-14 of the size in double precision, proportionally finer in a wider one
    small = 1e-14 * scale * float(np.finfo(c.x.dtype).eps / np.finfo(np.float64).eps)
    group = g
    lu: Factors | None = None
    last = np.full(n, np.inf)  # each sample's last step
    moving = np.ones(n, dtype=bool)  # the samples of ``sub`` still iterated
    for _ in range(max_iter):
        chord = lu is not None and bool(np.all(last[moving] <= CHORD_FROM * scale))
        if chord:
            res = _system(sub, group, jacobian=False)[0]
        else:
            res, jac, _, _ = _system(sub, group)
            assert jac is not None
            lu = Factors(jac, overwrite=True)
        assert lu is not None
        sing = ~(np.abs(lu.ratio) >= 1e-13)
        step = lu.solve(res)  # J·step = Φ: the move is −step
        hold = sing | ~moving
        step[:, hold] = 0.0
        size = np.max(np.abs(step), axis=0)
        if chord:
            slow = ~(size <= CHORD_RATE * last) & ~hold
            if slow.any():
                step[:, slow] = 0.0
                size[slow] = np.inf  # still moving
                lu = None
        for j, p in enumerate(pts):
            sub.x[p] -= step[2 * j : 2 * j + 2]
        moving &= ~(size <= small) & ~sing
        last = size
        count = np.count_nonzero(moving)
        if count == 0:
            break
        if count < SHRINK * moving.size:
            if sub is not c:  # the samples leaving, back into the chunk
                done = ~moving
                for p in pts:
                    c.x[p][:, live[done]] = sub.x[p][:, done]
            live = live[moving]
            sub = _positions_at(sub, moving)
            group = kind_of(g).take(g, live)  # type: ignore[assignment]
            last = last[moving]
            if lu is not None:
                lu = lu.at(moving)
            moving = np.ones(live.size, dtype=bool)
    if sub is not c:
        for p in pts:
            c.x[p][:, live] = sub.x[p]


def _positions_at(c: Chunk, idx: NDArray[Any]) -> Chunk:
    """A copy of the chunk's positions and inputs at samples ``idx`` (indices or a mask), for
    the Newton iteration, which reads nothing else (an input held for all samples, one column
    wide, stays as it is)."""
    n = c.x.shape[-1]

    def take(arr: F) -> F:
        if arr.shape[-1] != n:
            return arr
        # ``take`` and ``compress`` keep the batch axis last in memory (a fancy index would not)
        if idx.dtype == bool:
            return np.compress(idx, arr, axis=-1)
        return np.take(arr, idx, axis=-1)

    x = take(c.x)
    # velocities and accelerations are not read by a position pass: x stands in for them
    return Chunk(
        x, x, x, take(c.q), take(c.qd), take(c.qdd), c.trans, c.status, c.failed,
        c.close_tol, c.singular_tol, nudge=None if c.nudge is None else take(c.nudge),
    )  # fmt: skip


def newton_rates(c: Chunk, g: NewtonGroup, k: int) -> F:
    """Velocities and accelerations of the group's points, by one factorisation of the
    Jacobian; returns the sign of its determinant."""
    pts = list(g.points)
    for p in pts:
        c.v[p] = 0.0
        c.a[p] = 0.0
    _, jac, r1, _ = _system(c, g, rates=1)
    assert jac is not None and r1 is not None
    lu = Factors(jac, overwrite=True)
    sing = ~(np.abs(lu.ratio) >= c.singular_tol**2)
    flag(c, sing, Code.SINGULAR, k)
    vel = lu.solve(r1)
    vel[:, sing] = np.nan
    for j, p in enumerate(pts):
        c.v[p] = -vel[2 * j : 2 * j + 2]
    _, _, _, r2 = _system(c, g, jacobian=False, rates=2)
    assert r2 is not None
    acc = lu.solve(r2)
    acc[:, sing] = np.nan
    for j, p in enumerate(pts):
        c.a[p] = -acc[2 * j : 2 * j + 2]
    ratio = lu.ratio.astype(np.float64)
    if c.near is not None:
        np.minimum(c.near, np.abs(ratio), out=c.near)
    return np.sign(ratio)  # type: ignore[no-any-return]


def ropes_on_sheaves(c: Chunk, g: NewtonGroup, k: int) -> None:
    """Flag the samples where a rope of the group would leave a sheave: a wrap below zero
    (the rope would not touch it, and its length is not the one solved for) or a segment with
    no tangent; their points are NaN."""
    bad = np.zeros(c.x.shape[-1], dtype=bool)
    for con in g.constraints:
        if not isinstance(con, CRope):
            continue
        x = c.x
        with np.errstate(invalid="ignore"):
            geo = rope_path([(x[p, 0], x[p, 1]) for p in con.points], con.signed, con.wraps0)
            for w in geo.wraps:
                bad |= ~(np.asarray(w) >= -1e-12)
            for ell in geo.ell:
                bad |= ~np.isfinite(ell)
    bad &= c.status == 0
    if bad.any():
        flag(c, bad, Code.ROPE_OFF_SHEAVE, k)
        for p in g.points:
            c.x[p][:, bad] = np.nan


def rotary_branch_ok(c: Chunk, g: NewtonGroup) -> NDArray[np.bool_]:
    """True where every driver-angle constraint points its body the driven way (not θ + π)."""
    ok = np.ones(c.x.shape[-1], dtype=bool)
    for con in g.constraints:
        if isinstance(con, CAngle):
            q = c.q[con.input]
            if con.ref is None:
                vx, vy = np.ones_like(q), np.zeros_like(q)
            else:
                vx = c.x[con.ref[1], 0] - c.x[con.ref[0], 0]
                vy = c.x[con.ref[1], 1] - c.x[con.ref[0], 1]
            cs, sn = np.cos(q), np.sin(q)
            ex, ey = cs * vx - sn * vy, sn * vx + cs * vy
            dpx = c.x[con.p, 0] - c.x[con.pivot, 0]
            dpy = c.x[con.p, 1] - c.x[con.pivot, 1]
            ok &= ex * dpx + ey * dpy > 0
    return ok


# ---- a pose out of reach: which constraint cannot be met, and by how much

#: a group whose least-squares residual stalls with a constraint missed by more than this
#: fraction of the size cannot be reached; below it, Newton merely did not get there
REACH_TOL = 1e-9
#: Levenberg–Marquardt passes, at most, of each stage of the diagnosis
REACH_ITER = 200
#: weight of the constraints kept while the one that cannot be met is pushed to its limit
REACH_WEIGHT = 1e3
#: rounds of the method of multipliers that meet the other constraints
REACH_ROUNDS = 4


def _rows(g: NewtonGroup) -> NDArray[np.intp]:
    """The constraint of each of the group's equations (a frame gives two), shape (m,)."""
    return np.array(
        [
            k
            for k, con in enumerate(g.constraints)
            for _ in range(2 if isinstance(con, CFrame) else 1)
        ],
        dtype=np.intp,
    )


def _reference(x: F, con: CAngle, q: F) -> tuple[F, F]:
    """The direction a driver-angle constraint drives its body (not unit), shape (n,) each."""
    if con.ref is None:
        vx, vy = np.ones_like(q), np.zeros_like(q)
    else:
        vx = x[con.ref[1], 0] - x[con.ref[0], 0]
        vy = x[con.ref[1], 1] - x[con.ref[0], 1]
    cs, sn = np.cos(q), np.sin(q)
    return cs * vx - sn * vy, sn * vx + cs * vy


def _lengths(c: Chunk, g: NewtonGroup, *, jacobian: bool = True) -> tuple[F, F | None]:
    """The group's equations as lengths (m): residual (m, n) and, with ``jacobian``, its
    Jacobian (m, m, n).

    ``|p − q|² − d²`` over ``|p − q| + d`` is ``|p − q| − d``; a point-on-line cross product
    over the line's length is the point's distance from it; a frame's equations are lengths
    already. A driver angle is the signed chord ``2·|p − pivot|·sin(φ/2)`` between the point
    and where the driven direction puts it at its radius (φ the angle between them): unlike
    Newton's cross product it is zero at φ = 0 alone, not at φ = π too (a body pointing
    against its driver is not a pose that meets it). The Jacobian is that of these lengths,
    exactly: a least-squares minimum is where its gradient vanishes.
    """
    res, jac, _, _ = _system(c, g, jacobian=jacobian)
    x, n = c.x, c.x.shape[-1]
    col = {p: 2 * k for k, p in enumerate(g.points)}
    row = 0
    for con in g.constraints:
        if isinstance(con, CFrame):
            row += 2
            continue
        if isinstance(con, CAngle):
            ex, ey = _reference(x, con, c.q[con.input])
            dx, dy = x[con.p, 0] - x[con.pivot, 0], x[con.p, 1] - x[con.pivot, 1]
            phi = np.arctan2(_cross(ex, ey, dx, dy), ex * dx + ey * dy)
            r = np.hypot(dx, dy)
            res[row] = 2.0 * r * np.sin(phi / 2.0)
            if jac is not None:
                jac[row] = 0.0
                ur, cs, sn = 1.0 / np.where(r > 0, r, 1.0), np.cos(phi / 2.0), 2 * np.sin(phi / 2)
                # ∂/∂(p − pivot): 2 sin(φ/2)·d̂ + cos(φ/2)·perp(d̂)
                gx, gy = (sn * dx - cs * dy) * ur, (sn * dy + cs * dx) * ur
                for p, sign in ((con.p, 1.0), (con.pivot, -1.0)):
                    if p in col:
                        jac[row, col[p]] += sign * gx
                        jac[row, col[p] + 1] += sign * gy
                if con.ref is not None:  # φ falls as the reference turns: −r·cos(φ/2)·∂θ_ref
                    vx = x[con.ref[1], 0] - x[con.ref[0], 0]
                    vy = x[con.ref[1], 1] - x[con.ref[0], 1]
                    v2 = vx * vx + vy * vy
                    v2 = np.where(v2 > 0, v2, 1.0)
                    hx, hy = r * cs * vy / v2, -r * cs * vx / v2
                    for p, sign in ((con.ref[1], 1.0), (con.ref[0], -1.0)):
                        if p in col:
                            jac[row, col[p]] += sign * hx
                            jac[row, col[p] + 1] += sign * hy
            row += 1
            continue
        if isinstance(con, CDist | CRope):  # (L² − d²)/(L + d) = L − d, L = |p − q| or a rope's
            r = _length(x, con)
            size = r + np.abs(dist(c, con.dist)[0])
            res[row] /= np.where(size > 0, size, 1.0)
            if jac is not None:  # ∂L = ∂(L²) / (2·L)
                jac[row] /= np.where(r > 0, 2.0 * r, 1.0)
        else:  # ρ = cross(u, g)/|u|: its ends' rows gain ∓ρ·û/|u| from |u|
            ux, uy = x[con.l2, 0] - x[con.l1, 0], x[con.l2, 1] - x[con.l1, 1]
            u = np.hypot(ux, uy)
            u = np.where(u > 0, u, 1.0) + np.zeros(n)
            res[row] /= u
            if jac is not None:
                jac[row] /= u
                for p, sign in ((con.l2, -1.0), (con.l1, 1.0)):
                    if p in col:
                        jac[row, col[p]] += sign * res[row] * ux / (u * u)
                        jac[row, col[p] + 1] += sign * res[row] * uy / (u * u)
        row += 1
    return res, jac


def _length(x: F, con: CDist | CRope) -> F:
    """A distance constraint's |p − q|, or a rope's length over its sheaves, shape (n,)."""
    if isinstance(con, CDist):
        return np.hypot(x[con.p, 0] - x[con.q, 0], x[con.p, 1] - x[con.q, 1])  # type: ignore[no-any-return]
    pts = [(x[p, 0], x[p, 1]) for p in con.points]
    return np.asarray(rope_path(pts, con.signed, con.wraps0).length)


def misses(c: Chunk, g: NewtonGroup) -> tuple[F, F]:
    """How far each of the group's constraints is from met, at the chunk's positions.

    Parameters
    ----------
    c : Chunk
        The positions (and inputs) of the samples.
    g : NewtonGroup
        The group.

    Returns
    -------
    length : ndarray, shape (n_constraints, n)
        The miss as a length (m, ≥ 0): a distance's error, a point's distance from where its
        body's frame or its slider's line puts it, or the chord by which a driven body misses
        its angle, at the point's radius.
    amount : ndarray, shape (n_constraints, n)
        The miss in the constraint's own terms: a distance's error (achieved − required, m), a
        point's distance from its frame's place or its line (m), a driver's angle error (rad).
    """
    x, n = c.x, c.x.shape[-1]
    length = np.empty((len(g.constraints), n))
    amount = np.empty((len(g.constraints), n))
    for k, con in enumerate(g.constraints):
        if isinstance(con, CDist | CRope):  # a rope's: its length's error
            amount[k] = _length(x, con) - np.abs(dist(c, con.dist)[0])
            length[k] = np.abs(amount[k])
        elif isinstance(con, CFrame):
            amount[k] = length[k] = np.hypot(_frame(x, con, 0), _frame(x, con, 1))
        elif isinstance(con, CLine):
            ux, uy = x[con.l2, 0] - x[con.l1, 0], x[con.l2, 1] - x[con.l1, 1]
            gx, gy = x[con.p, 0] - x[con.l1, 0], x[con.p, 1] - x[con.l1, 1]
            amount[k] = _cross(ux, uy, gx, gy) / np.hypot(ux, uy)
            length[k] = np.abs(amount[k])
        else:
            ex, ey = _reference(x, con, c.q[con.input])
            dx, dy = x[con.p, 0] - x[con.pivot, 0], x[con.p, 1] - x[con.pivot, 1]
            amount[k] = np.arctan2(_cross(ex, ey, dx, dy), ex * dx + ey * dy)
            length[k] = 2.0 * np.hypot(dx, dy) * np.abs(np.sin(amount[k] / 2.0))
    return length, amount


def _least_squares(
    c: Chunk,
    g: NewtonGroup,
    weight: F | None,
    iters: int,
    shift: F | None = None,
    still: float = 1e-13,
) -> NDArray[np.bool_]:
    """Levenberg–Marquardt on the group's residuals in metres (plus ``shift`` and times
    ``weight``, each shape (m, n), where given), in place in ``c.x``, every sample at once;
    returns where it stalled (no step lowered the sum of squares by more than ``still`` of
    it for eight passes running). The damping follows the gain over the one the linear model
    promised (Nielsen's rule). Stalled samples leave the iteration, as in Newton's
    (`SHRINK`): a batch costs what its slowest samples need."""
    pts = list(g.points)
    n = c.x.shape[-1]
    size = 2 * len(pts)
    live = np.arange(n)  # the samples in ``sub``, as indices of ``c``
    sub, group = c, g
    stalled = np.zeros(n, dtype=bool)

    def evaluate(jacobian: bool) -> tuple[F, F | None]:
        res, jac = _lengths(sub, group, jacobian=jacobian)
        if shift is not None:
            res = res + shift[:, live]
        if weight is None:
            return res, jac
        w = weight[:, live]
        return res * w, None if jac is None else jac * w[:, None, :]

    res, jac = evaluate(True)
    cost = np.sum(res * res, axis=0)
    lam, grow = np.full(n, 1e-3), np.full(n, 2.0)
    idle = np.zeros(n, dtype=np.int64)
    eye = np.eye(size)[:, :, None]
    for _ in range(iters):
        assert jac is not None
        normal = np.einsum("rin,rjn->ijn", jac, jac)
        grad = np.einsum("rin,rn->in", jac, res)
        trace = np.einsum("iin->n", normal)
        damp = lam * np.where(trace > 0, trace / size, 1.0)
        step = -Factors(normal + damp * eye, overwrite=True).solve(grad)
        step[:, ~np.isfinite(step).all(axis=0)] = 0.0
        before = np.stack([sub.x[p].copy() for p in pts])
        for j, p in enumerate(pts):
            sub.x[p] += step[2 * j : 2 * j + 2]
        trial, _ = evaluate(False)
        new = np.sum(trial * trial, axis=0)
        better = new < cost
        promised = -2.0 * np.einsum("in,in->n", step, grad)
        promised -= np.einsum("in,ijn,jn->n", step, normal, step)
        ratio = (cost - new) / np.where(promised > 0, promised, np.inf)
        for j, p in enumerate(pts):
            sub.x[p][:, ~better] = before[j][:, ~better]
        gain = np.where(better, cost - new, 0.0)
        idle = np.where(gain > still * cost, 0, idle + 1)
        cost = np.where(better, new, cost)
        shrink = np.maximum(1.0 / 3.0, 1.0 - (2.0 * ratio - 1.0) ** 3)
        lam = np.clip(np.where(better, lam * shrink, lam * grow), 1e-15, 1e12)
        grow = np.where(better, 2.0, grow * 2.0)
        settled = idle >= 8
        if settled.all():
            break
        if np.count_nonzero(~settled) < SHRINK * settled.size:  # the settled ones leave
            for p in pts:
                c.x[p][:, live[settled]] = sub.x[p][:, settled]
            stalled[live[settled]] = True
            keep = ~settled
            live = live[keep]
            sub = _positions_at(sub, keep)
            group = kind_of(g).take(g, live)
            cost, lam, grow, idle = cost[keep], lam[keep], grow[keep], idle[keep]
        res, jac = evaluate(True)
    if sub is not c:
        for p in pts:
            c.x[p][:, live] = sub.x[p]
    stalled[live] = idle >= 8
    return stalled


def _project(c: Chunk, g: NewtonGroup, keep: F, tol: float) -> None:
    """Move the group's points, least, onto its equations where ``keep`` is 1 (shape (m, n);
    0 leaves an equation out) by Gauss–Newton's minimum-norm steps, in place; a sample whose
    kept equations are not then met to ``tol`` (m) goes back to where it was."""
    pts = list(g.points)
    before = np.stack([c.x[p].copy() for p in pts])
    eq = keep.shape[0]
    for _ in range(8):
        res, jac = _lengths(c, g)
        assert jac is not None
        res, jac = res * keep, jac * keep[:, None, :]
        outer = np.einsum("rin,sin->rsn", jac, jac)
        trace = np.einsum("rrn->n", outer)
        outer += (1e-14 * trace + (keep == 0)) * np.eye(eq)[:, :, None]
        step = -np.einsum("rin,rn->in", jac, Factors(outer, overwrite=True).solve(res))
        step[:, ~np.isfinite(step).all(axis=0)] = 0.0
        for j, p in enumerate(pts):
            c.x[p] += step[2 * j : 2 * j + 2]
    res, _ = _lengths(c, g, jacobian=False)
    met = np.max(np.abs(res * keep), axis=0) <= tol
    for j, p in enumerate(pts):
        c.x[p][:, ~met] = before[j][:, ~met]


def _driven(con: Constraint) -> bool:
    """Whether a group's constraint is a driver's: a driven length, or a driver's angle."""
    return isinstance(con, CAngle) or (isinstance(con, CDist | CRope) and con.dist.kind == "input")


def out_of_reach(
    c: Chunk, g: NewtonGroup, scale: float, iters: int = REACH_ITER
) -> tuple[NDArray[np.bool_], NDArray[np.int16], F]:
    """Which of a group's samples that Newton did not solve cannot be reached at all, the
    constraint that cannot be met, and by how much.

    From the chunk's positions of the group's points (a start near the sample: a solved
    neighbour's, or the sketch's), Levenberg–Marquardt minimises the sum of the squares of the
    group's residuals, each in metres (`misses`). Where it stalls with a constraint missed by
    more than `REACH_TOL` of the size, no pose meets them all (near the start): the pose is out
    of reach. Where the residual goes to zero, a pose exists and Newton merely did not get there
    (its status stays "did not converge").

    The constraint named is the driver (a driven length or a driver's angle) missed most at
    that stall — the input that asks for the pose — or, where no driver's is missed, the
    constraint missed most. By how much is then measured with every other constraint met: the
    named one alone is pushed to its limit (a second minimisation, the others weighted by
    `REACH_WEIGHT` and their targets moved by the method of multipliers for `REACH_ROUNDS`
    rounds, then the points moved onto the others exactly). For a point held by two distances
    a and b from points c apart, that is the triangle's own shortfall, c − (a + b) or
    |a − b| − c.

    Parameters
    ----------
    c : Chunk
        The samples (only those Newton did not solve): their known points, inputs, and the
        group's points at the start; the group's points are moved in place.
    g : NewtonGroup
        The group, its per-sample constants taken at these samples.
    scale : float
        The mechanism's size (m).
    iters : int
        Passes, at most, of each minimisation.

    Returns
    -------
    out : ndarray of bool, shape (n,)
        True where the pose is out of reach.
    unmet : ndarray of int16, shape (n,)
        Index into ``g.constraints`` of the constraint that cannot be met (−1 where ``out`` is
        False).
    amount : ndarray, shape (n,)
        By how much, in that constraint's own terms (`misses`): a distance achieved less the
        required (m, negative where the points cannot get that far apart), a point's distance
        from its body's frame or its slider's line (m), a driver's angle error (rad); NaN where
        ``out`` is False.
    """
    n = c.x.shape[-1]
    unmet = np.full(n, -1, dtype=np.int16)
    amount = np.full(n, np.nan)
    start = np.isfinite(c.x[list(g.points)]).all(axis=(0, 1))
    # a sum of squares going to zero falls by a large fraction a pass, even at a singular
    # root (linearly); one settling on a minimum above zero creeps: 1e-9 a pass is settled
    stalled = _least_squares(c, g, None, iters, still=1e-9)
    length, _ = misses(c, g)
    length = np.nan_to_num(length, nan=-1.0)
    out = start & stalled & (np.max(length, axis=0) > REACH_TOL * scale)
    if not out.any():
        return out, unmet, amount
    # the driver missed most, where one is missed: the input that asks for the pose
    driven = np.array([_driven(con) for con in g.constraints])[:, None]
    by_driver = np.where(driven, length, -1.0)
    worst = np.where(
        np.max(by_driver, axis=0) > REACH_TOL * scale,
        np.argmax(by_driver, axis=0),
        np.argmax(length, axis=0),
    )
    rows = _rows(g)
    mine = rows[:, None] == worst[None, :]  # (m, n): the named constraint's equations
    # the others as penalties, their multipliers' estimates carried in ``shift`` (the method of
    # multipliers): each round leaves them a factor of about REACH_WEIGHT² nearer to met
    shift = np.zeros(mine.shape)
    for _ in range(REACH_ROUNDS):
        _least_squares(c, g, np.where(mine, 1.0, REACH_WEIGHT), iters, shift)
        shift += np.where(mine, 0.0, _lengths(c, g, jacobian=False)[0])
    _project(c, g, np.where(mine, 0.0, 1.0), REACH_TOL * scale)
    _, final = misses(c, g)
    unmet[out] = worst[out]
    amount[out] = np.take_along_axis(final, worst[None], axis=0)[0][out]
    return out, unmet, amount
