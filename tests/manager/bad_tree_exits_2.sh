#!/usr/bin/env bash
# A bad behavior_tree file (missing, malformed XML, unknown node) stops hunav_manager --scenario,
# hunav_run and run_experiment.sh (both modes) before anything starts: file:line: key: what on
# stderr, exit 2, no result written, nothing left running.
# shellcheck source=../integration/common.sh
source "$REPO/tests/integration/common.sh"

mkdir -p "$WORK/trees"
printf '<root BTCPP_format="4">\n<BehaviorTree ID="T">\n</root>\n' > "$WORK/trees/malformed.xml"
printf '<root BTCPP_format="4">\n<BehaviorTree ID="T">\n<Dance/>\n</BehaviorTree>\n</root>\n' \
  > "$WORK/trees/unknown.xml"

# scenario NAME TREE: a corridor with one person whose behavior_tree is TREE (relative to the file).
scenario() {
  cat > "$WORK/$1.yaml" <<YAML
name: $1
dt: 0.01
time_limit: 5.0
map:
  walls:
    - [[-2.0, -2.0], [18.0, -2.0]]
    - [[-2.0, 2.0], [18.0, 2.0]]
robot:
  radius: 0.3
  start: {x: 0.0, y: 0.0, yaw: 0.0}
  goal: {x: 15.0, y: 0.0, radius: 0.3}
people:
  hunav_loader:
    ros__parameters:
      agents: [walker]
      walker:
        id: 1
        behavior: 1
        behavior_tree: $2
        init_pose: {x: 13.0, y: 0.6, h: 3.14159}
        goals: [g1]
        g1: {x: 0.0, y: 0.6}
YAML
}
scenario missing trees/nowhere.xml
scenario malformed trees/malformed.xml
scenario unknown trees/unknown.xml
# The agent's behavior_tree key is on line 19: the error names it (not the agent's first key).
declare -A want=(
  [missing]="missing.yaml:19: walker.behavior_tree: $WORK/trees/nowhere.xml: cannot open behavior tree file"
  [malformed]="malformed.yaml:19: walker.behavior_tree: $WORK/trees/malformed.xml:"
  [unknown]="unknown.yaml:19: walker.behavior_tree: $WORK/trees/unknown.xml:3: unknown node 'Dance'"
)

expect_2() {  # expect_2 WHAT MESSAGE COMMAND...: exit 2 and MESSAGE in the output
  local what=$1 message=$2 rc=0
  shift 2
  "$@" > "$WORK/out.txt" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || { cat "$WORK/out.txt"; fail "$what: exit $rc, want 2"; }
  grep -qF -- "$message" "$WORK/out.txt" || { cat "$WORK/out.txt"; fail "$what: no '$message'"; }
}

for name in missing malformed unknown; do
  file="$WORK/$name.yaml"
  expect_2 "hunav_manager $name" "${want[$name]}" "$BIN/hunav_manager" --scenario "$file" --lcm-url memq://
  expect_2 "hunav_run $name" "${want[$name]}" "$BIN/hunav_run" --scenario "$file" --out "$WORK/run_$name"
  [ ! -e "$WORK/run_$name" ] || fail "hunav_run $name: wrote $WORK/run_$name"
done
expect_2 "hunav_run malformed (XML error)" "malformed.xml:" "$BIN/hunav_run" --scenario "$WORK/malformed.yaml" \
  --out "$WORK/run_malformed"
grep -q ": XML: " "$WORK/out.txt" || { cat "$WORK/out.txt"; fail "malformed: no XML error"; }

for mode in inprocess lockstep; do
  expect_2 "run_experiment $mode" "${want[unknown]}" "$RUN" --scenario "$WORK/unknown.yaml" --mode "$mode" \
    --out "$WORK/exp_$mode"
  [ ! -f "$WORK/exp_$mode/states.csv" ] || fail "run_experiment $mode: a run started"
done
no_orphans
echo "bad behavior trees rejected with exit 2 before the run"
