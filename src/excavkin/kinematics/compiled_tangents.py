"""Design sensitivities as one compiled loop: the compiled plan's source differentiated forward.

The compiled plan (`excavkin.kinematics.compiled`) is the straight-line source of one
loop over samples, every dimension read from a constants table. Here that source is
differentiated, statement by statement, in forward mode: each expression is cut into single
operations (the same operations, in the same order), every value is computed once per sample,
and then, for each of the k parameters in turn, a second straight-line pass carries one
tangent per value by the chain rule — ``d(a·b) = da·b + a·db``, ``d√a = da / (2√a)``, … —
from the seeds ``∂(constant)/∂(parameter)`` of the constants table and of a held driver's
sketch value. The seeds are the tangents of `vary` run on
dual numbers (`excavkin.kinematics.dual`), as the NumPy path has them: a sketch
coordinate, a length, an attachment coefficient that depends on several sketch coordinates.
A branch of the source (a dyad near its dead position, a singular step) is taken on the
values, as the NumPy kernels' masks are.

The NumPy path (`excavkin.kinematics.sensitivity`) stays the reference: the tests hold
the two to 1e-13 of each column's scale. Rows that did not solve get NaN, as there. Only a
closed-form plan is compiled; Newton groups' tangents run in NumPy.
"""

from __future__ import annotations

import ast
import functools
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from excavkin import backends
from excavkin.arrays import FloatArray as F
from excavkin.kinematics import compiled as compiled_plan
from excavkin.kinematics import fast_atan2
from excavkin.kinematics.dual import Dual, seed
from excavkin.kinematics.one_at_a_time import one_at_a_time
from excavkin.kinematics.threads import over_chunks
from excavkin.structure.design import take, vary
from excavkin.structure.plan import SolvePlan

if TYPE_CHECKING:
    from excavkin.kinematics.result import KinematicResult

#: samples per kernel call (a thread's share of the work at a time)
CHUNK = 16384

#: a plan of more points (`excavkin.kinematics.compiled.size`) has its tangents solved in
#: NumPy: the tangent kernel is one loop, not yet cut into kernels compiled one by one as the
#: kinematic and forces kernels are, and numba's compile of one loop grows faster than its
#: length
COMPILE_POINTS = 100


def unsupported(plan: SolvePlan) -> str | None:
    """Why the plan's tangents cannot be compiled (None: they can): the plan's own reason
    (`excavkin.kinematics.compiled.unsupported`), or more than `COMPILE_POINTS` points.

    Parameters
    ----------
    plan : SolvePlan

    Returns
    -------
    str or None
    """
    points = compiled_plan.size(plan)
    if points > COMPILE_POINTS:
        return (
            f"of this plan ({points} points) would take the compiler too long: more than "
            f"{COMPILE_POINTS} points are solved in NumPy"
        )
    return compiled_plan.unsupported(plan)


#: the NumPy tangent path's tolerances for its own masks (the solve's statuses decide the rest)
CLOSE_TOL, SINGULAR_TOL = 1e-10, 1e-7

Kernel = Callable[..., None]
#: tangent array → the entries (indices before the sample's) to write
Keep = dict[str, set[tuple[int, ...]]]


class Outputs(Protocol):
    """The tangent arrays a solve fills (`_Tangents`)."""

    x: F
    v: F
    a: F
    q: F
    trans: F
    body: F
    element: F


def is_compiled(plan: SolvePlan, keep: Keep | None = None) -> bool:
    """Whether the plan's tangent kernel has been compiled, in this process or an earlier one."""
    return backends.is_cached(source(plan, keep))


def compile_tangents(plan: SolvePlan, keep: Keep | None = None) -> Kernel:
    """The plan's tangent kernel (of the entries ``keep``, default all): made once per
    structure, kept in memory and on disk (`excavkin.backends.kernel_of`)."""
    return backends.kernel_of(source(plan, keep), "tangents")


