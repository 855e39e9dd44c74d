"""The machine report: the core's layout (values, tables, charts, the file written safely), each
family's sections for every built-in machine — their numbers read back from the page equal the
analyses' own — and ``excavkin loader|excavator report``."""

from __future__ import annotations

import functools
import math
import re
import tomllib
from html.parser import HTMLParser
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

import excavkin
from excavkin.cli import main
from excavkin.families import load_machine
from excavkin.outputs.machine_report import (
    Chart,
    MachineReport,
    Section,
    Table,
    Value,
    build_machine_report,
    write_machine_report,
)
from excavkin.outputs.tables import OutputError

matplotlib.use("Agg")

#: the sweeps' sizes here: small, the numbers checked do not depend on them
SAMPLES = {"loader": 5, "excavator": 4}


class _Values(HTMLParser):
    """Every ``data-key`` element of a page: its SI value, unit and shown text."""

    def __init__(self) -> None:
        super().__init__()
        self.found: dict[str, tuple[float, str, str]] = {}
        self._open: tuple[str, float, str] | None = None
        self.ids: list[str] = []
        self.images = 0

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = dict(attrs)
        if a.get("id"):
            self.ids.append(str(a["id"]))
        if tag == "img" and str(a.get("src", "")).startswith("data:image/png;base64,"):
            self.images += 1
        if "data-key" in a:
            assert a["data-key"] not in self.found, f"key {a['data-key']} twice"
            self._open = (str(a["data-key"]), float(str(a["data-si"])), str(a["data-unit"]))

    def handle_data(self, data: str) -> None:
        if self._open is not None:
            key, si, unit = self._open
            self.found[key] = (si, unit, data)
            self._open = None


def values(text: str) -> _Values:
    p = _Values()
    p.feed(text)
    return p


def assert_self_contained(text: str) -> None:
    assert text.startswith("<!DOCTYPE html>")
    assert not re.search(r"<(script|link|img|iframe)[^>]+(src|href)=\"?(https?:)?//", text)
    assert "<script src" not in text and "@import" not in text
    assert "url(http" not in text


# ---------------------------------------------------------------------------------- the core
def test_a_value_is_shown_in_its_unit_and_carries_si() -> None:
    assert Value(1.2344, "length", "mm").text() == "1\u2009234"
    assert Value(142_600.0, "force", "kN", 1).text(with_unit=True) == "142.6\u00a0kN"
    assert Value(math.radians(45.0), "angle", "deg", 1).text() == "45.0"
    assert Value(float("nan"), "mass", "kg").text() == "—"
    assert Value(-1e-9, "length", "mm").text() == "0"
    assert Value(3.0, "", "m^3", 2).text() == "3.00"
    with pytest.raises(ValueError, match="2 cells for 3 columns"):
        Table("t", ("a", "b", "c"), (("x", "y"),))


def _small_report() -> MachineReport:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    return MachineReport(
        "demo <machine>",
        "a family",
        "",
        (("mass", Value(1800.0, "mass", "kg", key="mass")), ("axle", "rigid")),
        (
            Section(
                "size",
                "Size",
                "ISO 0000",
                "what it is",
                (
                    Table(
                        "sizes", ("figure", "mm"), (("reach", Value(1.25, "length", "mm", 0, "r")),)
                    ),
                ),
                (Chart("a line", "ISO 0000", fig, "line"),),
                ("reach: limited by the ruler",),
            ),
        ),
        "excavkin x",
    )


def test_the_core_lays_out_what_it_is_given(tmp_path: Path) -> None:
    text = build_machine_report(_small_report())
    assert_self_contained(text)
    assert "demo &lt;machine&gt;" in text and "<machine>" not in text  # escaped
    v = values(text)
    assert v.found["mass"] == (1800.0, "kg", "1\u2009800")
    assert v.found["r"] == (1.25, "mm", "1\u2009250")
    assert v.images == 1 and "size-section" in v.ids and "line" in v.ids
    assert "reach: limited by the ruler" in text and "ISO 0000" in text
    assert "Plotly.newPlot" not in text and len(text) < 500_000  # no plotly.js: none needed


