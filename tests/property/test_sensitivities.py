"""Exact design sensitivities against 8th-order central differences of whole solves, for every
column kind of every closed-form example — positions, velocities, accelerations, transmission
angles, driver values and forces — at the nominal design and inside a family of designs."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import excavkin
from excavkin.errors import InputError
from excavkin.structure.design import joint_offsets

#: 8th-order central-difference weights for the first derivative (offsets −4 … 4)
WEIGHTS = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])


def differences(mech, values, rates, params, name, step):  # type: ignore[no-untyped-def]
    """d(every float column)/d(name) by 8th-order central differences of whole solves."""
    tables = []
    for k in range(-4, 5):
        moved = dict(params)
        moved[name] = params.get(name, mech.parameters.get(name, 0.0)) + k * step
        res = mech.solve(values, rates=rates, params=moved, loads="model")
        assert res.kinematics.status.all_ok
        tables.append(res.to_frame())
    cols = [c for c in tables[0].columns if tables[0][c].dtype.kind == "f"]
    cols = [c for c in cols if not c.startswith(("d(", "design."))]
    return {
        c: sum(w * t[c].to_numpy() for w, t in zip(WEIGHTS, tables, strict=True)) / step
        for c in cols
    }


def check(mech, values, names, params=None) -> float:  # type: ignore[no-untyped-def]
    rates = {k: 0.07 for k in values}
    params = params or {}
    res = mech.solve(values, rates=rates, params=params, sensitivities=names, loads="model")
    table = res.to_frame()
    worst = 0.0
    for name in names:
        mass = name.endswith((".mass", ".inertia"))
        step = 3e-4 * (abs(mech.parameters[name]) if mass else mech.plan.scale)
        fd = differences(mech, values, rates, params, name, step)
        for col, ref in fd.items():
            exact = res.sensitivity(col, name)
            # a derivative that is zero is judged against the column's own size per length
            floor = 1e-3 * max(np.abs(table[col].to_numpy()).max(), 1e-3) / mech.plan.scale
            scale = max(np.abs(ref).max(), floor)
            worst = max(worst, float(np.abs(exact - ref).max() / scale))
    return worst


@pytest.mark.parametrize(
    ("name", "names"),
    [
        ("fourbar", ["A-B", "O4-B", "O4.x", "A.y", "O2.y"]),
        ("slider_crank", None),
        ("excavator", None),
        ("rope_shovel", None),
        ("pasika_module", None),
    ],
)
def test_sensitivities_equal_8th_order_differences(name: str, names: list[str] | None) -> None:
    mech = excavkin.load(excavkin.example_path(name))
    rng = np.random.default_rng(7)
    n = 6
    values = {
        k: v + rng.uniform(-0.1, 0.1, n)
        if mech.input_kind(k) == "angle"
        else v * (1 + rng.uniform(-0.01, 0.01, n))
        for k, v in mech.sketch_values().items()
    }
    if names is None:  # every fourth dimension, a mass, a centre of mass and a pin offset
        names = [k for k in mech.parameters if not k.endswith((".mass", ".inertia"))][::4][:5]
        names = [k for k in names if ".center_of_mass." not in k]
        names += [k for k in mech.parameters if k.endswith((".mass", ".center_of_mass.x"))][:2]
        names += list(joint_offsets(mech.model))[-1:]
    assert check(mech, values, names) <= 1e-8


def test_sensitivities_inside_a_family_of_designs() -> None:
    """Each sample's derivative is taken at its own design."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    rng = np.random.default_rng(11)
    n = 5
    params = {"A-B": 0.12 + rng.uniform(-5e-3, 5e-3, n), "O4.x": 0.1 + rng.uniform(-5e-3, 5e-3, n)}
    values = {"crank": rng.uniform(0, 2 * np.pi, n)}
    assert check(mech, values, ["A-B", "O4.x", "B.x"], params) <= 1e-8


def test_a_held_driver_moves_with_its_sketch() -> None:
    """The arm cylinder held at its sketch length: moving its end E changes that length by
    exactly the derivative of |E − G|."""
    mech = excavkin.load(excavkin.example_path("excavator"))
    res = mech.solve({"boom_cyl": [mech.sketch_values()["boom_cyl"]]}, sensitivities=["E.x"])
    (ex, ey), (gx, gy) = mech.model.points["E"], mech.model.points["G"]
    expected = (ex - gx) / np.hypot(ex - gx, ey - gy)
    assert res.sensitivity("arm_cyl.value", "E.x")[0] == pytest.approx(expected, rel=1e-12)


