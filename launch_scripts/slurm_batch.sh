#!/usr/bin/env bash
# The matrix of launch_scripts/run_batch.sh on a Slurm cluster: a few runs per array task (in the
# inprocess mode one hunav_run process per scenario and planner of the task, as run_batch.sh's chunks),
# then one aggregation job (hunav_summary) once every task has ended. See --help.
set -euo pipefail

prog=slurm_batch
# shellcheck source=lib.sh
source "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/lib.sh"
run_batch="$repo_root/launch_scripts/run_batch.sh"

usage() {
  cat <<'EOF'
Usage:
  launch_scripts/slurm_batch.sh --scenarios LIST --planners LIST --seeds SEEDS --out DIR [options]
      Writes DIR/matrix.tsv and submits a job array (--runs-per-task runs per task) and an
      aggregation job that starts once every task has ended (sbatch --dependency=afterany).
  launch_scripts/slurm_batch.sh --scenarios LIST --planners LIST --seeds SEEDS --print-matrix
      Prints the matrix: index, scenario file, scenario, planner, seed (task T holds the rows
      T*N .. T*N+N-1, N = --runs-per-task).
  launch_scripts/slurm_batch.sh --task DIR [--dry-run]
      (What each array task runs.) Runs the rows of task $SLURM_ARRAY_TASK_ID in DIR/matrix.tsv,
      except those finished already (ended goal_reached, time_limit or stuck: run_batch.sh --help):
      in the inprocess mode one hunav_run --seeds process per scenario and planner among them
      (run_batch.sh's chunks: the same result files), else one run_experiment.sh per row; --dry-run
      prints the rows and the commands instead.
  launch_scripts/slurm_batch.sh --aggregate DIR
      (What the final job runs.) hunav_summary DIR.

Options of a submission (the matrix options are run_batch.sh's: --scenarios, --planners, --seeds,
--mode, --duration, --timeout, --profile, --metrics FILE, --format F, --counterfactual,
--no-states-csv, --no-per-tick-files,
--planner-config NAME=FILE, --planner-cmd NAME=CMD):
  --runs-per-task N    runs per array task (default: 10 in the inprocess mode, where a task's runs
                       share a process; 1 in lockstep and realtime); the task's wall-clock need is
                       the sum of its runs' (give sbatch --time accordingly)
  --max-parallel N     at most N tasks at a time (sbatch --array=0-M%N)
  --sbatch-args "..."  more sbatch options for both jobs (e.g. "--partition=short --time=00:20:00")
  --dry-run            print the sbatch commands instead of submitting them
  -h, --help           show this help

The batch folder has run_batch.sh's layout (runs/<scenario>__<planner>__seed<N>/, matrix.tsv, the
summary files), so run_batch.sh and this script can fill the same folder, and either can resume it.
DIR must be on a file system every node sees; each task uses one CPU (--cpus-per-task=1) and, in the
default inprocess mode, no network. The run options of the submission are stored in DIR/slurm_options
and read by every task. Environment: HUNAV_BIN_DIR (binaries, default <repo>/build/bin).
EOF
}

