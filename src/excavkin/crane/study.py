r"""Design studies and optimisation of a crane: a study file that names a crane machine file,
whose parameters are the crane's (`crane_parameters`) and whose metrics are its rated figures
(`COLUMNS`), one value per design.

::

    [study]
    machine = "telescopic_crane_machine"
    method = "sobol"
    samples = 32

    [parameters]
    "turning.counterweight.mass" = ["3500 kg", "6000 kg"]
    "cylinders.luff.bore" = ["220 mm", "280 mm"]

    [metrics]
    moment = { column = "load_moment" }
    mass = { column = "mass" }

The parameters of a crane are its mechanism's points (``P.x``, ``P.y``) and bodies' masses,
inertias and centres of mass, and, named after the machine file's tables,

=====================================  ============================================
``cylinders.ROLE.bore``                piston diameter (m), ROLE luff, knuckle, telescope
``cylinders.ROLE.rod``                 rod diameter (m)
``cylinders.ROLE.retracted``           pin-to-pin length fully retracted (m)
``cylinders.ROLE.stroke``              stroke (m)
``circuits.NAME.working``              working pressure (Pa)
``circuits.NAME.relief``               port relief pressure (Pa)
``hoist.line_pull``                    the winch's rated single-line pull (N)
``turning.NAME.mass``                  a mass that slews (kg)
``fixed.NAME.mass``                    a mass of the carrier (kg)
=====================================  ============================================

Each design is a crane of its own (`design_crane`), rated by its load chart over a fixed grid
(`CHART_STEP` of radius over its working range, the second cylinder at its two ends and its
middle, four slew sectors), each cell the least over the sectors.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.crane.machine import Crane
from excavkin.errors import require_known
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
from excavkin.studies.machine_study import MachineStudy

#: The crane's columns and their kinds: the largest radius and the highest tip of its working
#: range (`excavkin.crane.reach`); from its load chart, each cell the least over the sectors,
#: the largest capacity and the largest load moment (the capacity's weight × radius, N·m); its
#: mass without a load.
COLUMNS: dict[str, str] = {
    "reach": "length",
    "height": "length",
    "capacity.max": "mass",
    "load_moment": "torque",
    "mass": "mass",
}
#: the chart's radius step (m) and the working range's samples over each stroke
CHART_STEP, RANGE_SAMPLES = 0.25, 41


def crane_parameters(machine: Crane) -> dict[str, float]:
    """Every parameter of the crane and its nominal value (SI): its mechanism's points and
    bodies' mass properties, then ``cylinders.ROLE.KEY``, ``circuits.NAME.KEY``,
    ``hoist.line_pull``, ``turning.NAME.mass`` and ``fixed.NAME.mass`` (module docstring).

    Parameters
    ----------
    machine : Crane

    Returns
    -------
    dict of str to float
    """
    model = machine.mechanism.model
    out = {k: v for k, v in machine.mechanism.parameters.items() if model_parameter(model, k)}
    out.update(cylinder_parameters(machine.cylinders, machine.circuits))
    out["hoist.line_pull"] = machine.hoist.line_pull
    for key, masses in (("turning", machine.support.turning), ("fixed", machine.support.fixed)):
        for m in masses:
            out[f"{key}.{m.name}.mass"] = float(m.mass)
    return out


def crane_parameter_kind(name: str, machine: Crane) -> str:
    """The physical kind of a crane parameter (for units at the edges).

    Parameters
    ----------
    name : str
        A name of `crane_parameters`.
    machine : Crane

    Returns
    -------
    str
    """
    from excavkin.structure.design import parameter_kind

    if name == "hoist.line_pull":
        return "force"
    if name.startswith(("turning.", "fixed.")):
        return "mass"
    if name.startswith("cylinders."):
        return "length"
    if name.startswith("circuits."):
        return "pressure"
    return parameter_kind(name, machine.mechanism.model)


def design_crane(machine: Crane, params: Mapping[str, float]) -> Crane:
    """One design as a crane of its own: the model, cylinders, circuits, hoist and masses of
    ``params``, the rest as the nominal crane's.

    Parameters
    ----------
    machine : Crane
        The nominal crane.
    params : mapping of str to float
        Parameter name (of `crane_parameters`) → SI value.

    Returns
    -------
    Crane

    Raises
    ------
    InputError
        A name that is not a parameter of the crane.
    ModelError, AssemblyError
        A design whose booms do not assemble or whose cylinders or circuits cannot be.
    """
    import dataclasses

    from excavkin.machinery.base import Mass
    from excavkin.mechanism import Mechanism

    require_known("parameter", params, crane_parameters(machine))
    cylinders, circuits = design_cylinders(machine.cylinders, machine.circuits, params)
    sup = machine.support

    def masses(key: str, group: Sequence[Mass]) -> tuple[Mass, ...]:
        return tuple(
            dataclasses.replace(m, mass=float(params.get(f"{key}.{m.name}.mass", m.mass)))
            for m in group
        )

    return Crane(
        Mechanism(model_with(machine.mechanism.model, params)),
        machine.kind,
        machine.linkage,
        cylinders,
        circuits,
        dataclasses.replace(
            machine.hoist,
            line_pull=float(params.get("hoist.line_pull", machine.hoist.line_pull)),
        ),
        dataclasses.replace(
            sup, turning=masses("turning", sup.turning), fixed=masses("fixed", sup.fixed)
        ),
        gravity=machine.gravity,
        name=machine.name,
        source=machine.source,
        stability=machine.stability,
    )


def crane_figures(machine: Crane, names: Sequence[str]) -> dict[str, float]:
    """The columns ``names`` (of `COLUMNS`) of one crane.

    Parameters
    ----------
    machine : Crane
    names : sequence of str
        Names of `COLUMNS`.

    Returns
    -------
    dict of str to float
        SI; NaN where the chart has no cell in reach.
    """
    from excavkin.crane.chart import load_chart
    from excavkin.crane.reach import reach

    require_known("crane column", names, COLUMNS)
    wanted = set(names)
    rg = reach(machine, RANGE_SAMPLES)
    x, y = rg.tip[..., 0], rg.tip[..., 1]
    out = {"reach": float(x.max()), "height": float(y.max()), "mass": machine.mass}
    if wanted & {"capacity.max", "load_moment"}:
        lo = max(float(x.min()), 0.0)
        radius = np.arange(np.ceil(lo / CHART_STEP) * CHART_STEP, x.max() + 1e-9, CHART_STEP)
        chart = load_chart(machine, radius)
        least = chart.capacity.min(axis=2)  # every sector of a cell in reach together
        good = np.isfinite(least)
        out["capacity.max"] = float(least[good].max()) if good.any() else np.nan
        moment = machine.gravity * least * chart.radius[:, None]
        out["load_moment"] = float(moment[good].max()) if good.any() else np.nan
    return {k: float(out[k]) for k in names}


def crane_columns(
    machine: Crane, params: Mapping[str, F], names: Sequence[str], n: int
) -> tuple[dict[str, F], NDArray[np.bool_]]:
    """The columns ``names`` of n designs, design i ``params[k][i]``; and which are valid,
    shape (n,). Each distinct design is rated once.

    Parameters
    ----------
    machine : Crane
        The nominal crane.
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
        lambda p: crane_figures(design_crane(machine, p), names),
        COLUMNS,
        "crane column",
    )


def _load(path: Path) -> Crane:
    """The machine file's crane."""
    from excavkin.crane.machine_file import load_machine

    return load_machine(path)


#: The crane as a family of designs
#: ([`DesignFamily`][excavkin.machinery.designs.DesignFamily]): the parameters of
#: `crane_parameters`, the columns `COLUMNS`, no poses.
FAMILY = Family(
    "crane",
    COLUMNS,
    frozenset(),
    False,
    _load,
    crane_parameters,
    crane_parameter_kind,
    unposed(crane_columns),
)


def load_crane_study(path: str | Path) -> MachineStudy:
    """A study file whose ``[study]`` names a crane ``machine`` (module docstring), read by
    [`excavkin.studies.machine_study.load_machine_study`][] with the crane's family.

    Parameters
    ----------
    path : str or pathlib.Path
        The study file (TOML), naming a crane's machine file beside it or a built-in one.

    Returns
    -------
    MachineStudy

    Raises
    ------
    ModelError, UnitError
        An entry of the file that is wrong, named with its file and table.
    """
    return ms.load_machine_study(path, FAMILY)
