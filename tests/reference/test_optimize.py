"""Optimisation against known optima: Freudenstein's three-precision-point function generator
(closed form), and the best least transmission angle of a crank-rocker against a brute-force
grid."""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from excavkin.errors import InputError
from excavkin.studies.design_space import sample_designs
from excavkin.studies.metrics import Constraint, Metric, Poses, evaluate
from excavkin.studies.optimize import optimize

D = 0.1  # ground link, m


def freudenstein() -> tuple[np.ndarray, np.ndarray, tuple[float, float, float]]:
    """y = log10(x) on [1, 2] with θ over 60°–120° and φ over 100°–160°, at the three
    Chebyshev precision points: the input and output angles, and the crank, coupler and rocker
    lengths from Freudenstein's equation K₁cos φ − K₂cos θ + K₃ = cos(θ − φ)."""
    x = 1.5 - 0.5 * np.cos((2 * np.arange(1, 4) - 1) * np.pi / 6)
    th = np.radians(60 + 60 * (x - 1))
    ph = np.radians(100 + 60 * np.log10(x) / np.log10(2))
    m = np.c_[np.cos(ph), -np.cos(th), np.ones(3)]
    k = np.linalg.solve(m, np.cos(th - ph))
    a, c = D / k[0], D / k[1]
    b = np.sqrt(a * a + c * c + D * D - 2 * a * c * k[2])
    return th, ph, (a, b, c)


def generator(a: float, b: float, c: float, th: float, ph: float) -> excavkin.Mechanism:
    """A four-bar sketched at the first precision point (so on the solution's branch), its
    lengths given by [lengths] entries (the parameters)."""
    from tests.models import fourbar_model

    pts = {
        "O2": (0.0, 0.0),
        "A": (a * np.cos(th), a * np.sin(th)),
        "B": (D + c * np.cos(ph), c * np.sin(ph)),
        "O4": (D, 0.0),
    }
    lengths = {("O2", "A"): a, ("A", "B"): b, ("O4", "B"): c}
    return excavkin.Mechanism(fourbar_model(pts, "function generator", lengths))


def test_the_closed_form_is_a_function_generator() -> None:
    th, ph, (a, b, c) = freudenstein()
    mech = generator(a, b, c, th[0], ph[0])
    res = mech.solve({"crank": th})
    np.testing.assert_allclose(res.column("rocker.angle"), ph, rtol=0, atol=1e-14)


def test_freudensteins_generator_is_found_to_1e8() -> None:
    th, ph, exact = freudenstein()
    a, b, c = exact
    # start 15 % off: the sketch keeps the branch, the lengths are the unknowns
    mech = generator(1.15 * a, 0.85 * b, 1.1 * c, th[0], ph[0])
    bounds = {"O2-A": (0.5 * a, 1.5 * a), "A-B": (0.5 * b, 1.5 * b), "O4-B": (0.5 * c, 1.5 * c)}
    target = Metric("error", "rocker.angle", "sumsq", target=tuple(ph))
    best = optimize(mech, bounds, Poses({"crank": th}, {}, {}), target, "min", maxiter=500)
    found = np.array([best.params["O2-A"], best.params["A-B"], best.params["O4-B"]])
    np.testing.assert_allclose(found, exact, rtol=1e-8)
    assert best.value < 1e-28 and best.feasible
    assert len(best.history) >= 2 and best.history[-1] <= best.history[0]


def test_differential_evolution_finds_it_too() -> None:
    th, ph, exact = freudenstein()
    a, b, c = exact
    mech = generator(a, b, c, th[0], ph[0])
    bounds = {"O2-A": (0.8 * a, 1.2 * a), "A-B": (0.8 * b, 1.2 * b), "O4-B": (0.8 * c, 1.2 * c)}
    target = Metric("error", "rocker.angle", "sumsq", target=tuple(ph))
    best = optimize(
        mech, bounds, Poses({"crank": th}, {}, {}), target, "min",
        method="differential-evolution", maxiter=60, popsize=12, seed=2,
    )  # fmt: skip
    found = np.array([best.params["O2-A"], best.params["A-B"], best.params["O4-B"]])
    np.testing.assert_allclose(found, exact, rtol=1e-8)


def test_the_best_least_transmission_angle_beats_a_brute_force_grid() -> None:
    """Maximise the least transmission angle of the crank-rocker over a turn by its coupler and
    rocker (epigraph form, exact gradients); a 61 × 61 grid of the same box never does
    better, and its best is within a grid step of the optimum."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    bounds = {"A-B": (0.10, 0.14), "O4-B": (0.07, 0.11)}
    poses = Poses({"crank": np.linspace(0.0, 2 * np.pi, 181)}, {}, {})
    gamma = Metric("gamma_min", "B.transmission", "min")
    best = optimize(mech, bounds, poses, gamma, "max")
    grid = sample_designs(bounds, 61, "grid")
    table = evaluate(mech, grid, poses, [gamma])
    ok = table["poses_failed"] == 0
    brute = table["gamma_min"][ok].max()
    assert best.value >= brute - 1e-9
    i = int(table["gamma_min"][ok].idxmax())
    step = np.array([(hi - lo) / 60 for lo, hi in bounds.values()])
    near = np.abs(np.array([grid[k][i] for k in bounds]) - np.array(list(best.params.values())))
    assert (near <= 1.5 * step).all()
    assert best.value - brute < 2e-3  # a grid step's worth of angle


def test_a_constraint_binds_and_is_named() -> None:
    """Maximise the least transmission angle with the rocker's greatest angle held 0.05 rad
    below where the free optimum has it: the constraint is active at the optimum, met to
    round-off, and the optimum is lower."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    bounds = {"A-B": (0.10, 0.14), "O4-B": (0.07, 0.11)}
    poses = Poses({"crank": np.linspace(0.0, 2 * np.pi, 181)}, {}, {})
    gamma = Metric("gamma_min", "B.transmission", "min")
    swing_hi = Metric("rocker_max", "rocker.angle", "max")
    free = optimize(mech, bounds, poses, gamma, "max", metrics=[swing_hi])
    limit = free.metrics["rocker_max"] - 0.05
    held = optimize(
        mech, bounds, poses, gamma, "max",
        metrics=[swing_hi], constraints=[Constraint("rocker_max", high=limit)],
    )  # fmt: skip
    assert held.feasible and "rocker_max" in held.active
    assert held.metrics["rocker_max"] <= limit + 1e-9
    assert held.value < free.value


