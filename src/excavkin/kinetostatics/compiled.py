"""The kinetostatic back-substitution compiled to one machine-code loop over samples (numba).

`solve_forces` reduces each moving body's loads to a force and a moment, then solves the
equilibrium along the solve plan, step by step from the last
(`excavkin.kinetostatics.structured`) — each operation an array operation over a chunk of
samples. Here those same operations are *traced*: they run once on symbols instead of arrays,
and every arithmetic operation they do is written down as one line of straight-line source.
numba compiles the loop over samples of that source (as `excavkin.kinematics.compiled` does
for a solve plan), so a sample's equations stay in registers. Because the trace runs the NumPy
path's own functions (`body_loads`, `back_substitute`), the operations and their order are the
NumPy path's; only a Newton group's dense block's row swaps, which NumPy makes with ``where``,
become a branch. Tests hold the two to 1e-15 of each column's scale.

The source depends on the plan's steps, the equilibrium system's unknowns, which bodies have a
mass (and a moment of inertia), which loads act where, and whether inertia and gravity are on;
every value — a mass, a centre of mass, a load — is read from a constants table (one column
for all samples, or one per sample for a family of designs or loads that vary), so one kernel
serves every design of a model, and it is cached on disk. Its length grows with the model's
size, and so does numba's compile time: the automatic choice compiles models of at most
`excavkin.kinematics.compiled.AUTO_POINTS` points, as the kinematics does, and a source of more
than `excavkin.kinematics.split.PASS` statements is compiled in passes, one by one
(`excavkin.kinematics.split`), so that the compile grows about as the model does.
"""

from __future__ import annotations

import dataclasses
import math
import threading
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.backends import Kernel
from excavkin.kinematics.compiled import table
from excavkin.kinematics.threads import over_chunks
from excavkin.kinetostatics.body_loads import body_loads
from excavkin.kinetostatics.equilibrium import StaticsSystem
from excavkin.kinetostatics.inertia import MassProperties
from excavkin.kinetostatics.loads import EvaluatedLoads
from excavkin.kinetostatics.structured import (
    SINGULAR_SINE,
    Arithmetic,
    StructuredSystem,
    back_substitute,
)
from excavkin.model.cams import LiftLaw

#: samples per call of the kernel (a thread's share of the work at a time)
CHUNK = 32768


class _Sym:
    """A per-sample value while the back-substitution is traced: each operation on it writes a line
    computing a new local variable. NumPy's scalars defer to it (``__array_ufunc__``)."""

    __slots__ = ("g", "name", "nonzero")

    def __init__(self, g: _Source, name: str, nonzero: bool = True) -> None:
        self.g, self.name, self.nonzero = g, name, nonzero

    def _op(self, a: object, op: str, b: object) -> _Sym:
        return self.g.tmp(f"{_text(a)} {op} {_text(b)}")

    def __mul__(self, o: object) -> _Sym:
        return self._op(self, "*", o)

    def __rmul__(self, o: object) -> _Sym:
        return self._op(o, "*", self)

    def __add__(self, o: object) -> _Sym:
        return self._op(self, "+", o)

    def __radd__(self, o: object) -> _Sym:
        return self._op(o, "+", self)

    def __sub__(self, o: object) -> _Sym:
        return self._op(self, "-", o)

    def __rsub__(self, o: object) -> _Sym:
        return self._op(o, "-", self)

    def __truediv__(self, o: object) -> _Sym:
        return self._op(self, "/", o)

    def __rtruediv__(self, o: object) -> _Sym:
        return self._op(o, "/", self)

    def __neg__(self) -> _Sym:
        return self.g.tmp(f"-{self.name}")

    def __getitem__(self, _: object) -> _Sym:  # a chunk's slice of a per-sample value
        return self

    def __ne__(self, other: object) -> bool:  # "is it ever nonzero", as the NumPy path asks
        return self.nonzero if other == 0.0 else NotImplemented  # type: ignore[return-value]

    def __eq__(self, other: object) -> bool:
        return not self.nonzero if other == 0.0 else NotImplemented  # type: ignore[return-value]

    __hash__ = object.__hash__

    def __array_ufunc__(self, ufunc: Any, method: str, *args: Any, **kw: Any) -> Any:
        ops = {np.multiply: "*", np.add: "+", np.subtract: "-", np.true_divide: "/"}
        if method != "__call__" or kw:
            return NotImplemented
        if ufunc in ops and len(args) == 2:
            return self._op(args[0], ops[ufunc], args[1])
        if ufunc is np.negative:
            return -args[0]
        if ufunc is np.sqrt:
            return self.g.tmp(f"math.sqrt({_text(args[0])})")
        if ufunc is np.arctan2 and len(args) == 2:  # a cam's turn from its points
            return self.g.tmp(f"math.atan2({_text(args[0])}, {_text(args[1])})")
        return NotImplemented


