"""Gear trains against a published worked example, and against the tabular method.

Kos, L., "Analysis of Planetary Transmissions", the test run of its calculation program
(University of Ljubljana, LECAD, http://lecad.uni-lj.si/~leon/FS/PlanetryTransmissions/
node8.html): input the sun (21 teeth), the ring (108 teeth) held, output the carrier, planets of
43 teeth, centre distance 56.8 mm. Printed: "Transmission ratio: 6.14286".
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.testing import assert_allclose

import excavkin
from excavkin.model.entities import Torque

MODEL = Path(__file__).parent / "data" / "planetary_21_43_108.toml"


def test_planetary_transmission_ratio_reproduces_the_printed_digits() -> None:
    mech = excavkin.load(MODEL)
    q = np.linspace(-40.0, 40.0, 9)  # many turns of the sun: exact at every one
    res = mech.solve({"input": q}, rates={"input": 1.0}, accels={"input": 0.0})
    assert res.status.all_ok
    w_carrier = res.body("carrier")[1]
    ratio = 1.0 / w_carrier
    assert f"{ratio[0]:.5f}" == "6.14286"
    assert_allclose(ratio, 1.0 + 108 / 21, rtol=1e-14)  # n_s/n_c = 1 + z_r/z_s


def test_planetary_by_the_tabular_method() -> None:
    """The tabular method, written out: lock the train and turn it +1 with the carrier, then
    hold the carrier and turn the ring −1 (so the ring's sum is 0)."""
    zs, zp, zr = 21, 43, 108
    # row 1 (all +1): sun 1, planet 1, ring 1, carrier 1
    # row 2 (carrier held, ring −1): ring −1, planet −zr/zp, sun +zr/zs, carrier 0
    sun, planet, carrier = 1 + zr / zs, 1 - zr / zp, 1.0
    mech = excavkin.load(MODEL)
    q = np.linspace(0.0, 25.0, 5)
    res = mech.solve({"input": q}, rates={"input": sun}, accels={"input": 0.0})
    assert_allclose(res.body("carrier")[1], carrier, rtol=1e-14)
    assert_allclose(res.body("planet")[1], planet, rtol=1e-14)
    # angles: the carrier's orientation is its sketch one plus q / 6.14286…, every turn
    ang = np.unwrap(res.body("carrier")[0])
    assert_allclose(ang - ang[0], (q - q[0]) * zs / (zs + zr), atol=1e-12)


def test_planetary_torques_follow_the_ratio_and_the_pitch_radii() -> None:
    """Static output torque T on the carrier: the sun needs T / 6.14286; the sun-planet tooth
    force is the sun's torque over its operating pitch radius, a·zs/(zs + zp)."""
    mech = excavkin.load(MODEL)
    res = mech.solve({"input": np.linspace(0.0, 3.0, 7)})
    out = 250.0
    f = mech.forces(res, loads=[Torque("load", "carrier", -out)])
    torque = f.torque("input")
    assert_allclose(torque, out * 21 / 129, rtol=1e-13)
    a = 0.0568
    assert_allclose(f.column("sun_planet.tooth"), torque / (a * 21 / 64), rtol=1e-13)
    # the planet's moment: both tooth forces at its two operating pitch radii
    assert_allclose(
        f.column("planet_ring.tooth") * a * 43 / 65,
        f.column("sun_planet.tooth") * a * 43 / 64,
        rtol=1e-13,
    )
    # the radial part tan 20° of the tangential one, towards the sun's centre on the sun
    fx, fy = f.column("O.sun.Fx"), f.column("O.sun.Fy")
    ring = f.column("O.ring.Fx"), f.column("O.ring.Fy")
    assert np.all(np.isfinite(ring))
    w = f.column("sun_planet.tooth")
    assert_allclose(np.hypot(fx, fy), w / np.cos(np.radians(20.0)), rtol=1e-12)


RACK_TRAIN = """
schema_version = 1
name = "motor, compound gear and rack"
[units]
length = "mm"
[points]
OZ = [0, 0]
OX = [40, 0]
Z1 = [0, 10]
X1 = [40, 30]
G1 = [-100, -50]
G2 = [300, -50]
R1 = [0, -20]
R2 = [100, -20]
[bodies]
frame = { points = ["OZ", "OX", "G1", "G2"], ground = true }
z = { points = ["OZ", "Z1"] }
xy = { points = ["OX", "X1"] }
platform = { points = ["R1", "R2"] }
[drivers.motor]
type = "rotary"
body = "z"
pivot = "OZ"
[gears.zy]
gears = ["z", "xy"]
ratio = 3
[racks.lift]
rack = "platform"
pinion = "xy"
along = ["G1", "G2"]
radius = "PITCH_RADIUS mm"
"""


def test_rack_and_pinion_platform_reproduces_the_printed_digits() -> None:
    """Ryan, V., "Rack and pinion examination answer" (technologystudent.com, gears1/rkpin2,
    2003): a motor at 240 rev/min turns gear Z, which turns gear Y at one third of its speed,
    "Gear Y = 80 rpm"; gear X, compound with Y, has 13 teeth at a rack pitch of 4 mm, so the
    platform travels 13 × 80 = 1040 teeth, "1040 (teeth) x 4mm … = 4160mm" in one minute."""
    radius = 13 * 4 / (2 * np.pi)  # mm: a pitch circle of 13 teeth of 4 mm
    mech = excavkin.loads(RACK_TRAIN.replace("PITCH_RADIUS", repr(radius)), "rack.toml")
    q0 = mech.sketch_values()["motor"]
    rate = 240 * 2 * np.pi / 60  # rad/s
    minute = np.array([q0, q0 + rate * 60.0])
    res = mech.solve({"motor": minute}, rates={"motor": rate})
    assert res.status.all_ok
    rpm_y = np.abs(res.body("xy")[1]) * 60 / (2 * np.pi)
    assert_allclose(rpm_y, 80.0, rtol=1e-14)
    assert f"{rpm_y[0]:.0f}" == "80"
    travel = (res.point("R1")[0][1, 0] - res.point("R1")[0][0, 0]) * 1000  # mm
    assert f"{abs(travel):.0f}" == "4160"
    assert_allclose(abs(travel), 4160.0, rtol=1e-12)
    speed = np.abs(res.point("R1")[1][:, 0]) * 60e3  # mm/min
    assert_allclose(speed, 4160.0, rtol=1e-14)


def test_planetary_power_balances_with_the_planets_inertia() -> None:
    mech = excavkin.load(MODEL)
    rng = np.random.default_rng(6)
    n = 200
    res = mech.solve(
        {"input": rng.uniform(-50, 50, n)},
        rates={"input": rng.uniform(-300, 300, n)},
        accels={"input": rng.uniform(-900, 900, n)},
    )
    f = mech.forces(res, loads=[Torque("load", "carrier", -250.0)])
    assert np.abs(f.power_balance().relative).max() < 1e-9
    # a family of designs (the planet's pin moved) solves as each design alone
    params = {"P.x": np.array([0.0568, 0.0570, 0.0565])}
    q = {"input": np.array([0.3, 2.0, 5.0])}
    fam = mech.solve(q, params=params, rates={"input": 1.5})
    for i in range(3):
        one = mech.solve(
            {"input": q["input"][i : i + 1]}, params={"P.x": float(params["P.x"][i])},
            rates={"input": 1.5},
        )  # fmt: skip
        assert_allclose(fam.positions[i], one.positions[0], rtol=0, atol=0)
