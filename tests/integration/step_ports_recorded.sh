#!/usr/bin/env bash
# The step channels on ports of their own (channel_ports=1, run_experiment.sh's default in its
# namespace) change nothing but speed, and --record still holds them:
#  1. a lockstep run with --record has the in-process run's fingerprint, and its log holds one
#     STEP_REQUEST and one STEP_REPLY per step (no resends in a healthy run) beside every world state;
#  2. on a bus with channel_ports=1 (--shared-bus, in a namespace made by this test), a plain LCM
#     subscriber on the URL's port hears the planner's channels and the world states but not the step
#     channels, which the run's recorder has.
source "$(dirname "$0")/common.sh"
source "$(dirname "$0")/lcm_log.sh"

"$RUN" --scenario "$REPO/scenarios/passing.yaml" --mode inprocess --out "$WORK/inprocess" >"$WORK/ip.txt" 2>&1 ||
  { cat "$WORK/ip.txt"; fail "inprocess run failed"; }
"$RUN" --scenario "$REPO/scenarios/passing.yaml" --mode lockstep --record --out "$WORK/lockstep" >"$WORK/ls.txt" 2>&1 ||
  { cat "$WORK/ls.txt"; cat "$WORK"/lockstep/logs/*.log; fail "lockstep run with --record failed"; }
grep -q "STEP_REQUEST and STEP_REPLY on ports of their own" "$WORK/ls.txt" ||
  { cat "$WORK/ls.txt"; fail "the lockstep run does not use channel ports"; }
a=$(json_field "$WORK/inprocess/run.json" fingerprint)
b=$(json_field "$WORK/lockstep/run.json" fingerprint)
[ "$a" = "$b" ] || fail "fingerprints differ: inprocess $a, lockstep with channel ports $b"

# check_step_log COUNTS RUN_JSON WORLD_LOG LABEL: every world state, one request and reply per step.
check_step_log() {
  local counts=$1 ticks steps resends
  ticks=$(json_field "$2" ticks)
  # "resends so far" in the world's summary line: a resent request is recorded twice.
  resends=$(sed -n -E 's/.* ([0-9]+) resends so far.*/\1/p' "$3" | tail -n 1)
  [ -n "$resends" ] || fail "$4: no summary line in $3"
  echo "$4: $ticks ticks, $resends resends; log: $(paste -sd' ' "$counts")"
  [ "$(count_of "$counts" WORLD_STATE)" = "$ticks" ] || fail "$4: $(count_of "$counts" WORLD_STATE) world states of $ticks"
  # Tick 0 is the initial state; each later state follows one step exchange.
  steps=$((ticks - 1 + resends))
  for channel in STEP_REQUEST STEP_REPLY; do
    [ "$(count_of "$counts" "$channel")" = "$steps" ] ||
      fail "$4: $(count_of "$counts" "$channel") $channel messages in the log, expected $steps (ticks - 1 + resends)"
  done
  for channel in ROBOT_OBSERVATION ROBOT_COMMAND; do
    [ "$(count_of "$counts" "$channel")" -gt 0 ] || fail "$4: no $channel in the log"
  done
}
log_counts "$WORK/lockstep/run.lcmlog" >"$WORK/lockstep.counts" || fail "malformed log"
check_step_log "$WORK/lockstep.counts" "$WORK/lockstep/run.json" "$WORK/lockstep/logs/worldsim.log" lockstep
no_orphans

# 2. The same with --shared-bus and a plain listener on the URL's port.
if [ "$(id -u)" -eq 0 ]; then netns=(unshare --net); else netns=(unshare --map-root-user --net); fi
"${netns[@]}" bash -s "$RUN" "$REPO" "$BIN" "$WORK" <<'SH' >"$WORK/shared.txt" 2>&1 || { cat "$WORK/shared.txt"; fail "shared-bus run failed"; }
set -euo pipefail
RUN=$1 REPO=$2 BIN=$3 WORK=$4
ip link set lo up
ip route add 224.0.0.0/4 dev lo
plain='udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304'
"$BIN/hunav_record" --out "$WORK/plain.lcmlog" --lcm-url "$plain" >"$WORK/plain_recorder.txt" 2>&1 &
recorder=$!
# (This shell has none of common.sh's helpers.) Ready within 60 s, however loaded the machine.
for _ in $(seq 600); do grep -qx ready "$WORK/plain_recorder.txt" && break; sleep 0.1; done
grep -qx ready "$WORK/plain_recorder.txt" || { echo "hunav_record did not start"; cat "$WORK/plain_recorder.txt"; exit 1; }
"$RUN" --scenario "$REPO/scenarios/passing.yaml" --mode lockstep --record --out "$WORK/shared" \
  --shared-bus "$plain&channel_ports=1" || { cat "$WORK"/shared/logs/*.log; exit 1; }
kill -TERM "$recorder"
wait "$recorder"
SH
c=$(json_field "$WORK/shared/run.json" fingerprint)
[ "$c" = "$a" ] || fail "fingerprints differ: inprocess $a, shared bus with channel ports $c"
log_counts "$WORK/shared/run.lcmlog" >"$WORK/shared.counts" || fail "malformed log of the shared-bus run"
check_step_log "$WORK/shared.counts" "$WORK/shared/run.json" "$WORK/shared/logs/worldsim.log" shared-bus
log_counts "$WORK/plain.lcmlog" >"$WORK/plain.counts" || fail "malformed log of the plain listener"
echo "plain listener on the URL's port: $(paste -sd' ' "$WORK/plain.counts")"
for channel in STEP_REQUEST STEP_REPLY; do
  [ -z "$(count_of "$WORK/plain.counts" "$channel")" ] || fail "$channel reached the URL's own port"
done
for channel in WORLD_STATE ROBOT_OBSERVATION ROBOT_COMMAND EPISODE_EVENT NAV_GOAL; do
  [ "$(count_of "$WORK/plain.counts" "$channel")" = "$(count_of "$WORK/shared.counts" "$channel")" ] ||
    fail "the plain listener heard $(count_of "$WORK/plain.counts" "$channel") $channel messages, the run's recorder $(count_of "$WORK/shared.counts" "$channel")"
done
no_orphans
if [ -n "$(our_pid record)" ]; then fail "hunav_record left running"; fi
echo "channel ports: same fingerprint $a, step channels recorded, and off the URL's port"
