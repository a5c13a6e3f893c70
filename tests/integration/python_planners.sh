#!/usr/bin/env bash
# The documented planners, end to end, as a user runs them (docs/planner_contract.md):
#   docs_lockstep, docs_realtime: the Python planner block of docs/planner_contract.md, saved as a file,
#     run by run_experiment.sh --planner-cmd in lockstep and in real time, to the goal of passing;
#   example_lockstep, example_realtime: the C++ example planner (planners/examples/), the same way;
#   map_<scenario>: python/examples/map_planner.py in lockstep, to the goal of passing, cafe,
#     warehouse or house, using the MAP it received; map_passing_realtime: the same in real time.
# Usage: python_planners.sh CASE
source "$(dirname "$0")/common.sh"
case_name=${1:?usage: python_planners.sh CASE}
py=/usr/bin/python3

# Runs run_experiment.sh and checks the episode reached its goal: run_to_goal NAME SCENARIO MODE CMD
run_to_goal() {
  local name=$1 scenario=$2 mode=$3 cmd=$4 status
  "$RUN" --scenario "$REPO/scenarios/$scenario.yaml" --mode "$mode" --planner "$name" --planner-cmd "$cmd" \
    --out "$WORK/$name" > "$WORK/$name.txt" 2>&1 || true
  status=$(json_field "$WORK/$name/run.json" status 2>/dev/null || echo "no run.json")
  if [ "$status" != goal_reached ]; then
    cat "$WORK/$name.txt"
    tail -n 40 "$WORK/$name"/logs/*.log || true
    fail "$name on $scenario ($mode): $status, not goal_reached"
  fi
  [ "$(json_field "$WORK/$name/run.json" planner)" = "$name" ] || fail "run.json planner is not '$name'"
  echo "$name on $scenario ($mode): goal_reached after $(json_field "$WORK/$name/run.json" sim_time) s"
  no_orphans
}

case $case_name in
  docs_lockstep | docs_realtime)
    # The block exactly as the documentation shows it.
    $py - "$REPO/docs/planner_contract.md" "$WORK/my_planner.py" <<'PY'
import re, sys
doc = open(sys.argv[1]).read()
block = re.search(r"<!-- python-planner:[^\n]*-->\n```python\n(.*?)```", doc, re.S)
if not block:
    sys.exit("no python-planner block in docs/planner_contract.md")
open(sys.argv[2], "w").write(block.group(1))
PY
    run_to_goal docs "passing" "${case_name#docs_}" "exec $py '$WORK/my_planner.py' --episodes 1"
    grep -q "planner_dropped_messages" "$WORK/docs/run.json" || fail "run.json lacks planner_dropped_messages"
    [ "$(json_field "$WORK/docs/run.json" planner_dropped_messages)" = 0 ] \
      || fail "the planner's announcements were not heard (planner_dropped_messages is not 0)"
    ;;
  example_lockstep | example_realtime)
    run_to_goal example "passing" "${case_name#example_}" "exec '$BIN/example_planner' \"\$LCM_DEFAULT_URL\" 1"
    ;;
  map_*)
    scenario=${case_name#map_}
    mode=lockstep
    case $scenario in *_realtime) scenario=${scenario%_realtime} mode=realtime ;; esac
    run_to_goal map "$scenario" "$mode" "exec $py '$REPO/python/examples/map_planner.py' --episodes 1"
    grep -q "map_planner: map of episode 1:" "$WORK/map/logs/planner.log" \
      || { cat "$WORK/map/logs/planner.log"; fail "the map planner never received the MAP"; }
    ;;
  *) fail "unknown case '$case_name'" ;;
esac
