"""Issue 17 ("Trust and the first hour"): a model of thousands of points checks and compiles.

The plan builder offers each step kind only what a newly placed point may have made ready,
instead of scanning the whole model after every step; these tests check that the plan of a
large generated model is the one its structure dictates (every step, in order, each point
placed once from points already placed), and that a small model whose points and bodies are
listed in a shuffled order gets exactly the plan of a plain scan in the order the builder
documents: attach first, then the first rotary driver, the first dyad point in the file's
order, the first slider.
"""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from click.testing import CliRunner

import excavkin
from excavkin.cli import main
from excavkin.structure.plan import Attach, Dyad, Fixed, Rotate
from tests.models import fourbar_chain, truss


def _placed_in_order(plan: excavkin.Mechanism) -> None:
    """Every point placed exactly once, each step from points placed before it."""
    steps = plan.plan.steps
    assert isinstance(steps[0], Fixed)
    known = set(steps[0].points)
    for st in steps[1:]:
        before = {
            Rotate: lambda s: (s.pivot,),
            Dyad: lambda s: (s.a, s.b),
            Attach: lambda s: (s.a, s.b),
        }[type(st)](st)
        assert all(i in known for i in before), st
        assert st.point not in known, st
        known.add(st.point)
    assert known == set(range(len(plan.plan.points)))


def _holds_its_bars(mech: excavkin.Mechanism, n_samples: int) -> None:
    """Solved over a few crank angles: every two-point body keeps its sketch length."""
    q = mech.sketch_values()["crank"] + np.linspace(-0.05, 0.05, n_samples)
    res = mech.solve({"crank": q})
    assert res.status.all_ok
    names = {n: i for i, n in enumerate(mech.plan.points)}
    sketch = mech.model.points
    for b in mech.model.bodies:
        if len(b.points) == 2 and not b.ground:
            i, j = names[b.points[0]], names[b.points[1]]
            length = math.dist(sketch[b.points[0]], sketch[b.points[1]])
            got = np.hypot(*(res.positions[:, i] - res.positions[:, j]).T)
            np.testing.assert_allclose(got, length, rtol=1e-12, atol=0)
    # at the sketch's own input the sketch comes back
    at = mech.solve({"crank": [mech.sketch_values()["crank"]]})
    np.testing.assert_allclose(at.positions[0], [sketch[n] for n in mech.plan.points], atol=1e-12)


def test_a_2000_point_truss_plans_a_dyad_per_point_in_order() -> None:
    n = 2000
    mech = excavkin.loads(truss(n), "truss")
    steps = mech.plan.steps
    assert len(mech.plan.points) == n
    assert len(steps) == 2 + (n - 3)  # the ground, the crank, a dyad per further point
    assert isinstance(steps[1], Rotate) and mech.plan.points[steps[1].point] == "P1"
    idx = {p: i for i, p in enumerate(mech.plan.points)}
    for k, st in zip(range(3, n), steps[2:], strict=True):
        assert isinstance(st, Dyad)
        assert (st.point, st.a, st.b) == (idx[f"P{k}"], idx[f"P{k - 2}"], idx[f"P{k - 1}"])
    assert mech.plan.mobility.mobility == 1 and mech.inputs == ("crank",)
    # bodies: ground, crank, two bars per dyad; joints: a pair fewer than the bodies at each point
    assert mech.plan.mobility.links == 2 + 2 * (n - 3)
    _placed_in_order(mech)
    _holds_its_bars(mech, 16)


