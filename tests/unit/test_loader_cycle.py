"""The SAE J732 cycle against a hand computation: each time is the swept volume over the
pumps' flow, each pressure the static cylinder force of virtual work (central differences of
the potential energy of the solved poses, no transfer functions) over the inlet area."""

from __future__ import annotations

import math

import numpy as np
import pytest
from click.testing import CliRunner

from excavkin.cli import main
from excavkin.errors import InputError
from excavkin.loader.cycle import cycle
from excavkin.loader.machine import Loader, floor_angle
from excavkin.loader.machine_file import load_machine
from excavkin.loader.poses import ground_pose
from excavkin.loader.tipping import static_tipping
from tests.conftest import EXAMPLES

Q = 230e-3 / 60.0  # the built-in machine's one pump, feeding both functions (m³/s)


@pytest.fixture(scope="module")
def loader() -> Loader:
    return load_machine(EXAMPLES / "wheel_loader_machine.toml")


def _areas(bore: float, rod: float, count: int) -> tuple[float, float]:
    a = count * math.pi / 4.0 * bore**2
    return a, a - count * math.pi / 4.0 * rod**2


def _energy(loader: Loader, L: np.ndarray, load: float) -> np.ndarray:
    """Potential energy (J) of the linkage and a load at the rated load's centre of gravity."""
    res = loader.solve(L)
    assert res.status.ok.all()
    pos = res.positions
    mp = loader.mass_points
    y = mp.locate(pos)[:, :, 1]
    v = loader.gravity * (y * mp.mass).sum(axis=1)
    a = floor_angle(loader, pos)
    hinge = pos[:, loader.index(loader.pins.hinge)]
    x, yl = loader.bucket.load_cg
    yp = hinge[:, 1] + np.sin(a) * x + np.cos(a) * yl
    return np.asarray(v + load * loader.gravity * yp)


def _force(loader: Loader, L: np.ndarray, w: int, load: float, h: float = 1e-6) -> float:
    up, down = L.copy(), L.copy()
    up[w] += h
    down[w] -= h
    return float((_energy(loader, up[None], load) - _energy(loader, down[None], load))[0] / (2 * h))


def test_times_are_swept_volume_over_flow(loader) -> None:
    c = cycle(loader)
    lift_bore, lift_ann = _areas(0.14, 0.08, 2)  # the machine file's lift cylinders
    tilt_bore, tilt_ann = _areas(0.18, 0.09, 1)
    ground = ground_pose(loader)[0]
    top = 1.733 + 1.02  # retracted + stroke
    assert c["raise"].time == pytest.approx(lift_bore * (top - ground) / Q, rel=1e-12)
    assert c["lower empty"].time == pytest.approx(lift_ann * (top - ground) / Q, rel=1e-12)
    # a Z-bar extends its tilt cylinder to roll back: the dump retracts it over its stroke
    assert c["dump"].direction == "retract"
    assert c["dump"].time == pytest.approx(tilt_ann * 0.5 / Q, rel=1e-12)
    assert c.total == pytest.approx(sum(p.time for p in c.phases))


def test_pressures_and_powers_are_the_static_forces_of_virtual_work(loader) -> None:
    roc = static_tipping(loader).rated_operating_capacity
    c = cycle(loader)
    top, roll = loader.full_lift(), loader.full_rollback()
    cases = {
        "raise": (0, roll, roc),
        "lower empty": (0, roll, 0.0),
        "dump": (1, top, 0.0),
    }
    for name, (w, held, load) in cases.items():
        p = c[name]
        assert p.load == pytest.approx(load, rel=1e-12)
        cyl = loader.cylinders[w]
        area = cyl.bore_area if p.direction == "extend" else cyl.annulus_area
        sign = 1.0 if p.direction == "extend" else -1.0
        L = np.empty(2)
        L[1 - w] = held
        L[w] = p.length_at_peak
        f = _force(loader, L, w, load)
        assert p.pressure == pytest.approx(sign * f / area, rel=1e-6, abs=1e3)
        assert p.power == pytest.approx(p.pressure * Q, rel=1e-12)
        # the largest over the stroke: no pose of a coarse grid needs more
        grid = np.linspace(p.start, p.end, 9)
        for x in grid:
            L[w] = x
            assert sign * _force(loader, L, w, load) / area <= p.pressure + 1e3
    # the rated load raised is above what the linkage alone needs, within the working pressure
    assert 0.0 < c["raise"].pressure < c["raise"].working
    assert c["lower empty"].pressure < 0.0  # overrunning
    heavy = cycle(loader, load=40_000.0)
    assert heavy["raise"].over_working and "above the working pressure" in heavy.summary()


def test_the_table_and_the_command(loader, tmp_path) -> None:
    c = cycle(loader)
    frame = c.to_frame()
    assert list(frame["phase"]) == ["raise", "lower empty", "dump"]
    assert frame.attrs["excavkin.units"]["time"] == "s"
    assert frame.attrs["excavkin.units"]["flow"] == "m^3/s"
    out = tmp_path / "cycle.csv"
    r = CliRunner().invoke(main, ["loader", "cycle", "wheel_loader_machine", "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert "hydraulic cycle (SAE J732)" in r.output and f"{c['raise'].time:6.2f} s" in r.output
    bad = CliRunner().invoke(main, ["loader", "cycle", "wheel_loader_machine", "--load", "-1"])
    assert bad.exit_code == 2 and "Traceback" not in bad.output
    with pytest.raises(InputError, match="load"):
        cycle(loader, load=float("nan"))


def _variant(tmp_path, hydraulics: str):
    text = (EXAMPLES / "wheel_loader_machine.toml").read_text(encoding="utf-8")
    head = text[: text.index("[hydraulics]")]
    path = tmp_path / "m.toml"
    path.write_text(head + hydraulics, encoding="utf-8")
    (tmp_path / "wheel_loader.toml").write_text(
        (EXAMPLES / "wheel_loader.toml").read_text(encoding="utf-8"), encoding="utf-8"
    )
    return path


def test_pumps_in_confluence_add_their_flows(loader, tmp_path) -> None:
    two = (
        '[hydraulics.pumps.P1]\nflow = "150 L/min"\nfeeds = ["lift", "tilt"]\n\n'
        '[hydraulics.pumps.P2]\nflow = "100 L/min"\nfeeds = ["lift"]\n'
    )
    c = cycle(load_machine(_variant(tmp_path, two)), load=0.0)
    ref = cycle(loader, load=0.0)
    assert c["raise"].flow == pytest.approx(250e-3 / 60.0, rel=1e-12)
    assert c["raise"].time == pytest.approx(ref["raise"].time * 230.0 / 250.0, rel=1e-12)
    assert c["dump"].time == pytest.approx(ref["dump"].time * 230.0 / 150.0, rel=1e-12)
    assert c["dump"].pressure == pytest.approx(ref["dump"].pressure, rel=1e-12)


def test_a_machine_without_pumps_is_one_message(tmp_path) -> None:
    path = _variant(tmp_path, "")
    r = CliRunner().invoke(main, ["loader", "cycle", str(path)])
    assert r.exit_code == 2 and "[hydraulics]" in r.output and "Traceback" not in r.output
