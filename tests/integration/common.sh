# shellcheck shell=bash
# Helpers for the integration tests. Sourced; expects REPO and BIN set by the caller (ctest).
set -euo pipefail
# Processes are looked for in this test's own process tree only, never machine-wide, so that another
# user's runs (or a second test run) on the machine cannot fail this test. The test shell becomes a
# child subreaper (prctl PR_SET_CHILD_SUBREAPER = 36, kept across exec), so a process whose parent
# died is re-parented to it and still counts as this test's.
if [ "${HUNAV_IT_SUBREAPER:-}" != "$$" ]; then
  HUNAV_IT_SUBREAPER=$$ exec /usr/bin/python3 -c '
import ctypes, os, sys
if ctypes.CDLL(None, use_errno=True).prctl(36, 1, 0, 0, 0) != 0:
    sys.exit("common.sh: prctl(PR_SET_CHILD_SUBREAPER) failed")
os.execv("/bin/bash", ["bash"] + sys.argv[1:])' "$0" "$@"
fi
# shellcheck disable=SC2034  # used by the tests that source this file
RUN="$REPO/launch_scripts/run_experiment.sh"
export HUNAV_BIN_DIR="$BIN"
WORK=$(mktemp -d /tmp/hunav_it.XXXXXX)
cleanup_work() { rm -rf "$WORK"; }
trap cleanup_work EXIT

fail() { echo "FAIL: $*" >&2; exit 1; }

json_field() {  # json_field FILE KEY -> value (strings unquoted)
  python3 -c 'import json,sys; v=json.load(open(sys.argv[1]))[sys.argv[2]]; print(str(v).lower() if isinstance(v,bool) else v)' "$1" "$2"
}

metric() {  # metric METRICS_CSV NAME -> value in the last row
  python3 -c 'import csv,sys; rows=list(csv.DictReader(open(sys.argv[1]))); print(rows[-1][sys.argv[2]])' "$1" "$2"
}

check_layout() {  # check_layout DIR: the shared layout checker, when shared/ is beside the repo
  local checker="$REPO/../shared/tools/check_outputs.py"
  if [ -f "$checker" ]; then python3 "$checker" "$1" || fail "layout check of $1"; fi
}

descendants() {  # the PIDs below this test shell (its whole process tree)
  ps -e -o pid=,ppid= | awk -v root=$$ '{ parent[$1] = $2 }
    END { for (p in parent) { q = p; while ((q in parent) && q != root && q > 1) q = parent[q]; if (q == root && p != root) print p } }'
}

our_pids() {  # our_pids REGEX: PIDs of this test's tree whose command line matches REGEX
  local p args
  for p in $(descendants); do
    args=$(tr '\0' ' ' 2>/dev/null < "/proc/$p/cmdline") || continue
    if [[ $args =~ $1 ]]; then echo "$p"; fi
  done
}

our_processes() { our_pids "^$BIN/hunav_(run|worldsim|manager|planner|evaluator|record) "; }

our_pid() {  # our_pid NAME: the PID of this test's hunav_NAME (or another binary of BIN) process
  our_pids "^$BIN/(hunav_)?$1( |\$)" | head -n1
}

# wait_until SECONDS WHAT COMMAND...: runs COMMAND every 0.1 s until it succeeds; after SECONDS of
# wall-clock time, fails naming WHAT. Bounds are generous: a loaded machine makes a test slower, never
# fail, and a test that passes waits only as long as the condition takes.
wait_until() {
  local bound=$1 what=$2 end
  shift 2
  end=$((SECONDS + bound))
  until "$@"; do
    [ "$SECONDS" -lt "$end" ] || fail "$what (still not after $bound s)"
    sleep 0.1
  done
}

none_of_ours() { [ -z "$(our_processes)" ]; }
no_orphans() {  # no process of ours may survive a run (they get 30 s to exit)
  local end=$((SECONDS + 30))
  until none_of_ours; do
    if [ "$SECONDS" -ge "$end" ]; then
      ps -o pid,args -p "$(our_processes | paste -sd,)" >&2 || true
      fail "processes left behind"
    fi
    sleep 0.1
  done
}

has_rows() { [ -f "$1" ] && [ "$(wc -l < "$1")" -gt "$2" ]; }
wait_for_rows() {  # wait_for_rows FILE N: until FILE has more than N lines
  wait_until 120 "$1 never got $2 rows" has_rows "$1" "$2"
}

# wait_printed_ready FILE: until FILE (a started process's output) holds the line "ready"; else shows it.
printed_ready() { grep -q -x ready "$1" 2>/dev/null; }
wait_printed_ready() {
  (wait_until 60 "$1 has no line 'ready'" printed_ready "$1") || { cat "$1" >&2; fail "the process never printed ready"; }
}

# reached_sim_time FILE T: FILE (a states.csv being written) holds a row at simulated time T s or later.
reached_sim_time() {
  [ -f "$1" ] && awk -F, -v t="$2" 'NR > 1 && $1 + 0 >= t { found = 1; exit } END { exit !found }' "$1"
}
wait_for_sim_time() {  # wait_for_sim_time FILE T: until FILE has reached T s of simulated time
  wait_until 120 "$1 never reached t = $2 s" reached_sim_time "$1" "$2"
}
