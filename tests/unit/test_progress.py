"""Progress on long analyses: the analyses report their own work (``progress=``) and the
command line shows it on a terminal's stderr only, never with ``-q``."""

from __future__ import annotations

import io

import pytest
from click.testing import CliRunner

import excavkin
from excavkin.cli import main
from excavkin.cli.progress import staged
from excavkin.excavator.machine_file import load_machine
from excavkin.excavator.search import part


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.fixture(scope="module")
def machine():  # type: ignore[no-untyped-def]
    return load_machine(excavkin.example_path("excavator_machine"))


def fractions(calls: list[tuple[int, int]]) -> list[float]:
    return [d / t for d, t in calls]


def test_working_ranges_report_their_work_and_give_the_same_figures(machine) -> None:  # type: ignore[no-untyped-def]
    from excavkin.excavator.ranges import working_ranges

    calls: list[tuple[int, int]] = []
    with_progress = working_ranges(machine, progress=lambda d, t: calls.append((d, t)))
    f = fractions(calls)
    assert f == sorted(f) and f[-1] == 1.0 and 0 < f[0] < 0.05 and len(f) > 100
    plain = working_ranges(machine)
    assert [x.value for x in with_progress.figures] == [x.value for x in plain.figures]


def test_rated_forces_report_their_searches(machine) -> None:  # type: ignore[no-untyped-def]
    from excavkin.excavator.stability import base_rated_force

    calls: list[tuple[int, int]] = []
    r = base_rated_force(machine, "bucket", progress=lambda d, t: calls.append((d, t)))
    f = fractions(calls)
    assert f == sorted(f) and f[-1] == 1.0
    assert r.rated.force == base_rated_force(machine, "bucket").rated.force


def test_a_part_maps_its_own_count_into_the_tasks() -> None:
    calls: list[tuple[int, int]] = []
    second = part(lambda d, t: calls.append((d, t)), 1, 4)
    assert second is not None
    second(3, 10)
    assert calls == [(13, 40)]
    assert part(None, 1, 4) is None


def test_stages_draw_a_bar_on_a_terminal_only_and_never_when_quiet() -> None:
    for stream, quiet, drawn in ((Terminal(), False, True), (Terminal(), True, False),
                                 (io.StringIO(), False, False)):  # fmt: skip
        with staged("rated forces", 2, quiet=quiet, stream=stream) as next_stage:
            for _ in range(2):
                report = next_stage()
                report(1, 2)
                report(2, 2)
        assert ("rated forces" in stream.getvalue()) is drawn


def test_long_commands_take_quiet_and_print_no_bar_off_a_terminal() -> None:
    for args in (
        ["excavator", "ranges", "excavator_machine", "-q"],
        ["optimize", "crank_rocker", "-q"],
    ):
        r = CliRunner().invoke(main, args)
        assert r.exit_code == 0, r.output
        assert "━" not in r.output and "optimising" not in r.output


def test_tolerance_bands_report_each_batch_of_draws() -> None:
    import numpy as np

    from excavkin.studies.tolerance import tolerance_bands

    mech = excavkin.load(excavkin.example_path("fourbar"))
    sweep = {"crank": np.radians(np.arange(0.0, 360.0, 10.0))}
    calls: list[tuple[int, int]] = []
    kw = {"tolerances": {"A-B": "±0.1 mm"}, "draws": 50_000, "columns": ["B.y"]}
    bands = tolerance_bands(mech, sweep, progress=lambda d, t: calls.append((d, t)), **kw)
    assert calls[-1] == (50_000, 50_000) and len(calls) > 1
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)
    np.testing.assert_array_equal(bands.mc_max, tolerance_bands(mech, sweep, **kw).mc_max)


def test_pin_loads_report_their_steps(machine) -> None:  # type: ignore[no-untyped-def]
    from excavkin.excavator.pin_loads import pin_loads
    from excavkin.excavator.ranges import stroke_grid

    calls: list[tuple[int, int]] = []
    pin_loads(machine, stroke_grid(machine, 5), "arm", progress=lambda d, t: calls.append((d, t)))
    assert calls == [(1, 3), (2, 3), (3, 3)]


@pytest.mark.parametrize(
    "args",
    [
        ["excavator", "forces", "excavator_machine", "-q"],
        ["excavator", "pins", "excavator_machine", "--samples", "5", "-q"],
        ["excavator", "cycle", "excavator_machine", "-q"],
        ["tolerance", "fourbar", "--sweep", "crank=0deg:360deg:7", "--tol", "A-B=±0.1mm",
         "--draws", "1000", "-q"],
    ],
)  # fmt: skip
def test_more_commands_take_quiet(args: list[str]) -> None:
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    assert "━" not in r.output


def test_a_simulation_reports_its_solve(tmp_path) -> None:  # type: ignore[no-untyped-def]
    import numpy as np

    from excavkin.motion import get_law
    from excavkin.simulation.timeline import simulate

    mech = excavkin.load(excavkin.example_path("pasika_module"))
    calls: list[tuple[int, int]] = []
    law = {"cyl": get_law("cubic", 0.5, 5.0)}
    res = simulate(mech, law, samples=1001, progress=lambda d, t: calls.append((d, t)))
    assert calls and calls[-1] == (1001, 1001)
    np.testing.assert_array_equal(
        res.column("rocker.epsilon"), simulate(mech, law, samples=1001).column("rocker.epsilon")
    )
    out = tmp_path / "run.csv"
    args = ["simulate", str(excavkin.example_path("pasika_module")), "--drive",
            "cyl=cubic:500mm:5s", "-o", str(out), "-q"]  # fmt: skip
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
