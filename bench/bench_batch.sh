#!/usr/bin/env bash
# Speed of whole batches (issue 17): launch_scripts/run_batch.sh on the paper's matrix, passing,
# crossing and combined x dwb, scl, sfw x SEEDS (default 1-10: 90 runs), into a fresh folder each
# time, every result file and the summary included. Prints the wall time, runs per second, and the
# CPU time of the whole batch (user + system of every process, from the kernel: what the runs cost
# whatever else shares the machine), so that the floor (the simulation's own CPU) can be read off
# against bench_episode's figures.
#   bench/bench_batch.sh [--bin DIR] [--seeds 1-10] [--jobs 2] [--repeat 3] [-- run_batch.sh options]
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
bin=${HUNAV_BIN_DIR:-$repo/build/bin}
seeds=1-10 jobs=2 repeat=3
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --bin) bin=$2; shift 2 ;;
    --seeds) seeds=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --repeat) repeat=$2; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    -h | --help) sed -n '2,8p' "$0"; exit 0 ;;
    *) echo "bench_batch: unknown option $1" >&2; exit 2 ;;
  esac
done
work=$(mktemp -d "${TMPDIR:-/tmp}/bench_batch.XXXXXX")
trap 'rm -rf "$work"' EXIT
echo "bench_batch: run_batch.sh --scenarios passing,crossing,combined --planners dwb,scl,sfw --seeds $seeds --jobs $jobs ${extra[*]}"
echo "machine: $(nproc) cores, $(uname -r); load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for k in $(seq 1 "$repeat"); do
  out="$work/batch$k"
  # /usr/bin/time's user and system include every descendant process (they are all waited for).
  /usr/bin/time -f '%e %U %S' -o "$work/time$k" env HUNAV_BIN_DIR="$bin" "$repo/launch_scripts/run_batch.sh" \
    --scenarios passing,crossing,combined --planners dwb,scl,sfw --seeds "$seeds" --jobs "$jobs" \
    --out "$out" "${extra[@]}" >"$work/log$k" 2>&1 || { tail -n 20 "$work/log$k"; exit 1; }
  runs=$(find "$out/runs" -mindepth 2 -maxdepth 2 -name metrics.csv | wc -l)
  read -r wall user sys <"$work/time$k"
  awk -v c="$(nproc)" -v k="$k" -v r="$runs" -v w="$wall" -v u="$user" -v s="$sys" 'BEGIN {
    printf "  batch %d: %d runs in %.2f s wall = %.1f runs/s (%.1f per core); CPU %.2f s user + %.2f s system = %.1f ms per run\n",
      k, r, w, r / w, r / w / c, u, s, 1000 * (u + s) / r }'
done
