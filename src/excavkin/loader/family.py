"""The wheel-loader family, as the wing registers it (entry-point group ``excavkin.families``).

A loader machine file says ``family = "loader"`` at its top level; the key is required (no
file written before it exists).
"""

from __future__ import annotations

from excavkin.families import Family

#: the value of the machine file's ``family`` key
NAME = "loader"

FAMILY = Family(
    name=NAME,
    kind="machine",
    reader="excavkin.loader.machine_file:load_machine",
    recognises=None,
    description="wheel loader: a Z-bar or parallel-lift front on an articulated chassis",
)
