"""The wheel-loader wing: its machine file (family "loader") and its SAE J732 / ISO 7131
dimensions, checked against a closed-form solution of the Z-bar linkage written here from the
model's sketch points alone (circle intersections, no engine)."""

from __future__ import annotations

import functools
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin.errors import ModelError
from excavkin.families import families
from excavkin.families import load_machine as load_any_machine
from excavkin.loader.dimensions import DISCHARGE, dimensions
from excavkin.loader.machine import Loader, floor_angle
from excavkin.loader.machine_file import load_machine
from excavkin.loader.poses import ground_pose, lift_for_hinge_height, tilt_for_angle
from tests.conftest import EXAMPLES

MACHINE = EXAMPLES / "wheel_loader_machine.toml"


@pytest.fixture(scope="module")
def loader() -> Loader:
    return load_machine(MACHINE)


# ---------------------------------------------------------------- the linkage by hand
@functools.cache
def _sketch() -> dict[str, np.ndarray]:
    """The model's points, read straight from its file (mm → m)."""
    data = tomllib.loads((EXAMPLES / "wheel_loader.toml").read_text(encoding="utf-8"))
    return {k: np.array(v, dtype=float) / 1e3 for k, v in data["points"].items()}


def _circle(a: np.ndarray, ra: float, b: np.ndarray, rb: float, side: float) -> np.ndarray:
    d = b - a
    dist = math.hypot(*d)
    x = (ra**2 - rb**2 + dist**2) / (2 * dist)
    h = math.sqrt(ra**2 - x**2)
    e = d / dist
    return a + x * e + side * h * np.array([-e[1], e[0]])


