"""Headless Chromium for the HTML reports: open a page, wait for Bokeh, read what it drew.

Used by tests/test_report_browser.py and benchmarks/report_bench.py. Needs
Debian's ``chromium`` and ``chromium-driver`` (``.ci/run`` installs them) and
selenium (the ``[test]`` extra); without them :func:`open_chromium` fails,
it never skips.
"""

from __future__ import annotations

import shutil
import time
from pathlib import Path
from typing import Any, Dict

import numpy as np

#: Debian's binaries.
CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"
#: Window of the headless browser, px (a laptop screen, tall enough for a whole log report).
WINDOW = (1400, 1900)

#: JavaScript: true once Bokeh has a document and every plot of it has drawn at least once.
_READY = """
const B = window.Bokeh;
if (!B || !B.documents || B.documents.length === 0) return false;
const views = [];
const walk = (v) => { if (!v) return; views.push(v); for (const c of (v.child_views ?? [])) walk(c);
                      for (const c of (v.renderer_views?.values?.() ?? [])) walk(c); };
for (const v of B.index.roots ?? Object.values(B.index)) walk(v);
const plots = views.filter((v) => v.model?.type === 'Figure' || v.model?.constructor?.__name__ === 'Figure');
const ready = plots.length > 0 && plots.every((v) => v.is_idle !== false && v.has_finished?.() !== false);
return ready ? performance.now() / 1000 : false;
"""

#: JavaScript: what the page holds and drew (counts of models, canvases that are not blank).
_INSPECT = """
const doc = window.Bokeh.documents[0];
const models = [...doc.all_models];
const name = (m) => m.type ?? m.constructor.__name__;
const figures = models.filter((m) => name(m) === 'Figure');
const glyphs = models.filter((m) => name(m) === 'GlyphRenderer');
const walk = (root, out) => {
  for (const el of root.querySelectorAll('*')) { if (el.tagName === 'CANVAS') out.push(el);
                                                 if (el.shadowRoot) walk(el.shadowRoot, out); }
  return out; };
const canvases = walk(document, []);
let drawn = 0;
for (const c of canvases) {
  if (c.width === 0 || c.height === 0) continue;
  const ctx = c.getContext('2d');
  if (!ctx) continue;
  const px = ctx.getImageData(0, 0, c.width, c.height).data;
  let colours = new Set();
  for (let i = 0; i < px.length && colours.size < 3; i += 4 * 97)  // a sparse sample of the pixels
    colours.add(px[i] << 16 | px[i + 1] << 8 | px[i + 2] | px[i + 3] << 24);
  if (colours.size >= 3) drawn += 1;
}
const empty = glyphs.filter((g) => { const d = g.data_source?.data; if (!d) return false;
  const cols = d instanceof Map ? [...d.values()] : Object.values(d);
  return cols.length > 0 && cols[0].length === 0; });
const hasData = (r) => { const d = r.data_source?.data; if (!d) return false;
  const cols = d instanceof Map ? [...d.values()] : Object.values(d); return cols.length > 0 && cols[0].length > 0; };
const dataGlyph = (r) => name(r) === 'GlyphRenderer' && ['Line', 'Scatter', 'Quad'].includes(name(r.glyph))
                         && hasData(r);
const bare = figures.filter((f) => !f.renderers.some(dataGlyph));
const hovers = figures.filter((f) => f.toolbar.tools.some((t) => name(t) === 'HoverTool')).length;
return {figures: figures.length, glyph_renderers: glyphs.length, figures_without_data: bare.length,
        figures_with_hover: hovers, canvases: canvases.length, drawn_canvases: drawn,
        empty_glyph_renderers: empty.length, x_ranges: [...new Set(figures.map((f) => f.x_range.id))].length,
        tables: models.filter((m) => name(m) === 'DataTable').length};
"""


def open_chromium():
    """A headless Chromium WebDriver (selenium); AssertionError naming what is missing."""
    assert shutil.which("chromium") or Path(CHROMIUM).exists(), \
        "chromium not found: apt-get install chromium chromium-driver (.ci/run installs them)"
    assert Path(CHROMEDRIVER).exists(), "chromedriver not found: apt-get install chromium-driver"
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                     f"--window-size={WINDOW[0]},{WINDOW[1]}", "--hide-scrollbars", "--force-device-scale-factor=1"):
        options.add_argument(argument)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)


