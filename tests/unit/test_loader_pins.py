"""Pin loads over the lift against independent statics: the bucket's free body (its pins, the
load and its weight sum to zero) and each cylinder's force by virtual work through the engine's
transfer functions (``machine.solve(L, one-hot rates)``), not through the equilibrium matrix."""

from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

from excavkin.cli import main
from excavkin.errors import InputError
from excavkin.loader.breakout import breakout
from excavkin.loader.machine import Loader
from excavkin.loader.machine_file import load_machine
from excavkin.loader.pins import CASES, pin_loads
from excavkin.loader.tipping import static_tipping
from tests.conftest import EXAMPLES

SAMPLES = 7


@pytest.fixture(scope="module")
def loader() -> Loader:
    return load_machine(EXAMPLES / "wheel_loader_machine.toml")


@pytest.fixture(scope="module")
def result(loader):
    return pin_loads(loader, SAMPLES)


def test_the_loads_are_the_rated_figures(loader, result) -> None:
    g = loader.gravity
    tip = static_tipping(loader)
    expected = {
        "breakout": breakout(loader).tilt.force,
        "rated load": tip.rated_operating_capacity * g,
        "tipping": tip.straight.load * g,
    }
    for name in CASES:
        c = result[name]
        assert c.ok.all()
        assert np.allclose(c.force[:, 0], 0.0)
        assert c.force[:, 1] == pytest.approx(np.full(SAMPLES, -expected[name]), rel=1e-12)
    # from the ground pose to full lift; the breakout case's floor is level
    h = result["rated load"].hinge_height
    assert np.all(np.diff(h) > 0.0)
    assert result["breakout"].lengths[-1, 0] == pytest.approx(loader.full_lift())
    b = result["breakout"]
    pos = loader.solve(b.lengths).positions
    e = pos[:, loader.index(loader.linkage.edge)]
    k = pos[:, loader.index(loader.linkage.heel)]
    assert np.allclose(e[:, 1], k[:, 1], atol=1e-7)
    # 100 mm behind the edge, along the floor
    assert np.allclose(np.hypot(*(e - b.point).T), 0.1, atol=1e-12)


def test_the_buckets_free_body_is_in_equilibrium(loader, result) -> None:
    bucket = loader.linkage.bucket
    mass = next(b.mass for b in loader.mechanism.model.bodies if b.name == bucket)
    for c in result.cases:
        fr = c.forces
        total = c.force.copy()
        total[:, 1] -= mass * loader.gravity
        pins = [p for p, b in fr.pins if b == bucket]
        assert len(pins) == 2  # the hinge pin and the tilt link's pin
        for p in pins:
            total += fr.pin(p, bucket)
        scale = np.abs(c.force).max()
        assert np.abs(total).max() < 1e-9 * scale


def test_cylinder_forces_by_virtual_work(loader, result) -> None:
    mp = loader.mass_points
    for c in result.cases:
        L = c.lengths
        for w in range(2):
            res = loader.solve(L, np.eye(2)[w])
            pos, vel = res.positions, res.velocities
            hinge = loader.index(loader.pins.hinge)
            e, k = loader.index(loader.linkage.edge), loader.index(loader.linkage.heel)
            d = pos[:, e] - pos[:, k]
            dv = vel[:, e] - vel[:, k]
            omega = (d[:, 0] * dv[:, 1] - d[:, 1] * dv[:, 0]) / (d**2).sum(axis=1)
            r = c.point - pos[:, hinge]
            vx = vel[:, hinge] + omega[:, None] * np.column_stack([-r[:, 1], r[:, 0]])
            dy = mp.locate(vel)[:, :, 1]  # ∂y of each mass point / ∂L_w
            # f·δL + Σ loads·δx = 0, the weight (0, −m g) and the load P at X
            f = loader.gravity * dy @ mp.mass - (c.force * vx).sum(axis=1)
            assert c.cylinder_force[:, w] == pytest.approx(f, rel=1e-9)


def test_largest_table_and_command(loader, result, tmp_path) -> None:
    top = result.largest()
    assert [t[0] for t in top] == list(result.cases[0].pins)
    for pin, load, case, h in top:
        j = result.cases[0].pins.index(pin)
        assert load == max(float(np.nanmax(c.load[:, j])) for c in result.cases)
        k = int(np.nanargmax(result[case].load[:, j]))
        assert result[case].load[k, j] == load and result[case].hinge_height[k] == h
    # the lift cylinders' largest push, over the bore of both, against the 27.5 MPa port relief
    push = max(float(np.nanmax(c.cylinder_force[:, 0])) for c in result.cases)
    p = push / (2 * np.pi / 4 * 0.14**2)
    line = next(ln for ln in result.summary().splitlines() if "lift cylinders push" in ln)
    assert f"{p / 1e6:5.1f} MPa" in line
    assert ("beyond the port relief 27.5 MPa" in line) == (p > 27.5e6)
    frame = result.to_frame()
    assert len(frame) == 3 * SAMPLES
    assert frame.attrs["excavkin.units"][f"pin.{loader.pins.hinge}"] == "N"
    out = tmp_path / "pins.csv"
    r = CliRunner().invoke(
        main, ["loader", "pins", "wheel_loader_machine", "--samples", "5", "-o", str(out)]
    )
    assert r.exit_code == 0, r.output
    assert "pin hinge pin" in r.output and out.exists()
    bad = CliRunner().invoke(main, ["loader", "pins", "wheel_loader_machine", "--samples", "1"])
    assert bad.exit_code == 2 and "Traceback" not in bad.output
    with pytest.raises(InputError, match="samples"):
        pin_loads(loader, 1)
