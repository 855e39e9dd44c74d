"""A Newton group's compiled source: the per-sample Newton iteration of
`excavkin.step_kinds.newton_solve`, written out for the compiled plan of a model with groups
(`excavkin.kinematics.compiled_newton`).

Per sample, the group's equations (the constraints of `excavkin.step_kinds.constraints`, a
rope's length over its sheaves by `excavkin.step_kinds.rope_path`'s formulas) fill a residual
row and a Jacobian held in small scratch arrays, and the kernel's own LU with partial pivoting on
equilibrated rows (`factor_source`, the arithmetic of `excavkin.step_kinds.small_systems.Factors`)
solves them. The iteration has the NumPy path's start (the positions handed in), tolerance
(a step below 1e-14 of the size), singular test (|det| over the rows' norms below 1e-13), cap
(50 passes), dyad sides (a dyad on the wrong side mirrored, then iterated again) and statuses
(not converged where a residual stays above 1e-10·size²; a rope off its sheaves). Its rates solve
the same Jacobian with the differentiated constraints, as `newton_rates` does; a group's branch
check (`excavkin.kinematics.solve`'s) is written after every step.

The source is linear in the group's constraints (one block of lines each) and loops over the
matrix size at run time: no recursion, no unrolling that grows as its square.
"""

from __future__ import annotations

import re
from typing import Any

from excavkin.step_kinds.constraints import CAngle, CDist, CFrame, CLine, CRope
from excavkin.step_kinds.state import Code

__all__ = [
    "MAX_ITER",
    "UNROLL",
    "emit_group",
    "factor_source",
    "unrolled_factor",
    "unrolled_solve",
]

#: Newton passes at most (`newton_solve.newton_positions`'s cap)
MAX_ITER = 50

#: once a sample's last Newton step is below this fraction of the size, later steps reuse its
#: last factorisation (chord steps), as long as each shrinks by `CHORD_RATE` or more
#: (`newton_solve.CHORD_FROM`, per sample)
CHORD_FROM = 1e-4
CHORD_RATE = 0.1

_FACTOR = """

@numba.njit(
    numba.float64(numba.float64[:, ::1], numba.float64[:, ::1], numba.int64[::1],
                  numba.float64[::1], numba.float64[::1]),
    nogil=True, cache=True, error_model="numpy",
)
def factor_M(J, LU, piv, scl, rec):
    \"\"\"LU of the MxM matrix J into LU, rows scaled to unit norm, partial pivoting; returns
    det over the rows' norms (0 at a zero pivot).\"\"\"
    for r in range(M):
        s = 0.0
        for c in range(M):
            s += J[r, c] * J[r, c]
        nrm = math.sqrt(s)
        scl[r] = 1.0 / (nrm if nrm > 0.0 else 1.0)
        for c in range(M):
            LU[r, c] = J[r, c] * scl[r]
    ratio = 1.0
    dead = False
    for k in range(M - 1):
        best = abs(LU[k, k])
        p = 0
        for r in range(1, M - k):
            mag = abs(LU[k + r, k])
            if mag > best:
                best = mag
                p = r
        piv[k] = p
        if p != 0:
            for c in range(k, M):
                t = LU[k, c]
                LU[k, c] = LU[k + p, c]
                LU[k + p, c] = t
            ratio = -ratio
        ratio *= LU[k, k]
        if LU[k, k] == 0.0:
            dead = True
        rec[k] = 1.0 / LU[k, k]
        for r in range(k + 1, M):
            LU[r, k] /= LU[k, k]
            for c in range(k + 1, M):
                LU[r, c] -= LU[r, k] * LU[k, c]
    ratio *= LU[M - 1, M - 1]
    rec[M - 1] = 1.0 / LU[M - 1, M - 1]
    if dead:
        ratio = 0.0
    return ratio


@numba.njit(
    numba.void(numba.float64[:, ::1], numba.int64[::1], numba.float64[::1],
               numba.float64[::1], numba.float64[::1]),
    nogil=True, cache=True, error_model="numpy",
)
def lusolve_M(LU, piv, scl, rec, b):
    \"\"\"Solve with the factors of factor_M, in place in b.\"\"\"
    for r in range(M):
        b[r] *= scl[r]
    for k in range(M - 1):
        p = piv[k]
        if p != 0:
            t = b[k]
            b[k] = b[k + p]
            b[k + p] = t
        for r in range(k + 1, M):
            b[r] -= LU[r, k] * b[k]
    for k in range(M - 1, -1, -1):
        b[k] *= rec[k]
        for r in range(k):
            b[r] -= LU[r, k] * b[k]
"""


