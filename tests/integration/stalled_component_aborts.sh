#!/usr/bin/env bash
# Stalls end a run like deaths: a SIGSTOPped world (realtime) is found by run_experiment.sh's
# supervision (stopped for HUNAV_STALL_LIMIT s), a planner that stops answering in realtime by the
# world (no command for its silence limit, 1 s); both aborted, naming the stalled process, exit 1.
# And run_batch.sh stops a run that hangs at its default per-run timeout (margin + 2 x time limit).
source "$(dirname "$0")/common.sh"
scenario="$REPO/tests/integration/data/endless_corridor.yaml"

run_and_stop() {  # run_and_stop NAME VICTIM EXPECTED_REASON_PREFIX MAX_SECONDS [env...]
  local name=$1 victim=$2 prefix=$3 max=$4
  shift 4
  local out="$WORK/$name" script pid stopped_at rc=0 took
  env "$@" "$RUN" --scenario "$scenario" --mode realtime --out "$out" > "$WORK/$name.txt" 2>&1 &
  script=$!
  wait_for_sim_time "$out/states.csv" 2  # 2 s into the run
  pid=$(our_pid "$victim")
  [ -n "$pid" ] || fail "$name: no $victim process"
  stopped_at=$(date +%s.%N)
  kill -STOP "$pid"
  wait "$script" || rc=$?
  took=$(python3 -c "print(round($(date +%s.%N) - $stopped_at, 2))")
  [ "$rc" -eq 1 ] || { cat "$WORK/$name.txt"; fail "$name: exit $rc, expected 1"; }
  [ "$(json_field "$out/run.json" status)" = aborted ] || fail "$name: status $(json_field "$out/run.json" status)"
  case "$(json_field "$out/run.json" reason)" in "$prefix"*) ;; *) fail "$name: reason $(json_field "$out/run.json" reason)" ;; esac
  python3 -c "import sys; sys.exit(0 if $took < $max else 1)" || fail "$name: the run ended $took s after the stop"
  no_orphans
  echo "$name: aborted ($(json_field "$out/run.json" reason)) $took s after SIGSTOP"
}

run_and_stop world_stopped worldsim "worldsim stalled: stopped (process state T)" 5
# The script would see the stopped planner only after 60 s: the world's own watchdog ends it first.
run_and_stop planner_silent planner "planner stalled: no robot command for 1000 ms" 4 HUNAV_STALL_LIMIT=60

# run_batch.sh: a realtime run whose world hangs (stopped, the script's stall check off) is stopped at
# the default timeout: HUNAV_BATCH_TIMEOUT_MARGIN 4 + 2 x --duration 8 = 20 s, exit 124, not finished.
# (8 s, not less: the evaluator writes states.csv in blocks, the first about 2 s into the run, and the
# test must find the world still running after it saw them, however loaded the machine.)
"$REPO/launch_scripts/run_batch.sh" --help | grep -q "HUNAV_BATCH_TIMEOUT_MARGIN (60) + 2 x the run's time limit" ||
  fail "run_batch.sh --help does not document the default timeout"
batch="$WORK/batch"
HUNAV_STALL_LIMIT=600 HUNAV_BATCH_TIMEOUT_MARGIN=4 "$REPO/launch_scripts/run_batch.sh" --scenarios "$scenario" \
  --planners dwb --seeds 1 --mode realtime --duration 8 --jobs 1 --out "$batch" > "$WORK/batch.txt" 2>&1 &
batch_pid=$!
run="$batch/runs/endless_corridor__dwb__seed1"
wait_for_rows "$run/states.csv" 10
pid=$(our_pid worldsim)
[ -n "$pid" ] || fail "batch: no world process"
stopped_at=$(date +%s.%N)
kill -STOP "$pid"
rc=0
wait "$batch_pid" || rc=$?
took=$(python3 -c "print(round($(date +%s.%N) - $stopped_at, 1))")
[ "$rc" -eq 1 ] || { cat "$WORK/batch.txt"; fail "batch: exit $rc, expected 1 (a run did not finish)"; }
grep -q "exited with 124\|NOT FINISHED: aborted (wall-clock timeout" "$WORK/batch.txt" ||
  { cat "$WORK/batch.txt"; fail "batch: the run was not stopped by the timeout"; }
case "$(json_field "$run/run.json" reason)" in "wall-clock timeout: the run still ran after 20 s"*) ;;
  *) fail "batch: reason $(json_field "$run/run.json" reason)" ;; esac
python3 -c "import sys; sys.exit(0 if $took < 30 else 1)" || fail "batch: the hung run took $took s to stop"
no_orphans
echo "batch: the hung run stopped by the default timeout ($took s after the stall)"
