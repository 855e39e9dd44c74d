"""A closed-form plan compiled to one machine-code loop over samples (numba).

The NumPy kernels (`excavkin.step_kinds`) run each step over a whole chunk, so a
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

Only a closed-form plan at full order is compiled here (a plan with Newton groups has kernels of
its own, `excavkin.kinematics.compiled_newton`); the precision check's wider solves and the
emulated rounding run in NumPy. Which path a solve takes is decided in one place,
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
from excavkin.step_kinds import Dist, kind_of
from excavkin.structure.plan import SolvePlan
from excavkin.structure.plan_memo import PlanMemo

#: a plan of more points is not compiled unasked: numba's compile takes about a second a point
#: (a kernel of more than `excavkin.kinematics.vectorise.PASS` statements is compiled in
#: passes, one by one: `bench_backends.py --large`), which a batch does not pay back (a kernel
#: compiled before is used all the same)
AUTO_POINTS = 40

#: a plan of more points is not compiled at all (`too_large`): its kernel, compiled in passes,
#: grows about linearly — a chain of 34 points 14 s, of 301 points 4–8 minutes on a loaded
#: machine (`bench_backends.py --large`) — so that one of 1,000 points would take half an
#: hour; NumPy solves such a plan at 60–70 ns a sample a point
COMPILE_POINTS = 1000

#: a cam table's pieces compile as a point's steps do, two pieces for a point (a piece is six
#: lines of the kernel: its knot's test, its weight and its share of five sums)
PIECES_PER_POINT = 2

Kernel = Callable[..., None]
#: the generated code's arctangent: arithmetic, inlined (`excavkin.kinematics.fast_atan2`)
ATAN2 = fast_atan2.NAME


def size(plan: SolvePlan) -> int:
    """The plan's size as the automatic choice weighs it against `AUTO_POINTS`: its points,
    and its cams' table pieces (`PIECES_PER_POINT` to a point).

    Parameters
    ----------
    plan : SolvePlan

    Returns
    -------
    int
    """
    pieces = sum(len(cm.lift) - 1 for cm in plan.model.cams if not callable(cm.lift))
    return len(plan.points) + -(-pieces // PIECES_PER_POINT)


def supports(plan: SolvePlan) -> bool:
    """Whether the plan can be compiled: every step one that compiles (closed-form)."""
    return unsupported(plan) is None


def too_large(points: int) -> str | None:
    """Why a plan or model of ``points`` points (cams' table pieces counted, `size`) is not
    compiled (None: it may be), for `excavkin.backends.Job`: more than `COMPILE_POINTS`.

    Parameters
    ----------
    points : int

    Returns
    -------
    str or None
    """
    if points <= COMPILE_POINTS:
        return None
    return (
        f"of this plan ({points} points) would take the compiler too long: more than "
        f"{COMPILE_POINTS} points are solved in NumPy"
    )


def unsupported(plan: SolvePlan) -> str | None:
    """Why the plan cannot be compiled (None: it can), for `excavkin.backends.Job`."""
    big = too_large(size(plan))
    if big is not None:
        return big
    for st in plan.steps:
        kind = kind_of(st)
        why = kind.uncompiled(st)
        if why is None:
            continue
        if kind.iterative:
            return "of this plan have a Newton group, solved in NumPy"
        return f"of this plan have {why}, solved in NumPy"
    return None


#: the last kernel sources made, by plan of one design: a solve asks twice (is it cached? then
#: run it), and a mechanism solves its one plan again and again
_made: PlanMemo[str] = PlanMemo()


def kernel_source(
    plan: SolvePlan, per_sample: bool = False, by_design: bool = False, keep: bool = False
) -> str:
    """The source of the plan's compiled kernel (`compile_plan`): the generated loop
    (`source`) rewritten over blocks of samples, branch-free, so that the compiler
    vectorises it (`excavkin.kinematics.vectorise`). Made once per plan object (0.1–0.5 ms
    a time: a tenth of a four-bar solve of 10⁴ samples). ``by_design``: its constants table
    has a column per design of a study, each design's poses one after another (`run_designs`).
    ``keep``: `run_designs`' calling convention (the rows kept, the far samples' tops) with
    the constants as ``per_sample`` reads them (`excavkin.kinematics.vectorise.vectorised`)."""
    key = (per_sample, by_design, keep)
    made = _made.get(plan, key)
    if made is not None:
        return made
    text = vectorised(source(plan, write_at_rest=False), per_sample, by_design, keep)
    if not any(np.ndim(v) for v in constants(plan)):  # (a family's plan holds its arrays)
        _made.put(plan, text, key)
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
    `AUTO_POINTS` points (its `size`, cams' tables counted) is not compiled unasked, and one
    whose kernel is `split` is solved in NumPy unless a backend is named."""
    return backends.Job(
        "kinematics",
        lambda: kernel_source(plan, per_sample),
        numpy,
        compiled,
        unsupported(plan),
        unasked=size(plan) <= AUTO_POINTS,
        scalar=lambda: source(plan, write_at_rest=False),
        device=device,
        slower=lambda: split(kernel_source(plan, per_sample)),
    )


