#!/usr/bin/env bash
# Runs a matrix of episodes (scenarios x planners x seeds) in parallel with GNU parallel, one
# run_experiment.sh per run, each into its own folder; skips runs already finished (resumable); then
# aggregates the batch with hunav_summary. See --help.
set -euo pipefail

# SIGINT / SIGTERM at any moment: the batch runs in a child process with a process group of its own;
# this process starts it, waits for it and, on a signal, sends SIGINT to that group (the child ends;
# GNU parallel sends its jobs SIGTERM and gives them 30 s to write what they recorded), waits until
# the group is gone, and exits 130 / 143. Nothing else runs here: bash 5.2 can fail to parse a trap's
# action when the signal comes while it expands a command substitution (exit 2, "unexpected EOF
# while looking for matching `)'"), and this process expands none.
if [ -z "${HUNAV_BATCH_CHILD:-}" ] && [ "${1:-}" != --run-one ] && [ "${1:-}" != --run-chunk ]; then
  # shellcheck disable=SC2317  # reachable: the traps below call it
  stop_batch() {
    trap '' INT TERM
    [ -n "${batch_pid:-}" ] || exit "$2"
    kill -s INT -- "-$batch_pid" 2>/dev/null || true
    local waited=0
    while kill -0 -- "-$batch_pid" 2>/dev/null && [ "$waited" -lt 600 ]; do  # 60 s at most
      sleep 0.1
      waited=$((waited + 1))
    done
    kill -s KILL -- "-$batch_pid" 2>/dev/null || true
    echo "run_batch: interrupted by SIG$1: the jobs were stopped; run the same command again to finish the batch" >&2
    exit "$2"
  }
  trap 'stop_batch INT 130' INT
  trap 'stop_batch TERM 143' TERM
  set -m  # the child's own process group
  HUNAV_BATCH_CHILD=1 "$BASH" "$0" "$@" &
  batch_pid=$!
  set +m
  batch_rc=0
  wait "$batch_pid" || batch_rc=$?
  exit "$batch_rc"
fi

prog=run_batch
# shellcheck source=lib.sh
source "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/lib.sh"

