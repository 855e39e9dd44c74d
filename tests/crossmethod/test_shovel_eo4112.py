"""The EO-4112 rope backhoe as a built-in machine of the shovel wing, against the paper wing's
closed-form reference (Maksimov; `excavkin.papers.rope_shovel.reference`): the bucket's attitude
through the general engine equals the reference's to round-off, hauled by the machine's drag
winch; the drag rope's tension against the bucket's weight by virtual work."""

from __future__ import annotations

import numpy as np
import pytest
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
    # where the drag rope pulls, the sample is ok unless the boom's hoist would have to push
    pulls = h.tension >= 0
    assert set(h.status[pulls & (h.hoist >= 0)]) == {"ok"}
    assert set(h.status[pulls & (h.hoist < 0)]) == {"slack hoist rope (it would have to push)"}
    out = tmp_path / "h.csv"
    r = CliRunner().invoke(main, ["shovel", "haul", "eo4112_machine", "--samples", "7",
                                  "--load", "3", "-8", "-o", str(out)])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "bucket to stick" in r.output and out.stat().st_size > 500
    r = CliRunner().invoke(main, ["shovel", "haul", "mining_shovel_machine"])
    assert r.exit_code == 2 and "haul takes a rope backhoe" in r.output


# ---- the boom's hoist ([boom]: estimates; the paper and its model have no boom geometry)


def _rot(beta: float) -> np.ndarray:
    c, s = np.cos(beta), np.sin(beta)
    return np.array([[c, -s], [s, c]])


def _boom_model(hoe: RopeBackhoe, boom, hoist_mode: str):
    """The backhoe's mechanism on a moving boom: pinned at its foot O3 to the revolving frame
    and held by the hoist tackle P–G (a locked or driven linear driver), every point turned
    from the model's frame (the paper's: "x forward, y up" turned by π, then by the boom's
    angle β) into the side view, x forward and y up, where the engine's gravity acts along −y."""
    import dataclasses

    from excavkin.model.entities import Body, LinearDriver

    to_view = -_rot(boom.angle)  # p_view = −R(β)·p_model
    model = hoe.mechanism.model
    pts = {k: tuple(to_view @ np.asarray(v)) for k, v in model.points.items()}
    for name, p in (("O3", boom.foot), ("P", boom.block), ("G", boom.gantry)):
        pts[name] = tuple(to_view @ np.asarray(p))
    bodies = []
    for b in model.bodies:
        if b.ground:
            b = Body(
                b.name, (*b.points, "O3", "P"), mass=boom.mass,
                center_of_mass=tuple(to_view @ np.asarray(boom.centre)),
            )  # fmt: skip
        bodies.append(b)
    bodies.append(Body("revolving frame", ("O3", "G"), ground=True))
    linear = (*model.linear, LinearDriver("hoist", ("P", "G"), hoist_mode))
    moving = dataclasses.replace(model, points=pts, bodies=tuple(bodies), linear=linear)
    return to_view, moving


def _hoist_by_moving_boom(hoe: RopeBackhoe, boom, fe, load):
    """The tackle's pull and the foot pin's force on the boom (the model's frame) from the
    general kinetostatics of the model with a moving boom (`_boom_model`)."""
    from excavkin.kinetostatics import Gravity
    from excavkin.mechanism import Mechanism

    to_view, model = _boom_model(hoe, boom, "locked")
    mech = Mechanism(model)
    static = mech.solve({"drag": fe})
    assert static.status.ok.all()
    dig = PointForce("dig", "bucket", "D", tuple(to_view @ np.asarray(load, float)))
    first = mech.forces(static, [dig, Gravity(boom.gravity)])
    tension = -first.force("drag") / hoe.drag.parts
    # the drag rope's free part pulls the boom at its sheave towards the drum's take-off
    f = static.point(boom.sheave)[0]
    u = to_view @ np.asarray(boom.lead) - f
    u /= np.hypot(u[:, 0], u[:, 1])[:, None]
    lead = PointForce("drag lead", model.bodies[0].name, boom.sheave, tension[:, None] * u)
    forces = mech.forces(static, [dig, Gravity(boom.gravity), lead])
    np.testing.assert_allclose(-forces.force("drag") / hoe.drag.parts, tension, rtol=1e-12)
    return -forces.force("hoist"), np.linalg.solve(to_view, forces.pin("O3", "boom").T).T


