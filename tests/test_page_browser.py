"""The interactive page (``linkgen page``) in a real browser: headless Chromium driven by Selenium.
The page loads from the file alone without a console error, and clicking the crank-angle slider at
one of its ticks puts the crank pin's marker where the closed form puts the pin at that angle,
mapped to pixels through the axis ranges plotly reports from the page. The screenshot is
kept beside the page in the test's tmp dir."""

import json
import math
import shutil
from pathlib import Path

import numpy as np

from linkgen.families.planar.positions import positions
from linkgen.pipeline.registry import load, stage

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM, CHROMEDRIVER = shutil.which("chromium") or "/usr/bin/chromium", shutil.which("chromedriver") or "/usr/bin/chromedriver"
# The marker's centre against the closed form's pin [px]: plotly rounds marker positions to 0.01 px
# in the SVG; 1 px covers that and the browser's sub-pixel layout of the plot area.
PIN_PIXELS = 1.0
FRAMES = 12
# A slider step that moves the pin by less than this [px] would not show the mechanism moving.
MOVES = 20.0


def _driver():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1300,950",
              "--force-device-scale-factor=1"):
        opts.add_argument(a)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=opts)


PIN_JS = """
const gd = document.getElementById('linkgen-page');
const k = gd.data.findIndex(t => t.name === arguments[0]);
const node = gd.querySelectorAll('.scatterlayer .trace')[k].querySelector('path.point');
const r = node.getBoundingClientRect(), box = gd.querySelector('.main-svg').getBoundingClientRect();
const xa = gd._fullLayout.xaxis, ya = gd._fullLayout.yaxis;
return JSON.stringify({px: [r.left + r.width / 2 - box.left, r.top + r.height / 2 - box.top],
                       x: [xa.range, xa._offset, xa._length], y: [ya.range, ya._offset, ya._length],
                       data: [gd.data[k].x[0], gd.data[k].y[0]]});
"""
VISIBLE_JS = ("const t = document.getElementById('linkgen-page').data.find(t => t.name.startsWith(arguments[0])); "
              "return t.visible")
CURRENT_JS = "return [...document.querySelectorAll('.slider-container text')].map(t => t.textContent).join('|')"


def _click_step(d, k: int) -> None:
    """Click the slider's rail at its k-th tick, as a user does, and wait for the page to show it."""
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.support.ui import WebDriverWait

    rail = d.find_element("css selector", ".slider-rail-rect")
    tick = d.find_elements("css selector", ".slider-tick-rect")[k].rect
    r = rail.rect
    ActionChains(d).move_to_element_with_offset(rail, round(tick["x"] + tick["width"] / 2 - r["x"] - r["width"] / 2),
                                                0).click().perform()
    label = d.execute_script("return document.getElementById('linkgen-page')._fullLayout.sliders[0].steps[arguments[0]]"
                             ".label", k)
    WebDriverWait(d, 10).until(lambda drv: f"φ = {label}" in drv.execute_script(CURRENT_JS))


def _expected_pixels(axes, x, y):
    """Data → pixels through the axis ranges read from the page (y grows downwards on screen)."""
    (xr, xo, xl), (yr, yo, yl) = axes
    return np.array([xo + (x - xr[0]) / (xr[1] - xr[0]) * xl, yo + (yr[1] - y) / (yr[1] - yr[0]) * yl])


def test_page_loads_and_the_slider_moves_the_crank_pin(tmp_path):
    desc = load(ROOT / "models" / "fourbar.toml")
    page = tmp_path / "fourbar.html"
    stage(desc, "page")(desc, page, FRAMES)
    mech = desc
    phi = np.linspace(mech.drive.start, mech.drive.stop, FRAMES, endpoint=False)
    pin = positions(mech, phi).points["A"]
    d = _driver()
    try:
        d.get(page.as_uri())
        seen = []
        for k in (3, 7, 0):
            _click_step(d, k)
            assert f"φ = {math.degrees(phi[k]):.0f}°" in d.execute_script(CURRENT_JS)
            got = json.loads(d.execute_script(PIN_JS, "crank pin"))
            want = _expected_pixels((got["x"], got["y"]), *pin[k])
            np.testing.assert_allclose(got["px"], want, atol=PIN_PIXELS)
            seen.append(np.array(got["px"]))
        from selenium.webdriver.support.ui import WebDriverWait

        # the vectors turn on and off from the legend (each click takes effect after plotly's double-click delay)
        for want in (True, "legendonly"):
            item = next(e for e in d.find_elements("css selector", ".legend .traces")
                        if e.text.startswith("acceleration"))
            item.find_element("css selector", ".legendtoggle").click()
            WebDriverWait(d, 5).until(lambda drv: drv.execute_script(VISIBLE_JS, "acceleration") == want)
        d.save_screenshot(str(tmp_path / "fourbar_page.png"))
        external = d.execute_script("return document.querySelectorAll('script[src], link[href]').length")
        errors = [e for e in d.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]
    finally:
        d.quit()
    assert errors == []
    assert min(np.linalg.norm(a - b) for a, b in zip(seen, seen[1:])) > MOVES
    assert (tmp_path / "fourbar_page.png").stat().st_size > 10_000
    assert external == 0  # self-contained: plotly.js inline, nothing fetched, works offline