def test_a_2000_point_truss_of_cylinders_plans_each_dyad_by_its_cylinder() -> None:
    n = 2000
    mech = excavkin.loads(truss(n, cylinders=True), "cylinders")
    assert mech.inputs == ("crank", *(f"cyl{k}" for k in range(3, n)))
    assert mech.plan.mobility.mobility == n - 2
    idx = {p: i for i, p in enumerate(mech.plan.points)}
    for k, st in zip(range(3, n), mech.plan.steps[2:], strict=True):
        assert isinstance(st, Dyad)
        assert (st.point, st.a, st.b) == (idx[f"P{k}"], idx[f"P{k - 2}"], idx[f"P{k - 1}"])
        assert st.da.kind == "fixed" and st.db.kind == "input" and st.db.label == f"cyl{k}"
    assert {mech.input_kind(name) for name in mech.inputs[1:]} == {"length"}
    _placed_in_order(mech)
    lengths = {f"cyl{k}": mech.sketch_values()[f"cyl{k}"] * 1.001 for k in range(3, n)}
    res = mech.solve({"crank": [mech.sketch_values()["crank"]], **lengths})
    assert res.status.all_ok
    for k in range(3, n):
        got = np.hypot(*(res.positions[0, idx[f"P{k}"]] - res.positions[0, idx[f"P{k - 1}"]]))
        np.testing.assert_allclose(got, lengths[f"cyl{k}"], rtol=1e-12)


def test_a_2000_point_chain_of_four_bars_plans_a_dyad_and_an_attach_per_stage() -> None:
    stages = 666
    mech = excavkin.loads(fourbar_chain(stages), "chain")
    steps = mech.plan.steps
    assert len(mech.plan.points) == 3 * stages + 1 == 1999
    assert len(steps) == 2 + 2 * stages - 1
    assert len(steps[0].points) == stages + 1  # every O on the ground
    name = mech.plan.points.__getitem__
    for k in range(stages):
        dyad = steps[2 + 2 * k]
        assert isinstance(dyad, Dyad)
        assert (name(dyad.point), name(dyad.a), name(dyad.b)) == (f"B{k}", f"A{k}", f"O{k + 1}")
        if k + 1 < stages:
            attach = steps[3 + 2 * k]
            assert isinstance(attach, Attach) and name(attach.point) == f"A{k + 1}"
            assert attach.body == f"rocker{k}"
    assert mech.plan.mobility.mobility == 1
    _placed_in_order(mech)
    _holds_its_bars(mech, 8)


def test_check_of_a_large_model_prints_every_step(tmp_path) -> None:
    path = tmp_path / "truss.toml"
    path.write_text(truss(2000))
    r = CliRunner().invoke(main, ["check", str(path)])
    assert r.exit_code == 0, r.output
    plan = r.output.split("  plan    :\n")[1].splitlines()
    steps = [line for line in plan if line.startswith("    ") and ". " in line]
    assert len(steps) == 1999
    assert steps[-1].split()[1:4] == ["dyad", "P1999", "from"]
    # by hand: the ground, the crank and two bars a dyad; pairs: one at P0, P1 and the last
    # point, two at P2 and the last but one, three at each point between (four bodies meet)
    n = 2000
    links, pairs = 2 + 2 * (n - 3), 1 + 1 + 2 + 3 * (n - 5) + 2 + 1
    assert f"mobility: M = 3·({links} − 1) − 2·{pairs} − 0 = 1" in r.output
    assert r.output.rstrip().endswith("ok: the model is valid and assembles at its sketch")


def _scan_plan(model: excavkin.Model) -> list[tuple[str, str]]:
    """The plan's order by plain scans of the whole model after every step (what the builder
    documents, for bodies, rotary drivers and two-bar dyads only): (kind, point) per step."""
    known = set(model.ground.points)
    out: list[tuple[str, str]] = []
    pivot_of = {d.body: d.pivot for d in model.rotary}
    used: set[str] = set()

    def partners(p: str) -> list[str]:
        return [a for b in model.bodies if p in b.points for a in b.points if a != p and a in known]

    while len(known) < len(model.points):
        added = False
        for b in model.bodies:  # attach: one pass in body order
            if b.ground:
                continue
            if sum(n in known for n in b.points) >= 2:
                for n in b.points:
                    if n not in known:
                        out.append(("attach", n))
                        known.add(n)
                        added = True
        if added:
            continue
        for d in model.rotary:
            p = next(n for n in model.body(d.body).points if n != pivot_of[d.body])
            if d.name not in used and d.pivot in known and p not in known:
                out.append(("rotate", p))
                known.add(p)
                used.add(d.name)
                break
        else:
            p = next(p for p in model.points if p not in known and len(set(partners(p))) >= 2)
            out.append(("dyad", p))
            known.add(p)
    return out


