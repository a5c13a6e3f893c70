#!/usr/bin/env bash
# Values every process's message checks would reject are load errors: file:line: key, exit 2, before
# anything starts (before: the run started, then aborted with "manager did not answer", exit 1).
# And bad input that used to exit 1 without a line: a map whose image is a folder, a states.csv row
# with a person of radius 1e6 m ("per-tick value ... is not finite", nothing written).
source "$(dirname "$0")/common.sh"

# HuNavSim's agents file (tests/data/hunav_files, MIT) with agent1's v1 `behavior: 4` (line 14)
# replaced by a v1.5 custom mapping holding 1e6 (the key on line 17).
hunav_agents() {  # hunav_agents KEY VALUE > FILE
  python3 - "$REPO/tests/data/hunav_files/agents.yaml" "$1" "$2" <<'EOF'
import sys
text = open(sys.argv[1]).read()
old = "      behavior: 4\n"
assert old in text
print(text.replace(old, "      behavior:\n        type: 4\n        configuration: custom\n        %s: %s\n"
                   % (sys.argv[2], sys.argv[3]), 1), end="")
EOF
}
scenario() {  # scenario PEOPLE_FILE [TREE]: an open square around HuNavSim's cafe agents
  cat <<EOF
name: bounds
time_limit: 2.0
map:
  walls: [[[-20, -20], [20, -20], [20, 20], [-20, 20], [-20, -20]]]
robot:
  start: {x: 0.0, y: 0.0, yaw: 0.0}
  goal: {x: 5.0, y: 0.0, radius: 0.3}
people: $1
EOF
}
expect_2() {  # expect_2 WHAT PATTERN CMD...: exit 2 and PATTERN on stderr/stdout
  local what=$1 pattern=$2 rc=0
  shift 2
  timeout 120 "$@" > "$WORK/out.txt" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || { cat "$WORK/out.txt"; fail "$what: exit $rc, want 2"; }
  grep -qF -- "$pattern" "$WORK/out.txt" || { cat "$WORK/out.txt"; fail "$what: no '$pattern'"; }
}

for key in dist goal_force_factor duration; do
  hunav_agents "$key" 1e7 > "$WORK/agents_$key.yaml"
  scenario "agents_$key.yaml" > "$WORK/bounds_$key.yaml"
  want="$WORK/agents_$key.yaml:17: hunav_loader.ros__parameters.agent1.behavior.$key: must be in ["
  expect_2 "hunav_run $key" "$want" "$BIN/hunav_run" --scenario "$WORK/bounds_$key.yaml" --out "$WORK/run_$key"
  expect_2 "hunav_worldsim $key" "$want" "$BIN/hunav_worldsim" --scenario "$WORK/bounds_$key.yaml"
  expect_2 "hunav_manager $key" "$want" "$BIN/hunav_manager" --scenario "$WORK/bounds_$key.yaml" --lcm-url memq://
  [ ! -e "$WORK/run_$key/states.csv" ] || fail "$key: a run started"
done
# The same file at the bound loads and runs to its end in process.
hunav_agents dist 1e5 > "$WORK/agents_ok.yaml"
scenario agents_ok.yaml > "$WORK/bounds_ok.yaml"
rc=0
"$BIN/hunav_run" --scenario "$WORK/bounds_ok.yaml" --planner none --out "$WORK/run_ok" > "$WORK/out.txt" 2>&1 || rc=$?
[ "$rc" -eq 0 ] || { cat "$WORK/out.txt"; fail "dist 1e5: exit $rc, want 0"; }
[ "$(json_field "$WORK/run_ok/run.json" status)" = time_limit ] || fail "dist 1e5: not time_limit"

# A tree port beyond the bound: the scenario's tree file is checked at load.
mkdir -p "$WORK/trees"
cat > "$WORK/trees/fast.xml" <<'EOF'
<root BTCPP_format="4">
  <BehaviorTree ID="Fast">
    <ThreateningNav speed="1e10"/>
  </BehaviorTree>
</root>
EOF
python3 - "$REPO/tests/data/hunav_files/agents.yaml" > "$WORK/agents_tree.yaml" <<'EOF'
import sys
text = open(sys.argv[1]).read()
print(text.replace("      behavior: 4\n", "      behavior: 4\n      behavior_tree: trees/fast.xml\n", 1), end="")
EOF
scenario agents_tree.yaml > "$WORK/bounds_tree.yaml"
want="$WORK/trees/fast.xml:3: ThreateningNav: port speed: '1e10' is outside [-1e6, 1e6]"
expect_2 "hunav_run tree port" "$want" "$BIN/hunav_run" --scenario "$WORK/bounds_tree.yaml" --out "$WORK/run_tree"
expect_2 "hunav_manager tree port" "$want" "$BIN/hunav_manager" --scenario "$WORK/bounds_tree.yaml" --lcm-url memq://

# A map whose image is a folder: the map yaml's image line (before: exit 1, "basic_filebuf::underflow").
mkdir -p "$WORK/map/folder.pgm"
printf 'image: folder.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\n' > "$WORK/map/map.yaml"
printf 'name: folder_map\nmap:\n  map_server: map/map.yaml\nrobot:\n  start: {x: -1.0, y: -1.0}\n' > "$WORK/folder_map.yaml"
expect_2 "map image folder" "$WORK/map/map.yaml:1: image: " \
  "$BIN/hunav_run" --scenario "$WORK/folder_map.yaml" --out "$WORK/run_map"
grep -q "folder.pgm: not a regular file" "$WORK/out.txt" || { cat "$WORK/out.txt"; fail "map image folder: message"; }

# An empty scenario and a list: file:1: (before: no line).
: > "$WORK/empty.yaml"
expect_2 "empty scenario" "$WORK/empty.yaml:1: expected a mapping at the top level" \
  "$BIN/hunav_run" --scenario "$WORK/empty.yaml" --out "$WORK/run_empty"

# A recorded run, then its states.csv with one person's radius 1e6 m: file:line: radius, exit 2,
# and nothing of the output folder lost (before: exit 1 "per-tick value ... is not finite").
"$BIN/hunav_run" --scenario "$REPO/scenarios/passing.yaml" --duration 1 --out "$WORK/rec" > /dev/null 2>&1 ||
  fail "the recorded run failed"
mkdir -p "$WORK/src"
cp "$WORK/rec/run.json" "$WORK/src/"
python3 - "$WORK/rec/states.csv" > "$WORK/src/states.csv" <<'EOF'
import sys
lines = open(sys.argv[1]).read().splitlines()
cols = lines[0].split(",")
for i, line in enumerate(lines):
    f = line.split(",")
    if i == 20 and f[1] == "agent":
        f[cols.index("radius")] = "1e6"
    elif i == 20:
        sys.exit("row 20 is not an agent row")
    print(",".join(f))
EOF
mkdir -p "$WORK/offline"
echo keep > "$WORK/offline/metrics.csv"
expect_2 "states.csv radius 1e6" "$WORK/src/states.csv:21: radius: must be in [0, 100] m" \
  "$BIN/hunav_evaluator" --states "$WORK/src/states.csv" --out "$WORK/offline"
[ "$(cat "$WORK/offline/metrics.csv")" = keep ] || fail "the output folder's metrics.csv changed"
no_orphans
echo "bounds checked at load: exit 2 with file:line: key"
