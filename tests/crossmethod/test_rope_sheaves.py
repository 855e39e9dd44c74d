"""A rope over sheaves against independent computations: its length and its derivatives
against a root-finding construction of the tangents in 40-digit arithmetic (mpmath), the
motion against 8th-order differences, the tension against moments by hand, power balance with
inertia, the compiled equilibrium against NumPy's, and the exact sensitivities."""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from excavkin import Gravity, Mechanism, Model, PointForce, Rope
from excavkin.model.entities import Body, RotaryDriver, Slider
from excavkin.step_kinds.rope_path import rope_path, sketch_wraps
from tests.conftest import fd_derivatives

mp.mp.dps = 40

#: 8th-order central-difference weights for the first derivative (offsets −4 … 4)
WEIGHTS = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])


def tangent(c1, s1, c2, s2):  # type: ignore[no-untyped-def]
    """The direction angle α of the free segment from circle 1 to circle 2 (signed radii),
    by root finding: the segment P1→P2, P = c − s·n(α), runs along u(α)."""
    dx, dy = c2[0] - c1[0], c2[1] - c1[1]

    def f(a):  # type: ignore[no-untyped-def]
        return mp.cos(a) * dy - mp.sin(a) * dx - (s2 - s1)

    a = mp.findroot(f, mp.atan2(dy, dx))
    assert mp.cos(a) * dx + mp.sin(a) * dy > 0
    return a


def mp_length(pts, signed):  # type: ignore[no-untyped-def]
    """Free segments (projections of D on u) plus arcs (the turns, in (0, 2π) by their sense)."""
    alphas = [tangent(pts[k], signed[k], pts[k + 1], signed[k + 1]) for k in range(len(pts) - 1)]
    total = mp.mpf(0)
    for k, a in enumerate(alphas):
        dx, dy = pts[k + 1][0] - pts[k][0], pts[k + 1][1] - pts[k][1]
        total += mp.cos(a) * dx + mp.sin(a) * dy
    for k in range(1, len(pts) - 1):
        turn = (alphas[k] - alphas[k - 1]) * (1 if signed[k] > 0 else -1)
        total += abs(signed[k]) * (turn % (2 * mp.pi))
    return total


PATH = [(-1.0, 3.0), (1.5, 2.0), (0.4, -0.3), (3.0, 0.2), (2.2, 2.9)]
SIGNED = [0.0, -0.3, 0.25, 0.4, 0.0]  # cw, ccw, ccw: a wrap near π on the middle sheaves


def test_length_gradient_and_rates_against_mpmath() -> None:
    wraps0 = sketch_wraps(PATH, SIGNED)
    pts = [(np.array([x]), np.array([y])) for x, y in PATH]
    geo = rope_path(pts, SIGNED, wraps0)
    exact = mp_length([(mp.mpf(x), mp.mpf(y)) for x, y in PATH], [mp.mpf(s) for s in SIGNED])
    assert float(geo.length[0]) == pytest.approx(float(exact), rel=1e-15)
    rng = np.random.default_rng(7)
    vel = rng.standard_normal((len(PATH), 2))
    acc = rng.standard_normal((len(PATH), 2))

    def moved(t):  # type: ignore[no-untyped-def]
        return [
            (mp.mpf(x) + t * vel[k, 0] + t * t / 2 * acc[k, 0],
             mp.mpf(y) + t * vel[k, 1] + t * t / 2 * acc[k, 1])
            for k, (x, y) in enumerate(PATH)
        ]  # fmt: skip

    def length(t):  # type: ignore[no-untyped-def]
        return mp_length(moved(t), [mp.mpf(s) for s in SIGNED])

    d1 = mp.diff(length, 0)
    d2 = mp.diff(length, 0, 2)
    v = [(np.array([a]), np.array([b])) for a, b in vel]
    a_ = [(np.array([a]), np.array([b])) for a, b in acc]
    assert float(geo.rate(v)[0]) == pytest.approx(float(d1), rel=1e-14)
    assert float((geo.rate(a_) + geo.curvature(v))[0]) == pytest.approx(float(d2), rel=1e-13)
    # the gradient: u_{k−1} − u_k at each path point
    for k in range(len(PATH)):
        for c in (0, 1):

            def one(t, k=k, c=c):  # type: ignore[no-untyped-def]
                pts = [(mp.mpf(x), mp.mpf(y)) for x, y in PATH]
                p = list(pts[k])
                p[c] += t
                pts[k] = (p[0], p[1])
                return mp_length(pts, [mp.mpf(s) for s in SIGNED])

            u = geo.ux if c == 0 else geo.uy
            grad = (u[k - 1][0] if k else 0.0) - (u[k][0] if k < len(u) else 0.0)
            assert float(grad) == pytest.approx(float(mp.diff(one, 0)), rel=1e-13, abs=1e-15)


