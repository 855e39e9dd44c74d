"""Kinetostatics: API, columns, sign conventions, NaN handling and redundancy detection."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin.errors import InputError, ModelError, UnitError
from excavkin.kinematics import KinematicResult
from excavkin.kinetostatics import (
    ForceResult,
    Gravity,
    PointForce,
    StaticallyIndeterminateError,
    Torque,
    centre_of_mass,
    compile_statics,
    inertia_loads,
    model_loads,
    solve_forces,
)
from excavkin.kinetostatics.equilibrium import _dense_solve
from excavkin.mechanism import Mechanism
from excavkin.model import Body, LinearDriver, Model, RotaryDriver
from tests.conftest import EXAMPLES
from tests.crossmethod.test_power_balance import EXAMPLES_WITH_MASS


@pytest.fixture(scope="module")
def fourbar() -> Mechanism:
    return excavkin.load(excavkin.example_path("fourbar"))


def _sweep(mech: Mechanism, n: int = 13) -> KinematicResult:
    return mech.solve({"crank": np.linspace(0.0, 2 * np.pi, n)}, {"crank": 12.0}, {"crank": -30.0})


# ------------------------------------------------------------------------------ columns
def test_force_columns_fourbar(fourbar: Mechanism) -> None:
    res = fourbar.forces(_sweep(fourbar), [Gravity()])
    cols = list(res.to_frame(kinematics=False).columns)
    assert cols == [
        "O2.ground.Fx",
        "O2.ground.Fy",
        "O2.crank.Fx",
        "O2.crank.Fy",
        "A.crank.Fx",
        "A.crank.Fy",
        "A.coupler.Fx",
        "A.coupler.Fy",
        "B.coupler.Fx",
        "B.coupler.Fy",
        "B.rocker.Fx",
        "B.rocker.Fy",
        "O4.ground.Fx",
        "O4.ground.Fy",
        "O4.rocker.Fx",
        "O4.rocker.Fy",
        "crank.torque",
        "ground.Rx",
        "ground.Ry",
    ]
    full = res.to_frame()
    kin_cols = list(res.kinematics.to_frame().columns)
    assert list(full.columns) == kin_cols[:-1] + cols + ["status"]
    assert res.to_frame(kinematics=False, resultants=("rocker",)).columns[-1] == "rocker.Ry"
    assert_allclose(res.column("B.rocker.Fy"), res.pin("B", "rocker")[:, 1])
    assert_allclose(res.column("coupler.Rx"), res.resultant("coupler")[:, 0])
    with pytest.raises(KeyError):
        res.column("B.ground.Fx")


def test_linear_and_slider_columns() -> None:
    mech = excavkin.load(excavkin.example_path("slider_crank"))
    cols = mech.solve(loads=[Gravity()]).to_frame(kinematics=False).columns
    assert {"pin_on_slide.normal", "piston_on_slide.normal", "crank.torque"} <= set(cols)
    mech = excavkin.load(excavkin.example_path("pasika_module"))
    res = mech.solve({"cyl": [0.8, 0.9]}, loads=[Gravity()])
    assert "cyl.force" in res.to_frame(kinematics=False).columns
    # the cylinder's frame end O is a pin of the frame alone: it passes the cylinder's force
    u = res.kinematics.positions[:, 2] - res.kinematics.positions[:, 0]  # O→A
    u /= np.hypot(u[:, 0], u[:, 1])[:, None]
    assert_allclose(res.pin("O", "ground"), -res.force("cyl")[:, None] * u, rtol=1e-12)
    assert res.force("cyl").shape == (2,)


def test_pins_equal_and_opposite_on_examples() -> None:
    for name in EXAMPLES_WITH_MASS:
        mech = excavkin.load(excavkin.example_path(name))
        vals = {k: np.full(5, v) for k, v in mech.sketch_values().items()}
        res = mech.solve(vals, {k: 0.5 for k in vals}, loads=[Gravity()])
        sy = res.system
        for node in sy.nodes:
            ks = [k for k, (i, _) in enumerate(sy.slots) if i == node]
            elems = [e for e in sy.elements if node in (e[1], e[2])]
            sliders = [s for s in sy.sliders if s[1] == node]
            ropes = [r for r in sy.ropes if node in r[1]]  # a rope over sheaves acts there too
            if elems or sliders or ropes:
                continue
            total = res.pin_force[:, ks].sum(axis=1)
            scale = np.abs(res.pin_force[:, ks]).max()
            assert_allclose(total, 0.0, atol=1e-12 * scale, err_msg=f"{name} {sy.points[node]}")


def test_linear_force_sign_pushes_apart() -> None:
    """A cylinder propping a loaded arm from below pushes (> 0); a rope from above pulls (< 0)."""
    for c_y, sign in ((-1.0, 1.0), (1.0, -1.0)):
        model = Model(
            "strut",
            {"O": (0.0, 0.0), "P": (1.0, 0.0), "C": (0.0, c_y)},
            (Body("frame", ("O", "C"), ground=True), Body("arm", ("O", "P"))),
            linear=(LinearDriver("cyl", ("C", "P")),),
        )
        mech = Mechanism(model)
        res = mech.solve(loads=[PointForce("w", "arm", "P", (0.0, -100.0))])
        assert np.sign(res.force("cyl")[0]) == sign
        assert_allclose(abs(res.force("cyl")[0]), 100.0 * np.sqrt(2.0), rtol=1e-13)


# ------------------------------------------------------------------------ API behaviour
def test_solve_with_loads_returns_force_result(fourbar: Mechanism) -> None:
    assert isinstance(fourbar.solve({"crank": 0.3}), KinematicResult)
    res = fourbar.solve({"crank": [0.3, 0.4]}, loads=[])
    assert isinstance(res, ForceResult)
    assert len(res) == 2
    assert isinstance(fourbar.solve(loads="model"), ForceResult)
    assert fourbar.loads == ()
    other = excavkin.load(excavkin.example_path("fourbar"))
    with pytest.raises(InputError, match="another mechanism"):
        fourbar.forces(other.solve())


def test_model_loads_and_gravity_switch() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    assert model_loads(mech.model) == ()
    assert model_loads(mech.model, gravity=True) == (Gravity(),)
    assert model_loads(mech.model, gravity=False) == ()


def test_inertia_only_vs_static(fourbar: Mechanism) -> None:
    kin = _sweep(fourbar)
    dyn = solve_forces(kin, [])
    static = solve_forces(kin, [], inertia=False)
    assert np.abs(dyn.driver_torque).max() > 0
    assert_allclose(static.pin_force, 0.0, atol=0)
    assert_allclose(static.driver_torque, 0.0, atol=0)


def test_ground_resultant_balances_loads_and_inertia(fourbar: Mechanism) -> None:
    kin = _sweep(fourbar)
    push = np.stack([np.linspace(-5, 5, len(kin)), np.full(len(kin), 2.0)], axis=1)
    res = fourbar.forces(kin, [Gravity(), PointForce("push", "coupler", "B", push)])
    fin, _ = inertia_loads(kin)
    m = res.mass.mass[:, None]
    total = fin.sum(axis=1) + (m * np.array([0.0, -9.80665])).sum(axis=0) + push
    assert_allclose(res.resultant("ground"), total, rtol=1e-12, atol=1e-12)
    # a moving body's resultant balances its own loads and inertia
    j = kin.plan.bodies.index("rocker")
    assert_allclose(
        res.resultant("rocker"),
        -(fin[:, j] + res.mass.mass[j] * np.array([0.0, -9.80665])),
        rtol=1e-12,
    )


def test_failed_samples_stay_nan(fourbar: Mechanism) -> None:
    kin = fourbar.solve({"crank": np.array([0.1, np.nan, 0.3])}, {"crank": 5.0})
    assert list(kin.status.ok) == [True, False, True]
    res = fourbar.forces(kin, [Gravity()])
    assert np.isnan(res.pin_force[1]).all() and np.isnan(res.driver_torque[1]).all()
    assert np.isfinite(res.pin_force[[0, 2]]).all()
    assert not res.ok[1] and not res.singular.any()
    frame = res.to_frame()
    assert frame["status"].iloc[1] != "ok" and np.isnan(frame["crank.torque"].iloc[1])
    assert np.isnan(res.resultant("ground")[1]).all()


def test_dense_block_flags_singular_samples() -> None:
    a = [
        [np.array([1.0, 1.0, 2.0]), np.array([2.0, 2.0, 0.0])],
        [np.array([3.0, 1.0, 0.0]), np.array([4.0, 2.0, 5.0])],
    ]
    b = [np.array([1.0, 1.0, 1.0]), np.array([2.0, 2.0, 2.0])]
    sol, singular = _dense_solve(a, b, 3, 1e-12)  # type: ignore[arg-type]
    assert list(singular) == [False, True, False]
    assert_allclose([sol[0][0], sol[1][0]], np.linalg.solve([[1, 2], [3, 4]], [1, 2]))
    assert_allclose([sol[0][2], sol[1][2]], np.linalg.solve([[2, 0], [0, 5]], [1, 2]))


# ------------------------------------------------------------------------------ loads
def test_callable_array_and_constant_loads_agree(fourbar: Mechanism) -> None:
    kin = _sweep(fourbar)
    n = len(kin)
    const = fourbar.forces(
        kin, [PointForce("f", "rocker", "B", (3.0, -4.0)), Torque("t", "coupler", 0.25)]
    )
    arrays = fourbar.forces(
        kin,
        [
            PointForce("f", "rocker", "B", np.tile([3.0, -4.0], (n, 1))),
            Torque("t", "coupler", np.full(n, 0.25)),
        ],
    )
    funcs = fourbar.forces(
        kin,
        [
            PointForce("f", "rocker", "B", lambda r: (3.0, -4.0)),
            Torque("t", "coupler", lambda r: np.full(len(r), 0.25)),
        ],
    )
    assert_allclose(arrays.pin_force, const.pin_force, rtol=1e-14)
    assert_allclose(funcs.pin_force, const.pin_force, rtol=1e-14)


def test_resistance_along_velocity() -> None:
    """A resistance opposing the point's velocity: the driver supplies its power."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    kin = mech.solve({"crank": np.linspace(0.1, 6.0, 50)}, {"crank": 10.0})

    def resist(res: KinematicResult) -> np.ndarray:
        _, v, _ = res.point("B")
        return -50.0 * v / np.hypot(v[:, 0], v[:, 1])[:, None]

    res = mech.forces(
        kin,
        [PointForce("dig", "rocker", "B", resist)],
    )
    pb = res.power_balance()
    assert np.all(pb.load < 0) and np.all(pb.driver > 0)
    assert_allclose(pb.driver, pb.kinetic_rate - pb.load, rtol=1e-12)