# ---------------------------------------------------------------------------------------------------
# Inside the cluster: one task, or the aggregation
# ---------------------------------------------------------------------------------------------------
case "${1:-}" in
  --task)
    [ "$#" -ge 2 ] || usage_error "--task needs the batch folder"
    out=$(cd "$2" && pwd)
    dry_run=0
    [ "${3:-}" != --dry-run ] || dry_run=1
    [ -n "${SLURM_ARRAY_TASK_ID:-}" ] || usage_error "--task: SLURM_ARRAY_TASK_ID is not set (run it as an array task)"
    [[ $SLURM_ARRAY_TASK_ID =~ ^[0-9]+$ ]] || usage_error "--task: SLURM_ARRAY_TASK_ID is not a number"
    per_task=1
    [ ! -s "$out/slurm_runs_per_task" ] || per_task=$(cat "$out/slurm_runs_per_task")
    is_count "$per_task" || { err "$out/slurm_runs_per_task:1: not a number of runs: '$per_task'"; exit 2; }
    first=$((SLURM_ARRAY_TASK_ID * per_task))
    rows=$(awk -F'\t' -v a="$first" -v b="$((first + per_task))" '$1 >= a && $1 < b' "$out/matrix.tsv")
    [ -n "$rows" ] || { err "no row for task $SLURM_ARRAY_TASK_ID (rows $first..$((first + per_task - 1))) in $out/matrix.tsv"; exit 2; }
    options=()
    if [ -s "$out/slurm_options" ]; then mapfile -t options <"$out/slurm_options"; fi
    mode=inprocess
    for ((k = 0; k + 1 < ${#options[@]}; k++)); do [ "${options[k]}" != --mode ] || mode=${options[k + 1]}; done
    # The commands of the task: in the inprocess mode one chunk per scenario and planner (consecutive
    # rows), else one run per row.
    commands=()
    group="" seeds=""
    flush_group() {
      [ -n "$seeds" ] || return 0
      IFS=$'\t' read -r g_file g_scenario g_planner <<<"$group"
      commands+=("$(printf '%q ' "$run_batch" --run-chunk "$out" "$g_file" "$g_scenario" "$g_planner" "$seeds" "${options[@]}")")
      seeds=""
    }
    while IFS=$'\t' read -r _ file scenario planner seed; do
      [ "$dry_run" -eq 0 ] || printf 'task %s: scenario %s planner %s seed %s (%s)\n' "$SLURM_ARRAY_TASK_ID" "$scenario" "$planner" "$seed" "$file"
      if [ "$mode" = inprocess ] && [ "$per_task" -gt 1 ]; then
        [ "$file"$'\t'"$scenario"$'\t'"$planner" = "$group" ] || flush_group
        group="$file"$'\t'"$scenario"$'\t'"$planner"
        seeds=${seeds:+$seeds,}$seed
      else
        commands+=("$(printf '%q ' "$run_batch" --run-one "$out" "$file" "$scenario" "$planner" "$seed" "${options[@]}")")
      fi
    done <<<"$rows"
    flush_group
    if [ "$dry_run" -eq 1 ]; then
      printf '%s\n' "${commands[@]}"
      exit 0
    fi
    # A run finished without --counterfactual is not finished for a batch with it (run_batch.sh).
    cf=0
    for o in "${options[@]}"; do [ "$o" != --counterfactual ] || cf=1; done
    # One CPU per task: each hunav_run on one thread (run_batch.sh --run-chunk passes --single-thread).
    export HUNAV_BATCH_COUNTERFACTUAL=$cf HUNAV_BIN_DIR=$bin_dir HUNAV_BATCH_SINGLE_THREAD=1
    # Every command runs (a failed run does not stop the task's others); the task's exit code is the
    # last non-zero one.
    task_rc=0
    for c in "${commands[@]}"; do
      rc=0
      eval "$c" || rc=$?
      [ "$rc" -eq 0 ] || task_rc=$rc
    done
    exit "$task_rc"
    ;;
  --aggregate)
    [ "$#" -ge 2 ] || usage_error "--aggregate needs the batch folder"
    exec "$bin_dir/hunav_summary" "$2"
    ;;
esac

# ---------------------------------------------------------------------------------------------------
# Submission
# ---------------------------------------------------------------------------------------------------
matrix_args=() out="" print_matrix=0 dry_run=0 max_parallel="" sbatch_args="" run_options=() runs_per_task="" mode=inprocess
while [ "$#" -gt 0 ]; do
  split_option "$1"
  case "$opt" in
    -h | --help) usage; exit 0 ;;
    --print-matrix) print_matrix=1 ;;
    --dry-run) dry_run=1 ;;
    --counterfactual | --no-states-csv | --no-per-tick-files) matrix_args+=("$opt"); run_options+=("$opt") ;;
    --scenarios | --planners | --seeds | --out | --mode | --duration | --timeout | --profile | --max-parallel | \
      --sbatch-args | --planner-cmd | --planner-config | --metrics | --format | --runs-per-task)
      # An empty value is passed on: run_batch.sh judges the matrix options, and --sbatch-args "" is no extra option.
      option_value_or_empty "$@"
      case "$opt" in
        --scenarios | --planners | --seeds) matrix_args+=("$opt" "$value") ;;
        --mode | --duration | --timeout | --profile | --planner-cmd | --format)
          [ "$opt" != --mode ] || mode=$value
          matrix_args+=("$opt" "$value"); run_options+=("$opt" "$value") ;;
        --metrics)
          # The tasks may start in another folder: the file by its absolute path.
          [ ! -f "$value" ] || value=$(readlink -f "$value")
          matrix_args+=("$opt" "$value"); run_options+=("$opt" "$value") ;;
        --planner-config)
          # The tasks may start in another folder: the file by its absolute path.
          [[ $value != *=* ]] || [ ! -f "${value#*=}" ] || value="${value%%=*}=$(readlink -f "${value#*=}")"
          matrix_args+=("$opt" "$value"); run_options+=("$opt" "$value") ;;
        --out) out=$value ;;
        --max-parallel) max_parallel=$value ;;
        --runs-per-task) runs_per_task=$value ;;
        --sbatch-args) sbatch_args=$value ;;
      esac ;;
    *) usage_error "unknown argument '$1'" ;;
  esac
  shift $((1 + taken))
