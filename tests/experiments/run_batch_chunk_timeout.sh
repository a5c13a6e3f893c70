#!/usr/bin/env bash
# run_batch.sh in-process runs the whole matrix in one hunav_run (--runs), each run with its own
# wall-clock limit. A run longer than the limit (the 300-person crowd for 120 s of simulation,
# --timeout 1) is stopped soon after it: recorded as aborted with the timeout as its reason (not as
# interrupted), not finished (exit 1, it runs again next time), and the next run of the batch still
# runs to its end.
# Expects REPO and BIN (ctest sets them).
set -euo pipefail
export HUNAV_BIN_DIR="$BIN"
WORK=$(mktemp -d /tmp/hunav_batch_timeout.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
out="$WORK/batch"
start=$(date +%s.%N)
rc=0
"$REPO/launch_scripts/run_batch.sh" --scenarios crowd,passing --planners dwb --seeds 1 --duration 120 --timeout 1 \
  --jobs 1 --out "$out" >"$WORK/log" 2>&1 || rc=$?
took=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
[ "$rc" -eq 1 ] || { cat "$WORK/log"; fail "exit $rc, expected 1 (a run did not finish)"; }
run="$out/runs/crowd__dwb__seed1"
grep -q '"status": "aborted"' "$run/run.json" || { cat "$run/run.json"; fail "the stopped run is not aborted"; }
grep -q '"reason": "wall-clock timeout: the run ran longer than 1 s"' "$run/run.json" ||
  { cat "$run/run.json"; fail "the reason is not the timeout"; }
grep -q 'crowd dwb seed 1: NOT FINISHED: aborted' "$WORK/log" || { cat "$WORK/log"; fail "no NOT FINISHED line"; }
grep -q '"complete": true' "$out/runs/passing__dwb__seed1/run.json" || fail "the passing run did not run"
# The crowd's run took its 1 s, then the time to end the tick and write what it recorded.
awk -v t="$took" 'BEGIN { exit !(t < 20) }' || fail "the batch took $took s"
echo "run timeout: aborted after the limit, the other run ran; $took s"