def fill(
    out: Outputs,
    plan: SolvePlan,
    inputs: tuple[F, F, F],
    names: Sequence[str],
    given: dict[str, Any],
    base: dict[str, Any],
    workers: int | None = None,
    keep: Keep | None = None,
    kernel: Kernel | None = None,
) -> None:
    """Fill ``out`` with the tangents of every sample's state with respect to ``names`` (of
    the entries ``keep`` only, if given: the others stay 0).

    Parameters
    ----------
    out : Outputs
        Arrays of shape (k, …, n) of zeros, written for every sample where a derivative is
        not identically 0 (a fixed point's velocity is not).
    plan : SolvePlan
        The solved result's plan (its per-sample branch signs included).
    inputs : tuple of ndarray
        The drivers' values, rates and accelerations, each (n_inputs, n).
    names : sequence of str
        The parameters, in the order of the tangents' leading axis.
    given : dict
        The parameters given per sample (arrays of shape (n,)) or for all (scalars).
    base : dict
        Each of ``names`` at its value (nominal, or as given).
    workers : int, optional
        Threads (default: one per core).
    keep : Keep, optional
        The entries to fill (default: all).
    kernel : callable, optional
        The tangent kernel of ``plan`` and ``keep`` (default: `compile_tangents`).
    """
    q, qd, qdd = inputs
    n, m = q.shape[1], len(names)
    if kernel is None:
        kernel = compile_tangents(plan, keep)
    per_sample = any(np.ndim(v) for v in (*given.values(), *base.values()))
    # one design: its seeds are computed once, on one sample
    nominal = None if per_sample else _Seeds(plan, given, base, names, 1)

    def one(s: int) -> None:
        part = slice(s, min(s + CHUNK, n))
        if nominal is None:
            cut = {k: v[part] if np.ndim(v) else v for k, v in given.items()}
            own = {k: v[part] if np.ndim(v) else v for k, v in base.items()}
            seeds = _Seeds(take(plan, part), cut, own, names, part.stop - s)
            tables = seeds.tables(slice(None), m)
        else:
            tables = nominal.tables(part, m, n)
        kernel(
            q[:, part], qd[:, part], qdd[:, part], *tables, CLOSE_TOL, SINGULAR_TOL,
            out.x[..., part], out.v[..., part], out.a[..., part], out.q[..., part],
            out.trans[..., part], out.body[..., part], out.element[..., part],
        )  # fmt: skip

    over_chunks(n, CHUNK, workers, one)


#: a result's arrays and the tangent arrays the compiled kernel writes them to; the drivers'
#: rates and accelerations do not depend on the design (their tangents are 0 throughout)
_FIELDS: tuple[tuple[str, str, int | None], ...] = (
    ("positions", "tx", None), ("velocities", "tv", None), ("accelerations", "ta", None),
    ("body_angle", "tbody", 0), ("body_omega", "tbody", 1), ("body_epsilon", "tbody", 2),
    ("inputs", "tq", None), ("input_rates", "", None), ("input_accels", "", None),
    ("element_length", "telement", 0), ("element_rate", "telement", 1),
    ("element_accel", "telement", 2), ("element_angle", "telement", 3),
    ("element_omega", "telement", 4), ("element_epsilon", "telement", 5),
    ("transmission", "ttrans", None),
)  # fmt: skip


def entries(result: KinematicResult, columns: Sequence[str]) -> Keep:
    """The tangent arrays' entries that hold the derivatives of ``columns``: read from the
    result's own column layout (each array of a one-row copy numbered, then its columns
    read back), so that the two never disagree. An unknown column is an error naming it."""
    import dataclasses

    one = result.rows(0, 1)
    where: list[tuple[str, tuple[int, ...]]] = []
    coded: dict[str, Any] = {}
    for name, store, lead in _FIELDS:
        shape = np.shape(getattr(one, name))[1:]
        codes = np.arange(len(where), len(where) + int(np.prod(shape)), dtype=np.float64)
        for idx in np.ndindex(*shape):
            where.append((store, idx if lead is None else (lead, *idx)))
        coded[name] = codes.reshape(1, *shape)
    numbered = dataclasses.replace(one, time=None, parameters=None, tangents=None, **coded)
    found = {c.name: arr for c, arr in numbered._columns()}
    keep: Keep = {}
    for name in columns:
        if name not in found:
            from excavkin.errors import unknown_name

            raise unknown_name("column", name, list(found))
        store, idx = where[int(found[name][0])]
        if store:
            keep.setdefault(store, set()).add(idx)
    return keep