@pytest.mark.parametrize(
    ("load", "err", "match"),
    [
        (PointForce("f", "nobody", "B", (1.0, 0.0)), ModelError, "unknown body"),
        (PointForce("f", "crank", "B", (1.0, 0.0)), ModelError, "not a point of body"),
        (PointForce("f", "rocker", "B", (1.0, 0.0, 2.0)), InputError, "shape"),
        (PointForce("f", "rocker", "B", np.zeros((3, 2))), InputError, "shape"),
        (
            PointForce("f", "rocker", "B", "ten"),
            UnitError,
            "load 'f': cannot read 'ten' as a force",
        ),
        (PointForce("f", "rocker", "B", lambda r: 1 / 0), InputError, "ZeroDivisionError"),
        (Torque("t", "rocker", np.zeros(4)), InputError, "shape"),
        (Torque("t", "rocker", 1.0, "rocker"), ModelError, "another body"),
        (Torque("t", "rocker", 1.0, "elsewhere"), ModelError, "unknown body"),
        (Gravity(9.81, (0.0, 0.0)), ModelError, "direction"),
        ("gravity", InputError, "not a load record"),
    ],
)
def test_bad_loads(fourbar: Mechanism, load: object, err: type, match: str) -> None:
    kin = _sweep(fourbar, 5)
    with pytest.raises(err, match=match):
        fourbar.forces(kin, [load])  # type: ignore[list-item]


