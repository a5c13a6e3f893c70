#!/usr/bin/env bash
# --counterfactual in one process and as separate processes in lockstep (the evaluator process runs
# the robot-free episode after the END): the same counterfactual.csv byte for byte, the same
# counterfactual_* values, and the files of the run itself as without --counterfactual.
source "$(dirname "$0")/common.sh"
scenario="$REPO/scenarios/crossing.yaml"
for mode in inprocess lockstep; do
  "$RUN" --scenario "$scenario" --mode "$mode" --counterfactual --out "$WORK/$mode" > "$WORK/$mode.txt" 2>&1 \
    || { cat "$WORK/$mode.txt"; cat "$WORK/$mode"/logs/*.log 2>/dev/null; fail "$mode run failed"; }
  [ -s "$WORK/$mode/counterfactual.csv" ] || fail "$mode: no counterfactual.csv"
  check_layout "$WORK/$mode"
done
"$RUN" --scenario "$scenario" --mode inprocess --out "$WORK/plain" > "$WORK/plain.txt" 2>&1 \
  || { cat "$WORK/plain.txt"; fail "plain run failed"; }
cmp "$WORK/inprocess/counterfactual.csv" "$WORK/lockstep/counterfactual.csv" \
  || fail "counterfactual.csv differs between inprocess and lockstep"
for m in counterfactual_people_affected counterfactual_delay counterfactual_goals_missed counterfactual_path_added \
  counterfactual_mean_deviation counterfactual_max_deviation counterfactual_extra_effort; do
  a=$(metric "$WORK/inprocess/metrics.csv" "$m")
  b=$(metric "$WORK/lockstep/metrics.csv" "$m")
  [ -n "$a" ] || fail "inprocess: no $m in metrics.csv"
  [ "$a" = "$b" ] || fail "$m: inprocess $a, lockstep $b"
done
[ "$(metric "$WORK/inprocess/metrics.csv" counterfactual_people_affected)" != 0 ] \
  || fail "the robot crossing the group should disturb someone"
cmp "$WORK/plain/states.csv" "$WORK/inprocess/states.csv" || fail "--counterfactual changed states.csv"
[ ! -e "$WORK/plain/counterfactual.csv" ] || fail "a run without --counterfactual wrote counterfactual.csv"
! head -n 1 "$WORK/plain/metrics.csv" | grep -q counterfactual || fail "a run without --counterfactual has its columns"
no_orphans
echo "counterfactual.csv identical in both modes; $(metric "$WORK/inprocess/metrics.csv" counterfactual_people_affected) people affected"