class _Seeds:
    """The constants table and the held drivers' sketch values, with their tangents."""

    def __init__(
        self,
        plan: SolvePlan,
        given: dict[str, Any],
        base: dict[str, Any],
        names: Sequence[str],
        size: int,
    ) -> None:
        duals: dict[str, Any] = {**given, **seed(base, list(names), size)}
        with np.errstate(divide="ignore", invalid="ignore"):
            varied, held, _ = vary(plan, duals)
        self.constants = compiled_plan.constants(varied)
        self.held = [h if isinstance(h, Dual) else Dual(np.nan, 0.0) for h in held]

    def tables(self, part: slice, m: int, n: int | None = None) -> tuple[F, F, int, F, F, int]:
        """K, its tangents KT (k, m, columns) and the column stride; the held values HV, their
        tangents HT and stride. ``n``: entries of that length hold every sample (a smooth
        continuation's branch signs) and are cut to ``part``."""
        k, kt, ks = _table(self.constants, part, m, n)
        h, ht, hs = _table(self.held, part, m, n)
        return k, kt, ks, h, ht, hs


def _table(entries: list[Any], part: slice, m: int, n: int | None) -> tuple[F, F, int]:
    """Values (k, columns) and tangents (k, m, columns) of the entries, one column for all
    samples (stride 0) when none varies, else one per sample of ``part``."""
    vals, tans = [], []
    for e in entries:
        val = np.asarray(e.val if isinstance(e, Dual) else e, dtype=np.float64)
        tan = np.asarray(e.tan if isinstance(e, Dual) else 0.0, dtype=np.float64)
        if n is not None and val.ndim and val.shape[-1] == n:
            val = val[..., part]
        if n is not None and tan.ndim > 1 and tan.shape[-1] == n:
            tan = tan[..., part]
        vals.append(val)
        tans.append(tan)
    widths = {v.size for v in vals} | {t.shape[-1] for t in tans if t.ndim > 1}
    cols = max(widths, default=1)
    out = np.empty((len(entries), cols))
    tout = np.zeros((len(entries), m, cols))
    for i, (val, tan) in enumerate(zip(vals, tans, strict=True)):
        out[i] = val.reshape(-1)
        tout[i] = tan if tan.ndim == 0 else tan.reshape(m, -1)
    return out, tout, 1 if cols > 1 else 0


# ---------------------------------------------------------------------------------------------
# source generation


def source(plan: SolvePlan, keep: Keep | None = None) -> str:
    """The tangent kernel's Python source for ``plan`` (closed-form steps only); with
    ``keep``, only those tangent arrays' entries are written (the compiler then drops what
    only the others needed)."""
    frozen = None if keep is None else tuple(sorted((k, tuple(sorted(v))) for k, v in keep.items()))
    return _source(compiled_plan.source(plan), len(plan.inputs), frozen)


@functools.lru_cache(maxsize=64)
@one_at_a_time
def _source(text: str, inputs: int, frozen: tuple[tuple[str, tuple[Any, ...]], ...] | None) -> str:
    """`source` from the compiled plan's source (the same text: the same kernel)."""
    keep = None if frozen is None else {k: set(v) for k, v in frozen}
    loop = _loop_body(text)
    d = _Differ(keep)
    for st in loop:
        d.statement(st)
    for k in range(inputs):
        if keep is None or (k,) in keep.get("tq", ()):
            d.out2.append(f"tq[p_, {k}, i] = {_held(k)}")
    return (
        _HEAD
        + "".join(f"        {line}\n" for line in d.out1)
        + "        for p_ in range(m):\n"
        + "".join(f"            {line}\n" for line in d.out2)
    )


