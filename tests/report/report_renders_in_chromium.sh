#!/usr/bin/env bash
# Report pages rendered in headless Chromium: a batch of real runs (the passing scenario, two planners,
# two seeds) through hunav_run and hunav_report, then the DOM after the scripts ran must show every
# figure drawn (data-points > 0), no JavaScript error and a stuck run's badge; a page broken on
# purpose must be reported.
# Needs REPO and BIN (set by ctest) and the Debian package chromium.
set -euo pipefail
: "${REPO:?set REPO to the repository}" "${BIN:?set BIN to the bin folder of a build}"
WORK=$(mktemp -d /tmp/hunav_report_chromium.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

command -v chromium >/dev/null 2>&1 ||
  fail "chromium is not installed (Debian package chromium: bash launch_scripts/setup.sh installs it)"

# render PAGE OUT: the DOM of PAGE after its scripts ran, into OUT (bounded: 120 s).
render() {
  local profile
  profile=$(mktemp -d "$WORK/profile.XXXXXX")
  # TMPDIR: Chromium's own org.chromium.Chromium.* folders go with $WORK, not into /tmp.
  if ! TMPDIR="$WORK" timeout 120 chromium --headless --no-sandbox --disable-gpu --user-data-dir="$profile" \
      --virtual-time-budget=5000 --dump-dom "file://$1" >"$2" 2>"$WORK/chromium.err"; then
    tail -n 20 "$WORK/chromium.err" >&2
    fail "chromium could not render $1"
  fi
  [ -s "$2" ] || fail "chromium gave an empty DOM for $1"
}

# check DOM PLOT...: the page says it drew without error, and each figure PLOT (data-plot, or "map"
# for the canvas) has points. Prints what it found.
check() {
  python3 - "$@" <<'PY'
import re, sys
dom = open(sys.argv[1], encoding="utf-8").read()
root = re.search(r"<html[^>]*>", dom).group(0)
status = re.search(r'data-report-status="([^"]*)"', root).group(1)
errors = int(re.search(r'data-js-errors="(\d+)"', root).group(1))
box = re.search(r'id="js-errors"[^>]*>([^<]*)', dom)
if status != "drawn" or errors != 0:
    sys.exit(f"page not drawn: status {status}, {errors} JavaScript error(s): {box.group(1) if box else ''}")
for plot in sys.argv[2:]:
    if plot == "map":
        tag = re.search(r"<canvas[^>]*class=\"map\"[^>]*>", dom)
    else:
        tag = re.search(r"<svg[^>]*data-plot=\"" + re.escape(plot) + r"\"[^>]*>", dom)
    if not tag:
        sys.exit(f"figure {plot} is missing")
    points = int(re.search(r'data-points="(\d+)"', tag.group(0)).group(1))
    if points <= 0:
        sys.exit(f"figure {plot} has no points drawn")
    print(f"  {plot}: {points} points")
for table in re.findall(r"<table[^>]*>", dom):
    rows = re.search(r'data-rows="(\d+)"', table)
    if rows is None or int(rows.group(1)) <= 0:
        sys.exit(f"empty table: {table}")
PY
}

# Four short runs in the batch layout of run_batch.sh.
batch="$WORK/batch"
for planner in dwb sfw; do
  for seed in 1 2; do
    run_dir="$batch/runs/passing__${planner}__seed${seed}"
    "$BIN/hunav_run" --scenario "$REPO/scenarios/passing.yaml" --planner "$planner" --seed "$seed" --duration 12 \
      --out "$run_dir" --quiet >"$WORK/run.txt" 2>&1 || { cat "$WORK/run.txt"; fail "hunav_run $planner seed $seed failed"; }
  done
done
# One run shown as stuck (as the world ends a run that makes no progress for the scenario's
# stuck_timeout): its badge must carry the stuck colour on both pages.
sed -i -E 's/"status": *"[a-z_]*"/"status": "stuck"/' "$batch/runs/passing__sfw__seed1/run.json"
# summary.csv, summary_stats.csv and paired.csv from the runs' metrics.csv rows (mean, sample std,
# 95% CI with Student's t), as the batch aggregation writes them.
python3 - "$batch" <<'PY'
import csv, glob, json, math, os, statistics, sys
batch = sys.argv[1]
t95 = {1: 12.706, 2: 4.303, 3: 3.182}
rows, names = [], None
for run_dir in sorted(glob.glob(os.path.join(batch, "runs", "*"))):
    metrics = list(csv.DictReader(open(os.path.join(run_dir, "metrics.csv"))))[-1]
    info = json.load(open(os.path.join(run_dir, "run.json")))
    names = list(metrics)[7:]  # after the provenance columns (profile, people_model, ...)
    rows.append((info, os.path.relpath(run_dir, batch), metrics))
def num(v):
    return 1.0 if v == "true" else 0.0 if v == "false" else float(v)
with open(os.path.join(batch, "summary.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["scenario", "planner", "seed", "status", "sim_time", "wall_time", "run_dir"] + names)
    for info, rel, m in rows:
        w.writerow([info["scenario"], info["planner"], info["seed"], info["status"], info["sim_time"], info["wall_time"], rel]
                   + [m[n] for n in names])
values = {}
for info, rel, m in rows:
    for n in names:
        values.setdefault((info["planner"], n), {})[info["seed"]] = num(m[n])
with open(os.path.join(batch, "summary_stats.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["scenario", "planner", "behavior", "metric", "n", "mean", "std", "ci95_low", "ci95_high"])
    for (planner, n), by_seed in values.items():
        v = list(by_seed.values())
        mean, std = statistics.mean(v), statistics.stdev(v)
        half = t95[len(v) - 1] * std / math.sqrt(len(v))
        w.writerow(["passing", planner, "all", n, len(v), mean, std, mean - half, mean + half])
with open(os.path.join(batch, "paired.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["scenario", "planner_a", "planner_b", "metric", "n", "mean_diff", "ci95_low", "ci95_high", "significant"])
    for n in names:
        a, b = values[("dwb", n)], values[("sfw", n)]
        d = [a[s] - b[s] for s in sorted(a)]
        mean, std = statistics.mean(d), statistics.stdev(d)
        half = t95[len(d) - 1] * std / math.sqrt(len(d))
        w.writerow(["passing", "dwb", "sfw", n, len(d), mean, mean - half, mean + half,
                    "true" if (mean - half > 0 or mean + half < 0) else "false"])
PY

# Hand-written verdicts of an expect: block, as hunav_summary writes them from the runs' expect.json:
# sfw seed 1 fails the one condition, so the page shows dwb 2/2 passed, sfw 1/2 and one failing row.
cat >"$batch/expectations.csv" <<'CSV'
scenario,planner,seed,metric,condition,value,pass
passing,dwb,1,robot_on_person_collision,== 0,0,true
passing,dwb,2,robot_on_person_collision,== 0,0,true
passing,sfw,1,robot_on_person_collision,== 0,2,false
passing,sfw,2,robot_on_person_collision,== 0,0,true
CSV

"$BIN/hunav_report" "$batch" >"$WORK/report.txt" 2>&1 || { cat "$WORK/report.txt"; fail "hunav_report failed on the batch"; }
grep -q "and 4 run page(s)" "$WORK/report.txt" || { cat "$WORK/report.txt"; fail "hunav_report did not write the 4 run pages"; }

run_page="$batch/runs/passing__dwb__seed1/report.html"
size=$(stat -c %s "$run_page")
echo "run page: $size bytes"
render "$run_page" "$WORK/run_dom.html"
check "$WORK/run_dom.html" map closest_distance robot_speed social_work intrusions || fail "run page: see above"
grep -q 'id="metrics-table"[^>]*data-rows="3[0-9]"' "$WORK/run_dom.html" || fail "run page: the metrics table does not list every metric"

echo "batch page:"
render "$batch/report.html" "$WORK/batch_dom.html"
check "$WORK/batch_dom.html" ci-passing paired-passing || fail "batch page: see above"
grep -q 'id="runs-table"[^>]*data-rows="4"' "$WORK/batch_dom.html" || fail "batch page: the runs table does not list the 4 runs"
grep -q 'href="runs/passing__sfw__seed2/report.html"' "$WORK/batch_dom.html" || fail "batch page: no link to a run page"
grep -q '<table class="expectations"[^>]*data-rows="1"' "$WORK/batch_dom.html" ||
  fail "batch page: no table of the one failing expectation"
grep -q 'class="badge bad" data-planner="sfw" data-passed="1" data-failed="1"' "$WORK/batch_dom.html" ||
  fail "batch page: no failing expectations badge for sfw"
grep -q 'class="badge ok" data-planner="dwb" data-passed="2" data-failed="0"' "$WORK/batch_dom.html" ||
  fail "batch page: no passing expectations badge for dwb"
echo "the expectations show their badges and the failing condition"
[ "$(grep -o '<span class="badge stuck">stuck</span>' "$WORK/batch_dom.html" | wc -l)" -eq 1 ] ||
  fail "batch page: the stuck run has no stuck badge"
render "$batch/runs/passing__sfw__seed1/report.html" "$WORK/stuck_dom.html"
grep -q '<span class="badge stuck">stuck</span>' "$WORK/stuck_dom.html" || fail "run page: no stuck badge"
echo "the stuck run has its badge on both pages"

# A run with --counterfactual: its page shows each person against its robot-free run.
"$BIN/hunav_run" --scenario "$REPO/scenarios/passing.yaml" --planner dwb --seed 1 --out "$WORK/cf_run" --quiet \
  --counterfactual >"$WORK/cf_run.txt" 2>&1 || { cat "$WORK/cf_run.txt"; fail "hunav_run --counterfactual failed"; }
"$BIN/hunav_report" "$WORK/cf_run" >"$WORK/cf_report.txt" 2>&1 || { cat "$WORK/cf_report.txt"; fail "hunav_report failed on the counterfactual run"; }
render "$WORK/cf_run/report.html" "$WORK/cf_dom.html"
grep -q 'id="counterfactual-table"[^>]*data-rows="2"' "$WORK/cf_dom.html" || fail "run page: no counterfactual table of the 2 people"
grep -q 'people moved more than 0.1 m' "$WORK/cf_dom.html" || fail "run page: no counterfactual caption"
! grep -q 'id="counterfactual-table"' "$WORK/run_dom.html" || fail "run page: a counterfactual table without counterfactual.csv"
echo "the counterfactual run shows its people against the robot-free run"

# The check catches a page whose script fails: a run page with its data cut short.
sed 's|"frameT":\[|"frameT":[oops|' "$run_page" >"$WORK/broken.html"
render "$WORK/broken.html" "$WORK/broken_dom.html"
if check "$WORK/broken_dom.html" map >"$WORK/broken.txt" 2>&1; then fail "a broken page passed the check"; fi
grep -q "JavaScript error" "$WORK/broken.txt" || { cat "$WORK/broken.txt"; fail "the broken page's error was not reported"; }
echo "a broken page is reported: $(cat "$WORK/broken.txt")"
echo "OK"