def test_duplicate_loads(fourbar: Mechanism) -> None:
    kin = _sweep(fourbar, 3)
    with pytest.raises(ModelError, match="duplicate"):
        fourbar.forces(kin, [Torque("t", "rocker", 1.0), Torque("t", "crank", 1.0)])
    with pytest.raises(ModelError, match="more than once"):
        fourbar.forces(kin, [Gravity(), Gravity()])


def test_gravity_direction_is_normalised(fourbar: Mechanism) -> None:
    kin = _sweep(fourbar, 5)
    a = fourbar.forces(kin, [Gravity(9.81, (0.0, -3.0))])
    b = fourbar.forces(kin, [Gravity(9.81)])
    assert_allclose(a.pin_force, b.pin_force, rtol=1e-14)


# ------------------------------------------------------------------------------- inertia
def test_centre_of_mass_default_and_given() -> None:
    model = Model(
        "arm",
        {"O": (0.0, 0.0), "A": (2.0, 0.0), "C": (1.0, 3.0), "G": (-1.0, 0.0)},
        (Body("frame", ("O", "G"), ground=True), Body("arm", ("O", "A", "C"), mass=3.0)),
        rotary=(RotaryDriver("d", "arm", "O", "frame"),),
    )
    mech = Mechanism(model)
    kin = mech.solve({"d": [0.0, np.pi / 2]}, {"d": 2.0})
    s, v, a = centre_of_mass(kin)
    j = kin.plan.bodies.index("arm")
    assert_allclose(s[0, j], [1.0, 1.0], atol=1e-14)  # centroid of O, A, C
    assert_allclose(s[1, j], [-1.0, 1.0], atol=1e-14)
    assert_allclose(v[0, j], 2.0 * np.array([-1.0, 1.0]), atol=1e-14)
    assert_allclose(a[0, j], -4.0 * np.array([1.0, 1.0]), atol=1e-13)
    assert np.isnan(s[:, kin.plan.ground]).all()
    force, couple = inertia_loads(kin)
    assert_allclose(force[0, j], 12.0 * np.array([1.0, 1.0]), atol=1e-12)
    assert_allclose(couple, 0.0)


