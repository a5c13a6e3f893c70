#!/usr/bin/env bash
# The passing scenario in one process and as separate processes in a private network namespace:
# both reach the goal with the same fingerprint, and every tick is recorded.
source "$(dirname "$0")/common.sh"
"$RUN" --scenario "$REPO/scenarios/passing.yaml" --mode inprocess --out "$WORK/inprocess" > "$WORK/ip.txt" 2>&1 \
  || { cat "$WORK/ip.txt"; fail "inprocess run failed"; }
"$RUN" --scenario "$REPO/scenarios/passing.yaml" --mode lockstep --out "$WORK/lockstep" > "$WORK/ls.txt" 2>&1 \
  || { cat "$WORK/ls.txt"; cat "$WORK"/lockstep/logs/*.log; fail "lockstep run failed"; }
for mode in inprocess lockstep; do
  d="$WORK/$mode"
  [ "$(json_field "$d/run.json" status)" = goal_reached ] || fail "$mode: status $(json_field "$d/run.json" status)"
  [ "$(metric "$d/metrics.csv" completed)" = true ] || fail "$mode: completed is not true"
  [ "$(json_field "$d/run.json" ticks)" = "$(json_field "$d/run.json" recorded_ticks)" ] || fail "$mode: ticks lost"
  check_layout "$d"
done
a=$(json_field "$WORK/inprocess/run.json" fingerprint)
b=$(json_field "$WORK/lockstep/run.json" fingerprint)
[ "$a" = "$b" ] || fail "fingerprints differ: inprocess $a, lockstep $b"
grep -q "$a" "$WORK/ip.txt" || fail "the run does not print its fingerprint"
no_orphans
echo "same fingerprint $a in both modes"