def factor_source(m: int) -> str:
    """The generated source's LU of an m×m system: ``factor_m`` and ``lusolve_m``, the size a
    literal; the arithmetic of `excavkin.step_kinds.small_systems.Factors`, operation for
    operation.

    Parameters
    ----------
    m : int
        The system's size.

    Returns
    -------
    str
    """
    text = _FACTOR.replace("_M(", f"_{m}(").replace("MxM", f"{m}x{m}")
    return re.sub(r"\bM\b", str(m), text)


def unrolled_factor(m: int, pre: str) -> list[str]:
    """Lines that factor the m×m matrix held in the locals ``{pre}a{r}_{c}``, in place, as
    `factor_source` does: rows scaled to unit norm (``{pre}sc{r}``), then partial pivoting,
    the first row of the largest magnitude of a column exchanged with row k
    (``{pre}p{k}``: its offset below k, 0 for none), the pivots' reciprocals ``{pre}rc{k}``
    and ``ratio``, the determinant over the rows' norms (0 at a zero pivot). Straight-line:
    the compiler keeps a small system in registers.

    Parameters
    ----------
    m : int
        The size.
    pre : str
        The locals' prefix.

    Returns
    -------
    list of str
    """

    def a(r: int, c: int) -> str:
        return f"{pre}a{r}_{c}"

    out = []
    for r in range(m):
        out.append("s_ = " + " + ".join(f"{a(r, c)} * {a(r, c)}" for c in range(m)))
        out += ["s_ = math.sqrt(s_)", f"{pre}sc{r} = 1.0 / (s_ if s_ > 0.0 else 1.0)"]
        out += [f"{a(r, c)} *= {pre}sc{r}" for c in range(m)]
    out += ["ratio = 1.0", "dead = False"]
    for k in range(m - 1):
        pk = f"{pre}p{k}"  # the pivot's row, below row k (0: row k itself)
        out += [f"best = abs({a(k, k)})", f"{pk} = 0"]
        for r in range(k + 1, m):
            out += [
                f"mag = abs({a(r, k)})",
                "if mag > best:",
                "    best = mag",
                f"    {pk} = {r - k}",
            ]
        for r in range(k + 1, m):
            out.append(f"if {pk} == {r - k}:")
            for c in range(k, m):
                out.append(f"    {a(k, c)}, {a(r, c)} = {a(r, c)}, {a(k, c)}")
        out += [
            f"if {pk} != 0:",
            "    ratio = -ratio",
            f"ratio *= {a(k, k)}",
            f"if {a(k, k)} == 0.0:",
            "    dead = True",
            f"{pre}rc{k} = 1.0 / {a(k, k)}",
        ]
        for r in range(k + 1, m):
            out.append(f"{a(r, k)} /= {a(k, k)}")
            for c in range(k + 1, m):
                out.append(f"{a(r, c)} -= {a(r, k)} * {a(k, c)}")
    out += [
        f"ratio *= {a(m - 1, m - 1)}",
        f"{pre}rc{m - 1} = 1.0 / {a(m - 1, m - 1)}",
        "if dead:",
        "    ratio = 0.0",
    ]
    return out


def unrolled_solve(m: int, pre: str, b: list[str]) -> list[str]:
    """Lines that solve with the factors of `unrolled_factor`, in place in the locals ``b``.

    Parameters
    ----------
    m : int
        The size.
    pre : str
        The factors' prefix.
    b : list of str
        The right-hand side's locals.

    Returns
    -------
    list of str
    """

    def a(r: int, c: int) -> str:
        return f"{pre}a{r}_{c}"

    out = [f"{b[r]} *= {pre}sc{r}" for r in range(m)]
    for k in range(m - 1):
        for r in range(k + 1, m):
            out += [f"if {pre}p{k} == {r - k}:", f"    {b[k]}, {b[r]} = {b[r]}, {b[k]}"]
        for r in range(k + 1, m):
            out.append(f"{b[r]} -= {a(r, k)} * {b[k]}")
    for k in range(m - 1, -1, -1):
        out.append(f"{b[k]} *= {pre}rc{k}")
        for r in range(k):
            out.append(f"{b[r]} -= {a(r, k)} * {b[k]}")
    return out


