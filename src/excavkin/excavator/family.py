"""The excavator family, as the wing registers it (entry-point group ``excavkin.families``).

An excavator machine file says ``family = "excavator"`` at its top level; a file without the
key is an excavator's when it has a ``[front]`` table (files written before the key existed).
The core never reads ``[front]``: only this wing does.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from excavkin.families import Family

if TYPE_CHECKING:
    from excavkin.machinery.file_fields import MachineReader

#: the value of the machine file's ``family`` key
NAME = "excavator"


def recognises(data: Mapping[str, Any]) -> bool:
    """Whether a file without the ``family`` key is an excavator's: it has a ``[front]`` table.

    Parameters
    ----------
    data : mapping
        The file's top-level table.

    Returns
    -------
    bool
    """
    return isinstance(data.get("front"), dict)


def check_family(r: MachineReader, data: Mapping[str, Any]) -> None:
    """Refuse a machine file that names another family than the excavator.

    Parameters
    ----------
    r : MachineReader
        The file's reader (for the message).
    data : mapping
        The file's top-level table; without a ``family`` key it is taken as an excavator's.

    Raises
    ------
    ModelError
        Naming the file and the key.
    """
    name = data.get("family", NAME)
    if name != NAME:
        raise r.err(
            f"family = {name!r}: this reader reads excavator machine files "
            f'(family = "{NAME}", or no family key)',
            None,
            "family",
        )


FAMILY = Family(
    name=NAME,
    kind="machine",
    reader="excavkin.excavator.machine_file:load_machine",
    recognises=recognises,
    description="hydraulic excavator: a backhoe front on a swinging upper structure",
)
