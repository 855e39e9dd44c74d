"""Pin loads and cylinder forces over the working range, against independent routes.

* every moving body's free-body equilibrium written by hand: its pin forces (from the result),
  its weight at its centre of mass placed from the example files' sketch, the cylinders' half
  weights and the tool force or lift load sum to zero, in force and in moment;
* every pin's equilibrium with the cylinders' forces from virtual work (``forces.py``,
  ``lift.py``): the pin passes to its bodies what the cylinders ending at it push;
* the cylinder forces equal the virtual-work ones to 1e-9;
* the pin load is the largest member force, and the maxima equal a brute-force search over
  the poses solved one at a time.
"""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from excavkin.errors import InputError
from excavkin.excavator.forces import gravity_terms, tool_forces
from excavkin.excavator.lift import cylinder_limits, hydraulic_lift
from excavkin.excavator.machine import Machine, transfer
from excavkin.excavator.machine_file import load_machine
from excavkin.excavator.pin_loads import CASES, PinLoads, load_maxima, pin_labels, pin_loads
from excavkin.excavator.ranges import stroke_grid
from tests.crossmethod.test_excavator_stability import G, _files, _poses


@pytest.fixture(scope="module")
def machine() -> Machine:
    return load_machine(excavkin.example_path("excavator_machine"))


def _applied(machine: Machine, r: PinLoads, gravity: bool) -> dict[str, list]:
    """Per moving body, its applied forces [(force (n, 2), point (n, 2))], from the example
    files: the weight at the centre of mass (sketch → pose by the body's first two points),
    half of each cylinder's weight on the first moving body at each of its moving ends, and
    the tool force (against the tool's motion) or the lift load."""
    model, mach = _files()
    mm = 1e-3
    sketch = {k: np.array(v) * mm for k, v in model["points"].items()}
    kin = r.forces.kinematics
    n = len(r.lengths)
    out: dict[str, list] = {}
    moving = [(k, b) for k, b in model["bodies"].items() if not b.get("ground")]
    for name, body in moving:
        out[name] = []
        if not gravity:
            continue
        a, b = body["points"][:2]
        s0, s1 = sketch[a], sketch[b]
        c0, c1 = kin.point(a)[0], kin.point(b)[0]
        turn = np.arctan2(*(c1 - c0).T[::-1]) - np.arctan2(*(s1 - s0)[::-1])
        v = np.array(body["center_of_mass"]) * mm - s0
        com = c0 + np.column_stack(
            [np.cos(turn) * v[0] - np.sin(turn) * v[1], np.sin(turn) * v[0] + np.cos(turn) * v[1]]
        )
        out[name].append((np.tile([0.0, -body["mass"] * G], (n, 1)), com))
    if gravity:
        for spec in mach["cylinders"].values():
            for pin in model["drivers"][spec["driver"]]["between"]:
                holder = next((k for k, b in moving if pin in b["points"]), None)
                if holder is not None:
                    w = np.tile([0.0, -0.5 * spec["mass"] * G], (n, 1))
                    out[holder].append((w, kin.point(pin)[0]))
    if r.case == "lift":
        out["bucket"].append((np.column_stack([np.zeros(n), -r.tool_force]), r.tool_point))
    else:
        tf = tool_forces(machine, r.lengths, r.case, gravity=gravity)  # type: ignore[arg-type]
        out["bucket"].append((-tf.force[:, None] * tf.direction, kin.point("W")[0]))
    return out


def _cross(r: np.ndarray, f: np.ndarray) -> np.ndarray:
    return r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0]


def _virtual_work_cylinders(machine: Machine, r: PinLoads) -> np.ndarray:
    """f_c = W·∂y_P/∂L_c + G_c for the lift load (``lift.py``), ``tool_forces`` otherwise."""
    if r.case == "lift":
        tr = transfer(machine, r.lengths)
        _, J = tr.point(machine, machine.lift_point)
        G = gravity_terms(machine, tr.d) if r.gravity else 0.0
        return r.tool_force[:, None] * J[:, 1, :] + G
    working = "arm" if r.case == "arm" else "bucket"
    return tool_forces(machine, r.lengths, working, gravity=r.gravity).cylinder_force