#: a system this size or smaller is factored straight-line in locals (its code grows as m³/3)
UNROLL = 8


class _Names:
    """The group's constants as read into locals, and its scratch arrays' names."""

    def __init__(self, g: Any, st: Any, k: int) -> None:
        self.k = k
        self.pre = f"g{k}_"
        self.col = {p: 2 * i for i, p in enumerate(st.points)}
        self.m = 2 * len(st.points)
        self.cons: list[dict[str, Any]] = []
        pre = self.pre
        for c, con in enumerate(st.constraints):
            e: dict[str, Any] = {}
            if isinstance(con, CDist | CRope):
                d, dd, ddd = g.dist(con.dist, f"{pre}d{c}")
                e["d"], e["dd"], e["ddd"] = d, dd or "0.0", ddd or "0.0"
            if isinstance(con, CFrame):
                e["s"], e["t"] = f"{pre}s{c}", f"{pre}t{c}"
                g.emit(f"{e['s']} = {g.const()}", f"{e['t']} = {g.const()}")
            if isinstance(con, CRope):
                e["r"] = [f"{pre}r{c}_{i}" for i in range(len(con.points))]
                e["w"] = [f"{pre}w{c}_{i}" for i in range(len(con.points))]
                for name in e["r"] + e["w"]:
                    g.emit(f"{name} = {g.const()}")
            self.cons.append(e)
        self.signs = [f"{pre}sg{i}" for i in range(len(st.dyads))]
        for name in self.signs:
            g.emit(f"{name} = {g.const()}")
        #: a small system is factored in locals, straight-line; a larger one by `factor_source`
        self.unrolled = self.m <= UNROLL
        if self.unrolled:
            self.fac = unrolled_factor(self.m, pre)
            self.sol = unrolled_solve(self.m, pre, [self.rv(r) for r in range(self.m)])
            return
        J, LU, piv, scl, rec, R = g.scratch(k, self.m)
        self.J, self.R = J, R
        self.fac = [f"ratio = factor_{self.m}({J}, {LU}, {piv}, {scl}, {rec})"]
        self.sol = [f"lusolve_{self.m}({LU}, {piv}, {scl}, {rec}, {R})"]

    def rv(self, r: int) -> str:
        """Row r of the right-hand side (the residual, then the solution)."""
        return f"{self.pre}b{r}" if self.unrolled else f"{self.R}[{r}]"

    def jv(self, r: int, c: int) -> str:
        """Entry (r, c) of the Jacobian (then of its factors)."""
        return f"{self.pre}a{r}_{c}" if self.unrolled else f"{self.J}[{r}, {c}]"

    def init(self) -> list[str]:
        """An unrolled system's locals, defined before the iteration reads them."""
        if not self.unrolled:
            return []
        m, pre = self.m, self.pre
        out = [f"{self.jv(r, c)} = 0.0" for r in range(m) for c in range(m)]
        out += [f"{pre}sc{r} = 1.0" for r in range(m)] + [f"{pre}rc{r} = 1.0" for r in range(m)]
        out += [f"{pre}p{k} = 0" for k in range(m - 1)]
        return out + [f"{self.rv(r)} = 0.0" for r in range(m)]


