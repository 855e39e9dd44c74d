"""Dual numbers over NumPy arrays: forward-mode derivatives through the plan's own kernels.

A `Dual` holds a value array and, for m parameters at once, the derivative of every
element with respect to each: ``tan`` has shape ``(m, *value.shape)``. Arithmetic and the few
functions the kernels use (``sqrt``, ``hypot``, ``arctan2``, ``cos``, ``sin``, ``abs``,
``maximum``, ``where``) carry the derivatives by the chain rule, so that running a solve plan on
duals gives each result's exact derivative with respect to the dimensions — the derivative of
the closed forms themselves, not a difference quotient. Comparisons act on the values (the
kernels' masks), and indexing indexes both parts.
"""

from __future__ import annotations

from typing import Any

import numpy as np


def _parts(x: Any) -> tuple[Any, Any]:
    """Value and tangent (0 for a plain number or array)."""
    if isinstance(x, Dual):
        return x.val, x.tan
    return x, 0.0


def _lead(k: Any) -> tuple[Any, ...]:
    """An index of a value, for its tangent (one more leading axis)."""
    return (slice(None), *(k if isinstance(k, tuple) else (k,)))


class Dual:
    """A value array and its derivatives with respect to m parameters (leading axis)."""

    __array_priority__ = 1000

    def __init__(self, val: Any, tan: Any) -> None:
        self.val = np.asarray(val)
        self.tan = np.asarray(tan)

    # ---- shape and indexing
    @property
    def ndim(self) -> int:
        return int(self.val.ndim)

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(self.val.shape)

    @property
    def dtype(self) -> np.dtype[Any]:
        return self.val.dtype

    def __len__(self) -> int:
        return len(self.val)

    def __getitem__(self, k: Any) -> Dual:
        if self.tan.ndim == 0:  # a constant: no tangent to index
            return Dual(self.val[k], self.tan)
        return Dual(self.val[k], self.tan[_lead(k)])

    def __setitem__(self, k: Any, other: Any) -> None:
        v, t = _parts(other)
        self.val[k] = v
        self.tan[_lead(k)] = t

    # ---- arithmetic (a plain operand has no tangent: its products and sums are skipped)
    def __add__(self, o: Any) -> Dual:
        if not isinstance(o, Dual):
            return Dual(self.val + o, self.tan)
        return Dual(self.val + o.val, self.tan + o.tan)

    __radd__ = __add__

    def __sub__(self, o: Any) -> Dual:
        if not isinstance(o, Dual):
            return Dual(self.val - o, self.tan)
        return Dual(self.val - o.val, self.tan - o.tan)

    def __rsub__(self, o: Any) -> Dual:
        return Dual(o - self.val, -self.tan)

    def __mul__(self, o: Any) -> Dual:
        if not isinstance(o, Dual):
            return Dual(self.val * o, self.tan * o)
        return Dual(self.val * o.val, self.tan * o.val + self.val * o.tan)

    __rmul__ = __mul__

    def __truediv__(self, o: Any) -> Dual:
        if not isinstance(o, Dual):
            return Dual(self.val / o, self.tan / o)
        q = self.val / o.val
        return Dual(q, (self.tan - q * o.tan) / o.val)

    def __rtruediv__(self, o: Any) -> Dual:
        q = o / self.val
        return Dual(q, -q * self.tan / self.val)

    def __pow__(self, k: int) -> Dual:
        return Dual(self.val**k, k * self.val ** (k - 1) * self.tan)

    def __neg__(self) -> Dual:
        return Dual(-self.val, -self.tan)

    def __abs__(self) -> Dual:
        return Dual(np.abs(self.val), np.sign(self.val) * self.tan)

    # ---- comparisons: on the values (the kernels' masks)
    def __lt__(self, o: Any) -> Any:
        return self.val < _parts(o)[0]

    def __le__(self, o: Any) -> Any:
        return self.val <= _parts(o)[0]

    def __gt__(self, o: Any) -> Any:
        return self.val > _parts(o)[0]

    def __ge__(self, o: Any) -> Any:
        return self.val >= _parts(o)[0]

    def __array_ufunc__(self, ufunc: Any, method: str, *inputs: Any, **kwargs: Any) -> Any:
        if method != "__call__" or kwargs.get("out") is not None:
            return NotImplemented
        rule = _RULES.get(ufunc.__name__)
        if rule is None:
            if ufunc.__name__ in _ON_VALUES:  # masks and tests read the values
                return ufunc(*(_parts(x)[0] for x in inputs))
            return NotImplemented
        return rule(*inputs)

    def __array_function__(self, func: Any, types: Any, args: Any, kwargs: Any) -> Any:
        if func is np.where:
            cond, a, b = args
            (av, at), (bv, bt) = _parts(a), _parts(b)
            return Dual(np.where(cond, av, bv), np.where(cond, at, bt))
        if func is np.ndim:
            return self.ndim
        if func is np.stack:  # components into a vector: the tangents' axis stays first
            items, axis = args[0], kwargs.get("axis", args[1] if len(args) > 1 else 0)
            n = np.ndim(np.asarray(_parts(items[0])[0]))
            axis = axis if axis >= 0 else axis + n + 1
            vals = [np.asarray(_parts(x)[0]) for x in items]
            shape = np.broadcast_shapes(*(v.shape for v in vals))
            ms = [np.shape(x.tan)[0] for x in items if isinstance(x, Dual) and x.tan.ndim]
            if not ms:
                return Dual(np.stack(vals, axis=axis), 0.0)
            m = ms[0]
            tans = [
                np.broadcast_to(x.tan if isinstance(x, Dual) and x.tan.ndim else 0.0, (m, *shape))
                for x in items
            ]
            return Dual(np.stack(vals, axis=axis), np.stack(tans, axis=axis + 1))
        if func is np.any or func is np.all:
            return func(self.val, *args[1:], **kwargs)
        return NotImplemented


