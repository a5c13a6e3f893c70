#!/usr/bin/env bash
# The taxonomy scenarios built from HuNavSim 2.0's nodes (overtaking, approaching, following,
# group_conversation) with dwb, scl and sfw, in one process and as separate processes in lockstep:
# every run ends and both modes give the same fingerprint. In lockstep the manager also publishes
# PEOPLE_SOCIAL (its trees speak and converse): recorded, and the world states are unchanged by it.
source "$(dirname "$0")/common.sh"
for scenario in overtaking approaching following group_conversation; do
  for planner in dwb scl sfw; do
    tag="${scenario}_${planner}"
    "$RUN" --scenario "$REPO/scenarios/$scenario.yaml" --planner "$planner" --mode inprocess \
      --out "$WORK/$tag/inprocess" > "$WORK/$tag.ip.txt" 2>&1 \
      || { cat "$WORK/$tag.ip.txt"; fail "$tag: inprocess run failed"; }
    "$RUN" --scenario "$REPO/scenarios/$scenario.yaml" --planner "$planner" --mode lockstep \
      --out "$WORK/$tag/lockstep" > "$WORK/$tag.ls.txt" 2>&1 \
      || { cat "$WORK/$tag.ls.txt"; cat "$WORK/$tag"/lockstep/logs/*.log; fail "$tag: lockstep run failed"; }
    for mode in inprocess lockstep; do
      d="$WORK/$tag/$mode"
      [ "$(json_field "$d/run.json" status)" = goal_reached ] || fail "$tag $mode: status $(json_field "$d/run.json" status)"
      [ "$(json_field "$d/run.json" ticks)" = "$(json_field "$d/run.json" recorded_ticks)" ] || fail "$tag $mode: ticks lost"
    done
    a=$(json_field "$WORK/$tag/inprocess/run.json" fingerprint)
    b=$(json_field "$WORK/$tag/lockstep/run.json" fingerprint)
    [ "$a" = "$b" ] || fail "$tag: fingerprints differ: inprocess $a, lockstep $b"
    echo "$tag: same fingerprint $a in both modes"
  done
done
no_orphans
