#!/usr/bin/env bash
# run_batch.sh end to end on a small matrix (passing x dwb, sfw x seeds 1-2, 5 s of simulation each,
# in-process: no network): the batch folder's layout, then resumability (a second invocation runs
# nothing, a third reruns only the run whose results were removed, a fourth only the run marked
# aborted, which the summary's statistics leave out, a fifth nothing after a run is marked stuck,
# which they keep), then a batch without states.csv and per-tick files (the same metrics), then bad
# arguments, then a folder another run holds.
# Expects REPO and BIN (ctest sets them).
set -euo pipefail
export HUNAV_BIN_DIR="$BIN"
WORK=$(mktemp -d /tmp/hunav_batch_test.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
BATCH="$REPO/launch_scripts/run_batch.sh"
out="$WORK/batch"
args=(--scenarios passing --planners "dwb,sfw" --seeds 1-2 --jobs 2 --duration 5 --out "$out")

"$BATCH" "${args[@]}" >"$WORK/first.log" 2>&1 || { cat "$WORK/first.log"; fail "first invocation failed"; }
grep -q 'run_batch: \[4/4\]' "$WORK/first.log" || { cat "$WORK/first.log"; fail "no progress line [4/4]"; }
grep -q '^run_batch: 4 runs in ' "$WORK/first.log" || fail "the first invocation did not run 4 runs"
mkdir -p "$WORK/first_metrics"
for d in "$out"/runs/*; do cp "$d/metrics.csv" "$WORK/first_metrics/${d##*/}.csv"; done
cp "$out/paired.csv" "$WORK/first_metrics/paired.csv"

for f in matrix.tsv batch.log summary.csv summary_stats.csv paired.csv summary.md; do
  [ -s "$out/$f" ] || fail "missing $out/$f"
done
for p in dwb sfw; do
  for s in 1 2; do
    d="$out/runs/passing__${p}__seed$s"
    { [ -s "$d/metrics.csv" ] && [ -s "$d/run.json" ] && [ -s "$d/states.csv" ]; } || fail "incomplete run folder $d"
    # In-process batches run the matrix in one hunav_run (--runs): each run's own console output.
    grep -q "^run passing_${p}_s$s: " "$d/logs/hunav_run.log" || fail "no console log in $d/logs"
    grep -q "^results in $d\$" "$d/logs/hunav_run.log" || fail "$d/logs/hunav_run.log holds another run's output"
    checker="$REPO/../shared/tools/check_outputs.py"
    if [ -f "$checker" ]; then python3 "$checker" "$d" >/dev/null || fail "layout check of $d"; fi
  done
done

python3 - "$out" <<'PY'
import csv, sys
out = sys.argv[1]
rows = list(csv.reader(open(out + "/summary.csv")))
head = rows[0]
assert head[:7] == ["scenario", "planner", "seed", "status", "sim_time", "wall_time", "run_dir"], head
metrics_head = next(csv.reader(open(out + "/runs/passing__dwb__seed1/metrics.csv")))
assert head[7:] == metrics_head[7:], "summary.csv metric columns differ from metrics.csv's"
body = rows[1:]
assert [(r[0], r[1], r[2]) for r in body] == [("passing", "dwb", "1"), ("passing", "dwb", "2"),
                                             ("passing", "sfw", "1"), ("passing", "sfw", "2")], body
assert all(r[3] == "time_limit" and float(r[4]) == 5.0 for r in body), body
assert body[0][6] == "runs/passing__dwb__seed1"
stats = list(csv.DictReader(open(out + "/summary_stats.csv")))
assert list(stats[0].keys()) == ["scenario", "planner", "behavior", "metric", "n", "mean", "std", "ci95_low", "ci95_high"]
t = [r for r in stats if r["planner"] == "dwb" and r["behavior"] == "all" and r["metric"] == "time_to_reach_goal"]
assert len(t) == 1 and t[0]["n"] == "2" and float(t[0]["mean"]) == 5.0, t
assert any(r["behavior"] == "regular" for r in stats), "no per-behavior rows"
paired = list(csv.DictReader(open(out + "/paired.csv")))
assert list(paired[0].keys()) == ["scenario", "planner_a", "planner_b", "metric", "n", "mean_diff", "ci95_low", "ci95_high", "significant"]
assert all(r["planner_a"] == "dwb" and r["planner_b"] == "sfw" and r["n"] == "2" for r in paired)
md = open(out + "/summary.md").read()
assert "## Scenario `passing`" in md and "| metric | unit | dwb | sfw |" in md and "paired comparisons" in md
PY

