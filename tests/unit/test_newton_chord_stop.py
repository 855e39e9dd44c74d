"""A chord step whose successor would be far below the tolerance ends a sample's Newton
iteration (`excavkin.step_kinds.newton_solve.CHORD_STOP`): the pass that only confirmed it is
not made, and the positions move by less than the tolerance (1e-14 of the size)."""

from __future__ import annotations

import numpy as np
import pytest

from excavkin import Mechanism
from excavkin.kinematics import compiled_newton
from excavkin.step_kinds import newton_emit, newton_solve
from tests.property.test_random_linkages import TRIAD, triad


def _solve(mech: Mechanism, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    res = mech.solve({"crank": q}, rates={"crank": 1.3}, accels={"crank": -0.4}, backend="numpy")
    return res.positions, res.velocities, res.status.code


def test_the_stop_saves_passes_and_moves_nothing_beyond_the_tolerance(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    mech = Mechanism(triad(TRIAD))
    q = mech.sketch_values()["crank"] + np.linspace(-np.pi, np.pi, 20_001)
    calls = {"n": 0}
    system = newton_solve._system

    def counted(*args: object, **kw: object) -> object:
        calls["n"] += 1
        return system(*args, **kw)  # type: ignore[arg-type]

    monkeypatch.setattr(newton_solve, "_system", counted)
    x, v, code = _solve(mech, q)
    with_stop = calls["n"]
    monkeypatch.setattr(newton_solve, "CHORD_STOP", 0.0)  # never: the step below 1e-14 alone
    calls["n"] = 0
    x0, v0, code0 = _solve(mech, q)
    assert calls["n"] > with_stop  # passes saved
    np.testing.assert_array_equal(code, code0)
    assert (code == 0).all()
    size = mech.plan.scale
    np.testing.assert_allclose(x, x0, rtol=0, atol=1e-14 * size)
    np.testing.assert_allclose(v, v0, rtol=1e-12, atol=1e-12)


def test_the_compiled_iteration_stops_as_numpy_does() -> None:
    """The generated positions kernel has the same stop, from the same constant."""
    text = compiled_newton.source(Mechanism(triad(TRIAD)).plan)
    assert newton_emit.CHORD_STOP == newton_solve.CHORD_STOP
    stop = f"if chord and size * size <= {newton_solve.CHORD_STOP} * small * last:"
    assert text.count(stop) == 1
