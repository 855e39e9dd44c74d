"""A closed-form plan compiled to one machine-code loop over samples (numba).

The NumPy kernels (`excavkin.kinematics.kernels`) run each step over a whole chunk, so a
step's temporaries go to memory and come back for the next one. Here the plan is written out
as the straight-line source of one function, every point's position, velocity and acceleration
a local scalar, and numba compiles its loop over samples: a sample's whole state stays in
registers, and only the results are stored. The source depends on the plan's structure alone
(step kinds, point indices, which distances are driven); every dimension — a sketch coordinate,
a length, an attachment coefficient, a dyad's side — is read from a constants table, one column
per sample for a family of designs or one for all. So one compiled kernel serves every design
of a model, and it is cached on disk between runs.

The generated code does the NumPy kernels' arithmetic in the same order, flags the same
statuses at the same step (the first failure wins), and computes the derived body and element
quantities and the finiteness check of `excavkin.kinematics.solve`. The NumPy path stays
the reference: tests hold the two to 1e-15 of each column's scale.

Only a closed-form plan at full order is compiled; Newton groups, the precision check's wider
solves and the emulated rounding run in NumPy. Which path a solve takes is decided in one place,
`excavkin.backends.choose`; the kernels are cached there too.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from excavkin import backends
from excavkin.arrays import FloatArray as F
from excavkin.kinematics import fast_atan2
from excavkin.kinematics.kernels import Chunk, Code
from excavkin.kinematics.vectorise import vectorised
from excavkin.structure.plan import Attach, Dist, Dyad, Fixed, Rotate, SliderStep, SolvePlan

#: a plan of more points is not compiled unasked: numba's compile time and memory grow faster
#: than the kernel's length (a 68-point chain's kernel took minutes and 4 GB), and one kernel
#: per plan has no way to split it yet (a kernel compiled before is used all the same)
AUTO_POINTS = 40

Kernel = Callable[..., None]
#: the generated code's arctangent: arithmetic, inlined (`excavkin.kinematics.fast_atan2`)
ATAN2 = fast_atan2.NAME


def supports(plan: SolvePlan) -> bool:
    """Whether the plan can be compiled: closed-form steps only."""
    return all(isinstance(st, Fixed | Rotate | Attach | Dyad | SliderStep) for st in plan.steps)


def unsupported(plan: SolvePlan) -> str | None:
    """Why the plan cannot be compiled (None: it can), for `excavkin.backends.Job`."""
    return None if supports(plan) else "of this plan have a Newton group, solved in NumPy"


#: the last kernel sources made, by plan of one design (its id, and the plan itself so that an
#: id reused by another plan is not taken for it): a solve asks twice (is it cached? then run
#: it), and a mechanism solves its one plan again and again
_made: dict[tuple[int, bool], tuple[SolvePlan, str]] = {}


def kernel_source(plan: SolvePlan, per_sample: bool = False) -> str:
    """The source of the plan's compiled kernel (`compile_plan`): the generated loop
    (`source`) rewritten over blocks of samples, branch-free, so that the compiler
    vectorises it (`excavkin.kinematics.vectorise`). Made once per plan object (0.1–0.5 ms
    a time: a tenth of a four-bar solve of 10⁴ samples)."""
    key = (id(plan), per_sample)
    made = _made.get(key)
    if made is not None and made[0] is plan:
        return made[1]
    text = vectorised(source(plan, write_at_rest=False), per_sample)
    if not any(np.ndim(v) for v in constants(plan)):  # (a family's plan holds its arrays)
        if len(_made) >= 16:
            _made.clear()
        _made[key] = (plan, text)
    return text


def job(
    plan: SolvePlan,
    per_sample: bool = False,
    numpy: Callable[[], None] = lambda: None,
    compiled: Callable[[Kernel], None] = lambda kernel: None,
    device: Callable[[Kernel], None] | None = None,
) -> backends.Job:
    """The plan's kinematics as a `excavkin.backends.Job`: its kernel's source, run by
    ``numpy()``, ``compiled(kernel)`` or, on a device, ``device(kernel)`` with the plain
    loop's kernel (`source`; nothing, by default: a job to choose for); a plan of more than
    `AUTO_POINTS` points is not compiled unasked."""
    return backends.Job(
        "kinematics",
        lambda: kernel_source(plan, per_sample),
        numpy,
        compiled,
        unsupported(plan),
        unasked=len(plan.points) <= AUTO_POINTS,
        scalar=lambda: source(plan, write_at_rest=False),
        device=device,
    )


def constants(plan: SolvePlan) -> list[Any]:
    """The plan's dimensions in the order the generated source reads them (floats, or arrays
    of one value per sample)."""
    out: list[Any] = []
    for st in plan.steps:
        if isinstance(st, Fixed):
            for cx, cy in st.coords:
                out += [cx, cy]
        elif isinstance(st, Rotate):
            out.append(st.radius)
        elif isinstance(st, Attach):
            out += [st.s, st.t]
        elif isinstance(st, Dyad):
            out += [_fixed(st.da), _fixed(st.db), st.sign]
        elif isinstance(st, SliderStep):
            out += [_fixed(st.da), st.sign]
    return out


def per_sample(plan: SolvePlan) -> bool:
    """Whether the plan's constants differ from sample to sample (a family of designs)."""
    return any(np.ndim(v) for v in constants(plan))


