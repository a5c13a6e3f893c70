#!/usr/bin/env bash
# SIGINT (or SIGTERM) to run_experiment.sh mid-run stops every process and keeps what was recorded,
# with one status per cause in every mode (README.md, "Statuses and exit codes"): `interrupted`,
# reason "interrupted (SIGINT/SIGTERM)", complete false, exit 130 (SIGINT) or 143 (SIGTERM). Before,
# the same interrupt gave aborted/incomplete depending on timing, and hunav_run complete: true.
source "$(dirname "$0")/common.sh"
# Job control: without it bash starts background jobs with SIGINT ignored, as a Ctrl-C would not be.
set -m
check_interrupted() {  # check_interrupted LABEL DIR RC EXPECTED_RC
  local label=$1 out=$2 rc=$3 want=$4
  [ "$rc" -eq "$want" ] || fail "$label: exit $rc, expected $want"
  [ -f "$out/run.json" ] || fail "$label: no run.json"
  [ "$(json_field "$out/run.json" status)" = interrupted ] || fail "$label: status $(json_field "$out/run.json" status)"
  [ "$(json_field "$out/run.json" reason)" = "interrupted (SIGINT/SIGTERM)" ] ||
    fail "$label: reason $(json_field "$out/run.json" reason)"
  [ "$(json_field "$out/run.json" complete)" = false ] || fail "$label: complete is not false"
  local rows ticks
  rows=$(wc -l < "$out/states.csv")
  ticks=$(json_field "$out/run.json" recorded_ticks)
  [ "$rows" -eq $((2 * ticks + 1)) ] || fail "$label: states.csv has $rows lines for $ticks ticks (robot + 1 person)"
  [ "$(wc -l < "$out/metrics.csv")" -eq 2 ] || fail "$label: metrics.csv has no row"
  check_layout "$out"
  echo "$label interrupted after $ticks ticks: exit $rc, results kept"
}
for case in lockstep:INT inprocess:INT realtime:INT lockstep:TERM inprocess:TERM; do
  mode=${case%%:*} sig=${case#*:}
  out="$WORK/$mode-$sig"
  "$RUN" --scenario "$REPO/tests/integration/data/endless_corridor.yaml" --mode "$mode" --out "$out" \
    > "$WORK/$mode-$sig.txt" 2>&1 &
  script=$!
  if [ "$mode" = realtime ]; then wait_for_rows "$out/states.csv" 200; else wait_for_rows "$out/states.csv" 2000; fi
  kill -"$sig" "$script"
  rc=0
  wait "$script" || rc=$?
  if [ "$sig" = INT ]; then want=130; else want=143; fi
  check_interrupted "$mode $sig" "$out" "$rc" "$want"
  no_orphans
done
# hunav_run itself, interrupted: the same status, complete false, exit 130.
out="$WORK/hunav_run"
"$BIN/hunav_run" --scenario "$REPO/tests/integration/data/endless_corridor.yaml" --out "$out" > "$WORK/hunav_run.txt" 2>&1 &
pid=$!
wait_for_rows "$out/states.csv" 2000
kill -INT "$pid"
rc=0
wait "$pid" || rc=$?
check_interrupted "hunav_run INT" "$out" "$rc" 130
no_orphans
