"""What the paper studies share: a run of the engine under a paper's names, published values,
finite differences for the papers' own derivative checks, and a plain-text table.

Every quantity is SI (m, rad, s) with the batch axis first: arrays of shape ``(n,)``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from excavkin.arrays import FloatArray
from excavkin.mechanism import Mechanism

if TYPE_CHECKING:
    from excavkin.kinematics.result import KinematicResult


@dataclass(frozen=True, slots=True)
class PaperRun:
    """A paper's quantities computed by the engine.

    Attributes
    ----------
    columns : dict of str to ndarray, shape (n,)
        The paper's quantities by name, SI.
    kinds : dict of str to str
        Quantity kind of each column (``"angle"``, ``"velocity"``, ...), for display units.
    result : KinematicResult
        The engine's result they were read from.
    """

    columns: dict[str, FloatArray]
    kinds: dict[str, str]
    result: KinematicResult

    def __getitem__(self, name: str) -> FloatArray:
        return self.columns[name]

    def __len__(self) -> int:
        return len(self.result)


@dataclass(frozen=True, slots=True)
class Published:
    """One published (or reconstructed) value beside ours.

    Attributes
    ----------
    quantity : str
        What it is, in words, with the paper's symbol.
    published : str
        The value as the paper (or the spec) states it, or ``"not published"``.
    ours : str
        The engine's value, formatted.
    source : str
        Where the published value comes from.
    """

    quantity: str
    published: str
    ours: str
    source: str


def wrap(a: npt.ArrayLike) -> FloatArray:
    """Angles wrapped to ``(-π, π]``, shape preserved."""
    x = np.asarray(a, dtype=np.float64)
    return np.asarray(np.arctan2(np.sin(x), np.cos(x)), dtype=np.float64)


def load_paper_model(name: str) -> Mechanism:
    """Load a seed paper's example model by its file stem (``"rope_shovel"``, ...).

    Parameters
    ----------
    name : str
        ``"pasika_module"``, ``"rope_shovel"`` or ``"arm_vector"``.

    Returns
    -------
    Mechanism
    """
    import excavkin

    return excavkin.load(excavkin.example_path(name))


def central_differences(values: FloatArray, h: float) -> tuple[FloatArray, FloatArray]:
    """First and second derivatives by 8th-order central differences (Fornberg 1988).

    Parameters
    ----------
    values : ndarray, shape (9, n)
        ``f(x + k h)`` for ``k = -4 … 4`` (rows), at n points.
    h : float
        Step.

    Returns
    -------
    d1, d2 : ndarray, shape (n,)
    """
    d1 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
    d2 = np.array([-1 / 560, 8 / 315, -1 / 5, 8 / 5, -205 / 72, 8 / 5, -1 / 5, 8 / 315, -1 / 560])
    return d1 @ values / h, d2 @ values / (h * h)


def rel_error(engine: FloatArray, ref: FloatArray, angle: bool) -> float:
    """Largest difference of the engine from a reference, relative to the reference's scale."""
    d = np.abs(wrap(engine - ref)) if angle else np.abs(engine - ref)
    scale = float(np.nanmax(np.abs(ref)))
    return float(np.nanmax(d) / scale) if scale > 0.0 else float(np.nanmax(d))


def text_table(headers: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """Rows of strings as a plain-text table with aligned columns.

    Parameters
    ----------
    headers : sequence of str
    rows : sequence of sequence of str

    Returns
    -------
    str
    """
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(headers)]
    fmt = "  ".join(f"{{:<{w}}}" for w in widths)
    lines = [fmt.format(*headers), "  ".join("-" * w for w in widths)]
    lines += [fmt.format(*r) for r in rows]
    return "\n".join(line.rstrip() for line in lines)
