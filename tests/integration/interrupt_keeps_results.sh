#!/usr/bin/env bash
# SIGINT to run_experiment.sh mid-run stops every process and keeps what was recorded.
source "$(dirname "$0")/common.sh"
# Job control: without it bash starts background jobs with SIGINT ignored, as a Ctrl-C would not be.
set -m
for mode in lockstep inprocess; do
  out="$WORK/$mode"
  "$RUN" --scenario "$REPO/tests/integration/data/endless_corridor.yaml" --mode "$mode" --out "$out" \
    > "$WORK/$mode.txt" 2>&1 &
  script=$!
  wait_for_rows "$out/states.csv" 2000
  kill -INT "$script"
  rc=0
  wait "$script" || rc=$?
  [ "$rc" -ne 0 ] || fail "$mode: interrupted run exited 0"
  [ -f "$out/run.json" ] || fail "$mode: no run.json after SIGINT"
  # Either the world closed the episode as aborted (interrupted), or the evaluator was stopped first
  # and marked the recording incomplete; never a normal ending.
  status=$(json_field "$out/run.json" status)
  case "$status" in aborted|incomplete) ;; *) fail "$mode: status $status after SIGINT" ;; esac
  rows=$(wc -l < "$out/states.csv")
  ticks=$(json_field "$out/run.json" recorded_ticks)
  [ "$rows" -eq $((2 * ticks + 1)) ] || fail "$mode: states.csv has $rows lines for $ticks ticks (robot + 1 person)"
  [ "$(wc -l < "$out/metrics.csv")" -eq 2 ] || fail "$mode: metrics.csv has no row"
  check_layout "$out"
  no_orphans
  echo "$mode interrupted after $ticks ticks: exit $rc, results kept"
done
