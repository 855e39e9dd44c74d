"""Machine families, registered by the wings: the core knows none of them by name.

A machine file names its family with a top-level key, ``family = "excavator"``. A wing (a
package above the machinery layer: the excavator, later a wheel loader or a crane) registers
its [`Family`][excavkin.families.Family] under the entry-point group ``excavkin.families`` in
``pyproject.toml``::

    [project.entry-points."excavkin.families"]
    excavator = "excavkin.excavator.family:FAMILY"

The core reads machine files through it: [`examples`][excavkin.examples] lists a built-in file
under its family's example kind, and [`load_machine`][excavkin.families.load_machine] reads a
machine file of any family with its family's reader. A file without the ``family`` key is
claimed by the family whose ``recognises`` says it is one of its own (the excavator's: a
``[front]`` table), so that files written before the key keep reading.

The entry points are the installed package's: after a wing is added, reinstall the package
(``pip install -e .``) for its family to be found.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cache
from importlib import import_module
from pathlib import Path
from typing import Any

#: the entry-point group through which wings register their families
GROUP = "excavkin.families"


@dataclass(frozen=True, slots=True)
class Family:
    """A machine family, as its wing registers it.

    Attributes
    ----------
    name : str
        The value of a machine file's ``family`` key (``"excavator"``).
    kind : str
        The example kind its built-in files are listed under (``"machine"``).
    reader : str
        ``"module:function"``: the function that reads one of its machine files, given a path
        or a built-in name; imported only when called.
    recognises : callable, optional
        ``recognises(data) -> bool`` on a file's top-level table: whether a file without the
        ``family`` key is one of this family's (files written before the key existed).
    description : str
        One line, for listings.
    """

    name: str
    kind: str
    reader: str
    recognises: Callable[[Mapping[str, Any]], bool] | None = None
    description: str = ""

    def read(self, path: str | Path) -> Any:
        """Read one of this family's machine files with its reader.

        Parameters
        ----------
        path : str or Path
            The file, or the name of a built-in machine.

        Returns
        -------
        object
            The family's machine.
        """
        module, _, function = self.reader.partition(":")
        return getattr(import_module(module), function)(path)


@cache
def _registered() -> tuple[Family, ...]:
    from importlib.metadata import entry_points

    out = []
    for ep in entry_points(group=GROUP):
        fam = ep.load()
        if not isinstance(fam, Family):
            raise TypeError(f"entry point {ep.name!r} of {GROUP!r} is not a Family: {fam!r}")
        out.append(fam)
    return tuple(out)


def families() -> dict[str, Family]:
    """The families the installed wings register, by name (the entry points are read once per
    process).

    Returns
    -------
    dict of str to Family

    Raises
    ------
    TypeError
        An entry point that is not a `Family` (a wing's packaging error).
    """
    return {fam.name: fam for fam in _registered()}


def family_of(data: Mapping[str, Any], source: str | None = None) -> Family | None:
    """The family of a file's top-level table: the one its ``family`` key names, else the one
    that recognises it; None for a file of no family (a mechanism model).

    Parameters
    ----------
    data : mapping
        The file's top-level table.
    source : str, optional
        The file, for messages.

    Returns
    -------
    Family or None

    Raises
    ------
    ModelError
        A ``family`` key that is not a string, or names no installed family.
    """
    known = families()
    if "family" in data:
        from excavkin.errors import ModelError, did_you_mean

        name = data["family"]
        if not isinstance(name, str) or name not in known:
            hint = did_you_mean(name, list(known)) if isinstance(name, str) else ""
            raise ModelError(
                f"family = {name!r} is no known machine family{hint} "
                f"(installed: {', '.join(sorted(known)) or 'none'})",
                entry="family",
                source=source,
            )
        return known[name]
    for fam in known.values():
        if fam.recognises is not None and fam.recognises(data):
            return fam
    return None


def load_machine(path: str | Path) -> Any:
    """Read a machine file of any family with its family's reader.

    Parameters
    ----------
    path : str or Path
        The file, or the name of a built-in machine (``excavkin.examples("machine")``).

    Returns
    -------
    object
        The family's machine (an excavator's
        [`Machine`][excavkin.excavator.machine.Machine]).

    Raises
    ------
    ModelError
        The file cannot be read, names no known family, or is of no family.
    """
    import excavkin
    from excavkin.errors import ModelError
    from excavkin.io.toml_model import read_text_file, read_toml

    file = excavkin.source_file(path, "machine")
    fam = family_of(read_toml(read_text_file(file), str(file)), str(file))
    if fam is None:
        raise ModelError(
            'is no machine file: it names no family (family = "...") and no installed family '
            f"recognises it (installed: {', '.join(sorted(families())) or 'none'})",
            source=str(file),
        )
    return fam.read(file)
