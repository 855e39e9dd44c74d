"""The rope-shovel wing's machine file, drives, options, commands and studies (issue 27)."""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

import excavkin
from excavkin.cli import main
from excavkin.errors import ExcavkinError, InputError, ModelError
from excavkin.families import families
from excavkin.shovel.dig import dig
from excavkin.shovel.machine import Shovel
from excavkin.shovel.machine_file import loads_machine
from excavkin.shovel.study import (
    COLUMNS,
    design_shovel,
    shovel_columns,
    shovel_figures,
    shovel_parameters,
)

matplotlib.use("Agg")
SOURCE = excavkin.example_path("mining_shovel_machine")
TEXT = SOURCE.read_text()


def _read(text: str) -> Shovel:
    machine = loads_machine(text, str(SOURCE))
    assert isinstance(machine, Shovel)
    return machine


@pytest.fixture(scope="module")
def shovel() -> Shovel:
    return _read(TEXT)


def test_the_family_is_registered_and_the_file_read(shovel) -> None:
    fam = families()["shovel"]
    assert fam.kind == "machine" and "mining_shovel_machine" in excavkin.examples("machine")
    assert isinstance(fam.read("mining_shovel_machine"), Shovel)
    h, c = shovel.hoist, shovel.crowd
    # the drives from the motors: pull n·τ·i/R, speed ω·R/i; force n·τ·i/r, speed ω·r/i
    omega_h, omega_c = 750 * 2 * math.pi / 60, 900 * 2 * math.pi / 60
    assert h.pull == pytest.approx(2 * 16e3 * 80 / 0.95, rel=1e-12)
    assert h.speed == pytest.approx(omega_h * 0.95 / 80, rel=1e-12)
    assert c.force == pytest.approx(9e3 * 60 / 0.6, rel=1e-12)
    assert c.speed == pytest.approx(omega_c * 0.6 / 60, rel=1e-12)
    assert h.motor.power == pytest.approx(2 * 16e3 * omega_h, rel=1e-12)
    assert shovel.front_mass == 207000.0 and shovel.base is not None
    assert shovel.base.mass == 1.25e6
    assert "hoist 2695 kN" in repr(shovel)


def test_the_machine_files_gearing_is_the_models_rope(shovel) -> None:
    other = _read(TEXT.replace("gear_ratio = 80", "gear_ratio = 70"))
    rope = next(r for r in other.mechanism.model.ropes if r.name == "hoist")
    assert rope.gear_ratio == 70.0 and rope.drum_radius == 0.95
    # the same rope length, so the same pose, at the new motor angle
    a = shovel.solve(np.array([35.0]), np.array([8.0])).point("K")[0]
    b = other.solve(np.array([35.0]), np.array([8.0])).point("K")[0]
    np.testing.assert_allclose(a, b, atol=1e-9)
    np.testing.assert_allclose(other.hoist.angle(35.0), 35.0 * 70 / 0.95)


@pytest.mark.parametrize(
    ("old", "new", "where"),
    [
        ('family = "shovel"', 'family = "loader"', "this reader reads rope-shovel"),
        ('boom = "boom"', 'boom = "jib"', "[front] 'boom': 'jib' is not a body"),
        ('teeth = "K"', 'teeth = "S"', "[front] 'teeth': 'S' is not a point of the body"),
        ('suspension = "suspension"', 'suspension = "hoist"', "not a locked rope"),
        ('rope = "hoist"', 'rope = "suspension"', "[hoist] 'rope'"),
        ('driver = "crowd"', 'driver = "brace"', "not a driven linear driver"),
        ("length = [29.0, 46.0]", "length = [46.0, 29.0]", "must be below the longest"),
        ("length = [29.0, 46.0]", "length = 29", "must be [shortest, longest]"),
        ("motors = 2 ", "motors = 0 ", "[hoist] 'motors'"),
        ("motor_torque = 16 ", "motor_torque = -16 ", "[hoist] 'motor_torque'"),
        ('payload_point = "PC"', 'payload_point = "BF"', "not a point of the dipper"),
        ("[crowd]", "[crowds]", "crowds"),
        ("pinion_radius = 0.6 ", "pinion_radius = 0.5 ", "passes 0.6 m from the shipper shaft"),
    ],
)
def test_each_bad_entry_is_one_message(old: str, new: str, where: str) -> None:
    assert old in TEXT
    with pytest.raises(ModelError) as err:
        _read(TEXT.replace(old, new, 1))
    assert where in str(err.value) and "mining_shovel_machine.toml" in str(err.value)


@pytest.mark.parametrize(
    ("kw", "message"),
    [
        ({"samples": 2}, "samples"),
        ({"crowd_speed": 1.5}, "crowd speed"),
        ({"model": "coulomb"}, "unknown soil model"),
        ({"soil_name": "mud"}, "unknown soil"),
        ({"depth": 0.0}, "depth"),
        ({"rake": 0.0}, "rake"),
        ({"fill": 1.2}, "fill"),
        ({"extension": 20.0}, "outside the crowd's range"),
        ({"extension": 5.0}, "puts the tooth tip on the ground"),
    ],
)
def test_the_dig_refuses_bad_options_by_name(shovel, kw, message) -> None:
    with pytest.raises(InputError, match=message):
        dig(shovel, **kw)


