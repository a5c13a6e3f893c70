#!/usr/bin/env bash
# The leftover-process check (common.sh, no_orphans) looks at this test's own process tree only: a
# process that looks like ours but belongs to someone else (here a decoy named like hunav_manager,
# started outside the checking shell's tree) must not fail it, while one of its own tree must, even
# after its parent died (the test shell is a child subreaper). Before, pgrep looked machine-wide, and
# two test runs on one machine failed each other.
source "$(dirname "$0")/common.sh"
# A decoy outside the checker's tree: a sibling of the checking shell below.
bash -c "exec -a '$BIN/hunav_manager --decoy' sleep 30" &
decoy=$!
trap 'kill "$decoy" 2>/dev/null || true; cleanup_work' EXIT
named_like_ours() { [[ $(tr '\0' ' ' 2>/dev/null < "/proc/$1/cmdline") == "$BIN/hunav_"* ]]; }
wait_until 60 "the decoy never took its name" named_like_ours "$decoy"
# A fresh test shell (a script of its own, so common.sh makes it a subreaper): MODE clean or orphan.
cat > "$WORK/checker.sh" <<'CHECKER'
source "$REPO/tests/integration/common.sh"
if [ "$1" = orphan ]; then
  # A process of its own tree whose parent exits at once: re-parented to this shell, still its own.
  bash -c "exec -a '$BIN/hunav_planner --orphan' sleep 30 &"
  orphan_seen() { pid=$(our_pid planner) && [ -n "$pid" ]; }
  wait_until 60 "the orphan is not seen in the own tree" orphan_seen
  kill "$pid"
  echo "orphan seen: $pid"
else
  no_orphans
  echo "the decoy outside the tree is ignored"
fi
CHECKER
checker() { env -u HUNAV_IT_SUBREAPER REPO="$REPO" BIN="$BIN" bash "$WORK/checker.sh" "$1"; }
checker clean || fail "a process outside the test's tree failed no_orphans"
checker orphan || fail "an orphan of the test's own tree was not found"