def test_a_local_method_refuses_a_constraint_it_cannot_write_exactly() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    poses = Poses({"crank": np.linspace(0.0, 2 * np.pi, 13)}, {}, {})
    gamma = Metric("gamma_min", "B.transmission", "min")
    with pytest.raises(InputError, match="differential-evolution"):
        optimize(
            mech, {"A-B": (0.1, 0.14)}, poses, gamma, "max",
            constraints=[Constraint("gamma_min", high=1.0)],
        )  # fmt: skip


# ---- the classical transmission-angle problem


def dead_centre_family(lam: object, psi: object, phi: object) -> tuple[object, object, object]:
    """Crank, coupler and rocker (ground 1) of the crank-rocker whose rocker swings ψ while the
    crank turns φ, with coupler/crank = λ: the loop equations at the two dead centres,
    (1 + λ)Z₁ − Z₂ = 1 and e^{iφ}(1 − λ)Z₁ − e^{iψ}Z₂ = 1, Z₁ the crank and Z₂ the rocker at
    the extended dead centre — solved in mpmath."""
    import mpmath as mp

    a11, a12 = 1 + lam, -1  # type: ignore[operator]
    a21, a22 = mp.exp(1j * phi) * (1 - lam), -mp.exp(1j * psi)  # type: ignore[operator]
    det = a11 * a22 - a12 * a21
    z1, z2 = (a22 - a12) / det, (a11 - a21) / det
    return abs(z1), lam * abs(z1), abs(z2)  # type: ignore[operator]


def test_the_classical_transmission_angle_optimum_is_found_to_1e8() -> None:
    """Swing 45° while the crank turns 210°: the one-parameter family of such crank-rockers is
    searched in 40-digit arithmetic for the least deviation of the transmission angle from
    90° (the crank at 0° and 180° gives its extremes); the optimiser, over all three lengths
    with the swing and the turn as equality constraints, finds the same design."""
    import mpmath as mp

    from excavkin.studies.study_file import load_optimization

    mp.mp.dps = 40
    psi, phi = mp.radians(45), mp.radians(210)

    def deviation(lam: object) -> object:
        a2, a3, a4 = dead_centre_family(lam, psi, phi)
        cos_lo = (a3**2 + a4**2 - (1 - a2) ** 2) / (2 * a3 * a4)  # type: ignore[operator]
        cos_hi = (a3**2 + a4**2 - (1 + a2) ** 2) / (2 * a3 * a4)  # type: ignore[operator]
        return max(abs(mp.acos(cos_lo) - mp.pi / 2), abs(mp.acos(cos_hi) - mp.pi / 2))

    lam = mp.findroot(lambda x: mp.diff(deviation, x), 2.2)
    exact = [float(v) for v in dead_centre_family(lam, psi, phi)]
    # an interior optimum of the family, not an end of it
    assert deviation(lam) < deviation(lam - mp.mpf("1e-3"))
    assert deviation(lam) < deviation(lam + mp.mpf("1e-3"))

    study, settings = load_optimization(excavkin.example_path("crank_rocker_transmission"))
    by_name = {m.name: m for m in study.metrics}
    mech = excavkin.load(study.model)
    best = optimize(
        mech, study.bounds, study.poses, by_name[settings["objective"]], settings["sense"],
        metrics=study.metrics, constraints=study.constraints, x0={"crank": 0.3, "coupler": 1.0},
    )  # fmt: skip
    got = [best.params[k] for k in ("crank", "coupler", "rocker")]
    np.testing.assert_allclose(got, exact, rtol=1e-8)
    assert best.value == pytest.approx(float(deviation(lam)), rel=1e-9)
    assert best.feasible and set(best.active) == {"swing", "crank_turn"}
    assert best.metrics["swing"] == pytest.approx(np.radians(45), abs=1e-10)
    assert best.metrics["crank_turn"] == pytest.approx(np.radians(30), abs=1e-10)


def test_change_and_a_deviation_from_a_target_are_their_definitions() -> None:
    """`change` is the last pose's value less the first's; `absmax` with a target the largest
    distance from it — each against the column itself, per design."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    crank = np.radians(np.linspace(20, 140, 7))
    poses = Poses({"crank": crank}, {}, {})
    designs = {"A-B": np.array([0.115, 0.12, 0.125])}
    metrics = [
        Metric("turn", "rocker.angle", "change"),
        Metric("off", "B.transmission", "absmax", (np.pi / 2,)),
    ]
    table = evaluate(mech, designs, poses, metrics)
    for i, ab in enumerate(designs["A-B"]):
        res = mech.solve({"crank": crank}, params={"A-B": ab})
        phi4, mu = res.column("rocker.angle"), res.column("B.transmission")
        # an angle: followed along the poses (here no ±180° on the way: the plain difference)
        assert table["turn"][i] == pytest.approx(phi4[-1] - phi4[0], abs=1e-14)
        assert table["off"][i] == np.max(np.abs(mu - np.pi / 2))
