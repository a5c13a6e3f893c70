"""run_experiment.sh --view against a live run in its private network namespace (this test runs in
a namespace of its own, standing for the host): the page reached from outside the run's namespace
draws the robot and every person where the world published them (states.csv of the same run, every
tick), the metrics panel updates, the real-time factor shows, and there is no JavaScript error. The
screenshot goes to $HUNAV_VIEW_SCREENSHOT when set (docs/images/hunav_view.png)."""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time

from cdp import GENEROUS, Browser, states_at
from pagecheck import SNAPSHOT_JS, compare


def main():
    repo, bindir = os.environ["REPO"], os.environ["BIN"]
    work = tempfile.mkdtemp(prefix="hunav_view_live.")
    out = os.path.join(work, "live")
    env = dict(os.environ, HUNAV_BIN_DIR=bindir)
    # The browser first (its start is the slow part on a loaded machine): the realtime run's 12 s are
    # left for the page to follow.
    browser = Browser()
    run = subprocess.Popen([os.path.join(repo, "launch_scripts", "run_experiment.sh"), "--scenario",
                            os.path.join(repo, "scenarios", "cafe.yaml"), "--mode", "realtime", "--duration", "12",
                            "--view", "--out", out],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
    lines, url_box = [], []

    def reader():
        for line in run.stdout:
            lines.append(line)
            m = re.search(r"watch this run live: (http://\S+)", line)
            if m:
                url_box.append(m.group(1))
    reading = threading.Thread(target=reader, daemon=True)
    reading.start()
    problems, snapshots, metric_times = [], [], set()
    try:
        deadline = time.time() + GENEROUS
        while not url_box and time.time() < deadline and run.poll() is None:
            time.sleep(0.1)
        if not url_box:
            raise AssertionError("run_experiment.sh printed no URL:\n" + "".join(lines))
        url = url_box[0]
        print("view at", url)
        browser.goto(url)
        browser.wait_for("window.hunavView.drawn.people.length === 6 && window.hunavView.drawn.t > 0.5")
        # Eight snapshots 1 s of simulated time apart (about 1 s of wall-clock time in realtime), while the
        # run lasts: the page must follow it and the metrics panel update.
        sampling_end = time.time() + GENEROUS
        for k in range(8):
            snapshots.append(browser.eval(SNAPSHOT_JS))
            metric_times.add(browser.eval("document.getElementById('metrics-time').textContent"))
            if k == 4:
                browser.screenshot(os.path.join(work, "hunav_view.png"))
            next_t = snapshots[-1]["t"] + 1.0
            while (run.poll() is None and time.time() < sampling_end
                   and not browser.eval("window.hunavView.drawn.t >= %r" % next_t)):
                browser.pump(0.1)
            if run.poll() is not None or time.time() >= sampling_end:
                break
        rtf = browser.eval("window.hunavView.app.frame.rtf")
        path_points = browser.eval("window.hunavView.app.frame.path"
                                   " ? window.hunavView.app.frame.path.points.length : 0")
        laser_beams = browser.eval("window.hunavView.app.frame.laser"
                                   " ? window.hunavView.app.frame.laser.ranges.length : 0")
        metric_rows = browser.eval("document.querySelectorAll('#metrics tr').length")
        scene = browser.eval("window.hunavView.app.scene && window.hunavView.app.scene.shapes.length")
        errors = browser.js_errors()
        run.wait(GENEROUS)
        reading.join(GENEROUS)  # the script's last lines
        print("".join(lines[-6:]))
        if run.returncode != 0:
            problems.append("run_experiment.sh exited %s" % run.returncode)
        states = os.path.join(out, "states.csv")
        checked = 0
        for snap in snapshots:
            p, c = compare(snap, states_at(states, snap["t"], tol=1e-6))
            problems += p
            checked += c
            print("t=%.2f tick %s: robot (%.3f, %.3f), %d people"
                  % (snap["t"], snap["tick"], snap["robot"]["x"], snap["robot"]["y"], len(snap["people"])))
        if len({s["tick"] for s in snapshots}) < 5:
            problems.append("the page did not follow the run: ticks %s" % [s["tick"] for s in snapshots])
        if checked < 10:
            problems.append("only %d drawn centres could be checked by colour" % checked)
        if len([m for m in metric_times if m]) < 3:
            problems.append("the metrics panel did not update: %s" % sorted(metric_times))
        if not metric_rows or metric_rows < 10:
            problems.append("the metrics panel shows %s rows" % metric_rows)
        if rtf is None or not 0.5 < rtf < 1.5:
            problems.append("a realtime run's real-time factor shows as %r" % rtf)
        if not path_points or path_points < 2:
            problems.append("no planned path (ROBOT_PATH) reached the page")
        if laser_beams != 180:
            problems.append("the laser scan reached the page with %r beams, the scenario has 180" % laser_beams)
        if not scene or scene < 10:
            problems.append("the map was not drawn (%r shapes)" % scene)
        if errors:
            problems.append("JavaScript errors: %s" % errors)
        log = open(os.path.join(out, "logs", "view.log")).read()
        if "frames sent" not in log:
            problems.append("hunav_view did not stop with the run: %s" % log)
        target = os.environ.get("HUNAV_VIEW_SCREENSHOT")
        if target:
            shutil.copy(os.path.join(work, "hunav_view.png"), target)
    finally:
        browser.close()
        if run.poll() is None:
            run.terminate()
            run.wait(30)
        shutil.rmtree(work, ignore_errors=True)
    for p in problems:
        print("FAIL:", p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
