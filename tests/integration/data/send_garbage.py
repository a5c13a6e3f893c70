#!/usr/bin/env python3
"""Sends undecodable LCM datagrams on the run's bus: send_garbage.py DELAY_S CHANNEL:PORT_OFFSET:COUNT...

Each datagram is a well-formed LCM short message (magic "LC02", a sequence number, the channel name)
whose payload is 16 bytes that match no type's fingerprint, so the subscriber's decode fails and it
must drop and count it. The bus is LCM_DEFAULT_URL's multicast group and port (plus the offset: 1 for
STEP_REQUEST under channel_ports=1, channels.hpp)."""
import os
import re
import socket
import struct
import sys
import time

url = os.environ["LCM_DEFAULT_URL"]
m = re.match(r"udpm://([\d.]+):(\d+)", url)
if not m:
    sys.exit(f"send_garbage.py: not a udpm URL: {url}")
group, port = m.group(1), int(m.group(2))
time.sleep(float(sys.argv[1]))
sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
sock.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 0)
seq = 0
for spec in sys.argv[2:]:
    channel, offset, count = spec.split(":")
    for _ in range(int(count)):
        packet = struct.pack(">II", 0x4C433032, seq) + channel.encode() + b"\0" + b"\xde\xad\xbe\xef" * 4
        sock.sendto(packet, (group, port + int(offset)))
        seq += 1
        time.sleep(0.01)
print(f"send_garbage.py: sent {seq} datagrams on {url}", flush=True)
