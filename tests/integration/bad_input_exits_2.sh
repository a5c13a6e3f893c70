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
no_orphans
echo "bad input rejected with exit 2"
