#!/usr/bin/env bash
# hunav_run --seeds/--planners runs many episodes in one process: every result file must be the same,
# byte for byte, as one hunav_run process per episode (run.json apart from its wall time and its own
# path). Real inputs: HuNavSim's cafe map and agents, the behaviors of combined, the seeded crowd
# generator (a new crowd per seed), all three planners. Then the list errors (exit 2, item named).
set -euo pipefail
repo=$1 bin=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/hunav_seed_list.XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# scenario duration: short limits keep the test bounded; the crowd holds 300 people.
cases=("passing 0" "combined 20" "cafe 10" "crowd 2")
for c in "${cases[@]}"; do
  read -r scenario duration <<<"$c"
  dur=()
  [ "$duration" = 0 ] || dur=(--duration "$duration")
  "$bin/hunav_run" --scenario "$repo/scenarios/$scenario.yaml" --planners dwb,scl,sfw --seeds 1-2 \
    "${dur[@]}" --out "$work/list" --quiet >"$work/list_$scenario.log" || fail "the list run of $scenario exited $?"
  for planner in dwb scl sfw; do
    for seed in 1 2; do
      "$bin/hunav_run" --scenario "$repo/scenarios/$scenario.yaml" --planner "$planner" --seed "$seed" \
        "${dur[@]}" --out "$work/single/${scenario}__${planner}__seed${seed}" --quiet >/dev/null ||
        fail "the single run of $scenario $planner $seed exited $?"
    done
  done
  grep -q "6 episodes: 6 ended on their own" "$work/list_$scenario.log" || fail "$(tail -n 1 "$work/list_$scenario.log")"
done

# same_files A B FILES WHAT: every file listed (paths relative to both trees) has the same bytes in A
# and B (run.json: without wall_time and the states file's path).
strip() { grep -v -E '"(wall_time|states_file)"' "$1"; }
same_files() {
  local f
  while read -r f; do
    if [ "${f##*/}" = run.json ]; then
      diff <(strip "$1/$f") <(strip "$2/$f") >/dev/null || fail "$4: $f differs"
    else
      cmp -s "$1/$f" "$2/$f" || fail "$4: $f differs"
    fi
  done <"$3"
}
(cd "$work/list" && find . -type f | sort) >"$work/list.files"
(cd "$work/single" && find . -type f | sort) >"$work/single.files"
diff -u "$work/single.files" "$work/list.files" || fail "the list run wrote other files"
[ "$(wc -l <"$work/list.files")" -ge 96 ] || fail "only $(wc -l <"$work/list.files") files"
same_files "$work/single" "$work/list" "$work/list.files" "the list run"
# --single-thread (what run_batch.sh's chunks use when every core runs one): the same files again, for
# the combined behaviors and the 300-person crowd (whose pair forces otherwise use the pool's helper).
for scenario in combined crowd; do
  limit=20
  [ "$scenario" != crowd ] || limit=2
  "$bin/hunav_run" --scenario "$repo/scenarios/$scenario.yaml" --planners dwb,scl,sfw --seeds 1-2 --duration "$limit" \
    --single-thread --out "$work/single_thread" --quiet >/dev/null || fail "the --single-thread run of $scenario exited $?"
done
(cd "$work/single_thread" && find . -type f | sort) >"$work/single_thread.files"
grep -E '^\./(combined|crowd)__' "$work/list.files" | diff -u - "$work/single_thread.files" || fail "--single-thread wrote other files"
same_files "$work/list" "$work/single_thread" "$work/single_thread.files" "--single-thread"

# The crowd is drawn from each seed: seed 1 and seed 2 start differently.
cmp -s "$work/list/crowd__dwb__seed1/states.csv" "$work/list/crowd__dwb__seed2/states.csv" &&
  fail "the crowds of seeds 1 and 2 are the same"

# --folder-label names the folders (run_batch.sh's label of a scenario file whose name: differs);
# the run id keeps the scenario's name.
"$bin/hunav_run" --scenario "$repo/scenarios/passing.yaml" --seeds 3 --folder-label copy --duration 1 \
  --out "$work/label" --quiet >/dev/null || fail "--folder-label run exited $?"
grep -q '"run_id": "passing_dwb_s3"' "$work/label/copy__dwb__seed3/run.json" || fail "--folder-label: no copy__dwb__seed3"

# Bad lists: exit 2, the item named, nothing run.
expect_bad() {
  local want=$1
  shift
  local rc=0
  "$bin/hunav_run" --scenario "$repo/scenarios/passing.yaml" --out "$work/bad" "$@" >"$work/bad.out" 2>"$work/bad.err" || rc=$?
  [ "$rc" = 2 ] || fail "$* exited $rc, not 2"
  grep -q -- "$want" "$work/bad.err" || fail "$*: stderr $(cat "$work/bad.err") does not say $want"
  [ ! -e "$work/bad" ] || fail "$*: something ran"
}
expect_bad "'5-3' goes down" --seeds 1,5-3
expect_bad "unknown planner 'nope'" --planners dwb,nope --seeds 1
expect_bad "'dwb' is given twice" --planners dwb,dwb --seeds 1
expect_bad "seed" --seeds 2 --seed 3
echo "seed lists: every file of 24 episodes in one process equals one process per episode, and with --single-thread"
