"""A closed-form plan compiled to one machine-code loop over samples (numba, optional).

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

Only a closed-form plan at full order is compiled; Newton groups, the precision check's wider
solves and the emulated rounding run in NumPy.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import os
import sys
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.kinematics import fast_atan2
from excavkin.kinematics.kernels import Chunk, Code
from excavkin.kinematics.vectorise import vectorised
from excavkin.step_kinds import Dist, kind_of
from excavkin.structure.plan import SolvePlan

#: below this many samples the NumPy path is used: a compiled call saves little there
THRESHOLD = 1 << 17
#: a kernel not yet compiled costs 5–20 s to compile (the four-bar's, the excavator's); it is
#: compiled unasked only for a batch this large, where it saves about as much (0.05–0.15 µs a
#: sample), and it is kept on disk for every later solve
COMPILE_AT = 20_000_000
#: a plan of more points is not compiled unasked: numba's compile time and memory grow faster
#: than the kernel's length (a 68-point chain's kernel took minutes and 4 GB), and one kernel
#: per plan has no way to split it yet
AUTO_POINTS = 40

Kernel = Callable[..., None]
#: the generated code's arctangent: arithmetic, inlined (`excavkin.kinematics.fast_atan2`)
ATAN2 = fast_atan2.NAME

_lock = threading.Lock()
_kernels: dict[str, Kernel] = {}


def available() -> bool:
    """Whether numba can be imported (``EXCAVKIN_COMPILED=0`` turns the compiled path off)."""
    if os.environ.get("EXCAVKIN_COMPILED", "") == "0":
        return False
    return importlib.util.find_spec("numba") is not None


def numba_installed() -> bool:
    """Whether numba can be imported (whatever ``EXCAVKIN_COMPILED`` says)."""
    return importlib.util.find_spec("numba") is not None


def supports(plan: SolvePlan) -> bool:
    """Whether the plan can be compiled: every step of a kind that compiles (closed-form)."""
    return all(kind_of(st).compiles for st in plan.steps)


def use(plan: SolvePlan, n: int, compiled: bool | None, per_sample: bool = False) -> bool:
    """Whether a solve of ``n`` samples takes the compiled path (``compiled`` None: when numba
    is installed and the batch is large — `THRESHOLD` for a kernel already compiled,
    `COMPILE_AT` for one to compile — and the plan has at most `AUTO_POINTS` points);
    ``per_sample``: the kernel for a constants table
    of a column per sample (`compile_plan`)."""
    if compiled is None:
        if n < THRESHOLD or len(plan.points) > AUTO_POINTS or not supports(plan):
            return False
        if not available():
            return False
        return n >= COMPILE_AT or is_compiled(plan, per_sample)
    if compiled and not (supports(plan) and importlib.util.find_spec("numba") is not None):
        from excavkin.errors import InputError

        why = "has a Newton group" if not supports(plan) else "needs numba"
        raise InputError(
            f"compiled=True: this plan {why} (pip install 'excavkin[fast]' for numba); "
            "leave compiled unset to choose automatically"
        )
    return compiled


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
    run_table(kernel, (k, stride), c, body, element, near, near_step, start)


def run_table(
    kernel: Kernel,
    consts: tuple[F, int],
    c: Chunk,
    body: F,
    element: F,
    near: F,
    near_step: np.ndarray,
    start: int = 0,
) -> None:
    """`run` with the chunk's constants table and stride (`table`) given: a
    whole solve's table is made once, and each chunk takes its columns."""
    k, stride = consts
    kernel(
        c.q, c.qd, c.qdd, k, stride, c.x, c.v, c.a, c.trans, body, element,
        c.status, c.failed, c.close_tol, c.singular_tol, near, near_step, start,
    )  # fmt: skip


def compile_plan(plan: SolvePlan, per_sample: bool = False) -> Kernel:
    """The plan's compiled kernel: made once per structure, kept in memory and on disk (numba
    compiles it at its first call). It is the generated loop (`source`) rewritten over
    blocks of samples, branch-free, so that the compiler vectorises it
    (`excavkin.kinematics.vectorise`); ``per_sample``: for a constants table with a
    column per sample (`table`'s stride 1), else for one column."""
    return kernel_of(vectorised(source(plan, write_at_rest=False), per_sample))


def is_compiled(plan: SolvePlan, per_sample: bool = False) -> bool:
    """Whether the plan's kernel has been compiled, in this process or an earlier one."""
    return source_compiled(vectorised(source(plan, write_at_rest=False), per_sample))


def kernel_of(text: str) -> Kernel:
    """The ``kernel`` function of a generated source: imported once, kept in memory and on
    disk (a source made by another module's generator, too)."""
    key = _key(text)
    with _lock:
        kernel = _kernels.get(key)
        if kernel is None:
            kernel = _load(text, key)
            _kernels[key] = kernel
            with contextlib.suppress(OSError):  # what a later process's is_compiled reads
                (cache_dir() / f"excavkin_kernel_{key}.compiled").touch()
    return kernel


def source_compiled(text: str) -> bool:
    """Whether a generated source's kernel has been compiled, here or in an earlier process."""
    key = _key(text)
    return key in _kernels or (cache_dir() / f"excavkin_kernel_{key}.compiled").exists()


def _key(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def cache_dir() -> Path:
    """Where generated kernels and numba's machine code are kept between runs."""
    base = os.environ.get("EXCAVKIN_CACHE_DIR") or os.environ.get("XDG_CACHE_HOME")
    root = Path(base) if base else Path.home() / ".cache"
    return (root if os.environ.get("EXCAVKIN_CACHE_DIR") else root / "excavkin") / "kernels"


def _load(text: str, key: str) -> Kernel:
    """Import the source from the cache folder (numba caches the machine code beside it); if the
    folder cannot be written, compile in memory for this process only."""
    name = f"excavkin_kernel_{key}"
    try:
        folder = cache_dir()
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / f"{name}.py"
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            tmp = folder / f".{name}.{os.getpid()}.tmp"
            tmp.write_text(text, encoding="utf-8")
            os.replace(tmp, path)
        spec = importlib.util.spec_from_file_location(name, path)
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
        return module.kernel  # type: ignore[no-any-return]
    except OSError:
        scope: dict[str, Any] = {}
        exec(compile(text.replace("cache=True", "cache=False"), name, "exec"), scope)
        return scope["kernel"]  # type: ignore[no-any-return]


# ---------------------------------------------------------------------------------------------
# source generation


def source(plan: SolvePlan, *, write_at_rest: bool = True) -> str:
    """The kernel's Python source for ``plan`` (closed-form steps only). ``write_at_rest``
    False: a fixed point's velocity and acceleration rows are left as they come (the kernel
    of `compile_plan`, whose caller hands them in zeroed)."""
    g = _Source(write_at_rest)
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


class _Source:
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