def _binary(name: str, reflected: str) -> Any:
    """A ufunc of two operands, at least one of them dual."""
    return lambda a, b: getattr(a, name)(b) if isinstance(a, Dual) else getattr(b, reflected)(a)


def _sqrt(a: Dual) -> Dual:
    r = np.sqrt(a.val)
    with np.errstate(divide="ignore", invalid="ignore"):
        return Dual(r, a.tan / (2.0 * r))


def _hypot(a: Any, b: Any) -> Dual:
    (av, at), (bv, bt) = _parts(a), _parts(b)
    r = np.hypot(av, bv)
    with np.errstate(divide="ignore", invalid="ignore"):
        return Dual(r, (av * at + bv * bt) / r)


def _arctan2(y: Any, x: Any) -> Dual:
    (yv, yt), (xv, xt) = _parts(y), _parts(x)
    r2 = xv * xv + yv * yv
    with np.errstate(divide="ignore", invalid="ignore"):
        return Dual(np.arctan2(yv, xv), (xv * yt - yv * xt) / r2)


def _maximum(a: Any, b: Any) -> Dual:
    (av, at), (bv, bt) = _parts(a), _parts(b)
    pick = av >= bv
    return Dual(np.maximum(av, bv), np.where(pick, at, bt))


_RULES: dict[str, Any] = {
    "add": _binary("__add__", "__radd__"),
    "subtract": _binary("__sub__", "__rsub__"),
    "multiply": _binary("__mul__", "__rmul__"),
    "true_divide": _binary("__truediv__", "__rtruediv__"),
    "divide": _binary("__truediv__", "__rtruediv__"),  # true_divide's name in NumPy 2
    "negative": lambda a: -a,
    "absolute": abs,
    "sqrt": _sqrt,
    "hypot": _hypot,
    "arctan2": _arctan2,
    "cos": lambda a: Dual(np.cos(a.val), -np.sin(a.val) * a.tan),
    "sin": lambda a: Dual(np.sin(a.val), np.cos(a.val) * a.tan),
    "maximum": _maximum,
}
_ON_VALUES = {"isfinite", "isnan", "less", "less_equal", "greater", "greater_equal", "sign"}


def seed(values: dict[str, Any], names: list[str], n: int) -> dict[str, Dual]:
    """Each parameter as a dual over ``n`` samples whose tangent is 1 for its own row of
    ``names``."""
    out = {}
    m = len(names)
    for name in names:
        val = np.broadcast_to(np.asarray(values[name], dtype=np.float64), (n,)).copy()
        tan = np.zeros((m, n))
        tan[names.index(name)] = 1.0
        out[name] = Dual(val, tan)
    return out


def zeros(shape: tuple[int, ...], m: int) -> Dual:
    """A dual of zeros with m tangents."""
    return Dual(np.zeros(shape), np.zeros((m, *shape)))
