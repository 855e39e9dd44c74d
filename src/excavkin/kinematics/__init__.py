"""Exact, vectorised positions, velocities and accelerations along a solve plan."""

from excavkin.kinematics.result import KinematicResult, Status
from excavkin.kinematics.solve import Assembly, Tolerances, assemble
from excavkin.kinematics.sweep import solve_kinematics

__all__ = ["Assembly", "KinematicResult", "Status", "Tolerances", "assemble", "solve_kinematics"]
