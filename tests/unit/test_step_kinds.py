"""Step kinds: one module each, a registry (`excavkin.step_kinds`).

Every registered kind implements every operation; a kind that leaves one out is refused when
it registers, with the operation named; every step of every built-in example's plan is of a
registered kind, and the kinds' data agree with the plans (each point placed once, each
driver's effort carried once, the compiled constants read as many times as listed).
"""

from __future__ import annotations

import inspect
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import excavkin
from excavkin.families import load_machine
from excavkin.kinematics import compiled as compiled_plan
from excavkin.step_kinds import (
    OPERATIONS,
    Attach,
    CamRockerStep,
    CamStep,
    Dyad,
    Fixed,
    GearStep,
    NewtonGroup,
    RackStep,
    Rotate,
    SliderStep,
    StepKind,
    kind_of,
    register,
    registered,
)
from excavkin.step_kinds.base import ATTRIBUTES, missing_operations
from excavkin.structure.plan import SolvePlan


def _plans() -> dict[str, SolvePlan]:
    """The solve plan of every built-in example: models, and the machines' mechanisms."""
    out = {name: excavkin.load(name).plan for name in excavkin.examples("model")}
    for name in excavkin.examples("machine"):
        out[name] = load_machine(name).mechanism.plan
    # a gear train, a rack and a cam (no built-in example has them), from the tests' data
    out["planetary"] = excavkin.load(DATA / "planetary_21_43_108.toml").plan
    out["rack on an arm"] = excavkin.load(DATA / "rack_on_arm.toml").plan
    out["disc cam"] = excavkin.load(DATA / "disc_cam.toml").plan
    out["cam rocker"] = excavkin.load(DATA / "cam_rocker.toml").plan
    return out


DATA = Path(__file__).parents[1] / "reference" / "data"


PLANS = _plans()


def test_the_ten_kinds_are_registered() -> None:
    kinds = {Fixed, Rotate, Attach, Dyad, SliderStep, NewtonGroup, GearStep, RackStep, CamStep}
    kinds.add(CamRockerStep)
    assert set(registered()) == kinds
    names = [kind.name for kind in registered().values()]
    assert len(set(names)) == len(names)


@pytest.mark.parametrize("record", list(registered()), ids=lambda r: r.__name__)
def test_every_kind_implements_every_operation(record: type) -> None:
    kind = registered()[record]
    cls = type(kind)
    assert missing_operations(cls) == []
    assert cls.record is record
    for op in OPERATIONS:
        fn = inspect.getattr_static(cls, op)
        # its own code, not the base's abstract placeholder
        assert fn is not inspect.getattr_static(StepKind, op), op
        assert not getattr(fn, "__isabstractmethod__", False), op
    assert isinstance(cls.compiles, bool) and isinstance(cls.iterative, bool)


def _all_but(skip: str) -> dict[str, Any]:
    """A kind's class body with every operation but ``skip``."""

    def op(self: object, *args: object, **kwargs: object) -> None:
        return None

    body: dict[str, Any] = {name: op for name in OPERATIONS if name != skip}
    body.update(name="probe", record=complex, compiles=False, iterative=False)
    return body


@pytest.mark.parametrize("missing", OPERATIONS)
def test_an_incomplete_kind_is_refused_naming_the_operation(missing: str) -> None:
    before = registered()
    cls = type("Incomplete", (StepKind,), _all_but(missing))
    with pytest.raises(TypeError, match=rf"step kind Incomplete does not implement: {missing}$"):
        register(cls)
    assert registered() == before


def test_a_kind_without_its_record_is_refused() -> None:
    body = _all_but("")
    del body["record"]
    cls = type("NoRecord", (StepKind,), body)
    with pytest.raises(TypeError, match="does not implement: record"):
        register(cls)
    assert "record" in ATTRIBUTES


def test_a_complete_probe_registers_and_a_second_for_its_record_is_refused() -> None:
    cls = type("Probe", (StepKind,), _all_but(""))
    try:
        register(cls)
        assert type(kind_of(1j)) is cls
        again = type("Again", (StepKind,), _all_but(""))
        with pytest.raises(TypeError, match="record complex is registered already, by Probe"):
            register(again)
    finally:
        from excavkin.step_kinds.base import REGISTRY

        REGISTRY.pop(complex, None)
    with pytest.raises(TypeError, match="no step kind is registered for complex"):
        kind_of(1j)


