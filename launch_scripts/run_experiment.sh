#!/usr/bin/env bash
# Runs one HuNav-LCM episode and writes its results into one folder. See --help, and README.md.
#
# Modes:
#   inprocess (default)  build/bin/hunav_run: everything in one process on memq://, no network.
#   lockstep, realtime   evaluator, manager, planner and world as separate processes over LCM UDP
#                        multicast, inside a private network namespace made for this run (or on the bus
#                        given with --shared-bus).
# Inside the namespace the bus is the default one with channel_ports=1 (common/transport/include/hunav/open_bus.hpp):
# STEP_REQUEST and STEP_REPLY, sent every tick between the world and the manager only, travel on
# ports 7668 and 7669 of their own, so their datagrams wake only the process that listens (less CPU
# per tick: docs/performance.md, "Bus backends"). Every other channel, the planner's included, stays
# on 7667, where a user's planner, lcm-spy and lcm-logger find it. The evaluator listens on 7667 only.
#
# Every process this script starts is stopped when the run ends or the script is interrupted; on an
# interrupt the evaluator is asked to stop first (SIGTERM) so it still writes what it recorded.
# The script supervises what it started: when a process exits before the world ended the episode, or
# stays stopped (SIGSTOP) for HUNAV_STALL_LIMIT s, or --timeout passes, it writes the reason into
# $HUNAV_STOP_REASON_FILE and stops the run, so the evaluator (and the world) record it as `aborted`
# with that reason (common/core/include/hunav/episode_status.hpp; README.md, "Statuses and exit codes").
set -euo pipefail

prog=run_experiment
# shellcheck source=lib.sh
source "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/lib.sh"
ready_timeout=${HUNAV_READY_TIMEOUT:-30}  # s to wait for a process's "ready" line
eval_grace=${HUNAV_EVAL_GRACE:-60}        # s the evaluator gets to write its files
stop_grace=${HUNAV_STOP_GRACE:-10}        # s any other process gets to stop after SIGTERM
stall_limit=${HUNAV_STALL_LIMIT:-2}       # s a process may stay stopped (SIGSTOP) before the run is aborted