HOIST = Rope(
    "hoist", ("A", "S", "E"), mode="winch", drum_radius=0.25, gear_ratio=20.0, radii=(0.3,),
    wraps=("cw",),
)  # fmt: skip


def boom(rope: Rope = HOIST, mass: bool = True) -> Model:
    """A boom O–S pivoted at O, its tip sheave S (radius 0.3 m) wrapped by a rope from the mast
    A down to an anchor E: the rope's length sets the boom's angle."""
    return Model(
        "boom over a sheave",
        {"O": (0.0, 0.0), "A": (-1.0, 3.0), "E": (-2.0, 0.5), "S": (1.5, 2.0)},
        (
            Body("ground", ("O", "A", "E"), ground=True),
            Body(
                "boom",
                ("O", "S"),
                mass=120.0 if mass else None,
                inertia=60.0 if mass else None,
                center_of_mass=(0.8, 1.0) if mass else None,
            ),
        ),
        ropes=(rope,),
        gravity=Gravity() if mass else None,
    )


def test_motion_against_8th_order_differences() -> None:
    mech = Mechanism(boom(mass=False))
    assert mech.plan.has_newton
    theta = mech.plan.input_sketch[0] + np.linspace(-60.0, 60.0, 9)
    res = mech.solve({"hoist": theta}, {"hoist": 3.0}, {"hoist": -0.7})
    assert res.status.all_ok
    d1, d2 = fd_derivatives(lambda t: mech.solve({"hoist": theta + t}).positions, 1e-2)
    scale = np.abs(d1).max()
    assert np.abs(res.velocities - 3.0 * d1).max() < 1e-9 * 3.0 * scale
    expected = 9.0 * d2 - 0.7 * d1
    assert np.abs(res.accelerations - expected).max() < 1e-7 * np.abs(expected).max()
    # the rope's length is the winch's payout at every sample
    s = res.positions[:, 3]
    for i in range(len(theta)):
        pts = [(-1.0, 3.0), (float(s[i, 0]), float(s[i, 1])), (-2.0, 0.5)]
        exact = mp_length([(mp.mpf(x), mp.mpf(y)) for x, y in pts], [0, -0.3, 0])
        assert float(exact) == pytest.approx(theta[i] * 0.25 / 20.0, rel=1e-13)


def test_tension_and_sheave_pin_by_hand() -> None:
    """A weight W at the sheave's pin: about O, T·cross(S, u1 − u0) = W·x_S, the directions
    u0 (A to the sheave) and u1 (the sheave to E) by mpmath's tangents; the sheave's pin
    carries T·(u1 − u0), the rope's ends T along their segments."""
    mech = Mechanism(boom(mass=False))
    theta = mech.plan.input_sketch[0] + np.linspace(-40.0, 40.0, 5)
    kin = mech.solve({"hoist": theta})
    load = [PointForce("w", "boom", "S", (0.0, -1000.0))]
    f = mech.forces(kin, load)
    compiled = mech.forces(kin, load, backend="numba")
    np.testing.assert_allclose(compiled.tension("hoist"), f.tension("hoist"), rtol=1e-14)
    t = f.tension("hoist")
    for i in range(len(theta)):
        sx, sy = (mp.mpf(float(c)) for c in kin.positions[i, 3])
        a0 = tangent((mp.mpf(-1), mp.mpf(3)), 0, (sx, sy), mp.mpf(-0.3))
        a1 = tangent((sx, sy), mp.mpf(-0.3), (mp.mpf(-2), mp.mpf(0.5)), 0)
        du = (mp.cos(a1) - mp.cos(a0), mp.sin(a1) - mp.sin(a0))
        hand = 1000 * sx / (sx * du[1] - sy * du[0])
        assert float(t[i]) == pytest.approx(float(hand), rel=1e-12)
        # the sheave's pin passes the resultant of its two segments to the boom
        expected = (float(t[i] * du[0]), float(t[i] * du[1]))
        np.testing.assert_allclose(f.pin("S", "boom")[i], expected, rtol=1e-11, atol=1e-9)
        end = f.pin("A", "ground")[i]
        np.testing.assert_allclose(
            end, (float(t[i] * mp.cos(a0)), float(t[i] * mp.sin(a0))), rtol=1e-11
        )


