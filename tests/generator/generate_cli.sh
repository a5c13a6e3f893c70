#!/usr/bin/env bash
# hunav_generate's command line: bad options exit 2 naming the option and write nothing; the same
# seeds give the same bytes; what it writes loads in hunav_run; --map places people on HuNavSim's
# cafe map; a map too small for the robot's start and goal far apart is refused (exit 1, the reason,
# nothing written).
set -euo pipefail
BIN=${HUNAV_BIN:?set HUNAV_BIN to the bin folder of the build}
REPO=$(cd "$(dirname "$0")/../.." && pwd)
WORK=$(mktemp -d /tmp/hunav_generate.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

expect_2() {  # expect_2 NAMED ARGS...: exit 2, the message names NAMED, nothing written
  local named=$1 rc=0
  shift
  "$BIN/hunav_generate" "$@" > "$WORK/out.txt" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || { cat "$WORK/out.txt"; fail "exit $rc for '$*', expected 2"; }
  grep -q -- "$named" "$WORK/out.txt" || { cat "$WORK/out.txt"; fail "'$*': the message does not name $named"; }
  [ ! -e "$WORK/bad" ] || fail "'$*' wrote $WORK/bad"
}
expect_2 --seed --seed -1 --out "$WORK/bad"
expect_2 --seed --seed abc --out "$WORK/bad"
expect_2 --size --size 3 --out "$WORK/bad"
expect_2 --size --size 20,10 --out "$WORK/bad"
expect_2 --size --size 10,1000 --out "$WORK/bad"
expect_2 --size --size 10,ten --out "$WORK/bad"
expect_2 --count --count 0 --out "$WORK/bad"
expect_2 --layout --layout castle --out "$WORK/bad"
expect_2 --people --people 5,2 --out "$WORK/bad"
expect_2 --time-factor --time-factor 0.5 --out "$WORK/bad"
expect_2 --robot-radius --robot-radius 2 --out "$WORK/bad"
expect_2 --out --seed 1
expect_2 no_such_map.yaml --map "$WORK/no_such_map.yaml" --out "$WORK/bad"

# The same seeds twice: the same bytes.
"$BIN/hunav_generate" --seed 42 --count 3 --size 10,14 --out "$WORK/a" > "$WORK/a.txt"
"$BIN/hunav_generate" --seed 42 --count 3 --size 10,14 --out "$WORK/b" > /dev/null
diff -r "$WORK/a" "$WORK/b" > /dev/null || fail "the same seeds gave different files"
[ "$(grep -c '^wrote ' "$WORK/a.txt")" = 3 ] || { cat "$WORK/a.txt"; fail "not one line per scenario"; }
for seed in 42 43 44; do
  { [ -f "$WORK/a/gen_$seed.yaml" ] && [ -f "$WORK/a/maps/gen_$seed.yaml" ] && [ -f "$WORK/a/maps/gen_$seed.pgm" ]; } ||
    fail "seed $seed: missing files"
done

# What it writes is an ordinary scenario: a short episode of it runs.
"$BIN/hunav_run" --scenario "$WORK/a/gen_42.yaml" --planner dwb --duration 2 --out "$WORK/run" > "$WORK/run.txt" 2>&1 ||
  { cat "$WORK/run.txt"; fail "hunav_run on a generated scenario"; }
grep -q '"status": "time_limit"' "$WORK/run/run.json" || fail "the 2 s episode did not end at its time limit"

# On HuNavSim's cafe map, referred to by its path from the output folder.
"$BIN/hunav_generate" --seed 1 --map "$REPO/scenarios/maps/map_cafe2.yaml" --out "$WORK/cafe" > "$WORK/cafe.txt"
grep -q "^  map_server: .*scenarios/maps/map_cafe2.yaml" "$WORK/cafe/map_cafe2_1.yaml" || fail "the cafe map is not referred to"
"$BIN/hunav_run" --scenario "$WORK/cafe/map_cafe2_1.yaml" --planner none --duration 1 --out "$WORK/cafe_run" > /dev/null 2>&1 ||
  fail "hunav_run on the scenario made on the cafe map"

# A 3 m x 3 m room: no start and goal 4 m apart. Refused, exit 1, with the reason; nothing written.
python3 - "$WORK/tiny" <<'PY'
import os, sys
d = sys.argv[1]; os.makedirs(d)
n = 80  # 4 m at 0.05 m: a wall round a 3 m x 3 m room in the middle
rows = bytes(0 if (10 <= x < 70 and 10 <= y < 70 and not (12 <= x < 68 and 12 <= y < 68)) else 254
             for y in range(n) for x in range(n))
open(os.path.join(d, "tiny.pgm"), "wb").write(b"P5\n%d %d\n255\n" % (n, n) + rows)
open(os.path.join(d, "tiny.yaml"), "w").write("image: tiny.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
                                               "occupied_thresh: 0.65\nfree_thresh: 0.25\n")
PY
rc=0
"$BIN/hunav_generate" --seed 5 --map "$WORK/tiny/tiny.yaml" --out "$WORK/tiny_out" > "$WORK/tiny.txt" 2>&1 || rc=$?
[ "$rc" -eq 1 ] || { cat "$WORK/tiny.txt"; fail "exit $rc for a map too small, expected 1"; }
grep -q "refused: seed 5: .*apart" "$WORK/tiny.txt" || { cat "$WORK/tiny.txt"; fail "no reason given"; }
[ -z "$(ls "$WORK/tiny_out" 2>/dev/null)" ] || fail "a refused seed wrote files"
echo "hunav_generate: option errors, determinism, loading, --map and refusal as documented"
