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
no_orphans
echo "bad input rejected with exit 2"
