#!/usr/bin/env bash
# A malformed scenario: file:line: key: what, exit 2, before anything starts; nothing left running.
source "$(dirname "$0")/common.sh"
bad="$REPO/tests/integration/data/malformed.yaml"
for mode in inprocess lockstep; do
  rc=0
  "$RUN" --scenario "$bad" --mode "$mode" --out "$WORK/$mode" > "$WORK/out.txt" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || { cat "$WORK/out.txt"; fail "$mode: exit $rc, want 2"; }
  grep -q "malformed.yaml:4: robot.radius: must be > 0" "$WORK/out.txt" || { cat "$WORK/out.txt"; fail "$mode: message"; }
  [ ! -f "$WORK/$mode/states.csv" ] || fail "$mode: a run started"
done
for bin in hunav_run hunav_worldsim; do
  rc=0
  "$BIN/$bin" --scenario "$bad" > "$WORK/out.txt" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || fail "$bin: exit $rc, want 2"
  grep -q "malformed.yaml:4: robot.radius" "$WORK/out.txt" || fail "$bin: message"
done
rc=0
"$BIN/hunav_planner" --scenario "$bad" > "$WORK/out.txt" 2>&1 || rc=$?
[ "$rc" -eq 2 ] || fail "hunav_planner: exit $rc, want 2"
rc=0
"$RUN" --scenario "$REPO/tests/integration/data/does_not_exist.yaml" > "$WORK/out.txt" 2>&1 || rc=$?
[ "$rc" -eq 2 ] || fail "missing scenario: exit $rc, want 2"
# A sample rate out of range: exit 2 from hunav_run (directly and through the script) and from the
# evaluator, before anything starts.
for cmd in "$BIN/hunav_run --scenario $REPO/scenarios/passing.yaml --out $WORK/rate" \
           "$RUN --scenario $REPO/scenarios/passing.yaml --out $WORK/rate" \
           "$BIN/hunav_evaluator --out $WORK/rate --episodes 1"; do
  rc=0
  # shellcheck disable=SC2086 # $cmd holds a command and its arguments (no spaces in the paths)
  $cmd --sample-rate 0.0000001 > "$WORK/out.txt" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || { cat "$WORK/out.txt"; fail "${cmd%% *} --sample-rate 1e-7: exit $rc, want 2"; }
  grep -q "sample rate must be 0 (every tick) or between 1e-6 and 1e6 Hz" "$WORK/out.txt" || fail "${cmd%% *}: message"
  [ ! -f "$WORK/rate/states.csv" ] || fail "${cmd%% *}: a run started"
done
# Flags CLI11 lets through or that overflowed: NaN durations and rates, huge wall-clock limits.
for cmd in "$BIN/hunav_run --scenario $REPO/scenarios/passing.yaml --out $WORK/flags --duration nan" \
           "$BIN/hunav_run --scenario $REPO/scenarios/passing.yaml --out $WORK/flags --sample-rate nan" \
           "$BIN/hunav_worldsim --scenario $REPO/scenarios/passing.yaml --startup-limit 1e10" \
           "$BIN/hunav_worldsim --scenario $REPO/scenarios/passing.yaml --silence-limit 1e10"; do
  rc=0
  # shellcheck disable=SC2086 # $cmd holds a command and its arguments (no spaces in the paths)
  timeout 60 $cmd > "$WORK/out.txt" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || { cat "$WORK/out.txt"; fail "$cmd: exit $rc, want 2"; }
done
[ ! -f "$WORK/flags/states.csv" ] || fail "a run with a bad flag started"
# Issue 31: a map file that is a symlink loop or /proc/self/mem (exit 1 with a filesystem exception),
# "sim_time": 1e400 in a run.json (exit 1 without file:line), an empty --states (it started a live
# evaluator), a frame interval no data set has (it ran for minutes): each exit 2 naming the problem.
mkdir -p "$WORK/maps"
ln -s loop.yaml "$WORK/maps/loop.yaml"
for map in loop.yaml /proc/self/mem; do
  printf 'name: m\nmap:\n  map_server: %s\nrobot:\n  radius: 0.3\n  start: {x: 0, y: 0, yaw: 0}\n  goal: {x: 1, y: 0, radius: 0.3}\n' \
    "$map" >"$WORK/maps/scenario.yaml"
  rc=0
  timeout 60 "$BIN/hunav_run" --scenario "$WORK/maps/scenario.yaml" --out "$WORK/maps/out" >"$WORK/out.txt" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || { cat "$WORK/out.txt"; fail "map_server $map: exit $rc, want 2"; }
  want="scenario.yaml:3: map.map_server"
  [ "$map" = loop.yaml ] || want="/proc/self/mem: cannot read the file"
  grep -q "$want" "$WORK/out.txt" || { cat "$WORK/out.txt"; fail "map_server $map: message"; }
done
rc=0
"$BIN/hunav_run" --scenario /proc/self/mem >"$WORK/out.txt" 2>&1 || rc=$?
[ "$rc" -eq 2 ] || { cat "$WORK/out.txt"; fail "--scenario /proc/self/mem: exit $rc, want 2"; }
"$BIN/hunav_run" --scenario "$REPO/scenarios/passing.yaml" --duration 1 --out "$WORK/overflow" --quiet >/dev/null
sed -i -E 's/"sim_time": [^,]*/"sim_time": 1e400/' "$WORK/overflow/run.json"
for cmd in "$BIN/hunav_evaluator --states $WORK/overflow/states.csv --out $WORK/overflow_again" \
           "$BIN/hunav_report $WORK/overflow"; do
  rc=0
  # shellcheck disable=SC2086 # $cmd holds a command and its arguments (no spaces in the paths)
  $cmd >"$WORK/out.txt" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || { cat "$WORK/out.txt"; fail "${cmd%% *}: sim_time 1e400: exit $rc, want 2"; }
  grep -q "run.json:[0-9]*: sim_time: .*1e400" "$WORK/out.txt" || { cat "$WORK/out.txt"; fail "${cmd%% *}: 1e400: message"; }
done
for opt in --states --log --salvage; do
  rc=0
  extra=()
  [ "$opt" != --salvage ] || extra=(--reason x)
  out=(--out "$WORK/empty")
  [ "$opt" != --salvage ] || out=()
  timeout 60 "$BIN/hunav_evaluator" "$opt" '' "${extra[@]}" "${out[@]}" >"$WORK/out.txt" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || { cat "$WORK/out.txt"; fail "hunav_evaluator $opt '': exit $rc, want 2"; }
  ! grep -q -x ready "$WORK/out.txt" || fail "hunav_evaluator $opt '' started a live evaluator"
done
rc=0
timeout 60 "$BIN/hunav_realism" --data "$REPO/tests/data/eth_ucy" --out "$WORK/realism" --frame-interval 65536 \
  >"$WORK/out.txt" 2>&1 || rc=$?
[ "$rc" -eq 2 ] || { cat "$WORK/out.txt"; fail "hunav_realism --frame-interval 65536: exit $rc, want 2"; }
grep -q -- "--frame-interval" "$WORK/out.txt" || { cat "$WORK/out.txt"; fail "hunav_realism: message"; }
no_orphans
echo "bad input rejected with exit 2"
