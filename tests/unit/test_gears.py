"""Gear pairs: the ``[gears]`` table, the gear step's closed forms (NumPy and compiled), the
tooth force along the line of action, the power balance, and exact sensitivities."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin.errors import InputError, MobilityError, ModelError
from excavkin.kinetostatics.solve import solve_forces
from excavkin.model.entities import Torque

PAIR = """
schema_version = 1
name = "gear pair"
[units]
length = "mm"
[points]
O1 = [0, 0]
O2 = [300, 0]
A = [0, 100]
B = [300, 200]
C = [250, 60]
[bodies]
frame = { points = ["O1", "O2"], ground = true }
pinion = { points = ["O1", "A"], mass = "1 kg", inertia = "0.01 kg*m^2", center_of_mass = [5, 3] }
wheel = { points = ["O2", "B", "C"], mass = "2 kg", inertia = "0.05 kg*m^2", \
center_of_mass = [320, 10] }
[drivers.motor]
type = "rotary"
body = "pinion"
pivot = "O1"
[gears.mesh]
gears = ["pinion", "wheel"]
GEAR_KEYS
[loads.brake]
type = "torque"
body = "wheel"
value = "10 N*m"
[gravity]
"""

EXTERNAL = 'radii = [100, 200]\npressure_angle = "25 deg"'


def pair(keys: str = EXTERNAL, points: str = "") -> excavkin.Mechanism:
    text = PAIR.replace("GEAR_KEYS", keys)
    if points:
        text = text.replace("O2 = [300, 0]", points)
    return excavkin.loads(text, "pair.toml")


def test_an_external_pair_turns_the_other_way_by_the_ratio_at_every_turn() -> None:
    mech = pair()
    assert "− 1 higher pair = 1" in mech.plan.mobility.describe()
    q = np.linspace(-60.0, 60.0, 241)  # about ten turns each way
    res = mech.solve({"motor": q}, rates={"motor": 2.0}, accels={"motor": 0.5})
    assert res.status.all_ok
    # independently: the wheel's mark B turns by −(q − q0)/2 about O2 from its sketch angle
    th = math.pi / 2 - (q - math.pi / 2) / 2
    b = res.point("B")
    assert_allclose(b[0][:, 0], 0.3 + 0.2 * np.cos(th), atol=1e-15)
    assert_allclose(b[0][:, 1], 0.2 * np.sin(th), atol=1e-15)
    assert_allclose(res.body("wheel")[1], -1.0, rtol=1e-15)
    assert_allclose(res.body("wheel")[2], -0.25, rtol=1e-15)


def test_an_internal_pair_turns_the_same_way() -> None:
    mech = pair("ratio = 3\ninternal = true", points="O2 = [-200, 0]")
    res = mech.solve({"motor": np.linspace(0.0, 10.0, 5)}, rates={"motor": 3.0})
    assert_allclose(res.body("wheel")[1], 1.0, rtol=1e-15)


def test_teeth_and_ratio_give_the_same_motion() -> None:
    q = {"motor": np.linspace(-3.0, 3.0, 7)}
    a = pair("teeth = [20, 40]").solve(q).positions
    b = pair("ratio = 2.0").solve(q).positions
    assert_allclose(a, b, rtol=0, atol=0)


def test_compiled_and_numpy_agree() -> None:
    mech = pair()
    q = np.linspace(-30.0, 30.0, 4001)
    kw = {"rates": {"motor": np.cos(q)}, "accels": {"motor": np.sin(q)}}
    r0 = mech.solve({"motor": q}, backend="numpy", **kw)
    r1 = mech.solve({"motor": q}, backend="numba", **kw)
    for name in ("positions", "velocities", "accelerations"):
        assert_allclose(getattr(r1, name), getattr(r0, name), rtol=0, atol=1e-14)
    loads = mech.model.loads
    f0 = mech.forces(r0, loads=loads, backend="numpy")
    f1 = mech.forces(r0, loads=loads, backend="numba")
    assert_allclose(f1.pin_force, f0.pin_force, rtol=1e-13, atol=1e-12)
    assert_allclose(f1.gear_force, f0.gear_force, rtol=1e-13, atol=1e-12)
    fd = solve_forces(r0, loads, method="dense")
    assert_allclose(fd.gear_force, f0.gear_force, rtol=1e-9)


@pytest.mark.parametrize(
    "keys",
    [EXTERNAL, "ratio = 3\ninternal = true", "ratio = 0.5\ninternal = true"],
    ids=["external", "internal ring is gear 2", "internal ring is gear 1"],
)
def test_power_balances_and_the_tooth_force_is_on_the_line_of_action(keys: str) -> None:
    points = {EXTERNAL: "", "ratio = 3\ninternal = true": "O2 = [-200, 0]"}.get(
        keys, "O2 = [100, 0]"
    )
    mech = pair(keys, points)
    rng = np.random.default_rng(3)
    q = rng.uniform(-20, 20, 200)
    res = mech.solve(
        {"motor": q},
        rates={"motor": rng.uniform(-5, 5, 200)},
        accels={"motor": rng.uniform(-9, 9, 200)},
    )
    f = mech.forces(res, loads=mech.model.loads)
    pb = f.power_balance()
    assert np.abs(pb.relative).max() < 1e-9
    # the wheel's pin takes the tooth force: tangential W and radial |W|·tan φ, so its
    # component along the line of centres is |W| tan φ (the gear's weight and inertia aside)
    g = mech.model.gears[0]
    w = f.gear_force[:, 0]
    x = res.positions
    u = x[:, 1] - x[:, 0]  # O1 → O2
    u /= np.hypot(u[:, 0], u[:, 1])[:, None]
    pin = f.pin_force[:, f.pins.index(("O1", "frame"))]
    pinion = f.pin_force[:, f.pins.index(("O1", "pinion"))]
    assert_allclose(pin, -pinion, atol=1e-9)
    static = pair(keys, points)
    fs = static.forces(static.solve({"motor": q}), loads=[ld for ld in static.model.loads])
    p = fs.pin_force[:, fs.pins.index(("O1", "pinion"))]
    # the static pinion: weight −m g at its centre of mass, the pin and the tooth force
    sense = -1.0 if g.internal else 1.0
    radial = np.einsum("ij,ij->i", p, u) * sense
    assert_allclose(radial, np.abs(fs.gear_force[:, 0]) * math.tan(g.pressure_angle), rtol=1e-9)
    assert np.all(np.isfinite(w))


def test_the_tooth_force_is_the_torque_over_the_pitch_radius() -> None:
    mech = pair()
    res = mech.solve({"motor": np.linspace(0.0, 7.0, 8)})
    load = [Torque("brake", "wheel", 10.0)]
    f = mech.forces(res, loads=load)
    # no gravity passed: the wheel holds 10 N·m by the tooth force at 0.2 m, the pinion needs 5
    assert_allclose(f.gear_force[:, 0], 10.0 / 0.2, rtol=1e-14)
    assert_allclose(f.torque("motor"), 5.0, rtol=1e-14)
    o2 = f.pin_force[:, f.pins.index(("O2", "wheel"))]
    assert_allclose(np.hypot(o2[:, 0], o2[:, 1]), 50.0 / math.cos(math.radians(25.0)), rtol=1e-13)


def test_sensitivities_equal_8th_order_differences() -> None:
    sys.path.insert(0, str(Path(__file__).parents[1] / "property"))
    from test_sensitivities import differences

    mech = pair()
    values = {"motor": np.array([0.3, 1.0, 7.0, -12.0])}
    rates = {"motor": 0.07}
    names = ["O2.x", "O1.y", "C.y", "wheel.mass", "A.x", "wheel.center_of_mass.x"]
    res = mech.solve(values, rates=rates, sensitivities=names, loads="model")
    table = res.to_frame()
    forces = [c for c in table.columns if c.endswith((".Fx", ".Fy", ".torque", ".tooth"))]
    force_scale = max(np.abs(table[c].to_numpy()).max() for c in forces)
    for name in names:
        step = 3e-4 * (2.0 if name == "wheel.mass" else mech.plan.scale)
        for col, ref in differences(mech, values, rates, {}, name, step).items():
            exact = res.sensitivity(col, name)
            own = force_scale if col in forces or col.endswith((".Rx", ".Ry")) else 0.0
            scale = max(np.abs(ref).max(), 1e-3 * max(np.abs(table[col]).max(), own, 1e-3))
            assert np.abs(exact - ref).max() / scale < 1e-8, (name, col)


@pytest.mark.parametrize(
    ("keys", "message"),
    [
        ("ratio = 2\nteeth = [1, 2]", "exactly one of ratio"),
        ("", "exactly one of ratio"),
        ("ratio = -2", "ratio must be positive"),
        ("ratio = 1\ninternal = true", "ring larger than its pinion"),
        (
            "radii = [100, 100]",
            r"need a centre distance of 0.2 m, but the pivots O1 and O2 are 0.3",
        ),
        ("teeth = [20.5, 40]", "two positive whole numbers"),
        ('ratio = 2\npressure_angle = "95 deg"', "pressure angle must be in"),
        ('ratio = 2\ncarrier = "wheel"', "three different bodies"),
        ('ratio = 2\ncarrier = "frme"', "did you mean 'frame'"),
        ("ratio = 2\nbacklash = 1", "unknown key backlash"),
    ],
)
def test_bad_gear_entries_are_refused_by_name(keys: str, message: str) -> None:
    with pytest.raises(ModelError, match=message) as info:
        pair(keys)
    assert "gears" in str(info.value) and "mesh" in str(info.value)


def test_a_gear_that_shares_no_pivot_with_its_carrier_is_refused() -> None:
    text = (
        PAIR.replace("GEAR_KEYS", "ratio = 2")
        .replace('wheel = { points = ["O2"', 'wheel = { points = ["W"')
        .replace("C = [250, 60]", "C = [250, 60]\nW = [300, 0]")
    )
    with pytest.raises(ModelError, match="shares 0 points with its carrier"):
        excavkin.loads(text, "pair.toml")


def test_a_redundant_mesh_is_refused() -> None:
    # the wheel driven by its own motor and by the mesh: one freedom too few
    text = PAIR.replace("GEAR_KEYS", "ratio = 2") + (
        '[drivers.second]\ntype = "rotary"\nbody = "wheel"\npivot = "O2"\n'
    )
    with pytest.raises(MobilityError):
        excavkin.loads(text, "pair.toml")


def test_the_generic_solver_holds_geared_bodies_in_closed_form() -> None:
    """``method="newton"`` places a gear train's bodies by their gear steps (their angles are
    linear in the inputs) and the rest in one Newton group
    (tests/crossmethod/test_geared_newton.py): the pair alone needs no group."""
    from excavkin.step_kinds import GearStep
    from excavkin.structure.builder import compile_plan

    plan = compile_plan(pair().model, method="newton")
    assert plan.method == "newton" and not plan.has_newton
    assert [type(st) for st in plan.steps].count(GearStep) == 1
    q = np.linspace(-3.0, 3.0, 7)
    a = pair().solve({"motor": q}, rates={"motor": 2.0}).positions
    b = excavkin.Mechanism(pair().model, method="newton").solve({"motor": q}).positions
    assert_allclose(b, a, rtol=0, atol=1e-15)


def test_a_geared_body_fixed_otherwise_too_is_refused() -> None:
    # a link from the frame to the wheel fixes its angle twice: by the mesh and by the link
    text = (
        PAIR.replace("GEAR_KEYS", "ratio = 2")
        .replace("[bodies]", '[bodies]\nlink = { points = ["C", "D"] }')
        .replace("C = [250, 60]", "C = [250, 60]\nD = [600, 60]")
        .replace('frame = { points = ["O1", "O2"]', 'frame = { points = ["O1", "O2", "D"]')
    )
    with pytest.raises(MobilityError):
        excavkin.loads(text, "pair.toml")


def test_drawings_show_the_pitch_circles_moving_with_their_centres() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from excavkin.outputs.drawing import draw_mechanism

    data = Path(__file__).parents[1] / "reference" / "data"
    mech = excavkin.load(data / "planetary_21_43_108.toml")
    res = mech.solve({"input": np.linspace(0.0, 3.0, 10)})
    fig, ax = plt.subplots()
    try:
        drawing = draw_mechanism(res, ax=ax, sample=0)
        radii = sorted(c.radius for _, c in drawing.circles)
        a = 56.8  # mm
        want = sorted([a * 21 / 64, a * 43 / 64, a * 43 / 65, a * 108 / 65])
        assert_allclose(radii, want, rtol=1e-12)
        drawing.set_sample(7)
        planet = mech.plan.points.index("P")
        for centre, circle in drawing.circles:
            assert_allclose(circle.center, res.positions[7, centre] * 1000, rtol=1e-12)
        assert any(centre == planet for centre, _ in drawing.circles)
    finally:
        plt.close(fig)


def test_the_report_figure_draws_the_pitch_circles() -> None:
    from excavkin.outputs.meshes import circle_paths
    from excavkin.outputs.scene import scene_of

    data = Path(__file__).parents[1] / "reference" / "data"
    mech = excavkin.load(data / "planetary_21_43_108.toml")
    res = mech.solve({"input": np.linspace(0.0, 3.0, 5)})
    scene, _ = scene_of(res, (), "mm")
    paths = circle_paths(scene, 3)
    assert len(paths) == 4
    centre = res.positions[3, mech.plan.points.index("P")] * 1000
    radius = np.hypot(*(paths[1] - centre).T)
    assert_allclose(radius, 56.8 * 43 / 64, rtol=1e-12)


PLANETARY = Path(__file__).parents[1] / "reference" / "data" / "planetary_21_43_108.toml"


def _check_ratio_sensitivities(mech: excavkin.Mechanism, names: list[str], values: dict) -> None:
    """Positions, rates, accelerations and forces (the tooth force too) differentiated by the
    ratios equal 8th-order central differences of models solved with moved ratios, on both
    backends."""
    sys.path.insert(0, str(Path(__file__).parents[1] / "property"))
    from test_sensitivities import differences

    rates = {k: 0.07 for k in values}
    for backend in ("numpy", "numba"):
        res = mech.solve(values, rates=rates, sensitivities=names, loads="model", backend=backend)
        table = res.to_frame()
        forces = [c for c in table.columns if c.endswith((".Fx", ".Fy", ".torque", ".tooth"))]
        force_scale = max(np.abs(table[c].to_numpy()).max() for c in forces)
        for name in names:
            seen = 0
            for col, ref in differences(mech, values, rates, {}, name, 1e-3).items():
                exact = res.sensitivity(col, name)
                own = force_scale if col in forces or col.endswith((".Rx", ".Ry")) else 0.0
                scale = max(np.abs(ref).max(), 1e-3 * max(np.abs(table[col]).max(), own, 1e-3))
                assert np.abs(exact - ref).max() / scale < 1e-8, (backend, name, col)
                seen += col.endswith(".tooth") and np.abs(ref).max() > 1e-3
            assert seen  # the tooth forces move with the ratio, and were checked


@pytest.mark.parametrize(
    ("keys", "points"),
    [("ratio = 2", ""), ("ratio = 3\ninternal = true", "O2 = [-200, 0]")],
    ids=["external", "internal"],
)
def test_a_pair_ratio_sensitivities_equal_8th_order_differences(keys: str, points: str) -> None:
    mech = pair(keys, points)
    assert mech.parameters["mesh.ratio"] == float(keys.split()[2])
    _check_ratio_sensitivities(mech, ["mesh.ratio"], {"motor": np.array([0.3, 1.0, 7.0, -12.0])})


def test_planetary_ratio_sensitivities_equal_8th_order_differences() -> None:
    text = PLANETARY.read_text() + '[loads.out]\ntype = "torque"\nbody = "carrier"\n'
    text += 'value = "-20 N*m"\n[gravity]\n'
    mech = excavkin.loads(text, "planetary.toml")
    names = ["sun_planet.ratio", "planet_ring.ratio"]
    _check_ratio_sensitivities(mech, names, {"input": np.array([0.3, 1.0, 7.0, -12.0])})


def test_a_family_of_ratios_turns_each_wheel_by_its_own_ratio() -> None:
    mech = pair("ratio = 2")
    ratios = np.array([1.5, 2.0, 4.0, -1.0])
    res = mech.solve({"motor": np.full(4, 2.0)}, params={"mesh.ratio": ratios})
    # independently: the wheel turns by −(q − q0)/ratio; a ratio not positive builds nothing
    assert res.status.ok.tolist() == [True, True, True, False]
    assert_allclose(res.body("wheel")[0][:3], math.pi / 2 - (2.0 - math.pi / 2) / ratios[:3])


def test_a_gear_ratio_of_a_model_with_a_cam_is_refused_by_name() -> None:
    text = (Path(PLANETARY).parent / "disc_cam.toml").read_text()
    text = text.replace("F2 = [0, 160]", "F2 = [0, 160]\nD = [-150, 0]\nE = [-150, 20]")
    text = text.replace("[drivers.shaft]", 'idler = { points = ["D", "E"] }\n[drivers.shaft]')
    text = text.replace('G2"], ground', 'G2", "D"], ground')
    text += '[gears.drive]\ngears = ["disc", "idler"]\nratio = 2\n'
    mech = excavkin.loads(text, "cam.toml")
    with pytest.raises(InputError, match=r"parameter drive.ratio: .* a cam \('lift'\)"):
        mech.solve({"shaft": [0.1, 0.2]}, params={"drive.ratio": [2.0, 2.5]})


def test_a_ratio_given_by_teeth_is_written_back_as_a_ratio(tmp_path: Path) -> None:
    from excavkin.io.model_write import model_text_with

    src = tmp_path / "pair.toml"
    src.write_text(PAIR.replace("GEAR_KEYS", "teeth = [20, 40]"))
    text = model_text_with(src, {"mesh.ratio": 2.5})
    (g,) = excavkin.loads(text, "pair.toml").model.gears
    assert g.ratio == 2.5 and "teeth" not in text
    src.write_text(PAIR.replace("GEAR_KEYS", "ratio = 2"))
    (g,) = excavkin.loads(model_text_with(src, {"mesh.ratio": 3.0}), "p.toml").model.gears
    assert g.ratio == 3.0
