r"""Design studies and optimisation of a wheel loader: a study file that names a loader machine
file, whose parameters are the loader's (`loader_parameters`) and whose metrics are its rated
figures (`COLUMNS`), each taken at the pose its standard defines.

::

    [study]
    machine = "wheel_loader_machine"  # a machine file beside this one, or a built-in example
    method = "sobol"
    samples = 64

    [parameters]                      # the loader's parameters, with bounds
    "chassis.counterweight.mass" = ["2500 kg", "3500 kg"]
    "cylinders.tilt.bore" = ["160 mm", "200 mm"]

    [metrics]                         # no poses: one value per design
    roc = { column = "rated_operating_capacity" }
    breakout = { column = "breakout.tilt" }

The parameters of a loader are its mechanism's points (``P.x``, ``P.y``) and bodies' masses,
inertias and centres of mass, and, named after the machine file's tables,

=====================================  ============================================
``cylinders.ROLE.bore``                piston diameter (m), ROLE lift, tilt
``cylinders.ROLE.rod``                 rod diameter (m)
``cylinders.ROLE.retracted``           pin-to-pin length fully retracted (m)
``cylinders.ROLE.stroke``              stroke (m)
``circuits.NAME.working``              working (main relief) pressure (Pa)
``circuits.NAME.relief``               port relief pressure (Pa)
``chassis.counterweight.mass``         the counterweight (kg)
=====================================  ============================================

Each design is a loader of its own (`design_loader`), rated by the wing's own analyses:
[`dimensions`][excavkin.loader.dimensions.dimensions],
[`breakout`][excavkin.loader.breakout.breakout],
[`static_tipping`][excavkin.loader.tipping.static_tipping],
[`parallel_lift`][excavkin.loader.parallel_lift.parallel_lift] and
[`cycle`][excavkin.loader.cycle.cycle]; each finds its pose by root-finding on the design's own
linkage, so a design is one call of each (vectorised over its poses), not a batch over designs.
A design whose linkage does not assemble, whose cylinders or circuits cannot be, or one of
whose figures does not exist (no pose gives it) is a design whose one "pose" fails.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.errors import require_known
from excavkin.loader.machine import Loader
from excavkin.machinery.designs import (
    Family,
    cylinder_parameters,
    design_cylinders,
    model_parameter,
    model_with,
    rate_designs,
    unposed,
)
from excavkin.studies import machine_study as ms
from excavkin.studies.machine_study import MachineStudy, optimize_machine

if TYPE_CHECKING:
    import pandas as pd

    from excavkin.studies.metrics import Constraint, Metric
    from excavkin.studies.optimize import Optimum

#: the chassis entries that are parameters, and their kinds
CHASSIS_KEYS: dict[str, str] = {"chassis.counterweight.mass": "mass"}

#: The loader's columns and their kinds: its SAE J732 / ISO 7131 dimensions
#: (`excavkin.loader.dimensions`), its breakout forces through the tilt and the lift circuit
#: (`excavkin.loader.breakout`), its static tipping loads and rated operating capacity
#: (`excavkin.loader.tipping`), the bucket's angle change and largest departure over the lift
#: with the tilt held (`excavkin.loader.parallel_lift`), its SAE J732 cycle times at the rated
#: operating capacity (`excavkin.loader.cycle`) and its operating mass.
COLUMNS: dict[str, str] = {
    "hinge_pin_height": "length",
    "dump_clearance": "length",
    "dump_reach": "length",
    "digging_depth": "length",
    "rollback_at_ground": "angle",
    "rollback_at_carry": "angle",
    "rollback_at_full_lift": "angle",
    "dump_angle": "angle",
    "breakout.tilt": "force",
    "breakout.lift": "force",
    "tipping.straight": "mass",
    "tipping.full_turn": "mass",
    "rated_operating_capacity": "mass",
    "lift.angle_change": "angle",
    "lift.deviation": "angle",
    "cycle.raise": "time",
    "cycle.lower_empty": "time",
    "cycle.dump": "time",
    "cycle.time": "time",
    "operating_mass": "mass",
}
#: the angle columns
ANGLES = frozenset(k for k, kind in COLUMNS.items() if kind == "angle")
#: the dimensions' figures by column (`excavkin.loader.dimensions.Dimensions` names them)
_FIGURES = {
    "hinge_pin_height": "hinge-pin height at full lift",
    "dump_clearance": "dump clearance at 45 deg",
    "dump_reach": "dump reach at 45 deg",
    "digging_depth": "digging depth",
    "rollback_at_ground": "rollback at ground",
    "rollback_at_carry": "rollback at carry",
    "rollback_at_full_lift": "rollback at full lift",
    "dump_angle": "dump angle at full lift",
}
#: samples of the lift for the parallel-lift columns (the command's default)
LIFT_SAMPLES = 101


def loader_parameters(machine: Loader) -> dict[str, float]:
    """Every parameter of the loader and its nominal value (SI): its mechanism's points and
    bodies' mass properties, then ``cylinders.ROLE.KEY``, ``circuits.NAME.KEY`` and
    ``chassis.counterweight.mass`` (module docstring).

    Parameters
    ----------
    machine : Loader

    Returns
    -------
    dict of str to float
    """
    model = machine.mechanism.model
    out = {k: v for k, v in machine.mechanism.parameters.items() if model_parameter(model, k)}
    out.update(cylinder_parameters(machine.cylinders, machine.circuits))
    out["chassis.counterweight.mass"] = float(machine.chassis.counterweight.mass)
    return out


def loader_parameter_kind(name: str, machine: Loader) -> str:
    """The physical kind of a loader parameter (for units at the edges).

    Parameters
    ----------
    name : str
        A name of `loader_parameters`.
    machine : Loader

    Returns
    -------
    str
    """
    from excavkin.structure.design import parameter_kind

    if name in CHASSIS_KEYS:
        return CHASSIS_KEYS[name]
    if name.startswith("cylinders."):
        return "length"
    if name.startswith("circuits."):
        return "pressure"
    return parameter_kind(name, machine.mechanism.model)


def design_loader(machine: Loader, params: Mapping[str, float]) -> Loader:
    """One design as a loader of its own: the model rebuilt with the points and bodies' mass
    properties of ``params``, the cylinders, circuits and counterweight of ``params``, the rest
    as the nominal loader's.

    Parameters
    ----------
    machine : Loader
        The nominal loader.
    params : mapping of str to float
        Parameter name (of `loader_parameters`) → SI value.

    Returns
    -------
    Loader

    Raises
    ------
    InputError
        A name that is not a parameter of the loader.
    ModelError, AssemblyError
        A design whose linkage does not assemble or whose cylinders or circuits cannot be.
    """
    import dataclasses

    from excavkin.mechanism import Mechanism

    require_known("parameter", params, loader_parameters(machine))

    cylinders, circuits = design_cylinders(machine.cylinders, machine.circuits, params)
    cw = machine.chassis.counterweight
    chassis = dataclasses.replace(
        machine.chassis,
        counterweight=dataclasses.replace(
            cw, mass=float(params.get("chassis.counterweight.mass", cw.mass))
        ),
    )
    return Loader(
        Mechanism(model_with(machine.mechanism.model, params)), machine.linkage, cylinders,
        circuits, machine.bucket, chassis, carry_height=machine.carry_height,
        gravity=machine.gravity, hydraulics=machine.hydraulics, name=machine.name,
        source=machine.source,
    )  # fmt: skip


def loader_figures(machine: Loader, names: Sequence[str]) -> dict[str, float]:
    """The columns ``names`` (of `COLUMNS`) of one loader, each from the wing's own analysis.

    Parameters
    ----------
    machine : Loader
    names : sequence of str
        Names of `COLUMNS`.

    Returns
    -------
    dict of str to float
        SI; NaN where a figure does not exist (its pose cannot be reached).

    Raises
    ------
    ExcavkinError
        Where an analysis cannot be made (no pose levels the floor on the ground, no pumps
        for the cycle …).
    """
    require_known("loader column", names, COLUMNS)
    out: dict[str, float] = {}
    wanted = set(names)
    if wanted & set(_FIGURES):
        from excavkin.loader.dimensions import dimensions

        dims = dimensions(machine)
        for col, figure in _FIGURES.items():
            out[col] = dims[figure]
    if wanted & {"breakout.tilt", "breakout.lift"}:
        from excavkin.loader.breakout import breakout

        b = breakout(machine)
        out["breakout.tilt"], out["breakout.lift"] = b.tilt.force, b.lift.force
    if wanted & {"tipping.straight", "tipping.full_turn", "rated_operating_capacity"}:
        from excavkin.loader.tipping import static_tipping

        t = static_tipping(machine)
        out["tipping.straight"], out["tipping.full_turn"] = t.straight.load, t.full_turn.load
        out["rated_operating_capacity"] = t.rated_operating_capacity
    if wanted & {"lift.angle_change", "lift.deviation"}:
        from excavkin.loader.parallel_lift import parallel_lift

        lift = parallel_lift(machine, LIFT_SAMPLES)
        out["lift.angle_change"], out["lift.deviation"] = lift.change, lift.deviation
    if any(n.startswith("cycle.") for n in wanted):
        from excavkin.loader.cycle import cycle

        c = cycle(machine)
        out["cycle.raise"] = c["raise"].time
        out["cycle.lower_empty"] = c["lower empty"].time
        out["cycle.dump"] = c["dump"].time
        out["cycle.time"] = c.total
    if "operating_mass" in wanted:
        out["operating_mass"] = machine.mass
    return {k: float(out[k]) for k in names}


def loader_columns(
    machine: Loader,
    params: Mapping[str, F],
    names: Sequence[str],
    n: int,
) -> tuple[dict[str, F], NDArray[np.bool_]]:
    """The columns ``names`` of n designs, design i ``params[k][i]``; and which are valid (the
    design can be built and every figure asked for exists), shape (n,). Each distinct design
    is rated once.

    Parameters
    ----------
    machine : Loader
        The nominal loader.
    params : mapping of str to ndarray, shape (n,)
        Parameter → its SI value in each design.
    names : sequence of str
        Names of `COLUMNS`.
    n : int
        The designs.

    Returns
    -------
    columns : dict of str to ndarray, shape (n,)
    ok : ndarray of bool, shape (n,)
    """
    return rate_designs(
        params,
        names,
        n,
        lambda p: loader_figures(design_loader(machine, p), names),
        COLUMNS,
        "loader column",
    )


def _load(path: Path) -> Loader:
    """The machine file's loader."""
    from excavkin.loader.machine_file import load_machine

    return load_machine(path)


