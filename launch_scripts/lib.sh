# shellcheck shell=bash
# What the launch scripts (run_experiment.sh, run_batch.sh, slurm_batch.sh, spy.sh) share, written once:
# where the repository and the binaries are, messages, option parsing and value checks, the LCM URL and
# the run's private network namespace, and starting, watching and stopping child processes.
# Sourced, not run: the script sets `prog` (the name its messages begin with), then
#   source "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/lib.sh"
# shellcheck disable=SC2034 # variables set here are the sourcing script's

# ---------------------------------------------------------------------------------------------------
# Where things are
# ---------------------------------------------------------------------------------------------------
# The sourcing script resolved through links (it re-runs itself by this path, and may be started from
# any folder or through a link); the repository is its folder's parent.
: "${prog:?the script sets prog before it sources lib.sh}"
script_path=$(readlink -f "${BASH_SOURCE[1]}")
repo_root=$(cd "$(dirname "$script_path")/.." && pwd)
bin_dir=${HUNAV_BIN_DIR:-$repo_root/build/bin}

# ---------------------------------------------------------------------------------------------------
# Messages: each line begins with the script's name, so interleaved logs of a batch say who spoke
# ---------------------------------------------------------------------------------------------------
log() { printf '%s: %s\n' "$prog" "$*"; }
err() { printf '%s: error: %s\n' "$prog" "$*" >&2; }
warn() { printf '%s: warning: %s\n' "$prog" "$*" >&2; }
# die MESSAGE: an error the user fixes outside the command line (a tool or file missing): exit 1.
die() {
  err "$*"
  exit 1
}
# usage_error MESSAGE: bad arguments: the message and where the help is, exit 2 (nothing was run).
usage_error() {
  err "$*"
  echo "$prog: see: launch_scripts/${script_path##*/} --help" >&2
  exit 2
}
# need_bin NAME: the build's program NAME must exist before anything starts.
need_bin() {
  [ -x "$bin_dir/$1" ] || die "$bin_dir/$1 is missing: build the project first (bash launch_scripts/setup.sh)"
}

# lock_folder DIR: an exclusive lock on the results folder DIR for as long as this script runs: flock
# on the folder itself, the lock the C++ tools take (result_files/include/hunav/results/folder_lock.hpp),
# which the processes this script starts inherit and take over. Another live run or batch holds DIR:
# exit 2 with a message.
lock_folder() {
  exec {folder_lock_fd}<"$1" || die "cannot open the folder '$1'"
  if ! flock -n "$folder_lock_fd"; then
    err "another run is writing into $1: give each run (and each batch) a results folder of its own"
    exit 2
  fi
}

# ---------------------------------------------------------------------------------------------------
# Options: --name value and --name=value both work. A loop reads them as
#   while [ "$#" -gt 0 ]; do split_option "$1"; case "$opt" in ... --x) option_value "$@"; x=$value ;;
#   esac; shift $((1 + taken)); done
# ---------------------------------------------------------------------------------------------------
# split_option ARG: --NAME=VALUE gives opt=--NAME, value=VALUE, inline=1; else opt=ARG, value="",
# inline=0. taken=0: no argument after ARG is used yet.
split_option() {
  opt=$1 value="" inline=0 taken=0
  case "$opt" in --*=*) value=${opt#*=} opt=${opt%%=*} inline=1 ;; esac
}
# option_value_or_empty "$@" (the arguments from the option on): $opt's value, inline or the next
# argument (then taken=1, for the loop's shift); none at all is a usage error naming the option.
option_value_or_empty() {
  [ "$inline" -eq 0 ] || return 0
  [ "$#" -ge 2 ] || usage_error "$opt needs a value"
  value=$2 taken=1
}
# option_value "$@": the same, and an empty value is a usage error too.
option_value() {
  option_value_or_empty "$@"
  [ -n "$value" ] || usage_error "$opt needs a non-empty value"
}
# no_value: a flag written with a value (--record=1) is a usage error.
no_value() { [ "$inline" -eq 0 ] || usage_error "$opt takes no value"; }

# is_number V: a plain decimal >= 0 (no sign, no exponent), as seconds and rates are written here.
is_number() { [[ $1 =~ ^([0-9]+([.][0-9]*)?|[.][0-9]+)$ ]]; }
is_positive() { is_number "$1" && awk -v v="$1" 'BEGIN { exit !(v > 0) }'; }
# is_count V: an integer >= 1 (jobs, tasks, runs per task).
is_count() { [[ $1 =~ ^[1-9][0-9]*$ ]]; }