def test_sensitivity_errors_are_plain() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    res = mech.solve({"crank": [0.1]})
    with pytest.raises(InputError, match="sensitivities="):
        res.sensitivity("B.x", "A-B")
    with pytest.raises(InputError, match="did you mean 'A-B'"):
        mech.solve({"crank": [0.1]}, sensitivities=["A-C"])


def test_a_newton_group_differentiates_by_the_implicit_function_theorem() -> None:
    """A class-III triad (Newton alone closes it): its sensitivities against 8th-order
    differences, kinematics and forces; and the four-bar solved by the generic solver gives the
    closed form's sensitivities."""
    from excavkin import Gravity
    from tests.property.test_random_linkages import TRIAD, triad

    model = triad(TRIAD)
    bodies = tuple(
        dataclasses.replace(b, mass=2.0, inertia=0.05) if b.name == "tri" else b
        for b in model.bodies
    )
    mech = excavkin.Mechanism(dataclasses.replace(model, bodies=bodies, gravity=Gravity()))
    assert mech.plan.has_newton
    q0 = mech.sketch_values()["crank"]
    values = {"crank": q0 + np.linspace(-0.4, 0.4, 5)}
    assert check(mech, values, ["O2.x", "C.y", "D.x", "tri.mass", "B@tri.x"]) <= 1e-8

    fourbar = excavkin.load(excavkin.example_path("fourbar"))
    generic = excavkin.Mechanism(fourbar.model, method="newton")
    q = {"crank": np.radians(np.linspace(0, 300, 7))}
    names = ["A-B", "O4.x", "B@rocker.x", "rocker.mass"]
    a = fourbar.solve(q, rates={"crank": 2.0}, sensitivities=names, loads="model")
    b = generic.solve(q, rates={"crank": 2.0}, sensitivities=names, loads="model")
    for col in ("B.x", "B.vy", "B.ay", "rocker.epsilon", "crank.torque", "O4.rocker.Fx"):
        for name in names:
            x, y = a.sensitivity(col, name), b.sensitivity(col, name)
            assert np.abs(x - y).max() <= 1e-12 * max(np.abs(x).max(), 1e-9), (col, name)


def test_load_magnitudes_are_parameters() -> None:
    """A model's own constant loads: their magnitudes vary per sample and have exact
    sensitivities (the forces are linear in them: the derivative is the response to a unit
    load, checked against a solve with the load doubled)."""
    text = excavkin.example_path("fourbar").read_text() + (
        '\n[loads.push]\ntype = "force"\nbody = "coupler"\npoint = "B"\nvalue = ["40 N", "-25 N"]\n'
        '\n[loads.brake]\ntype = "torque"\nbody = "rocker"\nvalue = "3 N*m"\n'
    )
    mech = excavkin.loads(text, "loaded.toml")
    assert mech.parameters["push.Fx"] == 40.0 and mech.parameters["brake.torque"] == 3.0
    q = {"crank": np.radians(np.linspace(0, 330, 12))}
    names = ["push.Fx", "push.Fy", "brake.torque", "A-B"]
    res = mech.solve(q, rates={"crank": 2.0}, loads="model", sensitivities=names)
    base = mech.solve(q, rates={"crank": 2.0}, loads="model")
    for name, nominal in (("push.Fx", 40.0), ("push.Fy", -25.0), ("brake.torque", 3.0)):
        twice = mech.solve(q, rates={"crank": 2.0}, loads="model", params={name: 2 * nominal})
        for col in ("crank.torque", "B.rocker.Fx", "ground.Ry"):
            slope = (twice.column(col) - base.column(col)) / nominal
            np.testing.assert_allclose(res.sensitivity(col, name), slope, rtol=1e-9, atol=1e-9)
        assert np.all(res.sensitivity("B.x", name) == 0.0)  # a load moves nothing
    per_sample = mech.solve(q, loads="model", params={"push.Fx": np.linspace(0, 80, 12)})
    one = mech.solve({"crank": q["crank"][3:4]}, loads="model", params={"push.Fx": 80 * 3 / 11})
    assert per_sample.torque("crank")[3] == pytest.approx(one.torque("crank")[0], rel=1e-12)


