"""Small models shared by several test modules."""

from __future__ import annotations

import math

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


def _toml(
    name: str,
    points: dict[str, tuple[float, float]],
    bodies: list[tuple[str, list[str], bool]],
    pivot: str,
    cylinders: tuple[tuple[str, str, str], ...] = (),
) -> str:
    """A model file in mm: the points, the bodies, a rotary driver ``crank`` of body
    ``crank`` about ``pivot`` from the ground, and driven ``cylinders`` (name, p, q)."""
    lines = ["schema_version = 1", f'name = "{name}"', "[units]", 'length = "mm"', "[points]"]
    lines += [f"{n} = [{x!r}, {y!r}]" for n, (x, y) in points.items()]
    lines.append("[bodies]")
    for body, pts, ground in bodies:
        listed = ", ".join(f'"{p}"' for p in pts)
        lines.append(f"{body} = {{ points = [{listed}]{', ground = true' if ground else ''} }}")
    lines += ["[drivers.crank]", 'type = "rotary"', 'body = "crank"', f'pivot = "{pivot}"']
    lines.append('reference = "ground"')
    for cyl, p, q in cylinders:
        lines += [f"[drivers.{cyl}]", 'type = "linear"', f'between = ["{p}", "{q}"]']
    return "\n".join(lines) + "\n"


def fourbar_chain(stages: int) -> str:
    """A chain of ``stages`` crank-rocker four-bars, as a model file: 3·stages + 1 points.

    A crank O0–A0 drives coupler A0–B0 and rocker O1–B0; each rocker carries the next stage's
    A, so that stage k is a dyad B_k (from A_k and O_{k+1}) and, but for the last, an attached
    A_{k+1}. The ground holds every O. Plan: the ground, the crank, then per stage a dyad and
    an attach: 2·stages + 1 steps."""
    points = {"O0": (0.0, 0.0), "A0": (0.0, 40.0)}
    bodies: list[tuple[str, list[str], bool]] = [("crank", ["O0", "A0"], False)]
    ground = ["O0"]
    for k in range(stages):
        x = 100.0 * k
        points[f"O{k + 1}"] = (x + 100.0, 0.0)
        points[f"B{k}"] = (x + 110.0, 90.0)
        ground.append(f"O{k + 1}")
        bodies.append((f"coupler{k}", [f"A{k}", f"B{k}"], False))
        rocker = [f"O{k + 1}", f"B{k}"]
        if k + 1 < stages:
            points[f"A{k + 1}"] = (x + 100.0, 40.0)
            rocker.append(f"A{k + 1}")
        bodies.append((f"rocker{k}", rocker, False))
    return _toml(f"chain of {stages} four-bars", points, [("ground", ground, True), *bodies], "O0")


def truss(n: int, cylinders: bool = False) -> str:
    """A triangulated strip of ``n`` points (n ≥ 4), as a model file.

    Points alternate between a lower and an upper rail (drawn a little irregular, so that no
    four of them form a parallelogram). P0 and P2 are the ground, the crank P0–P1 is driven,
    and each further point P_k is a dyad of two bars from P_(k−2) and P_(k−1). Plan: the
    ground, the crank, then n − 3 dyads in order; mobility 1. With ``cylinders`` the second
    bar of each dyad is a driven cylinder ``cylK`` instead (mobility n − 2)."""
    points: dict[str, tuple[float, float]] = {}
    for k in range(n):
        x = 100.0 * (k // 2) + (50.0 if k % 2 else 0.0) + 10.0 * math.sin(k)
        y = (100.0 if k % 2 else 0.0) + 10.0 * math.cos(1.7 * k)
        points[f"P{k}"] = (round(x, 6), round(y, 6))
    bodies: list[tuple[str, list[str], bool]] = [
        ("ground", ["P0", "P2"], True),
        ("crank", ["P0", "P1"], False),
    ]
    driven = []
    for k in range(3, n):
        bodies.append((f"bar{k}a", [f"P{k - 2}", f"P{k}"], False))
        if cylinders:
            driven.append((f"cyl{k}", f"P{k - 1}", f"P{k}"))
        else:
            bodies.append((f"bar{k}b", [f"P{k - 1}", f"P{k}"], False))
    return _toml(f"truss of {n} points", points, bodies, "P0", tuple(driven))
