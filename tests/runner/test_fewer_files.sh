#!/usr/bin/env bash
# hunav_run --no-states-csv and --no-per-tick-files leave out states.csv and the per-tick metric files
# (metrics_steps.csv, metrics_beh_<b>_steps.csv) and nothing else: every other file is the same, byte
# for byte, as with them (run.json apart from its wall time and states_file), on HuNavSim's cafe with
# its agents (several behaviors: several per-behavior files); --no-states-csv cannot go with
# --counterfactual, which reads states.csv back (exit 2, both named).
set -euo pipefail
repo=$1 bin=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/hunav_fewer_files.XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

run() {  # run NAME FLAGS...
  local name=$1
  shift
  "$bin/hunav_run" --scenario "$repo/scenarios/cafe.yaml" --duration 10 --out "$work/$name" --quiet "$@" \
    >/dev/null || fail "the run $name exited $?"
}
run all
run no_states --no-states-csv
run no_ticks --no-per-tick-files
run neither --no-states-csv --no-per-tick-files
{ [ -s "$work/all/states.csv" ] && [ -s "$work/all/metrics_steps.csv" ]; } || fail "files missing by default"
[ "$(find "$work/all" -maxdepth 1 -name 'metrics_beh_[1-6]_steps.csv' | wc -l)" -ge 2 ] || fail "cafe should have several behaviors"

# compare NAME PATTERN: NAME holds exactly all's files except those matching PATTERN, each the same.
compare() {
  local name=$1 left_out=$2 f
  (cd "$work/all" && find . -type f ! -name run.json | grep -v -E "$left_out" | sort) >"$work/expected_$name"
  (cd "$work/$name" && find . -type f ! -name run.json | sort) >"$work/files_$name"
  cmp -s "$work/expected_$name" "$work/files_$name" ||
    fail "$name: other files than expected: $(diff "$work/expected_$name" "$work/files_$name")"
  [ "$(wc -l <"$work/files_$name")" -ge 3 ] || fail "$name: too few files to compare"
  while read -r f; do
    cmp -s "$work/all/$f" "$work/$name/$f" || fail "$name: $f differs"
  done <"$work/files_$name"
  strip() { grep -v -E '"(wall_time|states_file)"' "$1"; }
  diff <(strip "$work/all/run.json") <(strip "$work/$name/run.json") >/dev/null || fail "$name: run.json differs"
}
compare no_states '^\./states\.csv$'
compare no_ticks '_steps\.csv$'
compare neither '^\./states\.csv$|_steps\.csv$'
grep -q '"states_file": ""' "$work/no_states/run.json" || fail "run.json names a states file it did not write"

rc=0
"$bin/hunav_run" --scenario "$repo/scenarios/passing.yaml" --no-states-csv --counterfactual --out "$work/bad" \
  >"$work/bad.log" 2>&1 || rc=$?
[ "$rc" = 2 ] || fail "--no-states-csv with --counterfactual exited $rc (expected 2)"
{ grep -q -- "--no-states-csv" "$work/bad.log" && grep -q -- "--counterfactual" "$work/bad.log"; } || fail "$(cat "$work/bad.log")"
echo "fewer files: $(wc -l <"$work/files_neither") files left, each the same as in a full run"