usage() {
  cat <<'EOF'
Usage: launch_scripts/run_experiment.sh --scenario FILE [options]

Runs one episode of a scenario and writes metrics.csv, the per-tick and per-behavior metric CSVs,
states.csv, run.json (and, with --record, run.lcmlog) into the output folder, then prints the metrics.

Options:
  --scenario FILE         scenario YAML (scenarios/README.md); required
  --planner NAME          dwb (default), scl, sfw or none; with --planner-cmd, the name your planner
                          is recorded under (letters, digits, . _ -; default: custom)
  --planner-config FILE   YAML parameters of the built-in planner (planners/config/<name>.yaml shows
                          every key and its default)
  --planner-cmd "CMD"     lockstep/realtime only: start CMD (run by bash, in the run's namespace, with
                          LCM_DEFAULT_URL set to the planner's bus and the build's python folder on
                          PYTHONPATH) as the robot planner instead of
                          hunav_planner; it must follow docs/planner_contract.md: publish
                          PLANNER_READY once subscribed and then every 0.5 s (the world starts the
                          episode only after it heard one, HUNAV_READY_TIMEOUT s at most), and answer
                          observations. Its output goes to DIR/logs/planner.log; it is stopped
                          (SIGTERM) when the episode has ended
  --seed N                seed (integer >= 0); default: the scenario's seed
  --mode MODE             inprocess (default: one process, no network), lockstep (separate processes,
                          lock-stepped, bit-identical to inprocess) or realtime (separate processes, the
                          world paced by the wall clock)
  --out DIR               output folder; default: results/<scenario>_<planner>_<seed> in the repository
  --duration SECONDS      simulated time limit; default: the scenario's time_limit
  --sample-rate HZ        evaluate and record states.csv at most HZ samples per second of simulation
                          time, 0 = every tick; default: the scenario's evaluation.sample_rate
  --record                also record the LCM traffic into DIR/run.lcmlog
  --shared-bus URL        lockstep/realtime only: use this LCM URL on the host's network instead of a
                          private network namespace (needs a multicast route, see below)
  --profile PROFILE       metrics profile: default or hunav_v1
  --experiment-tag TAG    free text stored in the experiment_tag column of metrics.csv
  --metrics FILE          metric selection YAML ('metrics: {name: false}', or HuNavSim's metrics.yaml:
                          its frequency is the sample rate and its experiment_tag the tag unless
                          --sample-rate / --experiment-tag are given); default: the scenario's
                          evaluation.metrics, else every metric
  --format FORMAT         result files: csv (default), or hunav_txt = csv plus HuNavSim v1's .txt files
  --people-model M        the model every person walks with: sfm (HuNavSim's social force model, the
                          default), sfm_calibrated, orca, orca_calibrated, ttc, ttc_calibrated, or a
                          parameter file (docs/people_models.md); recorded in run.json and metrics.csv
  --counterfactual        also run the episode with the same seed without the robot and measure the
                          robot's effect on each person: DIR/counterfactual.csv and the
                          counterfactual_* metrics in metrics.csv (docs/metrics.md). The robot-free
                          episode always runs in one process (hunav_run, or the evaluator process at
                          the end of a lockstep/realtime run): same results in every mode
  --timeout SECONDS       wall-clock guard: stop the run after this long (status aborted, what was
                          recorded kept, exit 124)
  --view                  lockstep/realtime only: start hunav_view for this run and print the URL where
                          a browser on this machine watches it live (view/README.md; port: HUNAV_VIEW_PORT,
                          default any free one)
  -h, --help              show this help

Exit status (README.md, "Statuses and exit codes"; run.json's status in brackets): 0 when the
episode ran to an end [goal_reached, time_limit, stuck]; 1 when it was aborted [aborted: a component
went silent, exited, stalled or never became ready; the reason names it]; 2 on bad arguments or a
bad scenario [nothing run]; 3 when it ran to an end but a condition of the scenario's expect: failed
(verdicts printed, and in DIR/expect.json); 124 when --timeout stopped it [aborted]; 130/143 when
interrupted by SIGINT/SIGTERM [interrupted].

Separate-process modes run inside a private network namespace (unshare --net as root, unshare -rn
otherwise), so parallel runs cannot hear each other. The script prints the namespace's PID; watch the
run with: launch_scripts/spy.sh --netns-pid PID. Process logs go to DIR/logs/<name>.log.
In the namespace the bus is the processes' default (build/bin/hunav_record --print-url) with
&channel_ports=1:
STEP_REQUEST and STEP_REPLY (world <-> manager, every tick) go to ports 7668 and 7669 of their own,
every other channel (the planner's ROBOT_OBSERVATION/ROBOT_COMMAND included) to 7667, the port
lcm-spy watches. --record records every port. (lcmtypes/README.md, docs/planner_contract.md)
With --shared-bus URL nothing is isolated and every process uses exactly that URL (all channels on
its one port, unless you add &channel_ports=1, which also takes the next two ports): give each
parallel run its own URL (address or port), and make sure multicast has a route, e.g. on loopback
only: sudo ip route add 224.0.0.0/4 dev lo

Environment: HUNAV_BIN_DIR (binaries, default <repo>/build/bin), HUNAV_READY_TIMEOUT (30 s: for a
process's "ready" line, and the world's wait for PLANNER_READY), HUNAV_EVAL_GRACE (60 s),
HUNAV_STOP_GRACE (10 s), HUNAV_STALL_LIMIT (2 s a process may stay stopped).
EOF
}

# ---------------------------------------------------------------------------------------------------
# Arguments
# ---------------------------------------------------------------------------------------------------
orig_args=("$@")
scenario=""
planner=dwb
seed=""
mode=inprocess
out=""
duration=""
sample_rate=""
metrics=""
format=""
record=0
shared_bus=""
profile=""
tag=""
timeout=""
planner_given=0
planner_config=""
planner_cmd=""
view=0
counterfactual=0
people_model=""

while [ "$#" -gt 0 ]; do
  split_option "$1"
  case "$opt" in
    -h | --help) usage; exit 0 ;;
    --record) no_value; record=1 ;;
    --view) view=1 ;;
    --counterfactual) no_value; counterfactual=1 ;;
    --scenario | --planner | --seed | --mode | --out | --duration | --sample-rate | --shared-bus | --profile | \
      --experiment-tag | --timeout | --planner-config | --planner-cmd | --metrics | --format | --people-model)
      option_value "$@"
      # A next argument that is an option is not this one's value (--opt=--x is taken as written).
      [ "$taken" -eq 0 ] || case "$value" in --*) usage_error "$opt needs a value (got the option '$value')" ;; esac
      case "$opt" in
        --scenario) scenario=$value ;;
        --planner) planner=$value; planner_given=1 ;;
        --planner-config) planner_config=$value ;;
        --planner-cmd) planner_cmd=$value ;;
        --seed) seed=$value ;;
        --mode) mode=$value ;;
        --out) out=$value ;;
        --duration) duration=$value ;;
        --sample-rate) sample_rate=$value ;;
        --shared-bus) shared_bus=$value ;;
        --profile) profile=$value ;;
        --experiment-tag) tag=$value ;;
        --metrics) metrics=$value ;;
        --format) format=$value ;;
        --people-model) people_model=$value ;;
        --timeout) timeout=$value ;;
      esac ;;
    *) usage_error "unknown argument '$1'" ;;
  esac
  shift $((1 + taken))
done

