#!/usr/bin/env bash
# Runs a command inside a private network namespace with multicast routed on loopback (README.md,
# "Modes and separate processes"): root uses unshare --net, others an unprivileged user namespace. Exit 77 (ctest: skip)
# when neither is allowed here.
set -euo pipefail
if [ -z "${HUNAV_IN_NETNS:-}" ]; then
  for flags in --net -rn; do
    if unshare $flags -- true 2>/dev/null; then
      HUNAV_IN_NETNS=1 exec unshare $flags -- "$BASH" "$0" "$@"
    fi
  done
  echo "cannot make a private network namespace here (unshare --net / -rn refused): skipped" >&2
  exit 77
fi
ip link set lo up
ip route add 224.0.0.0/4 dev lo
exec "$@"