def test_power_balance_and_slack() -> None:
    mech = Mechanism(boom())
    theta = mech.plan.input_sketch[0] + np.linspace(-80.0, 80.0, 17)
    res = mech.solve({"hoist": theta}, {"hoist": -25.0}, {"hoist": 9.0}, loads="model")
    assert res.ok.all()
    pb = res.power_balance()
    assert np.max(pb.relative) < 1e-9
    # a load lifting the boom towards the mast beyond what gravity holds: the rope would push
    lift = [*mech.loads, PointForce("up", "boom", "S", (0.0, 2500.0))]
    up = mech.solve({"hoist": theta}, loads=lift)
    assert (up.tension("hoist") < 0).all() and not up.ok.any()
    assert set(up.status_labels()) == {"slack rope 'hoist' (it would have to push)"}


def test_sensitivities_against_8th_order_differences() -> None:
    mech = Mechanism(boom())
    # (off the sketch: a sample given exactly at it is taken as held there, moving with it)
    values = {"hoist": mech.plan.input_sketch[0] + np.linspace(-50.0, 50.0, 4)}
    rates = {"hoist": 2.0}
    names = ["A.x", "E.y", "S.x", "S.y", "boom.mass"]
    res = mech.solve(values, rates=rates, sensitivities=names, loads="model")
    table = res.to_frame()
    for name in names:
        step = 3e-4 * (mech.parameters[name] if name.endswith(".mass") else mech.plan.scale)
        tables = []
        for k in range(-4, 5):
            moved = {name: mech.parameters[name] + k * step}
            tables.append(mech.solve(values, rates=rates, params=moved, loads="model").to_frame())
        for col in ("hoist.tension", "hoist.torque", "S.boom.Fx", "O.boom.Fy", "S.x", "S.vy"):
            fd = sum(w * t[col].to_numpy() for w, t in zip(WEIGHTS, tables, strict=True)) / step
            exact = res.sensitivity(col, name)
            floor = 1e-3 * max(np.abs(table[col].to_numpy()).max(), 1e-3) / mech.plan.scale
            scale = max(np.abs(fd).max(), floor)
            assert np.abs(exact - fd).max() / scale < 1e-8, (col, name)


def guyed(e: tuple[float, float]) -> Model:
    """The boom held by a locked rope from the mast A over its tip sheave S to the pin E of a
    crank turning about C: the crank's angle sets the boom's."""
    return Model(
        "boom on a guy",
        {"O": (0.0, 0.0), "A": (-1.0, 3.0), "C": (-2.0, 0.0), "E": e, "S": (1.5, 2.0)},
        (
            Body("ground", ("O", "A", "C"), ground=True),
            Body("boom", ("O", "S")),
            Body("crank", ("C", "E")),
        ),
        rotary=(RotaryDriver("crank", "crank", "C", "ground"),),
        ropes=(Rope("guy", ("A", "S", "E"), radii=(0.3,), wraps=("cw",)),),
    )


def test_locked_rope_over_a_sheave_in_a_family_of_designs() -> None:
    """A locked rope's length is its sketch's: a design that moves the crank's pin gets the
    length its own sketch gives, as a model drawn so."""
    mech = Mechanism(guyed((-2.0, 0.5)))
    q = np.radians([80.0, 90.0, 100.0])
    family = mech.solve({"crank": np.tile(q, 2)}, params={"E.y": np.repeat([0.5, 0.6], 3)})
    assert family.status.all_ok
    for k, ey in enumerate((0.5, 0.6)):
        alone = Mechanism(guyed((-2.0, ey))).solve({"crank": q})
        np.testing.assert_allclose(
            family.positions[3 * k : 3 * k + 3], alone.positions, rtol=0, atol=1e-12
        )
    np.testing.assert_allclose(family.positions[1, 4], (1.5, 2.0), atol=1e-12)


def test_drawn_along_its_tangents_and_arcs() -> None:
    import matplotlib

    matplotlib.use("Agg")
    from excavkin.outputs.drawing import draw_mechanism

    mech = Mechanism(boom(mass=False))
    res = mech.solve({"hoist": mech.plan.input_sketch[0] + np.linspace(-30.0, 30.0, 3)})
    d = draw_mechanism(res, sample=0)
    line, same = d.cylinders["hoist"]
    assert line is same
    d.set_sample(2)
    poly = np.column_stack([line.get_xdata(), line.get_ydata()]) / 1000.0  # drawn in mm
    # from the mast, round the sheave at its radius, down to the anchor
    np.testing.assert_allclose(poly[0], (-1.0, 3.0), atol=1e-12)
    np.testing.assert_allclose(poly[-1], (-2.0, 0.5), atol=1e-12)
    s = res.positions[2, 3]
    np.testing.assert_allclose(np.hypot(*(poly[1:-1] - s).T), 0.3, rtol=1e-12)
    # its drawn length is the rope's, to the arcs' chords
    drawn = np.sum(np.hypot(*np.diff(poly, axis=0).T))
    assert drawn == pytest.approx((mech.plan.input_sketch[0] + 30.0) * 0.25 / 20.0, rel=1e-3)