def split(text: str) -> bool:
    """Whether a generated kernel is split into a kernel for each pass
    (`excavkin.kinematics.vectorise.SPLIT_PASSES`): a large plan's, which compiles in a time
    that grows with its length but runs slower than NumPy (a 300-point chain 16 against 7 µs a
    sample), so that ``backend="auto"`` solves it in NumPy.

    Parameters
    ----------
    text : str
        The kernel's source (`kernel_source`).

    Returns
    -------
    bool
    """
    return "\ndef pass0_(" in text


def constants(plan: SolvePlan) -> list[Any]:
    """The plan's dimensions in the order the generated source reads them (floats, or arrays
    of one value per sample)."""
    out: list[Any] = []
    for st in plan.steps:
        out += kind_of(st).constants(st)
    return out


def per_sample(plan: SolvePlan) -> bool:
    """Whether the plan's constants differ from sample to sample (a family of designs)."""
    return any(np.ndim(v) for v in constants(plan))


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


def run_designs(
    kernel: Kernel,
    consts: F,
    poses: int,
    first: int,
    c: Chunk,
    body: F,
    element: F,
    near: F,
    near_step: np.ndarray,
    keep: np.ndarray,
    tops: np.ndarray,
    near_at: float,
    start: int = 0,
) -> None:
    """`run_table` for consecutive samples of a study (designs × ``poses``, design-major),
    with the kernel made ``by_design`` (`kernel_source`): ``consts`` is the constants table
    (`table`) of the designs from the chunk's first sample's on, one column a design, and
    ``first`` that sample's pose. The outputs' sample ``start`` is the chunk's first. A
    kernel made with ``keep`` (a solve of some columns) runs the same way, ``consts`` and
    ``poses`` as `run_table`'s table and stride, ``first`` unread.

    Parameters
    ----------
    kernel : callable
        The plan's kernel, compiled from ``kernel_source(plan, by_design=True)`` (or
        ``kernel_source(plan, per_sample, keep=True)``).
    consts : ndarray, shape (k, designs)
        The constants, a column per design, the chunk's first sample's design first.
    poses : int
        Poses per design.
    first : int
        The chunk's first sample's pose (0 … poses − 1).
    c : Chunk
        The inputs and outputs, as `run` takes them.
    body, element : ndarray
        The derived quantities' arrays (`Derived`), the chunk's samples.
    near : ndarray, shape (n,)
    near_step : ndarray of int16, shape (n,)
        Each sample's nearness to a dead position and nearest step.
    keep : ndarray of int8, shape (scratch rows,)
        Which of the kernel's rows (`excavkin.kinematics.vectorise.written_rows`) are
        written out (1) and which not (0: that row of the outputs is left as it is); the
        statuses and nearness always are.
    tops : ndarray of int64, shape (6,)
        Raised to each kind of quantity's (`excavkin.kinematics.precision.KINDS`) largest
        magnitude over the samples solved and no nearer a dead position than ``near_at``
        (every row, kept or not), as a float's bits.
    near_at : float
        The precision check's threshold (`excavkin.kinematics.precision.NEAR`).
    start : int
        The outputs' sample that the chunk's first is (they may be a whole pose set's).
    """
    kernel(
        c.q, c.qd, c.qdd, consts, poses, c.x, c.v, c.a, c.trans, body, element,
        c.status, c.failed, c.close_tol, c.singular_tol, near, near_step, start, first,
        keep, tops, near_at,
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
    g = Source(write_at_rest)
    for k, st in enumerate(plan.steps):
        kind_of(st).emit(g, st, k)  # a kind that does not compile raises TypeError
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


class Source:
    """Lines of the loop body, and the count of constants read so far: what each step kind's
    ``emit`` (`excavkin.step_kinds`) writes its source through."""

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
        #: the two-argument arctangent's name (`fast_atan2`), for the step kinds' source
        self.atan2 = ATAN2

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
        if d.winch:  # a winch: the blocks' distance from its motor's angle (the constant)
            k = value
            self.emit(
                f"{name} = {k} * q[{i}, i]",
                f"{name}d = {k} * qd[{i}, i]",
                f"{name}dd = {k} * qdd[{i}, i]",
            )
            return name, f"{name}d", f"{name}dd"
        self.emit(f"{name} = q[{i}, i]", f"{name}d = qd[{i}, i]", f"{name}dd = qdd[{i}, i]")
        return name, f"{name}d", f"{name}dd"

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
