#!/usr/bin/env bash
# hunav_run --no-states-csv leaves states.csv out and nothing else: every other file is the same, byte
# for byte, as with it (run.json apart from its wall time and states_file), on HuNavSim's cafe with its
# agents; and it cannot go with --counterfactual, which reads states.csv back (exit 2, both named).
set -euo pipefail
repo=$1 bin=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/hunav_no_states.XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

for run in with without; do
  flag=()
  [ "$run" = with ] || flag=(--no-states-csv)
  "$bin/hunav_run" --scenario "$repo/scenarios/cafe.yaml" --duration 10 --out "$work/$run" --quiet "${flag[@]}" \
    || fail "the run $run states.csv exited $?"
done
[ -s "$work/with/states.csv" ] || fail "no states.csv by default"
[ ! -e "$work/without/states.csv" ] || fail "states.csv written with --no-states-csv"
(cd "$work/with" && find . -type f ! -name states.csv ! -name run.json | sort) > "$work/files_with"
(cd "$work/without" && find . -type f ! -name run.json | sort) > "$work/files_without"
cmp -s "$work/files_with" "$work/files_without" || fail "other files differ: $(diff "$work/files_with" "$work/files_without")"
[ "$(wc -l < "$work/files_with")" -ge 3 ] || fail "too few files to compare"
while read -r f; do
  cmp -s "$work/with/$f" "$work/without/$f" || fail "$f differs without states.csv"
done < "$work/files_with"
strip() { grep -v -E '"(wall_time|states_file)"' "$1"; }
diff <(strip "$work/with/run.json") <(strip "$work/without/run.json") > /dev/null || fail "run.json differs"
grep -q '"states_file": ""' "$work/without/run.json" || fail "run.json names a states file it did not write"

rc=0
"$bin/hunav_run" --scenario "$repo/scenarios/passing.yaml" --no-states-csv --counterfactual --out "$work/bad" \
  > "$work/bad.log" 2>&1 || rc=$?
[ "$rc" = 2 ] || fail "--no-states-csv with --counterfactual exited $rc (expected 2)"
grep -q -- "--no-states-csv" "$work/bad.log" && grep -q -- "--counterfactual" "$work/bad.log" || fail "$(cat "$work/bad.log")"
echo "no states.csv: the other $(wc -l < "$work/files_with") files and run.json unchanged"
