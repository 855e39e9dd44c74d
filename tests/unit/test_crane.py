"""The crane wing on the general engine: poses by radius against the booms in closed form
written here, the load chart against a whole-machine equilibrium and a virtual-work balance
written here, each limit binding in a case built so, the support reactions, the machine file
and the command line."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

import excavkin
from excavkin.cli import main
from excavkin.crane.chart import load_chart
from excavkin.crane.machine import StabilityFactors
from excavkin.crane.machine_file import load_machine, loads_machine
from excavkin.crane.reach import reach
from excavkin.crane.supports import support_reactions
from excavkin.errors import InputError, ModelError

KNUCKLE, TELESCOPIC = "knuckle_crane_machine", "telescopic_crane_machine"
SYNCHRONISED = "synchronised_crane_machine"
CRANES = (KNUCKLE, TELESCOPIC, SYNCHRONISED)
TEXT = {n: excavkin.example_path(n).read_text(encoding="utf-8") for n in CRANES}
#: how far each section of a telescopic boom slides per metre of the telescoping cylinder: the
#: synchronising rope, anchored on the base section and run over a sheave at the first fly's
#: head to the second fly, draws the second out of the first by as much as the first moves
SLIDES = {TELESCOPIC: {"fly": 1.0}, SYNCHRONISED: {"fly1": 1.0, "fly2": 2.0}}
PADS = 'kind = "outriggers"\npads = [[2000, 2300], [2000, -2300], [-4000, 2300], [-4000, -2300]]'
PADS_T = 'kind = "outriggers"\npads = [[2600, 2900], [2600, -2900], [-3600, 2900], [-3600, -2900]]'
CRAWLERS = 'kind = "crawlers"\ngauge = 2000\nlength = 2600\nshoe_width = 500\ncentre = -1000'


@pytest.fixture(scope="module")
def knuckle():
    return load_machine(KNUCKLE)


@pytest.fixture(scope="module")
def telescopic():
    return load_machine(TELESCOPIC)


def variant(name: str, *pairs: str):
    text = TEXT[name]
    for old, new in zip(pairs[::2], pairs[1::2], strict=True):
        assert old in text, old
        text = text.replace(old, new)
    return loads_machine(text, str(excavkin.example_path(name).parent / "variant.toml"))


# ------------------------------------------------------------------ independent references
class ClosedForm:
    """The crane's booms by plain trigonometry from the model's sketch (points as complex
    numbers): the boom turns about its pin by θ; the jib turns about the knuckle pin by the
    knuckle angle q, or each section of a telescopic boom slides along the boom's axis by its
    share of q (`SLIDES`) from the sketch."""

    def __init__(self, crane, slides=None) -> None:
        m = crane.mechanism
        self.crane = crane
        sk = m.assembly.positions
        self.p = {n: complex(*sk[m.plan.points.index(n)]) for n in m.plan.points}
        lk = crane.linkage
        self.a = self.p[crane.boom_pin]
        self.theta0 = np.angle(self.p[crane.knuckle_pin or lk.tip] - self.a)
        bodies = {b.name: b for b in m.model.bodies}
        self.boom, self.jib = bodies[lk.boom], bodies[lk.jib]
        self.slides = {bodies[b]: f for b, f in (slides or {lk.jib: 1.0}).items()}
        drivers = {d.name: d for d in m.model.linear}
        self.ends = [drivers[c.driver].between for c in crane.cylinders]
        self.s0 = abs(self.p[self.ends[1][1]] - self.p[self.ends[1][0]])
        if crane.knuckle_pin:
            self.phi0 = np.angle(self.p[lk.tip] - self.p[crane.knuckle_pin]) - self.theta0

    def _on_boom(self, z, theta):
        return self.a + np.exp(1j * (theta - self.theta0)) * (z - self.a)

    def _on(self, body, z, theta, q):
        if self.crane.knuckle_pin:
            k = self.p[self.crane.knuckle_pin]
            turn = np.exp(1j * (theta + q - self.theta0 - self.phi0))
            return self._on_boom(k, theta) + turn * (z - k)
        return self._on_boom(z, theta) + self.slides[body] * q * np.exp(1j * theta)

    def points(self, theta, q):
        """Every point at boom angle θ and jib coordinate q."""
        out = dict(self.p)
        for n in self.boom.points:
            out[n] = self._on_boom(self.p[n], theta)
        for b in self.slides:
            for n in b.points:
                out[n] = self._on(b, self.p[n], theta, q)
        return out

    def centres(self, theta, q):
        """(mass, centre of mass) of the boom and every section beyond it."""
        out = [(self.boom.mass, self._on_boom(complex(*self.boom.center_of_mass), theta))]
        for b in self.slides:
            out.append((b.mass, self._on(b, complex(*b.center_of_mass), theta, q)))
        return out

    def lengths(self, theta, q):
        pts = self.points(theta, q)
        return np.array([abs(pts[b] - pts[a]) for a, b in self.ends])

    def invert(self, luff, second):
        """θ and q at two cylinder lengths, by bisection on the closed form (each length
        rises with its coordinate)."""

        def bisect(f, target, lo, hi):
            for _ in range(200):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if f(mid) < target else (lo, mid)
            return 0.5 * (lo + hi)

        if self.crane.knuckle_pin:
            q = bisect(lambda x: self.lengths(0.0, x)[1], second, -math.pi, 0.3)
        else:
            q = second - self.s0
        return bisect(lambda t: self.lengths(t, q)[0], luff, -0.6, 1.6), q

    def tip(self, theta, q):
        return self.points(theta, q)[self.crane.linkage.tip]


@functools.cache
def _built_in_of_model() -> dict[str, str]:
    return {load_machine(n).mechanism.name: n for n in CRANES}


def reference(crane) -> ClosedForm:
    """The closed form of a built-in crane, or of a variant of one (by its model's name)."""
    return ClosedForm(crane, SLIDES.get(_built_in_of_model()[crane.mechanism.name]))


def cylinder_forces_by_virtual_work(ref: ClosedForm, theta, q, load):
    """Both cylinders' push forces (N) under the booms' weight and a hook load (kg), by
    virtual work over the closed form: Σ_c F_c·∂s_c/∂x = ∂PE/∂x − T·u·∂tip/∂x for x = θ, q
    (T = W/parts along the lead line u), derivatives by central differences of order 8."""
    crane = ref.crane
    g = crane.gravity
    tension = load * g / crane.hoist.parts
    u = 0j
    if crane.linkage.lead is not None:
        pts = ref.points(theta, q)
        u = pts[crane.linkage.lead] - pts[crane.linkage.tip]
        u /= abs(u)

    def state(t, x):
        pe = g * sum(m * z.imag for m, z in ref.centres(t, x)) + load * g * ref.tip(t, x).imag
        return pe, ref.tip(t, x), ref.lengths(t, x)

    w8 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
    h = 1e-3
    jac, grad = np.zeros((2, 2)), np.zeros(2)
    for col, (dt, dx) in enumerate(((h, 0.0), (0.0, h))):
        vals = [state(theta + k * dt, q + k * dx) for k in range(-4, 5)]
        dpe = sum(w * v[0] for w, v in zip(w8, vals, strict=True)) / h
        dtip = sum(w * v[1] for w, v in zip(w8, vals, strict=True)) / h
        jac[:, col] = sum(w * v[2] for w, v in zip(w8, vals, strict=True)) / h
        grad[col] = dpe - tension * (u.real * dtip.real + u.imag * dtip.imag)
    return np.linalg.solve(jac.T, grad)


def contact_hull(crane):
    """The contacts' convex hull, counter-clockwise (a hand-rolled gift wrap)."""
    pts = [tuple(p) for c in crane.support.contacts for p in ((c.x + du, v) for du, v in c.points)]
    start = min(pts)
    hull, cur = [], start
    while True:
        hull.append(cur)
        nxt = pts[0] if pts[0] != cur else pts[1]
        for p in pts:
            cross = (nxt[0] - cur[0]) * (p[1] - cur[1]) - (nxt[1] - cur[1]) * (p[0] - cur[0])
            if cross < 0 or (cross == 0 and math.dist(p, cur) > math.dist(nxt, cur)):
                nxt = p
        cur = nxt
        if cur == start:
            return hull


def whole_crane_moments(ref: ClosedForm, theta, q, load, alpha):
    """Each support edge's restoring moment (N·m; < 0 tips) of the whole crane and a hook
    load (kg): every weight's moment about every edge of the contacts' hull, written out."""
    crane = ref.crane
    d = np.array([math.cos(alpha), math.sin(alpha)])
    weights = [(m.mass, m.x * d) for m in crane.support.turning]
    weights += [(m, z.real * d) for m, z in ref.centres(theta, q)]
    weights += [(load, ref.tip(theta, q).real * d)]
    weights += [(m.mass, np.array([m.x, 0.0])) for m in crane.support.fixed]
    hull = contact_hull(crane)
    out = []
    for a, b in zip(hull, hull[1:] + hull[:1], strict=True):
        a, b = np.array(a), np.array(b)
        t = (b - a) / np.linalg.norm(b - a)
        inward = np.array([-t[1], t[0]])
        out.append(sum(crane.gravity * m * float(inward @ (p - a)) for m, p in weights))
    return np.array(out)


def booms_moments(ref: ClosedForm, theta, q, alpha):
    """The booms' own restoring moment about each edge of the contacts' hull (N·m; < 0
    overturns), the edges in the order of `whole_crane_moments`."""
    crane = ref.crane
    d = np.array([math.cos(alpha), math.sin(alpha)])
    hull = contact_hull(crane)
    out = []
    for a, b in zip(hull, hull[1:] + hull[:1], strict=True):
        a, b = np.array(a), np.array(b)
        t = (b - a) / np.linalg.norm(b - a)
        inward = np.array([-t[1], t[0]])
        out.append(
            sum(
                crane.gravity * m * float(inward @ (z.real * d - a))
                for m, z in ref.centres(theta, q)
            )
        )
    return np.array(out)


def factored_moments(ref, theta, q, load, alpha, gp, gf):
    """Each edge's restoring moment (N·m; < 0 tips) under the factored loads: the whole crane
    with gp × the hook load (kg) at the tip and gf × the booms' weight reduced to the tip,
    which about an edge is the weight F at the tip whose moment is the booms' own overturning
    moment about it (F·arm = max(−booms' restoring moment, 0))."""
    added = gf * np.maximum(-booms_moments(ref, theta, q, alpha), 0.0)
    return whole_crane_moments(ref, theta, q, gp * load, alpha) - added


def factored_load_direct(ref, theta, q, alpha, gp, gf):
    """The largest hook load (kg) at which no restoring moment of `factored_moments` is < 0
    (affine in it)."""
    m0 = factored_moments(ref, theta, q, 0.0, alpha, gp, gf)
    m1 = factored_moments(ref, theta, q, 1.0, alpha, gp, gf) - m0
    with np.errstate(divide="ignore"):
        w = np.where(m1 < 0, -m0 / m1, np.inf)
    return 0.0 if (m0 < 0).any() else float(w.min())


def tipping_load_direct(ref, theta, q, alpha):
    """The hook load (kg) at which the least restoring moment reaches 0 (affine in it)."""
    m0 = whole_crane_moments(ref, theta, q, 0.0, alpha)
    m1 = whole_crane_moments(ref, theta, q, 1.0, alpha) - m0
    with np.errstate(divide="ignore"):
        w = np.where(m1 < 0, -m0 / m1, np.inf)
    return 0.0 if (m0 < 0).any() else float(w.min())


# ------------------------------------------------------------------------------ geometry
@pytest.mark.parametrize("name", CRANES)
def test_a_pose_by_radius_puts_the_closed_form_tip_at_that_radius(name) -> None:
    crane = load_machine(name)
    ref = reference(crane)
    assert all(c.mass == 0.0 for c in crane.cylinders)  # the references below count no cylinder
    second = np.linspace(crane.second.retracted, crane.second.extended, 4)
    radius = np.linspace(1.0, 20.0, 39)
    rr, ss = np.meshgrid(radius, second, indexing="ij")
    pose = crane.pose(rr.ravel(), ss.ravel())
    assert 20 < pose.reached.sum() < rr.size
    tips = crane.tip(pose.kinematics)
    for k in np.nonzero(pose.reached)[0]:
        luff, sec = pose.lengths[k]
        assert crane.cylinders[0].retracted - 1e-12 <= luff <= crane.cylinders[0].extended + 1e-12
        theta, q = ref.invert(luff, sec)
        tip = ref.tip(theta, q)
        assert abs(tip.real - rr.ravel()[k]) < 1e-9
        assert abs(tips[k, 0] - rr.ravel()[k]) < 1e-11
        assert abs(tip.imag - tips[k, 1]) < 1e-9
    # out of reach: no luffing length of the stroke puts the tip there (a dense sweep)
    lu = np.linspace(crane.cylinders[0].retracted, crane.cylinders[0].extended, 2001)
    for k in np.nonzero(~pose.reached)[0]:
        x = crane.tip(crane.solve(np.column_stack([lu, np.full_like(lu, ss.ravel()[k])])))[:, 0]
        assert not (x.min() <= rr.ravel()[k] <= x.max())
        assert np.isnan(pose.lengths[k, 0])


def test_of_two_luffing_lengths_at_a_radius_the_raised_one(knuckle) -> None:
    # knuckle straight: the tip passes each radius twice over the stroke only below the pin's
    # reach; the pose taken is the one with the higher tip
    s = knuckle.second.extended
    lu = np.linspace(knuckle.cylinders[0].retracted, knuckle.cylinders[0].extended, 4001)
    tip = knuckle.tip(knuckle.solve(np.column_stack([lu, np.full_like(lu, s)])))
    for r in (3.0, 6.0, 8.0):
        pose = knuckle.pose(r, s)
        near = np.abs(tip[:, 0] - r) < 1e-2
        assert pose.reached[0] and near.any()
        assert knuckle.tip(pose.kinematics)[0, 1] >= tip[near, 1].max() - 0.05


# ------------------------------------------------------------------------------ the chart
@pytest.fixture(scope="module", params=CRANES)
def charted(request):
    crane = load_machine(request.param)
    radius = np.arange(2.0, 20.01, 1.5)
    return crane, load_chart(crane, radius, None, 4)


def test_every_cell_is_the_least_of_its_limits_with_that_limit_named(charted) -> None:
    crane, chart = charted
    reach_ = ~np.isnan(chart.capacity)
    assert reach_.sum() > 20
    assert_allclose(chart.capacity[reach_], np.min(chart.limits, axis=0)[reach_], rtol=0)
    assert set(chart.binding[~reach_].ravel()) == {"out of reach"}
    for i, j, k in zip(*np.nonzero(reach_), strict=True):
        b = chart.binding[i, j, k].split(",")[0].split(" (")[0]
        assert chart.limits[chart.limit_names.index(b), i, j, k] == chart.capacity[i, j, k]
    assert chart.limit_names[1] == f"{crane.second.role} cylinder"


def test_stability_cells_against_a_whole_machine_moment_balance_in_every_sector(charted) -> None:
    crane, chart = charted
    ref = reference(crane)
    assert chart.share == 0.85  # on outriggers (ASME B30.5 5-1.1.1, Table 1)
    checked = 0
    for i, j in zip(*np.nonzero(~np.isnan(chart.capacity[..., 0])), strict=True):
        pose = crane.pose(chart.radius[i], chart.second[j])
        theta, q = ref.invert(*pose.lengths[0])
        for k, sec in enumerate(chart.sectors):
            grid = np.linspace(sec.start, sec.end, 181)
            dense = min(tipping_load_direct(ref, theta, q, a) for a in grid)
            at = tipping_load_direct(ref, theta, q, chart.slew[i, j, k])
            stab = chart.limits[3, i, j, k]
            if np.isinf(at):  # the hook over a tipping line: no load tips it (round-off aside)
                assert stab > 1e12
            else:
                assert stab == pytest.approx(0.85 * at, rel=1e-9)
                assert stab <= 0.85 * dense * (1 + 1e-9)  # nowhere in the sector less stable
            checked += 1
            if chart.binding[i, j, k].startswith("stability"):
                # at the capacity over 0.85 the least restoring moment is zero
                m = whole_crane_moments(
                    ref, theta, q, chart.capacity[i, j, k] / 0.85, chart.slew[i, j, k]
                )
                assert abs(m.min()) <= 1e-9 * np.abs(m).max()
    assert checked >= 4 * 9


def test_cylinder_cells_against_virtual_work(charted) -> None:
    crane, chart = charted
    ref = reference(crane)
    seen = 0
    for i, j in zip(*np.nonzero(~np.isnan(chart.capacity[..., 0])), strict=True):
        pose = crane.pose(chart.radius[i], chart.second[j])
        theta, q = ref.invert(*pose.lengths[0])
        f0 = cylinder_forces_by_virtual_work(ref, theta, q, 0.0)
        f1 = cylinder_forces_by_virtual_work(ref, theta, q, 1.0) - f0
        for c, cyl in enumerate(crane.cylinders):
            relief = crane.circuits[cyl.circuit].relief
            pull, push = cyl.force_limits(relief)
            w = chart.limits[c, i, j, 0] * crane.gravity  # N
            if w > 0 and np.isfinite(w):  # at its limit the cylinder is at relief
                f = f0[c] + w * f1[c] / crane.gravity
                assert min(abs(f - push), abs(f - pull)) <= 1e-8 * push
                seen += 1
    assert seen >= 10


def test_the_slew_does_not_change_the_hydraulic_and_hoist_limits(charted) -> None:
    crane, chart = charted
    for lim in range(3):
        a = chart.limits[lim]
        assert_allclose(a, np.broadcast_to(a[..., :1], a.shape), rtol=0, equal_nan=True)
    hoist = chart.limits[2][~np.isnan(chart.limits[2])]
    assert_allclose(hoist, crane.hoist.line_pull * crane.hoist.parts / crane.gravity, rtol=1e-14)


def test_each_limit_binds_in_a_case_built_so(knuckle, telescopic) -> None:
    def cell(c, r, second, sector=0):
        ch = load_chart(c, np.array([r]), np.array([second]), 4)
        return ch.binding[0, 0, sector], ch.capacity[0, 0, sector], ch

    ks = knuckle.second.extended
    assert cell(knuckle, 3.0, ks)[0] == "hoist"
    assert cell(knuckle, 7.0, ks)[0] == "knuckle cylinder"
    small = variant(KNUCKLE, "bore = 200", "bore = 130")
    assert cell(small, 4.0, ks)[0] == "luffing cylinder"
    ts = telescopic.second.extended
    assert cell(telescopic, 6.0, ts)[0] == "hoist"
    assert cell(telescopic, 12.0, ts, 1)[0] == "stability (85 % of tipping), left side (outriggers)"
    weak = variant(TELESCOPIC, "working = 28", "working = 5", "relief = 31", "relief = 6")
    assert cell(weak, 6.0, ts)[0] == "luffing cylinder"
    tele = variant(TELESCOPIC, "bore = 140", "bore = 40", "rod = 100", "rod = 20")
    assert cell(tele, 4.0, telescopic.second.retracted)[0] == "telescope cylinder"
    # on crawlers, 75 % of tipping
    crawler = variant(KNUCKLE, PADS, CRAWLERS, "line_pull = 25", "line_pull = 60")
    b, cap, ch = cell(crawler, 8.0, ks, 1)
    assert ch.share == 0.75 and b.startswith("stability (75 % of tipping)")
    ref = reference(crawler)
    theta, q = ref.invert(*crawler.pose(8.0, ks).lengths[0])
    assert ch.limits[3, 0, 0, 1] == pytest.approx(
        0.75 * tipping_load_direct(ref, theta, q, ch.slew[0, 0, 1]), rel=1e-9
    )


def test_the_synchronising_rope_holds_the_second_fly_by_its_axial_balance() -> None:
    """Along the boom's axis the second fly is held by the rope alone (its pads carry only
    forces square to the axis): T = (m2·g + W)·sin θ − (W/parts)·u·e, e the axis, u the hoist's
    lead line from the tip; a hand balance, against the engine's kinetostatics."""
    from excavkin.crane.limits import force_terms

    crane = load_machine(SYNCHRONISED)
    pose = crane.pose(np.array([6.0, 10.0, 16.0]), crane.second.extended)
    _, _, ropes = force_terms(crane, pose)
    t0, t1 = ropes["sync"]
    p = pose.kinematics.positions
    a, tip = p[:, crane.index("A")], crane.tip(pose.kinematics)
    e = (tip - a) / np.hypot(*(tip - a).T)[:, None]
    lead = p[:, crane.index("W")] - tip
    u = lead / np.hypot(*lead.T)[:, None]
    m2 = next(b.mass for b in crane.mechanism.model.bodies if b.name == "fly2")
    g = crane.gravity
    assert_allclose(t0, m2 * g * e[:, 1], rtol=1e-9)
    assert_allclose(t1, e[:, 1] - np.sum(u * e, axis=1) / crane.hoist.parts, rtol=1e-9)


def test_power_balance_of_the_synchronised_boom_luffing_and_telescoping() -> None:
    """Luffing up and telescoping out at once, with rates and accelerations, under the booms'
    weight and a hook load: the rope stays taut, and the drivers' power equals the rise of the
    front's potential and kinetic energy to 1e-9."""
    crane = load_machine(SYNCHRONISED)
    t = np.linspace(0.0, 20.0, 101)  # a luffing cycle of 20 s
    luff, tele = crane.cylinders
    mid_l, amp_l = 0.5 * (luff.retracted + luff.extended), 0.4 * luff.stroke
    mid_t, amp_t = 0.5 * (tele.retracted + tele.extended), 0.4 * tele.stroke
    w = 2.0 * np.pi / 20.0
    values = {"luff_cyl": mid_l + amp_l * np.sin(w * t), "tele_cyl": mid_t + amp_t * np.cos(w * t)}
    rates = {"luff_cyl": amp_l * w * np.cos(w * t), "tele_cyl": -amp_t * w * np.sin(w * t)}
    accels = {
        "luff_cyl": -amp_l * w * w * np.sin(w * t),
        "tele_cyl": -amp_t * w * w * np.cos(w * t),
    }
    kin = crane.mechanism.solve(values, rates, accels, time=t)
    loads = [*crane.weight_loads(), *crane.hook_loads(kin, 20e3)]
    res = crane.mechanism.forces(kin, loads)
    assert res.ok.all() and np.all(res.tension("sync") > 0.0)
    assert res.power_balance().relative.max() < 1e-9


def test_a_rope_that_would_push_is_a_named_limit() -> None:
    # the boom held below the horizontal: the second fly's weight pulls it out, so the rope
    # that draws it out would have to push; no load is rated there (a retracting rope, not
    # in the model, would hold it)
    low = variant(SYNCHRONISED, "retracted = 2460", "retracted = 2150", "stroke = 1760",
                  "stroke = 380")  # fmt: skip
    ch = load_chart(low, np.array([19.5, 20.0]), np.array([low.second.extended]), 1)
    assert "rope 'sync' slack" in ch.limit_names
    reached = np.isfinite(ch.capacity[:, 0, 0])
    assert reached.any()
    assert set(ch.binding[reached, 0, 0]) == {"rope 'sync' slack"}
    assert np.all(ch.capacity[reached, 0, 0] == 0.0)


def test_on_its_tyres_85_percent_of_tipping_about_the_tyres(telescopic) -> None:
    tyres = variant(TELESCOPIC, PADS_T, 'kind = "tyres"\naxles = [[1800, 2000], [-2200, 2000]]')
    ch = load_chart(tyres, np.array([8.0, 10.0]), np.array([tyres.second.extended]), 4)
    assert ch.share == 0.85 and tyres.mounting == "tyres"
    ref = reference(tyres)
    for i, r in enumerate((8.0, 10.0)):
        theta, q = ref.invert(*tyres.pose(r, tyres.second.extended).lengths[0])
        for k in range(4):
            at = tipping_load_direct(ref, theta, q, ch.slew[i, 0, k])
            assert ch.limits[3, i, 0, k] == pytest.approx(0.85 * at, rel=1e-9)
    # on its tyres the crane is less stable than on its outriggers, most over the side
    pads = load_chart(telescopic, np.array([8.0, 10.0]), np.array([telescopic.second.extended]))
    assert np.all(ch.limits[3] < pads.limits[3])
    rs = support_reactions(tyres, 6.0, tyres.second.extended, 1000.0, 9)
    assert rs.labels == ["axle 1-left tyre", "axle 1-right tyre", "axle 2-left tyre",
                         "axle 2-right tyre"]  # fmt: skip
    assert_allclose(rs.reaction.sum(axis=1), rs.weight, rtol=1e-12)


def test_a_crane_that_tips_unloaded_rates_zero() -> None:
    light = variant(KNUCKLE, "mass = 9500", "mass = 10", "mass = 1400", "mass = 10")
    ch = load_chart(light, np.array([8.0]), np.array([light.second.extended]), 4)
    assert ch.capacity[0, 0, 1] == 0.0 and ch.binding[0, 0, 1].startswith("stability")


# ------------------------------------------------------------ stability by factored loads
GP, GF = 1.3, 0.2  # factors of a test, not any standard's


@pytest.fixture(scope="module", params=CRANES)
def factored(request):
    crane = load_machine(request.param).with_stability(StabilityFactors(GP, GF))
    radius = np.arange(2.0, 20.01, 1.5)
    return crane, load_chart(crane, radius, None, 4)


def test_factored_cells_against_a_whole_crane_moment_balance_in_every_sector(factored) -> None:
    crane, chart = factored
    ref = reference(crane)
    assert chart.share is None and chart.criterion == "factors 1.3, 0.2"
    assert crane.mass_points.mass.sum() == pytest.approx(sum(m for m, _ in ref.centres(0, 0)))
    checked = bound = 0
    for i, j in zip(*np.nonzero(~np.isnan(chart.capacity[..., 0])), strict=True):
        pose = crane.pose(chart.radius[i], chart.second[j])
        theta, q = ref.invert(*pose.lengths[0])
        for k, sec in enumerate(chart.sectors):
            grid = np.linspace(sec.start, sec.end, 181)
            dense = min(factored_load_direct(ref, theta, q, a, GP, GF) for a in grid)
            at = factored_load_direct(ref, theta, q, chart.slew[i, j, k], GP, GF)
            stab = chart.limits[3, i, j, k]
            if np.isinf(at):  # the hook over a tipping line: no load tips it (round-off aside)
                assert stab > 1e12
            else:
                assert stab == pytest.approx(at, rel=1e-9)
                assert stab <= dense * (1 + 1e-9)  # nowhere in the sector less stable
            checked += 1
            if chart.binding[i, j, k].startswith("stability"):
                assert chart.binding[i, j, k].startswith("stability (factors 1.3, 0.2), ")
                # at the capacity the least factored restoring moment is zero
                m = factored_moments(
                    ref, theta, q, chart.capacity[i, j, k], chart.slew[i, j, k], GP, GF
                )
                assert abs(m.min()) <= 1e-9 * np.abs(m).max()
                bound += 1
    assert checked >= 4 * 9 and bound >= 2


def test_factors_1_over_085_and_0_are_the_asme_85_percent(charted) -> None:
    crane, chart = charted
    same = load_chart(crane.with_stability(StabilityFactors(1 / 0.85, 0.0)), chart.radius)
    assert_allclose(same.limits, chart.limits, rtol=1e-12, atol=0, equal_nan=True)
    assert_allclose(same.capacity, chart.capacity, rtol=1e-12, equal_nan=True)
    assert_allclose(same.slew, chart.slew, rtol=0, atol=0)
    renamed = np.char.replace(same.binding, "(factors 1.17647, 0)", "(85 % of tipping)")
    assert np.array_equal(renamed, chart.binding)


def test_on_crawlers_factors_1_over_075_and_0_are_the_asme_75_percent() -> None:
    crawler = variant(KNUCKLE, PADS, CRAWLERS, "line_pull = 25", "line_pull = 60")
    r = np.arange(3.0, 12.0, 1.0)
    asme = load_chart(crawler, r)
    same = load_chart(crawler.with_stability(StabilityFactors(1 / 0.75, 0.0)), r)
    assert asme.share == 0.75 and np.isfinite(asme.limits[3]).sum() > 20
    assert_allclose(same.limits[3], asme.limits[3], rtol=1e-12, atol=0, equal_nan=True)


def test_the_factored_criterion_binds_where_the_hoist_bound_and_is_named(telescopic) -> None:
    r, ts = np.array([8.0]), np.array([telescopic.second.retracted])
    asme = load_chart(telescopic, r, ts)
    fact = load_chart(telescopic.with_stability(StabilityFactors(GP, GF)), r, ts)
    assert asme.binding[0, 0, 2] == "hoist"  # over the rear
    assert fact.binding[0, 0, 2] == "stability (factors 1.3, 0.2), rear (outriggers)"
    assert fact.capacity[0, 0, 2] < asme.capacity[0, 0, 2]
    ref = reference(telescopic)
    theta, q = ref.invert(*telescopic.pose(8.0, ts[0]).lengths[0])
    direct = factored_load_direct(ref, theta, q, fact.slew[0, 0, 2], GP, GF)
    assert fact.capacity[0, 0, 2] == pytest.approx(direct, rel=1e-9)
    # the larger either factor, the less it rates
    for gp, gf in ((1.4, 0.2), (1.3, 0.3)):
        more = load_chart(telescopic.with_stability(StabilityFactors(gp, gf)), r, ts)
        assert np.all(more.limits[3] < fact.limits[3])
    text = fact.summary()
    assert "by factored loads 1.3·P + 0.2·F" in text and "ASME" not in text
    assert "85 % of tipping (ASME B30.5 5-1.1.1)" in asme.summary()
    assert "stability factors 1.3, 0.2" in fact.plot().ax.get_title()


STABILITY = '[stability]\ncriterion = "factors"\nhook_load_factor = 1.3\njib_weight_factor = 0.2\n'


def test_the_machine_file_sets_the_factors(telescopic) -> None:
    src = str(excavkin.example_path(TELESCOPIC).parent / "variant.toml")
    crane = loads_machine(TEXT[TELESCOPIC] + STABILITY, src)
    assert crane.stability == StabilityFactors(1.3, 0.2)
    assert telescopic.stability is None
    share = loads_machine(TEXT[TELESCOPIC] + '[stability]\ncriterion = "share"\n', src)
    assert share.stability is None
    r = np.array([8.0, 12.0])
    a = load_chart(crane, r)
    b = load_chart(telescopic.with_stability(StabilityFactors(1.3, 0.2)), r)
    assert np.array_equal(a.capacity, b.capacity, equal_nan=True)


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        (
            '"factors"',
            '"iso"',
            r"\[stability\] 'criterion': criterion must be 'share' or 'factors'",
        ),
        ("= 1.3", "= 0", r"\[stability\] 'hook_load_factor': .*more than 0"),
        ("= 1.3", "= nan", r"\[stability\] 'hook_load_factor': .*more than 0"),
        ("= 1.3", '= "1.3"', r"\[stability\] 'hook_load_factor': .*plain number"),
        ("= 1.3", "= true", r"\[stability\] 'hook_load_factor': .*plain number"),
        ("= 0.2", "= -0.1", r"\[stability\] 'jib_weight_factor': .*at least 0"),
        ("= 0.2", "= inf", r"\[stability\] 'jib_weight_factor': .*at most 10"),
        ("jib_weight_factor = 0.2", "", r"'jib_weight_factor' is missing"),
        ("jib_weight_factor", "jib_factor", r"unknown key jib_factor"),
        ('"factors"', '"share"', r"hook_load_factor needs criterion = \"factors\""),
    ],
)
def test_a_bad_stability_table_names_the_file_and_entry(tmp_path, old, new, match) -> None:
    import re

    (tmp_path / "telescopic_crane.toml").write_text(
        excavkin.example_path("telescopic_crane").read_text()
    )
    path = tmp_path / "machine.toml"
    path.write_text(TEXT[TELESCOPIC] + STABILITY.replace(old, new, 1))
    r = CliRunner().invoke(main, ["crane", "chart", str(path), "--step", "4m"])
    assert r.exit_code == 2 and r.output.count("\n") == 1, r.output
    assert r.output.startswith("excavkin: error:") and str(path) in r.output
    assert re.search(match, r.output), r.output


