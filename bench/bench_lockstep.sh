#!/usr/bin/env bash
# Speed of whole episodes as separate processes in lockstep, each its own LCM instance on udpm inside
# a private network namespace made for the benchmark (as run_experiment.sh --mode lockstep does).
# Per run: the real-time factor the world measures (sim_time / wall_time from START to END), and per
# process the CPU time (user + system) and context switches per tick, from the kernel's resource
# usage of each process (wait4, microseconds: /usr/bin/time rounds to 10 ms, 4 us per tick of the
# passing run): the wall clock is at the mercy of whatever else runs on the 2 cores; CPU time and
# switches are not.
#   bench/bench_lockstep.sh [--bin DIR] [--scenario FILE] [--repeat N] [--planners "dwb none"] [--nice N]
#                           [--url URL] [--rt PRIO] [--view]
# --nice N (root): run the processes at nice N (e.g. -10), so that other work on the machine delays
# their wake-ups less; the wall-clock figure then approaches that of an idle machine.
# --rt PRIO (root): run them under the real-time FIFO policy at PRIO (chrt -f), so that compiles on
# the other core(s) cannot delay a wake-up at all; the processes block between messages, and the
# kernel's real-time throttling keeps the machine responsive in any case.
# --url: the LCM URL inside the namespace (default: run_experiment.sh's, with channel_ports=1: STEP_REQUEST
# and STEP_REPLY on ports of their own, common/transport/include/hunav/channels.hpp); drop &channel_ports=1 to
# put every channel on one port. The evaluator gets the URL without that option, as in run_experiment.sh.
# After the runs of a planner: the median real-time factor and CPU per tick over the repeats.
# Figures of one port against channel ports: lcmtypes/README.md, "Ports".
# --view: every repeat runs twice, without and with hunav_view listening to the run's port (what
# run_experiment.sh --view attaches), interleaved; a summary for each, and the view's own CPU. The
# processes' CPU per tick tells what the view costs them (the kernel's delivery of each datagram to
# one more socket is charged to its publisher) whatever else the 2 cores do.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
bin=${HUNAV_BIN_DIR:-$repo/build/bin}
scenario=$repo/scenarios/passing.yaml
repeat=3
planners="dwb none"
nice_level=0
rt_prio=0
view=0
url=''  # below: our processes' default bus (asked of the build), with channel_ports=1
while [ $# -gt 0 ]; do
  case $1 in
    --bin) bin=$2; shift 2 ;;
    --scenario) scenario=$2; shift 2 ;;
    --repeat) repeat=$2; shift 2 ;;
    --planners) planners=$2; shift 2 ;;
    --nice) nice_level=$2; shift 2 ;;
    --url) url=$2; shift 2 ;;
    --rt) rt_prio=$2; shift 2 ;;
    --view) view=1; shift ;;
    *) echo "usage: $0 [--bin DIR] [--scenario FILE] [--repeat N] [--planners LIST] [--nice N] [--url URL] [--rt PRIO] [--view]" >&2; exit 2 ;;
  esac
done
for exe in hunav_worldsim hunav_manager hunav_planner hunav_evaluator hunav_record hunav_view; do
  [ -x "$bin/$exe" ] || { echo "$exe not built in $bin" >&2; exit 2; }
done
if [ -z "$url" ]; then
  url=$(env -u LCM_DEFAULT_URL "$bin/hunav_record" --print-url)  # kDefaultLcmUrl, its one definition
  if [[ $url == *\?* ]]; then url="$url&channel_ports=1"; else url="$url?channel_ports=1"; fi
fi
# "${timed[@]}" FILE PROGRAM ARGS...: runs PROGRAM and writes its user and system CPU seconds and its
# voluntary and involuntary context switches into FILE.
timed=(python3 -c '
import os, sys
pid = os.fork()
if pid == 0:
    os.execvp(sys.argv[2], sys.argv[2:])
_, status, usage = os.wait4(pid, 0)
with open(sys.argv[1], "w") as f:
    f.write(f"{usage.ru_utime:.6f} {usage.ru_stime:.6f} {usage.ru_nvcsw} {usage.ru_nivcsw}\n")
code = os.waitstatus_to_exitcode(status)
sys.exit(code if code >= 0 else 128 - code)')

if [ -z "${HUNAV_BENCH_NETNS:-}" ]; then
  flags=--net
  [ "$(id -u)" -eq 0 ] || flags=-rn
  view_args=()
  [ "$view" -eq 0 ] || view_args=(--view)
  HUNAV_BENCH_NETNS=1 exec unshare $flags -- "$BASH" "$0" --bin "$bin" --scenario "$scenario" --repeat "$repeat" \
    --planners "$planners" --nice "$nice_level" --url "$url" --rt "$rt_prio" "${view_args[@]}"
fi
ip link set lo up
ip route replace 224.0.0.0/4 dev lo

work=$(mktemp -d)
pids=()
stop_all() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  pids=()
}
trap 'stop_all; rm -rf "$work"' EXIT

start() {  # start NAME PROGRAM ARGS...: in the background, timed, waiting for its "ready" line
  local name=$1
  shift
  local sched=()
  [ "$rt_prio" -eq 0 ] || sched=(chrt -f "$rt_prio")
  nice -n "$nice_level" "${sched[@]}" "${timed[@]}" "$work/$name.time" "$@" > "$work/$name.out" 2>&1 &
  pids+=($!)
  [ "$name" = world ] && return 0
  for _ in $(seq 600); do
    grep -q '^ready' "$work/$name.out" 2>/dev/null && return 0
    sleep 0.05
  done
  echo "$name did not start:" >&2
  cat "$work/$name.out" >&2
  exit 1
}