def _text(v: object) -> str:
    """A value as source: a symbol's name, or a float literal that reads back exactly."""
    if isinstance(v, _Sym):
        return v.name
    f = float(v)  # type: ignore[arg-type]
    if math.isnan(f):
        return "nan"
    if math.isinf(f):
        return "inf" if f > 0 else "-inf"
    return f"({f!r})"


class _Source:
    """The lines of the loop body, and the values the constants table holds."""

    def __init__(self) -> None:
        self.lines: list[str] = []
        self.values: list[float | F] = []
        self.loaded: dict[str, _Sym] = {}
        self.n_tmp = 0

    def emit(self, line: str) -> None:
        self.lines.append(line)

    def tmp(self, expr: str) -> _Sym:
        self.n_tmp += 1
        name = f"t{self.n_tmp}"
        self.emit(f"{name} = {expr}")
        return _Sym(self, name)

    def load(self, name: str, expr: str) -> _Sym:
        """A value read once per sample (a point's coordinate, a body's ε)."""
        if name not in self.loaded:
            self.emit(f"{name} = {expr}")
            self.loaded[name] = _Sym(self, name)
        return self.loaded[name]

    def value(self, v: Any) -> _Sym:
        """A constant or per-sample value of the loads or masses: a row of the table."""
        k = len(self.values)
        arr = np.asarray(v, dtype=np.float64)
        self.values.append(float(arr) if arr.ndim == 0 else arr)
        name = f"c{k}"
        self.emit(f"{name} = K[{k}, j]")
        return _Sym(self, name, bool(np.any(arr != 0.0)))


class _Points:
    """``arr[k, c]`` of a (n_points, 2, n) array (or ``arr[j]`` of a (n_bodies, n) one), read
    at the sample."""

    def __init__(self, g: _Source, arr: str) -> None:
        self.g, self.arr = g, arr

    def __getitem__(self, key: Any) -> _Sym:
        if isinstance(key, tuple):
            k, c = (int(i) for i in key)
            return self.g.load(f"{self.arr}{k}_{c}", f"{self.arr}[{k}, {c}, i]")
        return self.g.load(f"{self.arr}{int(key)}", f"{self.arr}[{int(key)}, i]")


class _Masses:
    """The mass properties as the traced `body_loads` reads them: each value a row of the
    constants table, the bodies with a mass and their base points as they are."""

    def __init__(self, g: _Source, mp: MassProperties) -> None:
        self.base = mp.base
        self.massive = mp.massive
        nb = len(mp.base)
        self.mass = [g.value(mp.mass[j]) if j in self.massive else 0.0 for j in range(nb)]
        self.inertia = [g.value(mp.inertia[j]) if j in self.massive else 0.0 for j in range(nb)]
        self.com = [
            (g.value(mp.com[j, 0]), g.value(mp.com[j, 1])) if j in self.massive else (0.0, 0.0)
            for j in range(nb)
        ]


class _TracedLaw:
    """A cam's lift law as the traced source evaluates it: its knots and coefficients rows of
    the constants table (read before the trace, so that a cached trace reads them too), the
    piece the last whose knot the turn reaches, picked by weights of 1 and 0 as the compiled
    plan picks it (`excavkin.step_kinds.cam.emit_law`), the cubic as
    `excavkin.model.cams.LiftLaw` evaluates it, operation for operation."""

    def __init__(self, g: _Source, law: LiftLaw) -> None:
        self.g = g
        m = law.coef.shape[1]
        self.knots = [g.value(law.knots[k]) for k in range(m)]
        self.coef = [[g.value(law.coef[j, k]) for k in range(m)] for j in range(4)]

    def __call__(self, theta: Any) -> tuple[_Sym, _Sym, _Sym]:
        g = self.g
        two_pi = repr(2.0 * math.pi)
        turns = g.tmp(f"math.floor({_text(theta)} / {two_pi})")
        u = g.tmp(f"{_text(theta)} - {two_pi} * {turns.name}")
        m = len(self.knots)
        ge = [g.tmp(f"1.0 * ({u.name} >= {kn.name})") for kn in self.knots[1:]]
        weights = [g.tmp(f"1.0 - {ge[0].name}")] if m > 1 else [g.tmp("1.0")]
        weights += [g.tmp(f"{a.name} - {b.name}") for a, b in zip(ge, ge[1:], strict=False)]
        weights += ge[-1:]

        def pick(values: list[_Sym]) -> _Sym:
            out = g.tmp(f"{weights[0].name} * {values[0].name}")
            for w, v in zip(weights[1:], values[1:], strict=True):
                out = g.tmp(f"{out.name} + {w.name} * {v.name}")
            return out

        kt = pick(self.knots)
        c3, c2, c1, c0 = (pick(row) for row in self.coef)
        t = g.tmp(f"{u.name} - {kt.name}")
        s = ((c3 * t + c2) * t + c1) * t + c0
        s1 = (3.0 * c3 * t + 2.0 * c2) * t + c1
        s2 = 6.0 * c3 * t + 2.0 * c2
        return s, s1, s2