[ -n "$scenario" ] || usage_error "--scenario FILE is required (e.g. --scenario scenarios/passing.yaml)"
check_file --scenario "$scenario"
if [ -n "$planner_cmd" ]; then
  [ "$mode" != inprocess ] || usage_error "--planner-cmd needs --mode lockstep or realtime (your planner is a process of its own)"
  [ -z "$planner_config" ] || usage_error "--planner-config is for the built-in planners; give your planner its parameters in --planner-cmd"
  [ "$planner_given" -eq 1 ] || planner=custom
  [[ $planner =~ ^[A-Za-z0-9._-]+$ ]] || usage_error "--planner: a name of letters, digits, '.', '_' or '-' (got '$planner')"
  [ "$planner" != none ] || usage_error "--planner none runs without a planner; drop --planner-cmd or name your planner"
else
  case "$planner" in dwb | scl | sfw | none) ;; *) usage_error "--planner must be dwb, scl, sfw or none (got '$planner'), or name your own with --planner-cmd" ;; esac
fi
if [ -n "$planner_config" ]; then
  [ "$planner" != none ] || usage_error "--planner-config needs a planner (got --planner none)"
  check_file --planner-config "$planner_config"
  planner_config=$(readlink -f "$planner_config")
fi
check_choice --mode "$mode" inprocess lockstep realtime
if [ -n "$seed" ] && ! [[ $seed =~ ^[0-9]+$ ]]; then usage_error "--seed must be an integer >= 0 (got '$seed')"; fi
check_seconds --duration "$duration"
if [ -n "$sample_rate" ] && ! is_number "$sample_rate"; then usage_error "--sample-rate must be a number of Hz >= 0 (got '$sample_rate')"; fi
check_seconds --timeout "$timeout"
check_choice --profile "$profile" default hunav_v1
case "$tag" in *[,\"$'\n'$'\r']*) usage_error "--experiment-tag must not contain commas, quotes or line breaks" ;; esac
check_choice --format "$format" csv hunav_txt
# A parameter file is taken from here (the processes may run elsewhere); a name is checked by them.
if [ -n "$people_model" ] && [ -f "$people_model" ]; then people_model=$(readlink -f "$people_model"); fi
if [ -n "$metrics" ]; then
  check_file --metrics "$metrics"
  metrics=$(readlink -f "$metrics")  # the processes may run elsewhere
fi
for v in HUNAV_READY_TIMEOUT:"$ready_timeout" HUNAV_EVAL_GRACE:"$eval_grace" HUNAV_STOP_GRACE:"$stop_grace" \
  HUNAV_STALL_LIMIT:"$stall_limit"; do
  is_number "${v#*:}" || usage_error "${v%%:*} must be a number of seconds (got '${v#*:}')"
done
if [ -n "$shared_bus" ]; then
  [ "$mode" != inprocess ] || usage_error "--shared-bus needs --mode lockstep or realtime (inprocess uses no network)"
  [[ $shared_bus == *://* ]] || usage_error "--shared-bus needs an LCM URL such as 'udpm://239.255.76.67:7667?ttl=0' (got '$shared_bus')"
fi

scenario=$(readlink -f "$scenario")
# The scenario's name: its top-level `name:` (as the loader reads it), else the file name.
scenario_name=$(sed -n -E 's/^name:[[:space:]]*["'"'"']?([^"'"'"'#]*[^"'"'"'#[:space:]])["'"'"']?[[:space:]]*(#.*)?$/\1/p' "$scenario" | head -n 1)
if [ -z "$scenario_name" ]; then
  scenario_name=$(basename "$scenario")
  scenario_name=${scenario_name%.yaml}
  scenario_name=${scenario_name%.yml}
fi
scenario_name=${scenario_name//[^A-Za-z0-9._-]/_}
# The seed that names the default folder: --seed, else the scenario's top-level `seed:` (1 if absent).
seed_label=$seed
if [ -z "$seed_label" ]; then
  seed_label=$(sed -n -E 's/^seed:[[:space:]]*([0-9]+)[[:space:]]*(#.*)?$/\1/p' "$scenario" | head -n 1)
  [ -n "$seed_label" ] || seed_label=1
fi
[ -n "$out" ] || out="$repo_root/results/${scenario_name}_${planner}_${seed_label}"

netns_url=""
need_bin hunav_expect  # reads run.json for the run's last line (and judges expect: in the other modes)
if [ "$mode" = inprocess ]; then
  need_bin hunav_run
else
  for b in hunav_worldsim hunav_manager hunav_evaluator; do need_bin "$b"; done
  [ "$counterfactual" -eq 0 ] || need_bin hunav_run  # the evaluator's robot-free run
  [ "$planner" = none ] || [ -n "$planner_cmd" ] || need_bin hunav_planner
  [ "$record" -eq 0 ] || need_bin hunav_record
  # The bus inside the run's own namespace (not the user's $LCM_DEFAULT_URL, which is for the host).
  [ -n "$shared_bus" ] || netns_url=$(with_url_option "$(default_lcm_url)" channel_ports=1)
fi

# ---------------------------------------------------------------------------------------------------
# Separate-process modes: re-run this script inside a private network namespace
# ---------------------------------------------------------------------------------------------------
in_netns=0
if in_private_netns; then in_netns=1; fi

# --view: hunav_view for this run. Its HTTP socket opens here, in the host's namespace where the
# browser is; then it joins the run's namespace (this process's after the re-execution below: the
# same PID) for LCM, and it exits with the run (and, by pdeathsig, with this script).
if [ "$view" -eq 1 ] && [ "$in_netns" -eq 0 ]; then
  [ "$mode" != inprocess ] || usage_error "--view needs --mode lockstep or realtime (an in-process run has no bus to watch; replay it with: build/bin/hunav_view --results DIR)"
  need_bin hunav_view
  mkdir -p "$out/logs" || die "cannot create the output folder '$out'"
  view_log="$out/logs/view.log"
  view_args=(--scenario "$scenario" --port "${HUNAV_VIEW_PORT:-0}" --no-editor)
  if [ -n "$shared_bus" ]; then view_args+=(--lcm-url "$shared_bus"); else view_args+=(--lcm-url "$netns_url" --netns-pid "$$"); fi
  setsid setpriv --pdeathsig TERM -- "$bin_dir/hunav_view" "${view_args[@]}" >"$view_log" 2>&1 </dev/null &
  view_url=""
  for _ in $(seq 100); do
    view_url=$(sed -n -E 's#^hunav_view: open (http://[^ ]+) .*#\1#p' "$view_log" | head -n 1)
    if [ -n "$view_url" ] || ! kill -0 $! 2>/dev/null; then break; fi
    sleep 0.1
  done
  [ -n "$view_url" ] || { err "hunav_view did not start (see $view_log)"; cat "$view_log" >&2; exit 1; }
  log "watch this run live: $view_url"
fi

if [ "$mode" != inprocess ] && [ -z "$shared_bus" ] && [ "$in_netns" -eq 0 ]; then
  for tool in unshare ip; do
    command -v "$tool" >/dev/null 2>&1 ||
      die "'$tool' is not installed (packages util-linux and iproute2): run bash launch_scripts/setup.sh"
  done
  if ! netns_unshare_flags; then
    {
      err "cannot create a private network namespace for this run."
      echo "  unshare said: ${unshare_error:-nothing}"
      echo "  Separate-process runs use a namespace of their own so that their multicast traffic stays"
      echo "  private to the run. Fix one of:"
      if [ "$(id -u)" -ne 0 ]; then
        echo "    - run as root: sudo launch_scripts/run_experiment.sh ${orig_args[*]}"
        echo "    - or allow unprivileged user namespaces (a normal user needs them for unshare -rn):"
        echo "        sudo sysctl kernel.unprivileged_userns_clone=1"
        echo "        sudo sysctl user.max_user_namespaces=15000   (where it is 0)"
      else
        echo "    - this system refuses namespaces even to root (a container without CAP_SYS_ADMIN, or"
        echo "      seccomp?): allow them (e.g. docker run --cap-add SYS_ADMIN), or:"
      fi
      echo "    - run on a bus you choose, without a namespace: --shared-bus 'udpm://239.255.76.67:7667?ttl=0'"
      echo "      (multicast then needs a route; on loopback only: sudo ip route add 224.0.0.0/4 dev lo)"
      echo "    - or use --mode inprocess, which needs no network"
    } >&2
    exit 1
  fi
  reexec_in_private_netns "${orig_args[@]}"
fi

# ---------------------------------------------------------------------------------------------------
# Process bookkeeping and cleanup
# ---------------------------------------------------------------------------------------------------
cleaning=0
# Each process gets its own session, and SIGTERM when this script dies (lib.sh).
use_own_sessions
run_started_us=$(now_us)

cleanup() {
  [ "$cleaning" -eq 0 ] || return 0
  cleaning=1
  local name
  # The evaluator first, so it writes what it recorded, then everything else at once.
  if alive evaluator; then signal evaluator TERM; fi
  for name in "${started[@]}"; do
    if [ "$name" != evaluator ] && alive "$name"; then
      signal "$name" TERM
    fi
  done
  for name in "${started[@]}"; do
    if [ "$name" = evaluator ]; then stop "$name" TERM "$eval_grace"; else stop "$name" TERM "$stop_grace"; fi
  done
  # Whatever a process left running in its process group (children it started before it exited).
  local groups=() pg deadline_us
  for name in "${started[@]}"; do
    [ "$name" != display ] || continue  # tail, in this script's own group
    if kill -0 -- "-${pid_of[$name]}" 2>/dev/null; then groups+=("${pid_of[$name]}"); fi
  done
  [ "${#groups[@]}" -gt 0 ] || return 0
  for pg in "${groups[@]}"; do kill -s TERM -- "-$pg" 2>/dev/null || true; done
  deadline "$stop_grace"
  for pg in "${groups[@]}"; do
    while kill -0 -- "-$pg" 2>/dev/null && ! past "$deadline_us"; do sleep 0.1; done
    kill -s KILL -- "-$pg" 2>/dev/null || true
  done
}

# shellcheck disable=SC2317 # called from the traps below
on_signal() {
  trap '' INT TERM HUP
  if [ -n "${pid_of[evaluator]:-}" ]; then
    log "interrupted by SIG$1: stopping every process of this run (the evaluator first, to keep its results)"
  else
    log "interrupted by SIG$1: stopping every process of this run"
  fi
  cleanup
  [ -z "${out_dir:-}" ] || log "what was recorded is in $out_dir"
  case "$1" in INT) exit 130 ;; TERM) exit 143 ;; *) exit 129 ;; esac
}
trap 'on_signal INT' INT
trap 'on_signal TERM' TERM
trap 'on_signal HUP' HUP
trap cleanup EXIT

# tail_log NAME: the last lines of a process's log, for error messages.
tail_log() {
  local f="$log_dir/$1.log"
  [ -s "$f" ] || { echo "  ($f is empty)" >&2; return 0; }
  echo "  last lines of $f:" >&2
  tail -n 15 "$f" | sed 's/^/    /' >&2
}

# wait_ready NAME: waits for the line "ready" in NAME's log.
wait_ready() {
  local name=$1 deadline_us
  deadline "$ready_timeout"
  while ! grep -q -x -E 'ready\r?' "$log_dir/$name.log" 2>/dev/null; do
    if ! alive "$name"; then
      collect "$name"
      err "$name exited (code ${code_of[$name]}) before it was ready"
      tail_log "$name"
      return 1
    fi
    if past "$deadline_us"; then
      err "$name did not print 'ready' within ${ready_timeout} s (set HUNAV_READY_TIMEOUT to wait longer)"
      tail_log "$name"
      return 1
    fi
    sleep 0.1
  done
}

# exit_failed NAME: after NAME failed to start: exit 2 if it rejected its input, else 1.
exit_failed() {
  if [ "${code_of[$1]:-}" = 2 ]; then exit 2; fi
  exit 1
}

# proc_name NAME: how reasons name a process (its log's name; a user's planner with its command).
proc_name() {
  case "$1" in
    world) echo worldsim ;;
    planner) if [ -n "$planner_cmd" ]; then echo "planner (your command: $planner_cmd)"; else echo planner; fi ;;
    *) echo "$1" ;;
  esac
}