def test_a_rope_that_would_leave_its_sheave_is_a_failing_sample() -> None:
    """A carriage E on a 45° guide, pulled by a rope from A under a fixed sheave S (r = 0.2 m,
    turning counter-clockwise) up to E. Paid in, E slides down its guide until it reaches the
    line of the rope's tangent from A: there the wrap is zero (by hand, the rope is straight,
    L = |E − A|), and beyond it the rope would leave the sheave: those samples fail."""
    model = Model(
        "carriage on a rope",
        {
            "A": (-3.0, 0.0),
            "S": (0.0, 0.0),
            "G1": (2.0, 0.0),
            "H1": (3.0, 1.0),
            "G2": (2.5, 0.0),
            "H2": (3.5, 1.0),
            "E": (2.7, 0.7),
            "E2": (3.2, 0.7),
        },
        (
            Body("ground", ("A", "S", "G1", "H1", "G2", "H2"), ground=True),
            Body("car", ("E", "E2")),
        ),
        sliders=(Slider("left", "E", ("G1", "H1")), Slider("right", "E2", ("G2", "H2"))),
        ropes=(
            Rope(
                "hoist",
                ("A", "S", "E"),
                mode="winch",
                drum_radius=0.5,
                radii=(0.2,),
                wraps=("ccw",),
            ),
        ),  # fmt: skip
    )
    mech = Mechanism(model)
    slope = -np.tan(np.arcsin(0.2 / 3.0))  # the tangent from A under the sheave
    x = (2.0 + 3.0 * slope) / (1.0 - slope)  # where it meets the guide y = x − 2
    boundary = np.hypot(x + 3.0, x - 2.0) / 0.5  # the motor angle: L = |E − A| / (R/i)
    theta = boundary + np.array([-0.1, -1e-6, 1e-6, 0.1, 1.0])
    res = mech.solve({"hoist": theta})
    labels = list(res.status.labels())
    off = "a rope leaves a sheave (its wrap would be negative) at group E, E2"
    assert labels == [off, off, "ok", "ok", "ok"]
    assert np.isnan(res.positions[:2, 6]).all()
    np.testing.assert_allclose(res.positions[2, 6], (x, x - 2.0), atol=1e-6)


