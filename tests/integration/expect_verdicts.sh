#!/usr/bin/env bash
# Scenario expectations (expect:) against a deliberately bad planner: `none` (the robot stands still)
# on the CI suite's passing scenario must fail exactly `status` and `completed` when the run is cut at
# 8 s (the people, 13 m away at 0.9 m/s, are still about 6 m off: every distance condition passes),
# in one process and as separate processes (hunav_expect judges run.json), exit 3 both; a batch writes
# junit.xml with those failures, dwb's passes, and no test case for a scenario without expect:; an
# unknown metric name is a file:line: key error, exit 2.
source "$(dirname "$0")/common.sh"
suite="$REPO/scenarios/suites/passing.yaml"
py=/usr/bin/python3

for mode in inprocess lockstep; do
  d="$WORK/$mode"
  rc=0
  "$RUN" --scenario "$suite" --planner none --mode "$mode" --duration 8 --out "$d" > "$WORK/$mode.txt" 2>&1 || rc=$?
  [ "$rc" -eq 3 ] || { cat "$WORK/$mode.txt"; fail "$mode: exit $rc, expected 3 (expectations failed)"; }
  [ "$(json_field "$d/run.json" status)" = time_limit ] || fail "$mode: status $(json_field "$d/run.json" status)"
  # The printed verdicts: value, condition, PASS/FAIL per condition.
  grep -Eq '^expect status +== goal_reached +value time_limit +FAIL$' "$WORK/$mode.txt" || { cat "$WORK/$mode.txt"; fail "$mode: no status FAIL line"; }
  grep -Eq '^expect completed +== true +value false +FAIL$' "$WORK/$mode.txt" || fail "$mode: no completed FAIL line"
  grep -Eq '^expect robot_on_person_collision +== 0 +value 0 +PASS$' "$WORK/$mode.txt" || fail "$mode: no collision PASS line"
  grep -Eq '^expect time_to_reach_goal +<= 35 +value 8 +PASS$' "$WORK/$mode.txt" || fail "$mode: no time_to_reach_goal PASS line"
  grep -q '^expectations: 5 of 7 passed, 2 FAILED$' "$WORK/$mode.txt" || fail "$mode: no count line"
  # expect.json: the same verdicts for batch tools.
  $py - "$d/expect.json" <<'PY' || fail "$mode: expect.json"
import json, sys
j = json.load(open(sys.argv[1]))
failed = [c["metric"] for c in j["conditions"] if not c["pass"]]
assert j["passed"] is False and j["status"] == "time_limit", j
assert failed == ["status", "completed"], failed
assert len(j["conditions"]) == 7, j
PY
done
cmp <(grep -v run_id "$WORK/inprocess/expect.json") <(grep -v run_id "$WORK/lockstep/expect.json") ||
  fail "the modes' verdicts differ"

# A bad expect: block stops the run before it starts (unknown name: at its line, key expect.<name>).
bad="$WORK/bad_expect.yaml"
{ cat "$REPO/scenarios/passing.yaml"; printf 'expect:\n  completed: true\n  minimum_distance_to_peeple: {min: 0.5}\n'; } > "$bad"
line=$(($(wc -l < "$REPO/scenarios/passing.yaml") + 3))
rc=0
"$BIN/hunav_run" --scenario "$bad" --planner none --out "$WORK/bad" > "$WORK/bad.txt" 2>&1 || rc=$?
[ "$rc" -eq 2 ] || { cat "$WORK/bad.txt"; fail "unknown metric: exit $rc, expected 2"; }
grep -q "^$bad:$line: expect.minimum_distance_to_peeple: unknown metric" "$WORK/bad.txt" || { cat "$WORK/bad.txt"; fail "no file:line: key error"; }
[ ! -e "$WORK/bad/run.json" ] || fail "a run started with a bad expect: block"

# A batch: the suite's passing with none (fails) and dwb (passes), and a copy without expect: (no test case).
plain="$WORK/plain.yaml"
cp "$REPO/scenarios/passing.yaml" "$plain"
rc=0
"$REPO/launch_scripts/run_batch.sh" --scenarios "$suite,$plain" --planners none,dwb --seeds 1 --duration 30 \
  --jobs 2 --out "$WORK/batch" > "$WORK/batch.txt" 2>&1 || rc=$?
[ "$rc" -eq 3 ] || { cat "$WORK/batch.txt"; fail "batch: exit $rc, expected 3"; }
grep -q 'passing none seed 1: time_limit, expectations FAILED' "$WORK/batch.txt" || { cat "$WORK/batch.txt"; fail "batch: no FAILED line"; }
for run in passing__none__seed1 passing__dwb__seed1 plain__none__seed1 plain__dwb__seed1; do
  [ -s "$WORK/batch/runs/$run/run.json" ] || fail "batch: $run did not finish"
done
[ ! -e "$WORK/batch/runs/plain__dwb__seed1/expect.json" ] || fail "expect.json for a scenario without expect:"
$py - "$WORK/batch/junit.xml" "$WORK/batch/runs/passing__none__seed1/expect.json" <<'PY' || fail "junit.xml"
import json, sys
import xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
cases = root.findall("./testsuite/testcase")
assert root.tag == "testsuites" and root.get("tests") == "14" and root.get("errors") == "0", ET.tostring(root)
# 7 conditions x (none, dwb) on the suite's passing; none on the plain copy.
assert sorted({c.get("classname") for c in cases}) == ["passing.dwb", "passing.none"], [c.get("classname") for c in cases]
failed = {c.get("name"): c.find("failure").get("message") for c in cases if c.find("failure") is not None}
# The standing robot's failures are those of its expect.json, status and completed among them; dwb
# reaches its goal (~26 s).
verdicts = json.load(open(sys.argv[2]))["conditions"]
want = {f"seed 1: {v['metric']} {v['condition']}": f"{v['metric']} = {v['value']}, expected {v['condition']}"
        for v in verdicts if not v["pass"]}
assert failed == want, (failed, want)
assert failed["seed 1: status == goal_reached"] == "status = time_limit, expected == goal_reached", failed
assert failed["seed 1: completed == true"] == "completed = false, expected == true", failed
assert all(c.get("classname") == "passing.none" for c in cases if c.find("failure") is not None)
assert root.get("failures") == str(len(want))
PY
no_orphans
echo "bad planner: status and completed FAIL in both modes, exit 3; junit.xml as expected"