# exit_text NAME CODE: "NAME exited with status CODE", or "NAME was killed by SIGX" for 128 + a signal.
exit_text() {
  local sig=""
  if [ "$2" -gt 128 ] && [ "$2" -lt 193 ]; then sig=$(kill -l "$(($2 - 128))" 2>/dev/null || true); fi
  if [ -n "$sig" ]; then
    echo "$(proc_name "$1") was killed by SIG${sig#SIG} (exit status $2)"
  else
    echo "$(proc_name "$1") exited with status $2"
  fi
}

# abort_run REASON: ends the run as aborted with REASON: the reason file first (the evaluator and the
# world read it on SIGTERM: episode_status.hpp, stopCause), then every process is stopped, the
# evaluator first so it writes what it recorded.
abort_reason=""
abort_run() {
  abort_reason=$1
  err "aborting the run: $abort_reason"
  printf '%s\n' "$abort_reason" >"$HUNAV_STOP_REASON_FILE"
  cleanup
}

# supervise MAIN: waits for the main process (world or hunav_run) to exit. Meanwhile, every 0.1 s:
# another process that exited (a non-zero status at once; status 0, which ours give only after the
# episode's END, when the world has not followed within 1 s), a process stopped for $stall_limit s, or
# --timeout, aborts the run (abort_run). A main process killed by a signal aborts it too.
timed_out=0
supervise() {
  local main=$1 name code state now deadline_us stall_us
  local -A stopped_since=() exited_at=()
  stall_us=$(awk -v s="$stall_limit" 'BEGIN { printf "%d", s * 1000000 }')
  deadline "${timeout:-0}"
  while alive "$main"; do
    now=${EPOCHREALTIME//[.,]/}
    now=$((10#$now))
    if [ "$deadline_us" -ne 0 ] && [ "$now" -ge "$deadline_us" ]; then
      timed_out=1
      abort_run "wall-clock timeout: the run still ran after ${timeout} s (--timeout)"
      return 0
    fi
    for name in "${started[@]}"; do
      [ "$name" != display ] || continue
      if [ "$name" != "$main" ] && ! alive "$name"; then
        collect "$name"
        code=${code_of[$name]}
        if [ "$code" -ne 0 ]; then
          abort_run "$(exit_text "$name" "$code") before the episode ended"
          return 0
        fi
        [ -n "${exited_at[$name]:-}" ] || exited_at[$name]=$now
        if ((now - exited_at[$name] >= 1000000)); then
          abort_run "$(proc_name "$name") exited (status 0) before the episode ended"
          return 0
        fi
        continue
      fi
      proc_state "${pid_of[$name]}"
      if [ "$state" = T ] || [ "$state" = t ]; then
        [ -n "${stopped_since[$name]:-}" ] || stopped_since[$name]=$now
        if ((now - stopped_since[$name] >= stall_us)); then
          abort_run "$(proc_name "$name") stalled: stopped (process state $state) for ${stall_limit} s"
          return 0
        fi
      else
        unset "stopped_since[$name]"
      fi
    done
    sleep 0.1
  done
  collect "$main"
  code=${code_of[$main]}
  if [ "$code" -gt 128 ] && [ "$code" -lt 193 ] && [ "$code" -ne 130 ] && [ "$code" -ne 143 ]; then
    abort_run "$(exit_text "$main" "$code")"
  fi
}

# ---------------------------------------------------------------------------------------------------
# The run
# ---------------------------------------------------------------------------------------------------
mkdir -p "$out" || die "cannot create the output folder '$out'"
out_dir=$(cd "$out" && pwd)
# One run per results folder at a time (two tore states.csv); hunav_run and the evaluator take the
# lock over from this script.
lock_folder "$out_dir"
log_dir="$out_dir/logs"
mkdir -p "$log_dir"
if [ -e "$out_dir/metrics.csv" ]; then
  log "note: $out_dir already holds the results of an earlier run"
fi
# Where abort_run leaves its reason for the processes (none there: an interrupt is an interrupt).
export HUNAV_STOP_REASON_FILE="$log_dir/stop_reason.txt"
rm -f "$HUNAV_STOP_REASON_FILE"

seed_args=()
[ -z "$seed" ] || seed_args=(--seed "$seed")
duration_args=()
[ -z "$duration" ] || duration_args=(--duration "$duration")
planner_config_args=()
[ -z "$planner_config" ] || planner_config_args=(--config "$planner_config")
eval_args=()
[ -z "$profile" ] || eval_args+=(--profile "$profile")
[ -z "$tag" ] || eval_args+=(--experiment-tag "$tag")
[ -z "$sample_rate" ] || eval_args+=(--sample-rate "$sample_rate")
[ -z "$metrics" ] || eval_args+=(--metrics "$metrics")
[ -z "$format" ] || eval_args+=(--format "$format")
[ "$counterfactual" -eq 0 ] || eval_args+=(--counterfactual)
# The evaluator process has hunav_run run the robot-free episode after the END (it links no
# simulator): give it time (an in-process episode).
[ "$counterfactual" -eq 0 ] || [ "$mode" = inprocess ] || eval_args+=(--robot-free-program "$bin_dir/hunav_run")
model_args=()
[ -z "$people_model" ] || model_args=(--people-model "$people_model")

[ "$counterfactual" -eq 0 ] || [ -n "${HUNAV_EVAL_GRACE:-}" ] || eval_grace=600

log "scenario $scenario, planner $planner, seed ${seed:-$seed_label (from the scenario)}, mode $mode"
log "results will be written to $out_dir"
[ -z "$planner_config" ] || log "planner parameters from $planner_config"

main=""
if [ "$mode" = inprocess ]; then
  cmd=("$bin_dir/hunav_run" --scenario "$scenario" --planner "$planner" --out "$out_dir"
    "${seed_args[@]}" "${duration_args[@]}" "${eval_args[@]}" "${model_args[@]}")
  [ -z "$planner_config" ] || cmd+=(--planner-config "$planner_config")
  [ "$record" -eq 0 ] || cmd+=(--record "$out_dir/run.lcmlog")
  start hunav_run "$log_dir/hunav_run.log" "${cmd[@]}"
  main=hunav_run
  # Show its output (the metrics table at the end) as it comes; tail ends once hunav_run has exited.
  tail -n +1 -s 0.2 -f --pid="${pid_of[hunav_run]}" "$log_dir/hunav_run.log" &
  pid_of[display]=$!
  started+=(display)
  supervise hunav_run
  [ -n "$abort_reason" ] || wait_exit display 5 || true
else
  if [ -n "$shared_bus" ]; then
    url=$shared_bus
    log "LCM bus: $url (shared with the host: other programs on it will hear this run)"
    if ! multicast_route "$url"; then
      err "no route to the multicast address $mc_group: add one on loopback only with"
      echo "  sudo ip route add 224.0.0.0/4 dev lo" >&2
      exit 1
    fi
    if [ -n "$mc_dev" ] && [ "$mc_dev" != lo ]; then
      log "warning: multicast to $mc_group goes through interface $mc_dev, not loopback;"
      log "  to keep it on this host: sudo ip route add 224.0.0.0/4 dev lo (and keep ttl=0 in the URL)"
    fi
  else
    url=$netns_url
    loopback_multicast || die "cannot set up loopback multicast in the run's network namespace"
    log "private network namespace: PID $$ holds it; watch this run with: launch_scripts/spy.sh --netns-pid $$"
    log "LCM bus inside it: $url"
  fi
  # The evaluator hears only channels of the URL's own port: give it the URL without our option,
  # which plain LCM would warn about.
  eval_url=$(plain_lcm_url "$url")
  if [ "$eval_url" != "$url" ]; then
    log "STEP_REQUEST and STEP_REPLY on ports of their own (channel_ports=1); every other channel on the URL's port"
  fi
  export LCM_DEFAULT_URL=$eval_url

  if [ "$record" -eq 1 ]; then
    # hunav_record, not lcm-logger: lcm-logger's 30-message queue loses messages of lockstep bursts,
    # and it would not hear the step channels' own ports.
    start recorder "$log_dir/recorder.log" "$bin_dir/hunav_record" --out "$out_dir/run.lcmlog" --lcm-url "$url"
    wait_ready recorder || exit_failed recorder
  fi
  start evaluator "$log_dir/evaluator.log" "$bin_dir/hunav_evaluator" --out "$out_dir" --episodes 1 \
    --lcm-url "$eval_url" --scenario "$scenario" "${eval_args[@]}" "${model_args[@]}"
  wait_ready evaluator || exit_failed evaluator
  # The manager runs until stopped: without --episodes it listens to STEP_REQUEST alone (on its own
  # port), not to the world states of the URL's port that it would otherwise hear every tick.
  start manager "$log_dir/manager.log" "$bin_dir/hunav_manager" --scenario "$scenario" --lcm-url "$url" "${model_args[@]}"
  if [ -n "$planner_cmd" ]; then
    # Your planner hears the bus through LCM_DEFAULT_URL (the URL without our channel_ports option:
    # every planner channel is on its port). It need not print "ready": the world waits for its
    # PLANNER_READY message before the episode's START (HUNAV_READY_TIMEOUT s at most). The build's
    # Python folder (the message classes, `import lcm`) is on its PYTHONPATH.
    start planner "$log_dir/planner.log" env "PYTHONPATH=$(dirname "$bin_dir")/python${PYTHONPATH:+:$PYTHONPATH}" \
      bash -c "$planner_cmd"
    log "your planner '$planner': $planner_cmd (output in $log_dir/planner.log)"
  elif [ "$planner" != none ]; then
    start planner "$log_dir/planner.log" "$bin_dir/hunav_planner" --planner "$planner" --scenario "$scenario" \
      --lcm-url "$url" --episodes 1 "${planner_config_args[@]}"
  fi
  wait_ready manager || exit_failed manager
  if [ "$planner" != none ] && [ -z "$planner_cmd" ]; then wait_ready planner || exit_failed planner; fi
  log "processes ready (logs in $log_dir); starting the world"
  # The run id is the world's default, <scenario>_<planner>_s<seed>, as in hunav_run.
  start world "$log_dir/worldsim.log" "$bin_dir/hunav_worldsim" --scenario "$scenario" --planner "$planner" \
    --mode "$mode" --lcm-url "$url" --planner-ready-timeout "$ready_timeout" "${seed_args[@]}" "${duration_args[@]}"
  main=world
  supervise world
  if [ -z "$abort_reason" ]; then
    case "${code_of[world]}" in
      0 | 1) ;;  # the world published the episode's END event (ended or aborted)
      *)         # bad input (2) or a crash: no END will come, so the evaluator need not wait for it
        log "the world exited with ${code_of[world]}: stopping the evaluator (SIGTERM, it writes what it has)"
        stop evaluator TERM "$eval_grace" ;;
    esac
    # The evaluator exits by itself after the episode's END event, once its files are written.
    if ! wait_exit evaluator "$eval_grace"; then
      log "the evaluator is still running ${eval_grace} s after the world ended: SIGTERM, so it writes what it has"
      stop evaluator TERM "$eval_grace"
    fi
    # The recorder writes what it has received, then exits.
    [ "$record" -eq 0 ] || stop recorder TERM "$stop_grace"
    # The manager has nothing more to answer: stop it. Our planner exits by itself after the END
    # event (--episodes 1); without one, stop it. Your planner is stopped (the contract does not ask
    # it to count episodes).
    stop manager TERM "$stop_grace"
    if [ -n "${pid_of[planner]:-}" ]; then
      case "${code_of[world]}" in
        0 | 1)
          # Ours exits by itself after END, unless it is stopped (SIGSTOP): a stalled planner is not waited for.
          proc_state "${pid_of[planner]}"
          if [ -n "$planner_cmd" ] || [ "$state" = T ] || [ "$state" = t ]; then
            stop planner TERM "$stop_grace"
          else
            wait_exit planner 3 || stop planner TERM "$stop_grace"
          fi ;;
        *) stop planner TERM "$stop_grace" ;;
      esac
    fi
  fi
