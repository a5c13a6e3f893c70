#!/usr/bin/env bash
# lcm-spy's view of a run: every message of a recorded run (hunav_run --record, MAP included) decodes
# with the Java types jar the build makes for lcm-spy, through lcm-spy's own type lookup.
# Env: BIN (build/bin), JAR (the types jar), LCM_JAR, REPO.
set -euo pipefail
work=$(mktemp -d /tmp/hunav_spy.XXXXXX)
trap 'rm -rf "$work"' EXIT
"$BIN/hunav_run" --scenario "$REPO/scenarios/cafe.yaml" --duration 0.5 --record "$work/run.lcmlog" \
  --out "$work/out" --quiet
java -cp "$LCM_JAR:$JAR" "$REPO/tests/lcmtypes/SpyDecodesTheLog.java" "$work/run.lcmlog" | tee "$work/decoded.txt"
for line in "EPISODE_EVENT hunav.episode_event_t 2" "MAP hunav.map_t 1" "WORLD_STATE hunav.world_state_t 51" \
  "ROBOT_OBSERVATION hunav.robot_observation_t" "MAP 233 x 512 cells of 0.05 m, episode 1"; do
  grep -q "^$line" "$work/decoded.txt" || { echo "FAIL: no line '$line'" >&2; exit 1; }
done