usage() {
  cat <<'EOF'
Usage: launch_scripts/run_batch.sh --scenarios LIST --planners LIST --seeds SEEDS --out DIR [options]

Runs every (scenario, planner, seed) of the matrix, several at a time, then writes the batch summary
(hunav_summary DIR). In the inprocess mode one hunav_run process runs the whole matrix, --jobs episodes
at a time on threads of its own (hunav_run --runs: the same result files as one process per run, at
the speed of the simulation); in lockstep and realtime each run is a run_experiment.sh, several at a
time with GNU parallel.

  --scenarios LIST   comma-separated scenario names (scenarios/NAME.yaml) or YAML files
  --planners LIST    comma-separated planners: dwb, scl, sfw, none, or names given --planner-cmd
  --seeds SEEDS      seeds: A-B, N, or a comma-separated mix (1-10 or 1-5,8,20-22)
  --out DIR          the batch folder
  --jobs N           runs at a time, at most 1024 (default: the number of CPUs)
  --mode MODE        inprocess (default), lockstep or realtime (separate processes, each run in its own
                     private network namespace, made by run_experiment.sh)
  --duration S       simulated time limit of every run (default: each scenario's time_limit)
  --timeout S        wall-clock limit of every run (run_experiment.sh --timeout, hunav_run --runs' limit:
                     the run is stopped, aborted, and runs again next time); default, per run:
                     HUNAV_BATCH_TIMEOUT_MARGIN (60) + 2 x the run's time limit (--duration, else its
                     scenario's time_limit, else 60) s, so a run that hangs cannot hold the batch
  --profile P        metrics profile: default or hunav_v1
  --metrics FILE     metric selection of every run (run_experiment.sh --metrics; HuNavSim's
                     metrics.yaml too); default: each scenario's evaluation.metrics
  --format F         csv (default) or hunav_txt (run_experiment.sh --format)
  --people-model M   the model every person of every run walks with (run_experiment.sh
                     --people-model): sfm (HuNavSim's, the default), sfm_calibrated, orca,
                     orca_calibrated, ttc, ttc_calibrated or a parameter file; recorded in each run's
                     run.json and metrics.csv and in the summary. One batch folder per model: runs
                     finished before are kept whatever model they ran
  --counterfactual   also run every episode with the same seed without the robot and measure the
                     robot's effect on people (run_experiment.sh --counterfactual): counterfactual.csv
                     in each run folder, the counterfactual_* metrics in metrics.csv, and a section of
                     summary.md comparing the planners on them (docs/metrics.md); about twice the time.
                     A run finished before without it is run again
  --no-states-csv, --no-per-tick-files   (inprocess) runs without states.csv, or without the per-tick
                     metric files (hunav_run's options): the same metrics, summary and junit.xml, about
                     30% less CPU per run when only the metrics matter; the report's run pages then have
                     no replay. --no-states-csv not with --counterfactual (which reads states.csv back)
  --planner-config NAME=FILE   parameters of built-in planner NAME (run_experiment.sh --planner-config);
                     repeat for several planners
  --planner-cmd NAME=CMD       planner NAME of --planners is your program CMD (run_experiment.sh
                     --planner-cmd; needs --mode lockstep or realtime); repeat for several
  --print-matrix     print the matrix (index, scenario file, scenario, planner, seed; tab-separated)
                     and exit; the index order is scenario, then planner, then seed
  -h, --help         show this help

Layout of DIR:
  runs/<scenario>__<planner>__seed<N>/   the output folder of each run (run_experiment.sh --out),
                                         with its console output in logs/run_experiment.log
                                         (inprocess: logs/hunav_run.log)
  logs/hunav_run.log                     inprocess: the rest of hunav_run's console output
  logs/runs.tsv                          inprocess: the runs the last invocation handed to hunav_run
                                         (hunav_run --runs; its errors name lines of it)
  matrix.tsv                             the matrix (as --print-matrix)
  batch.log                              one line per invocation: arguments, duration, counts
  summary.csv, summary_stats.csv, paired.csv, summary.md   the aggregation (hunav_summary)
  paper_comparison.csv, paper_orderings.csv   the paper's means beside ours (passing, crossing, combined)
  expectations.csv                       the expect: verdicts, a row per run and condition (hunav_summary)
  junit.xml                              JUnit XML of the scenarios' expect: conditions (hunav_expect
                                         --junit): one <testcase> per run and condition, classname
                                         <scenario>.<planner>, name "seed <N>: <metric> <condition>";
                                         a failed condition is a <failure> with the value, a run that did
                                         not finish an <error>; runs without expect: give no test case

A run is finished when its folder holds a metrics.csv and a run.json with "complete": true and its
episode ended on its own (status goal_reached, time_limit or stuck: a stuck run is a result, a
failure to reach the goal, kept in the statistics); a second invocation with the same DIR runs only
the others (an interrupted, aborted or failed run starts again from an empty folder, and until then
stays out of the summary's statistics). Exit status: 0 when every run finished and the
summary was written; 1 when some run did not finish (the summary covers the others) or exited
non-zero after writing complete results (they are kept and count as finished); 2 on bad arguments;
3 when every run finished but some failed its scenario's expect: conditions (junit.xml says which; a
run that fails them is a finished run, not retried); 130 / 143 when stopped by SIGINT / SIGTERM (at
any moment: the running jobs get SIGTERM and 30 s to write what they recorded; the same command
finishes the batch later). One batch per DIR at a time (another on the same DIR: exit 2).

Environment: HUNAV_BIN_DIR (binaries, default <repo>/build/bin), HUNAV_BATCH_TIMEOUT_MARGIN (s, default
60: see --timeout), and what run_experiment.sh reads.
EOF
}

# finished RUN_DIR: the episode ended on its own (goal reached, time limit or stuck; not aborted by a
# signal or a silent component) and its results were written. The statuses of episode_status.hpp.
finished() {
  local is_done
  IFS=$'\t' read -r _ is_done _ < <(run_states "$1")
  [ "$is_done" = 1 ]
}

# run_states RUN_DIR...: one line per folder, in the order given, tab-separated: the folder, 1 when
# finished() holds for it (else 0), its run.json's status, reason and sim_time (- for none), and 1
# when its expect.json has a failed condition. run.json and expect.json read by a JSON parser
# (hunav_expect --states), one process for a whole chunk or batch: a grep per question and per run
# was most of a batch's shell time.
run_states() {
  [ "$#" -gt 0 ] || return 0
  need_bin hunav_expect
  local args=(--states "$@")
  [ "${HUNAV_BATCH_COUNTERFACTUAL:-0}" -eq 0 ] || args+=(--counterfactual)
  "$bin_dir/hunav_expect" "${args[@]}"
}

# judge_run RUN_DIR RC LOG: what became of a run that exited RC: sets `result` (the progress line's
# text) and `rc` (0 for a finished run, as a failed expect: condition is a result, not an error).
# Reads the run's state from `states` (run_states' lines by folder) when it holds it.
declare -A states=()
judge_run() {
  local run_dir=$1 log=$3 is_done=0 status="" reason="" sim="" expect_failed=0 line
  rc=$2
  line=${states[$run_dir]-}
  [ -n "$line" ] || line=$(run_states "$run_dir")
  IFS=$'\t' read -r _ is_done status reason sim expect_failed <<<"$line"
  [ "$status" != - ] || status=""
  [ "$reason" != - ] || reason=""
  [ "$sim" != - ] || sim=""
  if [ "$is_done" -eq 1 ] && { [ "$rc" -eq 3 ] || [ "$expect_failed" -eq 1 ]; }; then
    # A finished run that failed its scenario's expect: conditions: a result (junit.xml), not an error.
    result="$status, expectations FAILED (see $run_dir/expect.json)"
    rc=0
  elif [ "$is_done" -eq 1 ] && [ "$rc" -ne 0 ]; then
    # Complete results, but the run did not exit cleanly (a crash at exit?): keep them, say so.
    result="results complete, but the run exited $rc (see $log)"
    printf '%s\n' "${run_dir##*/}" >>"$out/.exited_nonzero"
  elif [ "$is_done" -eq 1 ]; then
    printf -v sim '%.2f' "$sim"
    result="$status after $sim s of simulation"
  elif [ -s "$run_dir/run.json" ]; then
    # It ended, but not on its own (interrupted, a component gone silent): not a result.
    result="NOT FINISHED: ${status:-no status}${reason:+ ($reason)}, exit $rc; runs again next time (see $log)"
    [ "$rc" -ne 0 ] || rc=1
  else
    result="FAILED (exit $rc, see $log)"
    [ "$rc" -ne 0 ] || rc=1
  fi
}

# finished_among RUN_DIR...: sets `finished_dirs` (the finished ones among them, as keys).
declare -A finished_dirs=()
finished_among() {
  local dir is_done
  finished_dirs=()
  [ "$#" -gt 0 ] || return 0
  while IFS=$'\t' read -r dir is_done _; do
    [ "$is_done" -eq 0 ] || finished_dirs[$dir]=1
  done < <(run_states "$@")
}

# progress LABEL RESULT [LABEL RESULT...]: one line per run, counted across the parallel jobs of this
# host (a chunk's runs under one lock).
progress() {
  if [ -n "${HUNAV_BATCH_TOTAL:-}" ]; then
    {
      flock 9
      done_count=0
      [ ! -s "$out/.progress" ] || read -r done_count <"$out/.progress"
      while [ "$#" -ge 2 ]; do
        done_count=$((done_count + 1))
        printf 'run_batch: [%d/%s] %s: %s\n' "$done_count" "$HUNAV_BATCH_TOTAL" "$1" "$2"
        shift 2
      done
      echo "$done_count" >"$out/.progress"
    } 9>"$out/.progress.lock"
  else
    while [ "$#" -ge 2 ]; do
      printf 'run_batch: %s: %s\n' "$1" "$2"
      shift 2
    done
  fi
}

# run_limit FILE DURATION: the default wall-clock limit of one run (see --help, --timeout): a realtime
# run takes its time limit in wall clock, the other modes far less; the margin covers start-up and
# writing the results.
run_limit() {
  local limit=$2
  [ -n "$limit" ] || limit=$(sed -n -E 's/^time_limit:[[:space:]]*([0-9.eE+]+)[[:space:]]*(#.*)?$/\1/p' "$1" | head -n 1)
  awk -v l="${limit:-60}" -v m="${HUNAV_BATCH_TIMEOUT_MARGIN:-60}" 'BEGIN { printf "%.0f", m + 2 * l }'
}

# The run options of PLANNER from a job's arguments, with the --planner-cmd/--planner-config of that
# planner only: sets run_options, and timeout/duration when given.
planner_options() {
  local planner=$1
  shift
  run_options=() given_timeout="" given_duration=""
  while [ "$#" -gt 0 ]; do
    case "$1" in
      --planner-cmd | --planner-config)
        [ "${2%%=*}" != "$planner" ] || run_options+=("$1" "${2#*=}")
        shift 2 ;;
      --timeout) given_timeout=$2; shift 2 ;;
      --duration) given_duration=$2; run_options+=("$1" "$2"); shift 2 ;;
      *) run_options+=("$1"); shift ;;
    esac
  done
}