fi

cleanup
main_code=${code_of[$main]:-1}

echo
if [ -n "$abort_reason" ]; then
  # The supervisor ended the run (README.md, "Statuses and exit codes"): 124 for --timeout, else 1.
  if [ "$timed_out" -eq 1 ]; then status_code=124; else status_code=1; fi
  err "the run was aborted: $abort_reason"
elif [ "$main_code" -eq 0 ]; then
  status_code=0
else
  status_code=$main_code
  case "$main_code" in
    1) err "$main exited with 1: the episode was aborted or an error occurred" ;;
    2) err "$main exited with 2: bad input (scenario or arguments)" ;;
    130 | 143) err "$main was interrupted (exit status $main_code)" ;;
    *) err "$main exited with $main_code" ;;
  esac
  if [ "$main" = world ]; then tail_log worldsim; fi
fi
if [ "$mode" != inprocess ] && [ -z "$abort_reason" ] && [ "${code_of[evaluator]:-0}" -ne 0 ]; then
  err "the evaluator exited with ${code_of[evaluator]}: the results may be incomplete"
  tail_log evaluator
  [ "$status_code" -ne 0 ] || status_code=1
fi

# fresh FILE: FILE was written by this run (not left by an earlier run into the same folder).
fresh() {
  local mtime
  [ -s "$1" ] && mtime=$(stat -c %.6Y "$1") && [ "${mtime//[.,]/}" -ge "$run_started_us" ]
}

