"""The crane family, as the wing registers it (entry-point group ``excavkin.families``).

A crane machine file says ``family = "crane"`` at its top level; the key is required.
"""

from __future__ import annotations

from excavkin.families import Family

#: the value of the machine file's ``family`` key
NAME = "crane"

FAMILY = Family(
    name=NAME,
    kind="machine",
    reader="excavkin.crane.machine_file:load_machine",
    recognises=None,
    description=(
        "knuckle-boom or telescopic crane: luffing, knuckle or telescoping cylinders, hoist "
        "reeving, outriggers or crawlers"
    ),
)
