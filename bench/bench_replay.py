#!/usr/bin/python3
"""How fast a replay opens in hunav_view's page (docs/performance.md, "Replays that open at once"):
for each source (a results folder, an LCM log), starts hunav_view on it, opens the page in headless
Chromium and measures
  - ready: from the navigation to the page showing the replay's first frame (window.hunavView.ready),
  - bytes: what the page transferred over the network until then (Resource Timing's transferSize:
    compressed bodies plus headers), and the largest single answer,
  - seek: the time to show the last second of the run after a jump of the slider there,
and the median over --repeat page loads.

  bench/bench_replay.py --results DIR [--log FILE] [--report] [--repeat N] [--bin DIR] [-- hunav_view options]

With --report it also writes hunav_report's page of the results folder and measures it the same way
(a file: its size, and the time until the page's scripts have run, document.readyState "complete").

Without --results and --log it makes them: hunav_run on scenarios/cafe.yaml (seed 3, dwb: a run of
about 100 s) with --record. Needs Debian's chromium and python3-websocket."""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import shutil
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "tests", "view"))
from cdp import Browser  # noqa: E402
from viewproc import View  # noqa: E402

BYTES_JS = """(() => {
  const nav = performance.getEntriesByType('navigation')[0];
  const res = performance.getEntriesByType('resource');
  const sizes = res.map((r) => r.transferSize);
  return {total: (nav ? nav.transferSize : 0) + sizes.reduce((a, b) => a + b, 0),
          largest: Math.max(0, ...sizes), requests: res.length + 1};
})()"""


def measure(browser, url, end_time_js):
    browser.call("Page.navigate", url="about:blank")
    t0 = time.monotonic()
    browser.call("Page.navigate", url=url + "/")
    browser.wait_for("window.hunavView && window.hunavView.ready && window.hunavView.app.frame")
    ready = time.monotonic() - t0
    sizes = browser.eval(BYTES_JS)
    t_end = browser.eval(end_time_js)
    t1 = time.monotonic()
    browser.eval("window.hunavView.seek(%r)" % (t_end - 0.5))
    browser.wait_for("window.hunavView.app.frame && window.hunavView.app.frame.t >= %r" % (t_end - 1.0))
    seek = time.monotonic() - t1
    return ready, sizes, seek


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--results")
    ap.add_argument("--log")
    ap.add_argument("--report", action="store_true")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--bin", default=os.environ.get("HUNAV_BIN_DIR", os.path.join(REPO, "build", "bin")))
    ap.add_argument("view_args", nargs="*", help="more hunav_view options (after --)")
    args = ap.parse_args()
    os.environ["BIN"] = args.bin
    work = tempfile.mkdtemp(prefix="bench_replay.")
    try:
        sources = []
        if not args.results and not args.log:
            out = os.path.join(work, "cafe")
            cafe = os.path.join(REPO, "scenarios", "cafe.yaml")
            subprocess.run([os.path.join(args.bin, "hunav_run"), "--scenario", cafe,
                            "--planner", "dwb", "--seed", "3", "--duration", "200", "--out", out, "--quiet",
                            "--record", os.path.join(out, "run.lcmlog")], check=True, stdout=subprocess.DEVNULL)
            args.results, args.log = out, os.path.join(out, "run.lcmlog")
        if args.results:
            sources.append(("results folder", ["--results", args.results]))
        if args.log:
            sources.append(("LCM log", ["--log", args.log]))
        # The run's last time, whatever the payload's shape (the slider's range is the run's).
        end_js = "Number(document.getElementById('slider').max)"
        browser = Browser()
        try:
            for label, src in sources:
                view = View(src + ["--no-editor"] + args.view_args)
                try:
                    runs = [measure(browser, view.url, end_js) for _ in range(args.repeat)]
                finally:
                    view.stop()
                ready = statistics.median(r[0] for r in runs)
                seek = statistics.median(r[2] for r in runs)
                total = statistics.median(r[1]["total"] for r in runs)
                largest = max(r[1]["largest"] for r in runs)
                print("%-15s ready %.3f s (min %.3f, max %.3f), %.2f MB transferred (largest answer %.2f MB, "
                      "%d requests), seek to the end %.3f s; median of %d"
                      % (label, ready, min(r[0] for r in runs), max(r[0] for r in runs), total / 1e6,
                         largest / 1e6, runs[0][1]["requests"], seek, args.repeat), flush=True)
            if args.report and args.results:
                page = os.path.join(work, "report.html")
                subprocess.run([os.path.join(args.bin, "hunav_report"), args.results, "-o", page], check=True,
                               stdout=subprocess.DEVNULL)
                times = []
                for _ in range(args.repeat):
                    browser.call("Page.navigate", url="about:blank")
                    t0 = time.monotonic()
                    browser.call("Page.navigate", url="file://" + page)
                    browser.wait_for("document.readyState === 'complete' && document.querySelector('canvas')")
                    times.append(time.monotonic() - t0)
                print("%-15s ready %.3f s (min %.3f, max %.3f), %.2f MB (one file); median of %d"
                      % ("hunav_report", statistics.median(times), min(times), max(times),
                         os.path.getsize(page) / 1e6, args.repeat), flush=True)
        finally:
            browser.close()
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
