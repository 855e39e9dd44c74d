"""Working-range figures of a family of designs, all searched at once.

The figures that are optima of the tooth tip over the whole stroke box, with no posture
imposed, are found for every design together: the pattern search of
`maximize_strokes` runs one problem per design, each within its
own strokes, every trial of every design one batch solve with the designs' own geometry. The
figures are those of [`working_ranges`][excavkin.excavator.ranges.working_ranges] of each design
built as a
machine of its own (tested), to the search's ~1e-9 m.

=====================  ===========================================================
figure                 definition (heights from the ground line, reaches from the swing axis)
=====================  ===========================================================
``max_digging_reach``  the farthest tip, any height
``max_digging_depth``  the lowest tip (SAE J1193 AC)
``max_cutting_height`` the highest tip
=====================  ===========================================================

A design whose front does not assemble everywhere in its stroke box (on a 9-level grid) gives
NaN, as [`working_ranges`][excavkin.excavator.ranges.working_ranges] refuses such a machine: its
figures
would sit at the edge of assembly.

The other figures impose a posture (the tip on the ground line, the bucket hanging, teeth
vertical) and are left to [`working_ranges`][excavkin.excavator.ranges.working_ranges] of one
design.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import BoolArray as B
from excavkin.arrays import FloatArray as F
from excavkin.excavator.designs import check_designs, cylinder_arrays, within_strokes
from excavkin.excavator.machine import ROLES, Machine
from excavkin.machinery.search import maximize_strokes

#: figure → (sign of the tip's coordinate it maximises, coordinate index)
FIGURES: dict[str, tuple[float, int]] = {
    "max_digging_reach": (1.0, 0),
    "max_digging_depth": (-1.0, 1),
    "max_cutting_height": (1.0, 1),
}


def design_ranges(
    machine: Machine,
    params: Mapping[str, ArrayLike],
    figures: Sequence[str] = tuple(FIGURES),
) -> dict[str, F]:
    """The free working-range figures (module docstring) of each design (m).

    Parameters
    ----------
    machine : Machine
    params : mapping of str to array_like, shape (d,)
        Each design's parameters (names of
        [`machine_parameters`][excavkin.excavator.designs.machine_parameters]); others nominal.
    figures : sequence of str
        Keys of `FIGURES`.

    Returns
    -------
    dict of str to ndarray, shape (d,)
        NaN for a design whose cylinders are impossible or whose front assembles nowhere.
    """
    from excavkin.errors import unknown_name

    for f in figures:
        if f not in FIGURES:
            raise unknown_name("working-range figure", f, list(FIGURES))
    sizes = {np.size(v) for v in params.values()}
    d = max(sizes) if sizes else 1
    per = {k: np.broadcast_to(np.asarray(v, dtype=np.float64), (d,)) for k, v in params.items()}
    cyl = cylinder_arrays(machine, per, d)
    lo = np.stack([cyl[r]["retracted"] for r in ROLES], axis=-1)
    hi = lo + np.stack([cyl[r]["stroke"] for r in ROLES], axis=-1)
    possible = check_designs(machine, per, d)
    lo, hi = np.where(possible[:, None], lo, 1.0), np.where(possible[:, None], hi, 2.0)
    tip_index = machine.mechanism.plan.points.index(machine.front.tip)
    geometry = {k: v for k, v in per.items() if k in machine.mechanism.parameters}
    possible &= _assembles(machine, geometry, lo, hi)
    out: dict[str, F] = {}
    for f in figures:
        sign, axis = FIGURES[f]

        def evaluate(L: F, sign: float = sign, axis: int = axis) -> tuple[F, F]:
            k = L.shape[1]
            flat = L.reshape(-1, 3)
            rows = {key: np.repeat(v, k) for key, v in geometry.items()}
            values = {drv: flat[:, i] for i, drv in enumerate(machine.drivers)}
            res = machine.mechanism.solve(values, params=rows or None)
            tip = res.positions[:, tip_index, axis]
            ok = res.status.solved & within_strokes(
                machine, flat, {key: np.repeat(v, k) for key, v in per.items()}
            )
            return np.where(ok, sign * tip, -np.inf).reshape(L.shape[:2]), L

        best, _ = maximize_strokes(evaluate, machine, (0, 1, 2), problems=d, strokes=(lo, hi))
        extreme = sign * best  # the tip's coordinate at the optimum
        if f == "max_digging_reach":
            value = extreme - machine.swing_axis
        elif f == "max_digging_depth":
            value = machine.ground_line - extreme
        else:
            value = extreme - machine.ground_line
        out[f] = np.where(possible & np.isfinite(best), value, np.nan)
    return out


#: levels per stroke of the grid on which every design must assemble
CHECK_LEVELS = 9


def _assembles(machine: Machine, geometry: Mapping[str, F], lo: F, hi: F) -> B:
    """Whether each design's front assembles at every point of a grid over its stroke box:
    where it does not, its strokes run past what the linkage allows, and its figures would
    sit at the edge of assembly (working_ranges refuses such a machine)."""
    d = len(lo)
    unit = np.stack(
        np.meshgrid(*[np.linspace(0.0, 1.0, CHECK_LEVELS)] * 3, indexing="ij"), axis=-1
    ).reshape(-1, 3)
    k = len(unit)
    L = (lo[:, None, :] + unit * (hi - lo)[:, None, :]).reshape(-1, 3)
    values = {drv: L[:, i] for i, drv in enumerate(machine.drivers)}
    rows = {key: np.repeat(v, k) for key, v in geometry.items()}
    res = machine.mechanism.solve(values, params=rows or None)
    return np.asarray(res.status.solved.reshape(d, k).all(axis=1))
