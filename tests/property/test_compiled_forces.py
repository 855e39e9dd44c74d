"""The compiled kinetostatic back-substitution (one machine-code loop per plan and equilibrium
system) against the NumPy back-substitution, the reference: every force column, the singular
flags and the NaN pattern, for every example with masses, with loads of every kind (constant,
one value per sample, functions of the motion, couples with a reaction, gravity), without
inertia, and for families of designs whose dimensions and masses vary per sample."""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from excavkin import backends
from excavkin.kinetostatics import ForceResult, Gravity, PointForce, Torque, compiled, solve_forces
from tests.property.test_compiled import sweep
from tests.property.test_designs import random_designs

WITH_MASSES = ["fourbar", "slider_crank", "excavator", "pasika_module", "mo100_hammer"]


def assert_same_forces(a: ForceResult, b: ForceResult) -> None:
    """Equal to 1e-15 of each column's scale (the traced kernel does the NumPy path's
    operations in its order), NaN where it is NaN, singular where it is."""
    np.testing.assert_array_equal(a.singular, b.singular)
    fa, fb = a.to_frame(kinematics=False), b.to_frame(kinematics=False)
    assert list(fa.columns) == list(fb.columns)
    for col in fa.columns:
        x, y = fa[col].to_numpy(), fb[col].to_numpy()
        if x.dtype.kind != "f":
            np.testing.assert_array_equal(x, y, err_msg=col)
            continue
        np.testing.assert_array_equal(np.isnan(x), np.isnan(y), err_msg=col)
        finite = np.isfinite(x)
        scale = max(np.max(np.abs(x[finite]), initial=0.0), 1e-300)
        assert np.max(np.abs(x - y)[finite], initial=0.0) <= 1e-15 * scale, col


def every_kind_of_load(mech: excavkin.Mechanism, n: int) -> list:
    """Gravity, a constant force, a force per sample, a force following the motion, a constant
    couple with a reaction and a couple per sample, on the moving bodies."""
    model = mech.model
    moving = [b for b in model.bodies if not b.ground]
    ground = next(b.name for b in model.bodies if b.ground)
    rng = np.random.default_rng(3)
    first, last = moving[0], moving[-1]

    def follow(res: excavkin.KinematicResult) -> np.ndarray:
        _, v, _ = res.point(last.points[-1])
        return -40.0 * v

    return [
        Gravity(),
        PointForce("push", first.name, first.points[-1], (120.0, -35.0)),
        PointForce("gust", last.name, last.points[0], rng.normal(0.0, 50.0, (n, 2))),
        PointForce("drag", last.name, last.points[-1], follow),
        Torque("motor", first.name, 15.0, reaction=ground),
        Torque("ripple", last.name, rng.normal(0.0, 5.0, n)),
    ]


@pytest.mark.parametrize("name", WITH_MASSES)
def test_each_example_compiled_forces_equal_numpy(name: str) -> None:
    mech = excavkin.load(excavkin.example_path(name))
    values = sweep(mech, 3001, 1.5)  # far enough that some samples cannot close
    for v in values.values():
        v[1500:1510] = np.nan  # and inputs that are no numbers: no forces either
    kin = mech.solve(values, rates={k: 0.7 for k in values}, accels={k: -0.3 for k in values})
    loads = every_kind_of_load(mech, len(kin))
    ref = mech.forces(kin, loads, backend="numpy")
    assert_same_forces(mech.forces(kin, loads, backend="numba"), ref)
    assert ref.ok.sum() > 100 and np.isnan(ref.pin_force).any()  # failures and forces both
    # statics at each pose (no inertia), and the model's own loads alone
    assert_same_forces(
        solve_forces(kin, loads, system=mech.statics, inertia=False, backend="numba"),
        solve_forces(kin, loads, system=mech.statics, inertia=False, backend="numpy"),
    )
    assert_same_forces(mech.forces(kin, backend="numba"), mech.forces(kin, backend="numpy"))


@pytest.mark.parametrize("name", ["fourbar", "excavator"])
def test_families_of_designs_compiled_forces_equal_numpy(name: str) -> None:
    """Dimensions, masses and inertias one per sample: the constants table holds a column per
    sample."""
    mech = excavkin.load(excavkin.example_path(name))
    values, params = random_designs(mech, np.random.default_rng(11), 2500)
    assert any(k.endswith(".mass") for k in params) or name == "fourbar"
    args = dict(rates={k: 0.2 for k in values}, accels={k: 0.1 for k in values}, params=params)
    kin = mech.solve(values, **args)
    loads = [Gravity(), PointForce("w", mech.model.bodies[-1].name, mech.model.bodies[-1].points[0],
                                   (0.0, -500.0))]  # fmt: skip
    assert_same_forces(
        mech.forces(kin, loads, backend="numba"), mech.forces(kin, loads, backend="numpy")
    )
    # through solve, as one call
    fast = mech.solve(values, **args, loads=loads, backend="numba")
    assert isinstance(fast, ForceResult)
    assert_same_forces(fast, mech.solve(values, **args, loads=loads, backend="numpy"))


