"""excavkin — analytical kinematics and kinetostatics of planar excavator mechanisms.

Describe a mechanism once (TOML or Python, with units); solve positions, velocities,
accelerations, transmission angles, and forces over millions of samples.

>>> import excavkin
>>> mech = excavkin.load("fourbar")
>>> mech.inputs
('crank',)
"""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
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
    from excavkin.model import (
        Body,
        CamFollower,
        GearPair,
        LinearDriver,
        Model,
        RackPinion,
        RotaryDriver,
        Slider,
    )
    from excavkin.model.entities import Gravity, PointForce, Rope, Torque
    from excavkin.studies.optimize import Optimum, optimize_study
    from excavkin.studies.study import StudyResult, run_study
    from excavkin.studies.study_file import load_study
    from excavkin.studies.tolerance import ToleranceBands, tolerance_bands

#: where each public name lives; imported on first use, so that ``import excavkin`` (and the
#: command line's ``--help``) does not load NumPy, pandas or pint before they are needed
_LAZY = {
    **dict.fromkeys(
        (
            "AssemblyError",
            "ExcavkinError",
            "InputError",
            "MobilityError",
            "ModelError",
            "SingularityWarning",
            "SolveFailure",
            "UnitError",
        ),
        "excavkin.errors",
    ),
    **dict.fromkeys(("KinematicResult", "Status", "Tolerances"), "excavkin.kinematics"),
    "Mechanism": "excavkin.mechanism",
    **dict.fromkeys(
        (
            "Body",
            "CamFollower",
            "GearPair",
            "LinearDriver",
            "Model",
            "RackPinion",
            "RotaryDriver",
            "Slider",
        ),
        "excavkin.model",
    ),
    **dict.fromkeys(("Gravity", "PointForce", "Rope", "Torque"), "excavkin.model.entities"),
    **dict.fromkeys(("ToleranceBands", "tolerance_bands"), "excavkin.studies.tolerance"),
    **dict.fromkeys(("Optimum", "optimize_study"), "excavkin.studies.optimize"),
    **dict.fromkeys(("StudyResult", "run_study"), "excavkin.studies.study"),
    "load_study": "excavkin.studies.study_file",
}


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'excavkin' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY})


__version__ = "0.1.0"

__all__ = [
    "AssemblyError",
    "Body",
    "CamFollower",
    "ExcavkinError",
    "GearPair",
    "Gravity",
    "InputError",
    "KinematicResult",
    "LinearDriver",
    "Mechanism",
    "MobilityError",
    "Optimum",
    "Model",
    "ModelError",
    "PointForce",
    "RackPinion",
    "Rope",
    "RotaryDriver",
    "SingularityWarning",
    "Slider",
    "SolveFailure",
    "Status",
    "StudyResult",
    "Torque",
    "ToleranceBands",
    "Tolerances",
    "UnitError",
    "example_path",
    "examples",
    "source_file",
    "load",
    "load_study",
    "loads",
    "optimize_study",
    "run_study",
    "tolerance_bands",
]


def load(path: str | Path) -> Mechanism:
    """Read, validate and compile a mechanism file (TOML).

    Parameters
    ----------
    path : str or Path
        The file, or the name of a built-in example (``"fourbar"``; [`examples`][excavkin.examples]
        lists
        them).

    Returns
    -------
    Mechanism

    Raises
    ------
    ModelError
        Naming the file, table and entry of the problem; for a file that does not exist, the
        nearest built-in example.

    Examples
    --------
    >>> import excavkin
    >>> excavkin.load("fourbar").inputs
    ('crank',)
    """
    from excavkin.io.toml_model import load_model
    from excavkin.mechanism import Mechanism

    return Mechanism(load_model(source_file(path)))


def loads(text: str, source: str | None = None) -> Mechanism:
    """Like [`load`][excavkin.load], from TOML text.

    Parameters
    ----------
    text : str
        The mechanism file's text.
    source : str, optional
        What error messages name as the file (default: none).

    Returns
    -------
    Mechanism

    Raises
    ------
    ModelError
        Naming the source, table and entry of the problem.
    """
    from excavkin.io.toml_model import loads_model
    from excavkin.mechanism import Mechanism

    return Mechanism(loads_model(text, source))


