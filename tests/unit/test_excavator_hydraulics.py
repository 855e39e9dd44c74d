"""Excavator hydraulics: speeds against volume flow, stroke and cycle times by hand, buckling
against the textbook formulas (Euler, Johnson and their transition), power against the
kinetostatics' power balance, and the [hydraulics] table's errors."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from excavkin.cli import main
from excavkin.errors import InputError, ModelError, UnitError
from excavkin.excavator.hydraulics import (
    Hydraulics,
    Pump,
    buckling,
    cycle_time,
    cylinder_speed,
    motion_power,
    pose_buckling,
    power_of,
    relief_buckling,
    strokes,
)
from excavkin.excavator.machine import ROLES
from excavkin.excavator.machine_file import loads_machine
from tests.conftest import EXAMPLES

MACHINE = EXAMPLES / "excavator_machine.toml"
LPM = 1e-3 / 60.0  # one litre per minute in m³/s


def _text(extra: str = "", **replace: str) -> str:
    text = MACHINE.read_text(encoding="utf-8").replace(
        'model = "excavator.toml"', f'model = "{(EXAMPLES / "excavator.toml").as_posix()}"'
    )
    for old, new in replace.items():
        assert old in text, old
        text = text.replace(old, new, 1)
    return text + extra


@pytest.fixture(scope="module")
def machine():  # type: ignore[no-untyped-def]
    return loads_machine(_text(), "m.toml")


def _areas(c):  # type: ignore[no-untyped-def]
    """Bore and annulus areas of all ``count`` cylinders, from the diameters."""
    return c.count * math.pi * c.bore**2 / 4.0, c.count * math.pi * (c.bore**2 - c.rod**2) / 4.0


def test_example_hydraulics_read_in_si(machine) -> None:  # type: ignore[no-untyped-def]
    h = machine.hydraulics
    assert h is not None
    assert [p.name for p in h.pumps] == ["P1", "P2"]
    assert [p.flow for p in h.pumps] == pytest.approx([220 * LPM] * 2, rel=1e-15)
    assert h.pumps[0].feeds == ("boom", "arm", "bucket") and h.pumps[1].feeds == ("boom", "arm")
    assert h.swing_speed == pytest.approx(11 * 2 * math.pi / 60, rel=1e-15)
    assert h.swing_angle == pytest.approx(math.pi / 2, rel=1e-15)
    assert (h.modulus, h.rod_yield) == pytest.approx((210e9, 500e6), rel=1e-15)
    # the feeding pumps' flows add
    assert [h.flow(r) for r in ROLES] == pytest.approx([440 * LPM, 440 * LPM, 220 * LPM])


def test_speed_times_area_is_the_volume_flow(machine) -> None:  # type: ignore[no-untyped-def]
    for c, s in zip(machine.cylinders, strokes(machine), strict=True):
        bore, annulus = _areas(c)
        q = machine.hydraulics.flow(c.role)
        assert s.flow == q
        assert s.extend_speed * bore == pytest.approx(q, rel=1e-12)
        assert s.retract_speed * annulus == pytest.approx(q, rel=1e-12)
        # the time of a full stroke: the swept volume over the flow
        assert s.extend_time == pytest.approx(c.stroke * bore / q, rel=1e-12)
        assert s.retract_time == pytest.approx(c.stroke * annulus / q, rel=1e-12)
        assert s.retract_time < s.extend_time
    # the two boom cylinders share the flow: twice the area, half the speed of one
    boom = machine.cylinders[0]
    assert boom.count == 2
    one = float(cylinder_speed(boom, 1e-3, "extend")) * 2
    assert one == pytest.approx(1e-3 / (math.pi * boom.bore**2 / 4), rel=1e-12)
    speeds = cylinder_speed(boom, np.array([1e-3, 2e-3]), "retract")
    assert speeds[1] == pytest.approx(2 * speeds[0], rel=1e-15)


def test_cycle_time_by_hand(machine) -> None:  # type: ignore[no-untyped-def]
    h = machine.hydraulics
    t = {}
    for c in machine.cylinders:
        bore, annulus = _areas(c)
        q = h.flow(c.role)
        t[c.role] = (c.stroke * bore / q, c.stroke * annulus / q)  # extend, retract
    # a backhoe digs by extending the arm and bucket cylinders; the boom rises extending
    dig = t["arm"][0] + t["bucket"][0]
    dump = t["arm"][1] + t["bucket"][1]
    swing = (math.pi / 2) / (11 * 2 * math.pi / 60)
    cy = cycle_time(machine)
    assert (cy.dig, cy.dump, cy.swing) == pytest.approx((dig, dump, swing), rel=1e-12)
    assert (cy.boom_up, cy.boom_down) == pytest.approx(t["boom"], rel=1e-12)
    seq = dig + t["boom"][0] + swing + dump + swing + t["boom"][1]
    assert cy.sequential == pytest.approx(seq, rel=1e-12)
    over = dig + max(t["boom"][0], swing) + dump + max(swing, t["boom"][1])
    assert cy.overlapped == pytest.approx(over, rel=1e-12)
    assert cy.overlapped < cy.sequential


def test_cycle_follows_the_digging_direction(machine) -> None:  # type: ignore[no-untyped-def]
    shovel = loads_machine(_text(**{'dig = "extend"': 'dig = "retract"'}), "m.toml")
    s = {st.role: st for st in strokes(shovel)}
    cy = cycle_time(shovel)
    assert cy.dig == pytest.approx(s["arm"].retract_time + s["bucket"].extend_time, rel=1e-15)


def _euler(E: float, d: float, L: np.ndarray) -> np.ndarray:
    return math.pi**2 * E * (math.pi * d**4 / 64) / L**2


def _johnson(E: float, sy: float, d: float, L: np.ndarray) -> np.ndarray:
    lam = L / (d / 4)
    return math.pi * d**2 / 4 * sy * (1 - sy * lam**2 / (4 * math.pi**2 * E))


def test_buckling_against_the_textbook_formulas(machine) -> None:  # type: ignore[no-untyped-def]
    E, sy = 200e9, 350e6
    c = machine.cylinders[1]
    d = c.rod
    lam1 = math.sqrt(2 * math.pi**2 * E / sy)
    L = np.array([0.3, 1.0, 2.0, 3.0, 5.0])
    b = buckling(c, L, 1e5, modulus=E, rod_yield=sy)
    assert b.transition == pytest.approx(lam1, rel=1e-15)
    np.testing.assert_allclose(b.slenderness, L / (d / 4), rtol=1e-15)
    short = L / (d / 4) < lam1
    assert short.any() and (~short).any()
    assert list(b.formula) == ["Johnson" if s else "Euler" for s in short]
    expect = np.where(short, _johnson(E, sy, d, L), _euler(E, d, L))
    np.testing.assert_allclose(b.critical, expect, rtol=1e-13)
    np.testing.assert_allclose(b.safety, expect / 1e5, rtol=1e-13)
    # a pulled cylinder cannot buckle
    pulled = buckling(c, L, -1e5, modulus=E, rod_yield=sy)
    assert np.all(np.isinf(pulled.safety))


def test_euler_and_johnson_meet_at_the_transition(machine) -> None:  # type: ignore[no-untyped-def]
    E, sy = 210e9, 500e6
    c = machine.cylinders[2]
    d = c.rod
    lt = math.sqrt(2 * math.pi**2 * E / sy) * d / 4  # the length at the transition slenderness
    half_squash = math.pi * d**2 / 4 * sy / 2
    assert _euler(E, d, np.array(lt)) == pytest.approx(half_squash, rel=1e-13)
    assert _johnson(E, sy, d, np.array(lt)) == pytest.approx(half_squash, rel=1e-13)
    eps = 1e-9
    b = buckling(c, [lt * (1 - eps), lt * (1 + eps)], 1.0, modulus=E, rod_yield=sy)
    assert list(b.formula) == ["Johnson", "Euler"]
    np.testing.assert_allclose(b.critical, half_squash, rtol=1e-8)
    with pytest.raises(InputError, match="positive"):
        buckling(c, 1.0, 1.0, modulus=0.0)
    with pytest.raises(InputError, match="lengths must be positive"):
        buckling(c, 0.0, 1.0)


def test_relief_and_pose_buckling(machine) -> None:  # type: ignore[no-untyped-def]
    h = machine.hydraulics
    for c, b in zip(machine.cylinders, relief_buckling(machine), strict=True):
        p = machine.circuits[c.circuit].relief * math.pi * c.bore**2 / 4  # one cylinder
        assert float(b.force[0]) == pytest.approx(p, rel=1e-13)
        assert float(b.length[0]) == c.retracted + c.stroke
        assert float(b.critical[0]) == pytest.approx(
            float(_euler(h.modulus, c.rod, np.array(c.retracted + c.stroke))), rel=1e-13
        )
    L = np.array([machine.lengths_min, machine.lengths_max])
    f = np.array([[2e5, -1e5, 3e5], [4e5, 2e5, -1.0]])
    checks = pose_buckling(machine, L, f)
    boom = checks[0]
    np.testing.assert_allclose(boom.force, f[:, 0] / 2, rtol=1e-15)  # two boom cylinders
    assert np.isinf(checks[1].safety[0]) and np.isinf(checks[2].safety[1])


def test_power_is_f_times_rate_and_p_times_q(machine) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(16)
    n = 12
    L = machine.lengths_min + rng.uniform(0.1, 0.9, (n, 3)) * (
        machine.lengths_max - machine.lengths_min
    )
    R = rng.uniform(-0.3, 0.3, (n, 3))
    R[0] = (0.2, 0.0, -0.1)  # one cylinder standing still
    p = motion_power(machine, L, R)
    # against the engine's own power balance: Σ f·L̇ = dT/dt − load power (gravity)
    res = machine.solve(L, R)
    fr = machine.mechanism.forces(res, machine.weight_loads())
    bal = fr.power_balance()
    assert np.all(np.abs(p.total - (bal.kinetic_rate - bal.load)) <= 1e-12 * bal.scale)
    np.testing.assert_allclose(
        p.force, np.stack([fr.force(d) for d in machine.drivers], axis=1), rtol=1e-15
    )
    # pump power p·Q equals f·L̇; the pressure acts on the inlet area
    np.testing.assert_allclose(p.pump_power, p.force * R, rtol=1e-12, atol=1e-9)
    bore = np.array([_areas(c)[0] for c in machine.cylinders])
    ann = np.array([_areas(c)[1] for c in machine.cylinders])
    ext, ret = R > 0, R < 0
    np.testing.assert_allclose((p.pressure * bore)[ext], p.force[ext], rtol=1e-12)
    np.testing.assert_allclose((-p.pressure * ann)[ret], p.force[ret], rtol=1e-12)
    np.testing.assert_allclose(p.flow, np.where(ext, bore, ann) * np.abs(R), rtol=1e-15)
    assert p.pressure[0, 1] == 0.0 and p.flow[0, 1] == 0.0
    # the weight's share of the power, against a central difference of the potential energy
    # g·Σ m·y of the front's mass points along the motion
    weightless = motion_power(machine, L, R, gravity=False)
    mp = machine.mass_points

    def potential(lengths: np.ndarray) -> np.ndarray:
        y = mp.locate(machine.solve(lengths).positions)[..., 1]
        return np.asarray(machine.gravity * (y @ mp.mass))

    h = 1e-6
    dv = (potential(L + h * R) - potential(L - h * R)) / (2 * h)
    np.testing.assert_allclose(p.total - weightless.total, dv, rtol=1e-6, atol=1e-3)


def test_power_of_an_overrunning_load(machine) -> None:  # type: ignore[no-untyped-def]
    # the boom lowering under its own weight: the cylinder pushes while retracting
    p = power_of(machine, [[1e5, 0.0, 0.0]], [[-0.2, 0.0, 0.0]])
    ann = _areas(machine.cylinders[0])[1]
    assert float(p.pressure[0, 0]) == pytest.approx(-1e5 / ann, rel=1e-15)
    assert float(p.pump_power[0, 0]) == pytest.approx(-2e4, rel=1e-12)


def test_without_hydraulics(tmp_path: Path) -> None:
    text = _text().split("\n[hydraulics]")[0]
    m = loads_machine(text, "m.toml")
    assert m.hydraulics is None
    with pytest.raises(InputError, match=r"no \[hydraulics\] table"):
        strokes(m)
    given = Hydraulics((Pump("P", 100 * LPM, ROLES),), 1.0, 1.0)
    assert strokes(m, given)[2].flow == pytest.approx(100 * LPM)
    path = tmp_path / "m.toml"
    path.write_text(text, encoding="utf-8")
    r = CliRunner().invoke(main, ["excavator", "cycle", str(path)])
    assert r.exit_code != 0 and "no [hydraulics] table" in r.output
    assert "Traceback" not in r.output


@pytest.mark.parametrize(
    ("old", "new", "pattern"),
    [
        ('flow = "220 L/min"', 'flow = "0 L/min"', r"\[hydraulics\.pumps\.P1\] 'flow'.*more than"),
        ('flow = "220 L/min"', 'flow = "220 bar"', r"\[hydraulics\.pumps\.P1\] 'flow'"),
        ('flow = "220 L/min"', "flow = 220", r"\[hydraulics\.pumps\.P1\] 'flow'.*needs a unit"),
        ('swing_speed = "11 rpm"', 'swing_speed = "-1 rpm"', r"\[hydraulics\] 'swing_speed'"),
        ('swing_speed = "11 rpm"', 'swing_speed = "100 rpm"', r"'swing_speed'.*at most"),
        ('swing_angle = "90 deg"', 'swing_angle = "400 deg"', r"\[hydraulics\] 'swing_angle'"),
        ('rod_yield = "500 MPa"', 'rod_yield = "0 MPa"', r"\[hydraulics\] 'rod_yield'"),
        ('rod_modulus = "210 GPa"', 'rod_modulus = "210 mm"', r"\[hydraulics\] 'rod_modulus'"),
        (
            'feeds = ["boom", "arm", "bucket"]',
            'feeds = ["boom", "dipper"]',
            r"\[hydraulics\.pumps\.P1\] 'feeds'.*dipper",
        ),
        ('feeds = ["boom", "arm", "bucket"]', "feeds = []", r"'feeds'"),
        ('feeds = ["boom", "arm", "bucket"]', 'feeds = ["boom", "boom"]', r"'feeds'.*distinct"),
        (
            'feeds = ["boom", "arm", "bucket"]',
            'feeds = ["boom", "arm"]',
            r"\[hydraulics\.pumps\].*no pump feeds the bucket cylinder",
        ),
        ('swing_angle = "90 deg"', 'swing_angel = "90 deg"', r"unknown key swing_angel"),
        (
            '[hydraulics.pumps.P2]\nflow = "220 L/min"\n',
            "[hydraulics.pumps.P2]\n",
            r"'flow' is missing",
        ),
    ],
)
def test_hydraulics_errors_name_table_and_entry(old: str, new: str, pattern: str) -> None:
    with pytest.raises((ModelError, UnitError), match=pattern) as info:
        loads_machine(_text(**{old: new}), "m.toml")
    assert str(info.value).startswith("m.toml")


@pytest.mark.parametrize(
    ("pumps", "speed", "pattern"),
    [
        ((Pump("P", -1.0, ROLES),), 1.0, "flow must be positive"),
        ((Pump("P", 1e-3, ("boom", "dipper")),), 1.0, "must feed"),
        ((Pump("P", 1e-3, ("boom", "arm")),), 1.0, "no pump feeds the bucket"),
        ((Pump("P", 1e-3, ROLES),), math.nan, "swing_speed"),
    ],
)
def test_hydraulics_checks_its_numbers(pumps: tuple[Pump, ...], speed: float, pattern: str) -> None:
    with pytest.raises(InputError, match=pattern):
        Hydraulics(pumps, speed, 1.0)


def test_swing_in_other_units() -> None:
    m = loads_machine(_text(**{'swing_speed = "11 rpm"': 'swing_speed = "66 deg/s"'}), "m.toml")
    assert m.hydraulics is not None
    assert m.hydraulics.swing_speed == pytest.approx(11 * 2 * math.pi / 60, rel=1e-14)


# ------------------------------------------------------------------ the command line
def test_cli_cycle(tmp_path: Path, machine) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "cycle.csv"
    args = ["excavator", "cycle", str(MACHINE), "-o", str(out)]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    assert "swing overlapping boom" in r.output and "ISO 6015 bucket force" in r.output
    table = pd.read_csv(out)
    st = table[table["section"] == "stroke"]
    assert list(st["cylinder"]) == list(ROLES)
    for c, (_, row) in zip(machine.cylinders, st.iterrows(), strict=True):
        bore, _ = _areas(c)
        assert row["extend_speed"] * bore == pytest.approx(row["flow"], rel=1e-12)
    cy = table[table["section"] == "cycle"].set_index("phase")["time"]
    assert cy["cycle, one motion at a time"] == pytest.approx(cycle_time(machine).sequential)
    bk = table[table["section"] == "buckling"]
    assert set(bk["case"]) == {
        "relief, fully extended",
        "ISO 6015 arm force",
        "ISO 6015 bucket force",
    }
    pushed = bk[bk["force"] > 0]
    np.testing.assert_allclose(pushed["safety"], pushed["critical"] / pushed["force"], rtol=1e-12)
    again = CliRunner().invoke(main, args)
    assert again.exit_code == 2 and "--force" in again.output


def test_cli_cycle_power_table_and_plot(tmp_path: Path, machine) -> None:  # type: ignore[no-untyped-def]
    from excavkin.excavator.cycle_power import cycle_power

    out, figure = tmp_path / "cycle.csv", tmp_path / "power.png"
    args = ["excavator", "cycle", str(MACHINE), "-o", str(out), "--plot", str(figure)]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    assert "Power along the cycle" in r.output and "cannot run at full flow" in r.output
    power = pd.read_csv(out)
    power = power[power["section"] == "power"].set_index("phase")
    cp = {p.name: p for p in cycle_power(machine).phases}
    assert set(power.index) == {k for k, p in cp.items() if p.role is not None}
    for name, row in power.iterrows():
        assert row["work"] == cp[str(name)].work and row["peak_power"] == cp[str(name)].peak
    assert figure.stat().st_size > 10_000
