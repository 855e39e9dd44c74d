"""The array type aliases that annotations share across excavkin.

Every module annotates NumPy arrays with these names instead of defining its own. Modules whose
signatures are dense with arrays import them under one-letter names::

    from excavkin.arrays import FloatArray as F

Shapes are not part of the type: each function documents its own (``shape (n, n_points, 2)``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["BoolArray", "FloatArray", "RealArray"]

#: An array of float64, SI values: what the solvers, results and studies hold.
FloatArray = NDArray[np.float64]

#: An array of booleans: masks over samples or designs.
BoolArray = NDArray[np.bool_]

#: A real array of the caller's precision (float64 or long double): the small dense solves run
#: in whatever precision they are given, so their annotations do not pin the dtype.
RealArray = NDArray[Any]
