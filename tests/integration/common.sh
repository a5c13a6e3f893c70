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

no_orphans() {  # no process of ours may survive a run (bounded wait: 5 s)
  for _ in $(seq 50); do [ -z "$(our_processes)" ] && return 0; sleep 0.1; done
  ps -o pid,args -p "$(our_processes | paste -sd,)" >&2 || true
  fail "processes left behind"
}

wait_for_rows() {  # wait_for_rows FILE N: until FILE has more than N lines (bounded: 30 s)
  for _ in $(seq 300); do
    [ -f "$1" ] && [ "$(wc -l < "$1")" -gt "$2" ] && return 0
    sleep 0.1
  done
  fail "$1 never got $2 rows"
}