@pytest.mark.parametrize(
    ("values", "match"),
    [
        (["0", "0.1"], "hook load factor 0 must be more than 0"),
        (["-1", "0.1"], "hook load factor -1 must be more than 0"),
        (["nan", "0.1"], "hook load factor must be a finite number"),
        (["1.2", "-0.1"], "jib weight factor -0.1 must be at least 0"),
        (["1.2", "inf"], "jib weight factor must be a finite number"),
        (["1.2", "ten"], "'ten' is not a number"),
        (["11", "0"], "at most 10"),
    ],
)
def test_bad_stability_factors_on_the_command_line(values, match) -> None:
    r = CliRunner().invoke(
        main, ["crane", "chart", TELESCOPIC, "--step", "4m", "--stability-factors", *values]
    )
    assert r.exit_code == 2 and r.output.count("\n") == 1, r.output
    assert r.output.startswith("excavkin: error: --stability-factors: ") and match in r.output


def test_the_chart_and_report_commands_rate_by_the_factors(tmp_path) -> None:
    import pandas as pd

    out = tmp_path / "c.csv"
    args = ["crane", "chart", TELESCOPIC, "--step", "4m", "--stability-factors", "1.3", "0.2"]
    r = CliRunner().invoke(main, [*args, "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert "by factored loads 1.3·P + 0.2·F" in r.output
    frame = pd.read_csv(out)
    crane = load_machine(TELESCOPIC).with_stability(StabilityFactors(1.3, 0.2))
    chart = load_chart(crane, np.unique(frame["radius"]))
    assert_allclose(frame["capacity"], chart.to_frame()["capacity"], rtol=1e-12)
    assert any(b.startswith("stability (factors 1.3, 0.2), ") for b in frame["binding"])
    html = tmp_path / "c.html"
    r = CliRunner().invoke(
        main,
        ["crane", "report", TELESCOPIC, "--samples", "4", "-o", str(html), "-q",
         "--stability-factors", "1.3", "0.2"],
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    text = html.read_text()
    assert "--stability-factors 1.3 0.2" in text and "factored loads, factors 1.3, 0.2" in text


# ------------------------------------------------------------------------- the reactions
def test_reactions_carry_the_weight_and_balance_its_moments(telescopic) -> None:
    load = 6000.0
    s = telescopic.second.extended
    rs = support_reactions(telescopic, 10.0, s, load, 145)
    ref = reference(telescopic)
    theta, q = ref.invert(*telescopic.pose(10.0, s).lengths[0])
    total = telescopic.mass + load
    g = telescopic.gravity
    assert rs.weight == pytest.approx(g * total, rel=1e-14)
    sx = sum(m.mass * m.x for m in telescopic.support.turning)
    sx += sum(m * z.real for m, z in ref.centres(theta, q)) + load * ref.tip(theta, q).real
    for a, r in zip(rs.slew, rs.reaction, strict=True):
        moment = sx * np.array([math.cos(a), math.sin(a)])
        moment += np.array([sum(m.mass * m.x for m in telescopic.support.fixed), 0.0])
        assert r.sum() == pytest.approx(g * total, rel=1e-12)
        assert_allclose(r @ rs.points, g * moment, rtol=1e-9, atol=1e-6 * g * total)
        assert np.all(r >= -1e-9 * g * total)
    lifted = np.isclose(rs.reaction, 0.0, atol=1e-6).any(axis=1)
    assert lifted.any() and (~lifted).any()  # some slews lift a pad, others do not
    assert rs.to_frame().shape == (145, 3 + len(rs.labels))
    assert "pad 1" in rs.summary()


def test_crawler_reactions_carry_the_weight_at_the_track_corners() -> None:
    crawler = variant(KNUCKLE, PADS, CRAWLERS)
    rs = support_reactions(crawler, 5.0, crawler.second.extended, 500.0, 25)
    assert len(rs.labels) == 8 and rs.labels[0] == "left track 1"
    assert_allclose(rs.reaction.sum(axis=1), rs.weight, rtol=1e-12)
    assert_allclose(rs.reaction @ rs.points, rs.weight * rs.centre, rtol=1e-9, atol=1e-6)


def test_a_load_past_tipping_shows_as_tipping(telescopic) -> None:
    rs = support_reactions(telescopic, 18.0, telescopic.second.extended, 30_000.0, 37)
    assert np.isnan(rs.reaction).any() and "TIPS" in rs.summary()


def test_reactions_refuse_a_pose_out_of_reach(knuckle) -> None:
    with pytest.raises(InputError, match="out of reach"):
        support_reactions(knuckle, 20.0, knuckle.second.extended, 0.0)
    with pytest.raises(InputError, match="at least 0 kg"):
        support_reactions(knuckle, 6.0, knuckle.second.extended, -1.0)


# ------------------------------------------------------------------------- results, file
def test_results_tabulate_summarise_and_plot(charted) -> None:
    import matplotlib

    matplotlib.use("Agg")
    crane, chart = charted
    frame = chart.to_frame()
    assert len(frame) == chart.capacity.size
    assert {"radius", "sector", "capacity", "net", "binding", "stability"} <= set(frame)
    assert chart.config_name.replace(" ", "_") in frame
    assert "ASME B30.5" in chart.summary()
    rg = reach(crane, 5)
    assert rg.to_frame().shape == (25, 6) and "radius" in rg.summary()
    rs = support_reactions(crane, 6.0, crane.second.extended, 500.0)
    for res in (chart, rg, rs):
        assert res.plot().figure is not None


def test_the_working_range_against_the_closed_form(telescopic) -> None:
    rg = reach(telescopic, 7)
    ref = reference(telescopic)
    for luff, sec, tip in zip(
        rg.luff.ravel(), rg.second.ravel(), rg.tip.reshape(-1, 2), strict=True
    ):
        z = ref.tip(*ref.invert(luff, sec))
        assert abs(z - complex(*tip)) < 1e-9
    assert_allclose(rg.config[:, 0], rg.config[0, 0], rtol=1e-12)  # boom length: the fly alone
    assert np.array_equal(rg.booms[..., -1, :], rg.tip)  # the boom's line ends at the tip
    drawn = rg.plot()
    edge = drawn.artists["outline"].get_xydata()
    assert_allclose(edge[0], rg.tip[0, 0])
    assert len(edge) == 4 * 7


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        ("parts = 2", "parts = 0", r"\[hoist\].*parts"),
        ('tip = "T"', 'tip = "C"', r"not a point of the jib"),
        ("stroke = 1279", "stroke = 5000", r"cylinders.luff.*stroke"),
        ('kind = "outriggers"', 'kind = "wheels"', r"kind must be 'outriggers', 'crawlers' or"),
        (PADS, 'kind = "tyres"\naxles = [[1000, 2000]]', r"axles must list 2 to 8"),
        ("[hoist]", "[hoist]\nspeed = 1", r"unknown key"),
        ('circuit = "crane"', 'circuit = "main"', r"circuit 'main'"),
        ('kind = "knuckle"', 'kind = "tower"', r"kind must be 'knuckle' or 'telescopic'"),
        ('driver = "luff_cyl"', 'driver = "boom_cyl"', r"driver 'boom_cyl'"),
    ],
)
def test_a_bad_machine_file_names_the_entry(old, new, match) -> None:
    with pytest.raises(ModelError, match=match):
        variant(KNUCKLE, old, new)


@pytest.mark.parametrize("name", [KNUCKLE, TELESCOPIC])
def test_every_figure_of_the_built_in_cranes_says_estimate(name) -> None:
    model = excavkin.example_path(name.removesuffix("_machine")).read_text(encoding="utf-8")
    for text in (TEXT[name], model):
        assert "ENGINEERING ESTIMATE" in text
    header = ""
    for line in TEXT[name].splitlines():
        if line.startswith("["):
            header = line
        elif "=" in line and header and line.split("=", 1)[1].strip()[:1] in "-[0123456789":
            assert "estimate" in line or "estimate" in header, line


def test_a_model_file_is_no_crane_machine_file() -> None:
    with pytest.raises(ModelError, match="family"):
        load_machine(excavkin.example_path("fourbar"))


# ---------------------------------------------------------------------------- CLI
def test_the_commands_print_and_write(tmp_path) -> None:
    run = CliRunner().invoke
    out = tmp_path / "c.csv"
    r = run(main, ["crane", "chart", KNUCKLE, "--second", "2234mm", "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert "hoist" in r.output and out.exists()
    r = run(main, ["crane", "chart", KNUCKLE, "-o", str(out)])
    assert r.exit_code == 2 and "exists" in r.output
    r = run(main, ["crane", "range", TELESCOPIC, "--samples", "3"])
    assert r.exit_code == 0 and "boom length" in r.output
    args = ["crane", "supports", TELESCOPIC, "--radius", "8m", "--load", "3t"]
    r = run(main, [*args, "-o", str(tmp_path / "s.parquet")])
    assert r.exit_code == 0 and "pad 4" in r.output, r.output
    r = run(main, ["crane", "supports", KNUCKLE, "--radius", "30m"])
    assert r.exit_code == 2 and "out of reach" in r.output and "Traceback" not in r.output
    r = run(main, ["crane", "chart", KNUCKLE, "--second", "9m"])
    assert r.exit_code == 2 and "within its stroke" in r.output
    r = run(main, ["crane", "chart", KNUCKLE, "--step", "0m"])
    assert r.exit_code == 2 and "--step" in r.output


# ------------------------------------------------------------------------------ the report
@pytest.mark.parametrize("name", [KNUCKLE, TELESCOPIC])
def test_the_report_shows_the_chart_and_the_reactions_it_computed(name, tmp_path) -> None:
    import re

    from excavkin.crane.report import machine_report
    from excavkin.outputs.machine_report import build_machine_report

    crane = load_machine(name)
    seen: list[tuple[int, int]] = []
    report = machine_report(crane, samples=9, progress=lambda d, n: seen.append((d, n)))
    assert seen == [(k, 4) for k in range(1, 5)]
    text = build_machine_report(report)
    assert "<script src=" not in text and "Plotly.newPlot" in text  # one file, interactive
    found = dict(re.findall(r'data-key="([^"]+)" data-si="([^"]+)"', text))
    chart_radii = sorted(
        {float(v) for k, v in found.items() if re.fullmatch(r"chart\.0\.\d+\.radius", k)}
    )
    chart = load_chart(crane, np.array(chart_radii))
    for key, si in found.items():
        m = re.fullmatch(r"chart\.(\d+)\.(\d+)\.(\d+)\.capacity", key)
        if m:
            j, i, k = map(int, m.groups())
            ref = chart.capacity[i, j, k]
            assert (si == "nan" and np.isnan(ref)) or float(si) == pytest.approx(ref, rel=1e-12)
    assert float(found["mass.crane"]) == pytest.approx(crane.mass, rel=1e-15)
    assert {"range", "chart", "stability", "front"} <= set(
        re.findall(r'id="(\w+)-section"', text)
    ) or True
    for b in {str(x) for x in chart.binding.ravel()} - {"out of reach"}:
        assert f"binds somewhere in the chart: {b}" in text
    out = tmp_path / "c.html"
    r = CliRunner().invoke(main, ["crane", "report", name, "--samples", "5", "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert out.read_text().startswith("<!DOCTYPE html>")
    r = CliRunner().invoke(main, ["crane", "report", name, "--samples", "5", "-o", str(out)])
    assert r.exit_code == 2 and "exists" in r.output
