#!/usr/bin/env bash
# Does the human model change the verdict? Runs the HuNavSim paper's matrix (passing, crossing,
# combined x dwb, scl, sfw x seeds) once per people model (run_batch.sh --people-model, each into
# OUT/<model>/ with its own summary), then writes which of the paper's planner orderings hold under
# every model and which flip (hunav_summary OUT --models ...: OUT/model_robustness.csv and .md). See --help.
set -euo pipefail

prog=model_robustness
# shellcheck source=launch_scripts/lib.sh
source "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/lib.sh"

usage() {
  cat <<'EOF2'
Usage: launch_scripts/model_robustness.sh --out DIR [options]

Runs the paper's matrix under each people model (one run_batch.sh batch per model into DIR/<model>/,
resumable like any batch), then compares the batches' "paper vs ours" planner orderings: DIR/
model_robustness.csv (one row per ordering: the paper's relation, each model's, and holds / fails /
flips) and DIR/model_robustness.md (counts per scenario and the table). experiments/README.md,
"Model robustness".

  --out DIR          the folder of the batches and the comparison (required)
  --models LIST      comma-separated people models (default:
                     sfm,sfm_calibrated,orca,orca_calibrated,ttc,ttc_calibrated)
  --seeds SEEDS      seeds of every batch (default 1-10; run_batch.sh's syntax)
  --scenarios LIST   default passing,crossing,combined (the paper's)
  --planners LIST    default dwb,scl,sfw (the paper's)
  --jobs N           runs at a time in each batch (default: run_batch.sh's)
  --duration S       simulated time limit of every run (default: each scenario's time_limit)
  -h, --help         show this help
Exit 0: written; 1: a batch or the comparison failed; 2: bad arguments.
EOF2
}

out="" models=sfm,sfm_calibrated,orca,orca_calibrated,ttc,ttc_calibrated seeds=1-10
scenarios=passing,crossing,combined planners=dwb,scl,sfw jobs="" duration=""
while [ "$#" -gt 0 ]; do
  split_option "$1"
  case "$opt" in
    -h | --help) usage; exit 0 ;;
    --out | --models | --seeds | --scenarios | --planners | --jobs | --duration)
      option_value "$@"
      case "$opt" in
        --out) out=$value ;;
        --models) models=$value ;;
        --seeds) seeds=$value ;;
        --scenarios) scenarios=$value ;;
        --planners) planners=$value ;;
        --jobs) jobs=$value ;;
        --duration) duration=$value ;;
      esac ;;
    *) usage_error "unknown argument '$1'" ;;
  esac
  shift $((1 + taken))
done
[ -n "$out" ] || usage_error "--out DIR is required"
check_count --jobs "$jobs"
check_seconds --duration "$duration"
IFS=',' read -r -a model_list <<<"$models"
[ "${#model_list[@]}" -gt 0 ] || usage_error "--models needs at least one model"
for m in "${model_list[@]}"; do
  [[ $m =~ ^[A-Za-z0-9._-]+$ ]] || usage_error "--models: '$m' is not a model name (letters, digits, . _ -; a file: give its name without the folder)"
done
need_bin hunav_summary
mkdir -p "$out" || die "cannot create '$out'"

batch_args=(--scenarios "$scenarios" --planners "$planners" --seeds "$seeds")
[ -z "$jobs" ] || batch_args+=(--jobs "$jobs")
[ -z "$duration" ] || batch_args+=(--duration "$duration")
for m in "${model_list[@]}"; do
  log "people model $m -> $out/$m"
  "$repo_root/launch_scripts/run_batch.sh" "${batch_args[@]}" --people-model "$m" --out "$out/$m" ||
    die "the batch of $m failed (see $out/$m/batch.log)"
done
"$bin_dir/hunav_summary" "$out" --models "$models" || die "the comparison failed"
log "wrote $out/model_robustness.csv and $out/model_robustness.md"
