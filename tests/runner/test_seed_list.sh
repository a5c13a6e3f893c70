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

# --runs (run_batch.sh's inprocess mode): the same 24 episodes as one list, in an order that mixes
# scenarios and planners (so that a thread's kept planner meets other maps), on 2 threads at once,
# each with a wall-clock limit it never reaches: the same files again, plus each run's console output
# in its logs/hunav_run.log, and a line per run.
list="$work/runs.tsv"
for c in "${cases[@]}"; do
  read -r scenario duration <<<"$c"
  for planner in sfw dwb scl; do
    for seed in 2 1; do
      printf '%s\t%s\t%s\t%s\t600\n' "$repo/scenarios/$scenario.yaml" "$scenario" "$planner" "$seed"
    done
  done
done | awk 'NR % 2 { print; next } { held[NR] = $0 } END { for (i = NR - NR % 2; i > 0; i -= 2) print held[i] }' >"$list"
[ "$(wc -l <"$list")" -eq 24 ] || fail "the run list has $(wc -l <"$list") lines"
# The durations differ per scenario, --duration is per invocation: one list per duration.
for c in "${cases[@]}"; do
  read -r scenario duration <<<"$c"
  dur=()
  [ "$duration" = 0 ] || dur=(--duration "$duration")
  grep -F "/$scenario.yaml" "$list" >"$work/runs_$scenario.tsv"
  "$bin/hunav_run" --runs "$work/runs_$scenario.tsv" --jobs 2 "${dur[@]}" --out "$work/runs" --quiet \
    >"$work/runs_$scenario.log" || fail "the --runs list of $scenario exited $?"
  grep -q "6 episodes: 6 ended on their own" "$work/runs_$scenario.log" || fail "$(tail -n 1 "$work/runs_$scenario.log")"
  [ "$(grep -c -E '^\[[1-6]/6\] '"$scenario"' (dwb|scl|sfw) seed [12]: (goal_reached|time_limit|stuck) after [0-9.]+ s of simulation$' \
    "$work/runs_$scenario.log")" -eq 6 ] || fail "--runs progress lines: $(cat "$work/runs_$scenario.log")"
done
(cd "$work/runs" && find . -type f ! -path '*/logs/*' | sort) >"$work/runs.files"
diff -u "$work/single.files" "$work/runs.files" || fail "the --runs list wrote other files"
same_files "$work/single" "$work/runs" "$work/runs.files" "--runs --jobs 2"
for f in "$work"/runs/*/logs/hunav_run.log; do
  grep -q "^results in $(dirname "$(dirname "$f")")\$" "$f" || fail "$f: $(cat "$f")"
done
[ "$(find "$work/runs" -path '*/logs/hunav_run.log' | wc -l)" -eq 24 ] || fail "not every run has its log"

# A run past its wall-clock limit (the 300-person crowd for 120 s, limit 1 s) is stopped soon after:
# aborted with the timeout as its reason, not finished (exit 1); the other thread's run is not
# stopped, and the run after the stopped one on its thread still runs.
printf '%s\tcrowd\tdwb\t1\t1\n%s\tpassing\tdwb\t1\t0\n%s\tpassing\tscl\t1\n' "$repo/scenarios/crowd.yaml" \
  "$repo/scenarios/passing.yaml" "$repo/scenarios/passing.yaml" >"$work/timeout.tsv"
rc=0
"$bin/hunav_run" --runs "$work/timeout.tsv" --jobs 2 --duration 120 --out "$work/timeout" --quiet >"$work/timeout.log" 2>&1 || rc=$?
[ "$rc" -eq 1 ] || fail "the timed-out list exited $rc, not 1: $(cat "$work/timeout.log")"
grep -q '"reason": "wall-clock timeout: the run ran longer than 1 s"' "$work/timeout/crowd__dwb__seed1/run.json" ||
  fail "the stopped run's reason: $(cat "$work/timeout/crowd__dwb__seed1/run.json")"
grep -q '"status": "aborted"' "$work/timeout/crowd__dwb__seed1/run.json" || fail "the stopped run is not aborted"
grep -q '"complete": false' "$work/timeout/crowd__dwb__seed1/run.json" || fail "the stopped run is complete"
grep -q '^\[[123]/3\] crowd dwb seed 1: NOT FINISHED: aborted (wall-clock timeout' "$work/timeout.log" ||
  fail "no NOT FINISHED line: $(cat "$work/timeout.log")"
for p in dwb scl; do
  grep -q '"status": "goal_reached"' "$work/timeout/passing__${p}__seed1/run.json" || fail "passing $p did not run to its goal"
done

# Bad run lists: exit 2 with file:line: column, nothing run.
expect_bad_list() {
  local want=$1 text=$2 rc=0
  printf '%b' "$text" >"$work/bad.tsv"
  "$bin/hunav_run" --runs "$work/bad.tsv" --out "$work/bad" >"$work/bad.out" 2>"$work/bad.err" || rc=$?
  [ "$rc" = 2 ] || fail "list '$text' exited $rc, not 2"
  grep -q -F -- "$want" "$work/bad.err" || fail "list '$text': stderr $(cat "$work/bad.err") does not say $want"
  [ ! -e "$work/bad" ] || fail "list '$text': something ran"
}
p="$repo/scenarios/passing.yaml"
expect_bad_list "bad.tsv:2: seed" "# a comment\n$p\tpassing\tdwb\t-1\n"
expect_bad_list "bad.tsv:1: planner" "$p\tpassing\tnope\t1\n"
expect_bad_list "bad.tsv:3: seed" "$p\tpassing\tdwb\t1\n\n$p\tpassing\tdwb\t1\n"
expect_bad_list "bad.tsv:1: label" "$p\t../x\tdwb\t1\n"
expect_bad_list "bad.tsv:1: timeout" "$p\tpassing\tdwb\t1\tsoon\n"
expect_bad_list "bad.tsv:1: a run is 4 to 6" "$p\tpassing\tdwb\n"
rc=0
"$bin/hunav_run" --runs "$list" --scenario "$p" >/dev/null 2>&1 || rc=$?
[ "$rc" = 2 ] || fail "--runs with --scenario exited $rc"

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
echo "seed lists: every file of 24 episodes in one process equals one process per episode, with --single-thread and with --runs --jobs 2; a run past its limit stops alone"
