# shellcheck shell=bash
# Reading LCM log files in the integration tests. Sourced after common.sh.

# log_counts LOG: "CHANNEL COUNT" per channel of an LCM log file; fails when the event stamps decrease.
log_counts() {
  python3 - "$1" <<'PY'
import collections, struct, sys
data = open(sys.argv[1], "rb").read()
counts, last, i = collections.Counter(), -1, 0
while i < len(data):
    sync, _, stamp, channel_len, data_len = struct.unpack(">IqqII", data[i:i + 28])
    if sync != 0xEDA1DA01:
        sys.exit(f"{sys.argv[1]}: bad sync word at byte {i}")
    if stamp < last:
        sys.exit(f"{sys.argv[1]}: event stamps decrease at byte {i}")
    last = stamp
    counts[data[i + 28:i + 28 + channel_len].decode()] += 1
    i += 28 + channel_len + data_len
for channel in sorted(counts):
    print(channel, counts[channel])
print("LAST_STAMP", last)
PY
}
count_of() { awk -v c="$2" '$1 == c { print $2 }' "$1"; }