@pytest.mark.parametrize("beta", [0.0, np.radians(25.0)])
@pytest.mark.parametrize("load", [(0.0, 20_000.0), (3000.0, -8000.0), (-6000.0, 12_000.0)])
def test_hoist_equals_a_model_with_a_moving_boom(beta, load):
    import dataclasses

    hoe = load_machine("eo4112_machine")
    assert hoe.boom is not None
    boom = dataclasses.replace(hoe.boom, angle=beta)
    hoe = RopeBackhoe(hoe.mechanism, hoe.drag, hoe.stick, hoe.bucket, hoe.name, None, boom)
    fe = np.linspace(3.72, 6.76, 9)
    static = hoe.mechanism.solve({"drag": fe})
    held = hoe.hoist(hoe.mechanism.forces(static, [PointForce("dig", "bucket", "D", load)]))
    pull, foot = _hoist_by_moving_boom(hoe, boom, fe, load)
    np.testing.assert_allclose(held.pull, pull, rtol=1e-9)
    np.testing.assert_allclose(held.tension * boom.parts, pull, rtol=1e-9)
    np.testing.assert_allclose(held.foot, foot, rtol=1e-9, atol=1e-9 * np.abs(foot).max())
    tension = hoe.rope_tension(hoe.mechanism.forces(static, [PointForce("d", "bucket", "D", load)]))
    assert set(held.status[(held.pull >= 0) & (tension >= 0)]) <= {"ok"}
    assert set(held.status[(held.pull < 0) & (tension >= 0)]) <= {
        "slack hoist rope (it would have to push)"
    }
    assert set(held.status[tension < 0]) <= {"slack drag rope (it would have to push)"}


def test_hoist_by_virtual_work():
    """A virtual lengthening of the tackle with the drag rope held: the boom turns about its
    foot and carries the mechanism; the loads' virtual work equals the tackle's, H·δℓ."""
    from excavkin.mechanism import Mechanism

    hoe = load_machine("eo4112_machine")
    boom = hoe.boom
    fe = np.linspace(3.72, 6.76, 9)
    load = np.array([2000.0, 15_000.0])
    static = hoe.mechanism.solve({"drag": fe})
    forces = hoe.mechanism.forces(static, [PointForce("dig", "bucket", "D", tuple(load))])
    held = hoe.hoist(forces)
    tension = hoe.rope_tension(forces)

    to_view, model = _boom_model(hoe, boom, "driven")
    mech = Mechanism(model)
    ell = np.hypot(*np.subtract(boom.gantry, boom.block))
    moved = mech.solve({"drag": fe, "hoist": np.full_like(fe, ell)},
                       {"drag": np.zeros_like(fe), "hoist": np.ones_like(fe)})  # fmt: skip
    assert moved.status.ok.all()
    back = np.linalg.inv(to_view)  # view → the model's frame, for vectors

    def rate(point: str) -> np.ndarray:
        return moved.point(point)[1] @ back.T

    down = boom.mass * boom.gravity * boom.down
    o3, c = np.asarray(boom.foot), np.asarray(boom.centre)
    f = np.asarray(hoe.mechanism.model.points[boom.sheave])
    u = (np.asarray(boom.lead) - f) / np.hypot(*(np.asarray(boom.lead) - f))
    # the boom's centre of mass turns with it: its rate from the foot's and the boom's spin
    omega = moved.body("boom")[1]
    r = c - o3
    v_c = omega[:, None] * np.array([-r[1], r[0]])
    work = rate("D") @ load + v_c @ down + tension * (rate(boom.sheave) @ u)
    np.testing.assert_allclose(held.pull, work, rtol=1e-9)


def test_a_hoist_that_would_push_is_a_status():
    from excavkin.shovel.boom import SLACK_HOIST
    from excavkin.shovel.haul import haul

    hoe = load_machine("eo4112_machine")
    fe = np.linspace(3.72, 6.76, 7)
    static = hoe.mechanism.solve({"drag": fe})
    lift = PointForce("lift", "bucket", "D", (0.0, -60_000.0))  # upwards: −y, the paper's frame
    held = hoe.hoist(hoe.mechanism.forces(static, [lift]))
    drag = hoe.rope_tension(hoe.mechanism.forces(static, [lift]))
    assert (held.pull < 0).all() and not held.ok.any() and (drag >= 0).any()
    assert set(held.status[drag >= 0]) == {SLACK_HOIST}
    assert set(held.status[drag < 0]) <= {"slack drag rope (it would have to push)"}
    pull, _ = _hoist_by_moving_boom(hoe, hoe.boom, fe, (0.0, -60_000.0))
    np.testing.assert_allclose(held.pull, pull, rtol=1e-9)
    h = haul(hoe, samples=21, force=(0.0, -60_000.0))
    assert set(h.status[h.hoist < 0]) <= {SLACK_HOIST, "slack drag rope (it would have to push)"}
    assert (h.status != "ok").all()
    assert "the hoist rope would push in" in h.summary()
    # the boom's own weight: the tackle holds it, 16.9 kN, whatever the stick does
    held = hoe.hoist(hoe.mechanism.forces(static, []))
    arm = hoe.boom.hoist_arm
    np.testing.assert_allclose(held.pull, 1800 * 9.80665 * 2.6 / arm, rtol=1e-12)
    assert held.ok.all()


