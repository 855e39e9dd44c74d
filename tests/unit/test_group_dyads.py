"""The dyads inside a Newton group: found as the closed form's, and kept on their sides."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from excavkin import Mechanism
from excavkin.kinematics.kernels import Chunk
from excavkin.kinematics.newton import newton_positions, side
from excavkin.kinematics.solve import assemble
from excavkin.structure.plan import Dyad, NewtonGroup
from tests.models import fourbar_model, parallelogram
from tests.property.test_random_linkages import TRIAD, triad, watt_sixbar

WATT = {
    "O2": (0.0, 0.0),
    "A": (0.1, 0.35),
    "B": (0.8, 0.9),
    "O4": (1.0, 0.0),
    "C": (1.4, 0.8),
    "D": (2.0, 1.3),
    "O6": (2.2, 0.1),
}


def dyads_of(model) -> tuple[list[tuple], list[tuple]]:  # noqa: ANN001
    """(point, a, b, sign) of the closed form's dyad steps and of the Newton group's dyads."""
    closed, newton = Mechanism(model).plan, Mechanism(model, method="newton").plan
    steps = [(s.point, s.a, s.b, s.sign) for s in closed.steps if isinstance(s, Dyad)]
    (group,) = [s for s in newton.steps if isinstance(s, NewtonGroup)]
    return steps, [(d.point, d.a, d.b, d.sign) for d in group.dyads]


def test_a_group_knows_the_closed_forms_dyads() -> None:
    model = fourbar_model({"O2": (0, 0), "A": (0, 0.4), "B": (0.9, 0.7), "O4": (1.0, 0)})
    steps, inside = dyads_of(model)
    assert inside == steps and len(steps) == 1
    # a six-bar's two, in solve order: C (on the rocker with B) is peeled between them
    steps, inside = dyads_of(watt_sixbar(WATT))
    assert inside == steps and len(steps) == 2


def test_a_class_three_group_has_none() -> None:
    (group,) = [s for s in Mechanism(triad(TRIAD)).plan.steps if isinstance(s, NewtonGroup)]
    assert group.dyads == ()


def test_a_dyad_started_on_the_wrong_side_comes_back() -> None:
    """Newton from the mirrored configuration converges there (it is a solution): the group
    moves B back to its sketch side, and with the side turned per sample, over to the other."""
    plan = Mechanism(parallelogram(), method="newton").plan
    (k, group) = next((k, s) for k, s in enumerate(plan.steps) if isinstance(s, NewtonGroup))
    (dyad,) = group.dyads
    sketch = assemble(plan).positions
    b, a, o4 = sketch[dyad.point], sketch[dyad.a], sketch[dyad.b]
    e = o4 - a
    mirrored = a + 2 * np.dot(b - a, e) / np.dot(e, e) * e - (b - a)
    x = np.repeat(sketch[:, :, None], 2, axis=2)
    x[dyad.point] = mirrored[:, None]
    q = np.full((1, 2), plan.input_sketch[0])
    zero = np.zeros((1, 2))
    status, failed = np.zeros(2, dtype=np.int8), np.full(2, -1, dtype=np.int16)
    chunk = Chunk(
        x, x.copy(), x.copy(), q, zero, zero, np.zeros((0, 2)), status, failed, 1e-10, 1e-7
    )
    turned = np.array([dyad.sign, -dyad.sign])  # sample 1 kept on the other side
    signed = replace(group, dyads=(replace(dyad, sign=turned),))
    newton_positions(chunk, signed, k, plan.scale)
    assert (chunk.status == 0).all()
    np.testing.assert_allclose(chunk.x[:, :, 0], sketch, rtol=0, atol=1e-15)
    np.testing.assert_allclose(chunk.x[dyad.point, :, 1], mirrored, rtol=0, atol=1e-15)
    assert np.sign(side(chunk.x, dyad)).tolist() == turned.tolist()
