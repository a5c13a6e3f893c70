#!/usr/bin/env bash
# Issue 31: one writer per results folder. Two runs into one --out at once both exited 0 and left a
# torn states.csv (the offline evaluator then failed on it). A bounded property test: rounds of three
# writers of random kinds (hunav_run; run_experiment.sh in process or in lockstep; the offline
# evaluator) started together into one folder. Every writer either ran (exit 0) or was refused
# before it wrote anything (exit 2, "another run is writing into"); metrics.csv gained exactly one
# row per writer that ran, each with the header's fields; the folder's states.csv reads back (the
# offline evaluator recomputes it) and matches its run.json. Over the rounds, writers overlapped
# (some were refused). A label with "../" is refused too (it escaped --out).
source "$(dirname "$0")/common.sh"
SCENARIO="$REPO/scenarios/passing.yaml"
"$BIN/hunav_run" --scenario "$SCENARIO" --duration 3 --out "$WORK/source" --quiet >/dev/null
RANDOM=31
refused_total=0
ran_total=0
for round in 1 2 3 4 5 6; do
  out="$WORK/shared$round"
  pids=() kinds=()
  for w in 1 2 3; do
    case $((RANDOM % 4)) in
      0) kind=hunav_run cmd=("$BIN/hunav_run" --scenario "$SCENARIO" --duration 4 --out "$out" --quiet) ;;
      1) kind=inprocess cmd=("$RUN" --scenario "$SCENARIO" --duration 4 --out "$out") ;;
      2) kind=lockstep cmd=("$RUN" --scenario "$SCENARIO" --duration 4 --mode lockstep --out "$out") ;;
      3) kind=offline cmd=("$BIN/hunav_evaluator" --states "$WORK/source/states.csv" --out "$out") ;;
    esac
    "${cmd[@]}" >"$WORK/r$round-w$w.txt" 2>&1 &
    pids+=("$!") kinds+=("$kind")
  done
  ran=0
  for w in 0 1 2; do
    rc=0
    wait "${pids[$w]}" || rc=$?
    case "$rc" in
      0) ran=$((ran + 1)) ;;
      2) grep -q "another run.*is writing into" "$WORK/r$round-w$((w + 1)).txt" ||
           { cat "$WORK/r$round-w$((w + 1)).txt"; fail "round $round: ${kinds[$w]} exited 2 without saying why"; }
         refused_total=$((refused_total + 1)) ;;
      *) cat "$WORK/r$round-w$((w + 1)).txt"; fail "round $round: ${kinds[$w]} exited $rc" ;;
    esac
  done
  ran_total=$((ran_total + ran))
  echo "round $round: ${kinds[*]}: $ran ran, $((3 - ran)) refused"
  [ "$ran" -ge 1 ] || fail "round $round: no writer ran"
  python3 - "$out" "$ran" <<'PY' || fail "round $round: the folder is not whole"
import csv, json, sys
out, ran = sys.argv[1], int(sys.argv[2])
rows = list(csv.reader(open(out + "/metrics.csv")))
assert len(rows) == 1 + ran, "metrics.csv has %d rows for %d writers that ran" % (len(rows) - 1, ran)
assert all(len(r) == len(rows[0]) for r in rows), "a metrics.csv row is torn"
r = json.load(open(out + "/run.json"))
lines = open(out + "/states.csv").read().split("\n")
assert lines[-1] == "", "states.csv ends in the middle of a row"
ticks = len({l.split(",")[0] for l in lines[1:-1]})
assert ticks == r["recorded_ticks"], "states.csv has %d ticks, run.json %d" % (ticks, r["recorded_ticks"])
PY
  "$BIN/hunav_evaluator" --states "$out/states.csv" --out "$WORK/check$round" >/dev/null 2>&1 ||
    fail "round $round: the offline evaluator cannot read states.csv"
done
[ "$refused_total" -gt 0 ] || fail "no writer was ever refused: the writers never overlapped"
# Folder labels and scenario names are confined to --out.
rc=0
"$BIN/hunav_run" --scenario "$SCENARIO" --seeds 1 --folder-label ../escape --duration 1 --out "$WORK/label/runs" \
  --quiet >"$WORK/label.txt" 2>&1 || rc=$?
[ "$rc" -eq 2 ] || { cat "$WORK/label.txt"; fail "--folder-label ../escape: exit $rc, expected 2"; }
[ ! -e "$WORK/label/escape__dwb__seed1" ] || fail "--folder-label ../escape wrote outside --out"
no_orphans
echo "$ran_total writers ran and $refused_total were refused over 6 rounds; every folder whole"