def test_the_haul_table_and_summary_carry_the_hoist(tmp_path):
    import pandas as pd

    from excavkin.shovel.haul import haul

    hoe = load_machine("eo4112_machine")
    h = haul(hoe, samples=11, force=(0.0, 20_000.0))
    static = hoe.mechanism.solve({"drag": h.length})
    held = hoe.hoist(
        hoe.mechanism.forces(static, [PointForce("l", "bucket", "D", (0.0, 20_000.0))])
    )
    np.testing.assert_array_equal(h.hoist, held.tension)
    np.testing.assert_array_equal(h.boom_foot, held.foot)
    frame = h.to_frame()
    assert frame.attrs["excavkin.units"]["hoist_tension"] == "N"
    assert "hoist rope" in h.summary() and "6 parts" in h.summary()
    out = tmp_path / "h.csv"
    r = CliRunner().invoke(main, ["shovel", "haul", "eo4112_machine", "--samples", "11",
                                  "--load", "0", "20", "-o", str(out)])  # fmt: skip
    assert r.exit_code == 0, r.output
    table = pd.read_csv(out, comment="#")
    np.testing.assert_allclose(table["hoist_tension"], held.tension, rtol=1e-9)
    assert "hoist rope" in r.output and "kN a part (6 parts)" in r.output


BOOM_ERRORS = [
    ("hoist_parts = 6 ", "hoist_parts = 0 ", "'hoist_parts'"),
    ("mass = 1800 ", "mass = -5 ", "'mass'"),
    ("mass = 1800 ", 'mass = "1800 m" ', "'mass'"),
    ("foot = [5.5, 0.0]", "foot = [5.5]", "'foot'"),
    ("foot = [5.5, 0.0]", "foot = [nan, 0.0]", "'foot'"),
    ("centre = [2.9, -0.2]", "centre = [2.9, 1e6]", "'centre'"),
    ("gantry = [7.3, -3.9]", "gantry = [0.5, -0.62]", "'gantry'"),
    ("gantry = [7.3, -3.9]", "gantry = [10.5, 0.6]", "'gantry'"),  # line through the foot
    ("gantry = [7.3, -3.9]", "gantry = [7.3, 3.9]", "'gantry'"),  # would push
    ("angle = 0 ", "angle = 120 ", "'angle'"),
    ("drag_lead = [6.2, 1.1]", "drag_lead = [4.2, 0.0]", "'drag_lead'"),
    ("hoist_parts = 6 ", "hoist_parts = 6\nsheave = 3 ", "sheave"),
    ("[boom]", "[boom]\ncolour = 'red'", "colour"),
    ("drag_lead = [6.2, 1.1]", "drag_lead = [6.2, 1.1]\n[gravity]\ng = -1 #", "'g'"),
]


@pytest.mark.parametrize(("old", "new", "entry"), BOOM_ERRORS)
def test_bad_boom_entries_get_one_message(tmp_path, old, new, entry):
    import excavkin

    text = excavkin.example_path("eo4112_machine").read_text()
    assert old in text
    _refused(tmp_path, text.replace(old, new, 1), entry)


@pytest.mark.parametrize(
    ("tail", "entry"),
    [("boom = 3", "[boom]"), ("[gravity]\ng = 9.81", "[gravity]")],  # gravity without a boom
)
def test_a_boom_that_is_no_table_or_missing(tmp_path, tail, entry):
    import excavkin

    text = excavkin.example_path("eo4112_machine").read_text()
    head = text[: text.index("\n# The boom and its hoist")]
    if tail.startswith("boom"):
        head = head.replace("schema_version = 1", "schema_version = 1\n" + tail)
    else:
        head += "\n" + tail + "\n"
    _refused(tmp_path, head, entry)


def _refused(tmp_path, text, entry):
    import excavkin

    (tmp_path / "rope_shovel.toml").write_text(excavkin.example_path("rope_shovel").read_text())
    path = tmp_path / "machine.toml"
    path.write_text(text)
    r = CliRunner().invoke(main, ["shovel", "haul", str(path), "--samples", "3"])
    assert r.exit_code == 2, r.output
    assert str(path) in r.output and entry in r.output, r.output
    assert "Traceback" not in r.output and r.output.count("error") == 1
