"""A machine file with new values of its parameters: a design of a machine written as a machine
file of its own, which loads as that design.

A machine's parameters are its mechanism's (``P.x``, ``BODY.mass`` …, written in its model)
and the machine file's own, named by their tables (``cylinders.lift.bore`` is the entry
``bore`` of ``[cylinders.lift]``). The new machine file is the old one's tables written anew
with the machine file's parameters replaced and its model written inline (``[model]``, which a
machine file may hold in place of a model file's name) with the mechanism's replaced, so that
the one file is the whole design: nothing refers back to the files it came from. Each value is
written in the unit the file writes that entry in (a bare number in the file's ``[units]``).
The file's leading comment block is kept, with a line naming the values set; the new file is
written whole or not at all, never over an existing file unless asked.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from os import PathLike
from pathlib import Path
from typing import Any

from excavkin.errors import ModelError
from excavkin.io.model_write import dumps, leading_comments, set_model_values, written_value
from excavkin.io.toml_model import read_text_file, read_toml

__all__ = ["machine_text_with", "write_machine_file"]

#: the kinds a machine file's units give an inline model that has no [units] of its own
_MODEL_KINDS = ("length", "angle", "mass", "inertia")


def machine_text_with(
    path: str | PathLike[str],
    values: Mapping[str, float],
    kinds: Mapping[str, str],
    mechanism: Collection[str],
    note: str = "",
) -> str:
    """The text of the machine file ``path`` with the parameters ``values`` (SI) written in and
    its model inline.

    Parameters
    ----------
    path : str or Path
        The machine file (TOML); its ``model`` names a model file beside it or is inline.
    values : mapping of str to float
        Parameter → its value, SI.
    kinds : mapping of str to str
        Each parameter's physical kind (``"length"``, ``"pressure"``, ``"mass"`` …).
    mechanism : collection of str
        The names of ``values`` that are the mechanism's (written into the model).
    note : str
        A comment line saying where the values come from.

    Returns
    -------
    str
        The new machine file's text.

    Raises
    ------
    ModelError
        A parameter with no entry in the machine file or its model, or a ``model`` that is
        neither a file's name nor a table, naming the file and the parameter.
    """
    source = str(path)
    text = read_text_file(Path(path))
    data = read_toml(text, source)
    units = data.get("units", {}) if isinstance(data.get("units"), dict) else {}
    spec = data.get("model")
    if isinstance(spec, str):
        model_file = Path(path).parent / spec
        model = read_toml(read_text_file(model_file), str(model_file))
        model_source = str(model_file)
    elif isinstance(spec, dict):
        model, model_source = spec, f"{source} [model]"
    else:
        raise ModelError("the machine file names no model (a file's name or a [model] table)",
                         entry="model", source=source)  # fmt: skip
    if not isinstance(model.get("units"), dict):
        # an inline model takes the machine file's units where it gives none: say which
        model["units"] = {k: v for k, v in units.items() if k in _MODEL_KINDS}
    set_model_values(model, {k: v for k, v in values.items() if k in mechanism}, model_source)
    data["model"] = model
    for name, value in values.items():
        if name in mechanism:
            continue
        holder, key = _entry(data, name, source)
        holder[key] = written_value(holder[key], float(value), kinds[name], units, data)
    head = leading_comments(text)
    if values:
        head += ["#"] * bool(head) + [f"# {note or 'values set'}: {', '.join(values)}"]
    return "\n".join([*head, dumps(data)]) if head else dumps(data)


def _entry(data: dict[str, Any], name: str, source: str) -> tuple[dict[str, Any], str]:
    """The table holding the machine-file parameter ``name`` (``cylinders.lift.bore``), and
    its key."""
    *tables, key = name.split(".")
    holder: Any = data
    for t in tables:
        holder = holder.get(t) if isinstance(holder, dict) else None
    if not isinstance(holder, dict) or key not in holder:
        raise ModelError(f"parameter {name!r} has no entry in the machine file", source=source)
    return holder, key


def write_machine_file(
    path: str | PathLike[str],
    values: Mapping[str, float],
    kinds: Mapping[str, str],
    mechanism: Collection[str],
    out: str | PathLike[str],
    *,
    force: bool = False,
    note: str = "",
) -> Path:
    """Write the machine file ``path`` with the parameters ``values`` (SI) to ``out``, whole or
    not at all ([`machine_text_with`][excavkin.io.machine_write.machine_text_with]).

    Parameters
    ----------
    path : str or Path
        The machine file.
    values : mapping of str to float
        Parameter → SI value.
    kinds : mapping of str to str
        Each parameter's physical kind.
    mechanism : collection of str
        The names of ``values`` that are the mechanism's.
    out : str or Path
        The new file (``.toml``); never the machine file itself.
    force : bool
        Replace an existing ``out``.
    note : str
        A comment saying where the values come from, written at the top.

    Returns
    -------
    Path
        The machine file written.

    Raises
    ------
    OutputError
        ``out`` exists (without ``force``), is the machine file, or is not a ``.toml`` file.
    """
    from excavkin.io.files import write_toml_from

    return write_toml_from(
        path, out, lambda: machine_text_with(path, values, kinds, mechanism, note), force=force,
        itself="is the machine file itself; write the design elsewhere",
    )  # fmt: skip