def _rope_lines(pre: str, con: CRope, e: dict[str, Any], pos: tuple[str, str]) -> list[str]:
    """The rope's segments (``{pre}ux{i}``, ``{pre}uy{i}``, ``{pre}l{i}``), wraps
    (``{pre}ph{i}``) and length (``{pre}L``) at the positions named ``pos``
    (`excavkin.step_kinds.rope_path.rope_path`)."""
    X, Y = pos
    pts, r, w = con.points, e["r"], e["w"]
    out = []
    for i in range(len(pts) - 1):
        a, b = pts[i], pts[i + 1]
        out += [
            f"dx = {X}{b} - {X}{a}",
            f"dy = {Y}{b} - {Y}{a}",
            f"rho = {r[i]} - {r[i + 1]}",
            "d2 = dx * dx + dy * dy",
            f"{pre}l{i} = math.sqrt(d2 - rho * rho)",
            f"{pre}ux{i} = ({pre}l{i} * dx - rho * dy) / d2",
            f"{pre}uy{i} = ({pre}l{i} * dy + rho * dx) / d2",
        ]
    out.append(f"{pre}L = 0.0")
    for i in range(len(pts) - 1):
        out.append(f"{pre}L = {pre}L + {pre}l{i}")
    for i in range(1, len(pts) - 1):
        out += [
            f"cr = {pre}ux{i - 1} * {pre}uy{i} - {pre}uy{i - 1} * {pre}ux{i}",
            f"dt = {pre}ux{i - 1} * {pre}ux{i} + {pre}uy{i - 1} * {pre}uy{i}",
            f"ph = (1.0 if {r[i]} > 0 else -1.0) * math.atan2(cr, dt)",
            f"tu = np.rint(({w[i]} - ph) / TWO_PI)",
            "if math.isfinite(tu):",
            "    ph = ph + TWO_PI * tu",
            f"{pre}ph{i} = ph",
            f"{pre}L = {pre}L + abs({r[i]}) * ph",
        ]
    return out


def _equations(n: _Names, st: Any, jac: bool, rates: int) -> list[str]:
    """Lines that fill the residual ``R`` (and with ``jac`` the Jacobian ``J``, zeroed first),
    or with ``rates`` 1 or 2 the right-hand side of the velocities or accelerations in ``R``
    (`newton_solve._equations`'s Φ̇ and Φ̈ with the rates the group's points hold)."""
    out: list[str] = []
    col = n.col
    seen: set[tuple[int, int]] = set()  # an entry's first term is assigned, the rest added
    row = 0

    later: list[str] = []  # a rope's or an angle's gradient, written after its lines

    def grad(r: int, p: int, gx: str, gy: str, to: list[str] | None = None) -> None:
        if jac and p in col:
            for c, value in ((col[p], gx), (col[p] + 1, gy)):
                op = "+=" if (r, c) in seen else "="
                seen.add((r, c))
                (out if to is None else to).append(f"{n.jv(r, c)} {op} {value}")

    def grad_later(r: int, p: int, gx: str, gy: str) -> None:
        grad(r, p, gx, gy, later)

    for c, con in enumerate(st.constraints):
        e = n.cons[c]
        if isinstance(con, CDist):
            p, q = con.p, con.q
            d, dd, ddd = e["d"], e["dd"], e["ddd"]
            out += [f"rx = X{p} - X{q}", f"ry = Y{p} - Y{q}"]
            if rates == 0:
                out.append(f"{n.rv(row)} = (rx * rx + ry * ry) - {d} * {d}")
                grad(row, p, "2 * rx", "2 * ry")
                grad(row, q, "-(2 * rx)", "-(2 * ry)")
            else:
                out += [f"wx = VX{p} - VX{q}", f"wy = VY{p} - VY{q}"]
                if rates == 1:
                    out.append(f"{n.rv(row)} = 2 * (rx * wx + ry * wy) - 2 * {d} * {dd}")
                else:
                    out += [
                        f"ax_ = AX{p} - AX{q}",
                        f"ay_ = AY{p} - AY{q}",
                        f"{n.rv(row)} = (2 * (rx * ax_ + ry * ay_) + 2 * (wx * wx + wy * wy)"
                        f" - 2 * ({dd} * {dd} + {d} * {ddd}))",
                    ]
            row += 1
        elif isinstance(con, CFrame):
            p, a, b, s, t = con.p, con.a, con.b, e["s"], e["t"]
            for comp in (0, 1):
                pre = ("X", "Y", "X", "Y") if rates == 0 else ("VX", "VY", "VX", "VY")
                if rates == 2:
                    pre = ("AX", "AY", "AX", "AY")
                PX, PY = pre[0], pre[1]
                wx, wy = f"({PX}{b} - {PX}{a})", f"({PY}{b} - {PY}{a})"
                if comp == 0:
                    out.append(f"{n.rv(row)} = {PX}{p} - {PX}{a} - {s} * {wx} + {t} * {wy}")
                    grad(row, p, "1.0", "0.0")
                    grad(row, a, f"{s} - 1.0", f"-{t}")
                    grad(row, b, f"-{s}", f"{t}")
                else:
                    out.append(f"{n.rv(row)} = {PY}{p} - {PY}{a} - {s} * {wy} - {t} * {wx}")
                    grad(row, p, "0.0", "1.0")
                    grad(row, a, f"{t}", f"{s} - 1.0")
                    grad(row, b, f"-{t}", f"-{s}")
                row += 1
        elif isinstance(con, CLine):
            p, l1, l2 = con.p, con.l1, con.l2
            out += [
                f"ux = X{l2} - X{l1}", f"uy = Y{l2} - Y{l1}",
                f"gx = X{p} - X{l1}", f"gy = Y{p} - Y{l1}",
            ]  # fmt: skip
            if rates == 0:
                out.append(f"{n.rv(row)} = ux * gy - uy * gx")
                grad(row, p, "-uy", "ux")
                grad(row, l2, "gy", "-gx")
                grad(row, l1, "uy - gy", "gx - ux")
            else:
                out += [
                    f"udx = VX{l2} - VX{l1}", f"udy = VY{l2} - VY{l1}",
                    f"gdx = VX{p} - VX{l1}", f"gdy = VY{p} - VY{l1}",
                ]  # fmt: skip
                if rates == 1:
                    out.append(f"{n.rv(row)} = (udx * gy - udy * gx) + (ux * gdy - uy * gdx)")
                else:
                    out += [
                        f"uax = AX{l2} - AX{l1}", f"uay = AY{l2} - AY{l1}",
                        f"gax = AX{p} - AX{l1}", f"gay = AY{p} - AY{l1}",
                        f"{n.rv(row)} = ((uax * gy - uay * gx) + 2 * (udx * gdy - udy * gdx)"
                        " + (ux * gay - uy * gax))",
                    ]  # fmt: skip
            row += 1
        elif isinstance(con, CRope):
            out += _rope(n, con, e, row, rates, grad_later) + later
            later.clear()
            row += 1
        else:
            out += _angle(n, con, row, rates, grad_later) + later
            later.clear()
            row += 1
    if jac and n.unrolled:  # (factored in place: an entry no constraint writes is zeroed)
        out += [f"{n.jv(r, c)} = 0.0" for r in range(n.m) for c in range(n.m) if (r, c) not in seen]
    return out


