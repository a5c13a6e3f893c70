#!/usr/bin/env bash
# run_experiment.sh --record, in one process and as separate processes: the LCM log holds every
# message of the run (every world state, stamped with its simulation time), hunav_evaluator --log
# recomputes exactly the live metrics from it, and lcm-logplayer replays it on a bus in a private
# network namespace where a subscriber (hunav_record; lcm-spy for a user) receives the whole run again.
source "$(dirname "$0")/common.sh"
source "$(dirname "$0")/lcm_log.sh"

# same_metrics LIVE OFFLINE: every column of the last row of two metrics.csv files is equal, as text.
same_metrics() {
  python3 - "$1" "$2" <<'PY'
import csv, sys
live = list(csv.DictReader(open(sys.argv[1])))[-1]
offline = list(csv.DictReader(open(sys.argv[2])))[-1]
if list(live) != list(offline):
    sys.exit("the metric columns differ")
diff = [f"{k}: live {live[k]}, from the log {offline[k]}" for k in live if k != "experiment_tag" and live[k] != offline[k]]
if diff:
    sys.exit("metrics differ:\n  " + "\n  ".join(diff))
print(f"  {len(live) - 6} metrics equal")
PY
}

for mode in inprocess lockstep; do
  d="$WORK/$mode"
  "$RUN" --scenario "$REPO/scenarios/passing.yaml" --mode "$mode" --record --out "$d" >"$WORK/$mode.txt" 2>&1 ||
    { cat "$WORK/$mode.txt"; cat "$d"/logs/*.log 2>/dev/null; fail "$mode run with --record failed"; }
  [ -s "$d/run.lcmlog" ] || fail "$mode: no run.lcmlog"
  log_counts "$d/run.lcmlog" >"$WORK/$mode.counts" || fail "$mode: malformed log"
  ticks=$(json_field "$d/run.json" ticks)
  echo "$mode: $ticks ticks; log: $(paste -sd' ' "$WORK/$mode.counts")"
  [ "$(count_of "$WORK/$mode.counts" WORLD_STATE)" = "$ticks" ] || fail "$mode: the log does not hold every world state"
  [ "$(count_of "$WORK/$mode.counts" EPISODE_EVENT)" = 2 ] || fail "$mode: the log misses the episode's START or END"
  for channel in STEP_REQUEST STEP_REPLY ROBOT_OBSERVATION ROBOT_COMMAND NAV_GOAL; do
    [ "$(count_of "$WORK/$mode.counts" "$channel")" -gt 0 ] || fail "$mode: no $channel in the log"
  done
  # Stamped with simulation time: the last event is at the end of the episode (step replies carry
  # the time of the next state, one dt later at most).
  sim_us=$(python3 -c "import sys; print(round(float(sys.argv[1]) * 1e6))" "$(json_field "$d/run.json" sim_time)")
  last=$(count_of "$WORK/$mode.counts" LAST_STAMP)
  { [ "$last" -ge "$sim_us" ] && [ "$last" -le $((sim_us + 10000)) ]; } ||
    fail "$mode: last event stamped $last us, the episode ended at $sim_us us of simulation time"
  "$BIN/hunav_evaluator" --log "$d/run.lcmlog" --out "$WORK/$mode-offline" >"$WORK/$mode-offline.txt" 2>&1 ||
    { cat "$WORK/$mode-offline.txt"; fail "$mode: hunav_evaluator --log failed"; }
  same_metrics "$d/metrics.csv" "$WORK/$mode-offline/metrics.csv" || fail "$mode: the metrics from the log differ"
  [ "$(json_field "$WORK/$mode-offline/run.json" recorded_ticks)" = "$ticks" ] || fail "$mode: ticks lost in the log"
done
no_orphans

# Replay the separate-process run's log in a private network namespace, recorded by a subscriber.
if [ "$(id -u)" -eq 0 ]; then netns=(unshare --net); else netns=(unshare --map-root-user --net); fi
"${netns[@]}" bash -s "$BIN" "$WORK" <<'SH' >"$WORK/replay.txt" 2>&1 || { cat "$WORK/replay.txt"; fail "replay failed"; }
set -euo pipefail
BIN=$1 WORK=$2
ip link set lo up
ip route add 224.0.0.0/4 dev lo
url='udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304'
"$BIN/hunav_record" --out "$WORK/replayed.lcmlog" --lcm-url "$url" >"$WORK/recorder.txt" 2>&1 &
recorder=$!
# (This shell has none of common.sh's helpers.) Ready within 60 s, however loaded the machine.
for _ in $(seq 600); do grep -qx ready "$WORK/recorder.txt" && break; sleep 0.1; done
grep -qx ready "$WORK/recorder.txt" || { echo "hunav_record did not start"; cat "$WORK/recorder.txt"; exit 1; }
timeout 120 lcm-logplayer --speed 20 --lcm-url "$url" "$WORK/lockstep/run.lcmlog"
kill -TERM "$recorder"
wait "$recorder"
cat "$WORK/recorder.txt"
SH
log_counts "$WORK/replayed.lcmlog" >"$WORK/replayed.counts" || fail "malformed replayed log"
echo "replayed: $(paste -sd' ' "$WORK/replayed.counts")"
for channel in WORLD_STATE EPISODE_EVENT STEP_REQUEST STEP_REPLY ROBOT_OBSERVATION ROBOT_COMMAND NAV_GOAL LIVE_METRICS; do
  [ "$(count_of "$WORK/replayed.counts" "$channel")" = "$(count_of "$WORK/lockstep.counts" "$channel")" ] ||
    fail "the replay delivered $(count_of "$WORK/replayed.counts" "$channel") $channel messages of $(count_of "$WORK/lockstep.counts" "$channel")"
done
"$BIN/hunav_evaluator" --log "$WORK/replayed.lcmlog" --out "$WORK/replayed-offline" >"$WORK/replayed-offline.txt" 2>&1 ||
  { cat "$WORK/replayed-offline.txt"; fail "hunav_evaluator --log failed on the replayed log"; }
same_metrics "$WORK/lockstep/metrics.csv" "$WORK/replayed-offline/metrics.csv" || fail "the replayed run's metrics differ"
no_orphans
if [ -n "$(our_pid record)" ]; then fail "hunav_record left running"; fi
echo "recorded in both modes, recomputed, and replayed: same metrics"