@pytest.mark.parametrize("gravity", [True, False])
@pytest.mark.parametrize("case", CASES)
def test_every_body_and_pin_is_in_equilibrium(machine: Machine, case: str, gravity: bool) -> None:
    L = _poses(machine, 12, seed=16 + CASES.index(case))
    r = pin_loads(machine, L, case, gravity=gravity)  # type: ignore[arg-type]
    assert r.held.sum() >= 10
    ok = r.held
    kin = r.forces.kinematics
    # body by body: the pin forces, the weights and the tool force balance
    for body, applied in _applied(machine, r, gravity).items():
        terms = [(r.forces.pin(p, b), kin.point(p)[0]) for p, b in r.forces.pins if b == body]
        terms += applied
        force = sum(f for f, _ in terms)
        moment = sum(_cross(x, f) for f, x in terms)
        scale = max(np.max(np.abs(f[ok])) for f, _ in terms)
        reach = max(np.max(np.abs(x[ok])) for _, x in terms)
        assert np.max(np.abs(force[ok])) <= 1e-9 * scale, body
        assert np.max(np.abs(moment[ok])) <= 1e-9 * scale * reach, body
    # pin by pin: the bodies receive what the cylinders ending there push (virtual work)
    f_vw = _virtual_work_cylinders(machine, r)
    np.testing.assert_allclose(r.cylinder_force[ok], f_vw[ok], rtol=1e-9, atol=0)
    model, mach = _files()
    ends = {k: model["drivers"][c["driver"]]["between"] for k, c in mach["cylinders"].items()}
    for p in r.pins:
        got = sum(r.forces.pin(q, b) for q, b in r.forces.pins if q == p)
        want = np.zeros_like(got)
        for c, role in enumerate(("boom", "arm", "bucket")):
            a, b = ends[role]
            if p in (a, b):
                other = b if p == a else a
                e = kin.point(p)[0] - kin.point(other)[0]
                want = want + f_vw[:, c, None] * e / np.hypot(*e.T)[:, None]
        scale = np.max(np.abs(f_vw[ok]))
        assert np.max(np.abs((got - want)[ok])) <= 1e-9 * scale, p


def test_the_pin_load_is_its_largest_member_force(machine: Machine) -> None:
    L = _poses(machine, 20, seed=3)
    r = pin_loads(machine, L, "arm")
    fr = r.forces
    ok = r.held
    j = {p: k for k, p in enumerate(r.pins)}

    def mag(p: str, b: str) -> np.ndarray:
        return np.hypot(*fr.pin(p, b).T)

    # a pin of two bodies: both receive the same force, opposite
    np.testing.assert_allclose(mag("A", "frame")[ok], mag("A", "boom")[ok], rtol=1e-12)
    np.testing.assert_allclose(r.load[ok, j["A"]], mag("A", "boom")[ok], rtol=1e-12)
    # the link junction: side link, H-link and the bucket cylinder's eye
    want = np.maximum(
        np.maximum(mag("K", "side_link"), mag("K", "h_link")), np.abs(r.cylinder_force[:, 2])
    )
    np.testing.assert_array_equal(r.load[ok, j["K"]], want[ok])
    # a cylinder end on one body carries the cylinder's force
    np.testing.assert_allclose(r.load[ok, j["D"]], np.abs(r.cylinder_force[ok, 0]), rtol=1e-9)
    assert r.members[j["K"]] == ("side_link", "h_link", "bucket cylinder")
    labels = pin_labels(machine)
    assert labels["K"] == "link junction / bucket cylinder rod eye" and labels["A"] == "boom foot"
    assert len(r.pins) == 11 and set(r.pins) == set(labels)


