#!/usr/bin/env bash
# Every process's drop count reaches run.json: undecodable datagrams sent to the manager
# (STEP_REQUEST) and to the planner (ROBOT_OBSERVATION) in the middle of a realtime run are dropped
# and counted by each, told to the world (step replies, PLANNER_READY) and written by the evaluator as
# manager_dropped_messages and planner_dropped_messages; the run itself is untouched (goal or time
# limit, complete). A clean run records 0 for both.
source "$(dirname "$0")/common.sh"
garbage="$REPO/tests/integration/data/send_garbage.py"
planner="$BIN/hunav_planner --planner dwb --scenario $REPO/scenarios/passing.yaml"

# 4 bad step requests and 3 bad observations, 1 s into a 3 s run (the next reply and observation tell them).
out="$WORK/garbage"
"$RUN" --scenario "$REPO/scenarios/passing.yaml" --mode realtime --duration 3 --planner dwb --out "$out" \
  --planner-cmd "/usr/bin/python3 $garbage 1.0 STEP_REQUEST:1:4 ROBOT_OBSERVATION:0:3 & exec $planner" \
  > "$WORK/garbage.txt" 2>&1 || { cat "$WORK/garbage.txt"; fail "the run with garbage exited non-zero"; }
grep -q "sent 7 datagrams" "$out/logs/planner.log" || { cat "$out/logs/planner.log"; fail "the garbage was not sent"; }
[ "$(json_field "$out/run.json" manager_dropped_messages)" = 4 ] \
  || fail "manager_dropped_messages $(json_field "$out/run.json" manager_dropped_messages), expected 4"
[ "$(json_field "$out/run.json" planner_dropped_messages)" = 3 ] \
  || fail "planner_dropped_messages $(json_field "$out/run.json" planner_dropped_messages), expected 3"
[ "$(json_field "$out/run.json" world_dropped_messages)" = 0 ] || fail "the world dropped messages"
[ "$(json_field "$out/run.json" complete)" = true ] || fail "the run with garbage is not complete"

# The same run without garbage: zeros, not unknowns.
clean="$WORK/clean"
"$RUN" --scenario "$REPO/scenarios/passing.yaml" --mode realtime --duration 3 --planner dwb --out "$clean" \
  > "$WORK/clean.txt" 2>&1 || { cat "$WORK/clean.txt"; fail "the clean run exited non-zero"; }
for key in manager_dropped_messages planner_dropped_messages world_dropped_messages dropped_messages; do
  [ "$(json_field "$clean/run.json" "$key")" = 0 ] || fail "clean run: $key $(json_field "$clean/run.json" "$key")"
done
no_orphans
echo "garbage: manager 4, planner 3 dropped and recorded; clean run: zeros"