# The recorder (the evaluator, or hunav_run in process) died before it wrote run.json (killed, or a
# crash): run.json from what it recorded, with status aborted and why (states.csv cut at its last
# whole sample), so the run's status, seed and reason are on record.
recorder=evaluator
[ "$mode" != inprocess ] || recorder=hunav_run
if [ "$status_code" -ne 2 ] && [ "${code_of[$recorder]:-0}" -ne 0 ] && ! fresh "$out_dir/run.json"; then
  salvage_reason=${abort_reason:-"$(exit_text "$recorder" "${code_of[$recorder]}") before it wrote run.json"}
  salvage_args=()
  for ((k = 0; k < ${#eval_args[@]}; k++)); do
    case ${eval_args[k]} in
      --counterfactual) ;;
      --robot-free-program) k=$((k + 1)) ;;  # and its value
      *) salvage_args+=("${eval_args[k]}") ;;
    esac
  done
  if "$bin_dir/hunav_evaluator" --salvage "$out_dir" --reason "$salvage_reason" --scenario "$scenario" \
    --planner "$planner" --mode "$mode" "${seed_args[@]}" "${salvage_args[@]}" >>"$log_dir/salvage.log" 2>&1; then
    log "the $recorder died before it wrote run.json: run.json written from what it recorded (status aborted)"
    [ "$status_code" -ne 0 ] || status_code=1
  else
    err "the $recorder died, and run.json could not be written from what it recorded (see $log_dir/salvage.log)"
  fi