def traceable(sy: StaticsSystem) -> bool:
    """Whether the system's cams can be traced: each lift law a table's (a function's
    cannot).

    Parameters
    ----------
    sy : StaticsSystem
        The equilibrium system.

    Returns
    -------
    bool
    """
    return all(isinstance(cm.law, LiftLaw) and cm.law.pieces is None for cm in sy.cams)


def _loads(g: _Source, ev: EvaluatedLoads) -> EvaluatedLoads:
    forces = tuple((b, p, g.value(fx), g.value(fy)) for b, p, fx, fy in ev.forces)
    torques = tuple((b, r, g.value(tau)) for b, r, tau in ev.torques)
    gravity = None if ev.gravity is None else (g.value(ev.gravity[0]), g.value(ev.gravity[1]))
    return EvaluatedLoads(forces, torques, gravity)  # type: ignore[arg-type]


_HEAD = '''\
"""Generated by excavkin.kinetostatics.compiled from an equilibrium system; do not edit."""
import math

import numba

nan, inf = math.nan, math.inf
A1, A2, A3 = numba.float64[:], numba.float64[:, :], numba.float64[:, :, :]
SIGNATURE = numba.void(A3, A3, A2, A2, numba.int64, A2, numba.boolean[:], numba.float64)


@numba.njit(SIGNATURE, nogil=True, cache=True, error_model="numpy")
def kernel(x, a, eps, K, ks, out, singular, rel_tol):
    for i in range(out.shape[1]):
        j = i * ks
'''


#: traced sources by what they depend on (`_shape`); a few kept
_traced: dict[tuple[Any, ...], str] = {}
_lock = threading.Lock()


def _shape(
    ss: StructuredSystem, mp: MassProperties, ev: EvaluatedLoads, inertia: bool
) -> tuple[Any, ...]:
    """All that the traced source depends on: the system and the plan's blocks, which bodies
    have a mass and a moment of inertia, where each load acts, whether gravity and inertia are
    on."""
    massive = mp.massive
    return (
        ss.system,
        ss.blocks,
        inertia,
        massive,
        tuple(bool(np.any(mp.inertia[j] != 0.0)) for j in massive),
        tuple(int(i) for i in mp.base.ravel()),
        tuple((b, p) for b, p, _, _ in ev.forces),
        tuple((b, r) for b, r, _ in ev.torques),
        ev.gravity is None,
    )


def source(
    ss: StructuredSystem, mp: MassProperties, ev: EvaluatedLoads, inertia: bool
) -> tuple[str, list[float | F]]:
    """The kernel's source for this system, masses and loads, and the values its constants
    table holds (in the order it reads them). The trace is made once for each
    `_shape`; the values are read anew each time.

    Parameters
    ----------
    ss : StructuredSystem
        The plan's steps and the equilibrium's unknowns
        (`excavkin.kinetostatics.structured.compile_structured`).
    mp : MassProperties
    ev : EvaluatedLoads
    inertia : bool
        Whether the d'Alembert inertia is on.

    Returns
    -------
    text : str
    values : list of float or ndarray
    """
    key = _shape(ss, mp, ev, inertia)
    g = _Source()
    masses: Any = _Masses(g, mp)
    loads = _loads(g, ev)
    laws = [_TracedLaw(g, cm.law) for cm in ss.system.cams]  # type: ignore[arg-type]
    text = _traced.get(key)
    if text is None:
        if laws:  # each cam's contact, in the system and in its blocks, with its traced law
            traced = {
                id(cm): dataclasses.replace(cm, law=law)
                for cm, law in zip(ss.system.cams, laws, strict=True)
            }
            blocks = tuple(
                dataclasses.replace(
                    b,
                    scalars=tuple(
                        dataclasses.replace(sc, mesh=traced[id(sc.mesh)])
                        if id(sc.mesh) in traced
                        else sc
                        for sc in b.scalars
                    ),
                )
                for b in ss.blocks
            )
            cams = tuple(traced[id(cm)] for cm in ss.system.cams)
            system = dataclasses.replace(ss.system, cams=cams)
            ss = dataclasses.replace(ss, system=system, blocks=blocks)
        text = _trace(g, ss, masses, loads, inertia)
        with _lock:  # (forces may be solved on several threads)
            while len(_traced) >= 16:
                _traced.pop(next(iter(_traced)), None)
            _traced[key] = text
    return text, g.values


