#!/usr/bin/env bash
# The floor of the multi-process lockstep, in a private network namespace:
#  1. round trip between two processes over LCM udpm (blocking handleTimeout as our Bus waits, and
#     zero-timeout polling), alone and with two more processes on the bus that hear every datagram;
#  2. an emulated lockstep tick (request, reply, then a state message to a third process, as world,
#     manager and evaluator do), with every channel on one port (what we run) or each on its own port;
#  3. the same round trip over bare UDP multicast sockets (the kernel alone, without LCM's threads).
# Prints per configuration the round trip and the CPU time (user + system) of every process per
# iteration, from /usr/bin/time. Run on demand:  bench/bench_lcm_roundtrip.sh [BIN_DIR] [COUNT] [NICE]
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$repo/build/bin}
count=${2:-20000}
nice_level=${3:-0}
exe=$bin/bench_lcm_roundtrip
[ -x "$exe" ] || { echo "bench_lcm_roundtrip not built in $bin" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "/usr/bin/time is missing (package time)" >&2; exit 2; }

if [ -z "${HUNAV_BENCH_NETNS:-}" ]; then
  flags=--net
  [ "$(id -u)" -eq 0 ] || flags=-rn
  HUNAV_BENCH_NETNS=1 exec unshare $flags -- "$BASH" "$0" "$bin" "$count" "$nice_level"
fi
ip link set lo up
ip route replace 224.0.0.0/4 dev lo

work=$(mktemp -d)
pids=()
names=()
stop_all() {  # SIGTERM to each program (the child of its /usr/bin/time, which then writes its figures)
  local pid child
  for pid in "${pids[@]}"; do
    for child in $(pgrep -P "$pid" || true); do kill "$child" 2>/dev/null || true; done
  done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  pids=()
}
trap 'stop_all; rm -rf "$work"' EXIT

start() {  # start NAME ARGS...: in the background, timed, waiting for its "ready"
  local name=$1
  shift
  nice -n "$nice_level" /usr/bin/time -o "$work/$name.time" -f "%U %S" "$exe" "$@" > "$work/$name.out" 2>&1 &
  pids+=($!)
  names+=("$name")
  for _ in $(seq 100); do
    grep -q ready "$work/$name.out" 2>/dev/null && return 0
    sleep 0.05
  done
  echo "$name did not start" >&2
  cat "$work/$name.out" >&2
  exit 1
}

measure() {  # measure LABEL PING_ARGS -- OTHER_ROLES...: one configuration
  local label=$1
  shift
  local ping_args=()
  while [ "$1" != -- ]; do ping_args+=("$1"); shift; done
  shift
  names=()
  local i=0
  for role_args in "$@"; do
    # shellcheck disable=SC2086 # role_args holds several words
    start "p$i" $role_args
    i=$((i + 1))
  done
  echo "== $label"
  nice -n "$nice_level" /usr/bin/time -o "$work/ping.time" -f "%U %S" "$exe" --role ping --count "$count" \
    "${ping_args[@]}" | sed 's/^/  /'
  stop_all
  local line
  line="  CPU per iteration (process lifetime): ping $(awk -v n="$count" '{printf "%.1f", ($1 + $2) / n * 1e6}' "$work/ping.time") us"
  for name in "${names[@]}"; do
    line+=", $name $(awk -v n="$count" '{printf "%.1f", ($1 + $2) / n * 1e6}' "$work/$name.time") us"
  done
  echo "$line"
}

measure "round trip, 2 processes" -- "--role pong"
measure "round trip, 2 processes + 2 that only hear the traffic" -- "--role pong" "--role listen" "--role listen"
measure "round trip polling with zero timeout, 2 processes" --wait spin -- "--role pong"
measure "emulated tick, one port (p0 pong, p1 takes STATE)" --state -- "--role pong" "--role listen --state"
measure "emulated tick, a port per channel" --state --split -- "--role pong --split" "--role listen --state --split"
measure "bare UDP multicast round trip (2 ports, no LCM)" --transport raw -- "--role pong --transport raw"