done

# run_batch.sh checks the matrix options and expands the matrix (the same index order).
if [ "$print_matrix" -eq 1 ]; then exec "$run_batch" "${matrix_args[@]}" --print-matrix; fi
[ -n "$out" ] || usage_error "--out DIR is required"
check_count --max-parallel "$max_parallel"
check_count --runs-per-task "$runs_per_task"
# In the inprocess mode a task's runs share one hunav_run process per scenario and planner.
[ -n "$runs_per_task" ] || { [ "$mode" = inprocess ] && runs_per_task=10 || runs_per_task=1; }
matrix=$("$run_batch" "${matrix_args[@]}" --print-matrix) || exit $?
mkdir -p "$out/runs" || die "cannot create the batch folder '$out'"
out=$(cd "$out" && pwd)
printf '%s\n' "$matrix" >"$out/matrix.tsv"
if [ "${#run_options[@]}" -gt 0 ]; then printf '%s\n' "${run_options[@]}" >"$out/slurm_options"; else : >"$out/slurm_options"; fi
count=$(wc -l <"$out/matrix.tsv")
echo "$runs_per_task" >"$out/slurm_runs_per_task"
tasks=$(((count + runs_per_task - 1) / runs_per_task))
array="0-$((tasks - 1))"
[ -z "$max_parallel" ] || array+="%$max_parallel"

# shellcheck disable=SC2206 # sbatch_args holds options, split on spaces on purpose
extra=($sbatch_args)
mkdir -p "$out/slurm_logs"
# --wrap runs this very file (sbatch would run a spooled copy of a script, far from the repository).
task_cmd=$(printf '%q ' env "HUNAV_BIN_DIR=$bin_dir" bash "$script_path" --task "$out")
summary_cmd=$(printf '%q ' env "HUNAV_BIN_DIR=$bin_dir" bash "$script_path" --aggregate "$out")
array_cmd=(sbatch --parsable --job-name=hunav_batch --array="$array" --cpus-per-task=1
  --output="$out/slurm_logs/task-%A_%a.log" "${extra[@]}" --wrap="$task_cmd")
summary_sbatch=(sbatch --parsable --job-name=hunav_summary --cpus-per-task=1
  --output="$out/slurm_logs/summary-%j.log" "${extra[@]}" --wrap="$summary_cmd")
log "$count runs in $tasks tasks of up to $runs_per_task -> $out (matrix.tsv)"
if [ "$dry_run" -eq 1 ]; then
  printf '%q ' "${array_cmd[@]}"
  echo
  printf '%q ' "${summary_sbatch[@]:0:2}" --dependency=afterany:ARRAY_JOB_ID "${summary_sbatch[@]:2}"
  echo
  exit 0
fi
command -v sbatch >/dev/null 2>&1 || die "sbatch is not available (is this a Slurm login node?); try --dry-run"
array_job=$("${array_cmd[@]}")
array_job=${array_job%%;*}
summary_job=$("${summary_sbatch[@]:0:2}" --dependency="afterany:$array_job" "${summary_sbatch[@]:2}")
log "submitted array job $array_job ($tasks tasks) and summary job ${summary_job%%;*}"
log "watch with: squeue -j $array_job; results in $out/summary.md when both are done"