#: The wheel loader as a family of designs
#: ([`DesignFamily`][excavkin.machinery.designs.DesignFamily]): the parameters of
#: `loader_parameters`, the columns `COLUMNS`, no poses.
FAMILY = Family(
    "loader",
    COLUMNS,
    ANGLES,
    False,
    _load,
    loader_parameters,
    loader_parameter_kind,
    unposed(loader_columns),
)


def load_loader_study(path: str | Path) -> MachineStudy:
    """A study file whose ``[study]`` names a loader ``machine`` (module docstring), read by
    [`excavkin.studies.machine_study.load_machine_study`][] with the loader's family.

    Parameters
    ----------
    path : str or pathlib.Path
        The study file (TOML), naming a loader's machine file beside it (a path from its
        folder) or a built-in loader example.

    Returns
    -------
    MachineStudy
        The loader, the design bounds, metrics, constraints and sampling, SI.

    Raises
    ------
    ModelError, UnitError
        An entry of the file that is wrong, named with its file and table.
    """
    return ms.load_machine_study(path, FAMILY)


def evaluate_loader(
    machine: Loader,
    designs: Mapping[str, F],
    metrics: Sequence[Metric],
    constraints: Sequence[Constraint] = (),
) -> pd.DataFrame:
    """The metrics of loader designs, one row per design.

    Parameters
    ----------
    machine : Loader
        The nominal loader.
    designs : mapping of str to ndarray, shape (d,)
        Parameter (of `loader_parameters`) → its SI value in each design.
    metrics : sequence of Metric
        Of `COLUMNS`.
    constraints : sequence of Constraint

    Returns
    -------
    pandas.DataFrame
        As [`excavkin.studies.metrics.evaluate`][] gives it.
    """
    return ms.evaluate_designs(FAMILY, machine, designs, np.zeros((1, 0)), metrics, constraints)


def optimize_loader(
    study: MachineStudy,
    *,
    method: str | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Optimum:
    """The best design of a loader study ([`excavkin.studies.machine_study.optimize_machine`][]
    with the study's ``[optimize]`` settings).

    Parameters
    ----------
    study : MachineStudy
        A loader study (`load_loader_study`).
    method : {"slsqp", "differential-evolution"}, optional
        Override the study's method.
    progress : callable, optional
        ``progress(iterations, maxiter)`` after each iteration.

    Returns
    -------
    Optimum
    """
    return optimize_machine(study, method=method, progress=progress)


__all__ = [
    "ANGLES",
    "COLUMNS",
    "FAMILY",
    "design_loader",
    "evaluate_loader",
    "load_loader_study",
    "loader_columns",
    "loader_figures",
    "loader_parameter_kind",
    "loader_parameters",
    "optimize_loader",
]