def _u(pre: str, comp: str, seg: int | None) -> str:
    """A segment's direction component, or 0.0 past the rope's end."""
    return "0.0" if seg is None else f"{pre}{comp}{seg}"


def _rope(n: _Names, con: CRope, e: dict[str, Any], row: int, rates: int, grad: Any) -> list[str]:
    pre = n.pre + "p_"
    d, dd, ddd = e["d"], e["dd"], e["ddd"]
    out = _rope_lines(pre, con, e, ("X", "Y"))
    pts = con.points
    last = len(pts) - 1
    L = f"{pre}L"
    if rates == 0:
        out.append(f"{n.rv(row)} = {L} * {L} - {d} * {d}")
        acc: dict[int, tuple[list[str], list[str]]] = {}
        for k, p in enumerate(pts):
            if p not in n.col:
                continue
            gx = (
                (f"{pre}ux{k - 1}" if k else "0.0") + " - " + (f"{pre}ux{k}" if k < last else "0.0")
            )
            gy = (
                (f"{pre}uy{k - 1}" if k else "0.0") + " - " + (f"{pre}uy{k}" if k < last else "0.0")
            )
            acc.setdefault(p, ([], []))
            acc[p][0].append(f"2 * {L} * ({gx})")
            acc[p][1].append(f"2 * {L} * ({gy})")
        for p, (xs, ys) in acc.items():
            grad(row, p, " + ".join(xs), " + ".join(ys))
        return out
    out.append("rate = 0.0")
    for k in range(last):
        a, b = pts[k], pts[k + 1]
        out.append(f"rate = rate + {pre}ux{k} * (VX{b} - VX{a}) + {pre}uy{k} * (VY{b} - VY{a})")
    if rates == 1:
        out.append(f"{n.rv(row)} = 2 * {L} * rate - 2 * {d} * {dd}")
        return out
    out.append("acc = 0.0")
    for k in range(last):
        a, b = pts[k], pts[k + 1]
        out.append(f"acc = acc + {pre}ux{k} * (AX{b} - AX{a}) + {pre}uy{k} * (AY{b} - AY{a})")
    out.append("cur = 0.0")
    for k in range(last):
        a, b = pts[k], pts[k + 1]
        out += [
            f"wr = -{pre}uy{k} * (VX{b} - VX{a}) + {pre}ux{k} * (VY{b} - VY{a})",
            f"cur = cur + wr * wr / {pre}l{k}",
        ]
    out.append(
        f"{n.rv(row)} = 2 * rate * rate + 2 * {L} * (acc + cur) - 2 * ({dd} * {dd} + {d} * {ddd})"
    )
    return out


