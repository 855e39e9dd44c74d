"""Honest precision near dead and change positions, against 40-digit arithmetic (mpmath).

Every sample marked ``ok`` must have its positions, velocities and accelerations within 1e-8 of
that quantity's scale over the sweep; samples where double precision cannot give that are
marked "rates lose precision", and the error estimate bounds the actual error.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

import excavkin
from excavkin import Model
from excavkin.kinematics import precision
from excavkin.kinematics.kernels import Code
from excavkin.structure.plan import Dyad, Fixed, Rotate
from tests.models import fourbar_model

TOL = 1e-8
pytestmark = pytest.mark.skipif(precision.WIDE is None, reason="long double is double here")


def _mp_fourbar(plan, theta: float, omega: float = 1.0):  # type: ignore[no-untyped-def]
    """C's position, velocity and acceleration and the rocker's ω, ε, in 40 digits, from the
    plan's own constants (so that the reference solves the same floating-point model)."""
    mp.mp.dps = 40
    fixed = next(s for s in plan.steps if isinstance(s, Fixed))
    rot = next(s for s in plan.steps if isinstance(s, Rotate))
    dy = next(s for s in plan.steps if isinstance(s, Dyad))
    pairs = zip(fixed.points, fixed.coords, strict=True)
    where = {p: tuple(mp.mpf(c) for c in xy) for p, xy in pairs}
    o = where[rot.pivot]
    th, w, r = mp.mpf(float(theta)), mp.mpf(omega), mp.mpf(rot.radius)
    b = (o[0] + r * mp.cos(th), o[1] + r * mp.sin(th))
    vb = (-r * w * mp.sin(th), r * w * mp.cos(th))
    ab = (-r * w * w * mp.cos(th), -r * w * w * mp.sin(th))
    d = where[dy.b]
    d1, d2 = mp.mpf(dy.da.value), mp.mpf(dy.db.value)
    ex, ey = d[0] - b[0], d[1] - b[1]
    l2 = ex * ex + ey * ey
    kk = (d1 * d1 - d2 * d2 + l2) / (2 * l2)
    h2 = d1 * d1 / l2 - kk * kk
    if h2 <= 0:  # does not close here, or exactly flat
        return np.full(8, np.nan), dy.point
    h = dy.sign * mp.sqrt(h2)
    c = (b[0] + kk * ex - h * ey, b[1] + kk * ey + h * ex)
    r1, r2 = (c[0] - b[0], c[1] - b[1]), (c[0] - d[0], c[1] - d[1])
    det = r1[0] * r2[1] - r1[1] * r2[0]

    def solve(f1, f2):  # type: ignore[no-untyped-def]
        return ((f1 * r2[1] - f2 * r1[1]) / det, (r1[0] * f2 - r2[0] * f1) / det)

    vc = solve(r1[0] * vb[0] + r1[1] * vb[1], mp.mpf(0))
    wv = (vc[0] - vb[0], vc[1] - vb[1])
    f1 = r1[0] * ab[0] + r1[1] * ab[1] - (wv[0] ** 2 + wv[1] ** 2)
    ac = solve(f1, -(vc[0] ** 2 + vc[1] ** 2))
    rr = r2[0] ** 2 + r2[1] ** 2
    om = (r2[0] * vc[1] - r2[1] * vc[0]) / rr
    eps = (r2[0] * ac[1] - r2[1] * ac[0]) / rr
    return np.array([*c, *vc, *ac, om, eps], dtype=np.float64), dy.point


#: kind of each reference value: position, velocity, acceleration, ω, ε
_KIND = np.array([0, 0, 1, 1, 2, 2, 3, 4])


def _errors(  # type: ignore[no-untyped-def]
    mech: excavkin.Mechanism,
    thetas: np.ndarray,
    rocker: str,
    closed: excavkin.Mechanism | None = None,
):
    """The engine's result, its error per sample relative to each kind's true scale, and the
    estimate (the reference from the constants of ``closed``'s plan, by default ``mech``'s)."""
    res = mech.solve({"crank": thetas}, rates={"crank": 1.0}, accels={"crank": 0.0})
    plan = (closed or mech).plan
    refs = []
    for t in thetas:
        ref, point = _mp_fourbar(plan, t)
        refs.append(ref)
    ref = np.array(refs)
    p, v, a = res.point(plan.points[point])
    _, om, eps = res.body(rocker)
    ours = np.column_stack([p, v, a, om, eps])
    finite = np.isfinite(ref).all(axis=1)
    top = [np.max(np.abs(ref[finite][:, k == _KIND])) for k in range(5)]
    # the engine's scales: each kind's largest magnitude, floored by ω·L, v²/L and ω²
    # (the mechanism's size L: its largest coordinate)
    length = float(np.max(np.abs(res.positions[res.status.ok])))
    kinds = ("length", "velocity", "acceleration", "angular velocity", "angular acceleration")
    given = dict(zip(kinds, top, strict=True))
    floored = precision.floored({**given, "length": max(top[0], length), "angle": np.pi})
    scale = np.array([floored[k] for k in kinds])
    rel = np.abs(ours - ref) / scale[_KIND]
    return res, rel.max(axis=1), res.error_estimate