def console_errors(driver) -> list:
    """The browser console's SEVERE entries since the last call (reading clears them)."""
    return [entry for entry in driver.get_log("browser") if entry.get("level") == "SEVERE"]


def load(driver, path: Path, timeout: float = 60.0) -> float:
    """Open ``path`` and wait until every plot has drawn; returns the page's own clock then (``performance.now()``,
    s since the navigation started: the load time a user sees, without WebDriver's overhead after it)."""
    driver.get("about:blank")
    console_errors(driver)
    start = time.perf_counter()
    driver.get(Path(path).resolve().as_uri())
    while True:
        seconds = driver.execute_script(_READY)
        if seconds is not False:
            return float(seconds)
        if time.perf_counter() - start > timeout:
            raise AssertionError(f"{path}: Bokeh did not render within {timeout:g} s")
        time.sleep(0.01)


def inspect(driver) -> Dict[str, Any]:
    """Counts of the loaded page: figures, glyph renderers, canvases, non-blank canvases, empty renderers,
    figures without a line, dots or bars holding data, distinct x ranges, data tables."""
    return driver.execute_script(_INSPECT)


def x_ranges(driver) -> list:
    """[start, end] of every figure's x range, in document order."""
    return driver.execute_script("""
        const name = (m) => m.type ?? m.constructor.__name__;
        return [...window.Bokeh.documents[0].all_models].filter((m) => name(m) === 'Figure')
                 .map((f) => [f.x_range.start, f.x_range.end]);""")


def wheel_zoom_first_plot(driver, delta: float = -300.0) -> None:
    """Scroll the mouse wheel over the middle of the first plot (its wheel tool zooms the time axis)."""
    driver.execute_script("""
        const walk = (root, out) => { for (const el of root.querySelectorAll('*')) { if (el.tagName === 'CANVAS')
            out.push(el); if (el.shadowRoot) walk(el.shadowRoot, out); } return out; };
        const canvas = walk(document, []).find((c) => c.width > 300 && c.height > 100);
        const box = canvas.getBoundingClientRect();
        const target = canvas.parentElement;  // Bokeh listens on the canvas view's events element
        const x = box.left + box.width / 2, y = box.top + box.height / 2;
        const root = canvas.getRootNode();
        const hit = (root.elementFromPoint ? root.elementFromPoint(x, y) : null) ?? target;
        hit.dispatchEvent(new WheelEvent('wheel', {deltaY: arguments[0], clientX: x, clientY: y, bubbles: true,
                                                       composed: true, cancelable: true}));
    """, delta)


def write_long_csv(path: Path, rows: int = 1_000_000, rate: float = 1000.0, baro_rate: float = 50.0,
                   seed: int = 0) -> Path:
    """A generic CSV log of ``rows`` rows from the simulator: a climb, cruise and descent at ``rate`` Hz,
    columns ``time`` (s), ``vertical_acceleration`` (m/s², noisy truth), ``baro_altitude`` (m, noisy, at
    ``baro_rate`` Hz, empty between) and ``true_altitude`` (m). Read it with
    ``--time time --accel vertical_acceleration --baro baro_altitude --reference true_altitude``."""
    from fusion_altitude import sim

    rng = np.random.default_rng(seed)
    trajectory = sim.climb_cruise_descend(duration=rows / rate, rate=rate, cruise_altitude=120.0)
    n = len(trajectory)
    accel = trajectory.vertical_acceleration + 0.05 + rng.normal(0.0, 0.3, n)
    every = int(round(rate / baro_rate))
    baro = np.full(n, np.nan)
    baro[::every] = trajectory.altitude[::every] + rng.normal(0.0, 0.5, baro[::every].size)
    with open(path, "w") as handle:
        handle.write("time,vertical_acceleration,baro_altitude,true_altitude\n")
        table = np.column_stack([trajectory.time, accel, baro, trajectory.altitude])
        lines = ["%.4f,%.4f,%s,%.3f" % (t, a, "" if b != b else "%.3f" % b, h) for t, a, b, h in table]
        handle.write("\n".join(lines) + "\n")
    return Path(path)


LONG_CSV_FLAGS = ["--time", "time", "--accel", "vertical_acceleration", "--baro", "baro_altitude",
                  "--reference", "true_altitude"]