_HEAD = (
    '''\
"""Generated by excavkin.kinematics.compiled_tangents from a solve plan's structure; do not
edit."""
import math

import numba
'''
    + fast_atan2.SOURCE
    + """

# arrays of any layout (the chunks are strided views): compiled once, at import; the inputs
# and constants are read only (a rate given once for every sample is a broadcast)
A2, A3, A4 = numba.float64[:, :], numba.float64[:, :, :], numba.float64[:, :, :, :]
R2, R3 = (numba.types.Array(numba.float64, d, "A", readonly=True) for d in (2, 3))
SIGNATURE = numba.void(
    R2, R2, R2, R2, R3, numba.int64, A2, A3, numba.int64, numba.float64, numba.float64,
    A4, A4, A4, A3, A3, A4, A4,
)


@numba.njit(SIGNATURE, nogil=True, cache=True, error_model="numpy")
def kernel(q, qd, qdd, K, KT, ks, HV, HT, hs, close_tol, singular_tol, tx, tv, ta, tq, ttrans,
           tbody, telement):
    nan = math.nan
    m = KT.shape[1]
    for i in range(q.shape[1]):
        jh = i * hs
"""
)


def _loop_body(text: str) -> list[ast.stmt]:
    """The statements of the compiled plan's loop over samples."""
    tree = ast.parse(text)
    fn = next(f for f in tree.body if isinstance(f, ast.FunctionDef) and f.name == "kernel")
    loop = next(s for s in ast.walk(fn) if isinstance(s, ast.For))
    return loop.body


def _held(k: int) -> str:
    """A driver's tangent: its sketch value's where it is held there, else 0."""
    return f"(HT[{k}, p_, jh] if q[{k}, i] == HV[{k}, jh] else 0.0)"


#: the arrays of results and the tangent arrays they become
_STORES = {"x": "tx", "v": "tv", "a": "ta", "trans": "ttrans", "body": "tbody"}
_STORES["element"] = "telement"
#: bookkeeping of statuses, nearness and the finiteness check: no tangents
_SKIP = {"st", "fk", "nr", "ns", "chk"}
_OPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/"}


def _skipped(name: str) -> bool:
    return name in _SKIP or name.startswith("chk")


def _kept(st: ast.stmt) -> bool:
    """Whether a statement computes a value or stores a result (not status bookkeeping)."""
    if isinstance(st, ast.Assign | ast.AugAssign):
        target = st.targets[0] if isinstance(st, ast.Assign) else st.target
        if isinstance(target, ast.Name):
            return not _skipped(target.id)
        return (
            isinstance(target, ast.Subscript)
            and isinstance(target.value, ast.Name)
            and target.value.id in _STORES
        )
    if isinstance(st, ast.If):
        return any(_kept(s) for s in (*st.body, *st.orelse))
    raise NotImplementedError(f"cannot differentiate {ast.unparse(st)!r}")


def _assigned(stmts: Sequence[ast.stmt]) -> Iterator[str]:
    for st in stmts:
        if not _kept(st):
            continue
        if isinstance(st, ast.If):
            yield from _assigned([*st.body, *st.orelse])
        elif isinstance(st, ast.Assign) and isinstance(st.targets[0], ast.Name):
            yield st.targets[0].id
        elif isinstance(st, ast.AugAssign) and isinstance(st.target, ast.Name):
            yield st.target.id