def _angle(n: _Names, con: CAngle, row: int, rates: int, grad: Any) -> list[str]:
    i, p, pv = con.input, con.p, con.pivot
    out = [f"cs = math.cos(q[{i}, i])", f"sn = math.sin(q[{i}, i])"]
    if con.ref is None:
        out += ["vx = 1.0", "vy = 0.0"]
    else:
        r0, r1 = con.ref
        out += [f"vx = X{r1} - X{r0}", f"vy = Y{r1} - Y{r0}"]
    out += [
        "ex = cs * vx - sn * vy", "ey = sn * vx + cs * vy",
        f"dpx = X{p} - X{pv}", f"dpy = Y{p} - Y{pv}",
    ]  # fmt: skip
    if rates == 0:
        out.append(f"{n.rv(row)} = ex * dpy - ey * dpx")
        grad(row, p, "-ey", "ex")
        grad(row, pv, "ey", "-ex")
        if con.ref is not None:
            out += ["gvx = cs * dpy - sn * dpx", "gvy = -sn * dpy - cs * dpx"]
            grad(row, con.ref[1], "gvx", "gvy")
            grad(row, con.ref[0], "-gvx", "-gvy")
        return out
    out += [f"qd_ = qd[{i}, i]", f"qdd_ = qdd[{i}, i]"]
    if con.ref is None:
        out += ["vdx = 0.0", "vdy = 0.0"]
    else:
        r0, r1 = con.ref
        out += [f"vdx = VX{r1} - VX{r0}", f"vdy = VY{r1} - VY{r0}"]
    out += [
        "rvdx = cs * vdx - sn * vdy", "rvdy = sn * vdx + cs * vdy",
        "edx = rvdx - qd_ * ey", "edy = rvdy + qd_ * ex",
        f"ddx = VX{p} - VX{pv}", f"ddy = VY{p} - VY{pv}",
    ]  # fmt: skip
    if rates == 1:
        out.append(f"{n.rv(row)} = (edx * dpy - edy * dpx) + (ex * ddy - ey * ddx)")
        return out
    if con.ref is None:
        out += ["vax = 0.0", "vay = 0.0"]
    else:
        r0, r1 = con.ref
        out += [f"vax = AX{r1} - AX{r0}", f"vay = AY{r1} - AY{r0}"]
    out += [
        "eax = cs * vax - sn * vay - 2 * qd_ * rvdy - qdd_ * ey - qd_ * qd_ * ex",
        "eay = sn * vax + cs * vay + 2 * qd_ * rvdx + qdd_ * ex - qd_ * qd_ * ey",
        f"dax = AX{p} - AX{pv}", f"day = AY{p} - AY{pv}",
        f"{n.rv(row)} = ((eax * dpy - eay * dpx) + 2 * (edx * ddy - edy * ddx)"
        " + (ex * day - ey * dax))",
    ]  # fmt: skip
    return out


def _indent(lines: list[str], by: str) -> list[str]:
    return [by + line for line in lines]


