#!/usr/bin/env bash
# A robot that makes no progress ends its episode `stuck`, a run that ran to its end: run_experiment.sh
# exits 0 in one process (hunav_run) and as separate processes (hunav_worldsim), and run.json says
# stuck, complete, with `completed` false.
source "$(dirname "$0")/common.sh"
scenario="$WORK/passing_stuck.yaml"
{ cat "$REPO/scenarios/passing.yaml"; printf 'stuck_timeout: 2\n'; } > "$scenario"

for mode in inprocess lockstep; do
  d="$WORK/$mode"
  rc=0
  "$RUN" --scenario "$scenario" --planner none --mode "$mode" --out "$d" > "$WORK/$mode.txt" 2>&1 || rc=$?
  [ "$rc" -eq 0 ] || { cat "$WORK/$mode.txt"; fail "$mode: exit $rc for a stuck episode, expected 0"; }
  [ "$(json_field "$d/run.json" status)" = stuck ] || fail "$mode: status $(json_field "$d/run.json" status)"
  # Without a planner the robot stands at its start from t = 0 (the people are still 10 m away at
  # 2 s): stuck at t = 0 + 2 s, tick 200, so 201 world states.
  [ "$(json_field "$d/run.json" ticks)" = 201 ] || fail "$mode: $(json_field "$d/run.json" ticks) ticks, not 201"
  [ "$(json_field "$d/run.json" complete)" = true ] || fail "$mode: run.json not complete"
  [ "$(metric "$d/metrics.csv" completed)" = false ] || fail "$mode: completed $(metric "$d/metrics.csv" completed)"
  json_field "$d/run.json" reason | grep -q '^the robot made no progress for 2 s (stayed within 0.5 m of (0.00, 0.00)' ||
    fail "$mode: reason $(json_field "$d/run.json" reason)"
  check_layout "$d"
done
[ "$(json_field "$WORK/inprocess/run.json" fingerprint)" = "$(json_field "$WORK/lockstep/run.json" fingerprint)" ] ||
  fail "the modes' fingerprints differ"
no_orphans
echo "stuck at 2 s in both modes, exit 0"
