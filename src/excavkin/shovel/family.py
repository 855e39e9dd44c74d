"""The rope-shovel family, as the wing registers it (entry-point group ``excavkin.families``).

A shovel machine file says ``family = "shovel"`` at its top level; the key is required.
"""

from __future__ import annotations

from excavkin.families import Family

#: the value of the machine file's ``family`` key
NAME = "shovel"

FAMILY = Family(
    name=NAME,
    kind="machine",
    reader="excavkin.shovel.machine_file:load_machine",
    recognises=None,
    description="rope shovel: hoist rope over the boom point, crowd, dipper on a handle",
)