def _iterate(n: _Names, st: Any) -> list[str]:
    """Newton passes from the points' current values (`newton_solve._iterate`, per sample):
    a chord step (the last factors again) once the last step is below `CHORD_FROM` of the
    size, taken only if it shrinks by `CHORD_RATE`, else the next pass factors afresh."""
    body = [f"chord = have and last <= {CHORD_FROM} * scale", "if chord:"]
    body += _indent(_equations(n, st, False, 0), "    ")
    body += ["else:"]
    body += _indent(_equations(n, st, True, 0), "    ")
    body += _indent(n.fac, "    ") + ["    have = True"]
    body += ["if not (abs(ratio) >= 1e-13):", "    break"]
    body += n.sol + ["size = 0.0", "nanstep = False"]
    each = ["if s_ > size:", "    size = s_", "elif s_ != s_:", "    nanstep = True"]
    if n.unrolled:
        for r in range(n.m):
            body += [f"s_ = abs({n.rv(r)})", *each]
    else:  # (a loop: a large group's source grows with its equations alone)
        body += [f"for r in range({n.m}):", f"    s_ = abs({n.R}[r])", *_indent(each, "    ")]
    body += [
        "if nanstep:",
        "    size = nan",
        f"if chord and not (size <= {CHORD_RATE} * last):",
        "    size = math.inf",
        "    have = False",
        "else:",
    ]
    for i, p in enumerate(st.points):
        body += [f"    X{p} -= {n.rv(2 * i)}", f"    Y{p} -= {n.rv(2 * i + 1)}"]
    body += ["if size <= small:", "    break", "last = size"]
    head = ["have = False", "last = math.inf", "ratio = 1.0", f"for it in range({MAX_ITER}):"]
    return head + _indent(body, "    ")


def emit_group(g: Any, st: Any, k: int, mode: str) -> None:
    """Write group ``st`` (plan step ``k``) into a Newton plan's source: ``mode``
    ``"positions"`` iterates from the positions handed in (``x``), ``"rates"`` reads them and
    solves the velocities and accelerations, and adds the group's branch check to ``g.after``.

    Parameters
    ----------
    g : emitter
        `excavkin.kinematics.compiled_newton`'s source being written.
    st : NewtonGroup
        The group.
    k : int
        Its plan step.
    mode : {"positions", "rates"}
        Which kernel.
    """
    n = _Names(g, st, k)
    for p in st.points:
        g.emit(f"X{p} = x[{p}, 0, i]", f"Y{p} = x[{p}, 1, i]")
    if mode == "positions":
        _positions(g, n, st, k)
    else:
        _rates(g, n, st, k)


def _positions(g: Any, n: _Names, st: Any, k: int) -> None:
    lines = n.init() + _iterate(n, st)
    if st.dyads:  # `keep_sides`: a pass a dyad, at most (one copy of the iteration)
        side: list[str] = ["moved = False"]
        for d, sign in zip(st.dyads, n.signs, strict=True):
            P, A, B = d.point, d.a, d.b
            side += [
                "if not moved:",
                f"    ex = X{B} - X{A}",
                f"    ey = Y{B} - Y{A}",
                f"    if (ex * (Y{P} - Y{A}) - ey * (X{P} - X{A})) * {sign} < 0:",
                f"        rx = X{P} - X{A}",
                f"        ry = Y{P} - Y{A}",
                "        e2 = ex * ex + ey * ey",
                "        t_ = (rx * ex + ry * ey) / (e2 if e2 > 0 else nan)",
                f"        mx = X{A} + 2.0 * t_ * ex - rx",
                f"        my = Y{A} + 2.0 * t_ * ey - ry",
                "        if math.isfinite(mx):",
                f"            X{P} = mx",
                "        if math.isfinite(my):",
                f"            Y{P} = my",
                "        moved = True",
            ]
        side += ["if not moved:", "    break"] + _iterate(n, st)
        lines += [f"for sides in range({len(st.dyads)}):"] + _indent(side, "    ")
    # converged: every residual within 1e-10·size²
    lines += _equations(n, st, False, 0)
    lines.append("bad = False")
    if n.unrolled:
        for r in range(n.m):
            lines += [f"bad |= not (abs({n.rv(r)}) <= 1e-10 * scale * scale)"]
    else:
        lines += [
            f"for r in range({n.m}):",
            f"    bad |= not (abs({n.R}[r]) <= 1e-10 * scale * scale)",
        ]
    lines += [
        "if bad:",
        "    if st == 0:",
        f"        st = {int(Code.NO_CONVERGENCE)}",
        f"        fk = {k}",
    ]
    lines += [f"    X{p} = nan\n    Y{p} = nan" for p in st.points]
    ropes = [(c, con) for c, con in enumerate(st.constraints) if isinstance(con, CRope)]
    if ropes:  # `ropes_on_sheaves`
        lines.append("off = False")
        for c, con in ropes:
            pre = f"{n.pre}o{c}_"
            lines += _rope_lines(pre, con, n.cons[c], ("X", "Y"))
            for i in range(1, len(con.points) - 1):
                lines += [f"if not ({pre}ph{i} >= -1e-12):", "    off = True"]
            for i in range(len(con.points) - 1):
                lines += [f"if not math.isfinite({pre}l{i}):", "    off = True"]
        lines += [
            "if off and st == 0:",
            f"    st = {int(Code.ROPE_OFF_SHEAVE)}",
            f"    fk = {k}",
        ]
        lines += [f"    X{p} = nan\n    Y{p} = nan" for p in st.points]
    out: list[str] = []
    for line in lines:
        out += line.split("\n")
    g.emit(*out)


