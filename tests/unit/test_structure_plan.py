"""The plan builder directly: which step places each point, errors naming the entry, every
constraint used once, and no function of the core longer than about 100 lines."""

from __future__ import annotations

import ast
import threading
from pathlib import Path

import numpy as np
import pytest

import excavkin
from excavkin.errors import AssemblyError, MobilityError
from excavkin.mechanism import Mechanism
from excavkin.structure.builder import PlanBuilder, compile_plan
from excavkin.structure.plan import Attach, Dyad, Fixed, NewtonGroup, Rotate, SliderStep
from tests.property.test_random_linkages import TRIAD, triad

SRC = Path(excavkin.__file__).parent


def kinds(plan: excavkin.structure.SolvePlan) -> dict[str, str]:
    """Point name → the kind of step that places it."""
    out: dict[str, str] = {}
    for st in plan.steps:
        if isinstance(st, Fixed):
            out |= {plan.points[i]: "fixed" for i in st.points}
        elif isinstance(st, NewtonGroup):
            out |= {plan.points[i]: "newton" for i in st.points}
        else:
            kind = {Rotate: "rotate", Attach: "attach", Dyad: "dyad", SliderStep: "slider"}
            out[plan.points[st.point]] = kind[type(st)]
    return out


def test_fourbar_is_fixed_rotate_dyad() -> None:
    plan = excavkin.load(excavkin.example_path("fourbar")).plan
    assert kinds(plan) == {"O2": "fixed", "O4": "fixed", "A": "rotate", "B": "dyad"}
    dyad = next(st for st in plan.steps if isinstance(st, Dyad))
    # B = (110, 90) mm lies left of A → O4 in the sketch: the branch sign is +
    assert dyad.sign == 1.0 and dyad.da.value == pytest.approx(0.120, abs=1e-15)


def test_slider_crank_places_pin_and_piston_by_slider_steps() -> None:
    plan = excavkin.load(excavkin.example_path("slider_crank")).plan
    assert kinds(plan) == {
        "O2": "fixed",
        "G1": "fixed",
        "G2": "fixed",
        "A": "rotate",
        "B": "slider",
        "C": "slider",
    }
    # the piston's second point C is placed by its own slide, 40 mm from B on body 'piston'
    c = next(
        st for st in plan.steps if isinstance(st, SliderStep) and st.slider == "piston_on_slide"
    )
    assert plan.points[c.a] == "B" and c.da.value == pytest.approx(0.040, abs=1e-15)


def test_a_triad_is_one_newton_group_and_method_newton_puts_everything_there() -> None:
    plan = Mechanism(triad(TRIAD)).plan
    groups = [st for st in plan.steps if isinstance(st, NewtonGroup)]
    assert len(groups) == 1 and plan.has_newton
    fourbar = excavkin.load(excavkin.example_path("fourbar")).model
    newton = compile_plan(fourbar, method="newton")
    assert kinds(newton) == {"O2": "fixed", "O4": "fixed", "A": "newton", "B": "newton"}


def test_every_constraint_is_used_exactly_once_in_every_example() -> None:
    for path in sorted((SRC.parents[1] / "examples").glob("*.toml")):
        if path.stem.endswith("_machine"):  # machine files (excavator, wheel loader)
            continue
        model = excavkin.load(path).model
        builder = PlanBuilder(model, "closed-form")
        builder.build()
        need = [0 if b.ground else 2 * len(b.points) - 3 for b in model.bodies]
        assert builder.body_used == need, path.stem
        driven_or_locked = {i for i, e in enumerate(builder.elements) if e.mode != "free"}
        assert builder.used_elem == driven_or_locked, path.stem
        assert builder.used_rotary == set(range(len(model.rotary))), path.stem


FOURBAR = excavkin.example_path("fourbar").read_text()


def test_a_redundant_driver_is_named() -> None:
    text = FOURBAR + '\n[drivers.extra]\ntype = "linear"\nbetween = ["A", "O4"]\n'
    with pytest.raises((MobilityError, excavkin.ModelError), match="extra|mobility|driver"):
        excavkin.loads(text, "redundant")


def test_a_dyad_drawn_on_its_base_line_is_refused_naming_the_point() -> None:
    # B drawn exactly on the line through A = (0, 40) and O4 = (100, 0), lengths from the sketch
    text = FOURBAR.replace("B  = [110, 90]", "B  = [50, 20]")
    text = text.replace('"A-B"  = 120\n', "").replace('"O4-B" = 90\n', "")
    with pytest.raises(AssemblyError, match="point B lies on the line through"):
        excavkin.loads(text, "collinear")


def test_engine_progress_is_serialised_monotone_and_changes_nothing() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    q = np.linspace(0.0, 2 * np.pi, 100_001)
    calls: list[tuple[int, int, str]] = []
    inside = threading.Lock()

    def progress(done: int, total: int) -> None:
        assert inside.acquire(blocking=False), "two progress calls at once"
        calls.append((done, total, threading.current_thread().name))
        inside.release()

    with_cb = mech.solve({"crank": q}, workers=2, chunk=7000, progress=progress)
    without = mech.solve({"crank": q}, workers=1)
    done = [c[0] for c in calls]
    assert done == sorted(done) and done[-1] == q.size and len(calls) == -(-q.size // 7000)
    assert {c[1] for c in calls} == {q.size}
    np.testing.assert_array_equal(with_cb.positions, without.positions)
    np.testing.assert_array_equal(with_cb.body_epsilon, without.body_epsilon)


CORE = ("structure", "kinematics", "kinetostatics")


@pytest.mark.parametrize("package", CORE)
def test_no_function_of_the_core_is_longer_than_100_lines(package: str) -> None:
    long = []
    for path in sorted((SRC / package).rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                n = node.end_lineno - node.lineno + 1  # type: ignore[operator]
                if n > 100:
                    long.append(f"{path.name}:{node.name} ({n} lines)")
    assert not long