eval_url=$(printf '%s' "$url" | sed -E 's/([?&])channel_ports=1(&|$)/\1/; s/[?&]$//')
echo "bus: $url (evaluator: $eval_url), nice $nice_level, real-time priority $rt_prio"
# The series: without the view, and with it (--view).
series=(plain)
[ "$view" -eq 0 ] || series+=(view)
for planner in $planners; do
  for kind in "${series[@]}"; do : > "$work/summary_${planner}_$kind"; done
  for i in $(seq "$repeat"); do
  for kind in "${series[@]}"; do
    out=$work/out_$planner${i}_$kind
    view_pid=""
    if [ "$kind" = view ]; then
      start view "$bin/hunav_view" --lcm-url "$eval_url" --port 0 --no-editor --scenario "$scenario"
      view_pid=${pids[-1]}
    fi
    start evaluator "$bin/hunav_evaluator" --out "$out" --episodes 1 --lcm-url "$eval_url"
    # As run_experiment.sh: the manager runs until stopped (SIGTERM once the world has ended), so that
    # it need not listen to the URL's own port for the END event.
    start manager "$bin/hunav_manager" --lcm-url "$url"
    manager_pid=${pids[-1]}
    names=(world manager evaluator)
    if [ "$planner" != none ]; then
      start planner "$bin/hunav_planner" --planner "$planner" --scenario "$scenario" --lcm-url "$url" --episodes 1
      names+=(planner)
    fi
    start world "$bin/hunav_worldsim" --scenario "$scenario" --planner "$planner" --mode lockstep --lcm-url "$url"
    wait "${pids[-1]}" || true
    # The manager itself, not the timing wrapper (which would die without writing its figures).
    mapfile -t manager_children < <(pgrep -P "$manager_pid")
    [ "${#manager_children[@]}" -eq 0 ] || kill -TERM "${manager_children[@]}" 2>/dev/null || true
    if [ -n "$view_pid" ]; then
      mapfile -t view_children < <(pgrep -P "$view_pid")
      [ "${#view_children[@]}" -eq 0 ] || kill -TERM "${view_children[@]}" 2>/dev/null || true
    fi
    for pid in "${pids[@]}"; do wait "$pid" || true; done
    pids=()
    [ "$kind" = plain ] || names+=(view)
    python3 - "$out/run.json" "$planner" "$work" "${names[@]}" >>"$work/summary_${planner}_$kind" <<'PY'
import json, sys
run = json.load(open(sys.argv[1]))
planner, work, names = sys.argv[2], sys.argv[3], sys.argv[4:]
ticks = run["ticks"]
print(f"lockstep planner {planner}{' with hunav_view' if 'view' in names else ''}: {run['status']}, {run['sim_time']:.2f} s simulated, {ticks} ticks in "
      f"{run['wall_time']:.3f} s: {run['sim_time'] / run['wall_time']:.0f}x real time, "
      f"{run['wall_time'] / ticks * 1e6:.1f} us per tick, fingerprint {run['fingerprint']}")
# The evaluator must have recorded every world state (lost_ticks: numbered states that never came;
# its stderr names datagrams its socket lost).
lost = [line.strip() for line in open(f"{work}/evaluator.out") if "lost" in line or "LOST" in line]
print(f"  evaluator: {run['recorded_ticks']} of {ticks} ticks recorded, {run['lost_ticks']} lost"
      + "".join(f"; {line}" for line in lost))
total = 0.0
parts = []
for name in names:
    user, system, voluntary, involuntary = open(f"{work}/{name}.time").read().split()[-4:]
    cpu = float(user) + float(system)
    total += cpu if name != "view" else 0.0  # the run's processes
    parts.append(f"{name} {cpu / ticks * 1e6:.1f} us ({float(system) / ticks * 1e6:.1f} sys), "
                 f"{(int(voluntary) + int(involuntary)) / ticks:.1f} sw")
print(f"  CPU per tick (whole process lifetimes, start-up included): total {total / ticks * 1e6:.1f} us; "
      + "; ".join(parts))
PY
    tail -n 3 "$work/summary_${planner}_$kind"
  done
  done
  for kind in "${series[@]}"; do
  python3 - "$work/summary_${planner}_$kind" "$planner" "$kind" <<'PY'
import re, statistics, sys
text = open(sys.argv[1]).read()
factors = [float(x) for x in re.findall(r"(\d+)x real time", text)]
cpu = {}
for line in text.splitlines():
    for name, us in re.findall(r"(total|world|manager|evaluator|planner|view) ([0-9.]+) us", line):
        cpu.setdefault(name, []).append(float(us))
print(f"planner {sys.argv[2]}{' with hunav_view' if sys.argv[3] == 'view' else ''}, {len(factors)} runs: median {statistics.median(factors):.0f}x real time "
      f"(min {min(factors):.0f}x, max {max(factors):.0f}x); median CPU us per tick: "
      + ", ".join(f"{k} {statistics.median(v):.1f}" for k, v in cpu.items()))
PY
  done
done