# ---------------------------------------------------------------------------------------------------
# One run (what each parallel job executes in the lockstep and realtime modes):
#   --run-one DIR FILE SCENARIO PLANNER SEED [run_experiment options]
# ---------------------------------------------------------------------------------------------------
if [ "${1:-}" = --run-one ]; then
  shift
  out=$1 file=$2 scenario=$3 planner=$4 seed=$5
  shift 5
  planner_options "$planner" "$@"
  run_options+=(--timeout "${given_timeout:-$(run_limit "$file" "$given_duration")}")
  run_dir="$out/runs/${scenario}__${planner}__seed${seed}"
  label="$scenario $planner seed $seed"
  if finished "$run_dir"; then
    result="skipped (finished before)"
    rc=0
  else
    rm -rf "$run_dir"
    mkdir -p "$run_dir/logs"
    rc=0
    "$repo_root/launch_scripts/run_experiment.sh" --scenario "$file" --planner "$planner" --seed "$seed" \
      --out "$run_dir" "${run_options[@]}" >"$run_dir/logs/run_experiment.log" 2>&1 </dev/null || rc=$?
    judge_run "$run_dir" "$rc" "$run_dir/logs/run_experiment.log"
  fi
  progress "$label" "$result"
  exit "$rc"
fi

# ---------------------------------------------------------------------------------------------------
# A chunk of runs (what each task of slurm_batch.sh executes): one hunav_run process runs
# several seeds of one scenario and planner (hunav_run --seeds: the same result files as one process
# per run), so that a batch costs its simulations, not a shell and a process per run.
#   --run-chunk DIR FILE SCENARIO PLANNER SEEDS(comma-separated) [run_experiment options]
# Seeds whose run is finished already are reported as skipped and not run again (slurm_batch.sh's
# tasks hand over their whole range; run_batch.sh itself leaves them out of its chunks).
# ---------------------------------------------------------------------------------------------------
if [ "${1:-}" = --run-chunk ]; then
  shift
  out=$1 file=$2 scenario=$3 planner=$4 seed_csv=$5
  shift 5
  planner_options "$planner" "$@"
  IFS=',' read -r -a given_seeds <<<"$seed_csv"
  # The run folders, without a subshell per seed.
  given_dirs=()
  for seed in "${given_seeds[@]}"; do given_dirs+=("$out/runs/${scenario}__${planner}__seed$seed"); done
  finished_among "${given_dirs[@]}"
  chunk_seeds=() chunk_dirs=() skipped=()
  for k in "${!given_seeds[@]}"; do
    seed=${given_seeds[k]} run_dir=${given_dirs[k]}
    if [ -n "${finished_dirs[$run_dir]-}" ]; then
      skipped+=("$scenario $planner seed $seed" "skipped (finished before)")
    else
      chunk_seeds+=("$seed")
      chunk_dirs+=("$run_dir")
    fi
  done
  [ "${#skipped[@]}" -eq 0 ] || progress "${skipped[@]}"
  [ "${#chunk_seeds[@]}" -gt 0 ] || exit 0
  seed_csv=$(IFS=','; echo "${chunk_seeds[*]}")
  run_args=()
  for ((k = 0; k < ${#run_options[@]}; k++)); do
    case "${run_options[k]}" in
      --mode) k=$((k + 1)) ;;  # inprocess: hunav_run itself
      *) run_args+=("${run_options[k]}") ;;
    esac
  done
  # The wall-clock limit applies to the chunk: the sum of its runs' limits.
  limit=$((${#chunk_seeds[@]} * ${given_timeout:-$(run_limit "$file" "$given_duration")}))
  rm -rf "${chunk_dirs[@]}"
  mkdir -p "$out/logs"
  chunk_log="$out/logs/${scenario}__${planner}__seeds${chunk_seeds[0]}-${chunk_seeds[${#chunk_seeds[@]} - 1]}.log"
  reason_file="$chunk_log.stop"
  rm -f "$reason_file"
  # hunav_run stays in this job's process group (lib.sh's start without use_own_sessions), so a
  # terminal's Ctrl-C reaches it too.
  # Every core busy with a chunk of its own (or a Slurm task's one CPU): each hunav_run on one thread.
  [ "${HUNAV_BATCH_SINGLE_THREAD:-0}" -eq 0 ] || run_args+=(--single-thread)
  start hunav_run "$chunk_log" env HUNAV_STOP_REASON_FILE="$reason_file" "$bin_dir/hunav_run" --scenario "$file" \
    --planner "$planner" --seeds "$seed_csv" --folder-label "$scenario" --out "$out/runs" --quiet "${run_args[@]}"
  # Past the limit: the reason first (the run is then recorded as aborted with it), then SIGTERM.
  # shellcheck disable=SC2317 # run by the watchdog
  chunk_timed_out() {
    echo "wall-clock timeout: the chunk ran longer than ${limit} s" >"$reason_file"
    signal hunav_run TERM
  }
  watchdog "$limit" chunk_timed_out
  # Ctrl-C or parallel's SIGTERM: hunav_run ends its episode and writes what it recorded.
  trap 'signal hunav_run TERM' INT TERM
  collect hunav_run
  end_watchdog
  rc=${code_of[hunav_run]}
  # Each run's part of the chunk's console output (up to its "results in" line), in its folder (the
  # folders hunav_run made; their logs/ made here in one go).
  made=()
  for run_dir in "${chunk_dirs[@]}"; do [ ! -d "$run_dir" ] || made+=("$run_dir/logs"); done
  [ "${#made[@]}" -eq 0 ] || mkdir -p "${made[@]}"
  # (The list through the environment: awk -v would read backslashes in the paths as escapes.)
  HUNAV_LOG_DIRS="$(printf '%s\n' "${made[@]}")" awk 'BEGIN { n = split(ENVIRON["HUNAV_LOG_DIRS"], m, "\n"); for (i = 1; i <= n; i++) has[m[i]] = 1 }
       { buf = buf $0 "\n" } /^results in / { log_file = substr($0, 12) "/logs"; if (log_file in has) {
         log_file = log_file "/hunav_run.log"; printf "%s", buf >log_file; close(log_file) } buf = "" }' "$chunk_log"
  states=()
  while IFS= read -r line; do states[${line%%$'\t'*}]=$line; done < <(run_states "${chunk_dirs[@]}")
  hunav_rc=$rc chunk_rc=0 lines=()
  for k in "${!chunk_seeds[@]}"; do
    run_dir=${chunk_dirs[k]}
    # hunav_run's exit code covers the chunk: judge each run by its files (a run that did not finish
    # counts as failed whatever the code).
    run_rc=0
    IFS=$'\t' read -r _ is_done _ <<<"${states[$run_dir]}"
    [ "$is_done" = 1 ] || run_rc=$((hunav_rc == 0 ? 1 : hunav_rc))
    judge_run "$run_dir" "$run_rc" "$chunk_log"
    lines+=("$scenario $planner seed ${chunk_seeds[k]}" "$result")
    [ "$rc" -eq 0 ] || chunk_rc=$rc
  done
  progress "${lines[@]}"
  rm -f "$reason_file"
  exit "$chunk_rc"
fi

# ---------------------------------------------------------------------------------------------------
# Arguments
# ---------------------------------------------------------------------------------------------------
scenarios="" planners="" seeds="" out="" jobs="" mode=inprocess duration="" timeout="" profile="" metrics="" format=""
people_model=""
print_matrix=0 counterfactual=0 no_states_csv=0 no_per_tick_files=0
planner_specs=()  # --planner-cmd NAME=CMD and --planner-config NAME=FILE, as option-value pairs
declare -A planner_cmd_of=()
while [ "$#" -gt 0 ]; do
  split_option "$1"
  case "$opt" in
    -h | --help) usage; exit 0 ;;
    --print-matrix) print_matrix=1 ;;
    --counterfactual) counterfactual=1 ;;
    --no-states-csv) no_states_csv=1 ;;
    --no-per-tick-files) no_per_tick_files=1 ;;
    --planner-cmd | --planner-config)
      [ "$inline" -eq 1 ] || [ "$#" -ge 2 ] || usage_error "$opt needs NAME=VALUE"
      option_value_or_empty "$@"
      [[ $value == ?*=?* ]] || usage_error "$opt needs NAME=VALUE (got '$value')"
      spec_name=${value%%=*} spec_value=${value#*=}
      [[ $spec_name =~ ^[A-Za-z0-9.-]+(_[A-Za-z0-9.-]+)*$ ]] || usage_error "$opt: '$spec_name' is not a planner name (letters, digits, . _ -)"
      case "$spec_value" in *$'\n'*) usage_error "$opt $spec_name: the value must be one line" ;; esac
      if [ "$opt" = --planner-config ]; then
        check_file "--planner-config $spec_name" "$spec_value"
        spec_value=$(readlink -f "$spec_value")
      else
        planner_cmd_of[$spec_name]=$spec_value
      fi
      for ((k = 0; k < ${#planner_specs[@]}; k += 2)); do
        [ "${planner_specs[k]}" != "$opt" ] || [ "${planner_specs[k + 1]%%=*}" != "$spec_name" ] ||
          usage_error "$opt: planner '$spec_name' given twice"
      done
      planner_specs+=("$opt" "$spec_name=$spec_value") ;;
    --scenarios | --planners | --seeds | --out | --jobs | --mode | --duration | --timeout | --profile | --metrics | --format | \
      --people-model)
      option_value "$@"
      case "$opt" in
        --scenarios) scenarios=$value ;;
        --planners) planners=$value ;;
        --seeds) seeds=$value ;;
        --out) out=$value ;;
        --jobs) jobs=$value ;;
        --mode) mode=$value ;;
        --duration) duration=$value ;;
        --timeout) timeout=$value ;;
        --profile) profile=$value ;;
        --metrics) metrics=$value ;;
        --format) format=$value ;;
        --people-model) people_model=$value ;;
      esac ;;
    *) usage_error "unknown argument '$1'" ;;
  esac
  shift $((1 + taken))