def test_the_file_is_never_overwritten_unless_asked(tmp_path: Path) -> None:
    out = tmp_path / "r.html"
    out.write_text("mine")
    with pytest.raises(OutputError, match="exists"):
        write_machine_report(_small_report(), out)
    assert out.read_text() == "mine"
    with pytest.raises(OutputError, match=r"\.html"):
        write_machine_report(_small_report(), tmp_path / "r.txt")
    with pytest.raises(OutputError, match="does not exist"):
        write_machine_report(_small_report(), tmp_path / "nowhere" / "r.html")
    write_machine_report(_small_report(), out, force=True)
    assert out.read_text().startswith("<!DOCTYPE html>")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.html"]  # no temporary left


# ------------------------------------------------------------------------- the families' reports
#: each built-in machine's family, by its file's ``family`` key (an excavator's file has none)
FAMILIES = {
    n: tomllib.loads(excavkin.example_path(n).read_text()).get("family", "excavator")
    for n in excavkin.examples("machine")
}
#: the families whose reports have the sections tested here (dimensions, forces, pins …); the
#: crane's and the rope shovel's reports have sections of their own, tested with their wings
#: (tests/unit/test_crane.py, tests/unit/test_shovel.py), and the rope backhoe has none
REPORTED = [n for n, f in FAMILIES.items() if f in ("loader", "excavator")]
LOADERS = [n for n in REPORTED if FAMILIES[n] == "loader"]
EXCAVATORS = [n for n in REPORTED if FAMILIES[n] == "excavator"]
OWN_REPORTS = {n: f for n, f in FAMILIES.items() if n not in REPORTED}


def _family(machine: object) -> str:
    from excavkin.loader.machine import Loader

    return "loader" if isinstance(machine, Loader) else "excavator"


@functools.cache
def page(name: str) -> tuple[object, str, str]:
    """(machine, family, page) of a built-in machine's report."""
    m = load_machine(excavkin.example_path(name))
    family = _family(m)
    if family == "loader":
        from excavkin.loader.report import machine_report
    else:
        from excavkin.excavator.report import machine_report
    seen: list[tuple[int, int]] = []
    report = machine_report(m, samples=SAMPLES[family], progress=lambda d, n: seen.append((d, n)))
    n = len(report.sections)
    assert seen == [(i + 1, n) for i in range(n)]
    return m, family, build_machine_report(report)


def test_every_built_in_machine_is_of_a_family_with_a_report() -> None:
    assert LOADERS and EXCAVATORS and sorted(LOADERS + EXCAVATORS) == sorted(REPORTED)
    assert sorted(OWN_REPORTS) == [
        "eo4112_machine",
        "knuckle_crane_machine",
        "mining_shovel_machine",
        "synchronised_crane_machine",
        "telescopic_crane_machine",
    ]
    assert set(OWN_REPORTS.values()) == {"crane", "shovel"}
    for n in REPORTED:
        assert _family(load_machine(excavkin.example_path(n))) == FAMILIES[n]


@pytest.mark.parametrize("name", REPORTED)
def test_the_report_is_self_contained_with_every_section(name) -> None:
    m, family, text = page(name)
    assert_self_contained(text)
    v = values(text)
    sections = {"identity", "dimensions", "forces", "pins", "front"}
    sections |= {"stability"} if family == "loader" or m.base is not None else set()
    sections |= {"cycle"} if m.hydraulics is not None else set()
    assert sections <= {i.removesuffix("-section") for i in v.ids}
    assert "Plotly.newPlot" in text and 'id="front"' in text  # the moving front
    assert v.images >= 5
    for key, (si, unit, shown) in v.found.items():  # what is shown is the SI value converted
        if math.isfinite(si) and unit and unit != "m^3":
            got = float(shown.replace("\u2009", ""))
            shown_value = Value(si, _KIND[unit], unit).shown
            digits = len(shown.partition(".")[2])
            assert abs(got - shown_value) <= 0.5 * 10.0**-digits + 1e-9, (key, shown, si)