def _fixed(d: Dist) -> Any:
    return d.value if d.kind == "fixed" else 0.0


def table(values: list[Any], n: int) -> tuple[F, int]:
    """The constants as a (k, m) table and the column stride: m = 1 and stride 0 when every
    constant is one number, else one column per sample."""
    if not any(np.ndim(v) for v in values):
        return np.array(values, dtype=np.float64).reshape(-1, 1), 0
    out = np.empty((len(values), n))
    for k, v in enumerate(values):
        out[k] = v
    return out, 1


def run(
    kernel: Kernel,
    plan: SolvePlan,
    c: Chunk,
    body: F,
    element: F,
    near: F,
    near_step: np.ndarray,
    start: int = 0,
    scalar: bool = False,
) -> None:
    """Solve a chunk with the ``kernel`` of ``plan``'s structure (`compile_plan`), at full
    order: its inputs are ``c.q``, ``c.qd`` and ``c.qdd``; it fills ``c``'s outputs, the derived
    quantities (``body`` and ``element``: `Derived`'s
    arrays) and each sample's nearness to a dead position and nearest step (``near``,
    ``near_step``, as `nearness`). The outputs are the
    whole solve's arrays, in C order; the chunk's samples start at ``start``.

    Bytes not written are bytes not paged in: ``c.v`` and ``c.a`` come zeroed (fresh
    ``np.zeros`` pages cost nothing until written), and a fixed point's rows are left so."""
    k, stride = table(constants(plan), c.q.shape[1])
    run_table(kernel, (k, stride), c, body, element, near, near_step, start, scalar)


def run_table(
    kernel: Kernel,
    consts: tuple[F, int],
    c: Chunk,
    body: F,
    element: F,
    near: F,
    near_step: np.ndarray,
    start: int = 0,
    scalar: bool = False,
) -> None:
    """`run` with the chunk's constants table and stride (`table`) given: a
    whole solve's table is made once, and each chunk takes its columns. ``scalar``: the
    kernel is the plain loop's (`source`, on a device): it takes the outputs' chunk, and no
    ``start``."""
    k, stride = consts
    if scalar:
        part = slice(start, start + c.q.shape[1])
        kernel(
            c.q, c.qd, c.qdd, k, stride, c.x[..., part], c.v[..., part], c.a[..., part],
            c.trans[:, part], body[..., part], element[..., part], c.status[part],
            c.failed[part], c.close_tol, c.singular_tol, near[part], near_step[part],
        )  # fmt: skip
        return
    kernel(
        c.q, c.qd, c.qdd, k, stride, c.x, c.v, c.a, c.trans, body, element,
        c.status, c.failed, c.close_tol, c.singular_tol, near, near_step, start,
    )  # fmt: skip


def compile_plan(plan: SolvePlan, per_sample: bool = False) -> Kernel:
    """The plan's compiled kernel (`kernel_source`): made once per structure, kept in memory
    and on disk (`excavkin.backends.kernel_of`); ``per_sample``: for a constants table with
    a column per sample (`table`'s stride 1), else for one column."""
    return backends.kernel_of(kernel_source(plan, per_sample), "kinematics")


