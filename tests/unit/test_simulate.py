"""Time-domain runs: drives, time grids, one-sided limits and ``excavkin simulate``."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

import excavkin
from excavkin.cli import main
from excavkin.errors import InputError
from excavkin.motion import (
    LAW_NAMES,
    ConstantSpeedCrank,
    Profile,
    RopeWinch,
    TrapezoidalLaw,
    dwell,
    get_law,
)
from excavkin.simulation.timeline import (
    Drive,
    driver_inputs,
    merge_breakpoints,
    normalise_drives,
    simulate,
    time_grid,
)

PASIKA = excavkin.example_path("pasika_module")
FOURBAR = excavkin.example_path("fourbar")


@pytest.fixture(scope="module")
def module() -> excavkin.Mechanism:
    return excavkin.load(PASIKA)


@pytest.fixture(scope="module")
def fourbar() -> excavkin.Mechanism:
    return excavkin.load(FOURBAR)


# ---------------------------------------------------------------------------------- Drive


def test_drive_adds_law_to_initial_or_sketch():
    law = get_law("cubic", 0.5, 5.0, start=1.0)
    t = np.array([0.0, 1.0, 3.5, 6.0, 9.0])
    st = Drive(law).state(t, 0.8)
    ref = law.evaluate(t)
    assert_allclose(st.s, 0.8 + ref.s, rtol=0, atol=1e-15)
    assert_allclose(st.v, ref.v, rtol=0, atol=0)
    assert_allclose(st.a, ref.a, rtol=0, atol=0)
    st2 = Drive(law, initial=1.0).state(t, 0.8)
    assert_allclose(st2.s, 1.0 + ref.s, rtol=0, atol=1e-15)
    # holds before the start and after the end
    assert st.s[0] == 0.8 and st.s[-1] == pytest.approx(1.3, abs=1e-15)
    assert Drive(law).interval == (1.0, 6.0)


def test_winch_shortens_the_rope_and_crank_turns():
    w = RopeWinch(100.0, 0.5, 25.0, 2.0)  # v = 1 m/s hauling in
    st = Drive(w, initial=12.0).state([0.0, 3.0], 0.0)
    assert_allclose(st.s, [12.0, 9.0])
    assert_allclose(st.v, [-1.0, -1.0])
    assert Drive(w).sign == -1.0 and Drive(w).interval is None
    c = Drive(ConstantSpeedCrank(2.0), initial=0.5).state([0.0, 1.5], 9.0)
    assert_allclose(c.s, [0.5, 3.5])
    assert_allclose(c.v, [2.0, 2.0])
    assert Drive(ConstantSpeedCrank(2.0)).breakpoints() == ()


def test_drive_rejects_non_laws():
    with pytest.raises(TypeError, match="law must be"):
        Drive(lambda t: t)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="initial"):
        Drive(get_law("345", 1.0, 1.0), initial=math.nan)


@pytest.mark.parametrize("name", LAW_NAMES)
def test_one_sided_limits_match_acceleration_jumps(name):
    """The drive's one-sided accelerations at the breakpoints are the law's own jumps."""
    law = get_law(name, 0.5, 5.0, start=0.7)
    d = Drive(law)
    times = np.array([tb for tb, _ in d.breakpoints()])
    left, right = d.state(times, 0.0, "left"), d.state(times, 0.0, "right")
    jumps = {j.time: j for j in law.acceleration_jumps()}
    for k, tb in enumerate(times):
        if tb in jumps:
            assert_allclose(
                [left.a[k], right.a[k]],
                [jumps[tb].a_before, jumps[tb].a_after],
                rtol=1e-12,
                atol=1e-15,
            )
        else:
            assert abs(right.a[k] - left.a[k]) <= 1e-9 * law.peak_acceleration
    # s and v are continuous at every breakpoint (no hard shock in any law)
    assert_allclose(left.s, right.s, rtol=0, atol=1e-15)
    assert_allclose(left.v, right.v, rtol=0, atol=1e-15)
    # rest outside: left of the start and right of the end
    assert left.a[0] == 0.0 and left.v[0] == 0.0
    assert right.a[-1] == 0.0 and right.v[-1] == 0.0


def test_profile_breakpoints_and_limits():
    p = Profile.from_laws([get_law("cubic", 0.5, 2.0), dwell(1.0), get_law("cubic", -0.5, 2.0)])
    d = Drive(p)
    bps = d.breakpoints()
    assert [tb for tb, _ in bps] == [0.0, 2.0, 3.0, 5.0]
    assert "join 1" in bps[1][1] and "join 2" in bps[2][1]
    t = np.array([2.0, 3.0])
    left, right = d.state(t, 1.0, "left"), d.state(t, 1.0, "right")
    assert_allclose(left.a, [-0.75, 0.0])
    assert_allclose(right.a, [0.0, -0.75])
    assert_allclose(left.s, [1.5, 1.5])


def test_merge_breakpoints_joins_coincident_times():
    drives = {
        "a": Drive(get_law("cubic", 1.0, 2.0)),
        "b": Drive(get_law("345", 1.0, 1.0, start=1.0)),
    }
    merged = merge_breakpoints(drives)
    assert [tb for tb, _ in merged] == [0.0, 1.0, 2.0]
    assert merged[2][1] == ("a: end of cubic", "b: end of 345")


# ---------------------------------------------------------------------------------- grids


def test_time_grid_union_and_options():
    drives = {
        "a": Drive(get_law("cubic", 1.0, 2.0, start=1.0)),
        "b": Drive(get_law("345", 1.0, 3.0, start=2.0)),
    }
    t = time_grid(drives, samples=9)
    assert t[0] == 1.0 and t[-1] == 5.0 and t.shape == (9,)
    t = time_grid(drives, samples=3, start=0.0, duration=10.0)
    assert_allclose(t, [0.0, 5.0, 10.0])
    crank = {"c": Drive(ConstantSpeedCrank(2 * math.pi))}
    assert time_grid(crank, samples=5)[-1] == pytest.approx(1.0)
    with pytest.raises(InputError, match="duration"):
        time_grid({"w": Drive(RopeWinch(1.0, 1.0, 1.0))}, samples=5)
    with pytest.raises(InputError, match="at least 2"):
        time_grid(drives, samples=1)
    with pytest.raises(InputError, match="> 0"):
        time_grid(drives, duration=-1.0)


def test_normalise_drives_checks_names_and_kinds(module, fourbar):
    with pytest.raises(InputError, match="unknown driver 'boom'"):
        normalise_drives(module, {"boom": get_law("cubic", 1.0, 1.0)})
    with pytest.raises(InputError, match="crank drives an angle"):
        normalise_drives(module, {"cyl": ConstantSpeedCrank(1.0)})
    with pytest.raises(InputError, match="winch drives a length"):
        normalise_drives(fourbar, {"crank": RopeWinch(1.0, 1.0, 1.0)})
    with pytest.raises(InputError, match="no drives"):
        normalise_drives(module, {})


# ---------------------------------------------------------------------------------- simulate


def test_simulate_feeds_exact_law_values(module):
    law = TrapezoidalLaw(0.5, 5.0, start=1.0, accel_fraction=0.25)
    res = simulate(module, {"cyl": law}, samples=201)
    assert res.time is not None and res.time[0] == 1.0 and res.time[-1] == 6.0
    st = law.evaluate(res.time)
    assert_allclose(res.column("cyl.value"), 0.8 + st.s, rtol=0, atol=1e-12)
    assert_allclose(res.column("cyl.rate"), st.v, rtol=0, atol=1e-13)
    assert_allclose(res.column("cyl.accel"), st.a, rtol=0, atol=1e-13)
    frame = res.to_frame()
    assert frame.columns[0] == "t"
    assert res.status.all_ok


def test_simulate_explicit_times_and_held_drivers(module):
    res = simulate(module, {"cyl": get_law("345", 0.5, 5.0)}, t=[-1.0, 10.0])
    assert_allclose(res.column("cyl.value"), [0.8, 1.3])
    assert_allclose(res.column("rocker.omega"), [0.0, 0.0], atol=1e-15)
    with pytest.raises(InputError, match=r"shape \(n,\)"):
        simulate(module, {"cyl": get_law("345", 0.5, 5.0)}, t=[[0.0, 1.0]])


def test_driver_inputs_side(module):
    law = get_law("cubic", 0.5, 5.0)
    v, r, a = driver_inputs(module, {"cyl": law}, [0.0, 5.0], side="left")
    assert_allclose(a["cyl"], [0.0, -0.12])
    v, r, a = driver_inputs(module, {"cyl": law}, [0.0, 5.0], side="right")
    assert_allclose(a["cyl"], [0.12, 0.0])


# ---------------------------------------------------------------------------------- CLI


def _run(args):
    return CliRunner().invoke(main, args, catch_exceptions=False)


def test_cli_simulate_pasika_module(tmp_path):
    out = tmp_path / "run.csv"
    r = _run(
        [
            "simulate",
            str(PASIKA),
            "--drive",
            "cyl=cubic:500mm:5s",
            "--samples",
            "51",
            "-o",
            str(out),
        ]
    )
    assert r.exit_code == 0, r.output
    frame = pd.read_csv(out)
    assert list(frame.columns[:1]) == ["t"] and len(frame) == 51
    assert_allclose(frame["t"].iloc[-1], 5.0)
    assert_allclose(frame["rocker.epsilon"].iloc[0], 0.12031, atol=5e-6)
    assert "6 soft shock(s)" in r.output and "rocker.epsilon" in r.output
    assert "J·Δε" in r.output
    # refuses to overwrite without --force
    r = CliRunner().invoke(
        main, ["simulate", str(PASIKA), "--drive", "cyl=345:0.5m:5s", "-o", str(out)]
    )
    assert r.exit_code != 0 and "--force" in r.output


def test_cli_simulate_fourbar_crank_and_shock_table(tmp_path):
    out, shocks = tmp_path / "c.csv", tmp_path / "s.csv"
    r = _run(
        [
            "simulate",
            str(FOURBAR),
            "--drive",
            "crank=crank:31.416rad/s:from=0deg",
            "--samples",
            "41",
            "-o",
            str(out),
            "--shock-table",
            str(shocks),
        ]
    )
    assert r.exit_code == 0, r.output
    frame = pd.read_csv(out)
    assert_allclose(frame["t"].iloc[-1], 2 * math.pi / 31.416)
    assert_allclose(frame["crank.rate"], 31.416)
    assert_allclose(frame["crank.value"], 31.416 * frame["t"], atol=1e-12)
    assert len(pd.read_csv(shocks)) == 0
    assert "0 soft shock(s)" in r.output


def test_cli_simulate_profile_from_several_drives(tmp_path):
    out = tmp_path / "p.csv"
    r = _run(
        [
            "simulate",
            str(PASIKA),
            "--drive",
            "cyl=345:0.3m:2s:from=0.9m",
            "--drive",
            "cyl=cycloidal:-0.3m:2s:start=3s",
            "--samples",
            "71",
            "-o",
            str(out),
            "--no-shocks",
        ]
    )
    assert r.exit_code == 0, r.output
    frame = pd.read_csv(out)
    assert_allclose(frame["cyl.value"].iloc[[0, 35, -1]], [0.9, 1.2, 0.9], atol=1e-12)
    assert "shock report" not in r.output


def test_cli_simulate_winch_on_a_length(tmp_path):
    out = tmp_path / "w.csv"
    r = _run(
        [
            "simulate",
            str(PASIKA),
            "--drive",
            "cyl=winch:motor=-10rad/s:drum=0.1m:gear=20:blocks=2:from=0.9m",
            "--duration",
            "4s",
            "--samples",
            "5",
            "-o",
            str(out),
        ]
    )
    assert r.exit_code == 0, r.output
    frame = pd.read_csv(out)
    # motor turning backwards pays the rope out: L = 0.9 + 10·0.1/(20·2)·t
    assert_allclose(frame["cyl.value"], 0.9 + 0.025 * frame["t"], atol=1e-12)


@pytest.mark.parametrize(
    ("drive", "message"),
    [
        ("cyl=bogus:0.5m:5s", "unknown motion law"),
        ("cyl=cubic:0.5s:5s", "cyl"),
        ("cyl=cubic:0.5m", "LAW:STROKE:DURATION"),
        ("cyl=cubic:0.5m:5s:foo=1", "unknown option 'foo'"),
        ("cyl=crank:1rad/s", "crank drives an angle"),
        ("arm=cubic:0.5m:5s", "unknown driver 'arm'"),
        ("cyl=winch:motor=1rad/s:drum=0.1m", "missing gear"),
        ("cyl=s-curve:0.5m:auto:v_max=0.2m/s:a_max=0.1m/s^2", "needs all of"),
    ],
)
def test_cli_simulate_errors(tmp_path, drive, message):
    r = CliRunner().invoke(
        main, ["simulate", str(PASIKA), "--drive", drive, "-o", str(tmp_path / "x.csv")]
    )
    assert r.exit_code != 0
    assert message in r.output
    assert "Traceback" not in r.output
    assert not (tmp_path / "x.csv").exists()


def test_cli_simulate_overlapping_laws(tmp_path):
    r = CliRunner().invoke(
        main,
        [
            "simulate",
            str(PASIKA),
            "--drive",
            "cyl=345:0.3m:2s",
            "--drive",
            "cyl=345:-0.3m:2s:start=1s",
            "-o",
            str(tmp_path / "x.csv"),
        ],
    )
    assert r.exit_code != 0 and "overlaps" in r.output


def test_cli_simulate_s_curve_limits_and_jerk_units(tmp_path):
    out = tmp_path / "s.csv"
    r = _run(
        [
            "simulate",
            str(PASIKA),
            "--drive",
            "cyl=s-curve:0.5m:auto:v_max=0.2m/s:a_max=0.1m/s^2:j_max=0.2m/s^3",
            "--samples",
            "11",
            "-o",
            str(out),
        ]
    )
    assert r.exit_code == 0, r.output
    law = get_law("s-curve", 0.5, None, v_max=0.2, a_max=0.1, j_max=0.2)
    assert_allclose(pd.read_csv(out)["t"].iloc[-1], law.duration)
    assert "0 soft shock(s)" in r.output


def _example_models():
    folder = FOURBAR.parent
    out = []
    for path in sorted(folder.glob("*.toml")):
        try:
            excavkin.load(path)
        except excavkin.ModelError:
            continue  # another file format in the folder (e.g. a machine description)
        out.append(path)
    return out


@pytest.mark.parametrize("path", _example_models(), ids=lambda p: p.stem)
def test_cli_simulate_every_example_model(tmp_path, path):
    """Every driver of every example model moved together by the 3-4-5 law: the run solves,
    the table has t, and the report finds the ends smooth (no shock of any kind)."""
    mech = excavkin.load(path)
    args = ["simulate", str(path), "--samples", "21", "-o", str(tmp_path / "run.csv")]
    for name in mech.inputs:
        if mech.input_kind(name) == "angle":
            args += ["--drive", f"{name}=345:5deg:1s"]
        else:
            args += ["--drive", f"{name}=345:{0.02 * mech.sketch_values()[name]!r}m:1s"]
    r = _run(args)
    assert r.exit_code == 0, r.output
    frame = pd.read_csv(tmp_path / "run.csv")
    assert frame.columns[0] == "t" and (frame["status"] == "ok").all()
    assert "0 hard shock(s)" in r.output and "0 soft shock(s)" in r.output


def test_cli_simulate_holds_undriven_drivers_where_set(tmp_path):
    """--set moves an undriven driver off its sketch value for the whole run; the positions
    equal a direct solve with that value, and the held driver adds no shocks."""
    model = excavkin.example_path("excavator")
    out = tmp_path / "held.csv"
    args = ["simulate", str(model), "--drive", "boom_cyl=cubic:0.3m:3s", "--samples", "31"]
    r = _run(
        [*args, "--set", "arm_cyl=2.5m", "-o", str(out), "--shock-table", str(tmp_path / "s.csv")]
    )
    assert r.exit_code == 0, r.output
    frame = pd.read_csv(out)
    assert (frame["arm_cyl.value"] == 2.5).all() and (frame["arm_cyl.rate"] == 0).all()
    mech = excavkin.load(model)
    direct = mech.solve(
        {"boom_cyl": frame["boom_cyl.value"].to_numpy(), "arm_cyl": 2.5},
        {"boom_cyl": frame["boom_cyl.rate"].to_numpy()},
        {"boom_cyl": frame["boom_cyl.accel"].to_numpy()},
    )
    assert_allclose(frame["T.x"], direct.column("T.x"), rtol=0, atol=1e-12)
    assert_allclose(frame["stick.omega"], direct.column("stick.omega"), rtol=0, atol=1e-12)
    shocks = pd.read_csv(tmp_path / "s.csv")
    assert len(shocks) > 0  # the cubic law's soft shocks at both ends
    assert "boom_cyl.accel" in set(shocks["column"])
    assert not {"arm_cyl.rate", "arm_cyl.accel"} & set(shocks["column"])
    for bad, message in (
        ("boom_cyl=2.5m", "both driven and held"),
        ("nope=1m", "unknown driver 'nope'"),
        ("arm_cyl=2.5s", "arm_cyl"),
    ):
        r = CliRunner().invoke(main, [*args, "--set", bad, "-o", str(tmp_path / "x.csv")])
        assert r.exit_code == 2 and message in r.output and "Traceback" not in r.output
    assert not (tmp_path / "x.csv").exists()
