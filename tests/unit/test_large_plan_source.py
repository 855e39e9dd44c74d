"""Issue 28 (first part): the compiled plan's generated source for a large model. On a chain of
33 four-bar stages the vectoriser folded an ``and`` of many operands into one chain as deep as
it was long, and ``ast.unparse`` raised RecursionError; the default path reached it at 2¹⁷
samples, so that such a model could not be solved at all with numba installed."""

from __future__ import annotations

import ast

import numpy as np
import pytest

from excavkin import Body, Mechanism, Model, RotaryDriver, backends
from excavkin.kinematics import compiled
from excavkin.kinematics.vectorise import vectorised


def chain(stages: int) -> Model:
    """A crank driving a chain of four-bars: each stage's rocker is the next one's crank."""
    points = {"G0": (0.0, 0.0), "P0": (0.0, 0.4)}
    bodies = [Body("crank", ("G0", "P0"))]
    for k in range(1, stages + 1):
        points[f"G{k}"] = (float(k), 0.0)
        points[f"P{k}"] = (k + 0.3 * (k % 2), 0.8)
        bodies += [
            Body(f"coupler{k}", (f"P{k - 1}", f"P{k}"), mass=1.0),
            Body(f"rocker{k}", (f"G{k}", f"P{k}"), mass=1.0),
        ]
    ground = Body("ground", tuple(f"G{k}" for k in range(stages + 1)), ground=True)
    return Model(
        name=f"chain of {stages} four-bars",
        points=points,
        bodies=(ground, *bodies),
        rotary=(RotaryDriver("crank", body="crank", pivot="G0", reference="ground"),),
    )


def _depth(node: ast.AST) -> int:
    """The deepest nesting of expressions under ``node`` (iteratively: no recursion limit)."""
    deepest, stack = 0, [(node, 1)]
    while stack:
        n, d = stack.pop()
        deepest = max(deepest, d)
        stack += [(c, d + 1) for c in ast.iter_child_nodes(n)]
    return deepest


def test_the_source_of_a_300_point_chain_is_generated_shallow() -> None:
    mech = Mechanism(chain(149))
    assert len(mech.plan.points) == 300
    text = vectorised(compiled.source(mech.plan, write_at_rest=False), False)
    tree = ast.parse(text)
    # the statuses' `and` of every output is a balanced tree: its depth grows as log n
    assert _depth(tree) < 60
    for per_sample in (False, True):  # a family of designs' kernel too
        ast.parse(vectorised(compiled.source(mech.plan, write_at_rest=False), per_sample))


def test_a_large_chain_solves_by_default_at_a_compiled_size() -> None:
    """At 2¹⁷ samples the default path looks for a compiled kernel; a plan of more than
    `AUTO_POINTS` points is not compiled unasked, and solves in NumPy."""
    mech = Mechanism(chain(33))
    assert len(mech.plan.points) > compiled.AUTO_POINTS
    job = compiled.job(mech.plan)
    assert backends.choose("auto", job, backends.COMPILE_AT) is backends.NUMPY
    q = np.pi / 2 + np.linspace(-0.05, 0.05, 1 << 17)
    result = mech.solve({"crank": q})
    assert result.status.all_ok
    small = mech.solve({"crank": q[::4096]})
    np.testing.assert_array_equal(result.positions[::4096], small.positions)


@pytest.mark.parametrize("functions", [True, False])
def test_a_kernel_cut_in_passes_gives_the_same_numbers(
    monkeypatch: pytest.MonkeyPatch, functions: bool
) -> None:
    """A large plan's loop body is cut into passes of `vectorise.PASS` statements, each a
    kernel of its own, the values carried between them in typed scratch rows: cut small here,
    the four-bar's kernel (a family of designs', and one that keeps some columns' rows)
    gives the one-pass kernel's numbers and statuses to the bit, failing samples included,
    and numba sees no name assigned twice in a pass."""
    from excavkin import example_path, load
    from excavkin.kinematics import vectorise

    def solve() -> list[np.ndarray]:
        vectorise.vectorised.cache_clear()
        mech = load(example_path("fourbar"))
        q = {"crank": np.linspace(0.0, 12.0, 3000)}
        r = {"crank": np.full(3000, 0.7)}
        one = mech.solve(q, r, backend="numba")
        params = {"A-B": np.linspace(0.5, 4.0, 3000) * mech.parameters["A-B"]}
        fam = mech.solve(q, r, params=params, backend="numba")
        asked = ["B.x", "B.vy", "rocker.angle", "crank.value"]  # a kernel that keeps rows
        (part,) = mech.solve_stream(q, r, columns=asked, backend="numba")
        some = part.to_frame()
        return [
            *(getattr(res, f) for res in (one, fam) for f in ("positions", "accelerations")),
            one.body_angle, one.transmission, one.status.code, fam.status.code,
            *(some[c].to_numpy() for c in asked), some["status"].to_numpy().astype(str),
        ]  # fmt: skip

    whole = solve()
    monkeypatch.setattr(vectorise, "PASS", 23)
    if not functions:  # the passes in one function (a plan of a few passes)
        monkeypatch.setattr(vectorise, "SPLIT_PASSES", 10**6)
    text = vectorised(compiled.source(Mechanism(chain(1)).plan, write_at_rest=False), False)
    assert text.count("for l") > 10 and "SL_" in text  # passes, booleans carried
    tree = ast.parse(text)
    passes = [f for f in tree.body if isinstance(f, ast.FunctionDef) and f.name[:4] == "pass"]
    if not functions:
        passes = [f for f in tree.body if isinstance(f, ast.FunctionDef) and f.name == "kernel"]
    assert len(passes) > 5 or not functions  # a kernel of its own for each pass
    if functions:  # each later pass copies the inputs into their rows again (vectorised so)
        assert all("T_q[" in ast.unparse(f) for f in passes)
    for kernel in passes:
        assigned = [t.id for n in ast.walk(kernel) if isinstance(n, ast.Assign)
                    for t in n.targets if isinstance(t, ast.Name)]  # fmt: skip
        assert len(assigned) == len(set(assigned))
    fourbar = compiled.source(load(example_path("fourbar")).plan, write_at_rest=False)
    assert ("def pass2_(" in vectorised(fourbar, False)) == functions
    cut = solve()
    assert (np.asarray(whole[-1]) != 0).any()  # some designs fail
    for a, b in zip(whole, cut, strict=True):
        np.testing.assert_array_equal(a, b)


def test_auto_solves_a_split_kernels_plan_in_numpy(monkeypatch: pytest.MonkeyPatch) -> None:
    """A kernel split into a kernel for each pass runs slower than NumPy: ``"auto"`` keeps
    NumPy for it at any size (cached or not), a backend named still runs it, and a kernel of
    one function is taken as before."""
    from excavkin import example_path, load
    from excavkin.kinematics import vectorise

    whole = load(example_path("fourbar")).plan
    vectorise.vectorised.cache_clear()
    assert not compiled.split(compiled.kernel_source(whole))
    assert backends.choose("auto", compiled.job(whole), 10**6).name == "numba"
    monkeypatch.setattr(vectorise, "PASS", 23)
    vectorise.vectorised.cache_clear()
    cut = load(example_path("fourbar")).plan
    assert compiled.split(compiled.kernel_source(cut))
    assert backends.choose("auto", compiled.job(cut), 10**6).name == "numpy"
    assert backends.choose("numba", compiled.job(cut), 10).name == "numba"
    vectorise.vectorised.cache_clear()
