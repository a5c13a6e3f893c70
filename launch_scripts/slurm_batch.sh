#!/usr/bin/env bash
# The matrix of launch_scripts/run_batch.sh on a Slurm cluster: one run per array task, then one
# aggregation job (hunav_summary) once every task has ended. See --help.
set -euo pipefail

script_path=$(readlink -f "${BASH_SOURCE[0]}")
repo_root=$(cd "$(dirname "$script_path")/.." && pwd)
run_batch="$repo_root/launch_scripts/run_batch.sh"
bin_dir=${HUNAV_BIN_DIR:-$repo_root/build/bin}

usage() {
  cat <<'EOF'
Usage:
  launch_scripts/slurm_batch.sh --scenarios LIST --planners LIST --seeds SEEDS --out DIR [options]
      Writes DIR/matrix.tsv and submits a job array (one task per run) and an aggregation job that
      starts once every task has ended (sbatch --dependency=afterany).
  launch_scripts/slurm_batch.sh --scenarios LIST --planners LIST --seeds SEEDS --print-matrix
      Prints the matrix: index (= SLURM_ARRAY_TASK_ID), scenario file, scenario, planner, seed.
  launch_scripts/slurm_batch.sh --task DIR [--dry-run]
      (What each array task runs.) Runs row $SLURM_ARRAY_TASK_ID of DIR/matrix.tsv, unless it is
      finished already (ended goal_reached, time_limit or stuck: run_batch.sh --help); --dry-run
      prints the row and the command instead.
  launch_scripts/slurm_batch.sh --aggregate DIR
      (What the final job runs.) hunav_summary DIR.

Options of a submission (the matrix options are run_batch.sh's: --scenarios, --planners, --seeds,
--mode, --duration, --timeout, --profile, --metrics FILE, --format F, --counterfactual,
--planner-config NAME=FILE, --planner-cmd NAME=CMD):
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

err() { printf 'slurm_batch: error: %s\n' "$*" >&2; }
usage_error() {
  err "$*"
  echo "slurm_batch: see: launch_scripts/slurm_batch.sh --help" >&2
  exit 2
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
    row=$(awk -F'\t' -v i="$SLURM_ARRAY_TASK_ID" '$1 == i { print; exit }' "$out/matrix.tsv")
    [ -n "$row" ] || { err "no row $SLURM_ARRAY_TASK_ID in $out/matrix.tsv"; exit 2; }
    IFS=$'\t' read -r index file scenario planner seed <<<"$row"
    options=()
    if [ -s "$out/slurm_options" ]; then mapfile -t options <"$out/slurm_options"; fi
    cmd=("$run_batch" --run-one "$out" "$file" "$scenario" "$planner" "$seed" "${options[@]}")
    if [ "$dry_run" -eq 1 ]; then
      printf 'task %s: scenario %s planner %s seed %s (%s)\n' "$index" "$scenario" "$planner" "$seed" "$file"
      printf '%q ' "${cmd[@]}"
      echo
      exit 0
    fi
    # A run finished without --counterfactual is not finished for a batch with it (run_batch.sh).
    cf=0
    for o in "${options[@]}"; do [ "$o" != --counterfactual ] || cf=1; done
    HUNAV_BATCH_COUNTERFACTUAL=$cf HUNAV_BIN_DIR=$bin_dir exec "${cmd[@]}"
    ;;
  --aggregate)
    [ "$#" -ge 2 ] || usage_error "--aggregate needs the batch folder"
    exec "$bin_dir/hunav_summary" "$2"
    ;;
esac

# ---------------------------------------------------------------------------------------------------
# Submission
# ---------------------------------------------------------------------------------------------------
matrix_args=() out="" print_matrix=0 dry_run=0 max_parallel="" sbatch_args="" run_options=()
while [ "$#" -gt 0 ]; do
  opt=$1 value=""
  case "$opt" in
    --*=*) value=${opt#*=}; opt=${opt%%=*} ;;
  esac
  case "$opt" in
    -h | --help) usage; exit 0 ;;
    --print-matrix) print_matrix=1 ;;
    --dry-run) dry_run=1 ;;
    --counterfactual) matrix_args+=("$opt"); run_options+=("$opt") ;;
    --scenarios | --planners | --seeds | --out | --mode | --duration | --timeout | --profile | --max-parallel | \
      --sbatch-args | --planner-cmd | --planner-config | --metrics | --format)
      if [ -z "$value" ]; then
        [ "$#" -ge 2 ] || usage_error "$opt needs a value"
        value=$2
        shift
      fi
      case "$opt" in
        --scenarios | --planners | --seeds) matrix_args+=("$opt" "$value") ;;
        --mode | --duration | --timeout | --profile | --planner-cmd | --format) matrix_args+=("$opt" "$value"); run_options+=("$opt" "$value") ;;
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
        --sbatch-args) sbatch_args=$value ;;
      esac ;;
    *) usage_error "unknown argument '$1'" ;;
  esac
  shift
done

# run_batch.sh checks the matrix options and expands the matrix (the same index order).
if [ "$print_matrix" -eq 1 ]; then exec "$run_batch" "${matrix_args[@]}" --print-matrix; fi
[ -n "$out" ] || usage_error "--out DIR is required"
if [ -n "$max_parallel" ] && ! [[ $max_parallel =~ ^[1-9][0-9]*$ ]]; then
  usage_error "--max-parallel must be an integer >= 1 (got '$max_parallel')"
fi
matrix=$("$run_batch" "${matrix_args[@]}" --print-matrix) || exit $?
mkdir -p "$out/runs" || { err "cannot create the batch folder '$out'"; exit 1; }
out=$(cd "$out" && pwd)
printf '%s\n' "$matrix" >"$out/matrix.tsv"
if [ "${#run_options[@]}" -gt 0 ]; then printf '%s\n' "${run_options[@]}" >"$out/slurm_options"; else : >"$out/slurm_options"; fi
count=$(wc -l <"$out/matrix.tsv")
array="0-$((count - 1))"
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
echo "slurm_batch: $count runs -> $out (matrix.tsv)"
if [ "$dry_run" -eq 1 ]; then
  printf '%q ' "${array_cmd[@]}"
  echo
  printf '%q ' "${summary_sbatch[@]:0:2}" --dependency=afterany:ARRAY_JOB_ID "${summary_sbatch[@]:2}"
  echo
  exit 0
fi
command -v sbatch >/dev/null 2>&1 || { err "sbatch is not available (is this a Slurm login node?); try --dry-run"; exit 1; }
array_job=$("${array_cmd[@]}")
array_job=${array_job%%;*}
summary_job=$("${summary_sbatch[@]:0:2}" --dependency="afterany:$array_job" "${summary_sbatch[@]:2}")
echo "slurm_batch: submitted array job $array_job ($count tasks) and summary job ${summary_job%%;*}"
echo "slurm_batch: watch with: squeue -j $array_job; results in $out/summary.md when both are done"