def _grown(rng: random.Random, steps: int) -> excavkin.Model:
    """A random mechanism grown step by step from a ground of three points: cranks driven
    from the ground, dyads of two bars from two placed points, and points added to a body
    already placed (attached); then listed with its points and bodies shuffled, so that many
    points are ready at once and the order of the file decides."""
    points = {f"G{i}": (rng.uniform(-1, 1), rng.uniform(-1, 1)) for i in range(3)}
    placed = list(points)
    bodies: dict[str, list[str]] = {}
    rotary = []
    for k in range(steps):
        p = f"Q{k}"
        points[p] = (rng.uniform(-1, 1), rng.uniform(-1, 1))
        kind = "crank" if k == 0 else rng.choice(["crank", "dyad", "dyad", "dyad", "grow"])
        if kind == "crank":
            pivot = rng.choice(placed)
            bodies[f"c{k}"] = [pivot, p]
            rotary.append(excavkin.RotaryDriver(f"d{k}", f"c{k}", pivot, "ground"))
        elif kind == "dyad":
            a, b = rng.sample(placed, 2)
            bodies[f"a{k}"], bodies[f"b{k}"] = [a, p], [b, p]
        else:
            bodies[rng.choice(list(bodies))].append(p)
        placed.append(p)
    names = list(points)
    rng.shuffle(names)
    listed = [excavkin.Body(b, tuple(pts)) for b, pts in bodies.items()]
    listed.append(excavkin.Body("ground", ("G0", "G1", "G2"), ground=True))
    rng.shuffle(listed)
    return excavkin.Model(
        "grown", {n: points[n] for n in names}, tuple(listed), rotary=tuple(rotary)
    )


@pytest.mark.parametrize("seed", range(40))
def test_shuffled_small_models_get_the_plan_of_a_plain_scan(seed: int) -> None:
    rng = random.Random(seed)
    if seed < 2:  # the generated chains, shuffled
        base = excavkin.loads(fourbar_chain(12) if seed else truss(30)).model
        names, bodies = list(base.points), list(base.bodies)
        rng.shuffle(names)
        rng.shuffle(bodies)
        model = excavkin.Model(
            base.name, {n: base.points[n] for n in names}, tuple(bodies), rotary=base.rotary
        )
    else:
        model = _grown(rng, rng.randint(4, 40))
    try:
        mech = excavkin.Mechanism(model)
    except excavkin.AssemblyError:  # a random sketch with a dyad drawn on its base line
        return
    kinds = {Attach: "attach", Rotate: "rotate", Dyad: "dyad"}
    got = [(kinds[type(s)], mech.plan.points[s.point]) for s in mech.plan.steps[1:]]
    assert got == _scan_plan(model)
    _placed_in_order(mech)


def test_a_wide_table_is_written_whole_and_its_frame_left_as_it_was(tmp_path) -> None:
    """The writer takes the columns from a view without the frame's attrs (pandas would copy
    the attrs into every column); the frame keeps them and the file has every column."""
    import pandas as pd

    from excavkin.outputs.tables import write_table

    mech = excavkin.loads(truss(200), "truss")
    res = mech.solve({"crank": mech.sketch_values()["crank"] + np.linspace(-0.01, 0.01, 5)})
    frame = res.to_frame()
    attrs = {k: dict(v) if isinstance(v, dict) else v for k, v in frame.attrs.items()}
    for suffix in ("csv", "parquet"):
        path = write_table(frame, tmp_path / f"wide.{suffix}")
        back = pd.read_csv(path) if suffix == "csv" else pd.read_parquet(path)
        assert list(back.columns) == [str(c) for c in frame.columns]
        numeric = [c for c, dtype in frame.dtypes.items() if dtype.kind == "f"]
        np.testing.assert_array_equal(back[numeric].to_numpy(), frame[numeric].to_numpy())
    assert frame.attrs == attrs and frame.attrs