class _Traced(Arithmetic):
    """The back-substitution's singular flags and dense blocks, written as source."""

    def __init__(self, g: _Source) -> None:
        self.g = g

    def flag(self, det: Any) -> None:
        self.g.emit(f"if abs({_text(det)}) <= {SINGULAR_SINE!r}:")
        self.g.emit("    sg = True")

    def dense(self, a: list[list[Any]], b: list[Any]) -> list[Any]:
        return [self.g.tmp(y.name) for y in _dense(self.g, a, b)]  # (the next block's y's)


def _trace(
    g: _Source, ss: StructuredSystem, masses: Any, loads: EvaluatedLoads, inertia: bool
) -> str:
    """Run the NumPy path's back-substitution on the symbols of ``g``: the kernel's source."""
    sy = ss.system
    x = _Points(g, "x")
    acc = _Points(g, "a") if inertia else None
    eps = _Points(g, "eps") if inertia else None
    rhs_body = body_loads(sy, masses, loads, x, acc, eps, slice(None))  # type: ignore[arg-type]
    g.emit("sg = False")
    sol = back_substitute(ss, x, rhs_body, _Traced(g))  # type: ignore[arg-type]
    for col, val in enumerate(sol):
        g.emit(f"out[{col}, i] = {_text(val)}")
    g.emit("singular[i] = sg")
    return _HEAD + "".join(f"        {line}\n" for line in g.lines)


def _dense(g: _Source, a: list[list[Any]], b: list[Any]) -> list[_Sym]:
    """Gaussian elimination with partial pivoting of a dense block, as
    `dense_block_solve` does it for each sample: the same
    operations, a row swap where its ``where`` swaps. Sets ``sg``: a pivot below ``rel_tol``
    times the block's largest entry."""
    r = len(b)
    m = [[f"m{i}_{k}" for k in range(r)] for i in range(r)]
    for i in range(r):
        for k in range(r):
            g.emit(f"{m[i][k]} = {_text(a[i][k])}")
        g.emit(f"b{i} = {_text(b[i])}")
    g.emit("scale = 0.0")
    for row in m:
        for v in row:  # np.maximum: a NaN wins
            g.emit(f"w = abs({v})")
            g.emit("scale = scale if (scale >= w or scale != scale) else w")
    for k in range(r):
        for i in range(k + 1, r):
            g.emit(f"if abs({m[i][k]}) > abs({m[k][k]}):")
            for j in range(k, r):
                g.emit(f"    {m[k][j]}, {m[i][j]} = {m[i][j]}, {m[k][j]}")
            g.emit(f"    b{k}, b{i} = b{i}, b{k}")
        g.emit(f"if abs({m[k][k]}) <= rel_tol * scale:")
        g.emit("    sg = True")
        g.emit(f"inv = 1.0 / {m[k][k]}")
        for i in range(k + 1, r):
            g.emit(f"f = {m[i][k]} * inv")
            for j in range(k + 1, r):
                g.emit(f"{m[i][j]} = {m[i][j]} - f * {m[k][j]}")
            g.emit(f"b{i} = b{i} - f * b{k}")
    for k in range(r - 1, -1, -1):
        g.emit(f"s = b{k}")
        for j in range(k + 1, r):
            g.emit(f"s = s - {m[k][j]} * y{j}")
        g.emit(f"y{k} = s / {m[k][k]}")
    return [_Sym(g, f"y{k}") for k in range(r)]


def solve(
    kernel: Kernel,
    values: list[float | F],
    x: F,
    a: F | None,
    eps: F | None,
    out: F,
    singular: np.ndarray,
    workers: int | None = None,
) -> None:
    """Fill ``out`` (n_unknowns, n) and ``singular`` (n,) with ``kernel`` (of a `source`'s
    text, compiled by a backend: `excavkin.backends`), over chunks of samples on a thread
    per core. ``x``, ``a``: (n_points, 2, n); ``eps``: (n_bodies, n) (``a`` and ``eps`` None:
    no inertia)."""
    n = out.shape[1]
    k, stride = table(values, n)
    acc = x if a is None else a
    e = np.empty((1, n)) if eps is None else eps

    def one(s: int) -> None:
        part = slice(s, min(s + CHUNK, n))
        kp = k[:, part] if stride else k
        kernel(x[:, :, part], acc[:, :, part], e[:, part], kp, stride, out[:, part],
               singular[part], 1e-12)  # fmt: skip

    over_chunks(n, CHUNK, workers, one)
