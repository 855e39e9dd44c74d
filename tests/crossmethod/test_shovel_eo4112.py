"""The EO-4112 rope backhoe as a built-in machine of the shovel wing, against the paper wing's
closed-form reference (Maksimov; `excavkin.papers.rope_shovel.reference`): the bucket's attitude
through the general engine equals the reference's to round-off, hauled by the machine's drag
winch; the drag rope's tension against the bucket's weight by virtual work."""

from __future__ import annotations

import numpy as np
from click.testing import CliRunner

from excavkin.cli import main
from excavkin.kinetostatics import PointForce
from excavkin.papers.rope_shovel.reference import (
    EO4112_DRIVE,
    EO4112_GEOMETRY,
    bucket_mechanism_from_drive,
)
from excavkin.shovel.machine import RopeBackhoe
from excavkin.shovel.machine_file import load_machine


def test_bucket_attitude_equals_the_paper_reference():
    hoe = load_machine("eo4112_machine")
    assert isinstance(hoe, RopeBackhoe)
    np.testing.assert_allclose(
        hoe.drag.speed,
        EO4112_DRIVE.omega_motor * EO4112_DRIVE.r_drum
        / (EO4112_DRIVE.gear_ratio * EO4112_DRIVE.multiplicity),
        rtol=1e-15,
    )  # fmt: skip
    phi1 = np.radians(np.linspace(60.0, 150.0, 91))
    ref = bucket_mechanism_from_drive(EO4112_GEOMETRY, EO4112_DRIVE, phi1)
    res = hoe.haul(ref.fe)
    assert res.status.ok.all()
    relative, absolute = hoe.attitude(res)
    np.testing.assert_allclose(res.body(hoe.stick)[0], ref.phi1, rtol=0, atol=1e-12)
    # angles compared modulo a turn (the engine's body angles are not unwrapped)
    np.testing.assert_allclose(np.angle(np.exp(1j * (relative - ref.phi7p))), 0.0, atol=1e-12)
    wrap = np.angle(np.exp(1j * (absolute - ref.phi1 - ref.phi7p)))  # κ = β = 0
    np.testing.assert_allclose(wrap, 0.0, atol=1e-12)
    # the rates from the winch: the stick's and the bucket's
    np.testing.assert_allclose(res.body(hoe.stick)[1], ref.omega1, rtol=1e-10)
    np.testing.assert_allclose(
        res.body(hoe.bucket)[1] - res.body(hoe.stick)[1], ref.omega7p, rtol=1e-9, atol=1e-12
    )


def test_drag_rope_tension_by_virtual_work():
    hoe = load_machine("eo4112_machine")
    fe = np.linspace(3.8, 6.6, 7)
    static = hoe.mechanism.solve({"drag": fe})
    load = PointForce("bucket weight and soil", "bucket", "D", (2000.0, -9000.0))
    forces = hoe.mechanism.forces(static, [load])
    tension = hoe.rope_tension(forces)
    # virtual work: parts·T·δ(FE) = F·δp_D, δp_D/δ(FE) the engine's transfer function
    _, v, _ = static.point("D")
    work = v @ np.array([2000.0, -9000.0])
    np.testing.assert_allclose(hoe.drag.parts * tension, work, rtol=1e-9)


def test_the_shovel_commands_refuse_a_backhoe_by_name():
    r = CliRunner().invoke(main, ["shovel", "dig", "eo4112_machine"])
    assert r.exit_code == 2
    assert "rope backhoe" in r.output and "Traceback" not in r.output


def test_the_haul_against_the_reference_and_its_command(tmp_path):
    from excavkin.shovel.haul import haul

    hoe = load_machine("eo4112_machine")
    h = haul(hoe, samples=31, force=(3000.0, -8000.0))
    ref = bucket_mechanism_from_drive(EO4112_GEOMETRY, EO4112_DRIVE, h.stick)
    np.testing.assert_allclose(h.length, ref.fe, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.angle(np.exp(1j * (h.to_stick - ref.phi7p))), 0.0, atol=1e-12)
    np.testing.assert_allclose(h.stick_rate, ref.omega1, rtol=1e-10)
    np.testing.assert_allclose(h.bucket_rate, ref.omega7p, rtol=1e-9, atol=1e-12)
    d = hoe.drag
    np.testing.assert_allclose(h.torque, h.tension * d.parts * d.drum_radius / d.gear_ratio)
    assert set(h.status[h.tension < 0]) == {"slack drag rope (it would have to push)"}
    assert set(h.status[h.tension >= 0]) == {"ok"}
    out = tmp_path / "h.csv"
    r = CliRunner().invoke(main, ["shovel", "haul", "eo4112_machine", "--samples", "7",
                                  "--load", "3", "-8", "-o", str(out)])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "bucket to stick" in r.output and out.stat().st_size > 500
    r = CliRunner().invoke(main, ["shovel", "haul", "mining_shovel_machine"])
    assert r.exit_code == 2 and "haul takes a rope backhoe" in r.output
