# Helpers for the integration tests. Sourced; expects REPO and BIN set by the caller (ctest).
set -euo pipefail
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

our_processes() { pgrep -f "$BIN/hunav_(run|worldsim|manager|planner|evaluator)" || true; }

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
