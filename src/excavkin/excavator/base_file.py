"""The excavator machine file's ``[lift]`` table (optional); its ``[base]`` table is the
machinery layer's [`read_base`][excavkin.machinery.base_file.read_base]::

    [lift]
    point = "Q"                         # load point of lift capacity (default: bucket pin)
"""

from __future__ import annotations

from typing import Any

from excavkin.machinery.base_file import read_base
from excavkin.machinery.file_fields import MachineReader

__all__ = ["read_base", "read_lift_point"]


def read_lift_point(r: MachineReader, data: dict[str, Any]) -> str | None:
    """The ``[lift]`` table's load point (ISO 10567 lift capacity).

    Parameters
    ----------
    r, data
        The file's reader and top-level table, as for
        [`read_base`][excavkin.machinery.base_file.read_base].

    Returns
    -------
    str or None
        The point's name, or None (the bucket pin).
    """
    if "lift" not in data:
        return None
    t = r.subtable(data, "lift", "lift")
    r.keys(t, {"point"}, "lift")
    return r.text(t, "point", "lift") if "point" in t else None
