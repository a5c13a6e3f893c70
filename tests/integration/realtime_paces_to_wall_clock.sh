#!/usr/bin/env bash
# Realtime mode: separate processes, the world paced to the wall clock, the robot driven by the
# latest command. A 2 s episode takes about 2 s and ends normally.
source "$(dirname "$0")/common.sh"
out="$WORK/realtime"
"$RUN" --scenario "$REPO/scenarios/passing.yaml" --mode realtime --duration 2 --out "$out" > "$WORK/rt.txt" 2>&1 \
  || { cat "$WORK/rt.txt"; fail "realtime run failed"; }
[ "$(json_field "$out/run.json" status)" = time_limit ] || fail "status $(json_field "$out/run.json" status)"
[ "$(json_field "$out/run.json" mode)" = realtime ] || fail "mode $(json_field "$out/run.json" mode)"
wall=$(json_field "$out/run.json" wall_time)
python3 -c "import sys; w=float(sys.argv[1]); sys.exit(0 if 1.95 <= w <= 3.0 else 1)" "$wall" \
  || fail "2 s of simulation took $wall s of wall time"
# The robot moved: the planner's commands arrived without lockstep.
python3 - "$out/states.csv" <<'PY' || fail "the robot did not move"
import csv, sys
xs = [float(r["x"]) for r in csv.DictReader(open(sys.argv[1])) if r["kind"] == "robot"]
sys.exit(0 if xs[-1] - xs[0] > 0.3 else 1)
PY
no_orphans
echo "realtime: 2 s simulated in $wall s"
