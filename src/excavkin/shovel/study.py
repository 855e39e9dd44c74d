r"""Design studies of a rope shovel: a study file that names a shovel machine file, whose
parameters are the shovel's (`shovel_parameters`) and whose metrics are its figures
(`COLUMNS`), one value per design.

::

    [study]
    machine = "mining_shovel_machine"  # a machine file beside this one, or a built-in example
    method = "sobol"
    samples = 16

    [parameters]
    "hoist.gear_ratio" = [70, 90]
    "S.y" = ["10.7 m", "11.2 m"]         # the shipper shaft's height

    [metrics]
    cutting_height = { column = "envelope.cutting_height" }
    margin = { column = "dig.margin" }

The parameters of a shovel are its mechanism's points (``P.x``, ``P.y``) and bodies' masses,
inertias and centres of mass, and, named after the machine file's tables,

=====================================  ============================================
``hoist.gear_ratio``                   motor turns per drum turn
``hoist.drum_radius``                  the hoist drum's radius (m)
``hoist.motor_torque``                 each hoist motor's rated torque (N·m)
``crowd.gear_ratio``                   motor turns per pinion turn
``crowd.pinion_radius``                the crowd pinion's pitch radius (m)
``crowd.motor_torque``                 each crowd motor's rated torque (N·m)
``dipper.payload``                     the rated payload (kg)
=====================================  ============================================

Each design is a shovel of its own (`design_shovel`), rated by the wing's own analyses: the
envelope ([`envelope`][excavkin.shovel.envelope.envelope], on a grid of `ENVELOPE_SAMPLES` a
side), the dig with its defaults ([`dig`][excavkin.shovel.dig.dig]) and the boom's loads along
it ([`boom_loads`][excavkin.shovel.loads.boom_loads]). A design whose front does not assemble,
or one of whose figures does not exist, is a design whose one "pose" fails.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.errors import require_known
from excavkin.machinery.designs import Family, model_parameter, model_with, rate_designs, unposed
from excavkin.shovel.machine import Shovel
from excavkin.studies import machine_study as ms

if TYPE_CHECKING:
    from excavkin.studies.machine_study import MachineStudy

#: the drives' and the dipper's parameters, and their kinds
DRIVE_KEYS: dict[str, str] = {
    "hoist.gear_ratio": "dimensionless",
    "hoist.drum_radius": "length",
    "hoist.motor_torque": "torque",
    "crowd.gear_ratio": "dimensionless",
    "crowd.pinion_radius": "length",
    "crowd.motor_torque": "torque",
    "dipper.payload": "mass",
}

#: The shovel's columns and their kinds: its envelope, its drives' rated pull, force and
#: speeds, the dig's least margin and largest efforts, the boom's largest loads along the dig,
#: and the front's mass.
COLUMNS: dict[str, str] = {
    "envelope.cutting_height": "length",
    "envelope.cutting_radius": "length",
    "envelope.dump_height": "length",
    "envelope.dump_radius": "length",
    "envelope.floor_radius": "length",
    "hoist.pull": "force",
    "hoist.speed": "velocity",
    "crowd.force": "force",
    "crowd.speed": "velocity",
    "dig.margin": "dimensionless",
    "dig.bail_pull": "force",
    "dig.crowd_force": "force",
    "loads.suspension": "force",
    "loads.boom_foot": "force",
    "front_mass": "mass",
}
_ENVELOPE = {
    "envelope.cutting_height": "cutting height",
    "envelope.cutting_radius": "cutting radius",
    "envelope.dump_height": "dump height",
    "envelope.dump_radius": "dump radius",
    "envelope.floor_radius": "radius at floor level",
}
#: grid poses a side of the envelope of each design
ENVELOPE_SAMPLES = 21


def shovel_parameters(machine: Shovel) -> dict[str, float]:
    """Every parameter of the shovel and its nominal value (SI): its mechanism's points and
    bodies' mass properties, then the drives' and the dipper's (`DRIVE_KEYS`).

    Parameters
    ----------
    machine : Shovel

    Returns
    -------
    dict of str to float
    """
    model = machine.mechanism.model
    out = {k: v for k, v in machine.mechanism.parameters.items() if model_parameter(model, k)}
    out.update(
        {
            "hoist.gear_ratio": machine.hoist.gear_ratio,
            "hoist.drum_radius": machine.hoist.drum_radius,
            "hoist.motor_torque": machine.hoist.motor.torque,
            "crowd.gear_ratio": machine.crowd.gear_ratio,
            "crowd.pinion_radius": machine.crowd.pinion_radius,
            "crowd.motor_torque": machine.crowd.motor.torque,
            "dipper.payload": machine.dipper.payload,
        }
    )
    return {k: float(v) for k, v in out.items()}


def shovel_parameter_kind(name: str, machine: Shovel) -> str:
    """The physical kind of a shovel parameter (for units at the edges).

    Parameters
    ----------
    name : str
        A name of `shovel_parameters`.
    machine : Shovel

    Returns
    -------
    str
    """
    from excavkin.structure.design import parameter_kind

    if name in DRIVE_KEYS:
        return DRIVE_KEYS[name]
    return parameter_kind(name, machine.mechanism.model)


def design_shovel(machine: Shovel, params: Mapping[str, float]) -> Shovel:
    """One design as a shovel of its own: the model rebuilt with the points and bodies' mass
    properties of ``params``, the drives and the payload of ``params`` (the hoist rope's drum
    radius and gear ratio with them), the rest as the nominal shovel's.

    Parameters
    ----------
    machine : Shovel
        The nominal shovel.
    params : mapping of str to float
        Parameter name (of `shovel_parameters`) → SI value.

    Returns
    -------
    Shovel

    Raises
    ------
    InputError
        A name that is not a parameter of the shovel.
    ModelError, AssemblyError
        A design whose front does not assemble.
    """
    from excavkin.mechanism import Mechanism

    require_known("parameter", params, shovel_parameters(machine))
    h, c = machine.hoist, machine.crowd
    hoist = dataclasses.replace(
        h,
        gear_ratio=float(params.get("hoist.gear_ratio", h.gear_ratio)),
        drum_radius=float(params.get("hoist.drum_radius", h.drum_radius)),
        motor=dataclasses.replace(
            h.motor, torque=float(params.get("hoist.motor_torque", h.motor.torque))
        ),
    )
    crowd = dataclasses.replace(
        c,
        gear_ratio=float(params.get("crowd.gear_ratio", c.gear_ratio)),
        pinion_radius=float(params.get("crowd.pinion_radius", c.pinion_radius)),
        motor=dataclasses.replace(
            c.motor, torque=float(params.get("crowd.motor_torque", c.motor.torque))
        ),
    )
    dipper = dataclasses.replace(
        machine.dipper, payload=float(params.get("dipper.payload", machine.dipper.payload))
    )
    model = model_with(
        machine.mechanism.model, {k: v for k, v in params.items() if k not in DRIVE_KEYS}
    )
    model = dataclasses.replace(
        model,
        ropes=tuple(
            dataclasses.replace(r, gear_ratio=hoist.gear_ratio, drum_radius=hoist.drum_radius)
            if r.name == hoist.rope
            else r
            for r in model.ropes
        ),
    )
    return Shovel(
        Mechanism(model), machine.front, hoist, crowd, dipper, machine.base, machine.gravity,
        machine.name, machine.source,
    )  # fmt: skip


def shovel_figures(machine: Shovel, names: Sequence[str]) -> dict[str, float]:
    """The columns ``names`` (of `COLUMNS`) of one shovel, each from the wing's own analysis.

    Parameters
    ----------
    machine : Shovel
    names : sequence of str
        Names of `COLUMNS`.

    Returns
    -------
    dict of str to float
        SI; NaN where a figure does not exist.

    Raises
    ------
    ExcavkinError
        Where an analysis cannot be made (the dig's start is not reached …).
    """
    require_known("shovel column", names, COLUMNS)
    wanted = set(names)
    out: dict[str, float] = {
        "hoist.pull": machine.hoist.pull,
        "hoist.speed": machine.hoist.speed,
        "crowd.force": machine.crowd.force,
        "crowd.speed": machine.crowd.speed,
        "front_mass": machine.front_mass,
    }
    if wanted & set(_ENVELOPE):
        from excavkin.shovel.envelope import envelope

        env = envelope(machine, ENVELOPE_SAMPLES)
        out.update({col: env[fig] for col, fig in _ENVELOPE.items()})
    if wanted & {"dig.margin", "dig.bail_pull", "dig.crowd_force", "loads.suspension",
                 "loads.boom_foot"}:  # fmt: skip
        from excavkin.shovel.dig import dig
        from excavkin.shovel.loads import boom_loads

        d = dig(machine)
        ok = d.ok
        loads = boom_loads(machine, d)
        nan = float("nan")
        out["dig.margin"] = float(np.min(d.margin[ok])) if ok.any() else nan
        out["dig.bail_pull"] = float(np.max(d.bail_pull[ok])) if ok.any() else nan
        out["dig.crowd_force"] = float(np.max(np.abs(d.crowd_force[ok]))) if ok.any() else nan
        out["loads.suspension"] = float(np.max(loads.suspension[ok])) if ok.any() else nan
        foot = np.hypot(loads.boom_foot[:, 0], loads.boom_foot[:, 1])
        out["loads.boom_foot"] = float(np.max(foot[ok])) if ok.any() else nan
    return {k: float(out[k]) for k in names}


def shovel_columns(
    machine: Shovel, params: Mapping[str, F], names: Sequence[str], n: int
) -> tuple[dict[str, F], NDArray[np.bool_]]:
    """The columns ``names`` of n designs, design i ``params[k][i]``; and which are valid,
    shape (n,). Each distinct design is rated once.

    Parameters
    ----------
    machine : Shovel
        The nominal shovel.
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
        lambda p: shovel_figures(design_shovel(machine, p), names),
        COLUMNS,
        "shovel column",
    )


def _load(path: Path) -> Shovel:
    from excavkin.errors import ModelError
    from excavkin.shovel.machine_file import load_machine

    machine = load_machine(path)
    if not isinstance(machine, Shovel):
        raise ModelError(f"{path}: a rope backhoe; a shovel study needs a rope shovel's file")
    return machine


#: The rope shovel as a family of designs: the parameters of `shovel_parameters`, the columns
#: `COLUMNS`, no poses.
FAMILY = Family(
    "shovel", COLUMNS, frozenset(), False, _load, shovel_parameters, shovel_parameter_kind,
    unposed(shovel_columns),
)  # fmt: skip


def load_shovel_study(path: str | Path) -> MachineStudy:
    """A study file whose ``[study]`` names a shovel ``machine`` (module docstring), read by
    [`excavkin.studies.machine_study.load_machine_study`][] with the shovel's family.

    Parameters
    ----------
    path : str or pathlib.Path
        The study file (TOML).

    Returns
    -------
    MachineStudy

    Raises
    ------
    ModelError, UnitError
        An entry of the file that is wrong, named with its file and table.
    """
    return ms.load_machine_study(path, FAMILY)
