#!/usr/bin/env bash
# hunav_evaluator records and scores runs; it builds no world and moves no people (issue 34: no arrow
# from the evaluator back up to the runner). Its --counterfactual has hunav_run do the robot-free run.
# Fails when the evaluator's executable holds code of the world, the manager, the planners or the
# runner (nm lists its defined symbols; the names are demangled).
set -euo pipefail
: "${EVALUATOR:?path of the hunav_evaluator executable}"
found=$(nm -C --defined-only "$EVALUATOR" | grep -E 'hunav::(worldsim|manager|planners|runner)::' | head -5 || true)
if [ -n "$found" ]; then
  echo "hunav_evaluator holds simulator code, for example:" >&2
  echo "$found" >&2
  exit 1
fi
# And it still names the program that runs the robot-free episode.
"$EVALUATOR" --help | grep -q -- --robot-free-program
echo "hunav_evaluator: no world, manager, planner or runner code"