_KIND = {"mm": "length", "kN": "force", "kg": "mass", "deg": "angle", "s": "time",
         "MPa": "pressure", "kW": "power", "L/min": "volume_flow", "kN*m": "torque",
         "kJ": "energy"}  # fmt: skip


def _close(found: dict[str, tuple[float, str, str]], key: str, expected: float) -> None:
    assert key in found, f"{key} not on the page"
    got = found[key][0]
    if math.isnan(expected):
        assert math.isnan(got), key
    else:
        assert_allclose(got, expected, rtol=1e-9, atol=1e-12, err_msg=key)


@pytest.mark.parametrize("name", LOADERS)
def test_the_loader_figures_are_the_analyses(name) -> None:
    m, _, text = page(name)
    from excavkin.loader.breakout import breakout
    from excavkin.loader.capacity import capacity
    from excavkin.loader.cycle import cycle
    from excavkin.loader.dimensions import dimensions
    from excavkin.loader.parallel_lift import parallel_lift
    from excavkin.loader.pins import pin_loads
    from excavkin.loader.tipping import static_tipping

    f = values(text).found
    _close(f, "mass.operating", m.mass)
    _close(f, "cylinder.lift.bore", m.cylinders[0].bore)
    for d in dimensions(m).figures:
        _close(f, f"dimensions.{d.name}", d.value)
    bo = breakout(m)
    for r in (bo.tilt, bo.lift):
        for what in ("force", "working", "hydraulic", "tipping"):
            _close(f, f"breakout.{r.circuit}.{what}", getattr(r, what))
    tl = static_tipping(m)
    _close(f, "tipping.straight.load", tl.straight.load)
    _close(f, "tipping.full turn.load", tl.full_turn.load)
    _close(f, "tipping.rated_operating_capacity", tl.rated_operating_capacity)
    n = SAMPLES["loader"]
    cap = capacity(m, n)
    _close(f, "capacity.to_full_height", cap.to_full_height)
    _close(f, "capacity.least_rollback", float(np.nanmin(cap.rollback)))
    pl = parallel_lift(m, n)
    _close(f, "parallel_lift.change", pl.change)
    _close(f, "parallel_lift.deviation", pl.deviation)
    cy = cycle(m)
    for p in cy.phases:
        _close(f, f"cycle.{p.name}.time", p.time)
        _close(f, f"cycle.{p.name}.pressure", p.pressure)
    _close(f, "cycle.total", cy.total)
    for pin, load, _, _ in pin_loads(m, n).largest():
        _close(f, f"pins.{pin}.load", load)
    assert f"limited by {bo.lift.limiting.replace('lift', 'lift cylinder')}" in text


@pytest.mark.parametrize("name", EXCAVATORS)
def test_the_excavator_figures_are_the_analyses(name) -> None:
    m, _, text = page(name)
    from excavkin.excavator.forces import rated_force
    from excavkin.excavator.hydraulics import cycle_time
    from excavkin.excavator.pin_loads import CASES, load_maxima, pin_loads
    from excavkin.excavator.ranges import stroke_grid, working_ranges
    from excavkin.excavator.stability import base_rated_force

    f = values(text).found
    _close(f, "mass.front", m.front_mass)
    for r in working_ranges(m).figures:
        _close(f, f"ranges.{r.key}", r.value)
    for at in ("lip", "tip"):
        for working in ("arm", "bucket"):
            _close(f, f"forces.{at}.{working}.force", rated_force(m, working, at=at).force)
    b = base_rated_force(m, "bucket", at="lip", swing="front")
    _close(f, "stability.lip.bucket.force", b.rated.force)
    _close(f, "stability.lip.bucket.tipping", b.tipping)
    grid = stroke_grid(m, SAMPLES["excavator"])
    for mx in load_maxima(tuple(pin_loads(m, grid, c) for c in CASES)):
        _close(f, f"pins.{mx.name}.load", mx.value)
    _close(f, "cycle.sequential", cycle_time(m).sequential)


