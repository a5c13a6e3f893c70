#!/usr/bin/env bash
# Every binary's answer to a bad command line: exit 2 with one short line naming what is wrong.
#  - "--seed abc": "--seed: expected a non-negative integer, got 'abc'" (CLI11's own check printed a
#    398-character range with a 309-digit number);
#  - an unknown flag alone is named ("--bogus" was reported as "--out is required");
#  - a missing input folder: exit 2 with the path named, hunav_summary like hunav_report.
set -euo pipefail
: "${REPO:?}" "${BIN:?}"
WORK=$(mktemp -d /tmp/hunav_cli.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# expect_2 WANT CMD...: CMD exits 2 and its output holds WANT (a fixed string).
expect_2() {
  local want=$1 rc=0
  shift
  "$@" > "$WORK/out.txt" 2>&1 < /dev/null || rc=$?
  [ "$rc" -eq 2 ] || { cat "$WORK/out.txt" >&2; fail "$*: exit $rc, want 2"; }
  grep -qF -- "$want" "$WORK/out.txt" || { cat "$WORK/out.txt" >&2; fail "$*: no '$want' in the output"; }
}

scenario="$REPO/scenarios/passing.yaml"
for bin in hunav_run hunav_worldsim; do
  for value in abc -3 1.5 99999999999999999999; do
    expect_2 "--seed: expected a non-negative integer, got '$value'" "$BIN/$bin" --scenario "$scenario" --seed "$value"
  done
  # One short line and the usual hint, no 309-digit range.
  [ "$(wc -c < "$WORK/out.txt")" -lt 120 ] || { cat "$WORK/out.txt" >&2; fail "$bin: message too long"; }
  expect_2 "--duration: expected a positive number, got 'abc'" "$BIN/$bin" --scenario "$scenario" --duration abc
done
expect_2 "--sample-rate: expected a non-negative number, got 'x'" "$BIN/hunav_run" --scenario "$scenario" --sample-rate x
expect_2 "--episodes: expected a non-negative integer, got 'two'" "$BIN/hunav_manager" --episodes two
expect_2 "--episodes: expected a non-negative integer, got '-1'" "$BIN/hunav_evaluator" --out "$WORK/e" --episodes -1
expect_2 "--episodes: expected a non-negative integer, got '1.5'" "$BIN/hunav_planner" --scenario "$scenario" --episodes 1.5
expect_2 "--max-frames: expected a positive integer, got '0'" "$BIN/hunav_report" "$WORK" --max-frames 0

# An unknown flag alone: named, whatever the binary requires.
for bin in hunav_run hunav_worldsim hunav_manager hunav_planner hunav_evaluator hunav_record hunav_report \
           hunav_summary hunav_expect hunav_view hunav_realism; do
  [ -x "$BIN/$bin" ] || fail "$BIN/$bin: not built"
  expect_2 "The following argument was not expected: --bogus" "$BIN/$bin" --bogus
  if grep -q "is required" "$WORK/out.txt"; then cat "$WORK/out.txt" >&2; fail "$bin --bogus: reports a requirement"; fi
done

# A missing input folder: exit 2, the path named.
expect_2 "$WORK/nonexistent: no such folder" "$BIN/hunav_summary" "$WORK/nonexistent"
expect_2 "$WORK/nonexistent: no such folder" "$BIN/hunav_report" "$WORK/nonexistent"
mkdir -p "$WORK/empty"
expect_2 "$WORK/empty/runs: no such folder" "$BIN/hunav_summary" "$WORK/empty"
echo "bad command lines: exit 2 with a short message"