def test_not_a_kind_is_refused() -> None:
    with pytest.raises(TypeError, match="is not a StepKind"):
        register(int)  # type: ignore[type-var]


def test_the_examples_cover_every_kind() -> None:
    seen = {type(st) for plan in PLANS.values() for st in plan.steps}
    assert seen == set(registered())


@pytest.mark.parametrize("name", sorted(PLANS))
def test_every_step_of_every_example_is_registered(name: str) -> None:
    plan = PLANS[name]
    for st in plan.steps:
        assert type(st) in registered()
        kind = kind_of(st)
        assert isinstance(kind.describe(st, plan.points), str)
    assert plan.describe().count("\n") == len(plan.steps) - 1


@pytest.mark.parametrize("name", sorted(PLANS))
def test_roles_place_each_point_once_and_carry_each_effort_once(name: str) -> None:
    plan = PLANS[name]
    placed: list[int] = []
    efforts: list[int] = []
    for st in plan.steps:
        role = kind_of(st).role(st)
        placed += role.places
        efforts += role.efforts
    assert sorted(placed) == list(range(len(plan.points)))
    assert sorted(efforts) == list(range(len(plan.inputs)))


@pytest.mark.parametrize("name", sorted(PLANS))
def test_drawings_mark_known_points_and_every_placed_one(name: str) -> None:
    plan = PLANS[name]
    for st in plan.steps:
        kind = kind_of(st)
        marks = kind.drawing(st)
        drawn = {p for m in marks for p in m.points}
        assert drawn <= set(range(len(plan.points)))
        assert set(kind.role(st).places) <= drawn


@pytest.mark.parametrize("name", sorted(PLANS))
def test_transmissions_and_folding_dyads_match_the_plan(name: str) -> None:
    plan = PLANS[name]
    indices = [kind_of(st).transmission(st) for st in plan.steps]
    given = sorted(i for i in indices if i is not None)
    assert given == list(range(len(plan.transmissions)))
    for k, st in enumerate(plan.steps):
        for place, d in kind_of(st).folding(st):
            turned = kind_of(st).turn(st, place, -1.0)
            (_, flipped) = next(f for f in kind_of(turned).folding(turned) if f[0] == place)
            assert flipped.sign == -d.sign
            assert kind_of(turned) is kind_of(st), k


@pytest.mark.parametrize("name", sorted(PLANS))
def test_compiled_constants_are_read_as_listed(name: str) -> None:
    plan = PLANS[name]
    if not compiled_plan.supports(plan):
        with pytest.raises(TypeError, match="cannot be compiled"):
            compiled_plan.source(plan)
        return
    text = compiled_plan.source(plan)
    listed = compiled_plan.constants(plan)
    read = [int(i) for i in re.findall(r"K\[(\d+), j\]", text)]
    assert len(set(read)) == len(read) and max(read) < len(listed)
    # a driven length's entry is listed (as 0.0) but read from the inputs instead
    driven = sum(len(kind_of(st).role(st).efforts) for st in plan.steps if type(st) is not Rotate)
    assert len(listed) - len(read) == driven
    assert all(listed[i] == 0.0 for i in set(range(len(listed))) - set(read))
    assert all(np.ndim(v) == 0 for v in listed)


def test_the_old_import_paths_name_the_same_objects() -> None:
    from excavkin import step_kinds
    from excavkin.kinematics import kernels, newton, small_systems
    from excavkin.step_kinds import newton_solve, state
    from excavkin.step_kinds import small_systems as moved
    from excavkin.structure import plan

    for name in ("Fixed", "Rotate", "Attach", "Dyad", "SliderStep", "NewtonGroup", "Dist"):
        assert getattr(plan, name) is getattr(step_kinds, name)
    for name in ("CDist", "CFrame", "CLine", "CAngle", "GroupDyad"):
        assert getattr(plan, name) is getattr(step_kinds, name)
    assert kernels.Chunk is state.Chunk and kernels.Code is state.Code
    assert newton.newton_positions is newton_solve.newton_positions
    assert small_systems.Factors is moved.Factors


def test_a_plan_with_a_step_of_no_kind_is_refused_by_name() -> None:
    import dataclasses

    plan = PLANS["fourbar"]
    odd = dataclasses.replace(plan, steps=(*plan.steps, "not a step"))
    with pytest.raises(TypeError, match="no step kind is registered for str"):
        odd.describe()
