"""The page replays a results folder and an LCM log of the same run: stepped to given times, it
draws the robot and every person where states.csv has them. The replay comes in chunks of 2 s here
(--replay-chunk-seconds), fetched as the page needs them: seeking and playing cross chunks. With
--replay-rate 0 every sample is a frame; by default 20 per second of simulation time (the evaluator's
sample rule) and the last sample."""
import gzip
import json
import os
import shutil
import subprocess
import sys
import tempfile
import urllib.request

from cdp import GENEROUS, Browser, states_at
from pagecheck import SNAPSHOT_JS, compare
from viewproc import View


def csv_times(states_csv):
    import csv
    with open(states_csv) as f:
        return sorted({float(r["t"]) for r in csv.DictReader(f) if r["kind"] == "robot"})


def kept_times(times, hz):
    """The sample times a replay at hz keeps: results::SampleRate's rule (the first sample, then the first
    at or after each multiple of the period from it), and the last sample."""
    if hz == 0:
        return list(times)
    period = round(1e6 / hz)
    first = round(times[0] * 1e6)
    kept, next_us = [times[0]], first + period
    for t in times[1:]:
        us = round(t * 1e6)
        if us >= next_us:
            kept.append(t)
            next_us = first + ((us - first) // period + 1) * period
    if kept[-1] != times[-1]:
        kept.append(times[-1])
    return kept


def check_chunk_api(view, label):
    """A chunk is the same JSON whether sent compressed (the page accepts gzip) or not; a bad index is
    refused."""
    problems = []
    status, plain = view.request("/api/replay/chunk?i=1")
    req = urllib.request.Request(view.url + "/api/replay/chunk?i=1", headers={"Accept-Encoding": "gzip"})
    with urllib.request.urlopen(req, timeout=GENEROUS) as r:
        encoding, packed = r.headers.get("Content-Encoding"), r.read()
    if status != 200 or encoding != "gzip" or json.loads(gzip.decompress(packed)) != json.loads(plain):
        problems.append("%s: chunk 1 is %s plain, %s compressed, or they differ" % (label, status, encoding))
    for query, want in (("i=x", 400), ("i=-1", 400), ("i=1e3", 400), ("", 400), ("i=99999", 404)):
        got = view.request("/api/replay/chunk?" + query)[0]
        if got != want:
            problems.append("%s: /api/replay/chunk?%s answered %d, not %d" % (label, query, got, want))
    return problems


def check_replay(browser, view_args, states_csv, label, rate):
    view = View(view_args + ["--replay-rate", str(rate), "--replay-chunk-seconds", "2"])
    problems = []
    try:
        browser.goto(view.url + "/")
        times = kept_times(csv_times(states_csv), rate)
        n = browser.eval("window.hunavView.app.replay.frameCount")
        if n != len(times):
            problems.append("%s: %d frames in the page, %d kept times of states.csv" % (label, n, len(times)))
        chunks = browser.eval("window.hunavView.app.replay.chunks.length")
        if chunks < 5:
            problems.append("%s: %d chunks for %.1f s (chunks of 2 s)" % (label, chunks, times[-1] - times[0]))
        problems += check_chunk_api(view, label)
        # Exact sample times, and times between samples (the frame at or before them is shown).
        mid = len(times) // 2
        wanted = [times[0], times[len(times) // 3], times[mid] + 0.6 * (times[mid + 1] - times[mid]), times[-1],
                  times[-1] + 5]
        checked = 0
        for t in wanted:
            browser.eval("window.hunavView.seekLoaded(%r)" % t, await_promise=True)
            snap = browser.eval(SNAPSHOT_JS)
            shown = max(x for x in times if x <= min(t, times[-1]) + 1e-9)
            if abs(snap["t"] - shown) > 1e-9:
                problems.append("%s: seek(%r) shows t=%r, the kept sample is t=%r" % (label, t, snap["t"], shown))
            p, c = compare(snap, states_at(states_csv, shown))
            problems += ["%s: %s" % (label, x) for x in p]
            checked += c
            print("%s: seek(%.3f) -> t=%.3f, robot at (%.3f, %.3f), %d people" %
                  (label, t, snap["t"], snap["robot"]["x"], snap["robot"]["y"], len(snap["people"])))
        if checked < 5:
            problems.append("%s: only %d drawn centres could be checked by colour" % (label, checked))
        # Play at 10x from the start: time moves on, and the frames drawn follow it into the chunks
        # after the first (past 5 s of the run: 0.5 s of wall-clock time on a quiet machine).
        browser.eval("window.hunavView.seekLoaded(%r)" % times[0], await_promise=True)
        fetched = browser.eval("window.hunavView.app.replay.fetched")
        browser.eval("document.getElementById('speed').value = '10';"
                     " document.getElementById('speed').dispatchEvent(new Event('change'));"
                     " document.getElementById('play').click()")
        try:
            browser.wait_for("window.hunavView.app.frame.t > %r" % (times[0] + 5))
        except AssertionError:
            problems.append("%s: played at 10x, the frame shown stays at t=%r (time %r)"
                            % (label, browser.eval("window.hunavView.app.frame.t"),
                               browser.eval("window.hunavView.app.replayTime")))
        browser.eval("document.getElementById('play').click()")
        if browser.eval("window.hunavView.app.replay.fetched") <= fetched:
            problems.append("%s: playing across chunks fetched none" % label)
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
        log = ["--log", os.path.join(out, "run.lcmlog"), "--no-editor", "--scenario",
               os.path.join(repo, "scenarios", "cafe.yaml")]
        for rate in (0, 20):
            problems += check_replay(browser, ["--results", out, "--no-editor"], states,
                                     "results, rate %d" % rate, rate)
            problems += check_replay(browser, log, states, "log, rate %d" % rate, rate)
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
