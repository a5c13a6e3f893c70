#!/usr/bin/env bash
# The people models behind the same behavior trees (docs/people_models.md): the combined scenario
# (regular, surprised, scared, curious, threatening and impassive people) with every person on ORCA,
# then on TTC, in one process and as separate processes in lockstep (run_experiment.sh
# --people-model, passed to hunav_manager and hunav_evaluator): the same fingerprint in both modes,
# the model recorded in run.json and metrics.csv, and a fingerprint of its own (another model moves
# the people otherwise). A parameter file works like a name; a bad name is exit 2 naming it.
source "$(dirname "$0")/common.sh"
scenario="$REPO/scenarios/combined.yaml"
"$RUN" --scenario "$scenario" --mode inprocess --duration 20 --out "$WORK/sfm" > "$WORK/sfm.txt" 2>&1 ||
  { cat "$WORK/sfm.txt"; fail "sfm run failed"; }
default_print=$(json_field "$WORK/sfm/run.json" fingerprint)
[ "$(json_field "$WORK/sfm/run.json" people_model)" = sfm ] || fail "the default run does not record people_model sfm"
for model in orca ttc; do
  for mode in inprocess lockstep; do
    d="$WORK/$model-$mode"
    "$RUN" --scenario "$scenario" --mode "$mode" --duration 20 --people-model "$model" --out "$d" > "$d.txt" 2>&1 ||
      { cat "$d.txt"; cat "$d"/logs/*.log 2>/dev/null; fail "$model $mode run failed"; }
    [ "$(json_field "$d/run.json" people_model)" = "$model" ] || fail "$model $mode: run.json people_model $(json_field "$d/run.json" people_model)"
    [ "$(json_field "$d/run.json" ticks)" = "$(json_field "$d/run.json" recorded_ticks)" ] || fail "$model $mode: ticks lost"
    head -1 "$d/metrics.csv" | grep -q '^experiment_tag,run_id,scenario,planner,seed,profile,people_model,' ||
      fail "$model $mode: metrics.csv has no people_model column"
    awk -F, -v m="$model" 'NR == 2 && $7 != m { exit 1 }' "$d/metrics.csv" || fail "$model $mode: metrics.csv does not say $model"
    check_layout "$d"
  done
  a=$(json_field "$WORK/$model-inprocess/run.json" fingerprint)
  b=$(json_field "$WORK/$model-lockstep/run.json" fingerprint)
  [ "$a" = "$b" ] || fail "$model: fingerprints differ: inprocess $a, lockstep $b"
  [ "$a" != "$default_print" ] || fail "$model: the same fingerprint as HuNavSim's model"
  echo "$model: same fingerprint $a in both modes"
done
# A parameter file of the same model and parameters moves the people the same way.
printf 'model: orca\n' > "$WORK/my_orca.yaml"
"$RUN" --scenario "$scenario" --mode inprocess --duration 20 --people-model "$WORK/my_orca.yaml" --out "$WORK/file" \
  > "$WORK/file.txt" 2>&1 || { cat "$WORK/file.txt"; fail "run with a parameter file failed"; }
[ "$(json_field "$WORK/file/run.json" fingerprint)" = "$(json_field "$WORK/orca-inprocess/run.json" fingerprint)" ] ||
  fail "the file 'model: orca' moves people otherwise than the name orca"
# A bad name: exit 2, named, nothing run.
rc=0
"$RUN" --scenario "$scenario" --mode inprocess --people-model walker --out "$WORK/bad" > "$WORK/bad.txt" 2>&1 || rc=$?
[ "$rc" -eq 2 ] || { cat "$WORK/bad.txt"; fail "a bad --people-model exits $rc, not 2"; }
grep -q -- "--people-model" "$WORK/bad.txt" || { cat "$WORK/bad.txt"; fail "the error does not name --people-model"; }
no_orphans
