#!/usr/bin/env bash
# run_experiment.sh supervises every process it started: killing the planner or the manager mid-run,
# in realtime (where the world used to drive on the planner's last command until the time limit) and
# in lockstep, ends the run within 2 s as `aborted`, with a reason naming the process and the signal
# that killed it; the evaluator still writes what it recorded; the script exits 1 and leaves no process
# behind. Killing the recorder itself (the evaluator in lockstep, hunav_run in process) left no run.json
# and a states.csv cut mid-row (issue 31): the script now writes run.json from what it recorded, with
# the same status and reason, and states.csv is cut at its last whole tick.
source "$(dirname "$0")/common.sh"
for case in realtime:planner realtime:manager lockstep:planner lockstep:manager lockstep:evaluator inprocess:run; do
  mode=${case%%:*}
  victim=${case#*:}
  named=$victim
  [ "$victim" != run ] || named=hunav_run
  out="$WORK/$mode-$victim"
  "$RUN" --scenario "$REPO/tests/integration/data/endless_corridor.yaml" --mode "$mode" --out "$out" \
    > "$WORK/$mode-$victim.txt" 2>&1 &
  script=$!
  if [ "$mode" = realtime ]; then
    wait_for_sim_time "$out/states.csv" 4  # 4 s into the run
  else
    wait_for_rows "$out/states.csv" 2000
  fi
  pid=$(our_pid "$victim")
  [ -n "$pid" ] || fail "$case: no $victim process found"
  killed_at=$(date +%s.%N)
  kill -KILL "$pid"
  rc=0
  wait "$script" || rc=$?
  done_at=$(date +%s.%N)
  [ "$rc" -eq 1 ] || { cat "$WORK/$mode-$victim.txt"; fail "$case: $victim killed but the script exited $rc (expected 1)"; }
  [ "$(json_field "$out/run.json" status)" = aborted ] || fail "$case: status $(json_field "$out/run.json" status)"
  [ "$(json_field "$out/run.json" complete)" = false ] || fail "$case: complete is not false"
  reason=$(json_field "$out/run.json" reason)
  case "$reason" in "$named was killed by SIGKILL"*) ;; *) fail "$case: the reason does not name the $named and SIGKILL: $reason" ;; esac
  grep -q "aborted.*$named was killed by SIGKILL" "$WORK/$mode-$victim.txt" || fail "$case: the script does not say why"
  [ "$(json_field "$out/run.json" seed)" = 3 ] || fail "$case: seed $(json_field "$out/run.json" seed)"
  [ "$(json_field "$out/run.json" scenario)" = endless_corridor ] || fail "$case: scenario $(json_field "$out/run.json" scenario)"
  [ "$(tail -c 1 "$out/states.csv" | od -An -c | tr -d ' ')" = '\n' ] || fail "$case: states.csv ends mid-row"
  "$BIN/hunav_evaluator" --states "$out/states.csv" --out "$WORK/$mode-$victim-offline" >/dev/null ||
    fail "$case: the offline evaluator cannot read states.csv"
  ended=$(python3 -c 'import os,sys; print(os.path.getmtime(sys.argv[1]))' "$out/run.json")
  python3 -c "import sys; sys.exit(0 if $ended - $killed_at < 2.0 else 1)" \
    || fail "$case: run.json written $(python3 -c "print($ended - $killed_at)") s after the kill"
  python3 -c "import sys; sys.exit(0 if $done_at - $killed_at < 4.0 else 1)" \
    || fail "$case: the script ended $(python3 -c "print($done_at - $killed_at)") s after the kill"
  rows=$(wc -l < "$out/states.csv")
  ticks=$(json_field "$out/run.json" recorded_ticks)
  [ "$rows" -eq $((2 * ticks + 1)) ] || fail "$case: states.csv has $rows lines for $ticks ticks"
  [ "$ticks" -gt 300 ] || fail "$case: only $ticks ticks recorded"
  no_orphans
  echo "$case killed: aborted ($reason), exit $rc; run.json $(python3 -c "print(round($ended - $killed_at, 2))") s and the script's exit $(python3 -c "print(round($done_at - $killed_at, 2))") s after the kill"
done
