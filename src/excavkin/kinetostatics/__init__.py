"""Kinetostatics: joint forces, cylinder forces and driver torques from the kinematics.

d'Alembert: the inertia of every body (−m·a_S at its centre of mass, −J·ε) joins the applied
loads, and the equilibrium of every moving body and every pin is solved for the pin forces, the
axial forces of the driven and locked linear elements, the slider normal forces and the rotary
drivers' torques (DESIGN.md §5, ``docs/kinetostatics.md``).

>>> import numpy as np, excavkin
>>> from excavkin.kinetostatics import Gravity, solve_forces
>>> mech = excavkin.load(excavkin.example_path("fourbar"))
>>> kin = mech.solve({"crank": np.radians([0.0, 90.0])}, {"crank": 10.0})
>>> res = solve_forces(kin, [Gravity()])
>>> res.driver_torque.shape
(2, 1)
>>> bool(np.all(res.power_balance().relative < 1e-9))
True
"""

from excavkin.kinetostatics.equilibrium import (
    StaticallyIndeterminateError,
    StaticsSystem,
    Unknown,
    compile_statics,
)
from excavkin.kinetostatics.inertia import (
    MassProperties,
    centre_of_mass,
    inertia_loads,
    kinetic_energy,
    kinetic_energy_rate,
)
from excavkin.kinetostatics.loads import (
    STANDARD_GRAVITY,
    Gravity,
    Load,
    PointForce,
    Torque,
    check_loads,
    model_loads,
)
from excavkin.kinetostatics.result import ForceResult, PowerBalance
from excavkin.kinetostatics.solve import solve_forces

__all__ = [
    "STANDARD_GRAVITY",
    "ForceResult",
    "Gravity",
    "Load",
    "MassProperties",
    "PointForce",
    "PowerBalance",
    "StaticallyIndeterminateError",
    "StaticsSystem",
    "Torque",
    "Unknown",
    "centre_of_mass",
    "check_loads",
    "compile_statics",
    "inertia_loads",
    "kinetic_energy",
    "kinetic_energy_rate",
    "model_loads",
    "solve_forces",
]