fi

if [ "$mode" != inprocess ]; then
  # The run's line and metrics table as hunav_run prints them (from the evaluator's run.json), then the
  # scenario's expect: conditions (docs/metrics.md, "Expectations"), judged by the same code as
  # hunav_run's (exit 3 when one failed; judged only for an episode that ran to an end).
  if fresh "$out_dir/run.json"; then
    expect_rc=0
    "$bin_dir/hunav_expect" --show --scenario "$scenario" --run-dir "$out_dir" || expect_rc=$?
    [ "$status_code" -ne 0 ] || status_code=$expect_rc
  elif [ "$status_code" -ne 2 ]; then
    err "the evaluator wrote no run.json (see $log_dir/evaluator.log)"
    [ "$status_code" -ne 0 ] || status_code=1
  fi
elif ! fresh "$out_dir/metrics.csv" && [ "$status_code" -eq 0 ]; then
  err "hunav_run wrote no metrics.csv"
  status_code=1
fi
if fresh "$out_dir/run.json"; then
  # run.json read by a JSON parser (hunav_expect --get: one value a line), not by pattern.
  status="" reason="" sim_time="" fingerprint=""
  { IFS= read -r status && IFS= read -r reason && IFS= read -r sim_time && IFS= read -r fingerprint; } < <(
    "$bin_dir/hunav_expect" --run-dir "$out_dir" --get status --get reason --get sim_time --get fingerprint ||
      err "cannot read $out_dir/run.json"
  ) || true
  log "run: status ${status} (${reason}), sim_time ${sim_time} s, fingerprint ${fingerprint}"
  case "$reason" in
    "planner not ready"*)
      if [ -n "$planner_cmd" ]; then
        err "your planner command '$planner_cmd' never announced itself: it must publish a planner_ready_t on"
        echo "  PLANNER_READY once subscribed, then every 0.5 s (docs/planner_contract.md, \"Readiness\"); its output: $log_dir/planner.log" >&2
      fi ;;
  esac
fi
if [ "$status_code" -eq 2 ]; then
  log "nothing was run (bad input); logs in $log_dir"
else
  log "results: $out_dir"
fi
exit "$status_code"
