#!/usr/bin/env bash
# Issue 31: forged messages injected into a lockstep run, over LCM in this test's private network
# namespace (tests/common/in_netns.sh runs it), cannot steer it. Each kind that ended such a run before
# (an END or START of another episode, an observation with seq 10^12, a 10,000-byte mode of invalid
# UTF-8, a PLANNER_READY count of 4.6e18) and its relatives (forged_messages.hpp), one every 2 ms,
# from the run's first world state to its end: the run ends as the clean run does, with the clean run's
# fingerprint (hunav_run's: the same in every mode), run.json is readable (hunav_expect), and the
# components counted what they dropped.
source "$(dirname "$0")/common.sh"
URL='udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304'
SCENARIO="$REPO/scenarios/passing.yaml"

clean=$("$BIN/hunav_run" --scenario "$SCENARIO" --planner dwb --out "$WORK/clean" --quiet |
  sed -n -E 's/.*fingerprint ([0-9a-f]{16}).*/\1/p')
[ -n "$clean" ] || fail "no fingerprint from the clean run"

"$BIN/forge_messages" "$URL" 120 31 >"$WORK/forger.log" 2>&1 &
forger=$!
wait_printed_ready "$WORK/forger.log"
rc=0
"$RUN" --scenario "$SCENARIO" --planner dwb --mode lockstep --shared-bus "$URL" --out "$WORK/forged" \
  >"$WORK/run.txt" 2>&1 || rc=$?
kill -TERM "$forger"
wait "$forger" || fail "the forger exited $?"
cat "$WORK/forger.log"
[ "$rc" -eq 0 ] || { cat "$WORK/run.txt"; fail "the forged run exited $rc"; }
run_json="$WORK/forged/run.json"
[ "$(json_field "$run_json" status)" = goal_reached ] || fail "status $(json_field "$run_json" status)"
[ "$(json_field "$run_json" fingerprint)" = "$clean" ] ||
  fail "fingerprint $(json_field "$run_json" fingerprint), the clean run's is $clean"
[ "$(json_field "$run_json" complete)" = true ] || fail "run.json is not complete"
[ "$(json_field "$run_json" mode)" = lockstep ] || fail "mode $(json_field "$run_json" mode)"
"$BIN/hunav_expect" --run-dir "$WORK/forged" --scenario "$SCENARIO" >/dev/null || fail "hunav_expect cannot read run.json"
forged=$(sed -n -E 's/^forged ([0-9]+) messages/\1/p' "$WORK/forger.log")
[ "${forged:-0}" -gt 100 ] || fail "only ${forged:-0} messages were forged during the run"
python3 - "$run_json" <<'PY' || fail "drop counts"
import json, sys
r = json.load(open(sys.argv[1]))
print("dropped: evaluator %(dropped_messages)d, world %(world_dropped_messages)d, manager %(manager_dropped_messages)d, "
      "planner %(planner_dropped_messages)d" % r)
assert r["dropped_messages"] > 0 and r["world_dropped_messages"] > 0 and r["planner_dropped_messages"] > 0
assert all(0 <= r[k] <= 10**15 for k in ["dropped_messages", "world_dropped_messages", "planner_dropped_messages"])
PY
no_orphans
echo "a lockstep run with $forged forged messages: goal_reached, fingerprint $clean as the clean run"
