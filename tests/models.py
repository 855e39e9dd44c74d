"""Small models shared by several test modules."""

from __future__ import annotations

import excavkin

ARM = """
schema_version = 1
name = "boom and stick"
[units]
length = "mm"
angle = "deg"
[points]
O  = [0, 0]
C1 = [400, -600]
D1 = [1400, 300]
C2 = [2300, 1200]
E  = [3200, 900]
D2 = [2950, 1350]
K  = [3700, -900]
[bodies]
frame = { points = ["O", "C1"], ground = true }
boom  = { points = ["O", "E", "D1", "C2"] }
stick = { points = ["E", "K", "D2"] }
[drivers.boom_cyl]
type = "linear"
between = ["C1", "D1"]
[drivers.stick_cyl]
type = "linear"
between = ["C2", "D2"]
"""


def double_rocker() -> excavkin.Mechanism:
    """The README four-bar with a 60 mm coupler: the crank cannot turn fully."""
    text = excavkin.example_path("fourbar").read_text()
    text = text.replace("A  = [0, 40]", "A  = [0, 80]").replace('"A-B"  = 120', '"A-B"  = 60')
    return excavkin.loads(text.replace("B  = [110, 90]", "B  = [50, 110]"), "double-rocker")


def fourbar_model(
    points: dict[str, tuple[float, float]],
    name: str = "four-bar",
    lengths: dict[tuple[str, str], float] | None = None,
) -> excavkin.Model:
    """A crank-rocker from its sketch ``{"O2", "A", "B", "O4"}``: ground O2–O4, crank O2–A
    driven from the ground, coupler A–B, rocker O4–B."""
    from excavkin import Body, Model, RotaryDriver

    return Model(
        name=name,
        points=dict(points),
        bodies=(
            Body("ground", ("O2", "O4"), ground=True),
            Body("crank", ("O2", "A")),
            Body("coupler", ("A", "B")),
            Body("rocker", ("O4", "B")),
        ),
        rotary=(RotaryDriver("crank", body="crank", pivot="O2", reference="ground"),),
        lengths=dict(lengths or {}),
    )


def parallelogram() -> excavkin.Model:
    """Four links of 100 mm, crank upright: a change point where the crank's end meets O4."""
    return fourbar_model(
        {"O2": (0.0, 0.0), "A": (0.0, 0.1), "B": (0.1, 0.1), "O4": (0.1, 0.0)}, "parallelogram"
    )
