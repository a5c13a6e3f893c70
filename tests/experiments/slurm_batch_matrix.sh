#!/usr/bin/env bash
# slurm_batch.sh without Slurm: the index -> (scenario, planner, seed) mapping of the array tasks,
# two tasks run for real and aggregated, and the submission (a stand-in sbatch records its arguments);
# then tasks of several runs (--runs-per-task: one hunav_run per scenario and planner of a task) give
# the same results as one run per task and skip what is finished.
# Expects REPO and BIN (ctest sets them).
set -euo pipefail
export HUNAV_BIN_DIR="$BIN"
WORK=$(mktemp -d /tmp/hunav_slurm_test.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
SLURM="$REPO/launch_scripts/slurm_batch.sh"
matrix=(--scenarios "passing,crossing" --planners "dwb,scl,sfw" --seeds "3-4,9")

# The matrix is run_batch.sh's, indexed (scenario * 3 + planner) * 3 + seed.
"$SLURM" "${matrix[@]}" --print-matrix >"$WORK/matrix.tsv"
"$REPO/launch_scripts/run_batch.sh" "${matrix[@]}" --print-matrix | cmp -s - "$WORK/matrix.tsv" ||
  fail "slurm_batch.sh and run_batch.sh print different matrices"
[ "$(wc -l <"$WORK/matrix.tsv")" -eq 18 ] || fail "expected 2 x 3 x 3 = 18 rows"
scenarios=(passing crossing) planners=(dwb scl sfw) seeds=(3 4 9)
i=0
for s in 0 1; do
  for p in 0 1 2; do
    for k in 0 1 2; do
      expected=$(printf '%d\t%s\t%s\t%s\t%d' "$i" "$REPO/scenarios/${scenarios[$s]}.yaml" "${scenarios[$s]}" "${planners[$p]}" "${seeds[$k]}")
      [ "$(sed -n "$((i + 1))p" "$WORK/matrix.tsv")" = "$expected" ] || fail "row $i is not: $expected"
      i=$((i + 1))
    done
  done
done

# Submission with a stand-in sbatch: it records its arguments and answers a job id.
mkdir -p "$WORK/bin"
cat >"$WORK/bin/sbatch" <<'SB'
#!/usr/bin/env bash
printf '%s\n' "$*" >>"$SBATCH_LOG"
echo "$((4000 + $(wc -l <"$SBATCH_LOG")))"
SB
chmod +x "$WORK/bin/sbatch"
out="$WORK/batch"
# dwb with a parameter file given by a relative path (the tasks get its absolute path).
printf 'dwb:\n  sim_time: 1.5\n' >"$WORK/dwb_params.yaml"
(cd "$WORK" && SBATCH_LOG="$WORK/sbatch.log" PATH="$WORK/bin:$PATH" \
  "$SLURM" "${matrix[@]}" --duration 2 --max-parallel 5 --sbatch-args "--partition=short" --runs-per-task 1 \
  --planner-config dwb=dwb_params.yaml --out "$out" >"$WORK/submit.log")
grep -qx -- "dwb=$WORK/dwb_params.yaml" "$out/slurm_options" || fail "slurm_options lacks the absolute --planner-config"
cmp -s "$out/matrix.tsv" "$WORK/matrix.tsv" || fail "the submitted matrix.tsv differs from --print-matrix"
[ "$(wc -l <"$WORK/sbatch.log")" -eq 2 ] || fail "expected two sbatch calls"
first=$(sed -n 1p "$WORK/sbatch.log") second=$(sed -n 2p "$WORK/sbatch.log")
[[ $first == *"--array=0-17%5"* && $first == *"--partition=short"* && $first == *"--task $out"* ]] || fail "array job: $first"
[[ $second == *"--dependency=afterany:4001"* && $second == *"--aggregate $out"* ]] || fail "summary job: $second"
grep -q 'submitted array job 4001 (18 tasks) and summary job 4002' "$WORK/submit.log" || fail "no submission message"

# Each task finds its row (dry run), e.g. task 13 = crossing, scl ((1 * 3 + 1) * 3 + 1), seed 4.
dry=$(SLURM_ARRAY_TASK_ID=13 "$SLURM" --task "$out" --dry-run)
line=${dry%%$'\n'*}
[ "$line" = "task 13: scenario crossing planner scl seed 4 ($REPO/scenarios/crossing.yaml)" ] || fail "task 13: $line"
rc=0
SLURM_ARRAY_TASK_ID=18 "$SLURM" --task "$out" >/dev/null 2>&1 || rc=$?
[ "$rc" -eq 2 ] || fail "a task beyond the matrix exited $rc, expected 2"

# Two tasks for real (the stored --duration 2 applies), then the aggregation job.
for t in 0 13; do SLURM_ARRAY_TASK_ID=$t "$SLURM" --task "$out" >/dev/null; done
{ [ -s "$out/runs/passing__dwb__seed3/run.json" ] && [ -s "$out/runs/crossing__scl__seed4/run.json" ]; } || fail "task runs missing"
grep -q '"sim_time": 2.0,' "$out/runs/crossing__scl__seed4/run.json" || fail "the task ignored --duration 2"
grep -q "planner parameters from $WORK/dwb_params.yaml" "$out/runs/passing__dwb__seed3/logs/run_experiment.log" ||
  fail "the dwb task did not get --planner-config"
if grep -q "planner parameters" "$out/runs/crossing__scl__seed4/logs/run_experiment.log"; then
  fail "the scl task got dwb's --planner-config"
fi
"$SLURM" --aggregate "$out" >/dev/null
[ "$(wc -l <"$out/summary.csv")" -eq 3 ] || fail "summary.csv should hold the two runs"
grep -q '^crossing,scl,4,time_limit,2,' "$out/summary.csv" || fail "crossing scl seed 4 not in summary.csv"

# A stuck run is finished: its task does not run it again, and the summary keeps it with its status.
json="$out/runs/passing__dwb__seed3/run.json"
sed -i -E 's/"status": *"[a-z_]*"/"status": "stuck"/' "$json"
before=$(stat -c '%Y' "$json")
task_out=$(SLURM_ARRAY_TASK_ID=0 "$SLURM" --task "$out")
[ "$task_out" = "run_batch: passing dwb seed 3: skipped (finished before)" ] || fail "the stuck run's task: $task_out"
[ "$before" = "$(stat -c '%Y' "$json")" ] || fail "the stuck run was run again"
"$SLURM" --aggregate "$out" >/dev/null
grep -q '^passing,dwb,3,stuck,2,' "$out/summary.csv" || fail "the stuck run is not in summary.csv as stuck"

# Several runs per task. The default in the inprocess mode is 10 (18 runs: tasks 0 and 1).
: >"$WORK/sbatch.log"
SBATCH_LOG="$WORK/sbatch.log" PATH="$WORK/bin:$PATH" "$SLURM" "${matrix[@]}" --duration 2 --out "$WORK/tens" \
  >"$WORK/submit_tens.log"
[[ $(sed -n 1p "$WORK/sbatch.log") == *"--array=0-1 "* ]] || fail "default runs per task: $(sed -n 1p "$WORK/sbatch.log")"
grep -q "18 runs in 2 tasks of up to 10" "$WORK/submit_tens.log" || fail "$(cat "$WORK/submit_tens.log")"
# A bad number of runs per task is a usage error (exit 2) naming the option, before anything is written.
for bad in 0 -3 x; do
  rc=0
  "$SLURM" "${matrix[@]}" --runs-per-task "$bad" --out "$WORK/bad_$bad" >"$WORK/bad.log" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || fail "--runs-per-task $bad exited $rc, expected 2"
  grep -q -- "--runs-per-task must be an integer >= 1" "$WORK/bad.log" || fail "--runs-per-task $bad: $(cat "$WORK/bad.log")"
  [ ! -e "$WORK/bad_$bad" ] || fail "--runs-per-task $bad created the batch folder"
done
# 4 per task: 5 tasks; task 3 holds rows 12-15 = crossing scl seeds 3, 4, 9 and crossing sfw seed 3:
# two hunav_run --seeds processes.
chunked="$WORK/chunked"
: >"$WORK/sbatch.log"
SBATCH_LOG="$WORK/sbatch.log" PATH="$WORK/bin:$PATH" "$SLURM" "${matrix[@]}" --duration 2 --runs-per-task 4 \
  --out "$chunked" >/dev/null
[[ $(sed -n 1p "$WORK/sbatch.log") == *"--array=0-4 "* ]] || fail "4 runs per task: $(sed -n 1p "$WORK/sbatch.log")"
dry=$(SLURM_ARRAY_TASK_ID=3 "$SLURM" --task "$chunked" --dry-run)
[ "$(grep -c '^task 3: scenario crossing' <<<"$dry")" -eq 4 ] || fail "task 3 rows: $dry"
[ "$(grep -c -- '--run-chunk' <<<"$dry")" -eq 2 ] || fail "task 3 should be two chunks: $dry"
plain=${dry//\\/}  # printf %q escapes the commas
{ grep -q -- "--run-chunk .* scl 3,4,9 " <<<"$plain" && grep -q -- "--run-chunk .* sfw 3 " <<<"$plain"; } || fail "task 3 chunks: $dry"
rc=0
SLURM_ARRAY_TASK_ID=5 "$SLURM" --task "$chunked" >/dev/null 2>&1 || rc=$?
[ "$rc" -eq 2 ] || fail "task 5 of 5 (beyond the matrix) exited $rc, expected 2"
SLURM_ARRAY_TASK_ID=3 "$SLURM" --task "$chunked" >"$WORK/task3.log"
[ "$(grep -c 'after 2.00 s of simulation' "$WORK/task3.log")" -eq 4 ] || fail "task 3: $(cat "$WORK/task3.log")"
# The same run as task 13 of the one-run-per-task batch: the same result.
fp() { "$BIN/hunav_expect" --run-dir "$1" --get fingerprint; }
[ "$(fp "$chunked/runs/crossing__scl__seed4")" = "$(fp "$out/runs/crossing__scl__seed4")" ] || fail "chunked and single runs differ"
cmp -s <(cut -d, -f2- "$chunked/runs/crossing__scl__seed4/metrics.csv") <(cut -d, -f2- "$out/runs/crossing__scl__seed4/metrics.csv") ||
  fail "chunked and single metrics differ"
# Again: every run is finished, nothing runs.
json="$chunked/runs/crossing__scl__seed9/run.json"
before=$(stat -c '%Y' "$json")
SLURM_ARRAY_TASK_ID=3 "$SLURM" --task "$chunked" >"$WORK/task3_again.log"
[ "$(grep -c 'skipped (finished before)' "$WORK/task3_again.log")" -eq 4 ] || fail "again: $(cat "$WORK/task3_again.log")"
[ "$before" = "$(stat -c '%Y' "$json")" ] || fail "a finished run of a chunk ran again"
# A damaged slurm_runs_per_task: the task stops with exit 2 naming the file, and runs nothing.
echo "four" >"$chunked/slurm_runs_per_task"
rc=0
SLURM_ARRAY_TASK_ID=3 "$SLURM" --task "$chunked" >"$WORK/damaged.log" 2>&1 || rc=$?
[ "$rc" -eq 2 ] || fail "a damaged slurm_runs_per_task exited $rc, expected 2"
grep -q "$chunked/slurm_runs_per_task:1: not a number of runs: 'four'" "$WORK/damaged.log" || fail "$(cat "$WORK/damaged.log")"
echo "PASS slurm_batch_matrix"
