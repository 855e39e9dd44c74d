"""A pose out of a Newton group's reach says which constraint cannot be met and by how much
(issue "Ropes over sheaves, pulley blocks, gears, racks and cams", item 6: clear messages),
not "Newton did not converge"; a group that could close but was not reached still says so.

The four-bars here are solved with the generic solver (``method="newton"``): one group, A and
B, with four constraints — the crank |O2A| = r, the crank's angle θ, the coupler |AB| = b and
the rocker |O4B| = c. Where |AO4| lies outside [|b − c|, b + c], B cannot close. The shortfall
of the constraint named is checked against the triangle's own geometry, each constraint's
reachable range with the three others met.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from click.testing import CliRunner

import excavkin
from excavkin import Mechanism
from excavkin.cli import main
from excavkin.kinematics.result import diagnose
from excavkin.outputs.events import as_table, find_events
from excavkin.step_kinds import CAngle, CDist, NewtonGroup
from excavkin.step_kinds.newton_solve import misses, out_of_reach
from excavkin.step_kinds.state import Chunk, Code
from tests.models import fourbar_model

#: crank 0.15, ground 0.3, coupler 0.3, rocker 0.1: |AO4| runs over [0.15, 0.45] and B closes
#: only for |AO4| in [0.2, 0.4]; out of reach near crank 0° (too close) and 180° (too far)
R, G, BL, CL = 0.15, 0.3, 0.3, 0.1


def _model():  # noqa: ANN202
    # an assembled sketch at crank 90°: A = (0, 0.15), |AO4| = 0.3354
    a = np.array([0.0, R])
    d = np.hypot(G, R)
    k = (BL**2 - CL**2 + d**2) / (2 * d)
    u = (np.array([G, 0.0]) - a) / d
    b = a + k * u + np.sqrt(BL**2 - k**2) * np.array([-u[1], u[0]])
    pts = {"O2": (0.0, 0.0), "A": (0.0, R), "B": (float(b[0]), float(b[1])), "O4": (G, 0.0)}
    return fourbar_model(pts, "out of reach")


def _nearest(values: np.ndarray, target: float) -> float:
    return float(values[np.argmin(np.abs(values - target))])


def expected(name: str, theta: float) -> float:
    """The named constraint's miss by hand: the value it can reach nearest its own, with the
    three others met, less its own (rad for the angle, m for the distances)."""
    lo, hi = abs(BL - CL), BL + CL
    a = R * np.array([np.cos(theta), np.sin(theta)])
    d = float(np.hypot(*(a - [G, 0.0])))
    if name == "rocker":  # B on a circle of b about A: |O4B| in [|d − b|, d + b]
        return float(np.clip(CL, abs(d - BL), d + BL) - CL)
    if name == "coupler":  # B on a circle of c about O4: |AB| in [|d − c|, d + c]
        return float(np.clip(BL, abs(d - CL), d + CL) - BL)
    if name == "crank":  # A on the ray at θ, |AO4| within [lo, hi]: its ends, r' ≥ 0
        ends = []
        for length in (lo, hi):
            disc = (G * np.cos(theta)) ** 2 - G * G + length * length
            if disc >= 0:
                ends += [G * np.cos(theta) + s * np.sqrt(disc) for s in (-1.0, 1.0)]
        return _nearest(np.array([e for e in ends if e >= 0]), R) - R
    # the angle: A on the circle of r, |AO4| within [lo, hi]: its ends ±arccos
    ends = []
    for length in (lo, hi):
        cos = (R * R + G * G - length * length) / (2 * R * G)
        if abs(cos) <= 1:
            ends += [s * np.arccos(cos) for s in (-1.0, 1.0)]
    turns = np.angle(np.exp(1j * (np.array(ends) - theta)))
    return _nearest(turns, 0.0)


def test_a_pose_out_of_reach_names_the_constraint_and_the_triangle_s_shortfall() -> None:
    q = np.radians(np.arange(0.0, 360.0, 5.0))
    closed = Mechanism(_model()).solve({"crank": q})
    res = Mechanism(_model(), method="newton").solve({"crank": q})
    st = res.status
    # out of reach: exactly the samples the closed form cannot close
    no_close = closed.status.code == Code.NO_CLOSURE
    assert no_close.sum() > 10 and (~no_close).sum() > 10
    np.testing.assert_array_equal(st.code == Code.OUT_OF_REACH, no_close)
    # crank 240°–320° close (B on the sketch's side), but only across poses that do not: the
    # continuation cannot get there, and says so — they are not called out of reach
    unreached = (q >= np.radians(239)) & (q <= np.radians(321))
    assert closed.status.ok[unreached].all()
    np.testing.assert_array_equal(st.code[unreached], Code.NO_CONVERGENCE)
    assert "Newton did not converge at group A, B" in st.message(int(np.flatnonzero(unreached)[0]))
    rest = ~no_close & ~unreached
    np.testing.assert_array_equal(st.code[rest], closed.status.code[rest])
    group = res.plan.steps[st.step[no_close][0]]
    assert isinstance(group, NewtonGroup)
    names = {}
    for j, con in enumerate(group.constraints):
        names[j] = con.dist.body if isinstance(con, CDist) else "angle"
        assert isinstance(con, CDist | CAngle)
    both_ways = set()
    for i in np.flatnonzero(no_close):
        name = names[int(st.unmet[i])]
        hand = expected(name, float(q[i]))
        np.testing.assert_allclose(st.miss[i], hand, rtol=0, atol=1e-13)
        assert abs(hand) > 1e-3
        both_ways.add(np.sign(hand))
    assert both_ways == {-1.0, 1.0}  # too close and too far, both met
    # crank 0° and 180°: A on the ground line, every distance of the triangle A, B, O4 in line,
    # and whichever is named misses by the triangle's slack, by the direct formulas (a = |AB|,
    # b = |O4B|, c = |AO4|): |a − b| − c folded, c − (a + b) stretched
    for deg, short in ((0.0, abs(BL - CL) - (G - R)), (180.0, (G + R) - (BL + CL))):
        i = int(np.flatnonzero(np.isclose(q, np.radians(deg)))[0])
        assert names[int(st.unmet[i])] != "angle" and short == pytest.approx(0.05)
        np.testing.assert_allclose(abs(st.miss[i]), short, rtol=0, atol=1e-15)
    # the reachable poses: the closed form's positions
    ok = st.ok
    np.testing.assert_allclose(res.positions[ok], closed.positions[ok], rtol=0, atol=1e-13)


def test_the_message_says_it_and_the_sample_s_amount() -> None:
    q = np.radians([180.0])  # |AO4| = 0.45: 0.05 beyond b + c
    st = Mechanism(_model(), method="newton").solve({"crank": q}).status
    assert st.code[0] == Code.OUT_OF_REACH
    name = ("O2–A (body 'crank')", "A–B (body 'coupler')", "O4–B (body 'rocker')")
    text = st.message(0)
    assert text.startswith("out of reach at group A, B: ")
    assert any(n in text for n in name)
    assert text.endswith(" m short") or text.endswith(" m too long")
    assert st.labels()[0] == st.label(0) and st.label(0).endswith("cannot be met")
    assert float(st.shortfall(0, "mm").split()[0]) == pytest.approx(abs(st.miss[0]) * 1e3, abs=0.05)


def test_the_diagnosis_leaves_every_value_and_every_other_status_as_it_was() -> None:
    """Reachable poses stay ok to the bit: the look again copies what it reads."""
    q = np.radians(np.arange(0.0, 360.0, 5.0))
    mech = Mechanism(_model(), method="newton")
    res = mech.solve({"crank": q})
    before = res.status
    plain = dataclasses.replace(
        before, code=np.where(before.code == Code.OUT_OF_REACH, Code.NO_CONVERGENCE, before.code)
    )
    plain = type(before)(plain.code.astype(np.int8), before.step, before.plan)
    x = np.moveaxis(res.positions, 0, -1)
    x0, q0 = x.copy(), res.inputs.T.copy()
    again = diagnose(res.plan, x, res.inputs.T, plain)
    np.testing.assert_array_equal(x, x0)
    np.testing.assert_array_equal(res.inputs.T, q0)
    np.testing.assert_array_equal(again.code, before.code)
    np.testing.assert_array_equal(again.unmet, before.unmet)
    np.testing.assert_array_equal(again.miss, before.miss)


def test_a_group_that_can_close_is_not_called_out_of_reach() -> None:
    """From a start far from the pose (B mirrored, A a quarter turn off), the minimisation
    finds the pose: Newton's failure there is its own, and the status stays 'did not
    converge'."""
    mech = Mechanism(_model(), method="newton")
    good = mech.solve({"crank": np.radians([90.0, 100.0])})
    assert good.status.all_ok
    (k,) = [k for k, s in enumerate(mech.plan.steps) if isinstance(s, NewtonGroup)]
    g = mech.plan.steps[k]
    x = np.moveaxis(good.positions, 0, -1).copy()
    a, b = g.points
    x[a] = np.array([[R], [0.0]])  # crank at 0°, B reflected
    x[b, 1] *= -1
    q = good.inputs.T.copy()
    n = q.shape[1]
    c = Chunk(x, x, x, q, 0 * q, 0 * q, np.empty((0, n)), np.zeros(n, np.int8),
              np.full(n, -1, np.int16), 0.0, 0.0)  # fmt: skip
    out, unmet, miss = out_of_reach(c, g, mech.plan.scale)
    assert not out.any() and (unmet == -1).all() and np.isnan(miss).all()
    length, _ = misses(c, g)  # it found a pose (this one, or B's mirror image)
    assert length.max() < 1e-12