@pytest.mark.parametrize("sheaved", [False, True])
def test_back_substitution_equals_the_pin_equations(sheaved: bool) -> None:
    """The equilibrium along the plan (a one-point Newton group with the rope's constraint)
    against the whole matrix of pin equations, per sample."""
    from excavkin.kinetostatics.solve import solve_forces

    model = boom() if sheaved else boom(Rope("hoist", ("A", "S"), 2, "winch", 0.25, 20.0))
    mech = Mechanism(model)
    theta = mech.plan.input_sketch[0] + np.linspace(-40.0, 40.0, 7)
    kin = mech.solve({"hoist": theta}, {"hoist": 5.0}, {"hoist": -2.0})
    load = [*mech.loads, PointForce("w", "boom", "S", (300.0, -1000.0))]
    along = solve_forces(kin, load)
    whole = solve_forces(kin, load, method="dense")
    scale = np.abs(whole.pin_force).max()
    np.testing.assert_allclose(along.pin_force, whole.pin_force, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(along.tension("hoist"), whole.tension("hoist"), rtol=1e-12)


def test_a_rope_too_short_for_any_pose_is_out_of_reach_by_its_shortfall() -> None:
    """A block on a vertical guide under a rope from A over its sheave to E, 6 m apart: no
    pose makes the rope shorter than 6 m (its tangents straight, no wrap), so a winch paid in
    to 5.95 m leaves the pose 0.05 m out of reach, the rope named."""
    model = Model(
        "block on a rope",
        {
            "A": (-3.0, 0.0),
            "E": (3.0, 0.0),
            "G1": (0.0, -2.0),
            "H1": (0.0, 2.0),
            "G2": (0.5, -2.0),
            "H2": (0.5, 2.0),
            "S": (0.0, 1.0),
            "S2": (0.5, 0.5),
        },
        (
            Body("ground", ("A", "E", "G1", "H1", "G2", "H2"), ground=True),
            Body("block", ("S", "S2")),
        ),
        sliders=(Slider("left", "S", ("G1", "H1")), Slider("right", "S2", ("G2", "H2"))),
        ropes=(
            Rope(
                "hoist", ("A", "S", "E"), mode="winch", drum_radius=0.5, radii=(0.1,), wraps=("cw",)
            ),
        ),  # fmt: skip
    )
    res = Mechanism(model).solve({"hoist": np.array([5.95 / 0.5, 6.5 / 0.5])})
    assert res.status.message(0) == (
        "out of reach at group S, S2: rope 'hoist' A–S–E (driven) is 0.05 m too long"
    )
    assert res.status.labels()[1] == "ok"


def test_sheave_radius_sensitivities_against_8th_order_differences() -> None:
    """The sheave's radius as a design parameter: the motion, the tension, the winch's torque
    and the pins' forces differentiated by it equal 8th-order differences of families of
    designs, which equal each design built as its own model (the next test)."""
    mech = Mechanism(boom())
    assert mech.parameters["hoist.radius.S"] == 0.3
    values = {"hoist": mech.plan.input_sketch[0] + np.linspace(-50.0, 50.0, 4)}
    rates = {"hoist": 2.0}
    name = "hoist.radius.S"
    res = mech.solve(values, rates=rates, sensitivities=[name], loads="model")
    table = res.to_frame()
    step = 1e-3
    tables = []
    for k in range(-4, 5):
        moved = {name: 0.3 + k * step}
        tables.append(mech.solve(values, rates=rates, params=moved, loads="model").to_frame())
    for col in ("hoist.tension", "hoist.torque", "S.boom.Fx", "O.boom.Fy", "S.x", "S.vy"):
        fd = sum(w * t[col].to_numpy() for w, t in zip(WEIGHTS, tables, strict=True)) / step
        exact = res.sensitivity(col, name)
        assert np.abs(fd).max() > 1e-3 * np.abs(table[col].to_numpy()).max()  # it moves
        scale = max(np.abs(fd).max(), 1e-3 * max(np.abs(table[col].to_numpy()).max(), 1e-3))
        assert np.abs(exact - fd).max() / scale < 1e-8, col


@pytest.mark.parametrize("locked", [False, True], ids=["winch", "locked"])
def test_sheave_radii_in_a_family_equal_each_design_as_its_own_model(locked: bool) -> None:
    import dataclasses

    radii = np.array([0.3, 0.25, 0.35])
    if locked:
        mech = Mechanism(guyed((-2.0, 0.5)))
        q = np.radians([80.0, 90.0, 100.0])
        values, rates, name = {"crank": q}, {"crank": 0.4}, "guy.radius.S"
    else:
        mech = Mechanism(boom())
        q = mech.plan.input_sketch[0] + np.array([-30.0, 10.0, 40.0])
        values, rates, name = {"hoist": q}, {"hoist": 2.0}, "hoist.radius.S"
    family = mech.solve(values, rates=rates, params={name: radii}, loads="model").to_frame()
    for k, r in enumerate(radii):
        model = mech.model
        rope = dataclasses.replace(model.ropes[0], radii=(float(r),))
        alone = Mechanism(dataclasses.replace(model, ropes=(rope,)))
        own = alone.solve({n: v[k : k + 1] for n, v in values.items()}, rates=rates,
                          loads="model").to_frame()  # fmt: skip
        for col in own.columns:
            if own[col].dtype.kind == "f" and np.isfinite(own[col].iloc[0]):
                ref = own[col].iloc[0]
                assert abs(family[col].iloc[k] - ref) <= 1e-11 * max(1.0, abs(ref)), col


def test_a_sheave_radius_is_written_back(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from excavkin.io.model_write import model_text_with
    from excavkin.io.toml_model import loads_model

    src = tmp_path / "boom.toml"
    src.write_text(
        'schema_version = 1\nname = "boom"\n[units]\nlength = "m"\n'
        "[points]\nO = [0, 0]\nA = [-1, 3]\nE = [-2, 0.5]\n"
        'S = [1.5, 2]\n[bodies]\nground = { points = ["O", "A", "E"], ground = true }\n'
        'boom = { points = ["O", "S"] }\n[ropes.hoist]\npath = ["A", "S", "E"]\n'
        'radii = ["300 mm"]\nwraps = ["cw"]\nmode = "winch"\ndrum_radius = 0.25\ngear_ratio = 20\n'
    )
    text = model_text_with(src, {"hoist.radius.S": 0.32})
    (rope,) = loads_model(text).ropes
    assert rope.radii == pytest.approx((0.32,), rel=1e-15)