def test_maxima_equal_a_brute_force_search(machine: Machine) -> None:
    """Each pose solved alone gives the batch's values, and the maxima are their largest."""
    L = stroke_grid(machine, 4)
    results = [pin_loads(machine, L, c) for c in CASES]  # type: ignore[arg-type]
    maxima = load_maxima(results)
    seen: dict[str, dict[tuple[str, int], float]] = {}
    for r in results:
        for i in range(len(L)):
            one = pin_loads(machine, L[i : i + 1], r.case)  # type: ignore[arg-type]
            np.testing.assert_allclose(one.load[0], r.load[i], rtol=1e-12)
            np.testing.assert_allclose(one.cylinder_force[0], r.cylinder_force[i], rtol=1e-12)
            if not one.held[0]:
                continue
            values = [*one.load[0], *np.abs(one.cylinder_force[0])]
            for name, v in zip([*r.pins, "boom", "arm", "bucket"], values, strict=True):
                seen.setdefault(name, {})[(r.case, i)] = float(v)
    assert [m.name for m in maxima] == [*results[0].pins, "boom", "arm", "bucket"]
    for m in maxima:
        best = max(seen[m.name].values())
        assert abs(m.value) == pytest.approx(best, rel=1e-12)
        # where it occurs: a pose of that case with that value (ties aside, the largest)
        assert seen[m.name][(m.case, m.index)] == pytest.approx(best, rel=1e-12)
        np.testing.assert_array_equal(m.lengths, L[m.index])
        for case in CASES:
            in_case = max(v for (c, _), v in seen[m.name].items() if c == case)
            assert m.by_case[case] == pytest.approx(in_case, rel=1e-12)


def test_a_given_lift_load_counts_where_it_is_held(machine: Machine) -> None:
    L = stroke_grid(machine, 7)
    cap = hydraulic_lift(machine, L).load
    W = 8000.0 * G
    r = pin_loads(machine, L, "lift", load=W)
    ok = r.forces.ok
    np.testing.assert_array_equal(r.held[ok], (cap >= W)[ok])
    assert 0.2 < r.held.mean() < 0.95
    np.testing.assert_array_equal(r.tool_force[ok], W)
    # the frame carries the load and the front's weight (the files' masses; half of the boom
    # cylinders' rests on the frame directly, outside the front's equilibrium)
    model, mach = _files()
    front = sum(b.get("mass", 0.0) for b in model["bodies"].values() if not b.get("ground"))
    front += (
        sum(c["mass"] for c in mach["cylinders"].values()) - 0.5 * mach["cylinders"]["boom"]["mass"]
    )
    frame = r.forces.pin("A", "frame") + r.forces.pin("C", "frame")
    np.testing.assert_allclose(frame[ok, 0], 0.0, atol=1e-9 * W)
    np.testing.assert_allclose(frame[ok, 1], -(W + front * G), rtol=1e-12)
    maxima = load_maxima([r])
    for m in maxima:
        j = r.pins.index(m.name) if m.kind == "pin" else None
        values = (
            r.load[:, j]
            if j is not None
            else np.abs(r.cylinder_force[:, ("boom", "arm", "bucket").index(m.name)])
        )
        assert abs(m.value) == np.max(values[r.held])
    # the default load is the capacity of each pose
    d = pin_loads(machine, L, "lift")
    np.testing.assert_allclose(d.tool_force[ok], cap[ok], rtol=1e-12)


def test_bad_input_is_refused(machine: Machine) -> None:
    L = _poses(machine, 3, seed=1)
    with pytest.raises(InputError, match="case must be"):
        pin_loads(machine, L, "boom")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="lift case only"):
        pin_loads(machine, L, "arm", load=1e4)
    with pytest.raises(InputError, match="not negative"):
        pin_loads(machine, L, "lift", load=-1.0)
    with pytest.raises(InputError, match=r"shape \(n, 3\)"):
        pin_loads(machine, L[:, :2], "lift")
    with pytest.raises(InputError, match="no load case"):
        load_maxima([])
    far = np.array([[10.0, 10.0, 10.0]])  # assembles nowhere
    r = pin_loads(machine, far, "bucket")
    assert not r.held.any() and np.isnan(r.load).all()
    with pytest.raises(InputError, match="no pose"):
        load_maxima([r])


@pytest.mark.parametrize("gravity", [True, False])
def test_the_default_lift_load_is_the_capacity(machine: Machine, gravity: bool) -> None:
    """One cylinder at its limit (the boom at working pressure, the others at relief), none
    beyond, with or without the front's weight."""
    r = pin_loads(machine, _poses(machine, 40, seed=7), "lift", gravity=gravity)
    ok = r.held
    assert ok.sum() >= 30
    lo, hi = cylinder_limits(machine)
    f = r.cylinder_force[ok]
    scale = np.maximum(np.abs(lo), hi)
    assert np.all(f >= lo - 1e-9 * scale) and np.all(f <= hi + 1e-9 * scale)
    at_limit = np.isclose(f, lo, rtol=1e-9, atol=0) | np.isclose(f, hi, rtol=1e-9, atol=0)
    assert at_limit.any(axis=1).all()