def test_the_command_line_lists_the_samples_out_of_reach_in_mm(tmp_path) -> None:
    """A coupler driven by its angle to the crank (a Newton group): folded past 119.0°, the
    crank and coupler bring B nearer O2 than 0.7 m, and the rocker of 0.3 m cannot reach it.
    The driver is named, and how far its angle is beyond the reachable ones."""
    model = tmp_path / "fold.toml"
    model.write_text(
        """schema_version = 1
name = "folding four-bar"
[units]
length = "m"
angle = "deg"
[points]
O2 = [0, 0]
O4 = [1, 0]
A  = [0.058, 0.365]
B  = [0.85, 0.26]
[bodies]
ground  = { points = ["O2", "O4"], ground = true }
crank   = { points = ["O2", "A"] }
coupler = { points = ["A", "B"] }
rocker  = { points = ["O4", "B"] }
[lengths]
"O2-A" = 0.37
"A-B"  = 0.8
"O4-B" = 0.3
[drivers.fold]
type = "rotary"
body = "coupler"
pivot = "A"
reference = "crank"
""",
        encoding="utf-8",
    )
    out = tmp_path / "out.csv"
    args = ["solve", str(model), "--sweep", "fold=0deg:130deg:14", "-o", str(out)]
    run = CliRunner().invoke(main, args)
    assert run.exit_code != 0 and not out.exists()
    assert "Newton did not converge" not in run.output
    # the reachable folds: |O2B|² = 0.37² + 0.8² + 2·0.37·0.8·cos(fold) ≥ 0.7², |fold| ≤ 119.0°
    limit = np.degrees(np.arccos((0.7**2 - 0.37**2 - 0.8**2) / (2 * 0.37 * 0.8)))
    assert (
        "out of reach at group A, B: driver 'fold' cannot be met: samples "
        f"12 (fold = 120°; {120 - limit:.3g}° off), 13 (fold = 130°; {130 - limit:.3g}° off)"
    ) in run.output
    # the amounts, to 1e-14 rad of the hand computation
    kin = excavkin.load(str(model)).solve({"fold": np.radians([120.0, 130.0])})
    np.testing.assert_allclose(
        kin.status.miss, np.radians(limit - np.array([120.0, 130.0])), atol=1e-14
    )


