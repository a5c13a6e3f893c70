#!/usr/bin/env bash
# run_experiment.sh's planner options, end to end:
#  --planner-config reaches the built-in planner in both modes (a shorter dwb horizon gives another
#    run than the defaults, the same one in one process and in lockstep);
#  --planner-cmd runs your own planner process (the example planner of planners/examples/) in
#    lockstep, recorded under the name given with --planner, and stops it afterwards;
#  bad combinations exit 2 before anything runs.
source "$(dirname "$0")/common.sh"
scenario="$REPO/scenarios/passing.yaml"

# A dwb that looks 0.8 s ahead instead of 1.7 s (planners/config/dwb.yaml: dwb.sim_time).
cat > "$WORK/short_dwb.yaml" <<'EOF'
dwb:
  sim_time: 0.8
EOF
grep -q '^  sim_time:' "$REPO/planners/config/dwb.yaml" || fail "planners/config/dwb.yaml has no dwb.sim_time (the test's premise)"

"$RUN" --scenario "$scenario" --duration 6 --out "$WORK/default" > "$WORK/default.txt" 2>&1 \
  || { cat "$WORK/default.txt"; fail "default run failed"; }
"$RUN" --scenario "$scenario" --duration 6 --planner-config "$WORK/short_dwb.yaml" --out "$WORK/short_ip" \
  > "$WORK/short_ip.txt" 2>&1 || { cat "$WORK/short_ip.txt"; fail "inprocess run with --planner-config failed"; }
"$RUN" --scenario "$scenario" --duration 6 --planner-config "$WORK/short_dwb.yaml" --mode lockstep \
  --out "$WORK/short_ls" > "$WORK/short_ls.txt" 2>&1 \
  || { cat "$WORK/short_ls.txt"; cat "$WORK"/short_ls/logs/*.log; fail "lockstep run with --planner-config failed"; }
default_fp=$(json_field "$WORK/default/run.json" fingerprint)
short_fp=$(json_field "$WORK/short_ip/run.json" fingerprint)
[ "$short_fp" != "$default_fp" ] || fail "--planner-config changed nothing (fingerprint $short_fp in both)"
[ "$(json_field "$WORK/short_ls/run.json" fingerprint)" = "$short_fp" ] \
  || fail "--planner-config: lockstep $(json_field "$WORK/short_ls/run.json" fingerprint), inprocess $short_fp"
no_orphans

# Your own planner: the example planner, started by the script in the run's namespace.
"$RUN" --scenario "$scenario" --duration 4 --mode lockstep --planner mine \
  --planner-cmd "exec '$BIN/example_planner'" --out "$WORK/mine" > "$WORK/mine.txt" 2>&1 \
  || { cat "$WORK/mine.txt"; cat "$WORK"/mine/logs/*.log; fail "lockstep run with --planner-cmd failed"; }
[ "$(json_field "$WORK/mine/run.json" planner)" = mine ] || fail "run.json planner is not 'mine'"
[ "$(json_field "$WORK/mine/run.json" status)" = time_limit ] || fail "status $(json_field "$WORK/mine/run.json" status)"
[ "$(json_field "$WORK/mine/run.json" ticks)" = 401 ] || fail "ticks $(json_field "$WORK/mine/run.json" ticks), expected 401"
path=$(metric "$WORK/mine/metrics.csv" path_length)
python3 -c "import sys; sys.exit(0 if float('$path') > 0.5 else 1)" || fail "the example planner did not drive the robot (path $path m)"
[ -f "$WORK/mine/logs/planner.log" ] || fail "no planner log"
no_orphans
if [ -n "$(our_pid example_planner)" ]; then fail "the example planner was left running"; fi

# A batch of both: the built-in dwb with the parameter file (the same run as above) and your planner.
"$REPO/launch_scripts/run_batch.sh" --scenarios passing --planners dwb,mine --seeds 1 --mode lockstep --jobs 1 \
  --duration 6 --planner-config "dwb=$WORK/short_dwb.yaml" --planner-cmd "mine=exec '$BIN/example_planner'" \
  --out "$WORK/batch" > "$WORK/batch.txt" 2>&1 || { cat "$WORK/batch.txt"; fail "the batch with --planner-cmd failed"; }
[ "$(json_field "$WORK/batch/runs/passing__dwb__seed1/run.json" fingerprint)" = "$short_fp" ] \
  || fail "the batch's dwb run did not use its --planner-config"
[ "$(json_field "$WORK/batch/runs/passing__mine__seed1/run.json" status)" = time_limit ] || fail "the batch's own planner run"
grep -q '^passing,mine,1,time_limit,' "$WORK/batch/summary.csv" || fail "summary.csv lacks the own planner's run"
no_orphans
for bad in "--planner-cmd mine=true" "--planners dwb --planner-cmd mine=true --mode lockstep" \
           "--planners mine --mode lockstep" "--planners dwb --planner-config dwb=$WORK/nowhere.yaml"; do
  rc=0
  read -ra bad_args <<<"$bad"
  [[ $bad == *--planners* ]] || bad_args=(--planners mine "${bad_args[@]}")
  "$REPO/launch_scripts/run_batch.sh" --scenarios passing --seeds 1 --out "$WORK/badbatch" "${bad_args[@]}" \
    > "$WORK/badbatch.txt" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || { cat "$WORK/badbatch.txt"; fail "run_batch.sh $bad: exit $rc, expected 2"; }
done

# Bad combinations: exit 2, nothing run.
expect_2() {  # expect_2 DESCRIPTION ARGS...: run_experiment.sh ARGS exits 2 with an error line
  local what=$1 rc=0
  shift
  "$RUN" --scenario "$scenario" --out "$WORK/bad" "$@" > "$WORK/bad.txt" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || { cat "$WORK/bad.txt"; fail "$what: exit $rc, expected 2"; }
  grep -q 'run_experiment: error:' "$WORK/bad.txt" || fail "$what: no error line"
}
expect_2 "--planner-cmd in one process" --planner-cmd true
expect_2 "--planner-cmd with --planner-config" --mode lockstep --planner-cmd true --planner-config "$WORK/short_dwb.yaml"
expect_2 "--planner-cmd with --planner none" --mode lockstep --planner-cmd true --planner none
expect_2 "--planner-cmd with a bad name" --mode lockstep --planner-cmd true --planner 'my planner'
expect_2 "an unknown planner without --planner-cmd" --planner mine
expect_2 "a missing --planner-config file" --planner-config "$WORK/nowhere.yaml"
echo "bad: [" > "$WORK/broken.yaml"
expect_2 "a malformed --planner-config file" --planner-config "$WORK/broken.yaml" --duration 1
grep -q 'broken.yaml' "$WORK/bad.txt" || fail "the malformed config's error does not name the file"
no_orphans
echo "planner options: config $short_fp in both modes (default $default_fp); own planner drove $path m"