done

# finished() (here and in every job) asks for counterfactual.csv too.
export HUNAV_BATCH_COUNTERFACTUAL=$counterfactual

[ -n "$scenarios" ] || usage_error "--scenarios LIST is required (e.g. --scenarios passing,crossing)"
[ -n "$planners" ] || usage_error "--planners LIST is required (e.g. --planners dwb,scl,sfw)"
[ -n "$seeds" ] || usage_error "--seeds is required (e.g. --seeds 1-10)"
[ "$print_matrix" -eq 1 ] || [ -n "$out" ] || usage_error "--out DIR is required"
check_choice --mode "$mode" inprocess lockstep realtime
if [ "$no_states_csv" -eq 1 ] || [ "$no_per_tick_files" -eq 1 ]; then
  [ "$mode" = inprocess ] || usage_error "--no-states-csv and --no-per-tick-files need --mode inprocess"
fi
[ "$no_states_csv" -eq 0 ] || [ "$counterfactual" -eq 0 ] ||
  usage_error "--no-states-csv is not possible with --counterfactual (which reads states.csv back)"
check_count --jobs "$jobs"
# More jobs than that only make GNU parallel probe its limits for minutes.
[ -z "$jobs" ] || { [ "${#jobs}" -le 4 ] && [ "$jobs" -le 1024 ]; } || usage_error "--jobs must be at most 1024 (got '$jobs')"
check_seconds --duration "$duration"
check_seconds --timeout "$timeout"
check_choice --profile "$profile" default hunav_v1
check_choice --format "$format" csv hunav_txt
# A parameter file from here (the runs may start elsewhere); a name is checked by hunav_run.
if [ -n "$people_model" ] && [ -f "$people_model" ]; then people_model=$(readlink -f "$people_model"); fi
if [ -n "$metrics" ]; then
  check_file --metrics "$metrics"
  metrics=$(readlink -f "$metrics")  # the runs may start in another folder
