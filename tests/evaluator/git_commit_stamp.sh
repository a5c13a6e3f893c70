#!/usr/bin/env bash
# cmake/GitCommit.cmake on a scratch repository: "unknown" outside git, the short commit, "-dirty"
# for changed tracked files only, a new commit picked up without reconfiguring, and the header left
# untouched (same mtime) when nothing changed. Then the wiring: run.json of this build carries the
# commit stamped into this build's header. Expects REPO, BIN and STAMP (the generated header).
set -euo pipefail
SCRIPT="$REPO/cmake/GitCommit.cmake"
WORK=$(mktemp -d /tmp/hunav_stamp.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

stamp() {  # stamp DIR -> the commit text the script writes for DIR
  cmake -DSOURCE_DIR="$1" -DOUTPUT="$WORK/out.hpp" -P "$SCRIPT"
  sed -n 's/^#define HUNAV_GIT_COMMIT_DEFAULT "\(.*\)"$/\1/p' "$WORK/out.hpp"
}

mkdir "$WORK/plain"
[ "$(stamp "$WORK/plain")" = unknown ] || fail "outside git: expected unknown, got $(stamp "$WORK/plain")"

scratch="$WORK/repo"
mkdir "$scratch"
git -C "$scratch" init -q
git -C "$scratch" config user.email test@example.invalid
git -C "$scratch" config user.name test
echo one > "$scratch/a.txt"
git -C "$scratch" add a.txt
git -C "$scratch" commit -q -m one
first=$(git -C "$scratch" rev-parse --short HEAD)
[ "$(stamp "$scratch")" = "$first" ] || fail "clean tree: expected $first, got $(stamp "$scratch")"

# Unchanged text: the header is not rewritten (so nothing that includes it is rebuilt).
touch -d '2000-01-01' "$WORK/out.hpp"
before=$(stat -c %Y "$WORK/out.hpp")
stamp "$scratch" > /dev/null
[ "$(stat -c %Y "$WORK/out.hpp")" = "$before" ] || fail "an unchanged stamp rewrote the header"

echo scratch > "$scratch/untracked.txt"
[ "$(stamp "$scratch")" = "$first" ] || fail "an untracked file made the tree dirty"
touch "$scratch/a.txt"
[ "$(stamp "$scratch")" = "$first" ] || fail "a touched but unchanged file made the tree dirty"

echo two > "$scratch/a.txt"
[ "$(stamp "$scratch")" = "$first-dirty" ] || fail "changed tracked file: expected $first-dirty, got $(stamp "$scratch")"

git -C "$scratch" commit -q -am two
second=$(git -C "$scratch" rev-parse --short HEAD)
[ "$second" != "$first" ] || fail "the scratch repository did not get a new commit"
[ "$(stamp "$scratch")" = "$second" ] || fail "new commit: expected $second, got $(stamp "$scratch")"

# This build: run.json says what this build's header says.
built=$(sed -n 's/^#define HUNAV_GIT_COMMIT_DEFAULT "\(.*\)"$/\1/p' "$STAMP")
[ -n "$built" ] || fail "no stamp in $STAMP"
env -u HUNAV_GIT_COMMIT "$BIN/hunav_run" --scenario "$REPO/scenarios/passing.yaml" --planner none --duration 0.5 \
  --out "$WORK/run" > /dev/null
recorded=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["git_commit"])' "$WORK/run/run.json")
[ "$recorded" = "$built" ] || fail "run.json git_commit $recorded, the build's stamp $built"
echo "PASS: stamps $first, $first-dirty, $second; this build $built"
