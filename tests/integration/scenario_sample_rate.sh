#!/usr/bin/env bash
# A scenario's evaluation.sample_rate reaches the evaluator in one process and as separate processes
# (run_experiment.sh hands the scenario to hunav_evaluator), and --sample-rate overrides it.
source "$(dirname "$0")/common.sh"
same_number() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a + 0 == b + 0) }'; }
scenario="$WORK/passing_10hz.yaml"
{ cat "$REPO/scenarios/passing.yaml"; printf 'evaluation:\n  sample_rate: 10\n'; } > "$scenario"

run() {  # run NAME MODE [run_experiment options]: a 2 s episode into $WORK/NAME
  local name=$1 mode=$2
  shift 2
  "$RUN" --scenario "$scenario" --mode "$mode" --duration 2 --out "$WORK/$name" "$@" > "$WORK/$name.txt" 2>&1 \
    || { cat "$WORK/$name.txt"; cat "$WORK/$name"/logs/*.log || true; fail "$name: the run failed"; }
}
run inprocess inprocess
run lockstep lockstep
run every_tick inprocess --sample-rate 0

# 2 s at dt 0.01 s: the world states at t = 0.00 .. 2.00 s (201 ticks). At 10 Hz the grid from the
# first state keeps t = 0.0, 0.1, .., 2.0: 21 samples; each has a row for the robot and the 2 people.
for name in inprocess lockstep; do
  d="$WORK/$name"
  same_number "$(json_field "$d/run.json" sample_rate)" 10 || fail "$name: sample_rate $(json_field "$d/run.json" sample_rate)"
  [ "$(json_field "$d/run.json" recorded_ticks)" = 21 ] || fail "$name: $(json_field "$d/run.json" recorded_ticks) samples, not 21"
  rows=$(($(wc -l < "$d/states.csv") - 1))
  [ "$rows" = 63 ] || fail "$name: $rows rows in states.csv, not 21 x 3 = 63"
  check_layout "$d"
done
# The two modes evaluate the same samples: the same metrics and the same fingerprint.
cut -d, -f7- "$WORK/inprocess/metrics.csv" > "$WORK/a.csv"
cut -d, -f7- "$WORK/lockstep/metrics.csv" > "$WORK/b.csv"
cmp -s "$WORK/a.csv" "$WORK/b.csv" || { diff "$WORK/a.csv" "$WORK/b.csv" >&2 || true; fail "the modes' metrics differ"; }
[ "$(json_field "$WORK/inprocess/run.json" fingerprint)" = "$(json_field "$WORK/lockstep/run.json" fingerprint)" ] \
  || fail "the modes' fingerprints differ"

# --sample-rate 0 overrides the scenario: every tick.
d="$WORK/every_tick"
same_number "$(json_field "$d/run.json" sample_rate)" 0 || fail "every_tick: sample_rate $(json_field "$d/run.json" sample_rate)"
[ "$(json_field "$d/run.json" recorded_ticks)" = "$(json_field "$d/run.json" ticks)" ] || fail "every_tick: ticks not all recorded"
no_orphans
echo "10 Hz from the scenario in both modes, every tick with --sample-rate 0"
