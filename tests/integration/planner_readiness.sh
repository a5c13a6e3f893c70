#!/usr/bin/env bash
# The readiness handshake (docs/planner_contract.md, "Readiness"): the world starts the episode only
# once the planner published PLANNER_READY. A --planner-cmd planner that starts slowly (it sleeps
# 1.5 s before it subscribes) sees the START and the END of every run (5 of 5; without the handshake
# it missed START); a planner that never announces itself ends the run aborted with a reason naming
# the missing PLANNER_READY, and an error naming its command, exit 1.
source "$(dirname "$0")/common.sh"
scenario="$REPO/tests/integration/data/endless_corridor.yaml"
slow="sleep 1.5; exec $BIN/example_planner \"\$LCM_DEFAULT_URL\" 1"
for i in 1 2 3 4 5; do
  out="$WORK/slow$i"
  mode=lockstep
  [ "$i" -le 3 ] || mode=realtime
  rc=0
  "$RUN" --scenario "$scenario" --mode "$mode" --duration 2 --planner-cmd "$slow" --planner slow --out "$out" \
    > "$WORK/slow$i.txt" 2>&1 || rc=$?
  [ "$rc" -eq 0 ] || { cat "$WORK/slow$i.txt" "$out"/logs/*.log; fail "run $i ($mode): exit $rc"; }
  [ "$(json_field "$out/run.json" status)" = time_limit ] || fail "run $i: status $(json_field "$out/run.json" status)"
  grep -q "START" "$out/logs/planner.log" || { cat "$out/logs/planner.log"; fail "run $i ($mode): the planner missed START"; }
  grep -q "END time_limit" "$out/logs/planner.log" || { cat "$out/logs/planner.log"; fail "run $i ($mode): the planner missed END"; }
  no_orphans
  echo "run $i ($mode): the slow planner saw START and END"
done

# A planner that never announces itself (it runs, but publishes nothing): aborted once the world's
# wait (HUNAV_READY_TIMEOUT s) is over.
out="$WORK/mute"
rc=0
start=$(date +%s.%N)
HUNAV_READY_TIMEOUT=3 "$RUN" --scenario "$scenario" --mode lockstep --planner-cmd "exec sleep 60" --planner mute \
  --out "$out" > "$WORK/mute.txt" 2>&1 || rc=$?
took=$(python3 -c "import sys; print(round($(date +%s.%N) - $start, 1))")
[ "$rc" -eq 1 ] || { cat "$WORK/mute.txt"; fail "a planner never ready: exit $rc, expected 1"; }
[ "$(json_field "$out/run.json" status)" = aborted ] || fail "never ready: status $(json_field "$out/run.json" status)"
case "$(json_field "$out/run.json" reason)" in
  "planner not ready: no PLANNER_READY message within 3 s"*) ;;
  *) fail "never ready: reason $(json_field "$out/run.json" reason)" ;;
esac
grep -q "your planner command 'exec sleep 60' never announced itself" "$WORK/mute.txt" ||
  { cat "$WORK/mute.txt"; fail "the error does not name the planner command"; }
python3 -c "import sys; sys.exit(0 if $took < 15 else 1)" || fail "never ready: the run took $took s"
no_orphans
echo "a planner never ready: aborted after $took s, exit 1"