def test_mo100_change_point_ok_rows_are_within_1e8_and_the_rest_are_flagged() -> None:
    mech = excavkin.load(excavkin.example_path("mo100_hammer"))
    near = np.array([s * 10.0**-k for k in np.arange(1.0, 7.5, 0.5) for s in (1, -1)])
    thetas = np.concatenate([np.radians(np.arange(-179.5, 180, 1.0)), near])
    res, err, est = _errors(mech, thetas, "rocker")
    ok = res.status.ok
    assert np.all(err[ok] <= TOL), err[ok].max()
    # double precision alone would be off by 0.08–2e5 here; these are flagged, not ok
    flagged = res.status.code == Code.IMPRECISE
    assert not ok[np.abs(thetas) <= 3e-5].any()
    assert flagged[(np.abs(thetas) <= 3e-5) & (np.abs(thetas) >= 1e-6)].all()
    assert "rates lose precision near a dead position at dyad C" in res.status.message(
        int(np.flatnonzero(flagged)[0])
    )
    # the estimate bounds the error wherever it was measured
    checked = ok & np.isfinite(est)
    assert checked.sum() >= 10
    assert np.all(err[checked] <= np.maximum(est[checked], 1e-14))


def _arccos_epsilon(theta: float) -> float:
    """The rocker's ε of the MO-100 by the textbook arccos/atan2 form (Norton), in double."""
    a, b, c, d = 0.048, 0.150, 0.120, 0.078
    w2 = 1.0
    bx, by = a * np.cos(theta), a * np.sin(theta)
    lx, ly = bx - d, by  # from the rocker pivot to the crank pin
    ln = np.hypot(lx, ly)
    th4 = np.arctan2(ly, lx) - np.arccos((c * c + ln * ln - b * b) / (2 * c * ln))
    cx, cy = d + c * np.cos(th4), c * np.sin(th4)
    th3 = np.arctan2(cy - by, cx - bx)
    w4 = a * w2 * np.sin(theta - th3) / (c * np.sin(th4 - th3))
    w3 = a * w2 * np.sin(th4 - theta) / (b * np.sin(th3 - th4))
    aa, bb = c * np.sin(th4), b * np.sin(th3)
    cc = a * w2 * w2 * np.cos(theta) + b * w3 * w3 * np.cos(th3) - c * w4 * w4 * np.cos(th4)
    dd, ee = c * np.cos(th4), b * np.cos(th3)
    ff = -a * w2 * w2 * np.sin(theta) - b * w3 * w3 * np.sin(th3) + c * w4 * w4 * np.sin(th4)
    return float((cc * ee - bb * ff) / (aa * ee - bb * dd))


def test_flagged_zone_is_narrower_than_the_arccos_forms() -> None:
    mech = excavkin.load(excavkin.example_path("mo100_hammer"))
    near = 10.0 ** np.arange(-7.0, -1.0, 0.25)
    thetas = np.concatenate([np.radians(np.arange(-179.5, 180, 1.0)), near])
    res, err, _ = _errors(mech, thetas, "rocker")
    plan = res.plan
    eps_scale = max(abs(_mp_fourbar(plan, t)[0][7]) for t in thetas)
    arccos_bad = []
    for t in near:
        true = _mp_fourbar(plan, t)[0][7]
        arccos_bad.append(abs(_arccos_epsilon(t) - true) > TOL * eps_scale)
    ours_bad = ~res.status.ok[-near.size :]
    # the arccos form is right about its own geometry (far from the change point)
    assert abs(_arccos_epsilon(0.5) - _mp_fourbar(plan, 0.5)[0][7]) < 1e-12 * eps_scale
    assert np.all(np.asarray(arccos_bad)[ours_bad])  # we flag only where arccos fails too
    assert np.sum(arccos_bad) > np.sum(ours_bad)  # and strictly fewer samples