fi

# Scenarios: NAME -> scenarios/NAME.yaml, else a file. The label (folder names, tables) is the file
# name without .yaml, made safe for folder names.
scenario_files=() scenario_labels=()
IFS=',' read -r -a items <<<"$scenarios"
for item in "${items[@]}"; do
  item=${item//[[:space:]]/}
  [ -n "$item" ] || continue
  if [ -f "$item" ]; then
    file=$(readlink -f "$item")
  elif [ -f "$repo_root/scenarios/$item.yaml" ]; then
    file="$repo_root/scenarios/$item.yaml"
  else
    usage_error "--scenarios: '$item' is neither a file nor scenarios/$item.yaml"
  fi
  label=$(basename "$file")
  label=${label%.yaml}
  label=${label%.yml}
  # Safe for a folder name, and no "__" (it separates the parts of a run folder's name) nor an
  # underscore at either end.
  label=${label//[^A-Za-z0-9._-]/-}
  while [[ $label == *__* ]]; do label=${label//__/_}; done
  label=${label#_}
  label=${label%_}
  [ -n "$label" ] || usage_error "--scenarios: cannot make a name for '$item'"
  for l in "${scenario_labels[@]}"; do
    [ "$l" != "$label" ] || usage_error "--scenarios: two scenarios are named '$label'"
  done
  scenario_files+=("$file")
  scenario_labels+=("$label")
done
[ "${#scenario_files[@]}" -gt 0 ] || usage_error "--scenarios: no scenario given"

planner_list=()
IFS=',' read -r -a items <<<"$planners"
for item in "${items[@]}"; do
  item=${item//[[:space:]]/}
  [ -n "$item" ] || continue
  if [ -z "${planner_cmd_of[$item]:-}" ]; then
    case "$item" in dwb | scl | sfw | none) ;; *) usage_error "--planners: '$item' is not dwb, scl, sfw or none, nor given --planner-cmd $item=CMD" ;; esac
  fi
  for p in "${planner_list[@]}"; do [ "$p" != "$item" ] || usage_error "--planners: '$item' given twice"; done
  planner_list+=("$item")
done
[ "${#planner_list[@]}" -gt 0 ] || usage_error "--planners: no planner given"
for ((k = 0; k < ${#planner_specs[@]}; k += 2)); do
  name=${planner_specs[k + 1]%%=*} known=0
  for p in "${planner_list[@]}"; do [ "$p" != "$name" ] || known=1; done
  [ "$known" -eq 1 ] || usage_error "${planner_specs[k]}: '$name' is not in --planners"
done
if [ "${#planner_cmd_of[@]}" -gt 0 ] && [ "$mode" = inprocess ]; then
  usage_error "--planner-cmd needs --mode lockstep or realtime (your planner is a process of its own)"
fi

seed_list=()
IFS=',' read -r -a items <<<"$seeds"
for item in "${items[@]}"; do
  item=${item//[[:space:]]/}
  if [[ $item =~ ^([0-9]+)-([0-9]+)$ ]]; then
    a=$((10#${BASH_REMATCH[1]})) b=$((10#${BASH_REMATCH[2]}))
    [ "$a" -le "$b" ] || usage_error "--seeds: '$item' goes down (write A-B with A <= B)"
    [ $((b - a)) -lt 100000 ] || usage_error "--seeds: '$item' holds too many seeds"
    for ((s = a; s <= b; s++)); do seed_list+=("$s"); done
  elif [[ $item =~ ^[0-9]+$ ]]; then
    seed_list+=("$((10#$item))")
  else
    usage_error "--seeds: '$item' is not N or A-B (seeds are integers >= 0)"
  fi
done
[ "${#seed_list[@]}" -gt 0 ] || usage_error "--seeds: no seed given"
mapfile -t seed_list < <(printf '%s\n' "${seed_list[@]}" | awk '!seen[$0]++')

# The matrix: index, scenario file, scenario, planner, seed (scenario-major, seeds innermost).
matrix() {
  local i=0 k p s
  for k in "${!scenario_files[@]}"; do
    for p in "${planner_list[@]}"; do
      for s in "${seed_list[@]}"; do
        printf '%d\t%s\t%s\t%s\t%d\n' "$i" "${scenario_files[$k]}" "${scenario_labels[$k]}" "$p" "$s"
        i=$((i + 1))
      done
    done
  done
}
if [ "$print_matrix" -eq 1 ]; then
  matrix
  exit 0
fi

# ---------------------------------------------------------------------------------------------------
# The batch
# ---------------------------------------------------------------------------------------------------
command -v parallel >/dev/null 2>&1 || die "GNU parallel is missing (package parallel): run bash launch_scripts/setup.sh"
need_bin hunav_summary
[ -n "$jobs" ] || jobs=$(nproc 2>/dev/null || echo 2)

mkdir -p "$out" || die "cannot create the batch folder '$out'"
out=$(cd "$out" && pwd)
# One batch per folder at a time (two would run the same runs into the same folders): locked before
# anything is written into it.
lock_folder "$out"
mkdir -p "$out/runs" || die "cannot create the batch folder '$out/runs'"
matrix >"$out/matrix.tsv"
total=$(wc -l <"$out/matrix.tsv")
# The matrix's run folders, and which are finished already.
matrix_dirs=()
while IFS=$'\t' read -r _ _ label planner seed; do
  matrix_dirs+=("$out/runs/${label}__${planner}__seed${seed}")
done <"$out/matrix.tsv"
finished_among "${matrix_dirs[@]}"
already=${#finished_dirs[@]}

# What every episode is run with (hunav_run's and run_experiment.sh's options alike).
episode_args=()
[ -z "$duration" ] || episode_args+=(--duration "$duration")
[ -z "$profile" ] || episode_args+=(--profile "$profile")
[ -z "$metrics" ] || episode_args+=(--metrics "$metrics")
[ -z "$format" ] || episode_args+=(--format "$format")
[ -z "$people_model" ] || episode_args+=(--people-model "$people_model")
[ "$counterfactual" -eq 0 ] || episode_args+=(--counterfactual)
[ "$no_states_csv" -eq 0 ] || episode_args+=(--no-states-csv)
[ "$no_per_tick_files" -eq 0 ] || episode_args+=(--no-per-tick-files)
# A job's (--run-one) options: those, the mode, the limit and the planners' commands and configs.
run_args=(--mode "$mode" "${episode_args[@]}")
[ -z "$timeout" ] || run_args+=(--timeout "$timeout")
run_args+=("${planner_specs[@]}")

log "$total runs (${#scenario_files[@]} scenarios x ${#planner_list[@]} planners x ${#seed_list[@]} seeds), $already already finished; $jobs at a time, mode $mode"
log "batch folder $out"
rm -f "$out/.progress" "$out/.exited_nonzero"
batch_started=$(date +%s.%N)
parallel_rc=0
# When the batch is stopped, parallel sends its jobs SIGTERM and gives them 30 s to write what they
# recorded (its default, 0.4 s, could cut a run's result files short) before SIGKILL.
termseq=TERM,30000,KILL,25
if [ "$mode" = inprocess ]; then
  # One hunav_run process runs every run still to do (hunav_run --runs: the matrix's order, $jobs
  # episodes at a time on threads of its own, each with its wall-clock limit), so that a batch costs
  # its simulations, not a shell, a process and a judge per chunk (docs/performance.md, "Batches").
  # Its progress lines are printed here as the runs end; the rest of its output goes to
  # logs/hunav_run.log, and each run's part to its folder's logs/hunav_run.log.
  need_bin hunav_run
  declare -A limit_of=() config_of=()
  for ((k = 0; k < ${#planner_specs[@]}; k += 2)); do
    [ "${planner_specs[k]}" != --planner-config ] || config_of[${planner_specs[k + 1]%%=*}]=${planner_specs[k + 1]#*=}
  done
  skipped=() todo_dirs=()
  mkdir -p "$out/logs"
  while IFS=$'\t' read -r _ file label planner seed; do
    run_dir="$out/runs/${label}__${planner}__seed${seed}"
    if [ -n "${finished_dirs[$run_dir]-}" ]; then
      skipped+=("$label $planner seed $seed" "skipped (finished before)")
      continue
    fi
    [ -n "${limit_of[$file]-}" ] || limit_of[$file]=${timeout:-$(run_limit "$file" "$duration")}
    todo_dirs+=("$run_dir")
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$file" "$label" "$planner" "$seed" "${limit_of[$file]}" "${config_of[$planner]-}"
  done <"$out/matrix.tsv" >"$out/logs/runs.tsv"
  export HUNAV_BATCH_TOTAL=$total
  [ "${#skipped[@]}" -eq 0 ] || progress "${skipped[@]}"
  if [ "${#todo_dirs[@]}" -gt 0 ]; then
    rm -rf "${todo_dirs[@]}"
    runs_log="$out/logs/hunav_run.log"
    : >"$runs_log"
    # SIGINT to the batch's group (see the top) reaches hunav_run, which ends its episodes and writes
    # what they recorded (the interrupted runs run again next time); this shell ends at once, and
    # hunav_run ignores the closed pipe.
    done_count=$already
    while IFS= read -r line; do
      if [[ $line =~ ^\[[0-9]+/[0-9]+\]\ (.*)$ ]]; then
        done_count=$((done_count + 1))
        printf 'run_batch: [%d/%d] %s\n' "$done_count" "$total" "${BASH_REMATCH[1]}"
      else
        printf '%s\n' "$line" >>"$runs_log"
      fi
    done < <(exec "$bin_dir/hunav_run" --runs "$out/logs/runs.tsv" --jobs "$jobs" --out "$out/runs" --quiet "${episode_args[@]}" \
      2>>"$runs_log" </dev/null)
    # hunav_run's exit code (bash waits for a process substitution by its pid); a failed expect:
    # condition is a result (junit.xml), an unfinished run is reported below.
    wait "$!" || parallel_rc=$?
    [ "$parallel_rc" -ne 3 ] || parallel_rc=0
  fi
else
  # Each job runs this script with --run-one. parallel hands the command to a shell and quotes the
  # fields it substitutes ({2}...{5}); the rest is quoted here. Ctrl-C reaches every run_experiment.sh,
  # which stops its processes cleanly; the interrupted runs are not finished and run again next time.
  job=$(printf '%q ' "$script_path" --run-one "$out")'{2} {3} {4} {5} '$(printf '%q ' "${run_args[@]}")
  HUNAV_BATCH_TOTAL=$total HUNAV_BIN_DIR=$bin_dir parallel --will-cite --jobs "$((jobs < total ? jobs : total))" \
    --line-buffer --termseq "$termseq" --colsep '\t' --arg-file "$out/matrix.tsv" "$job" &
  wait "$!" || parallel_rc=$?
fi
elapsed=$(awk -v a="$batch_started" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
rm -f "$out/.progress" "$out/.progress.lock"
exited_nonzero=()
if [ -f "$out/.exited_nonzero" ]; then mapfile -t exited_nonzero <"$out/.exited_nonzero"; fi
rm -f "$out/.exited_nonzero"

finished_among "${matrix_dirs[@]}"
done_now=${#finished_dirs[@]}
failed=()
for run_dir in "${matrix_dirs[@]}"; do
  [ -n "${finished_dirs[$run_dir]-}" ] || failed+=("${run_dir##*/}")
done

summary_rc=0
"$bin_dir/hunav_summary" "$out" || summary_rc=$?
printf '%s\t%s\tjobs=%s\tmode=%s\truns=%d\tran=%d\tfinished=%d\tfailed=%d\twall=%ss\n' \
  "$(date -Is)" "scenarios=${scenarios} planners=${planners} seeds=${seeds}" "$jobs" "$mode" "$total" \
  "$((total - already))" "$done_now" "${#failed[@]}" "$elapsed" >>"$out/batch.log"
log "$((total - already)) runs in ${elapsed} s with $jobs jobs; $done_now of $total finished"
if [ "${#failed[@]}" -gt 0 ]; then
  err "${#failed[@]} runs did not finish (run the same command again to retry them):"
  printf '  %s\n' "${failed[@]}" >&2
fi
if [ "${#exited_nonzero[@]}" -gt 0 ]; then
  err "${#exited_nonzero[@]} runs wrote complete results but exited non-zero (kept; see their logs/run_experiment.log):"
  printf '  %s\n' "${exited_nonzero[@]}" >&2
fi
# junit.xml: the verdicts of every run's expect.json (scenarios without expect: give no test case).
junit_rc=0
if [ -x "$bin_dir/hunav_expect" ]; then
  "$bin_dir/hunav_expect" --junit "$out" | sed 's/^hunav_expect: /run_batch: junit: /' || junit_rc=${PIPESTATUS[0]}
else
  err "$bin_dir/hunav_expect is missing: no junit.xml (build the project first)"
  junit_rc=1
fi
[ "$summary_rc" -eq 0 ] || die "hunav_summary failed (exit $summary_rc)"
log "summary in $out/summary.md (tables), summary.csv, summary_stats.csv, paired.csv"
if [ "${#failed[@]}" -gt 0 ] || [ "$parallel_rc" -ne 0 ]; then exit 1; fi
case "$junit_rc" in
  0) ;;
  3) err "some runs failed their scenario's expect: conditions (see $out/junit.xml)"; exit 3 ;;
  *) err "hunav_expect --junit failed (exit $junit_rc)"; exit 1 ;;
esac
exit 0