# ------------------------------------------------------------------- over-constraint
def test_redundant_link_is_named() -> None:
    """A link pinned to the frame at both ends locks nothing but is statically indeterminate."""
    model = Model(
        "redundant",
        {"G1": (0.0, 0.0), "G2": (1.0, 0.0), "A": (0.0, 0.5)},
        (
            Body("frame", ("G1", "G2"), ground=True),
            Body("brace", ("G1", "G2")),
            Body("crank", ("G1", "A")),
        ),
        rotary=(RotaryDriver("d", "crank", "G1", "frame"),),
    )
    with pytest.raises(StaticallyIndeterminateError, match="brace") as info:
        compile_statics(model)
    msg = str(info.value)
    assert "statically indeterminate" in msg
    assert "pin G1 on body 'brace'" in msg and "pin G2 on body 'brace'" in msg


def test_locked_cylinder_duplicating_a_link_is_named() -> None:
    """A locked cylinder alongside a rigid brace: two members carry one load path."""
    model = Model(
        "doubly braced",
        {"O": (0.0, 0.0), "C": (0.0, -1.0), "P": (1.0, 0.0), "Q": (0.5, -1.0)},
        (
            Body("frame", ("O", "C", "Q"), ground=True),
            Body("arm", ("O", "P")),
            Body("brace", ("Q", "P")),
        ),
        linear=(LinearDriver("cyl", ("C", "P"), "locked"),),
    )
    with pytest.raises(StaticallyIndeterminateError) as info:
        compile_statics(model)
    msg = str(info.value)
    assert "linear element 'cyl'" in msg and "body 'brace'" in msg