# The checks of option values; each passes an empty (not given) value and names the option on error.
# check_seconds OPT V: a number of seconds > 0.
check_seconds() { [ -z "$2" ] || is_positive "$2" || usage_error "$1 must be a number of seconds > 0 (got '$2')"; }
# check_count OPT V: an integer >= 1.
check_count() { [ -z "$2" ] || is_count "$2" || usage_error "$1 must be an integer >= 1 (got '$2')"; }
# check_choice OPT V CHOICE...: one of the CHOICEs, listed in the message as "a, b or c".
check_choice() {
  local o=$1 v=$2 c list=""
  shift 2
  [ -n "$v" ] || return 0
  for c in "$@"; do [ "$v" != "$c" ] || return 0; done
  for c in "${@:1:$#-1}"; do list+="${list:+, }$c"; done
  usage_error "$o must be $list or ${!#} (got '$v')"
}
# check_file WHAT FILE: a readable file (WHAT: the option, and the name it is given for).
check_file() { if [ ! -f "$2" ] || [ ! -r "$2" ]; then usage_error "$1: cannot read the file '$2'"; fi; }

# ---------------------------------------------------------------------------------------------------
# The LCM bus and the run's private network namespace
# ---------------------------------------------------------------------------------------------------
# default_lcm_url: the bus our processes use when told none (kDefaultLcmUrl in
# common/transport/include/hunav/open_bus.hpp, its one definition), asked of the build rather than written here.
default_lcm_url() {
  need_bin hunav_record
  env -u LCM_DEFAULT_URL "$bin_dir/hunav_record" --print-url
}
# with_url_option URL OPTION: URL with OPTION (name=value) added to its query.
with_url_option() { if [[ $1 == *\?* ]]; then printf '%s&%s' "$1" "$2"; else printf '%s?%s' "$1" "$2"; fi; }
# plain_lcm_url URL: URL without our option channel_ports=1 (common/transport/include/hunav/open_bus.hpp): the
# URL's own port only, where the evaluator listens.
plain_lcm_url() { printf '%s' "$1" | sed -E 's/([?&])channel_ports=1(&|$)/\1/; s/[?&]$//'; }
# foreign_lcm_url URL: URL without any option of ours (also receive=lcm), for LCM's own tools (lcm-spy).
foreign_lcm_url() { plain_lcm_url "$1" | sed -E 's/([?&])receive=lcm(&|$)/\1/; s/[?&]$//'; }

