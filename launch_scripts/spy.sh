#!/usr/bin/env bash
# Starts lcm-spy with HuNav-LCM's message types, so it decodes every channel.
#
# Debian's /usr/bin/lcm-spy wrapper passes -Xincgc, which Java 17 rejects, so this starts the class
# lcm.spy.Spy with java directly, with lcm.jar, jchart2d.jar and our generated types jar on the class path.
set -euo pipefail

prog=spy.sh
# shellcheck source=lib.sh
source "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/lib.sh"

usage() {
  cat <<'EOF'
Usage: launch_scripts/spy.sh [--lcm-url URL] [--netns-pid PID] [--step-channel CHANNEL]

Opens lcm-spy on an LCM bus, decoding HuNav-LCM's messages.

  --lcm-url URL     the bus (default: $LCM_DEFAULT_URL, else our processes' default bus, which
                    build/bin/hunav_record --print-url prints)
  --netns-pid PID   join the private network namespace of a running experiment first; PID is the one
                    launch_scripts/run_experiment.sh prints ("private network namespace: PID ... holds it")
  --step-channel CHANNEL
                    watch the port of its own that CHANNEL (STEP_REQUEST or STEP_REPLY) has in a run
                    with channel_ports=1 (the URL's port + 1 or + 2) instead of the URL's port
  -h, --help        show this help

What it shows: run_experiment.sh's lockstep and realtime runs in their namespace use channel_ports=1,
so the URL's port (7667) carries WORLD_STATE, EPISODE_EVENT, NAV_GOAL, LIVE_METRICS, ROBOT_OBSERVATION
and ROBOT_COMMAND, and STEP_REQUEST / STEP_REPLY (world <-> manager, every tick) travel on ports
7668 / 7669, which one lcm-spy does not hear: open a second one with --step-channel STEP_REQUEST (or
STEP_REPLY), or replay the run's --record log (it holds every port) with lcm-logplayer on one port.

It needs a display (DISPLAY set; for a headless check: xvfb-run -a launch_scripts/spy.sh).
Environment: HUNAV_TYPES_JAR (default <repo>/build/share/java/hunav_lcmtypes_java.jar), JAVA (default java).
EOF
}

url=${LCM_DEFAULT_URL:-}
netns_pid=""
step_channel=""
while [ "$#" -gt 0 ]; do
  split_option "$1"
  case "$opt" in
    -h | --help) usage; exit 0 ;;
    --lcm-url | --netns-pid | --step-channel)
      option_value "$@"
      case "$opt" in
        --lcm-url) url=$value ;;
        --netns-pid) netns_pid=$value ;;
        --step-channel) step_channel=$value ;;
      esac ;;
    *) usage_error "unknown argument '$1'" ;;
  esac
  shift $((1 + taken))
done

[ -n "$url" ] || url=$(default_lcm_url)
# channel_ports=1 and receive=lcm are our options, unknown to lcm-spy: drop them.
url=$(foreign_lcm_url "$url")
if [ -n "$step_channel" ]; then
  # The offsets of common/transport/include/hunav/channels.hpp (kOwnPortChannels).
  case "$step_channel" in
    STEP_REQUEST) offset=1 ;;
    STEP_REPLY) offset=2 ;;
    *) usage_error "--step-channel must be STEP_REQUEST or STEP_REPLY (got '$step_channel'; every other channel is on the URL's port)" ;;
  esac
  [[ $url =~ ^udpm://([0-9.]*)(:([0-9]+))?(.*)$ ]] || usage_error "--step-channel needs a udpm:// URL (got '$url')"
  address=${BASH_REMATCH[1]:-239.255.76.67}
  port=${BASH_REMATCH[3]:-7667}
  url="udpm://$address:$((port + offset))${BASH_REMATCH[4]}"
fi

java=${JAVA:-java}
lcm_jar=/usr/share/java/lcm.jar
jchart_jar=/usr/share/java/jchart2d.jar
types_jar=${HUNAV_TYPES_JAR:-$repo_root/build/share/java/hunav_lcmtypes_java.jar}

command -v "$java" >/dev/null 2>&1 || die "java is not installed (package default-jdk-headless): run bash launch_scripts/setup.sh"
[ -f "$lcm_jar" ] || die "$lcm_jar is missing (package liblcm-java): run bash launch_scripts/setup.sh"
[ -f "$jchart_jar" ] || die "$jchart_jar is missing (package libjchart2d-java): run bash launch_scripts/setup.sh"
classpath="$lcm_jar:$jchart_jar"
if [ -f "$types_jar" ]; then
  classpath="$classpath:$types_jar"
else
  warn "$types_jar is missing (build the project: bash launch_scripts/setup.sh);" \
    "lcm-spy will list the channels but not decode them"
fi
[ -n "${DISPLAY:-}" ] ||
  die "no display (DISPLAY is not set): run it in a desktop session, with ssh -X, or headless under: xvfb-run -a $0 ..."

prefix=()
if [ -n "$netns_pid" ]; then
  [[ $netns_pid =~ ^[0-9]+$ ]] || usage_error "--netns-pid must be a process id (got '$netns_pid')"
  [ -e "/proc/$netns_pid" ] ||
    die "no process $netns_pid: is the experiment still running? (run_experiment.sh prints the PID to use)"
  command -v nsenter >/dev/null 2>&1 || die "nsenter is missing (package util-linux)"
  # A run started by a normal user lives in a user namespace too (unshare -rn): entered as well.
  netns_join_command "$netns_pid"
  prefix=("${netns_join[@]}")
  if [[ $DISPLAY == localhost:* || $DISPLAY == 127.0.0.1:* ]]; then
    warn "DISPLAY=$DISPLAY is a TCP display on this host's loopback, which the run's" \
      "namespace cannot reach; use a local display (e.g. :0) or run the experiment with --shared-bus"
  fi
  "${prefix[@]}" true 2>/dev/null ||
    die "cannot enter the network namespace of process $netns_pid (as root: sudo $0 --netns-pid $netns_pid)"
  prefix+=(--)
  log "watching $url in the network namespace of process $netns_pid"
else
  log "watching $url"
  if ! multicast_route "$url"; then
    warn "no route to $mc_group: lcm-spy will see nothing. Watch a run's namespace with" \
      "--netns-pid PID, or add a loopback route: sudo ip route add 224.0.0.0/4 dev lo"
  elif [ -n "$mc_dev" ] && [ "$mc_dev" != lo ]; then
    warn "multicast to $mc_group goes through $mc_dev, not loopback; to keep" \
      "it on this host: sudo ip route add 224.0.0.0/4 dev lo (runs in a namespace: use --netns-pid PID)"
  fi
fi

exec "${prefix[@]}" "$java" -Djava.net.preferIPv4Stack=true -Xmx512m -cp "$classpath" lcm.spy.Spy --lcm-url "$url"