def _rot(v: np.ndarray, t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _cross(a: np.ndarray, b: np.ndarray) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _angle(v: np.ndarray) -> float:
    return math.atan2(v[1], v[0])


def hand(lift: float, tilt: float) -> dict[str, np.ndarray]:
    """The linkage at cylinder lengths, solved by hand: the lift arm turns about A until
    |CD| = lift; G from E and F; H turns with the bell crank; I from H and B; the bucket
    turns rigidly about B."""
    p = _sketch()
    A, C, D = p["A"], p["C"], p["D"]
    side_d = math.copysign(1.0, _cross(C - A, D - A))
    D1 = _circle(A, math.hypot(*(D - A)), C, lift, -side_d)
    if _cross(C - A, D1 - A) * side_d < 0:
        D1 = _circle(A, math.hypot(*(D - A)), C, lift, side_d)
    arm = _angle(D1 - A) - _angle(D - A)
    B, E = A + _rot(p["B"] - A, arm), A + _rot(p["E"] - A, arm)
    F, G0, H0, I0 = p["F"], p["G"], p["H"], p["I"]
    sg = math.copysign(1.0, _cross(F - p["E"], G0 - p["E"]))
    G = _circle(E, math.hypot(*(G0 - p["E"])), F, tilt, sg)
    crank = _angle(G - E) - _angle(G0 - p["E"])
    H = E + _rot(H0 - p["E"], crank)
    si = math.copysign(1.0, _cross(p["B"] - H0, I0 - H0))
    I = _circle(H, math.hypot(*(I0 - H0)), B, math.hypot(*(I0 - p["B"])), si)  # noqa: E741
    turn = _angle(I - B) - _angle(I0 - p["B"])
    out = {"B": B, "I": I}
    for k in ("W", "K"):
        out[k] = B + _rot(p[k] - p["B"], turn)
    return out


def hand_floor(lift: float, tilt: float) -> float:
    q = hand(lift, tilt)
    return _angle(q["W"] - q["K"])


# ---------------------------------------------------------------- the machine file
def test_the_loader_registers_its_family_and_reads_its_built_in_machine(loader) -> None:
    fam = families()["loader"]
    assert fam.kind == "machine" and "wheel_loader_machine" in excavkin.examples("machine")
    m = load_any_machine("wheel_loader_machine")
    assert isinstance(m, Loader) and m.roles == ("lift", "tilt")
    assert loader.pins.hinge == "B" and loader.pins.lift_arm_pin == "A"
    assert loader.pins.cyl_ends == (("C", "D"), ("F", "G"))
    assert loader.chassis.ground_line == pytest.approx(0.0)
    assert loader.chassis.rear_axle == pytest.approx(-3.3)
    assert loader.bucket.capacity == pytest.approx(3.0)
    assert loader.chassis.max_articulation == pytest.approx(math.radians(40))
    # operating mass: the linkage's bodies and cylinders, the frames and the counterweight
    assert loader.linkage_mass == pytest.approx(1900 + 420 + 90 + 1500 + 340 + 230)
    assert loader.mass == pytest.approx(loader.linkage_mass + 3600 + 7000 + 3000)
    assert 15_000 <= loader.mass <= 20_000
    assert loader.hydraulics is not None and loader.hydraulics.flow("tilt") == pytest.approx(
        230e-3 / 60
    )


def test_the_linkage_solves_in_closed_form(loader) -> None:
    """Every step of the plan is closed form: the ground, three dyads, attachments."""
    steps = [line.split()[1] for line in loader.mechanism.plan.describe().splitlines()]
    assert steps.count("dyad") == 3 and "newton" not in steps
    assert set(steps) == {"fixed", "dyad", "attach"}


def test_the_engine_agrees_with_the_linkage_solved_by_hand(loader) -> None:
    rng = np.random.default_rng(7)
    L = rng.uniform(loader.lengths_min, loader.lengths_max, size=(40, 2))
    res = loader.solve(L)
    assert res.status.ok.all()
    for i in range(len(L)):
        q = hand(*L[i])
        for name in ("B", "I", "W", "K"):
            assert_allclose(res.positions[i, loader.index(name)], q[name], atol=1e-9)
        assert floor_angle(loader, res.positions[i : i + 1])[0] == pytest.approx(
            hand_floor(*L[i]), abs=1e-12
        )


def _write(tmp_path: Path, old: str, new: str) -> Path:
    text = MACHINE.read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / "m.toml"
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    (tmp_path / "wheel_loader.toml").write_text(
        (EXAMPLES / "wheel_loader.toml").read_text(encoding="utf-8"), encoding="utf-8"
    )
    return path


@pytest.mark.parametrize(
    ("old", "new", "where"),
    [
        ("bore = 140", "bore = -140", r"cylinders\.lift.*bore"),
        ("rod = 90", "rod = 190", r"cylinders\.tilt.*rod"),
        ("wheelbase = 3300", "wheelbase = 0", r"chassis.*wheelbase"),
        ('max_articulation = "40 deg"', 'max_articulation = "80 deg"', r"chassis.*max_artic"),
        ('capacity = "3.0 m^3"', 'capacity = "3.0 m"', r"bucket.*capacity"),
        ('edge = "W"', 'edge = "Q"', r"linkage.*edge"),
        ('driver = "tilt_cyl"', 'driver = "tilt"', r"cylinders\.tilt.*driver"),
        ('rolls_back = "extend"', 'rolls_back = "out"', r"cylinders\.tilt.*rolls_back"),
        ('rear_axle = "oscillating"', 'rear_axle = "bogie"', r"chassis.*rear_axle"),
        ("[chassis.counterweight]", "[chassis.ballast]", r"chassis.*ballast"),
        ("working = 24.0", "working = 30.0", r"circuits\.lift.*working"),
        ("articulation = -1650", "articulation = 500", r"chassis.*articulation"),
        ('family = "loader"', 'family = "excavator"', r"(front|family)"),
        ("retracted = 1293", "retracted = 5293", r"cylinders\.tilt.*retracted"),
    ],
)
def test_bad_values_are_named_by_file_table_and_entry(tmp_path, old, new, where) -> None:
    path = _write(tmp_path, old, new)
    with pytest.raises(ModelError, match=where) as exc:
        load_any_machine(path)
    assert "m.toml" in str(exc.value)


# ---------------------------------------------------------------- dimensions (SAE J732)
def test_poses_meet_their_conditions_by_hand(loader) -> None:
    lift = np.linspace(loader.lengths_min[0], loader.lengths_max[0], 5)
    tilt = tilt_for_angle(loader, lift, -DISCHARGE)
    assert np.isfinite(tilt[[0, -1]]).all()  # reached at the lowest and the full lift
    for a, b in zip(lift, tilt, strict=True):
        if np.isfinite(b):
            assert hand_floor(a, b) == pytest.approx(-DISCHARGE, abs=1e-10)
        else:  # not reached: the floor stays above −45° over the whole tilt stroke
            ts = np.linspace(loader.lengths_min[1], loader.lengths_max[1], 101)
            assert min(hand_floor(a, t) for t in ts) > -DISCHARGE
    g = ground_pose(loader)
    q = hand(*g)
    assert hand_floor(*g) == pytest.approx(0.0, abs=1e-10)
    assert q["W"][1] == pytest.approx(0.0, abs=1e-9)
    carry = lift_for_hinge_height(loader, loader.carry_height)
    assert hand(carry, 1.5)["B"][1] == pytest.approx(loader.carry_height, abs=1e-9)
    assert math.isnan(lift_for_hinge_height(loader, 50.0))
    assert np.isnan(tilt_for_angle(loader, lift[:1], math.radians(170.0))).all()


def test_dimensions_against_the_bucket_turned_rigidly_by_hand(loader) -> None:
    d = dimensions(loader)
    p = _sketch()
    up, low = loader.lengths_max[0], loader.lengths_min[0]
    B_up = hand(up, 1.5)["B"]
    assert d["hinge-pin height at full lift"] == pytest.approx(B_up[1], abs=1e-9)
    # the bucket turned rigidly about its hinge pin to a floor 45° below horizontal: the sketch
    # has its floor level, so the edge is B + R(−45°)·(W − B) of the sketch
    W45 = B_up + _rot(p["W"] - p["B"], -DISCHARGE)
    assert d["dump clearance at 45 deg"] == pytest.approx(W45[1], abs=1e-9)
    assert d["dump reach at 45 deg"] == pytest.approx(W45[0] - 0.8, abs=1e-9)
    B_low = hand(low, 1.5)["B"]
    assert d["digging depth"] == pytest.approx(-(B_low[1] + p["W"][1] - p["B"][1]), abs=1e-9)
    g = ground_pose(loader)
    roll, dump = loader.lengths_max[1], loader.lengths_min[1]
    carry = lift_for_hinge_height(loader, loader.carry_height)
    assert d["rollback at ground"] == pytest.approx(hand_floor(g[0], roll), abs=1e-10)
    assert d["rollback at carry"] == pytest.approx(hand_floor(carry, roll), abs=1e-10)
    assert d["rollback at full lift"] == pytest.approx(hand_floor(up, roll), abs=1e-10)
    assert d["dump angle at full lift"] == pytest.approx(-hand_floor(up, dump), abs=1e-10)


def test_the_built_in_loader_lies_in_its_class(loader) -> None:
    d = dimensions(loader)
    assert 3.8 <= d["hinge-pin height at full lift"] <= 4.3
    assert 2.5 <= d["dump clearance at 45 deg"] <= 3.1
    assert 0.0 < d["digging depth"] <= 0.2
    assert math.radians(40) <= d["rollback at ground"] <= math.radians(50)
    assert math.radians(45) <= d["dump angle at full lift"] <= math.radians(55)
    frame = d.to_frame()
    assert list(frame["figure"])[0] == "hinge-pin height at full lift"
    assert frame.attrs["excavkin.units"]["lift_cyl"] == "m"
    assert set(frame["unit"]) == {"m", "rad"}
    assert "hinge-pin height at full lift" in d.summary() and "deg" in d.summary()
    with pytest.raises(KeyError, match="known"):
        d["reach"]