def test_the_dig_table_and_its_plot(shovel, tmp_path) -> None:
    d = dig(shovel, samples=9)
    frame = d.to_frame()
    assert len(frame) == 9 and frame.attrs["excavkin.units"]["bail_pull"] == "N"
    np.testing.assert_allclose(frame["bail_pull"], frame["bail_pull_per_rope"] * 2)
    # the hoist hauls in at its rated speed: the motor's speed is −v·i/R
    np.testing.assert_allclose(frame["hoist_length"].diff().dropna() / np.diff(d.time),
                               -shovel.hoist.speed)  # fmt: skip
    assert d.teeth[0, 1] == pytest.approx(0.0, abs=1e-9)
    assert d.fill[0] == 0.0 and d.fill[-1] == 1.0
    handle = d.plot(shovel)
    assert {"bail", "crowd", "margin"} <= set(handle.artists)
    with pytest.raises(TypeError):
        d.plot(shovel, colour="red")  # type: ignore[call-arg]


def test_the_commands_write_tables_and_figures(tmp_path) -> None:
    out, fig = tmp_path / "e.csv", tmp_path / "e.png"
    r = CliRunner().invoke(
        main, ["shovel", "envelope", "mining_shovel_machine", "--samples", "7", "-o", str(out),
               "--plot", str(fig)],
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "cutting height" in r.output and fig.stat().st_size > 10_000
    table = pd.read_csv(out)
    assert list(table["figure"]) == [
        "cutting height", "cutting radius", "dump height", "dump radius", "radius at floor level",
    ]  # fmt: skip
    again = CliRunner().invoke(main, ["shovel", "dig", "mining_shovel_machine", "-o", str(out)])
    assert again.exit_code == 2 and "--force" in again.output  # the file is kept
    assert list(pd.read_csv(out)["figure"])[0] == "cutting height"
    r = CliRunner().invoke(main, ["shovel", "loads", "mining_shovel_machine", "--samples", "4",
                                  "-o", str(tmp_path / "l.csv")])  # fmt: skip
    assert r.exit_code == 0 and "suspension ropes" in r.output
    bad = CliRunner().invoke(main, ["shovel", "dig", "mining_shovel_machine", "--rake", "190"])
    assert bad.exit_code == 2 and "--rake" in bad.output


def test_a_design_is_a_shovel_of_its_own(shovel) -> None:
    params = shovel_parameters(shovel)
    assert params["hoist.gear_ratio"] == 80.0 and params["S.y"] == pytest.approx(10.942)
    one = design_shovel(shovel, {"hoist.gear_ratio": 60.0, "dipper.payload": 80e3})
    assert one.hoist.speed == pytest.approx(shovel.hoist.speed * 80 / 60, rel=1e-12)
    assert next(r for r in one.mechanism.model.ropes if r.name == "hoist").gear_ratio == 60.0
    assert one.dipper.payload == 80e3 and shovel.dipper.payload == 100e3
    figures = shovel_figures(one, ["hoist.pull", "front_mass"])
    assert figures["hoist.pull"] == pytest.approx(shovel.hoist.pull * 60 / 80, rel=1e-12)
    cols, ok = shovel_columns(
        shovel, {"hoist.gear_ratio": np.array([60.0, 80.0, 60.0])}, ["hoist.speed"], 3
    )
    assert ok.all() and cols["hoist.speed"][0] == cols["hoist.speed"][2]
    with pytest.raises(ExcavkinError, match="parameter"):
        design_shovel(shovel, {"hoist.ratio": 60.0})
    assert set(COLUMNS) >= {"envelope.cutting_height", "dig.margin", "loads.suspension"}


def test_the_report_has_its_sections_and_values(tmp_path) -> None:
    import re

    out = tmp_path / "s.html"
    r = CliRunner().invoke(
        main, ["shovel", "report", "mining_shovel_machine", "--samples", "5", "-o", str(out), "-q"]
    )
    assert r.exit_code == 0, r.output
    text = out.read_text()
    assert re.findall(r"<h2[^>]*>(.*?)</h2>", text) == [
        "Machine", "Digging envelope", "Along a dig", "Boom loads", "Moving front",
    ]  # fmt: skip
    shown = re.search(r'data-key="hoist.pull"[^>]*>([^<]*)<', text)
    assert shown is not None and shown.group(1).replace("\u2009", "").replace(" ", "") == "2694.7"
    assert "<script" in text and "Plotly.newPlot" in text
    refused = CliRunner().invoke(main, ["shovel", "report", "eo4112_machine", "-o", str(out)])
    assert refused.exit_code == 2 and "rope backhoe" in refused.output


def test_stability_needs_a_base(tmp_path) -> None:
    no_base = TEXT[: TEXT.index("[base]")]
    path = tmp_path / "m.toml"
    model = SOURCE.parent / "mining_shovel.toml"
    path.write_text(no_base.replace('model = "mining_shovel.toml"', f'model = "{model}"'))
    assert _read(no_base).base is None
    r = CliRunner().invoke(main, ["shovel", "stability", str(path), "--samples", "3"])
    assert r.exit_code == 2 and "no [base] table" in r.output
