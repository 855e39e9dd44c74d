"""The excavator machine file's ``[hydraulics]`` table (optional): pumps feeding the boom, arm
and bucket, the swing and the rod material, read by the machinery layer's
[`read_hydraulics`][excavkin.machinery.hydraulics_file.read_hydraulics] (the table's fields
are written there)."""

from __future__ import annotations

from typing import Any

from excavkin.excavator.hydraulics import Hydraulics
from excavkin.machinery import hydraulics_file
from excavkin.machinery.file_fields import MachineReader


def read_hydraulics(r: MachineReader, data: dict[str, Any]) -> Hydraulics | None:
    """The ``[hydraulics]`` table as the excavator's
    [`Hydraulics`][excavkin.excavator.hydraulics.Hydraulics].

    Parameters
    ----------
    r, data
        The file's reader and top-level table, as for
        [`read_hydraulics`][excavkin.machinery.hydraulics_file.read_hydraulics].

    Returns
    -------
    Hydraulics or None
        None where the file has no ``[hydraulics]`` table.
    """
    return hydraulics_file.read_hydraulics(r, data, Hydraulics)