# multicast_route URL: for a udpm:// URL, how its group is routed on this host: sets mc_group and mc_dev
# (the interface, lo keeping it on the host). Returns 1 when the group has no route (LCM hears nothing).
multicast_route() {
  local route
  mc_group="" mc_dev=""
  [[ $1 =~ ^udpm://([0-9.]+) ]] && command -v ip >/dev/null 2>&1 || return 0
  mc_group=${BASH_REMATCH[1]}
  route=$(ip route get "$mc_group" 2>/dev/null) || return 1
  if [[ $route =~ dev[[:space:]]+([^[:space:]]+) ]]; then mc_dev=${BASH_REMATCH[1]}; fi
}

# in_private_netns: true in the copy of the script that reexec_in_private_netns started (its namespace
# differs from the one it was started from); the marker is not passed on to the processes of the run.
in_private_netns() {
  local parent=${HUNAV_NETNS_PARENT:-} here
  unset HUNAV_NETNS_PARENT
  here=$(readlink /proc/self/ns/net 2>/dev/null || echo unknown)
  [ -n "$parent" ] && [ "$parent" != "$here" ]
}
# netns_unshare_flags: the unshare flags that make a network namespace here (root: --net; anyone: a user
# namespace too, --map-root-user --net): sets unshare_flags, or returns 1 with unshare's complaint in
# unshare_error.
netns_unshare_flags() {
  local candidates c
  if [ "$(id -u)" -eq 0 ]; then candidates=("--net" "--map-root-user --net"); else candidates=("--map-root-user --net"); fi
  unshare_flags="" unshare_error=""
  for c in "${candidates[@]}"; do
    # shellcheck disable=SC2086 # $c holds flags
    if unshare_error=$(unshare $c -- true 2>&1); then
      unshare_flags=$c
      return 0
    fi
  done
  return 1
}
# reexec_in_private_netns ARGS...: runs the script again with ARGS in a new network namespace, as the
# same process (exec: the PID the script printed stays the namespace's holder). Needs netns_unshare_flags.
reexec_in_private_netns() {
  # shellcheck disable=SC2086 # $unshare_flags holds flags
  HUNAV_NETNS_PARENT=$(readlink /proc/self/ns/net 2>/dev/null || echo unknown) \
    exec unshare $unshare_flags -- "$BASH" "$script_path" "$@"
}
# loopback_multicast: inside the namespace, multicast on its own loopback (nothing leaves the run).
loopback_multicast() { ip link set lo up && ip route replace 224.0.0.0/4 dev lo; }
# netns_join_command PID: sets netns_join to the nsenter command that enters PID's network namespace,
# and its user namespace too when it has its own (a run started by a normal user: unshare -rn).
netns_join_command() {
  netns_join=(nsenter --target "$1" --net)
  if [ "$(readlink "/proc/$1/ns/user" 2>/dev/null || true)" != "$(readlink /proc/self/ns/user)" ]; then
    netns_join+=(--user --preserve-credentials)
  fi
}

# ---------------------------------------------------------------------------------------------------
# Child processes, by name: start, watch, stop
# ---------------------------------------------------------------------------------------------------
declare -A pid_of=()   # name -> pid of every process started
declare -A code_of=()  # name -> exit code once collected
started=()             # names in start order
launcher=()            # what start puts before each command (use_own_sessions)

# use_own_sessions: every later start gives its process a session of its own (setsid: a terminal's
# Ctrl-C reaches only the script, which stops them in order) and, where setpriv supports it, SIGTERM
# when the script dies, even by SIGKILL. Without it a process shares the script's process group.
use_own_sessions() {
  launcher=(setsid)
  if setpriv --help 2>/dev/null | grep -q -- --pdeathsig; then launcher+=(setpriv --pdeathsig TERM --); fi
}

# start NAME LOGFILE CMD...: starts CMD in the background, its output into LOGFILE (emptied first).
start() {
  local name=$1 logfile=$2
  shift 2
  : >"$logfile"
  "${launcher[@]}" "$@" >>"$logfile" 2>&1 </dev/null &
  pid_of[$name]=$!
  started+=("$name")
}

alive() { [ -n "${pid_of[$1]:-}" ] && [ -z "${code_of[$1]:-}" ] && kill -0 "${pid_of[$1]}" 2>/dev/null; }

# collect NAME: waits until NAME has exited and records its exit code. A trap that interrupts the wait
# (a forwarded Ctrl-C: status > 128) does not count as its exit: it waits again while the process lives.
collect() {
  local name=$1 rc
  [ -z "${code_of[$name]:-}" ] || return 0
  while :; do
    rc=0
    wait "${pid_of[$name]}" 2>/dev/null || rc=$?
    if [ "$rc" -le 128 ] || ! kill -0 "${pid_of[$name]}" 2>/dev/null; then break; fi
  done
  code_of[$name]=$rc
}

# signal NAME SIG: sends SIG to NAME's process group (it and anything it started), else to NAME alone.
signal() {
  local pid=${pid_of[$1]}
  kill -s "$2" -- "-$pid" 2>/dev/null || kill -s "$2" "$pid" 2>/dev/null || true
  # A stopped (SIGSTOPped) process handles SIGTERM only once continued.
  if [ "$2" = TERM ]; then kill -s CONT -- "-$pid" 2>/dev/null || kill -s CONT "$pid" 2>/dev/null || true; fi
}

# Wall-clock deadlines in microseconds (EPOCHREALTIME: no fork per check).
now_us() { local t=${EPOCHREALTIME//[.,]/}; echo "$((10#$t))"; }
# deadline SECONDS: sets $deadline_us to now + SECONDS (0 = none).
deadline() {
  if [ "$1" = 0 ]; then deadline_us=0; return 0; fi
  deadline_us=$(($(now_us) + $(awk -v s="$1" 'BEGIN { printf "%d", s * 1000000 }')))
}
# past DEADLINE_US: true once that deadline has passed (never for 0).
past() { [ "$1" -ne 0 ] && [ "$(now_us)" -ge "$1" ]; }

# wait_exit NAME SECONDS: waits until NAME has exited (SECONDS = 0: forever). Returns 1 on timeout.
wait_exit() {
  local name=$1 deadline_us
  deadline "$2"
  while alive "$name"; do
    if past "$deadline_us"; then return 1; fi
    sleep 0.1
  done
  collect "$name"
}

# stop NAME SIG GRACE: sends SIG, waits GRACE seconds, then SIGKILLs what is left.
stop() {
  local name=$1 sig=$2 grace=$3
  alive "$name" || { [ -z "${pid_of[$name]:-}" ] || collect "$name"; return 0; }
  signal "$name" "$sig"
  if ! wait_exit "$name" "$grace"; then
    err "$name did not stop within ${grace} s of SIG$sig: killing it"
    signal "$name" KILL
    wait_exit "$name" 0 || true
  fi
}

# watchdog SECONDS CMD...: runs CMD (a command or function) in the background once SECONDS have passed,
# unless end_watchdog comes first. It sleeps rather than polls: a long chunk of runs costs nothing.
watchdog() {
  local seconds=$1
  shift
  (
    trap 'kill "$sleeper" 2>/dev/null; exit 0' TERM
    sleep "$seconds" &
    sleeper=$!
    wait "$sleeper"
    "$@"
  ) &
  watchdog_pid=$!
}
end_watchdog() {
  kill -TERM "$watchdog_pid" 2>/dev/null || true
  wait "$watchdog_pid" 2>/dev/null || true
}

# proc_state PID: sets $state to the state letter of /proc/PID/stat (R, S, D, T stopped, t traced,
# Z ...), empty when gone. No subshell: it runs for every process ten times a second.
proc_state() {
  local line=""
  state=""
  { read -r line <"/proc/$1/stat"; } 2>/dev/null || return 0
  line=${line##*) }
  state=${line%% *}
}