def test_a_singular_pose_is_flagged_alike() -> None:
    """The four-bar's coupler and rocker made collinear (B on the line A–O4, a dead position):
    the dyad's two directions are parallel, and the kernel flags the samples the NumPy
    back-substitution flags; elsewhere its forces are the NumPy path's."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    kin = mech.solve({"crank": np.linspace(0.0, 6.0, 400)}, rates={"crank": 1.0})
    x = np.array(np.moveaxis(kin.positions, 0, -1))
    a = np.array(np.moveaxis(kin.accelerations, 0, -1))
    eps = np.array(np.moveaxis(kin.body_epsilon, 0, -1))
    pts = mech.plan.points
    ia, ib, io = pts.index("A"), pts.index("B"), pts.index("O4")
    x[ib, :, ::7] = x[ia, :, ::7] + 0.4 * (x[io, :, ::7] - x[ia, :, ::7])
    from excavkin.kinetostatics.body_loads import body_loads
    from excavkin.kinetostatics.inertia import MassProperties
    from excavkin.kinetostatics.loads import evaluate_loads
    from excavkin.kinetostatics.structured import compile_structured, solve_structured

    mp, sy = MassProperties.of(kin), mech.statics
    ss = compile_structured(mech.plan, sy)
    ev = evaluate_loads(mech.model, [Gravity()], kin)
    with np.errstate(all="ignore"):
        ref, singular = solve_structured(ss, x, body_loads(sy, mp, ev, x, a, eps, slice(None)))
    text, values = compiled.source(ss, mp, ev, inertia=True)
    out, flags = np.empty((sy.size, 400)), np.zeros(400, dtype=bool)
    compiled.solve(backends.kernel_of(text), values, x, a, eps, out, flags)
    assert singular[::7].all() and singular.sum() == len(singular[::7])
    np.testing.assert_array_equal(flags, singular)
    ok = ~singular
    scale = np.abs(ref[:, ok]).max()
    assert np.abs(out[:, ok] - ref[:, ok]).max() <= 1e-15 * scale


def test_the_source_depends_on_the_structure_not_the_values() -> None:
    """Two designs with other masses and loads of other sizes share one kernel: the values are
    in the constants table."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    kin = mech.solve({"crank": np.linspace(0.0, 6.0, 50)})
    from excavkin.kinetostatics.inertia import MassProperties
    from excavkin.kinetostatics.loads import evaluate_loads
    from excavkin.kinetostatics.structured import compile_structured

    sy = compile_structured(mech.plan, mech.statics)

    mp = MassProperties.of(kin)
    heavier = MassProperties(mp.mass * 2.0, mp.inertia * 3.0, mp.com * 0.5, mp.base)
    one = evaluate_loads(mech.model, [Gravity(), PointForce("p", "coupler", "B", (1.0, 2.0))], kin)
    two = evaluate_loads(mech.model, [Gravity(5.0), PointForce("p", "coupler", "B", (7.0, 0.5))],
                         kin)  # fmt: skip
    text, values = compiled.source(sy, mp, one, inertia=True)
    text2, values2 = compiled.source(sy, heavier, two, inertia=True)
    assert text == text2 and values != values2
    compiled._traced.clear()  # traced anew: the same source as the one kept
    assert compiled.source(sy, heavier, two, inertia=True) == (text2, values2)
    assert compiled.source(sy, mp, one, inertia=False)[0] != text


def test_streamed_parts_compiled_equal_numpy(monkeypatch: pytest.MonkeyPatch) -> None:
    """``solve_stream`` with loads passes ``compiled`` on to each part's forces."""
    mech = excavkin.load(excavkin.example_path("excavator"))
    values = sweep(mech, 5000, 0.5)
    args = dict(rates={k: 0.4 for k in values}, loads=[Gravity()], size=4096)
    calls = []
    solve = compiled.solve
    monkeypatch.setattr(compiled, "solve", lambda *a, **k: calls.append(1) or solve(*a, **k))
    fast = list(mech.solve_stream(values, backend="numba", **args))
    assert len(calls) == 2  # each part's forces by the kernel
    ref = list(mech.solve_stream(values, backend="numpy", **args))
    assert len(calls) == 2
    assert [p.start for p in fast] == [p.start for p in ref] == [0, 4096]
    for a, b in zip(fast, ref, strict=True):
        assert isinstance(a.result, ForceResult) and isinstance(b.result, ForceResult)
        assert_same_forces(a.result, b.result)
