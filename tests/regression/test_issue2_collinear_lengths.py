"""Regression (issue 2): a body point that [lengths] puts on the line of the body's first two
points must land on it exactly, not ~1e-8 off (the square root of a round-off-sized h²)."""

from __future__ import annotations

import excavkin

TEXT = """
schema_version = 1
[units]
length = "m"
angle = "deg"
[points]
O = [0, 0]
A = [1, 0]
M = [0.6, 0.0000001]
B = [2, 1]
Q = [3, 0]
[bodies]
ground = { points = ["O", "Q"], ground = true }
bar = { points = ["O", "A", "M"] }
link = { points = ["A", "B"] }
out = { points = ["Q", "B"] }
[lengths]
"O-A" = 1.3
"O-M" = 0.7
"A-M" = 0.6
[drivers.crank]
type = "rotary"
body = "bar"
pivot = "O"
reference = "ground"
"""


def test_point_on_the_base_line_stays_on_it() -> None:
    mech = excavkin.loads(TEXT)
    x, y = mech.plan.shapes["bar"].local["M"]
    assert y == 0.0
    assert abs(x - 0.7) < 1e-15
