#!/usr/bin/env bash
# Killing the manager or the planner mid-run: the world ends the episode `aborted`, naming the silent
# component, within 2 s; the evaluator still writes what it recorded; the script exits non-zero and
# leaves no process behind.
source "$(dirname "$0")/common.sh"
for victim in manager planner; do
  out="$WORK/$victim"
  "$RUN" --scenario "$REPO/tests/integration/data/endless_corridor.yaml" --mode lockstep --out "$out" \
    > "$WORK/$victim.txt" 2>&1 &
  script=$!
  wait_for_rows "$out/states.csv" 2000
  pid=$(pgrep -f "$BIN/hunav_$victim" | head -n1)
  [ -n "$pid" ] || fail "no $victim process found"
  killed_at=$(date +%s.%N)
  kill -KILL "$pid"
  rc=0
  wait "$script" || rc=$?
  [ "$rc" -ne 0 ] || fail "$victim killed but the script exited 0"
  [ "$(json_field "$out/run.json" status)" = aborted ] || fail "status $(json_field "$out/run.json" status)"
  reason=$(json_field "$out/run.json" reason)
  case "$reason" in *"$victim"*) ;; *) fail "the reason does not name the $victim: $reason" ;; esac
  # The world gives up after 1 s of silence; its END event carries its wall time.
  ended=$(python3 -c 'import os,sys; print(os.path.getmtime(sys.argv[1]))' "$out/run.json")
  python3 -c "import sys; d=$ended-$killed_at; sys.exit(0 if d < 2.0 else 1)" \
    || fail "run.json written $(python3 -c "print($ended-$killed_at)") s after the kill"
  [ "$(wc -l < "$out/states.csv")" -gt 2000 ] || fail "states.csv lost its rows"
  no_orphans
  echo "$victim killed: aborted ($reason), exit $rc"
done
