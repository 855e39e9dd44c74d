"""Many small dense linear systems at once: LU with partial pivoting over the batch axis.

A Newton group solves one m×m system per sample (m twice its point count: 4 for a four-bar,
6 for a triad). LAPACK's batched routines pay a call, a copy into column-major order and a
separate determinant per small matrix, so here the batch axis is the *last* one, as in the
solve's other arrays: ``a[i, j]`` is entry (i, j) of every sample, one contiguous row, and
each operation below is one NumPy call over whole rows. Python loops over the matrix size
only, never over samples.

The factorisation, per sample:

1. every row is scaled to unit Euclidean norm (equilibration; a zero row is left as it is);
2. Gaussian elimination with partial pivoting on the scaled rows: at step k the pivot is the
   largest ``|a[r, k]|``, r ≥ k, and rows k and r are exchanged (for the samples that pick r);
3. the determinant of the scaled matrix is the product of the pivots with the exchanges'
   signs. It equals det(a) over the product of a's row norms — the Hadamard ratio, 1 for
   orthogonal rows and 0 at a singular matrix: a scale-free distance from singular (the
   measure `excavkin.kinematics.precision` calls ``near``), got for free from the pivots.

The arithmetic is that of the array's own type, so a long-double system is factored in long
double. A singular sample (a zero pivot) gets inf or NaN in its solution and a ratio of 0; the
caller masks it by the ratio.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import RealArray as F


class Factors:
    """The LU factors of a batch of m×m matrices ``a``, shape (m, m, n).

    Attributes
    ----------
    ratio : ndarray, shape (n,)
        det(a) / ∏ ‖row of a‖, signed: its sign is the determinant's, its magnitude in [0, 1].

    Examples
    --------
    Two samples: a rotation (orthogonal rows, ratio 1) and a singular matrix (ratio 0).

    >>> import numpy as np
    >>> a = np.stack([[[0.0, -1.0], [1.0, 0.0]], [[1.0, 2.0], [2.0, 4.0]]], axis=-1)
    >>> lu = Factors(a)
    >>> lu.ratio
    array([1., 0.])
    >>> lu.solve(np.array([[1.0, 1.0], [2.0, 1.0]]))[:, 0]
    array([ 2., -1.])
    """

    __slots__ = ("_lu", "_pivots", "_recip", "_scale", "ratio")

    def __init__(self, a: F, *, overwrite: bool = False) -> None:
        """Factor ``a``; with ``overwrite`` its memory holds the factors (``a`` is then lost,
        and no second array of its size is made)."""
        m, m2, n = a.shape
        if m != m2:
            raise ValueError(f"square matrices expected, got {m}×{m2}")
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            norm = np.sqrt(np.einsum("ijn,ijn->in", a, a))
            self._scale = 1.0 / np.where(norm > 0.0, norm, 1.0)
            if overwrite and a.flags.c_contiguous:
                lu = a
                lu *= self._scale[:, None, :]
            else:  # row-major whatever ``a``'s layout: rows are exchanged by flat offsets
                lu = np.multiply(a, self._scale[:, None, :], order="C")
            ratio = np.ones(n, dtype=lu.dtype)
            # a zero pivot: singular, whatever NaN its divisions leave behind it
            dead = np.zeros(n, dtype=bool)
            self._pivots: list[NDArray[np.intp]] = []
            rows = _Rows(lu)
            for k in range(m - 1):
                pick = _largest(lu[k:, k])
                self._pivots.append(pick)
                rows.exchange(k, pick, k)
                np.negative(ratio, out=ratio, where=pick != 0)
                ratio *= lu[k, k]
                dead |= lu[k, k] == 0.0
                lu[k + 1 :, k] /= lu[k, k]  # the multipliers, kept below the diagonal
                lu[k + 1 :, k + 1 :] -= lu[k + 1 :, k, None, :] * lu[k, None, k + 1 :, :]
            ratio *= lu[m - 1, m - 1]
            ratio[dead] = 0.0
            self._recip = 1.0 / np.diagonal(lu).T  # (m, n): the pivots' reciprocals
        self._lu = lu
        self.ratio: F = ratio

    def at(self, keep: NDArray[np.bool_]) -> Factors:
        """The factors of the samples where ``keep``."""
        out = Factors.__new__(Factors)
        # ``compress`` keeps the batch axis last in memory (a fancy index would not)
        out._lu = np.compress(keep, self._lu, axis=-1)
        out._pivots = [p[keep] for p in self._pivots]
        out._recip = np.compress(keep, self._recip, axis=-1)
        out._scale = np.compress(keep, self._scale, axis=-1)
        out.ratio = self.ratio[keep]
        return out

    def solve(self, b: F) -> F:
        """Solve ``a·x = b`` for each sample.

        Parameters
        ----------
        b : ndarray, shape (m, n) or (m, k, n)
            One right-hand side per sample, or k of them.

        Returns
        -------
        ndarray, the shape of ``b``
        """
        lu = self._lu
        m = lu.shape[0]
        if not b.shape[-1]:
            return np.zeros(b.shape, dtype=np.result_type(b, lu))
        # a right-hand side's extra axes sit between the row and the sample axes
        mid = (None,) * (b.ndim - 2)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            x = np.multiply(b, self._scale[(slice(None), *mid)], order="C")
            rows = _Rows(x.reshape(m, -1, x.shape[-1]))
            for k, pick in enumerate(self._pivots):
                rows.exchange(k, pick, 0)
                x[k + 1 :] -= lu[(slice(k + 1, None), k, *mid)] * x[k]
            for k in range(m - 1, -1, -1):
                x[k] *= self._recip[(k, *mid)]
                if k:
                    x[:k] -= lu[(slice(None, k), k, *mid)] * x[k]
        return x


def _largest(col: F) -> NDArray[np.intp]:
    """Per sample, the row of ``col`` (shape (r, n)) with the largest magnitude; the first of
    equals. A running comparison row by row: ``argmax`` along a strided axis is far slower."""
    mag = np.abs(col)
    best = mag[0].copy()
    pick = np.zeros(col.shape[1], dtype=np.intp)
    for r in range(1, col.shape[0]):
        more = mag[r] > best
        np.copyto(pick, r, where=more)
        np.maximum(best, mag[r], out=best)
    # a NaN row wins nothing here; the NaN still reaches the pivot product through elimination
    return pick


class _Rows:
    """Row exchanges, per sample, in a contiguous array of shape (m, w, n): one gather and
    one scatter of flat indices per exchange, whichever rows each sample exchanges."""

    __slots__ = ("_arr", "_flat", "_grid")

    def __init__(self, arr: F) -> None:
        m, w, n = arr.shape
        if not arr.flags.c_contiguous:
            raise ValueError("row exchanges need a row-major array")
        self._arr = arr
        self._flat = arr.reshape(-1)  # a view, since ``arr`` is row-major
        self._grid = np.arange(w)[:, None] * n + np.arange(n)  # (column, sample) offsets

    def exchange(self, k: int, pick: NDArray[np.intp], first: int) -> None:
        """Exchange row k with row k + ``pick`` of each sample, in columns ``first`` on."""
        m, w, n = self._arr.shape
        where = self._grid[first:] + (k + pick) * (w * n)
        other = np.take(self._flat, where)
        self._flat[where] = self._arr[k, first:]  # (``np.put`` is several times slower)
        self._arr[k, first:] = other
