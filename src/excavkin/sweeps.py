"""Sweeps made on demand: input columns whose values are computed part by part, never whole.

A sweep of 10⁹ samples is 8 GB per input;
[`Mechanism.solve_stream`][excavkin.mechanism.Mechanism.solve_stream] takes these columns and makes
each part's values
as it solves that part, so memory stays bounded whatever the sample count. Given to
[`Mechanism.solve`][excavkin.mechanism.Mechanism.solve] (or to ``np.asarray``) they are
made whole, as the arrays they stand for.

>>> import numpy as np
>>> from excavkin.sweeps import Linspace, grid
>>> bool((Linspace(0.0, 1.0, 11).values(3, 6) == np.linspace(0.0, 1.0, 11)[3:6]).all())
True
>>> a, b = grid(Linspace(0.0, 1.0, 3), Linspace(5.0, 6.0, 2))
>>> a.values(0, 6).tolist(), b.values(0, 6).tolist()
([0.0, 0.0, 0.5, 0.5, 1.0, 1.0], [5.0, 6.0, 5.0, 6.0, 5.0, 6.0])
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F


class Lazy(ABC):
    """A column of n values made on demand, part by part."""

    @property
    @abstractmethod
    def size(self) -> int:
        """The number of values."""

    @abstractmethod
    def values(self, start: int, stop: int) -> F:
        """Values ``start`` … ``stop − 1``, a new float64 array.

        Parameters
        ----------
        start, stop : int
            The first value's index and one past the last's, ``0 ≤ start ≤ stop ≤ size``.

        Returns
        -------
        ndarray, shape (stop - start,)
        """

    @property
    def shape(self) -> tuple[int]:
        return (self.size,)

    @property
    def ndim(self) -> int:
        return 1

    def __len__(self) -> int:
        return self.size

    def __array__(self, dtype: Any = None, copy: Any = None) -> F:
        out = self.values(0, self.size)
        return out if dtype is None else out.astype(dtype, copy=False)


class Linspace(Lazy):
    """``np.linspace(start, stop, n)``, made on demand: the same numbers to the bit.

    Parameters
    ----------
    start, stop : float
        The first and last values (both included).
    n : int
        The number of values (at least 1).
    """

    def __init__(self, start: float, stop: float, n: int) -> None:
        if not 1 <= n <= 2**53:
            raise ValueError(f"a sweep has 1 to 2⁵³ samples, got {n}")
        self.start, self.stop, self.n = float(start), float(stop), int(n)

    @property
    def size(self) -> int:
        return self.n

    def values(self, start: int, stop: int) -> F:
        """Values ``start`` … ``stop − 1``, a new float64 array.

        Parameters
        ----------
        start, stop : int
            The first value's index and one past the last's, ``0 ≤ start ≤ stop ≤ size``.

        Returns
        -------
        ndarray, shape (stop - start,)
        """
        return self.at(np.arange(start, stop))

    def at(self, index: NDArray[np.integer[Any]]) -> F:
        """The values at the given indices (any shape).

        Parameters
        ----------
        index : ndarray of int
            Indices in ``0 … n − 1``, of any shape.

        Returns
        -------
        ndarray
            The values, of the shape of ``index``: what
            ``np.linspace(self.start, self.stop, self.n)[index]`` gives, to the bit.
        """
        # numpy's own arithmetic (numpy/_core/function_base.py), sample by sample
        y = np.asarray(index, dtype=np.float64)
        div = self.n - 1
        delta = self.stop - self.start
        if div > 0:
            step = delta / div
            y = y / div * delta if step == 0 else y * step
        else:
            y = y * delta
        y = y + self.start
        if div > 0:
            y[np.asarray(index) == div] = self.stop
        return np.asarray(y, dtype=np.float64)

    def __repr__(self) -> str:
        return f"Linspace({self.start!r}, {self.stop!r}, {self.n})"


class GridAxis(Lazy):
    """One input of a grid ([`grid`][excavkin.sweeps.grid]): its axis' value at each combination.

    Parameters
    ----------
    axes : sequence of Linspace or ndarray, shape (n_k,)
        Every axis of the grid, the first varying slowest.
    k : int
        Which axis this input takes its values from.
    """

    def __init__(self, axes: Sequence[Linspace | F], k: int) -> None:
        self.axes = axes
        self.k = k
        sizes = [a.size for a in axes]
        self.n = math.prod(sizes)
        # the last axis varies fastest
        self.stride = math.prod(sizes[k + 1 :])
        self.length = sizes[k]

    @property
    def size(self) -> int:
        return self.n

    def values(self, start: int, stop: int) -> F:
        """Values ``start`` … ``stop − 1``, a new float64 array.

        Parameters
        ----------
        start, stop : int
            The first value's index and one past the last's, ``0 ≤ start ≤ stop ≤ size``.

        Returns
        -------
        ndarray, shape (stop - start,)
        """
        index = (np.arange(start, stop) // self.stride) % self.length
        axis = self.axes[self.k]
        if isinstance(axis, Linspace):
            return axis.at(index)
        return np.asarray(axis, dtype=np.float64)[index]


def grid(*axes: Linspace | Sequence[float] | F) -> list[GridAxis]:
    """Every combination of the axes, the first varying slowest: the flattened
    ``np.meshgrid(*axes, indexing="ij")``, made on demand.

    Parameters
    ----------
    *axes : Linspace or array_like, shape (n_k,)
        The values of each input.

    Returns
    -------
    list of GridAxis
        One column per axis, each of ``prod(len(axis))`` values.
    """
    given: list[Linspace | F] = [
        a if isinstance(a, Linspace) else np.asarray(a, dtype=np.float64) for a in axes
    ]
    return [GridAxis(given, k) for k in range(len(given))]


def part_of(value: Any, start: int, stop: int) -> Any:
    """Samples ``start`` … ``stop − 1`` of an input: a lazy column's values made, an array
    sliced (a 0-d one is every sample's).

    Parameters
    ----------
    value : Lazy or array_like
        The input: a lazy column, an array with the sample axis first, or a scalar.
    start, stop : int
        The first sample and one past the last.

    Returns
    -------
    ndarray
        Those samples (a 0-d array unchanged).
    """
    if isinstance(value, Lazy):
        return value.values(start, stop)
    arr = np.asarray(value)
    return arr if arr.ndim == 0 else arr[start:stop]
