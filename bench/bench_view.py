#!/usr/bin/python3
"""hunav_view's costs (docs/performance.md, "View"):
  1. lockstep speed without a viewer, with hunav_view attached (run_experiment.sh --view), and with
     hunav_view plus a headless Chromium page drawing the run; interleaved, median real-time factor
     (sim_time / wall_time of run.json) over --repeat runs of each;
  2. frames per second the page draws 1000 people at (scenarios/crowd_1000.yaml, replayed at 1x in
     headless Chromium: every frame redraws the map, 1000 people with trails, the robot).
  bench/bench_view.py [--repeat N] [--scenario FILE] [--skip-lockstep] [--skip-fps]
Needs root (or unprivileged user namespaces) for the lockstep runs, Debian's chromium and
python3-websocket. Run it on a quiet machine: the three series share 2 cores with the browser."""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "tests", "view"))
from cdp import Browser  # noqa: E402


def lockstep_run(binary_dir, scenario, out, view, browser_holder):
    env = dict(os.environ, HUNAV_BIN_DIR=binary_dir)
    cmd = [os.path.join(REPO, "launch_scripts", "run_experiment.sh"), "--scenario", scenario, "--mode", "lockstep",
           "--out", out] + (["--view"] if view else [])
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
    browser = None
    for line in proc.stdout:
        m = re.search(r"watch this run live: (http://\S+)", line)
        if m and browser_holder is not None:
            browser = browser_holder
            browser.call("Page.navigate", url=m.group(1))
    proc.wait()
    if proc.returncode != 0:
        raise RuntimeError("run failed: %s" % " ".join(cmd))
    run = json.load(open(os.path.join(out, "run.json")))
    frames = browser.eval("window.hunavView ? window.hunavView.app.received : 0") if browser else None
    return run["sim_time"] / run["wall_time"], frames


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--scenario", default=os.path.join(REPO, "scenarios", "passing.yaml"))
    ap.add_argument("--bin", default=os.environ.get("HUNAV_BIN_DIR", os.path.join(REPO, "build", "bin")))
    ap.add_argument("--skip-lockstep", action="store_true")
    ap.add_argument("--skip-fps", action="store_true")
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="bench_view.")
    try:
        if not args.skip_lockstep:
            series = {"without viewer": [], "hunav_view attached": [], "hunav_view + Chromium page": []}
            browser = Browser()
            frames = []
            for i in range(args.repeat):
                for name in series:
                    out = os.path.join(work, "run_%d_%d" % (i, len(series[name])))
                    rtf, f = lockstep_run(args.bin, args.scenario, out, name != "without viewer",
                                          browser if "Chromium" in name else None)
                    series[name].append(rtf)
                    if f is not None:
                        frames.append(f)
                    shutil.rmtree(out, ignore_errors=True)
                latest = ", ".join("%s %.1fx" % (k, v[-1]) for k, v in series.items())
                print("round %d: %s" % (i + 1, latest), flush=True)
            browser.close()
            base = statistics.median(series["without viewer"])
            print("\nlockstep, %s, median of %d interleaved runs:" % (os.path.basename(args.scenario), args.repeat))
            for name, values in series.items():
                med = statistics.median(values)
                print("  %-28s %7.1fx real time (%+.1f%%; min %.1f, max %.1f)"
                      % (name, med, 100 * (med / base - 1), min(values), max(values)))
            print("  frames the page received per run: %s" % frames)
        if not args.skip_fps:
            out = os.path.join(work, "crowd")
            subprocess.run([os.path.join(args.bin, "hunav_run"),
                            "--scenario", os.path.join(REPO, "scenarios", "crowd_1000.yaml"),
                            "--out", out, "--duration", "10"], check=True, stdout=subprocess.DEVNULL)
            view = subprocess.Popen([os.path.join(args.bin, "hunav_view"),
                                     "--results", out, "--port", "0", "--no-editor"],
                                    stdout=subprocess.PIPE, text=True)
            url = None
            for line in view.stdout:
                m = re.match(r"hunav_view: open (http://\S+) ", line)
                if m:
                    url = m.group(1)
                    break
            browser = Browser(1280, 800, timeout=60)
            browser.call("Page.navigate", url=url)
            browser.wait_for("window.hunavView && window.hunavView.ready === true", 120)
            # (a) the page's own cost of a frame: state, trails and a full redraw, 30 frames per
            #     simulated second, timed inside the page (what the page can sustain);
            #     the chunks of those 4 s fetched first (the replay comes in chunks);
            cost = browser.eval("""(async () => { const v = window.hunavView; await v.preload(0, 4.0); v.seek(0);
              const t0 = performance.now(); let n = 0;
              for (let t = 0; t <= 4.0; t += 1 / 30, n++) v.seek(t);
              const ms = (performance.now() - t0) / n; return [n, ms, v.drawn.people.length]; })()""",
                                await_promise=True)
            # (b) frames shown per second while playing at 1x (requestAnimationFrame, compositing included).
            browser.eval("window.hunavView.seek(0); document.getElementById('play').click()")
            browser.pump(2.5)
            shown = browser.eval("window.hunavView.fps()")
            browser.close()
            view.terminate()
            view.wait()
            print("\nheadless Chromium, %d people: %.1f ms per frame (state, trails, redraw; %d frames) = %.0f frames "
                  "per second the page sustains; %.1f frames per second shown while playing at 1x" %
                  (cost[2], cost[1], cost[0], 1000 / cost[1], shown))
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