# -------------------------------------------------------------------------------------- CLI
@pytest.mark.parametrize(
    ("family", "machine"),
    [("loader", "wheel_loader_tp_machine"), ("excavator", "excavator_machine")],
)
def test_the_report_command_writes_refuses_and_forces(tmp_path, family, machine) -> None:
    out = tmp_path / "spec.html"
    args = [family, "report", machine, "-o", str(out), "--samples", str(SAMPLES[family])]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    assert f"wrote {out}" in r.output
    text = out.read_text()
    assert_self_contained(text)
    assert f"excavkin {family} report {machine} --samples {SAMPLES[family]}" in text
    stamp = out.stat().st_mtime_ns
    again = CliRunner().invoke(main, args)
    assert again.exit_code == 2 and "exists" in again.output and "--force" in again.output
    assert out.stat().st_mtime_ns == stamp
    if family == "loader":  # the quicker one: replaced when asked, quietly
        quiet = CliRunner().invoke(main, [*args, "--force", "-q"])
        assert quiet.exit_code == 0 and quiet.output == ""
        assert out.stat().st_mtime_ns != stamp


def test_the_report_command_refuses_bad_input_in_one_line(tmp_path) -> None:
    cases = [
        (["loader", "report", "excavator_machine", "-o", str(tmp_path / "a.html")],
         "loader machine files"),
        (["loader", "report", "wheel_loader_machine", "-o", str(tmp_path / "a.csv")], ".html"),
        (["excavator", "report", "excavator_machine", "--samples", "1"], "--samples"),
        (["excavator", "report", "excavator_machine", "--samples", "52"], "--samples"),
        (["loader", "report", "nowhere.toml"], "no such file"),
    ]  # fmt: skip
    for args, message in cases:
        r = CliRunner().invoke(main, args)
        assert r.exit_code == 2, (args, r.output)
        assert message in r.output and "Traceback" not in r.output
    assert list(tmp_path.iterdir()) == []


def test_the_default_file_is_named_after_the_machine(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    r = CliRunner().invoke(main, ["loader", "report", "wheel_loader_machine", "--samples", "3"])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "wheel_loader_machine.html").is_file()


def _cut(name: str, header: str, tmp_path: Path) -> Path:
    """A copy of a built-in machine file without its tables from ``header`` on."""
    text = excavkin.example_path(name).read_text()
    assert header in text
    path = tmp_path / f"{name}.toml"
    path.write_text(
        text[: text.index(header)]
        .replace('"wheel_loader.toml"', f'"{excavkin.example_path("wheel_loader")}"')
        .replace('"excavator.toml"', f'"{excavkin.example_path("excavator")}"')
    )
    return path


def test_a_machine_without_hydraulics_or_base_has_no_such_section(tmp_path) -> None:
    from excavkin.loader.report import report_sections

    loader = load_machine(_cut("wheel_loader_machine", "[hydraulics]", tmp_path))
    assert loader.hydraulics is None
    assert "cycle" not in [s.key for s in report_sections(loader, samples=3)]
    out = tmp_path / "excavator.html"
    path = _cut("excavator_machine", "# The base machine", tmp_path)
    r = CliRunner().invoke(
        main, ["excavator", "report", str(path), "-o", str(out), "--samples", "2"]
    )
    assert r.exit_code == 0, r.output
    ids = values(out.read_text()).ids
    assert "stability-section" not in ids and "cycle-section" not in ids
    assert "forces-section" in ids and "front" in ids
    assert "No base machine in the machine file: no stability section." in out.read_text()