class _Differ:
    """Writes the values' pass (``out1``: each operation once, in single assignments) and the
    tangents' pass (``out2``: one tangent per value, for the parameter ``p_``)."""

    def __init__(self, keep: Keep | None = None) -> None:
        self.keep = keep
        self.out1: list[str] = []
        self.out2: list[str] = []
        self.indent = ""
        #: each source name → the value it holds now (a temporary, literal or argument)
        self.bound: dict[str, str] = {}
        #: each value → its tangent's name (None: it does not depend on the parameters)
        self.tan: dict[str, str | None] = {}
        #: operations already computed (and whether without a tangent) → their value
        self.seen: dict[str, str] = {}
        self.count = 0

    def new(self, stem: str = "t") -> str:
        self.count += 1
        return f"{stem}_{self.count}"

    def emit(self, value: str | None, tangent: str | None) -> None:
        if value is not None:
            self.out1.append(self.indent + value)
        if tangent is not None:
            self.out2.append(self.indent + tangent)

    # ---- statements
    def statement(self, st: ast.stmt) -> None:
        if not _kept(st):
            return
        if isinstance(st, ast.If):
            self.branch(st)
            return
        target: ast.expr
        if isinstance(st, ast.AugAssign):
            target = st.target
            value: ast.expr = ast.BinOp(ast.Name(ast.unparse(target)), st.op, st.value)
        else:
            assert isinstance(st, ast.Assign)
            target, value = st.targets[0], st.value
        val, tan = self.expr(value)
        if isinstance(target, ast.Name):
            self.bound[target.id] = val
            return
        assert isinstance(target, ast.Subscript) and isinstance(target.value, ast.Name)
        index = self.rename(target.slice)
        elts = index.elts if isinstance(index, ast.Tuple) else [index]
        index_text = ", ".join(ast.unparse(e) for e in elts)
        store = _STORES[target.value.id]
        if self.keep is not None:
            at = tuple(int(ast.unparse(e)) for e in elts[:-1])
            if at not in self.keep.get(store, ()):
                return
        if tan is not None:  # else 0, as the arrays are made (their pages never touched)
            self.emit(None, f"{store}[p_, {index_text}] = {tan}")

    def branch(self, st: ast.If) -> None:
        """An ``if``: the names it assigns become variables set on either branch (their
        tangents likewise), the condition read on the values."""
        names = list(dict.fromkeys(_assigned([st])))
        phis: dict[str, str] = {}
        for name in names:
            phi = phis[name] = self.new(name)
            before = self.bound.get(name, "nan")
            dbefore = self.tan.get(before)
            self.emit(f"{phi} = {before}", f"d{phi} = {dbefore or '0.0'}")
            self.tan[phi] = f"d{phi}"
        test = ast.unparse(self.rename(st.test))
        self.emit(f"if {test}:", f"if {test}:")
        self.arm(st.body, phis)
        if any(_kept(s) for s in st.orelse):
            self.emit("else:", "else:")
            self.arm(st.orelse, phis)
        self.bound.update(phis)

    def arm(self, stmts: Sequence[ast.stmt], phis: dict[str, str]) -> None:
        outer_indent, outer_bound, outer_seen = self.indent, dict(self.bound), dict(self.seen)
        self.bound.update(phis)
        self.indent += "    "
        for s in stmts:
            self.statement(s)
        for name, phi in phis.items():
            now = self.bound[name]
            if now != phi:
                self.emit(f"{phi} = {now}", f"d{phi} = {self.tan.get(now) or '0.0'}")
        self.emit("pass", "pass")
        self.indent, self.bound, self.seen = outer_indent, outer_bound, outer_seen

    def rename(self, node: ast.expr) -> ast.expr:
        """The expression with each source name replaced by the value it holds."""
        bound = self.bound

        class Rename(ast.NodeTransformer):
            def visit_Name(self, n: ast.Name) -> ast.expr:
                return ast.Name(bound.get(n.id, n.id), ctx=ast.Load())

        return Rename().visit(ast.parse(ast.unparse(node), mode="eval").body)  # type: ignore[no-any-return]

    # ---- expressions: (value, tangent or None)
    def expr(self, node: ast.expr) -> tuple[str, str | None]:
        if isinstance(node, ast.Constant):
            return repr(node.value), None
        if isinstance(node, ast.Name):
            val = self.bound.get(node.id, node.id)
            return val, self.tan.get(val)
        if isinstance(node, ast.Subscript):
            return self.read(node)
        if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
            (a, da), (b, db) = self.expr(node.left), self.expr(node.right)
            return self.binary(_OPS[type(node.op)], a, da, b, db)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            a, da = self.expr(node.operand)
            return self.op(f"-{a}", da and f"-{da}")
        if isinstance(node, ast.Call):
            return self.call(node)
        if isinstance(node, ast.Compare):  # a test (1 or 0 in arithmetic): no tangent
            return self.op(ast.unparse(self.rename(node)), None)
        raise NotImplementedError(f"cannot differentiate {ast.unparse(node)!r}")

    def op(self, value: str, tangent: str | Callable[[str], str] | None) -> tuple[str, str | None]:
        """A value (one operation on values already named), and its tangent (or a function of
        the value's name giving it)."""
        # a helper (no tangent) is not the same value as an operation with one: 1 / b
        key = f"{tangent is None} {value}"
        if self.indent == "" and key in self.seen:
            out = self.seen[key]
            return out, self.tan[out]
        name = self.new()
        dname = None if tangent is None else f"d{name}"
        if callable(tangent):
            tangent = tangent(name)
        self.emit(f"{name} = {value}", None if tangent is None else f"{dname} = {tangent}")
        self.tan[name] = dname
        if self.indent == "":
            self.seen[key] = name
        return name, dname

    def helper(self, value: str) -> str:
        """A value the tangents need (a reciprocal, a cosine), computed once per sample."""
        return self.op(value, None)[0]

    def read(self, node: ast.Subscript) -> tuple[str, str | None]:
        assert isinstance(node.value, ast.Name)
        array = node.value.id
        text = ast.unparse(self.rename(node))
        if array == "K":
            idx = self.rename(node.slice)
            assert isinstance(idx, ast.Tuple)
            c, j = (ast.unparse(e) for e in idx.elts)
            return self.op(text, f"KT[{c}, p_, {j}]")
        if array == "q":
            idx = node.slice
            assert isinstance(idx, ast.Tuple) and isinstance(idx.elts[0], ast.Constant)
            return self.op(text, _held(int(ast.unparse(idx.elts[0]))))
        if array in ("qd", "qdd"):
            return self.op(text, None)
        raise NotImplementedError(f"cannot differentiate a read of {array!r}")

    def binary(
        self, op: str, a: str, da: str | None, b: str, db: str | None
    ) -> tuple[str, str | None]:
        value = f"{a} {op} {b}"
        if da is None and db is None:
            return self.op(value, None)
        if op in "+-":
            if db is None:
                return self.op(value, da)
            return self.op(value, f"{da} {op} {db}" if da else f"-{db}" if op == "-" else db)
        if op == "*":
            terms = [f"{da} * {b}" if da else "", f"{a} * {db}" if db else ""]
            return self.op(value, " + ".join(t for t in terms if t))
        # a / b: (da − (a / b)·db) / b
        inv = self.helper(f"1.0 / {b}")
        if db is None:
            return self.op(value, f"{da} * {inv}")
        if da is None:
            return self.op(value, lambda out: f"-({out} * {db}) * {inv}")
        return self.op(value, lambda out: f"({da} - {out} * {db}) * {inv}")

    def call(self, node: ast.Call) -> tuple[str, str | None]:
        fn = ast.unparse(node.func)
        args = [self.expr(a) for a in node.args]
        vals = ", ".join(a for a, _ in args)
        value = f"{fn}({vals})"
        if all(d is None for _, d in args):
            return self.op(value, None)
        (a, da), *rest = args
        if fn == "math.sqrt":
            half = self.helper(f"0.5 / {fn}({a})")
            return self.op(value, f"{da} * {half}")
        if fn == "math.cos":
            return self.op(value, f"-{self.helper(f'math.sin({a})')} * {da}")
        if fn == "math.sin":
            return self.op(value, f"{self.helper(f'math.cos({a})')} * {da}")
        if fn == "math.floor":  # piecewise constant: its tangent is 0 (a cam's whole turns)
            return self.op(value, None)
        if fn == "abs":
            sign = self.helper(f"(1.0 if {a} > 0.0 else -1.0 if {a} < 0.0 else 0.0)")
            return self.op(value, f"{sign} * {da}")
        if fn == fast_atan2.NAME:  # atan2(y, x)' = (x·dy − y·dx) / (x² + y²)
            (x, dx) = rest[0]
            inv = self.helper(f"1.0 / ({x} * {x} + {a} * {a})")
            terms = [f"{x} * {da}" if da else "", f"{a} * {dx}" if dx else ""]
            num = " - ".join(t for t in terms if t) if da else f"-{terms[1]}"
            return self.op(value, f"({num}) * {inv}")
        if fn == "max":  # the first where it is the greater or equal, as the dual numbers
            (b, db) = rest[0]
            pick = self.helper(f"{a} >= {b}")
            return self.op(value, f"({da or '0.0'} if {pick} else {db or '0.0'})")
        raise NotImplementedError(f"cannot differentiate {fn}")