# Resumable: nothing runs again, and the results are untouched.
before=$(stat -c '%Y.%N' "$out"/runs/*/run.json | md5sum)
"$BATCH" "${args[@]}" >"$WORK/second.log" 2>&1 || { cat "$WORK/second.log"; fail "second invocation failed"; }
grep -q '4 already finished' "$WORK/second.log" || fail "the second invocation did not see 4 finished runs"
grep -q '^run_batch: 0 runs in ' "$WORK/second.log" || { cat "$WORK/second.log"; fail "the second invocation ran something"; }
[ "$(grep -c 'skipped (finished before)' "$WORK/second.log")" -eq 4 ] || fail "not every run was skipped"
[ "$before" = "$(stat -c '%Y.%N' "$out"/runs/*/run.json | md5sum)" ] || fail "finished runs were rewritten"
[ "$(wc -l <"$out/batch.log")" -eq 2 ] || fail "batch.log should have one line per invocation"

# A run without its results (interrupted, failed) runs again, alone.
rm "$out/runs/passing__sfw__seed2/run.json"
"$BATCH" "${args[@]}" >"$WORK/third.log" 2>&1 || { cat "$WORK/third.log"; fail "third invocation failed"; }
grep -q '^run_batch: 1 runs in ' "$WORK/third.log" || { cat "$WORK/third.log"; fail "the third invocation did not rerun exactly one run"; }
grep -q 'passing sfw seed 2: time_limit' "$WORK/third.log" || fail "the rerun was not passing sfw seed 2"
[ "$(grep -c '^passing,' "$out/summary.csv")" -eq 4 ] || fail "summary.csv lost rows"

# An aborted run (its run.json as an interrupted episode leaves it: complete, status aborted) is not a
# result: hunav_summary leaves it out of the statistics, and the next invocation runs it again.
json="$out/runs/passing__dwb__seed1/run.json"
sed -i -E 's/"status": *"time_limit"/"status": "aborted"/; s/"reason": *"[^"]*"/"reason": "interrupted (SIGINT\/SIGTERM)"/' "$json"
grep -q '"status": "aborted"' "$json" || fail "could not mark $json aborted"
"$BIN/hunav_summary" "$out" >/dev/null || fail "hunav_summary failed on a batch with an aborted run"
python3 - "$out" <<'PY'
import csv, sys
out = sys.argv[1]
stats = list(csv.DictReader(open(out + "/summary_stats.csv")))
t = {r["planner"]: r["n"] for r in stats if r["behavior"] == "all" and r["metric"] == "time_to_reach_goal"}
assert t == {"dwb": "1", "sfw": "2"}, t  # dwb: seed 2 only
paired = [r for r in csv.DictReader(open(out + "/paired.csv")) if r["metric"] == "time_to_reach_goal"]
assert len(paired) == 1 and paired[0]["n"] == "1", paired  # only seed 2 has both
rows = [r for r in csv.DictReader(open(out + "/summary.csv")) if r["planner"] == "dwb" and r["seed"] == "1"]
assert len(rows) == 1 and rows[0]["status"] == "aborted", rows  # still listed, with its status
assert "**1 run left out of every table**" in open(out + "/summary.md").read()
PY
"$BATCH" "${args[@]}" >"$WORK/fourth.log" 2>&1 || { cat "$WORK/fourth.log"; fail "fourth invocation failed"; }
grep -q '^run_batch: 1 runs in ' "$WORK/fourth.log" || { cat "$WORK/fourth.log"; fail "the aborted run was not run again (alone)"; }
grep -q 'passing dwb seed 1: time_limit' "$WORK/fourth.log" || fail "the rerun was not passing dwb seed 1"
grep -q 'left out of every table' "$out/summary.md" && fail "summary.md still leaves a run out after the rerun"