def is_compiled(plan: SolvePlan, per_sample: bool = False) -> bool:
    """Whether the plan's kernel has been compiled, in this process or an earlier one."""
    return backends.is_cached(kernel_source(plan, per_sample))


# ---------------------------------------------------------------------------------------------
# source generation


def source(plan: SolvePlan, *, write_at_rest: bool = True) -> str:
    """The kernel's Python source for ``plan`` (closed-form steps only). ``write_at_rest``
    False: a fixed point's velocity and acceleration rows are left as they come (the kernel
    of `compile_plan`, whose caller hands them in zeroed)."""
    g = _Source(write_at_rest)
    for k, st in enumerate(plan.steps):
        if isinstance(st, Fixed):
            g.fixed(st)
        elif isinstance(st, Rotate):
            g.rotate(st)
        elif isinstance(st, Attach):
            g.attach(st)
        elif isinstance(st, Dyad):
            g.dyad(st, k)
        elif isinstance(st, SliderStep):
            g.slider(st, k)
        else:
            raise TypeError(f"step {k} ({type(st).__name__}) cannot be compiled")
    g.derived(plan)
    g.store(plan)
    return g.text()


_HEAD = (
    '''\
"""Generated by excavkin.kinematics.compiled from a solve plan's structure; do not edit."""
import math

import numba
'''
    + fast_atan2.SOURCE
    + """

# one signature, arrays of any layout (the chunks are strided views): compiled once, at import;
# the inputs and constants are read only (a rate given once for every sample is a broadcast)
A1, A2, A3 = numba.float64[:], numba.float64[:, :], numba.float64[:, :, :]
R2 = numba.types.Array(numba.float64, 2, "A", readonly=True)
SIGNATURE = numba.void(
    R2, R2, R2, R2, numba.int64, A3, A3, A3, A2, A3, A3, numba.int8[:], numba.int16[:],
    numba.float64, numba.float64, A1, numba.int16[:],
)


@numba.njit(SIGNATURE, nogil=True, cache=True, error_model="numpy")
def kernel(q, qd, qdd, K, ks, x, v, a, trans, body, element, status, failed, close_tol,
           singular_tol, near, near_step):
    nan = math.nan
    for i in range(status.shape[0]):
        j = i * ks
        st = status[i]
        fk = failed[i]
"""
)


#: independent sums in the finiteness check
_CHAINS = 8


