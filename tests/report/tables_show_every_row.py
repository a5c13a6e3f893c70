#!/usr/bin/env python3
"""The report pages show every row of every table, on screen and in print.

A real batch (launch_scripts/run_batch.sh: passing x dwb, sfw x seeds 1-3, 5 s each, in-process) and
its pages (hunav_report) are opened in headless Chromium (tests/view/cdp.py). No element around a
table may cut it: none may be shorter than what it holds while clipping or scrolling its overflow
(the tables used to scroll inside 620 px boxes, so a full-page screenshot or a print lost rows). In
print media nothing may cut a table sideways either. A full-page screenshot must cover the whole
page; HUNAV_REPORT_SCREENSHOT=FILE keeps it for a look.
Needs REPO and BIN (set by ctest), chromium and python3-websocket."""
import base64
import os
import shutil
import struct
import subprocess
import sys
import tempfile

REPO = os.environ["REPO"]
BIN = os.environ["BIN"]
sys.path.insert(0, os.path.join(REPO, "tests", "view"))
from cdp import Browser  # noqa: E402

# For every table: its rows, its height, and the elements around it that cut it (vertically; also
# sideways when `sideways`), with their sizes.
CLIPPED_JS = """((sideways) => {
  const out = [];
  document.querySelectorAll('table').forEach((t, k) => {
    const cut = [];
    for (let a = t.parentElement; a && a !== document.body && a !== document.documentElement; a = a.parentElement) {
      const cs = getComputedStyle(a);
      if (cs.overflowY !== 'visible' && a.scrollHeight > a.clientHeight + 1)
        cut.push(a.className + ': ' + a.clientHeight + ' of ' + a.scrollHeight + ' px tall');
      if (sideways && cs.overflowX !== 'visible' && a.scrollWidth > a.clientWidth + 1)
        cut.push(a.className + ': ' + a.clientWidth + ' of ' + a.scrollWidth + ' px wide');
    }
    out.push({ name: t.id || t.className || ('table ' + k), rows: t.tBodies[0] ? t.tBodies[0].rows.length : 0,
               height: t.getBoundingClientRect().height, cut: cut });
  });
  return out;
})"""


def fail(msg):
    print("FAIL: " + msg, file=sys.stderr)
    sys.exit(1)


def check_page(browser, url, label):
    browser.call("Emulation.setEmulatedMedia", media="")
    browser.call("Page.navigate", url=url)
    browser.wait_for("document.documentElement"
                     " && document.documentElement.getAttribute('data-report-status') === 'drawn'")
    errors = browser.exceptions + browser.console_errors
    if errors:
        fail("%s: JavaScript errors: %s" % (label, errors))
    tallest = 0
    for media, sideways in (("screen", False), ("print", True)):
        browser.call("Emulation.setEmulatedMedia", media=media)
        tables = browser.eval("(%s)(%s)" % (CLIPPED_JS, "true" if sideways else "false"))
        if not tables:
            fail("%s: no table on the page" % label)
        for t in tables:
            if t["rows"] <= 0:
                fail("%s (%s): table %s is empty" % (label, media, t["name"]))
            if t["cut"]:
                fail("%s (%s): table %s (%d rows, %.0f px) is cut by %s"
                     % (label, media, t["name"], t["rows"], t["height"], "; ".join(t["cut"])))
        tallest = max(tallest, max(t["height"] for t in tables))
        print("  %s, %s: %d tables, every row shown (tallest %.0f px)" % (label, media, len(tables), tallest))
    browser.call("Emulation.setEmulatedMedia", media="")
    return tallest


def full_page_png(browser, path):
    """A screenshot of the whole page; returns (width, height) of the PNG and of the page."""
    size = browser.call("Page.getLayoutMetrics")["cssContentSize"]
    w, h = int(size["width"]), int(size["height"])
    data = browser.call("Page.captureScreenshot", format="png", captureBeyondViewport=True,
                        clip={"x": 0, "y": 0, "width": w, "height": h, "scale": 1})["data"]
    png = base64.b64decode(data)
    with open(path, "wb") as f:
        f.write(png)
    pw, ph = struct.unpack(">II", png[16:24])  # IHDR
    return (pw, ph), (w, h)


def main():
    work = tempfile.mkdtemp(prefix="hunav_report_rows.")
    browser = None
    try:
        batch = os.path.join(work, "batch")
        env = dict(os.environ, HUNAV_BIN_DIR=BIN)
        r = subprocess.run([os.path.join(REPO, "launch_scripts", "run_batch.sh"), "--scenarios", "passing",
                            "--planners", "dwb,sfw", "--seeds", "1-3", "--jobs", "2", "--duration", "5",
                            "--out", batch],
                           env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
        if r.returncode != 0:
            fail("run_batch.sh failed:\n" + r.stdout)
        r = subprocess.run([os.path.join(BIN, "hunav_report"), batch], stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True, timeout=300)
        if r.returncode != 0:
            fail("hunav_report failed:\n" + r.stdout)
        browser = Browser(width=1280, height=800)
        tallest = check_page(browser, "file://" + os.path.join(batch, "report.html"), "batch page")
        # The check means something only when a table is taller than the old 620 px box: the metrics x
        # planners table has a row per metric (34).
        if tallest <= 620:
            fail("no table taller than 620 px (tallest %.0f): the check would not see a fixed-height box" % tallest)
        shot = os.environ.get("HUNAV_REPORT_SCREENSHOT") or os.path.join(work, "batch.png")
        (pw, ph), (w, h) = full_page_png(browser, shot)
        if ph < h or ph <= 800:
            fail("full-page screenshot %dx%d px, page %dx%d px" % (pw, ph, w, h))
        print("  full-page screenshot: %dx%d px (%s)" % (pw, ph, shot))
        check_page(browser, "file://" + os.path.join(batch, "runs", "passing__dwb__seed1", "report.html"), "run page")
        print("OK")
    finally:
        if browser is not None:
            browser.close()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
