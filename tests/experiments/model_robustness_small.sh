#!/usr/bin/env bash
# launch_scripts/model_robustness.sh end to end on a small matrix (passing x dwb, scl x seeds 1-2,
# 10 s of simulation, people on sfm and orca; in-process: no network): one batch per model, each
# recording its model (run.json, metrics.csv, summary.md), and the comparison of the paper's
# orderings (model_robustness.csv with a column per model and a verdict per ordering, and .md);
# bad arguments exit 2. Expects REPO and BIN (ctest sets them).
set -euo pipefail
export HUNAV_BIN_DIR="$BIN"
WORK=$(mktemp -d /tmp/hunav_robustness_test.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
SCRIPT="$REPO/launch_scripts/model_robustness.sh"
out="$WORK/out"
"$SCRIPT" --out "$out" --models sfm,orca --scenarios passing --planners dwb,scl --seeds 1-2 --duration 10 --jobs 2 \
  >"$WORK/log" 2>&1 || { cat "$WORK/log"; fail "model_robustness.sh failed"; }
for m in sfm orca; do
  [ -s "$out/$m/paper_orderings.csv" ] || fail "no $m/paper_orderings.csv"
  grep -q "People model: \`$m\` (4 runs)" "$out/$m/summary.md" || fail "$m/summary.md does not name its model"
  grep -q "\"people_model\": \"$m\"" "$out/$m/runs/passing__dwb__seed1/run.json" || fail "$m: run.json does not say $m"
done
head -1 "$out/model_robustness.csv" | grep -qx 'scenario,behavior,metric,planner_a,planner_b,paper,sfm,orca,verdict' ||
  fail "model_robustness.csv header: $(head -1 "$out/model_robustness.csv")"
rows=$(($(wc -l <"$out/model_robustness.csv") - 1))
[ "$rows" -gt 0 ] || fail "model_robustness.csv has no ordering"
# Every row's verdict follows from its columns.
awk -F, 'NR > 1 {
  p = $6; a = $7; b = $8
  if (p == "=") want = "paper_tie"; else if (a == "" || b == "") want = "missing";
  else if (a == p && b == p) want = "holds"; else if (a == b) want = "fails"; else want = "flips"
  if ($9 != want) { print "line " NR ": " $0 " (want " want ")"; bad = 1 } }
  END { exit bad }' "$out/model_robustness.csv" || fail "a verdict does not follow from its columns"
grep -q '^# Does the human model change the verdict?' "$out/model_robustness.md" || fail "no model_robustness.md"
# Bad arguments: exit 2.
rc=0
"$SCRIPT" --models sfm >/dev/null 2>&1 || rc=$?
[ "$rc" -eq 2 ] || fail "no --out: exit $rc"
rc=0
"$SCRIPT" --out "$WORK/x" --models 'a/b' >/dev/null 2>&1 || rc=$?
[ "$rc" -eq 2 ] || fail "a model with a slash: exit $rc"
echo "ok: $rows orderings compared"