def test_missing_driver_cannot_balance() -> None:
    model = Model(
        "floppy",
        {"O": (0.0, 0.0), "G": (1.0, 0.0), "A": (0.0, 1.0)},
        (Body("frame", ("O", "G"), ground=True), Body("arm", ("O", "A"))),
    )
    with pytest.raises(StaticallyIndeterminateError, match="cannot be balanced at body 'arm'"):
        compile_statics(model)


# ------------------------------------------------------------------------- TOML loads
TOML = """
schema_version = 1
[units]
length = "mm"
force = "kN"
[points]
O2 = [0, 0]
A  = [0, 40]
B  = [110, 90]
O4 = [100, 0]
[bodies]
ground  = { points = ["O2", "O4"], ground = true }
crank   = { points = ["O2", "A"] }
coupler = { points = ["A", "B"] }
rocker  = { points = ["O4", "B"], mass = "0.6 kg", center_of_mass = [105, 45] }
[drivers.crank]
type = "rotary"
body = "crank"
pivot = "O2"
"""


def _with(extra: str) -> str:
    """The base model with ``extra``: top-level keys first, tables at the end."""
    if extra.startswith("gravity ="):
        head, _, rest = extra.partition("\n")
        return TOML.replace("schema_version = 1\n", f"schema_version = 1\n{head}\n") + rest
    return TOML + extra


def test_toml_loads_and_gravity() -> None:
    text = _with("""gravity = "9.81 m/s^2"
[loads.push]
type = "force"
body = "rocker"
point = "B"
value = [0.5, "-200 N"]
[loads.motor]
type = "torque"
body = "rocker"
value = "2 N*m"
reaction = "ground"
""")
    mech = excavkin.loads(text)
    push, motor, grav = mech.loads
    assert isinstance(push, PointForce) and push.value == (500.0, -200.0)
    assert isinstance(motor, Torque) and motor.value == 2.0 and motor.reaction == "ground"
    assert grav == Gravity(9.81)
    res = mech.solve(loads="model")
    assert np.isfinite(res.driver_torque).all()


@pytest.mark.parametrize(
    ("extra", "expected"),
    [
        ("gravity = true", Gravity()),
        ("gravity = false", None),
        ("[gravity]\ndirection = [1, 0]", Gravity(9.80665, (1.0, 0.0))),
        ('[gravity]\ng = "32.174 ft/s^2"', Gravity(32.174 * 0.3048)),
    ],
)
def test_toml_gravity_forms(extra: str, expected: Gravity | None) -> None:
    model = excavkin.loads(_with(extra)).model
    if expected is None:
        assert model.gravity is None
    else:
        assert model.gravity is not None
        assert model.gravity.direction == expected.direction
        assert_allclose(model.gravity.g, expected.g, rtol=1e-12)


@pytest.mark.parametrize(
    ("extra", "match"),
    [
        (
            '[loads.x]\ntype = "force"\nbody = "rocker"\npoint = "A"\nvalue = [1, 2]',
            "point must name one of body 'rocker'",
        ),
        (
            '[loads.x]\ntype = "force"\nbody = "arm"\npoint = "B"\nvalue = [1, 2]',
            "body must name one of the bodies",
        ),
        ('[loads.x]\ntype = "push"\nbody = "rocker"\nvalue = 1', "type must be"),
        ('[loads.x]\ntype = "force"\nbody = "rocker"\npoint = "B"\nvalue = 1', "two components"),
        ('[loads.x]\ntype = "torque"\nbody = "rocker"\nvalue = 3', "needs a unit"),
        ('[loads.x]\ntype = "torque"\nbody = "rocker"\nvalue = "3 N"', "torque"),
        ('[loads.x]\ntype = "torque"\nbody = "rocker"', "needs a value"),
        (
            '[loads.x]\ntype = "torque"\nbody = "rocker"\nvalue = "1 N*m"\nreaction = "rocker"',
            "reaction must name another body",
        ),
        ('[loads.x]\ntype = "torque"\nbody = "rocker"\nvalue = "1 N*m"\nat = 1', "unknown key"),
        ('gravity = "9.81 m"', "acceleration"),
        ("[gravity]\ndirection = [0, 0]", "direction"),
    ],
)
def test_toml_load_errors(extra: str, match: str) -> None:
    with pytest.raises(ModelError, match=match):
        excavkin.loads(_with(extra), source="m.toml")


