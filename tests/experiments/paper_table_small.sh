#!/usr/bin/env bash
# "Paper vs ours" on a small real batch: run_batch.sh runs passing, crossing and combined with dwb and
# scl, seeds 1-2 (combined cut to 20 s of simulation), in-process; then summary.md, paper_comparison.csv
# and paper_orderings.csv must hold the paper's means (experiments/data/hunav_paper_means.yaml) beside
# the means of these runs (recomputed here from the runs' own metrics.csv) with verdicts that follow
# from them; and the batch report must carry the table (drawn in headless Chromium when installed).
# Expects REPO and BIN (ctest sets them).
set -euo pipefail
export HUNAV_BIN_DIR="$BIN"
WORK=$(mktemp -d /tmp/hunav_paper_table.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
out="$WORK/batch"

"$REPO/launch_scripts/run_batch.sh" --scenarios passing,crossing --planners dwb,scl --seeds 1-2 --jobs 2 \
  --out "$out" >"$WORK/batch.log" 2>&1 || { cat "$WORK/batch.log"; fail "run_batch.sh (passing, crossing) failed"; }
"$REPO/launch_scripts/run_batch.sh" --scenarios combined --planners dwb,scl --seeds 1-2 --jobs 2 --duration 20 \
  --out "$out" >"$WORK/batch2.log" 2>&1 || { cat "$WORK/batch2.log"; fail "run_batch.sh (combined) failed"; }
for f in paper_comparison.csv paper_orderings.csv summary.md; do [ -s "$out/$f" ] || fail "missing $out/$f"; done

/usr/bin/python3 - "$out" <<'PY'
import csv, glob, os, statistics, sys
out = sys.argv[1]
# Our means, from the run folders (whole run: metrics.csv; per behavior: metrics_beh_<code>.csv).
codes = {"all": None, "regular": 1, "curious": 5, "threatening": 6}
def ours(scenario, planner, behavior, metric):
    vals = []
    for d in sorted(glob.glob(f"{out}/runs/{scenario}__{planner}__seed*")):
        f = "metrics.csv" if codes[behavior] is None else f"metrics_beh_{codes[behavior]}.csv"
        row = list(csv.DictReader(open(os.path.join(d, f))))[-1]
        v = row[metric]
        vals.append(1.0 if v == "true" else 0.0 if v == "false" else float(v))
    return statistics.mean(vals)
rows = list(csv.DictReader(open(out + "/paper_comparison.csv")))
assert rows, "no rows"
assert {r["scenario"] for r in rows} == {"passing", "crossing", "combined"}, {r["scenario"] for r in rows}
assert {r["planner"] for r in rows} == {"dwb", "scl"}  # sfw did not run: no column
# 25 metrics for passing and crossing, 7 per behavior for combined; 2 planners each.
assert len(rows) == 2 * (25 + 25 + 21), len(rows)
def row(sc, beh, m, p):
    found = [r for r in rows if (r["scenario"], r["behavior"], r["metric"], r["planner"]) == (sc, beh, m, p)]
    assert len(found) == 1, (sc, beh, m, p, found)
    return found[0]
# The paper's values as printed in its tables, and ours as the runs gave them.
checks = [("crossing", "all", "intimate_space_intrusions", "dwb", 13.7), ("crossing", "all", "time_to_reach_goal", "scl", 14.6),
          ("passing", "all", "avg_distance_to_closest_person", "scl", 7.95), ("passing", "all", "completed", "dwb", 1.0),
          ("combined", "threatening", "social_work", "dwb", 6.46), ("combined", "curious", "personal_space_intrusions", "scl", 11.9)]
for sc, beh, m, p, paper in checks:
    r = row(sc, beh, m, p)
    assert abs(float(r["paper_mean"]) - paper) < 1e-9, (r, paper)
    assert r["n"] == "2", r
    assert abs(float(r["mean"]) - ours(sc, p, beh, m)) < 1e-9 * max(1.0, abs(float(r["mean"]))), (r, ours(sc, p, beh, m))
    lo, hi = float(r["ci95_low"]), float(r["ci95_high"])
    assert r["paper_in_ci"] == ("true" if lo <= paper <= hi else "false"), r
assert row("crossing", "all", "avg_distance_to_closest_person", "dwb")["paper_metric"] == "avg_dist_to_closest_person"
# Every verdict follows from the two pairs of means.
orderings = list(csv.DictReader(open(out + "/paper_orderings.csv")))
assert len(orderings) == 25 + 25 + 21, len(orderings)  # one pair (dwb, scl) per row
rel = lambda a, b: "<" if a < b else ">" if a > b else "="
for o in orderings:
    assert (o["planner_a"], o["planner_b"]) == ("dwb", "scl"), o
    pa = float(row(o["scenario"], o["behavior"], o["metric"], "dwb")["paper_mean"])
    pb = float(row(o["scenario"], o["behavior"], o["metric"], "scl")["paper_mean"])
    ma = ours(o["scenario"], "dwb", o["behavior"], o["metric"])
    mb = ours(o["scenario"], "scl", o["behavior"], o["metric"])
    assert o["paper"] == rel(pa, pb) and o["ours"] == rel(ma, mb), (o, pa, pb, ma, mb)
    want = ("agree" if o["ours"] == "=" else "paper_tie") if o["paper"] == "=" else ("agree" if o["ours"] == o["paper"] else "disagree")
    assert o["verdict"] == want, (o, want)
    assert o["significant"] in (("true", "false") if o["behavior"] == "all" else ("",)), o
md = open(out + "/summary.md").read()
for sc in ("passing", "crossing", "combined"):
    assert f"### `{sc}` vs the paper" in md, sc
    n_agree = sum(1 for o in orderings if o["scenario"] == sc and o["verdict"] == "agree")
    n_dis = sum(1 for o in orderings if o["scenario"] == sc and o["verdict"] == "disagree")
    assert f"Orderings: **{n_agree} agree, {n_dis} disagree**" in md, (sc, n_agree, n_dis)
assert "| metric (paper's name) | unit | dwb paper | dwb ours | scl paper | scl ours | dwb vs scl |" in md
assert "| avg_distance_to_closest_person (avg_dist_to_closest_person) | m | 1.45 |" in md
assert "People of behavior `threatening` only (paper: tab:combined, column Threatening)" in md
assert "- † `social_work`:" in md
PY

"$BIN/hunav_report" --no-run-pages "$out" >"$WORK/report.txt" 2>&1 || { cat "$WORK/report.txt"; fail "hunav_report failed"; }
grep -q '"paperOrderings":\[\["passing","all","time_to_reach_goal","dwb","scl","\\u003c",' "$out/report.html" ||
  fail "the batch page does not carry the paper's orderings"
grep -q '\["crossing","all","intimate_space_intrusions","intimate_space_intrusions","dwb",13.7,2,' "$out/report.html" ||
  fail "the batch page does not carry crossing's paper means"
if command -v chromium >/dev/null 2>&1; then
  timeout 120 chromium --headless --no-sandbox --disable-gpu --user-data-dir="$WORK/profile" --virtual-time-budget=5000 \
    --dump-dom "file://$out/report.html" >"$WORK/dom.html" 2>"$WORK/chromium.err" || fail "chromium could not render the page"
  grep -q 'data-report-status="drawn" data-js-errors="0"' "$WORK/dom.html" || fail "the batch page did not draw without errors"
  # passing and crossing: 25 rows of all people; combined: 7 rows per behavior.
  [ "$(grep -o '<table class="paper" data-behavior="all" data-rows="25"' "$WORK/dom.html" | wc -l)" -eq 2 ] ||
    fail "the batch page lacks the paper tables of passing and crossing"
  grep -q '<table class="paper" data-behavior="threatening" data-rows="7"' "$WORK/dom.html" ||
    fail "the batch page lacks combined's threatening table"
else
  echo "chromium not installed: the page's drawing is not checked (report_renders_in_chromium needs it too)"
fi
echo "PASS paper_table_small"
