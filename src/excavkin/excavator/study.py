"""Design studies and optimisation of an excavator machine: a study file that names a machine
file, whose parameters are the machine's
([`machine_parameters`][excavkin.excavator.designs.machine_parameters])
and whose metrics read the machine's columns at a set of cylinder lengths.

::

    [study]
    machine = "excavator_machine"   # a machine file beside this one, or a built-in example

    [parameters]                    # mechanism and machine parameters, with bounds
    "K.x" = ["6669.6 mm", "6769.6 mm"]
    "cylinders.bucket.bore" = ["120 mm", "130 mm"]

    [poses]                         # cylinder lengths: START:STOP:N, or one value
    boom_cyl = "2768 mm"
    arm_cyl = "2972 mm"
    bucket_cyl = "1645 mm:2765 mm:57"

    [metrics]
    force_min = { column = "rated.bucket", reduce = "min" }

A design's pose fails where the front does not assemble or a cylinder length lies outside that
design's stroke; a design whose cylinders or circuits are impossible fails at every pose.

The machine columns (`COLUMNS`) come from the engine's transfer functions, which have no
parameter sensitivities of their own here: the local method takes the gradient of every column
at every pose by central differences in the scaled parameters, all 2n + 1 designs of one
gradient solved as one batch. Differential evolution solves its whole population as one batch.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from excavkin.arrays import FloatArray as F
from excavkin.excavator.designs import (
    bucket_angle_to_stick,
    check_designs,
    check_parameters,
    design_tool_forces,
    design_transfer,
    machine_parameter_kind,
    machine_parameters,
    within_strokes,
)
from excavkin.excavator.forces import Working
from excavkin.excavator.machine import Machine, as_lengths
from excavkin.machinery.designs import Family
from excavkin.studies import machine_study as ms
from excavkin.studies.machine_study import MachineStudy, optimize_machine
from excavkin.studies.metrics import Constraint, Metric, Poses

if TYPE_CHECKING:
    import pandas as pd

#: The machine's columns and their kinds. ``rated.*``: the ISO 6015 tool force of the bucket
#: or arm cylinder at the lip, at working pressure, capped by the holding cylinders' reliefs,
#: without the front's weight (as rated forces are given); ``force.*``: the same with the
#: weight; ``bucket.angle_to_stick``: the bucket's angle relative to the stick
#: (`bucket_angle_to_stick`); ``tip.x``, ``tip.y``: the
#: tooth tip; ``range.*``: the design's working-range figure
#: (`design_ranges`), the same at every pose.
COLUMNS: dict[str, str] = {
    "rated.bucket": "force",
    "rated.arm": "force",
    "force.bucket": "force",
    "force.arm": "force",
    "bucket.angle_to_stick": "angle",
    "tip.x": "length",
    "tip.y": "length",
    "range.max_digging_reach": "length",
    "range.max_digging_depth": "length",
    "range.max_cutting_height": "length",
}
#: the angle columns (their ``change`` is followed along the poses)
ANGLES = frozenset(k for k, kind in COLUMNS.items() if kind == "angle")


def machine_columns(
    machine: Machine,
    lengths: ArrayLike,
    params: Mapping[str, ArrayLike],
    names: Sequence[str],
) -> tuple[dict[str, F], NDArray[np.bool_]]:
    """The columns ``names`` (of `COLUMNS`) at cylinder ``lengths`` (shape (n, 3)),
    sample i the design ``params[name][i]``, and which samples are valid (assembled, within
    their design's strokes, possible cylinders and circuits), shape (n,)."""
    L = as_lengths(lengths)
    n = len(L)
    for name in names:
        if name not in COLUMNS:
            from excavkin.errors import unknown_name

            raise unknown_name("machine column", name, list(COLUMNS))
    tr = design_transfer(machine, L, params)
    within = within_strokes(machine, L, params)
    ok = np.asarray(tr.result.status.solved & within & check_designs(machine, params, n))
    out: dict[str, F] = {}
    for name in names:
        if name.startswith(("rated.", "force.")):
            working: Working = "arm" if name.endswith("arm") else "bucket"
            f = design_tool_forces(
                machine, L, params, working, gravity=name.startswith("force."), transfer=tr
            )
            out[name] = f.force
        elif name == "bucket.angle_to_stick":
            out[name] = bucket_angle_to_stick(machine, tr)
        elif name.startswith("range."):
            out[name] = _design_figure(machine, params, n, name.removeprefix("range."))
        else:
            tip, _ = tr.point(machine, machine.front.tip)
            out[name] = np.asarray(tip[:, 0 if name == "tip.x" else 1])
    return out, ok


def _design_figure(machine: Machine, params: Mapping[str, ArrayLike], n: int, figure: str) -> F:
    """A working-range figure of each sample's design, searched once per distinct design."""
    from excavkin.excavator.design_ranges import design_ranges

    if not params:
        return np.full(n, design_ranges(machine, {}, [figure])[figure][0])
    names = sorted(params)
    rows = np.column_stack([np.broadcast_to(np.asarray(params[k], float), (n,)) for k in names])
    designs, which = np.unique(rows, axis=0, return_inverse=True)
    values = design_ranges(machine, dict(zip(names, designs.T, strict=True)), [figure])[figure]
    return np.asarray(values[which.reshape(-1)])


def pose_lengths(machine: Machine, poses: Poses) -> F:
    """The cylinder lengths of a pose set, shape (p, 3): each driver's values, or the model's
    sketch length for a driver not given."""
    return ms.pose_lengths(machine, poses)


def evaluate_machine(
    machine: Machine,
    designs: Mapping[str, F],
    lengths: ArrayLike,
    metrics: Sequence[Metric],
    constraints: Sequence[Constraint] = (),
) -> pd.DataFrame:
    """Every design at every pose (cylinder lengths, shape (p, 3)), as one batch of
    designs × poses samples; one row per design (columns as
    [`excavkin.studies.metrics.evaluate`][]'s)."""
    check_parameters(machine, designs)
    return ms.evaluate_designs(FAMILY, machine, designs, as_lengths(lengths), metrics, constraints)


def _load(path: Path) -> Machine:
    """The machine file's excavator."""
    from excavkin.excavator.machine_file import load_machine

    return load_machine(path)


#: The excavator as a family of designs ([`DesignFamily`][excavkin.machinery.designs.DesignFamily]):
#: the parameters of [`machine_parameters`][excavkin.excavator.designs.machine_parameters],
#: the columns `COLUMNS` at cylinder lengths (``[poses]``).
FAMILY = Family(
    "excavator",
    COLUMNS,
    ANGLES,
    posed=True,
    load=_load,
    parameters=machine_parameters,
    parameter_kind=machine_parameter_kind,
    evaluate=machine_columns,
)


def load_machine_study(path: str | Path) -> MachineStudy:
    """Read a study file whose ``[study]`` names an excavator ``machine`` (module docstring):
    [`excavkin.studies.machine_study.load_machine_study`][] with the excavator's family.

    Parameters
    ----------
    path : str or pathlib.Path
        The study file (TOML); its ``machine`` names an excavator's machine file beside it
        or a built-in excavator example.

    Returns
    -------
    MachineStudy
        The excavator, its design bounds, poses, metrics, constraints and sampling, SI.

    Raises
    ------
    ModelError, UnitError
        A wrong entry, named with its file and table.
    """
    return ms.load_machine_study(path, FAMILY)


__all__ = [
    "ANGLES",
    "COLUMNS",
    "FAMILY",
    "MachineStudy",
    "evaluate_machine",
    "load_machine_study",
    "machine_columns",
    "optimize_machine",
    "pose_lengths",
]
