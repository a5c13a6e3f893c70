#!/usr/bin/env bash
# The passing scenario in one process and as separate processes in a private network namespace:
# both reach the goal with the same fingerprint, and every tick is recorded; both name the run
# <scenario>_<planner>_s<seed> and print the same metrics table (units, 6 significant digits).
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
# One run id and one console format in every mode (lockstep once had <id>_<date>-<pid> and a raw table).
for mode in inprocess lockstep; do
  id=$(json_field "$WORK/$mode/run.json" run_id)
  [ "$id" = passing_dwb_s1 ] || fail "$mode: run_id $id, expected passing_dwb_s1"
done
table() {  # the metric table a run printed: its header and the "name  value[  unit]" lines after it
  awk '/^metric +value +unit$/ { t = 1; print; next } t && /^[A-Za-z0-9_]+  +[^ ]/ { print; next } t { exit }' "$1"
}
table "$WORK/ip.txt" > "$WORK/ip.table"
table "$WORK/ls.txt" > "$WORK/ls.table"
[ "$(wc -l < "$WORK/ip.table")" -gt 20 ] || { cat "$WORK/ip.txt"; fail "inprocess printed no metrics table"; }
grep -Eq '^time_to_reach_goal +[0-9.]+  s$' "$WORK/ip.table" || fail "the table has no unit for time_to_reach_goal"
diff "$WORK/ip.table" "$WORK/ls.table" >&2 || fail "lockstep prints another metrics table than inprocess"
grep -q "^run passing_dwb_s1: goal_reached " "$WORK/ls.txt" || { cat "$WORK/ls.txt"; fail "lockstep prints no run line"; }
no_orphans
echo "same fingerprint $a in both modes"