# A stuck run (no progress for the scenario's stuck_timeout) is a result, a failure to reach the goal:
# kept in the statistics, shown apart in summary.md, and not run again.
json="$out/runs/passing__sfw__seed1/run.json"
sed -i -E 's/"status": *"time_limit"/"status": "stuck"/' "$json"
grep -q '"status": "stuck"' "$json" || fail "could not mark $json stuck"
"$BATCH" "${args[@]}" >"$WORK/fifth.log" 2>&1 || { cat "$WORK/fifth.log"; fail "fifth invocation failed"; }
grep -q '^run_batch: 0 runs in ' "$WORK/fifth.log" || { cat "$WORK/fifth.log"; fail "the stuck run was run again"; }
python3 - "$out" <<'PY'
import csv, sys
out = sys.argv[1]
stats = list(csv.DictReader(open(out + "/summary_stats.csv")))
n = {r["planner"]: r["n"] for r in stats if r["behavior"] == "all" and r["metric"] == "completed"}
assert n == {"dwb": "2", "sfw": "2"}, n  # the stuck run counts
rows = [r for r in csv.DictReader(open(out + "/summary.csv")) if r["planner"] == "sfw" and r["seed"] == "1"]
assert len(rows) == 1 and rows[0]["status"] == "stuck", rows
md = open(out + "/summary.md").read()
assert "| planner | runs | goal_reached | time_limit | stuck | not ended |" in md, md
assert "| sfw | 2 | 0 | 1 | 1 | 0 |" in md, md
assert "left out of every table" not in md, md
PY

# --no-states-csv --no-per-tick-files: the same metrics of every run (and so the same statistics)
# without states.csv and the per-tick files.
lean="$WORK/lean"
"$BATCH" --scenarios passing --planners dwb,sfw --seeds 1-2 --jobs 2 --duration 5 --no-states-csv --no-per-tick-files \
  --out "$lean" >"$WORK/lean.log" 2>&1 || { cat "$WORK/lean.log"; fail "the lean batch failed"; }
for d in "$lean"/runs/*; do
  { [ ! -e "$d/states.csv" ] && [ -z "$(find "$d" -name '*_steps.csv')" ]; } || fail "$d holds states.csv or per-tick files"
  cmp -s "$d/metrics.csv" "$WORK/first_metrics/${d##*/}.csv" || fail "${d##*/}: the metrics differ from the full batch's"
done
[ "$(find "$lean/runs" -name metrics.csv | wc -l)" -eq 4 ] || fail "the lean batch did not write 4 runs"
cmp -s "$WORK/first_metrics/paired.csv" "$lean/paired.csv" || fail "the lean batch's paired.csv differs"

# Bad arguments: exit 2 and nothing run.
for bad in "--planners xyz" "--seeds 3-1" "--scenarios nowhere" "--jobs 0" "--mode fast" \
  "--no-states-csv --counterfactual" "--no-per-tick-files --mode lockstep"; do
  rc=0
  # shellcheck disable=SC2086 # $bad holds an option and its value
  "$BATCH" --scenarios passing --planners dwb --seeds 1 --out "$WORK/bad" $bad >/dev/null 2>"$WORK/bad.err" || rc=$?
  [ "$rc" -eq 2 ] || fail "'$bad' exited $rc, expected 2"
  grep -q 'run_batch: error:' "$WORK/bad.err" || fail "'$bad' printed no error"
done
[ ! -e "$WORK/bad" ] || fail "a rejected batch created its folder"

# A results folder another live run or batch holds (its flock, taken here as a run would) is refused:
# exit 2 with a message, nothing run, nothing of the holder's touched.
held="$WORK/held"
mkdir -p "$held"
echo "the holder's" >"$held/marker"
exec {holder_fd}<"$held"
flock -n "$holder_fd" || fail "could not take the lock of $held"
rc=0
"$BATCH" --scenarios passing --planners dwb --seeds 1 --duration 5 --out "$held" >/dev/null 2>"$WORK/held.err" || rc=$?
[ "$rc" -eq 2 ] || { cat "$WORK/held.err"; fail "a batch into a held folder exited $rc, expected 2"; }
grep -q 'another run is writing into' "$WORK/held.err" || { cat "$WORK/held.err"; fail "no message naming the held folder"; }
{ [ ! -e "$held/runs" ] && [ "$(cat "$held/marker")" = "the holder's" ]; } || fail "the refused batch wrote into $held"
exec {holder_fd}<&-
echo "PASS run_batch_small"
