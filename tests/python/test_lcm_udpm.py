"""`import lcm` over udpm:// between processes, in the private network namespace ctest runs this file
in (tests/common/in_netns.sh: multicast on loopback only; the test refuses to run outside one)."""
import os
import subprocess
import sys
import time

import pytest

import lcm
from hunav import map_t

URL = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304"


@pytest.fixture(autouse=True)
def only_in_a_private_namespace():
    if os.environ.get("HUNAV_IN_NETNS") != "1":
        pytest.fail("run in a private network namespace (tests/common/in_netns.sh): never on the real interface")


def receive(lc, wanted, limit_s=60.0):
    deadline = time.monotonic() + limit_s
    while not wanted() and time.monotonic() < deadline:
        lc.handle_timeout(100)


def test_a_message_from_another_process_arrives():
    lc = lcm.LCM(URL)
    got = []
    lc.subscribe("PING", lambda channel, data: got.append(data))
    # The sender publishes until it is killed: however late it starts on a loaded machine, the receiver
    # hears it within its bound.
    script = ("import lcm, time\n"
              f"lc = lcm.LCM({URL!r})\n"
              "while True:\n"
              "    lc.publish('PING', b'hello')\n"
              "    time.sleep(0.05)\n")
    sender = subprocess.Popen([sys.executable, "-c", script], env=os.environ)
    try:
        receive(lc, lambda: got)
    finally:
        sender.kill()
        sender.wait()
    assert got and got[0] == b"hello"


def test_a_large_map_is_reassembled_from_its_fragments():
    sender, receiver = lcm.LCM(URL), lcm.LCM(URL)
    got = []
    receiver.subscribe("MAP", lambda channel, data: got.append(map_t.decode(data)))
    m = map_t()
    m.resolution, m.width, m.height = 0.05, 1000, 1000  # 1 MB of cells: 16 fragments
    m.num_cells = m.width * m.height
    m.cells = [(k * 7) % 101 for k in range(m.num_cells)]
    m.episode, m.seq, m.scenario = 3, 1, "big"
    deadline = time.monotonic() + 60
    while not got and time.monotonic() < deadline:
        sender.publish("MAP", m.encode())
        receive(receiver, lambda: got, limit_s=1.0)
    assert got, "the map never arrived"
    assert (got[0].width, got[0].height, got[0].episode, got[0].scenario) == (1000, 1000, 3, "big")
    assert list(got[0].cells) == m.cells