def _rates(g: Any, n: _Names, st: Any, k: int) -> None:
    lines: list[str] = []
    for p in st.points:
        lines += [f"VX{p} = 0.0", f"VY{p} = 0.0", f"AX{p} = 0.0", f"AY{p} = 0.0"]
    lines += _equations(n, st, True, 0)
    lines += [
        *n.fac,
        f"ratio{k} = ratio",
        f"sing = not (abs(ratio{k}) >= singular_tol * singular_tol)",
        "if sing and st == 0:",
        f"    st = {int(Code.SINGULAR)}",
        f"    fk = {k}",
        "dead = nan if sing else 0.0",  # added to every rate: NaN where singular, no branch
    ]
    lines += _equations(n, st, False, 1)
    lines += n.sol
    for i, p in enumerate(st.points):
        lines += [
            f"VX{p} = -{n.rv(2 * i)} + dead",
            f"VY{p} = -{n.rv(2 * i + 1)} + dead",
        ]
    lines += _equations(n, st, False, 2)
    lines += n.sol
    for i, p in enumerate(st.points):
        lines += [
            f"AX{p} = -{n.rv(2 * i)} + dead",
            f"AY{p} = -{n.rv(2 * i + 1)} + dead",
        ]
    # the group's nearness to a dead position: its smallest |ratio| (NaN kept, as np.minimum)
    lines += [
        f"if gnear == gnear and not (abs(ratio{k}) >= gnear):",
        f"    gnear = abs(ratio{k})",
    ]
    g.emit(*lines)
    # the branch check, after every step (`excavkin.kinematics.solve._check_branches`)
    ref = g.ref()
    after = [
        f"sg = 1.0 if ratio{k} > 0 else (-1.0 if ratio{k} < 0 else "
        f"(0.0 if ratio{k} == 0 else nan))",
        "turned = 1.0",
        "flip = False",
    ]
    for d, sign in zip(st.dyads, n.signs, strict=True):
        P, A, B = d.point, d.a, d.b
        at = g.ref()
        after += [
            f"flip |= ((X{B} - X{A}) * (Y{P} - Y{A}) - (Y{B} - Y{A}) * (X{P} - X{A})) * {sign} < 0",
            f"turned *= 1.0 - 2.0 * ({sign} * {at} < 0)",
        ]
    for con in st.constraints:
        if isinstance(con, CAngle):
            i, p, pv = con.input, con.p, con.pivot
            if con.ref is None:
                vx, vy = "1.0", "0.0"
            else:
                vx, vy = f"(X{con.ref[1]} - X{con.ref[0]})", f"(Y{con.ref[1]} - Y{con.ref[0]})"
            after += [
                f"cs = math.cos(q[{i}, i])",
                f"sn = math.sin(q[{i}, i])",
                f"flip |= not ((cs * {vx} - sn * {vy}) * (X{p} - X{pv})"
                f" + (sn * {vx} + cs * {vy}) * (Y{p} - Y{pv}) > 0)",
            ]
    first = st.points[0]
    after += [
        f"flip |= sg != {ref} * turned",
        f"if flip & math.isfinite(X{first}) & (st == 0):",
        f"    st = {int(Code.BRANCH_CHANGED)}",
        f"    fk = {k}",
    ]
    g.after += after
