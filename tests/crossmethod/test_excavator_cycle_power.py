"""Power along the dig–swing–dump cycle against energy: over each phase the cylinders' work
equals the rise of the front's potential energy (its mass points) plus that of its kinetic
energy (the engine's body velocities), computed without the kinetostatics."""

from __future__ import annotations

import numpy as np
import pytest

import excavkin
from excavkin.excavator.cycle_power import PHASES, cycle_power
from excavkin.excavator.hydraulics import cycle_time
from excavkin.excavator.machine_file import load_machine
from excavkin.kinetostatics import kinetic_energy


@pytest.fixture(scope="module")
def machine():  # type: ignore[no-untyped-def]
    return load_machine(excavkin.example_path("excavator_machine"))


def test_each_phases_work_is_the_rise_of_potential_and_kinetic_energy(machine) -> None:  # type: ignore[no-untyped-def]
    n = 2001
    c = cycle_power(machine, samples=n)
    res = machine.solve(c.lengths, c.rates)
    mp = machine.mass_points
    height = mp.locate(res.positions)[:, :, 1]
    energy = machine.gravity * height @ mp.mass + kinetic_energy(res)
    scale = max(abs(p.work) for p in c.phases)
    for i, p in enumerate(c.phases):
        e = energy[i * n : (i + 1) * n]
        assert p.work == pytest.approx(e[-1] - e[0], abs=1e-7 * scale), p.name


def test_the_cycle_is_the_sequential_cycle_and_returns_to_its_start(machine) -> None:  # type: ignore[no-untyped-def]
    c = cycle_power(machine, samples=5)
    assert c.time[-1] == pytest.approx(cycle_time(machine).sequential, rel=1e-14)
    np.testing.assert_array_equal(c.lengths[0], c.lengths[-1])
    assert [p.name for p in c.phases] == [name for name, _, _ in PHASES]
    # one cylinder moves at a time, at its full-flow speed, over its full stroke
    for i, p in enumerate(c.phases):
        rates = c.rates[i * 5 : (i + 1) * 5]
        moving = np.flatnonzero(np.any(rates != 0.0, axis=0))
        assert len(moving) == (0 if p.role is None else 1)
        if p.role is not None:
            stroke = machine.cylinders[moving[0]].stroke
            assert abs(rates[0, moving[0]]) * p.duration == pytest.approx(stroke, rel=1e-14)


def test_a_phase_beyond_the_working_pressure_is_named(machine) -> None:  # type: ignore[no-untyped-def]
    c = cycle_power(machine, samples=101)
    for p in c.phases:
        if p.role is None:
            assert p.peak == 0.0 and p.work == 0.0
            continue
        beyond = p.peak_pressure > p.working_pressure
        assert (p.over_pressure > 0.0) == beyond


def test_samples_must_suit_simpsons_rule(machine) -> None:  # type: ignore[no-untyped-def]
    from excavkin.errors import InputError

    with pytest.raises(InputError, match="odd"):
        cycle_power(machine, samples=100)
