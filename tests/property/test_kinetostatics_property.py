"""Random assemblable mechanisms with random masses: power balance and pin equilibrium.

Hypothesis draws four-bar sketches (any sketch is assemblable: its lengths are read off it),
masses, centres of mass anywhere in the plane of the link, inertias, crank speed and
acceleration, gravity and a load; the crank then sweeps a full turn. At every solved sample:

* power balance: driver power = dT/dt − load power, ≤ 1e-9 relative;
* the pin forces on the two bodies of each pin are equal and opposite;
* every moving body is in equilibrium under its pin forces, loads and inertia (force and moment,
  recomputed here from the outputs);
* samples that cannot close are NaN in the forces too, never silently filled.
"""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from excavkin.kinetostatics import (
    ForceResult,
    Gravity,
    PointForce,
    centre_of_mass,
    inertia_loads,
)
from excavkin.mechanism import Mechanism
from excavkin.model import Body, Model, RotaryDriver
from tests.property.sketches import not_collinear, spread, watt_sketch

coord = st.floats(-1.0, 1.0, allow_nan=False)
point = st.tuples(coord, coord)
mass = st.floats(0.05, 20.0)
inertia = st.floats(0.0, 2.0)


def _check_equilibrium(res: ForceResult) -> None:
    """Recompute each moving body's force and moment balance from the outputs."""
    kin = res.kinematics
    ok = res.ok
    sy = res.system
    x = kin.positions
    fin, cin = inertia_loads(kin)
    s, _, _ = centre_of_mass(kin)
    g = res.evaluated.gravity or (0.0, 0.0)
    for j in sy.moving:
        p0 = sy.base[j][0]
        force = np.zeros((len(kin), 2))
        moment = np.zeros(len(kin))
        mags = np.zeros(len(kin))
        for k, (i, jj) in enumerate(sy.slots):
            if jj == j:
                f = res.pin_force[:, k]
                r = x[:, i] - x[:, p0]
                force += f
                moment += r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0]
                mags += np.hypot(f[:, 0], f[:, 1])
        m = res.mass.mass[j]
        if m > 0:
            f = fin[:, j] + m * np.asarray(g)
            r = s[:, j] - x[:, p0]
            force += f
            moment += r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0] + cin[:, j]
            mags += np.hypot(f[:, 0], f[:, 1]) + np.abs(cin[:, j])
        for body, pt, fx, fy in res.evaluated.forces:
            if body == j:
                f = np.stack(np.broadcast_arrays(fx, fy, np.zeros(len(kin)))[:2], axis=1)
                r = x[:, pt] - x[:, p0]
                force += f
                moment += r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0]
                mags += np.hypot(f[:, 0], f[:, 1])
        for k, (_, body, ref) in enumerate(sy.rotary):
            tau = res.driver_torque[:, k]
            moment += tau * ((body == j) - (ref == j))
        size = 4.0
        assert np.all(np.abs(force[ok]) <= 1e-10 * mags[ok, None] + 1e-300)
        assert np.all(np.abs(moment[ok]) <= 1e-10 * size * mags[ok] + 1e-300)


def _check(res: ForceResult) -> None:
    kin = res.kinematics
    ok = res.ok
    assert ok.any()
    assert np.isfinite(res.pin_force[ok]).all() and np.isfinite(res.driver_torque[ok]).all()
    assert np.isnan(res.pin_force[~kin.status.ok]).all()
    pb = res.power_balance()
    assert np.all(pb.relative[ok] <= 1e-9), float(np.max(pb.relative[ok]))
    pins = res.pins
    for point in {p for p, _ in pins}:
        ks = [k for k, (p, _) in enumerate(pins) if p == point]
        total = res.pin_force[:, ks].sum(axis=1)
        mag = np.abs(res.pin_force[:, ks]).max(axis=(1, 2))
        assert np.all(np.abs(total[ok]) <= 1e-12 * mag[ok, None] + 1e-300)
    _check_equilibrium(res)


def _com(p0: tuple, p1: tuple, s: float, t: float) -> tuple[float, float]:
    wx, wy = p1[0] - p0[0], p1[1] - p0[1]
    return p0[0] + s * wx - t * wy, p0[1] + s * wy + t * wx


@settings(
    max_examples=150,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.filter_too_much],
)
@given(
    st.lists(point, min_size=4, max_size=4),
    st.lists(
        st.tuples(mass, inertia, st.floats(-0.5, 1.5), st.floats(-1.0, 1.0)), min_size=3, max_size=3
    ),
    st.floats(0.2, 20.0),
    st.floats(-50.0, 50.0),
    st.floats(0.0, 2.0 * np.pi),
    st.tuples(st.floats(-100.0, 100.0), st.floats(-100.0, 100.0)),
)
def test_random_massive_fourbars(pts, props, w, al, g_dir, load) -> None:  # noqa: ANN001
    o2, a, b, o4 = pts
    if not (spread(pts) and not_collinear(a, o4, b)):
        return
    sk = {"O2": o2, "A": a, "B": b, "O4": o4}
    bodies = [Body("ground", ("O2", "O4"), ground=True)]
    for (name, p0, p1), (m, j, s, t) in zip(
        (("crank", "O2", "A"), ("coupler", "A", "B"), ("rocker", "O4", "B")), props, strict=True
    ):
        bodies.append(
            Body(name, (p0, p1), mass=m, inertia=j, center_of_mass=_com(sk[p0], sk[p1], s, t))
        )
    model = Model(
        "random massive four-bar",
        sk,
        tuple(bodies),
        rotary=(RotaryDriver("crank", "crank", "O2", "ground"),),
    )
    mech = Mechanism(model)
    q0 = mech.sketch_values()["crank"]
    kin = mech.solve({"crank": q0 + np.linspace(-np.pi, np.pi, 145)}, {"crank": w}, {"crank": al})
    loads = [
        Gravity(9.81, (float(np.cos(g_dir)), float(np.sin(g_dir)))),
        PointForce("p", "coupler", "B", load),
    ]
    _check(mech.forces(kin, loads))


def watt_sixbar(p: dict[str, tuple[float, float]], masses: list[float]) -> Model:
    links = (
        ("crank", ("O2", "A")),
        ("coupler", ("A", "B")),
        ("rocker", ("O4", "B", "C")),
        ("link", ("C", "D")),
        ("output", ("O6", "D")),
    )
    bodies = [Body("ground", ("O2", "O4", "O6"), ground=True)]
    for (name, pts), m in zip(links, masses, strict=True):
        cx = float(np.mean([p[q][0] for q in pts]))
        cy = float(np.mean([p[q][1] for q in pts]))
        bodies.append(Body(name, pts, mass=m, inertia=0.1 * m, center_of_mass=(cx, cy)))
    return Model(
        "Watt II six-bar",
        p,
        tuple(bodies),
        rotary=(RotaryDriver("crank", "crank", "O2", "ground"),),
    )


@settings(max_examples=200, deadline=None, derandomize=True)
@given(
    st.lists(point, min_size=7, max_size=7),
    st.lists(mass, min_size=5, max_size=5),
    st.floats(0.2, 10.0),
)
def test_random_massive_watt_sixbars(pts, masses, w) -> None:  # noqa: ANN001
    p = watt_sketch(pts)
    if p is None:
        return
    mech = Mechanism(watt_sixbar(p, masses))
    q0 = mech.sketch_values()["crank"]
    kin = mech.solve({"crank": q0 + np.linspace(-1.0, 1.0, 81)}, {"crank": w}, {"crank": -w})
    _check(mech.forces(kin, [Gravity()]))
