#!/usr/bin/env bash
# Speed of whole episodes as separate processes in lockstep (private network namespace):
# real-time factor from run.json (sim_time / wall_time of the world). Run on demand:
#   bench/bench_lockstep.sh [SCENARIO] [REPEAT]
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
scenario=${1:-$repo/scenarios/passing.yaml}
repeat=${2:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for planner in dwb none; do
  for i in $(seq "$repeat"); do
    "$repo/launch_scripts/run_experiment.sh" --scenario "$scenario" --planner "$planner" --mode lockstep \
      --out "$work/$planner$i" > /dev/null 2>&1 || true
    python3 - "$work/$planner$i/run.json" "$planner" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
print(f"lockstep planner {sys.argv[2]}: {r['status']}, {r['sim_time']:.2f} s simulated, {r['ticks']} ticks in "
      f"{r['wall_time']:.3f} s: {r['sim_time'] / r['wall_time']:.0f}x real time, "
      f"{r['wall_time'] / r['ticks'] * 1e6:.1f} us per tick")
PY
  done
done
