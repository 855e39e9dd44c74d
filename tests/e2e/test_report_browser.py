"""The HTML report as a person sees it: opened from file:// in headless Chromium.

Needs Debian's Chromium (``apt-get install -y chromium``: /usr/bin/chromium) and the Python
``playwright`` package (``pip install playwright``; its own browser download is not used). When
either is missing the test fails, saying what to install: it is never skipped.

Checks: the page loads with no console errors and fetches nothing from the network; the slider
moves the mechanism (the Plotly figure's data, read from the page, changes); Play animates it;
the curves zoom; the table download is there. A screenshot is saved to ``test-artifacts/``.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

import excavkin
from excavkin.outputs.report import default_sweep, write_report

CHROMIUM = os.environ.get("EXCAVKIN_CHROMIUM", "/usr/bin/chromium")
ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--disable-quic",
]
ARTIFACTS = Path(__file__).resolve().parents[2] / "test-artifacts"

PINS_JS = """() => {
  const gd = document.getElementById('mechanism');
  const t = gd.data.find(d => d.name === 'pins');
  const s = gd._fullLayout.sliders[0];
  return {x: Array.from(t.x), y: Array.from(t.y), active: s.active,
          sample: Number(s.steps[s.active].args[0][0])};
}"""


@pytest.fixture(scope="module")
def browser():
    if not (Path(CHROMIUM).is_file() or shutil.which(CHROMIUM)):
        pytest.fail(
            f"Chromium not found at {CHROMIUM}: install it with "
            "`apt-get install -y chromium` (or set EXCAVKIN_CHROMIUM)",
            pytrace=False,
        )
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        pytest.fail(
            "the Python package playwright is missing: `pip install playwright` "
            "(no `playwright install` needed; the system Chromium is used)",
            pytrace=False,
        )
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS, headless=True)
        yield b
        b.close()


def open_report(browser, path: Path):
    page = browser.new_page(viewport={"width": 1280, "height": 1000})
    problems: list[str] = []
    page.on(
        "console",
        lambda m: problems.append(f"console {m.type}: {m.text}") if m.type == "error" else None,
    )
    page.on("pageerror", lambda e: problems.append(f"page error: {e}"))
    outside: list[str] = []

    def route(r):
        if r.request.url.startswith(("file:", "data:", "blob:")):
            r.continue_()
        else:
            outside.append(r.request.url)
            r.abort()

    page.route("**/*", route)
    page.goto(path.as_uri())
    page.wait_for_function(
        "() => { const g = document.getElementById('mechanism'); "
        "const c = document.getElementById('curves'); "
        "return g && g._fullLayout && c && c._fullLayout; }",
        timeout=20000,
    )
    return page, problems, outside


def test_report_loads_and_its_slider_moves_the_mechanism(browser, tmp_path):
    mech = excavkin.load(excavkin.example_path("fourbar"))
    res = mech.solve(default_sweep(mech))
    path = write_report(mech, res, tmp_path / "fourbar.html")
    page, problems, outside = open_report(browser, path)
    try:
        before = page.evaluate(PINS_JS)
        assert before["active"] == 0
        assert np.allclose(np.c_[before["x"], before["y"]], res.positions[0] * 1000.0, atol=1e-4)

        # drag the slider's handle to about 60 % of its rail
        rail = page.locator("#mechanism .slider-rail-rect").first.bounding_box()
        grip = page.locator("#mechanism .slider-grip-rect").first.bounding_box()
        page.mouse.move(grip["x"] + grip["width"] / 2, grip["y"] + grip["height"] / 2)
        page.mouse.down()
        page.mouse.move(rail["x"] + 0.6 * rail["width"], rail["y"] + rail["height"] / 2, steps=8)
        page.mouse.up()
        page.wait_for_timeout(300)
        after = page.evaluate(PINS_JS)
        k = after["sample"]  # the frame of the active step is named by its sample
        assert 0.45 * len(res) < k < 0.75 * len(res), k
        # the drawing is the mechanism at the sample the slider shows
        moved = np.c_[after["x"], after["y"]]
        assert not np.allclose(moved, np.c_[before["x"], before["y"]])
        assert np.allclose(moved, res.positions[k] * 1000.0, atol=1e-4)
        note = page.evaluate(
            "() => document.getElementById('mechanism')._fullLayout.annotations[0].text"
        )
        assert note.startswith(f"crank = {np.degrees(res.inputs[k, 0]):.4g}°")
        ARTIFACTS.mkdir(exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "report.png"))
        page.screenshot(path=str(ARTIFACTS / "report-full.png"), full_page=True)

        # Play runs the animation, Pause stops it
        page.get_by_text("▶ Play").click()
        page.wait_for_timeout(600)
        page.get_by_text("❚❚ Pause").click()
        page.wait_for_timeout(200)
        played = page.evaluate(PINS_JS)
        assert played["sample"] != k

        # the curves zoom: drag a box on the first panel
        page.locator("#curves").scroll_into_view_if_needed()
        box = page.locator("#curves .nsewdrag").first.bounding_box()
        x0 = page.evaluate("() => document.getElementById('curves')._fullLayout.xaxis.range")
        page.mouse.move(box["x"] + 0.2 * box["width"], box["y"] + 0.3 * box["height"])
        page.mouse.down()
        page.mouse.move(box["x"] + 0.5 * box["width"], box["y"] + 0.7 * box["height"], steps=6)
        page.mouse.up()
        page.wait_for_timeout(300)
        x1 = page.evaluate("() => document.getElementById('curves')._fullLayout.xaxis.range")
        assert x1[1] - x1[0] < 0.5 * (x0[1] - x0[0])

        href = page.locator("#download-table").get_attribute("href")
        assert href.startswith("data:text/csv;base64,")
        assert "low transmission" in page.locator("#warnings-section").inner_text()

    finally:
        page.close()
    assert problems == [], problems
    assert outside == [], f"the report fetched from the network: {outside}"


def test_report_of_a_mechanism_that_does_not_close_everywhere(browser, tmp_path):
    text = excavkin.example_path("fourbar").read_text()
    text = text.replace("A  = [0, 40]", "A  = [0, 80]").replace('"A-B"  = 120', '"A-B"  = 60')
    mech = excavkin.loads(text.replace("B  = [110, 90]", "B  = [50, 110]"), "double-rocker")
    res = mech.solve({"crank": np.radians(np.linspace(0.0, 360.0, 73))})
    path = write_report(mech, res, tmp_path / "dr.html")
    page, problems, outside = open_report(browser, path)
    try:
        warnings = page.locator("#warnings-section").inner_text()
        assert "does not close" in warnings and "cannot close at dyad B" in warnings
        # at a sample that does not close the box says so
        page.evaluate(
            "() => Plotly.animate('mechanism', ['30'], {mode: 'immediate', "
            "frame: {duration: 0, redraw: false}, transition: {duration: 0}})"
        )
        page.wait_for_timeout(200)
        note = page.evaluate(
            "() => document.getElementById('mechanism')._fullLayout.annotations[0].text"
        )
        assert "cannot close" in note
        ARTIFACTS.mkdir(exist_ok=True)
        page.locator("#warnings-section").screenshot(path=str(ARTIFACTS / "report-warnings.png"))
    finally:
        page.close()
    assert problems == [], problems
    assert outside == []
