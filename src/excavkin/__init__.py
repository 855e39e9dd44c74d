"""excavkin — analytical kinematics and kinetostatics of planar excavator mechanisms.

Describe a mechanism once (TOML or Python, with units); solve positions, velocities,
accelerations, transmission angles, and forces over millions of samples.

>>> import excavkin
>>> mech = excavkin.load(excavkin.example_path("fourbar"))
>>> mech.inputs
('crank',)
"""

from __future__ import annotations

from pathlib import Path

from excavkin.errors import (
    AssemblyError,
    ExcavkinError,
    InputError,
    MobilityError,
    ModelError,
    SingularityWarning,
    SolveFailure,
    UnitError,
)
from excavkin.kinematics import KinematicResult, Status, Tolerances
from excavkin.mechanism import Mechanism
from excavkin.model import Body, LinearDriver, Model, RotaryDriver, Slider
from excavkin.model.entities import Gravity, PointForce, Torque

__version__ = "0.1.0"

__all__ = [
    "AssemblyError",
    "Body",
    "ExcavkinError",
    "Gravity",
    "InputError",
    "KinematicResult",
    "LinearDriver",
    "Mechanism",
    "MobilityError",
    "Model",
    "ModelError",
    "PointForce",
    "RotaryDriver",
    "SingularityWarning",
    "Slider",
    "SolveFailure",
    "Status",
    "Torque",
    "Tolerances",
    "UnitError",
    "example_path",
    "load",
    "loads",
]


def load(path: str | Path) -> Mechanism:
    """Read, validate and compile a mechanism file (TOML).

    Raises
    ------
    ModelError
        Naming the file, table and entry of the problem.
    """
    from excavkin.io.toml_model import load_model

    return Mechanism(load_model(path))


def loads(text: str, source: str | None = None) -> Mechanism:
    """Like :func:`load`, from TOML text."""
    from excavkin.io.toml_model import loads_model

    return Mechanism(loads_model(text, source))


def example_path(name: str) -> Path:
    """Path of a built-in example model, e.g. ``"fourbar"``, ``"slider_crank"``, ``"excavator"``."""
    here = Path(__file__).resolve().parent
    for folder in (here / "examples", here.parents[1] / "examples"):
        candidate = folder / f"{name}.toml"
        if candidate.is_file():
            return candidate
    known = sorted(
        {
            p.stem
            for f in (here / "examples", here.parents[1] / "examples")
            if f.is_dir()
            for p in f.glob("*.toml")
        }
    )
    raise ModelError(f"no built-in example {name!r} (known: {', '.join(known)})")