def _fourbar(r: float, g: float, b: float, c: float, theta: float, side: float) -> Model:
    """A crank-rocker sketch: ground O2→O4 along x, crank r at ``theta``, coupler b, rocker c,
    the coupler–rocker joint on ``side`` of the diagonal."""
    ax, ay = r * np.cos(theta), r * np.sin(theta)
    ex, ey = g - ax, -ay
    l2 = ex * ex + ey * ey
    kk = (b * b - c * c + l2) / (2 * l2)
    h = side * np.sqrt(b * b / l2 - kk * kk)
    bx, by = ax + kk * ex - h * ey, ay + kk * ey + h * ex
    return fourbar_model({"O2": (0.0, 0.0), "A": (ax, ay), "B": (bx, by), "O4": (g, 0.0)})


@pytest.mark.parametrize("seed", range(8))
def test_random_change_points_and_dead_positions(seed: int) -> None:
    """Random four-bars sampled ever nearer a change point (r + b = g + c, at θ = 0) or a dead
    position of the crank (the dyad stretched flat): ok rows within 1e-8, estimates bound the
    errors, and the samples nearest are flagged or exact."""
    rng = np.random.default_rng(seed)
    g = 1.0
    r = rng.uniform(0.1, 0.4)
    if seed % 2 == 0:  # change point: A, B, O4 collinear with the rocker folded back at θ = 0
        b = rng.uniform(1.0, 1.6)
        c = r + b - g
        centre = 0.0
    else:  # dead position: |A − O4| reaches b + c before the crank turns round
        b, c = rng.uniform(0.3, 0.6, size=2)
        big = b + c
        centre = float(np.arccos((r * r + g * g - big * big) / (2 * r * g)))
        centre = -centre  # approached from θ = 0 downwards... either side of 0 works
    deltas = 10.0 ** np.arange(-1.0, -8.0, -0.5)
    side = 1.0 if seed % 4 < 2 else -1.0
    if seed % 2 == 0:
        thetas = np.concatenate([deltas, -deltas, np.linspace(-3.0, 3.0, 61)])
        model = _fourbar(r, g, b, c, 1.0, side)
    else:
        thetas = np.concatenate([centre + deltas, np.linspace(centre + 0.2, -centre - 0.2, 41)])
        model = _fourbar(r, g, b, c, 0.0, side)
    mech = excavkin.Mechanism(model)
    res, err, est = _errors(mech, thetas, "rocker")
    ok = res.status.ok
    assert ok.sum() > 40
    assert np.all(err[ok] <= TOL), (err[ok].max(), thetas[ok][np.argmax(err[ok])])
    checked = ok & np.isfinite(est)
    assert checked.any()
    assert np.all(err[checked] <= np.maximum(est[checked], 1e-14))


@pytest.mark.parametrize("seed", [1, 3, 5, 7])
def test_newton_groups_near_dead_positions(seed: int) -> None:
    """The generic solver on the random four-bars driven ever nearer a dead position: its
    Jacobian's nearness to singular sends the samples to the extended-precision solve (the
    batched LU in long double), whose rows marked ok are within 1e-8 and whose estimates bound
    the errors, as the closed form's are."""
    rng = np.random.default_rng(seed)
    g, r = 1.0, rng.uniform(0.1, 0.4)
    b, c = rng.uniform(0.3, 0.6, size=2)
    centre = -float(np.arccos((r * r + g * g - (b + c) ** 2) / (2 * r * g)))
    deltas = 10.0 ** np.arange(-1.0, -8.0, -0.5)
    thetas = np.concatenate([centre + deltas, np.linspace(centre + 0.2, -centre - 0.2, 41)])
    model = _fourbar(r, g, b, c, 0.0, 1.0 if seed % 4 < 2 else -1.0)
    closed = excavkin.Mechanism(model)
    res, err, est = _errors(excavkin.Mechanism(model, method="newton"), thetas, "rocker", closed)
    ok = res.status.ok
    assert ok.sum() > 40
    assert np.all(err[ok] <= TOL), (err[ok].max(), thetas[ok][np.argmax(err[ok])])
    checked = ok & np.isfinite(est)
    assert checked.sum() >= 5  # the samples nearest the dead position were checked
    assert np.all(err[checked] <= np.maximum(est[checked], 1e-14))
