#!/usr/bin/env bash
# A manager, then a planner, killed mid-episode and started again (a crash and a supervisor's
# restart): the world keeps resending its pending request, whose full state lets the new process
# take the episode up at a seq and episode it has never seen, and the run goes on to its time limit.
# The world exits 0, the evaluator records every tick, no process is left behind.
# Runs in a private network namespace of its own (multicast on loopback only).
if [ -z "${HUNAV_RESYNC_NETNS:-}" ]; then
  flags="--map-root-user --net"
  [ "$(id -u)" -ne 0 ] || flags="--net"
  # shellcheck disable=SC2086 # $flags holds flags
  HUNAV_RESYNC_NETNS=1 exec unshare $flags -- bash "$0" "$@"
fi
source "$(dirname "$0")/common.sh"
ip link set lo up
ip route add 224.0.0.0/4 dev lo
# As run_experiment.sh: the step channels on ports of their own; the evaluator on the URL's port.
EVAL_URL='udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304'
URL="$EVAL_URL&channel_ports=1"
SCENARIO="$REPO/tests/integration/data/endless_corridor.yaml"
OUT="$WORK/out"
mkdir -p "$OUT"

declare -A pid_of=()
stop_all() {
  for name in "${!pid_of[@]}"; do kill -TERM "${pid_of[$name]}" 2>/dev/null || true; done
  cleanup_work
}
trap stop_all EXIT

start() {  # start NAME CMD...: in the background, output into $WORK/NAME.log
  local name=$1
  shift
  "$@" > "$WORK/$name.log" 2>&1 < /dev/null &
  pid_of[$name]=$!
}
wait_ready() {  # wait_ready NAME: until NAME prints "ready" (bounded: 120 s)
  local end=$((SECONDS + 120))
  until printed_ready "$WORK/$1.log"; do
    kill -0 "${pid_of[$1]}" 2>/dev/null || { cat "$WORK/$1.log" >&2; fail "$1 exited before it was ready"; }
    [ "$SECONDS" -lt "$end" ] || fail "$1 never printed ready"
    sleep 0.1
  done
}
rows() { if [ -f "$OUT/states.csv" ]; then wc -l < "$OUT/states.csv"; else echo 0; fi; }

start evaluator "$BIN/hunav_evaluator" --out "$OUT" --episodes 1 --lcm-url "$EVAL_URL"
start manager "$BIN/hunav_manager" --lcm-url "$URL" --episodes 1
start planner "$BIN/hunav_planner" --planner dwb --scenario "$SCENARIO" --lcm-url "$URL" --episodes 1
for name in evaluator manager planner; do wait_ready "$name"; done
# 400 s of simulation (40000 ticks, two rows each); a restart may take a while on a busy machine, so
# the world waits up to 10 s for a silent component instead of 1 s.
start world "$BIN/hunav_worldsim" --scenario "$SCENARIO" --planner dwb --mode lockstep --duration 400 \
  --silence-limit 10 --lcm-url "$URL"

wait_for_rows "$OUT/states.csv" 2000
for victim in manager planner; do
  # The world is held (SIGSTOP) while the victim dies and a new one starts, so that however slow
  # this machine is, the episode cannot run to its end meanwhile; continued, it resends its pending
  # request, which the new process answers.
  kill -STOP "${pid_of[world]}"
  kill -KILL "${pid_of[$victim]}"
  wait "${pid_of[$victim]}" 2>/dev/null || true
  planner_args=()
  [ "$victim" != planner ] || planner_args=(--planner dwb --scenario "$SCENARIO")
  start "$victim" "$BIN/hunav_$victim" --lcm-url "$URL" --episodes 1 "${planner_args[@]}"
  wait_ready "$victim"
  before=$(rows)
  kill -CONT "${pid_of[world]}"
  wait_for_rows "$OUT/states.csv" $(( before + 200 ))  # the run goes on with the new process
  echo "$victim killed and restarted at about row $before of states.csv"
done

rc=0
for _ in $(seq 1200); do kill -0 "${pid_of[world]}" 2>/dev/null || break; sleep 0.1; done
wait "${pid_of[world]}" || rc=$?
cat "$WORK/world.log"
[ "$rc" -eq 0 ] || fail "the world exited with $rc"
grep -q "episode 1 .*: time_limit" "$WORK/world.log" || fail "the episode did not run to its time limit"
for name in evaluator manager planner; do
  for _ in $(seq 300); do kill -0 "${pid_of[$name]}" 2>/dev/null || break; sleep 0.1; done
  wait "${pid_of[$name]}" || fail "$name (restarted or not) did not exit 0 after the episode"
  unset "pid_of[$name]"
done
unset "pid_of[world]"
[ "$(json_field "$OUT/run.json" status)" = time_limit ] || fail "run.json status $(json_field "$OUT/run.json" status)"
[ "$(json_field "$OUT/run.json" ticks)" = 40001 ] || fail "ticks $(json_field "$OUT/run.json" ticks)"
[ "$(json_field "$OUT/run.json" recorded_ticks)" = 40001 ] || fail "recorded $(json_field "$OUT/run.json" recorded_ticks) ticks"
no_orphans
echo "the run survived a manager and a planner restart: 40001 ticks recorded"