class _Source:
    """Lines of the loop body, and the count of constants read so far."""

    def __init__(self, write_at_rest: bool = True) -> None:
        self.write_at_rest = write_at_rest
        self.lines: list[str] = []
        self.n_const = 0
        #: (transmission index, plan step) of each dyad and slider
        self.finite: list[tuple[int, int]] = []
        self.n_checks = 0
        #: the derived values as stored (read back by the exact finiteness check)
        self.stored: list[str] = []
        #: the points of the fixed steps: at rest, their velocity and acceleration rows are
        #: left as they come (zero) unless ``write_at_rest``
        self.at_rest: set[int] = set()

    def emit(self, *lines: str) -> None:
        self.lines += lines

    def const(self) -> str:
        self.n_const += 1
        return f"K[{self.n_const - 1}, j]"

    def flag(self, cond: str, code: Code, k: int, indent: str = "") -> None:
        self.emit(
            f"{indent}if ({cond}) and st == 0:",
            f"{indent}    st = {int(code)}",
            f"{indent}    fk = {k}",
        )

    def dist(self, d: Dist, name: str) -> tuple[str, str | None, str | None]:
        """A distance's value and its rates' names (None: a fixed distance, at rest)."""
        value = self.const()
        if d.kind == "fixed":
            self.emit(f"{name} = {value}")
            return name, None, None
        i = d.input
        self.emit(f"{name} = q[{i}, i]", f"{name}d = qd[{i}, i]", f"{name}dd = qdd[{i}, i]")
        return name, f"{name}d", f"{name}dd"

    def fixed(self, st: Fixed) -> None:
        for p in st.points:
            self.at_rest.add(p)
            self.emit(
                f"X{p} = {self.const()}", f"Y{p} = {self.const()}",
                f"VX{p} = 0.0", f"VY{p} = 0.0", f"AX{p} = 0.0", f"AY{p} = 0.0",
            )  # fmt: skip

    def rotate(self, st: Rotate) -> None:
        p, o, i = st.point, st.pivot, st.input
        self.emit(f"r = {self.const()}", f"th = q[{i}, i]")
        if st.ref is not None:
            b0, b1 = st.ref
            self.emit(f"rx = X{b1} - X{b0}", f"ry = Y{b1} - Y{b0}", f"th = th + {ATAN2}(ry, rx)")
        self.emit(
            "cs = math.cos(th)", "sn = math.sin(th)",
            f"X{p} = X{o} + r * cs", f"Y{p} = Y{o} + r * sn",
            f"thd = qd[{i}, i]", f"thdd = qdd[{i}, i]",
        )  # fmt: skip
        if st.ref is not None:
            b0, b1 = st.ref
            self.emit(
                f"rvx = VX{b1} - VX{b0}", f"rvy = VY{b1} - VY{b0}",
                f"rax = AX{b1} - AX{b0}", f"ray = AY{b1} - AY{b0}",
                "r2 = rx * rx + ry * ry",
                "w_ref = (rx * rvy - ry * rvx) / r2",
                "thd = thd + w_ref",
                "thdd = thdd + (rx * ray - ry * rax - 2.0 * (rx * rvx + ry * rvy) * w_ref) / r2",
            )  # fmt: skip
        self.emit(
            f"VX{p} = VX{o} - r * thd * sn", f"VY{p} = VY{o} + r * thd * cs",
            f"AX{p} = AX{o} - r * (thdd * sn + thd * thd * cs)",
            f"AY{p} = AY{o} + r * (thdd * cs - thd * thd * sn)",
        )  # fmt: skip

    def attach(self, st: Attach) -> None:
        p, a, b = st.point, st.a, st.b
        self.emit(f"s = {self.const()}", f"t = {self.const()}")
        for X, Y in (("X", "Y"), ("VX", "VY"), ("AX", "AY")):
            self.emit(
                f"wx = {X}{b} - {X}{a}", f"wy = {Y}{b} - {Y}{a}",
                f"{X}{p} = {X}{a} + s * wx - t * wy", f"{Y}{p} = {Y}{a} + s * wy + t * wx",
            )  # fmt: skip

    def dyad(self, st: Dyad, k: int) -> None:
        p, a, b = st.point, st.a, st.b
        d1, d1d, d1dd = self.dist(st.da, "d1")
        d2, d2d, d2dd = self.dist(st.db, "d2")
        self.emit(
            f"sign = {self.const()}",
            f"ex = X{b} - X{a}", f"ey = Y{b} - Y{a}",
            "l2 = ex * ex + ey * ey",
            "kk = (d1 * d1 - d2 * d2 + l2) / (2.0 * l2)",
            "h2 = d1 * d1 / l2 - kk * kk",
            "if not (h2 >= close_tol):",
            "    size = abs(d1) + abs(d2)",
            "    tiny = 1e-12 * size",
        )  # fmt: skip
        self.flag("not (l2 > tiny * tiny) and abs(d1 - d2) <= tiny", Code.UNDETERMINED, k, "    ")
        self.emit("    if not (h2 >= -close_tol):")
        self.flag("True", Code.NO_CLOSURE, k, "        ")
        self.emit(
            "        h2 = nan",
            "    else:",
            "        h2 = max(h2, 0.0)",
            "h = sign * math.sqrt(h2)",
            f"X{p} = X{a} + kk * ex - h * ey", f"Y{p} = Y{a} + kk * ey + h * ex",
            f"r1x = X{p} - X{a}", f"r1y = Y{p} - Y{a}",
            f"r2x = X{p} - X{b}", f"r2y = Y{p} - Y{b}",
            "det = r1x * r2y - r1y * r2x",
            f"T{st.index} = {ATAN2}(abs(det), r1x * r2x + r1y * r2y)",
            f"S{st.index} = abs(det) / abs(d1 * d2)",
            "if not (abs(det) > singular_tol * abs(d1 * d2)):",
        )  # fmt: skip
        self.flag("True", Code.SINGULAR, k, "    ")
        self.emit(
            "    det = nan",
            "inv = 1.0 / det",
            f"f1 = r1x * VX{a} + r1y * VY{a}" + (f" + {d1} * {d1d}" if d1d else ""),
            f"f2 = r2x * VX{b} + r2y * VY{b}" + (f" + {d2} * {d2d}" if d2d else ""),
            "vpx = (f1 * r2y - f2 * r1y) * inv", "vpy = (r1x * f2 - r2x * f1) * inv",
            f"VX{p} = vpx", f"VY{p} = vpy",
            f"wx = vpx - VX{a}", f"wy = vpy - VY{a}",
            f"ux = vpx - VX{b}", f"uy = vpy - VY{b}",
            f"f1 = r1x * AX{a} + r1y * AY{a}"
            + (f" + {d1} * {d1dd} + {d1d} * {d1d}" if d1d else "") + " - (wx * wx + wy * wy)",
            f"f2 = r2x * AX{b} + r2y * AY{b}"
            + (f" + {d2} * {d2dd} + {d2d} * {d2d}" if d2d else "") + " - (ux * ux + uy * uy)",
            f"AX{p} = (f1 * r2y - f2 * r1y) * inv", f"AY{p} = (r1x * f2 - r2x * f1) * inv",
        )  # fmt: skip
        self.finite.append((st.index, k))

    def slider(self, st: SliderStep, k: int) -> None:
        p, a, l1, l2 = st.point, st.a, st.l1, st.l2
        d, dd, ddd = self.dist(st.da, "d")
        self.emit(
            f"sign = {self.const()}",
            f"ux = X{l2} - X{l1}", f"uy = Y{l2} - Y{l1}",
            "lu = math.sqrt(ux * ux + uy * uy)",
            "ex = ux / lu", "ey = uy / lu",
            f"gx = X{a} - X{l1}", f"gy = Y{a} - Y{l1}",
            "foot = gx * ex + gy * ey",
            "off = ex * gy - ey * gx",
            "s2 = (d * d - off * off) / (d * d)",
            "if not (s2 >= close_tol):",
            "    if not (s2 >= -close_tol):",
        )  # fmt: skip
        self.flag("True", Code.NO_CLOSURE, k, "        ")
        self.emit(
            "        s2 = nan",
            "    else:",
            "        s2 = max(s2, 0.0)",
            "along = foot + sign * abs(d) * math.sqrt(s2)",
            f"X{p} = X{l1} + along * ex", f"Y{p} = Y{l1} + along * ey",
            f"r1x = X{p} - X{a}", f"r1y = Y{p} - Y{a}",
            "dot = ux * r1x + uy * r1y",
            f"T{st.index} = {ATAN2}(abs(dot), abs(ux * r1y - uy * r1x))",
            f"S{st.index} = abs(dot) / (lu * abs(d))",
            "det = -dot",
            "if not (abs(det) > singular_tol * lu * abs(d)):",
        )  # fmt: skip
        self.flag("True", Code.SINGULAR, k, "    ")
        self.emit(
            "    det = nan",
            "inv = 1.0 / det",
            f"gx = X{p} - X{l1}", f"gy = Y{p} - Y{l1}",
            f"udx = VX{l2} - VX{l1}", f"udy = VY{l2} - VY{l1}",
            f"f1 = (ux * VY{l1} - uy * VX{l1}) - (udx * gy - udy * gx)",
            f"f2 = r1x * VX{a} + r1y * VY{a}" + (f" + {d} * {dd}" if dd else ""),
            "vpx = (f1 * r1y - ux * f2) * inv", "vpy = (-uy * f2 - r1x * f1) * inv",
            f"VX{p} = vpx", f"VY{p} = vpy",
            f"gdx = vpx - VX{l1}", f"gdy = vpy - VY{l1}",
            f"uddx = AX{l2} - AX{l1}", f"uddy = AY{l2} - AY{l1}",
            f"wx = vpx - VX{a}", f"wy = vpy - VY{a}",
            f"f1 = (ux * AY{l1} - uy * AX{l1}) - (uddx * gy - uddy * gx)"
            " - 2.0 * (udx * gdy - udy * gdx)",
            f"f2 = r1x * AX{a} + r1y * AY{a}"
            + (f" + {d} * {ddd} + {dd} * {dd}" if dd else "") + " - (wx * wx + wy * wy)",
            f"AX{p} = (f1 * r1y - ux * f2) * inv", f"AY{p} = (-uy * f2 - r1x * f1) * inv",
        )  # fmt: skip
        self.finite.append((st.index, k))

    def check(self, *names: str) -> None:
        """Add each value to the finiteness check's sums (several, so that no long chain of
        additions waits on itself): a sum that is not finite sends the sample to the exact
        check of every value it stored (a sum of finite values may overflow)."""
        for name in names:
            self.emit(f"chk{self.n_checks % _CHAINS} += {name}")
            self.n_checks += 1

    def derived(self, plan: SolvePlan) -> None:
        """Body angle, ω, ε and element length, rate, acceleration, angle, ω, ε
        (`Derived`)."""
        for j, (p0, p1) in enumerate(plan.body_base):
            if j == plan.ground or p0 < 0:
                continue
            self._segment(p0, p1, False)
            self.emit(f"body[0, {j}, i] = ang", f"body[1, {j}, i] = om", f"body[2, {j}, i] = eps")
            self.check("ang", "om", "eps")
            self.stored += [f"body[{k}, {j}, i]" for k in range(3)]
        for j, e in enumerate(plan.elements):
            self._segment(e.p, e.q, True)
            for k, name in enumerate(("ln", "rt", "ac", "ang", "om", "eps")):
                self.emit(f"element[{k}, {j}, i] = {name}")
            self.check("ln", "rt", "ac", "ang", "om", "eps")
            self.stored += [f"element[{k}, {j}, i]" for k in range(6)]

    def _segment(self, p: int, q: int, lengths: bool) -> None:
        self.emit(
            f"rx = X{q} - X{p}", f"ry = Y{q} - Y{p}",
            f"vx = VX{q} - VX{p}", f"vy = VY{q} - VY{p}",
            f"ax = AX{q} - AX{p}", f"ay = AY{q} - AY{p}",
            "r2 = rx * rx + ry * ry",
            "om = (rx * vy - ry * vx) / r2",
            f"ang = {ATAN2}(ry, rx)",
        )  # fmt: skip
        if not lengths:
            self.emit("eps = (rx * ay - ry * ax) / r2")
            return
        self.emit(
            "dot = rx * vx + ry * vy",
            "eps = (rx * ay - ry * ax - 2.0 * dot * om) / r2",
            "ln = math.sqrt(r2)",
            "rt = dot / ln",
            "ac = (rx * ax + ry * ay + vx * vx + vy * vy - rt * rt) / ln",
        )  # fmt: skip

    def store(self, plan: SolvePlan) -> None:
        """Write the points and transmission angles out, and each sample's nearness to a dead
        position; a value not finite on a row still ok is NOT_FINITE."""
        stored = list(self.stored)
        for p in range(len(plan.points)):
            for arr, (X, Y) in (("x", ("X", "Y")), ("v", ("VX", "VY")), ("a", ("AX", "AY"))):
                if arr != "x" and p in self.at_rest and not self.write_at_rest:
                    continue
                self.emit(f"{arr}[{p}, 0, i] = {X}{p}", f"{arr}[{p}, 1, i] = {Y}{p}")
                self.check(f"{X}{p}", f"{Y}{p}")
                stored += [f"{arr}[{p}, 0, i]", f"{arr}[{p}, 1, i]"]
        self.emit("nr = 1.0", "ns = -1")
        for index, k in sorted(self.finite):
            # sin γ: |det| over the product of the sides (NaN is never near)
            t, sg = f"T{index}", f"S{index}"
            self.emit(
                f"trans[{index}, i] = {t}",
                f"if {sg} < nr:", f"    nr = {sg}", f"    ns = {k}",
            )  # fmt: skip
            self.check(t)
            stored.append(f"trans[{index}, i]")
        every = " and ".join(f"math.isfinite({v})" for v in stored)
        self.emit(
            f"chk = {' + '.join(f'chk{m}' for m in range(_CHAINS))}",
            "near[i] = nr",
            "near_step[i] = ns",
            "if st == 0 and not math.isfinite(chk):",
            f"    if not ({every}):",
            f"        st = {int(Code.NOT_FINITE)}",
            "status[i] = st",
            "failed[i] = fk",
        )

    def text(self) -> str:
        body = [f"chk{m} = 0.0" for m in range(_CHAINS)] + self.lines
        return _HEAD + "".join(f"        {line}\n" for line in body)