def _example_folders() -> list[Path]:
    """The built-in examples: inside the installed package, or the checkout's examples/."""
    from importlib.resources import files

    here = Path(str(files("excavkin")))
    return [f for f in (here / "examples", here.parents[1] / "examples") if f.is_dir()]


def examples(kind: str | None = None) -> list[str]:
    """Names of the built-in examples.

    Parameters
    ----------
    kind : {"model", "machine", "study"}, optional
        Only mechanism models (for [`load`][excavkin.load]), only machine files (for
        [`excavkin.families.load_machine`][], or a family's own reader such as
        [`excavkin.excavator.machine_file.load_machine`][]) or only design studies (for
        ``excavkin study``, in ``examples/studies/``); default all. A file is a machine file
        of the kind its family registers ([`excavkin.families`][]).

    Returns
    -------
    list of str
    """
    import tomllib

    from excavkin.families import family_of

    names: dict[str, str] = {}
    for folder in _example_folders():
        for p in sorted(folder.glob("*.toml")):
            try:
                data = tomllib.loads(p.read_text(encoding="utf-8"))
            except tomllib.TOMLDecodeError:
                data = {}  # listed as a model: loading it names the problem
            family = family_of(data, str(p))
            names.setdefault(p.stem, "model" if family is None else family.kind)
        for p in sorted((folder / "studies").glob("*.toml")):
            names.setdefault(p.stem, "study")
    return sorted(n for n, k in names.items() if kind is None or k == kind)


def example_path(name: str) -> Path:
    """Path of a built-in example, e.g. ``"fourbar"``, ``"slider_crank"``, ``"excavator"``.

    Parameters
    ----------
    name : str
        The example's name (its file's stem); `examples` lists them.

    Returns
    -------
    Path
        Its ``.toml`` file: a mechanism model, a machine file or a design study.

    Raises
    ------
    ModelError
        For an unknown name, listing the closest and all known names.
    """
    for folder in _example_folders():
        for candidate in (folder / f"{name}.toml", folder / "studies" / f"{name}.toml"):
            if candidate.is_file():
                return candidate
    from excavkin.errors import ModelError, did_you_mean

    known = examples()
    hint = did_you_mean(name, known)
    raise ModelError(f"no built-in example {name!r}{hint} (known: {', '.join(known)})")


def source_file(name: str | Path, kind: str = "model") -> Path:
    """The file a user names: a path, or a built-in example's name.

    A name with no folder and no suffix that is not a file here is a built-in example of
    ``kind`` (``"fourbar"``); anything else is a path.

    Parameters
    ----------
    name : str or Path
        A path to a ``.toml`` file, or the name of a built-in example.
    kind : {"model", "machine", "study"}
        Which built-in examples a bare name may name.

    Returns
    -------
    Path

    Raises
    ------
    ModelError
        Neither an existing file nor a built-in example: the message names the closest
        built-in examples (a tutorial's ``examples/fourbar.toml`` run outside the repository
        is the built-in ``fourbar``).
    """
    from excavkin.errors import ModelError, did_you_mean

    path = Path(name)
    if path.exists():
        return path
    known = examples(kind)
    bare = not path.suffix and len(path.parts) == 1
    if bare and str(name) in known:
        return example_path(str(name))
    if bare:
        for other in ("model", "machine", "study"):
            if other != kind and str(name) in examples(other):
                raise ModelError(
                    f"a built-in {other}, and a {kind} is expected here (built-in {kind}s: "
                    f"{', '.join(known)}; `excavkin demo --list` lists them all)",
                    source=str(name),
                )
    hint = did_you_mean(path.stem, known)
    if path.stem in known and not bare:
        hint = f"; the built-in {kind} {path.stem!r} is read by its name alone"
    if not bare:
        raise ModelError(f"no such file{hint}", source=str(name))
    listing = ", ".join(known)
    raise ModelError(
        f"no such file, and no built-in example of that name{hint} (built-in {kind}s: {listing})",
        source=str(name),
    )