# ----------------------------------------------------------------------------- CLI
def _run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "excavkin", *args], capture_output=True, text=True)


@pytest.mark.parametrize("name", EXAMPLES_WITH_MASS)
def test_cli_forces_every_example_with_masses(name: str, tmp_path: Path) -> None:
    mech = excavkin.load(EXAMPLES / f"{name}.toml")
    driver, q0 = next(iter(mech.sketch_values().items()))
    unit = "rad" if mech.input_kind(driver) == "angle" else "m"
    span = 0.2 if unit == "rad" else 0.01 * mech.plan.scale
    out = tmp_path / "f.csv"
    # about its sketch a rope may have to push in some samples (the synchronised crane's, its
    # boom horizontal): those rows are written marked, never ok
    keep = ["--keep-going"] if mech.model.ropes else []
    r = _run(
        "solve",
        str(EXAMPLES / f"{name}.toml"),
        "--sweep",
        f"{driver}={q0 - span}{unit}:{q0 + span}{unit}:7",
        "--forces",
        "--gravity",
        "-o",
        str(out),
        *keep,
    )
    assert r.returncode == 0, r.stderr
    frame = pd.read_csv(out)
    res = mech.forces(
        mech.solve({driver: np.linspace(q0 - span, q0 + span, 7)}),
        model_loads(mech.model, gravity=True),
    )
    expected = res.to_frame(kinematics=False)
    assert list(frame.columns[-len(expected.columns) - 1 : -1]) == list(expected.columns)
    ok = res.ok
    assert ok.any() and np.array_equal((frame["status"] == "ok").to_numpy(), ok)
    assert ok.all() or not np.array_equal(ok, res.kinematics.status.ok)  # only a slack rope
    assert_allclose(
        frame[expected.columns].to_numpy()[ok], expected.to_numpy()[ok], rtol=1e-12, atol=1e-9
    )


def test_cli_gravity_switch(tmp_path: Path) -> None:
    fb = str(EXAMPLES / "fourbar.toml")
    outs = {}
    for flag in ("--gravity", "--no-gravity"):
        out = tmp_path / f"{flag}.csv"
        r = _run(
            "solve",
            fb,
            "--sweep",
            "crank=0deg:90deg:3",
            "--rate",
            "crank=0rad/s",
            "--forces",
            flag,
            "-o",
            str(out),
        )
        assert r.returncode == 0, r.stderr
        outs[flag] = pd.read_csv(out)
    assert_allclose(outs["--no-gravity"]["crank.torque"], 0.0, atol=1e-12)  # at rest
    assert np.abs(outs["--gravity"]["crank.torque"]).max() > 1e-3
    r = _run("solve", fb, "--sweep", "crank=0deg:90deg:3", "-o", str(tmp_path / "k.csv"))
    assert "crank.torque" not in pd.read_csv(tmp_path / "k.csv").columns


def test_bad_solver_options(fourbar: Mechanism) -> None:
    kin = _sweep(fourbar, 3)
    with pytest.raises(InputError, match="method"):
        solve_forces(kin, [], method="lu")
    with pytest.raises(InputError, match="chunk"):
        solve_forces(kin, [], chunk=0)
    # chunking does not change the answer
    a = solve_forces(kin, [Gravity()], chunk=1)
    b = solve_forces(kin, [Gravity()])
    assert_allclose(a.pin_force, b.pin_force, rtol=1e-15)
