"""The page replays a results folder and an LCM log of the same run: stepped to given times, it
draws the robot and every person where states.csv has them."""
import os
import shutil
import subprocess
import sys
import tempfile

from cdp import Browser, states_at
from pagecheck import SNAPSHOT_JS, compare
from viewproc import View


def csv_times(states_csv):
    import csv
    with open(states_csv) as f:
        return sorted({float(r["t"]) for r in csv.DictReader(f) if r["kind"] == "robot"})


def check_replay(browser, view_args, states_csv, label):
    view = View(view_args)
    problems = []
    try:
        browser.goto(view.url + "/")
        times = csv_times(states_csv)
        n = browser.eval("window.hunavView.app.replay.frames.length")
        if n != len(times):
            problems.append("%s: %d frames in the page, %d times in states.csv" % (label, n, len(times)))
        # Exact sample times, and times between samples (the frame at or before them is shown).
        wanted = [times[0], times[len(times) // 3], times[len(times) // 2] + 0.004, times[-1], times[-1] + 5]
        checked = 0
        for t in wanted:
            browser.eval("window.hunavView.seek(%r)" % t)
            snap = browser.eval(SNAPSHOT_JS)
            shown = max(x for x in times if x <= min(t, times[-1]) + 1e-9)
            if abs(snap["t"] - shown) > 1e-9:
                problems.append("%s: seek(%r) shows t=%r, states.csv's sample is t=%r" % (label, t, snap["t"], shown))
            p, c = compare(snap, states_at(states_csv, shown))
            problems += ["%s: %s" % (label, x) for x in p]
            checked += c
            print("%s: seek(%.3f) -> t=%.3f, robot at (%.3f, %.3f), %d people" %
                  (label, t, snap["t"], snap["robot"]["x"], snap["robot"]["y"], len(snap["people"])))
        if checked < 5:
            problems.append("%s: only %d drawn centres could be checked by colour" % (label, checked))
        # Play at 10x: time moves on (past 2 s of the run: 0.2 s of wall-clock time on a quiet machine).
        browser.eval("window.hunavView.seek(%r)" % times[0])
        browser.eval("document.getElementById('speed').value = '10';"
                     " document.getElementById('speed').dispatchEvent(new Event('change'));"
                     " document.getElementById('play').click()")
        try:
            browser.wait_for("window.hunavView.app.replayTime > %r" % (times[0] + 2))
        except AssertionError:
            problems.append("%s: played at 10x, the time stays at %r"
                            % (label, browser.eval("window.hunavView.app.replayTime")))
        browser.eval("document.getElementById('play').click()")
    finally:
        view.stop()
    return problems


def main():
    repo, bindir = os.environ["REPO"], os.environ["BIN"]
    work = tempfile.mkdtemp(prefix="hunav_view_replay.")
    problems = []
    browser = None
    try:
        out = os.path.join(work, "run")
        os.makedirs(out)
        # cafe: six people of five behaviors, a group, a map_server map; every tick recorded.
        subprocess.run([os.path.join(bindir, "hunav_run"), "--scenario", os.path.join(repo, "scenarios", "cafe.yaml"),
                        "--out", out, "--duration", "12", "--record", os.path.join(out, "run.lcmlog")],
                       check=True, stdout=subprocess.DEVNULL)
        states = os.path.join(out, "states.csv")
        browser = Browser()
        problems += check_replay(browser, ["--results", out, "--no-editor"], states, "results")
        problems += check_replay(browser, ["--log", os.path.join(out, "run.lcmlog"), "--no-editor",
                                           "--scenario", os.path.join(repo, "scenarios", "cafe.yaml")], states, "log")
        errors = browser.js_errors()
        if errors:
            problems.append("JavaScript errors: %s" % errors)
    finally:
        if browser:
            browser.close()
        shutil.rmtree(work, ignore_errors=True)
    for p in problems:
        print("FAIL:", p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