def _spring_loads(k: float = 400.0, c: float = 3.0):  # type: ignore[no-untyped-def]
    """A spring from B to a fixed point and a damper on the rocker: loads that are functions of
    the result, and so of the design."""
    from excavkin.kinetostatics import PointForce, Torque

    def spring(r):  # type: ignore[no-untyped-def]
        b = r.point("B")[0]
        return np.stack([-k * (b[:, 0] - 0.05), -k * (b[:, 1] - 0.2)], axis=-1)

    def damper(r):  # type: ignore[no-untyped-def]
        return -c * r.body("rocker")[1]

    return [PointForce("spring", "coupler", "B", spring), Torque("damper", "rocker", damper)]


def test_a_load_that_is_a_function_of_the_result_is_differentiated() -> None:
    """Force sensitivities under a spring and a damper (functions of the result) equal 8th-order
    differences of whole solves; holding the loads at their values would miss their own
    dependence on the design by far more than the tolerance."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    q, rates = {"crank": np.radians(np.linspace(10, 340, 9))}, {"crank": 3.0}
    loads = _spring_loads()
    names = ["A-B", "O4.x"]
    kin = mech.solve(q, rates=rates, sensitivities=names)
    res = mech.forces(kin, loads)
    held = mech.forces(kin, [dataclasses.replace(ld, value=ld.value(kin)) for ld in loads])
    for name in names:
        step = 3e-4 * mech.plan.scale
        tables = []
        for j in range(-4, 5):
            moved = {name: mech.parameters[name] + j * step}
            tables.append(mech.forces(mech.solve(q, rates=rates, params=moved), loads))
        for col in ("crank.torque", "B.rocker.Fx", "ground.Ry"):
            ref = sum(w * t.column(col) for w, t in zip(WEIGHTS, tables, strict=True)) / step
            scale = np.abs(ref).max()
            exact = res.sensitivity(col, name)
            assert np.abs(exact - ref).max() <= 1e-8 * scale, (name, col)
            assert np.abs(held.sensitivity(col, name) - ref).max() > 1e-3 * scale


def test_a_load_function_that_cannot_be_differentiated_is_refused() -> None:
    from excavkin.kinetostatics import Torque

    mech = excavkin.load(excavkin.example_path("fourbar"))
    kin = mech.solve({"crank": np.radians([10.0, 50.0])}, sensitivities=["A-B"])
    opaque = Torque("opaque", "rocker", lambda r: -2.0 * r.column("rocker.angle"))
    with pytest.raises(InputError, match="'opaque'.*cannot be differentiated"):
        mech.forces(kin, [opaque])
    # without sensitivities the same load is fine
    plain = mech.solve({"crank": np.radians([10.0, 50.0])})
    assert np.isfinite(mech.forces(plain, [opaque]).column("crank.torque")).all()
    # a function of time alone has no tangent to carry
    steady = Torque("steady", "rocker", lambda r: np.full(len(r), 0.5))
    assert np.isfinite(mech.forces(kin, [steady]).sensitivity("crank.torque", "A-B")).all()


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_only_the_columns_asked_for_are_differentiated(backend: str) -> None:
    """sensitivity_columns: the chosen columns' derivatives equal those of a full solve to the
    bit (compiled: the same loop with the other stores left out); any other column's is
    refused, not read as 0, and the table holds only the chosen ones."""
    pytest.importorskip("numba") if backend == "numba" else None
    mech = excavkin.load(excavkin.example_path("excavator"))
    names = ["D.x", "E.y", "G.x"]
    n = 64
    sketch = mech.sketch_values()
    values = {d: sketch[d] + np.linspace(-0.1, 0.1, n) for d in mech.plan.inputs}
    cols = ["W.x", "W.vy", "bucket.angle", "D.transmission"]
    full = mech.solve(values, sensitivities=names, backend=backend)
    some = mech.solve(values, sensitivities=names, sensitivity_columns=cols, backend=backend)
    assert some.tangent_columns == frozenset(cols)
    for c in cols:
        for p in names:
            np.testing.assert_array_equal(some.sensitivity(c, p), full.sensitivity(c, p))
    with pytest.raises(InputError, match="'W.y' was not computed"):
        some.sensitivity("W.y", "D.x")
    derivatives = [c for c in some.to_frame().columns if c.startswith("d(")]
    assert len(derivatives) == len(cols) * len(names)
    assert all(any(f"d({c})" in d for c in cols) for d in derivatives)
    with pytest.raises(InputError, match="W.xx"):
        mech.solve(values, sensitivities=names, sensitivity_columns=["W.xx"])
    with pytest.raises(InputError, match="without loads"):
        mech.solve(values, sensitivities=names, sensitivity_columns=cols, loads="model")
