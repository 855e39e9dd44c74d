"""The machine report as a person sees it: a loader's spec sheet opened from file:// in headless
Chromium (the set-up of ``test_report_browser``: Debian's Chromium and the ``playwright``
package, never skipped).

Checks: the page loads with no console errors and fetches nothing; every chart's PNG decodes;
the moving front's slider frames draw the linkage at the engine's positions; the navigation
links reach every section. A screenshot is saved to ``test-artifacts/``.
"""

from __future__ import annotations

import matplotlib
import numpy as np
from tests.e2e.test_report_browser import ARTIFACTS, browser  # noqa: F401 (a fixture)

import excavkin
from excavkin.families import load_machine
from excavkin.loader.report import front_lengths, machine_report
from excavkin.outputs.machine_report import write_machine_report

matplotlib.use("Agg")

PINS_JS = """(k) => {
  const gd = document.getElementById('front');
  const f = gd._transitionData._frames.find(f => f.name === String(k));
  const i = gd.data.findIndex(d => d.name === 'pins');
  const t = f.data[f.traces.indexOf(i)];
  return {x: Array.from(t.x), y: Array.from(t.y)};
}"""


def test_a_loader_report_loads_and_its_front_moves(browser, tmp_path):  # noqa: F811
    m = load_machine(excavkin.example_path("wheel_loader_machine"))
    path = write_machine_report(machine_report(m, samples=3), tmp_path / "loader.html")
    page = browser.new_page(viewport={"width": 1280, "height": 1000})
    problems: list[str] = []
    page.on("console", lambda x: problems.append(x.text) if x.type == "error" else None)
    page.on("pageerror", lambda e: problems.append(f"page error: {e}"))
    outside: list[str] = []

    def route(r):
        if r.request.url.startswith(("file:", "data:", "blob:")):
            r.continue_()
        else:
            outside.append(r.request.url)
            r.abort()

    page.route("**/*", route)
    try:
        page.goto(path.as_uri())
        page.wait_for_function(
            "() => { const g = document.getElementById('front'); return g && g._fullLayout; }",
            timeout=20000,
        )
        sizes = page.evaluate(
            "() => Array.from(document.images).map(i => [i.complete, i.naturalWidth])"
        )
        assert len(sizes) >= 7 and all(done and w > 300 for done, w in sizes), sizes
        # the frames draw the engine's positions of the front's lengths (mm)
        res = m.solve(front_lengths(m))
        points = [m.mechanism.plan.points.index(p) for p in (m.pins.hinge, m.pins.lift_arm_pin)]
        for k in (0, len(res) // 2, len(res) - 1):
            got = page.evaluate(PINS_JS, k)
            drawn = np.c_[got["x"], got["y"]]
            for j in points:  # each pin of the model is drawn where the engine put it
                assert np.min(np.hypot(*(drawn - res.positions[k, j] * 1e3).T)) < 1e-6
        # Play moves it
        page.locator("#front").scroll_into_view_if_needed()
        page.get_by_text("▶ Play").click()
        page.wait_for_timeout(700)
        page.get_by_text("❚❚ Pause").click()
        active = page.evaluate(
            "() => document.getElementById('front')._fullLayout.sliders[0].active"
        )
        assert active > 0
        for link in page.locator("nav a").all():
            target = link.get_attribute("href")
            assert page.locator(target).count() == 1, target
        ARTIFACTS.mkdir(exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "machine-report.png"), full_page=True)
    finally:
        page.close()
    assert problems == [], problems
    assert outside == [], f"the report fetched from the network: {outside}"
