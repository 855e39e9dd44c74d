"""A disc cam against a published worked example.

The textbook exercise quoted at mycoursehelp.com (QA 67124, "Design a cam to raise a valve with
simple harmonic motion …"): the valve rises 50 mm with simple harmonic motion in 1/3 of a
revolution, dwells for 1/12, falls with harmonic motion in 1/6 and stays closed for the rest;
a roller follower on the camshaft's axis, the camshaft at 100 rev/min. Printed answers: the
maximum velocity 0.39 m/s raising and 0.78 m/s lowering, the maximum acceleration 6.17 m/s²
and 24.67 m/s².
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.testing import assert_allclose

from excavkin import Body, CamFollower, Mechanism, Model, RotaryDriver

H = 0.050
RISE, DWELL, FALL = 2 * math.pi / 3, math.pi / 6, math.pi / 3


def valve(theta: Any) -> tuple[Any, Any, Any]:
    """The lift law: harmonic rise, dwell, harmonic fall, dwell (m, per rad of the cam)."""
    u = np.mod(theta, 2 * math.pi)
    up = u < RISE
    f0 = RISE + DWELL
    down = (u >= f0) & (u < f0 + FALL)
    top = (u >= RISE) & (u < f0)
    a, b = math.pi / RISE, math.pi / FALL
    v = u - f0
    s = np.where(up, H / 2 * (1 - np.cos(a * u)), np.where(down, H / 2 * (1 + np.cos(b * v)), 0.0))
    s = np.where(top, H, s)
    s1 = np.where(up, H / 2 * a * np.sin(a * u), np.where(down, -H / 2 * b * np.sin(b * v), 0.0))
    s2 = np.where(
        up, H / 2 * a * a * np.cos(a * u), np.where(down, -H / 2 * b * b * np.cos(b * v), 0.0)
    )
    return s, s1, s2


def test_valve_cam_reproduces_the_printed_maxima() -> None:
    model = Model(
        name="valve cam",
        points={"O": (0.0, 0.0), "G1": (0.0, -0.1), "G2": (0.0, 0.3), "C": (0.02, 0.0),
                "F1": (0.0, 0.035), "F2": (0.0, 0.2)},
        bodies=(
            Body("frame", ("O", "G1", "G2"), ground=True),
            Body("cam", ("O", "C")),
            Body("valve", ("F1", "F2")),
        ),
        rotary=(RotaryDriver("shaft", body="cam", pivot="O", reference="frame"),),
        cams=(CamFollower("lift", "cam", "valve", "frame", ("G1", "G2"), valve),),
    )  # fmt: skip
    mech = Mechanism(model)
    omega = 100 * 2 * math.pi / 60
    turn = np.linspace(0.0, 2 * math.pi, 72001)[:-1]
    res = mech.solve(
        {"shaft": mech.sketch_values()["shaft"] + turn},
        rates={"shaft": omega},
        accels={"shaft": 0.0},
    )
    assert res.status.all_ok
    _, v, a = res.point("F1")
    rising = turn < RISE
    falling = (turn >= RISE + DWELL) & (turn < RISE + DWELL + FALL)
    v_up, v_down = np.abs(v[rising, 1]).max(), np.abs(v[falling, 1]).max()
    a_up, a_down = np.abs(a[rising, 1]).max(), np.abs(a[falling, 1]).max()
    assert (f"{v_up:.2f}", f"{a_up:.2f}", f"{a_down:.2f}") == ("0.39", "6.17", "24.67")
    assert f"{v_down:.3f}"[:4] == "0.78"  # printed 0.78 (0.785…, cut to two places)
    # and exactly the closed forms: v = (h/2)(π/β)ω, a = (h/2)(π/β)²ω²
    assert_allclose(v_up, H / 2 * math.pi / RISE * omega, rtol=1e-8)
    assert_allclose(a_up, H / 2 * (math.pi / RISE * omega) ** 2, rtol=1e-12)
    assert_allclose(a_down, H / 2 * (math.pi / FALL * omega) ** 2, rtol=1e-12)
