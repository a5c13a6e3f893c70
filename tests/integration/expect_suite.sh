#!/usr/bin/env bash
# The CI suite (scenarios/suites/): each file is its scenario unchanged plus an expect: block, and dwb
# passes every condition for seed 1 through run_batch.sh (exit 0, junit.xml without failures).
source "$(dirname "$0")/common.sh"
py=/usr/bin/python3
names=()
for f in "$REPO"/scenarios/suites/*.yaml; do
  name=$(basename "$f" .yaml)
  names+=("$f")
  # The suite file minus its two header lines and its expect: block is the scenario (map paths one
  # folder up).
  $py - "$f" "$REPO/scenarios/$name.yaml" <<'PY' || fail "$f is not scenarios/$name.yaml plus expect:"
import sys
suite = open(sys.argv[1]).read().split("\n", 2)[2]
body = suite[: suite.index("\n\n# CI expectations")] + "\n"
orig = open(sys.argv[2]).read().replace("map_server: maps/", "map_server: ../maps/")
assert body == orig.rstrip("\n") + "\n", "differs"
PY
done
[ "${#names[@]}" -ge 3 ] || fail "the suite has ${#names[@]} scenarios"
list=$(IFS=,; echo "${names[*]}")
rc=0
"$REPO/launch_scripts/run_batch.sh" --scenarios "$list" --planners dwb --seeds 1 --jobs 2 --out "$WORK/batch" \
  > "$WORK/batch.txt" 2>&1 || rc=$?
[ "$rc" -eq 0 ] || { cat "$WORK/batch.txt"; cat "$WORK"/batch/runs/*/expect.json; fail "suite with dwb: exit $rc"; }
$py - "$WORK/batch/junit.xml" "${#names[@]}" <<'PY' || fail "junit.xml"
import sys
import xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
cases = root.findall("./testsuite/testcase")
assert len(cases) >= 5 * int(sys.argv[2]) and root.get("tests") == str(len(cases)), len(cases)
assert root.get("failures") == "0" and root.get("errors") == "0", ET.tostring(root)
assert all(c.get("classname").endswith(".dwb") and c.get("name").startswith("seed 1: ") for c in cases)
PY
no_orphans
echo "suite: ${#names[@]} scenarios, dwb seed 1 passes"