def test_events_say_each_run_out_of_reach_and_its_worst_shortfall() -> None:
    q = np.radians(np.arange(0.0, 360.0, 5.0))
    res = Mechanism(_model(), method="newton").solve({"crank": q})
    runs = [e for e in find_events(res) if e.kind == "does not close"]
    st = res.status
    # one run per reason: crank 0°–35°, 125°–235°, 240°–320° (not reached), 325°–355°
    assert [(int(e.samples[0]), int(e.samples[-1])) for e in runs] == [
        (0, 7),
        (25, 47),
        (48, 64),
        (65, 71),
    ]
    for e in runs:
        run = e.samples
        if st.code[run[0]] == Code.NO_CONVERGENCE:
            assert e.message.startswith("Newton did not converge at group A, B: samples 48–64")
            continue
        # the first sample's reason, by up to its worst over the samples that give it
        alike = run[st.unmet[run] == st.unmet[run[0]]]
        worst = alike[np.argmax(np.abs(st.miss[alike]))]
        assert e.message.startswith(st.label(run[0]) + ": samples ")
        assert e.message.endswith(f", by up to {st.shortfall(worst, 'mm')}")
        if "driver 'crank'" in e.message:  # an angle, in degrees
            assert st.shortfall(worst, "mm") == f"{np.degrees(abs(st.miss[worst])):.3g}° off"
    # a table read back without its result: the codes from the status labels
    np.testing.assert_array_equal(as_table(res.to_frame()).codes, st.code)


def test_the_rope_shovel_past_its_reach_names_the_drag_rope() -> None:
    """The EO-4112 rope backhoe's front (``rope_shovel``) by the generic solver, its drag rope
    F–E let out or hauled in past what the front can take. Let out: E cannot get further from
    F than |O1F| + |O1E| = 4.2 + 2.8 m (stick and rope in line), by hand. Hauled in: the
    bucket's four-bar folds flat first; its limit is the closed form's, found by bisection."""
    shovel = excavkin.load("rope_shovel")
    mech = Mechanism(shovel.model, method="newton")
    out = np.array([7.05, 7.3, 7.5])
    st = mech.solve({"drag": out}).status
    assert (st.code == Code.OUT_OF_REACH).all()
    assert all(st.label(i).endswith(": F–E (driven 'drag') cannot be met") for i in range(3))
    np.testing.assert_allclose(st.miss, 7.0 - out, rtol=0, atol=1e-12)
    assert st.message(1) == (
        "out of reach at group O2, K, E, B, C, D, H: F–E (driven 'drag') is 0.3 m short"
    )
    lo, hi = 3.0, 3.5  # the closed form: out at 3.0 (dyad D does not close), in at 3.5
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (
            (lo, mid) if shovel.solve({"drag": np.array([mid])}).status.solved[0] else (mid, hi)
        )
    short = np.array([1.0, 2.5, 3.0])
    st = mech.solve({"drag": short}).status
    assert (st.code == Code.OUT_OF_REACH).all()
    # the closed form takes a dyad as closing up to its close tolerance (1e-10 of the base²)
    np.testing.assert_allclose(st.miss, hi - short, rtol=0, atol=1e-6)
    assert np.ptp(short + st.miss) < 1e-12  # one limit, from wherever the pose asked for
