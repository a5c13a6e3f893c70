"""`import lcm` (python/lcm, over liblcm): upstream LCM's Python API on memq:// (one process, no
network), its event log against logs liblcm writes, and its behaviour with exceptions, signals and
threads. The udpm round trip between processes is tests/python/test_lcm_udpm.py (in a private network
namespace)."""
import signal
import subprocess
import threading
import time

import pytest

import lcm
from conftest import REPO
from hunav import robot_command_t


def command(v):
    c = robot_command_t()
    c.seq, c.v = 7, v
    return c.encode()


def test_the_upstream_api_is_there():
    assert {"LCM", "LCMSubscription", "Event", "EventLog"} <= set(dir(lcm))
    for name in ("publish", "subscribe", "unsubscribe", "handle", "handle_timeout", "fileno"):
        assert callable(getattr(lcm.LCM, name)), name
    assert callable(lcm.LCMSubscription.set_queue_capacity)
    for name in ("close", "read_next_event", "seek", "seek_to_timestamp", "size", "tell", "write_event"):
        assert callable(getattr(lcm.EventLog, name)), name


def test_publish_subscribe_round_trip():
    lc = lcm.LCM("memq://")
    got = []
    sub = lc.subscribe("ROBOT_COMMAND", lambda channel, data: got.append((channel, data)))
    assert isinstance(sub, lcm.LCMSubscription)
    lc.publish("ROBOT_COMMAND", command(0.25))
    lc.publish("OTHER", b"not for us")
    assert lc.handle_timeout(1000) == 1
    assert got == [("ROBOT_COMMAND", command(0.25))]
    assert robot_command_t.decode(got[0][1]).v == 0.25
    assert lc.handle_timeout(0) == 0  # "OTHER" has no subscriber: nothing to handle
    assert isinstance(lc.fileno(), int) and lc.fileno() >= 0


def test_channels_are_regular_expressions_and_unsubscribe_ends_a_subscription():
    lc = lcm.LCM("memq://")
    got = []
    sub = lc.subscribe("ROBOT_.*", lambda channel, data: got.append(channel))
    for channel in ("ROBOT_COMMAND", "ROBOT_OBSERVATION", "WORLD_STATE"):
        lc.publish(channel, b"x")
    while lc.handle_timeout(0):
        pass
    assert got == ["ROBOT_COMMAND", "ROBOT_OBSERVATION"]
    lc.unsubscribe(sub)
    lc.publish("ROBOT_COMMAND", b"x")
    assert lc.handle_timeout(0) == 0 and got == ["ROBOT_COMMAND", "ROBOT_OBSERVATION"]
    with pytest.raises(ValueError):
        lc.unsubscribe(sub)  # already ended
    with pytest.raises(ValueError):
        sub.set_queue_capacity(5)


def test_a_handler_may_unsubscribe_itself():
    lc = lcm.LCM("memq://")
    got = []

    def once(channel, data):
        got.append(data)
        lc.unsubscribe(holder[0])
    holder = [lc.subscribe("A", once)]
    lc.publish("A", b"1")
    lc.publish("A", b"2")
    while lc.handle_timeout(0):
        pass
    assert got == [b"1"]


def test_queue_capacity_is_set_on_the_subscription():
    lc = lcm.LCM("memq://")
    got = []
    sub = lc.subscribe("A", lambda channel, data: got.append(data))
    assert sub.set_queue_capacity(3) is None and sub.channel == "A"
    assert sub.set_queue_capacity(0) is None  # unbounded
    with pytest.raises(ValueError):
        sub.set_queue_capacity(-1)
    lc.publish("A", b"1")
    assert lc.handle_timeout(1000) == 1 and got == [b"1"]


def test_a_handlers_exception_reaches_the_caller_of_handle():
    lc = lcm.LCM("memq://")

    def fails(channel, data):
        raise KeyError("from the handler")
    lc.subscribe("A", fails)
    lc.publish("A", b"x")
    with pytest.raises(KeyError, match="from the handler"):
        lc.handle()
    lc.publish("A", b"y")
    with pytest.raises(KeyError):
        lc.handle_timeout(1000)


def test_bad_arguments_raise():
    lc = lcm.LCM("memq://")
    with pytest.raises(ValueError):
        lc.handle_timeout(-1)
    with pytest.raises(TypeError):
        lc.subscribe("A", "not callable")
    with pytest.raises(TypeError):
        lc.publish("A", 42)
    with pytest.raises(RuntimeError, match="Couldn't create LCM"):
        lcm.LCM("nosuchprovider://")


def test_handle_hears_ctrl_c_and_other_threads_run_meanwhile():
    lc = lcm.LCM("memq://")
    lc.subscribe("A", print)
    ticks = []
    worker = threading.Thread(target=lambda: [ticks.append(time.sleep(0.01)) for _ in range(20)])
    worker.start()  # runs while handle() waits (the GIL is released)
    timer = threading.Timer(0.3, signal.pthread_kill, (threading.main_thread().ident, signal.SIGINT))
    with pytest.raises(KeyboardInterrupt):
        timer.start()  # here, so that a signal early on a loaded machine is still inside the block
        lc.handle()  # nothing is ever published: only the signal ends the wait
    worker.join()
    assert len(ticks) == 20


def test_two_threads_cannot_handle_one_instance_at_once():
    lc = lcm.LCM("memq://")
    got = []
    lc.subscribe("A", lambda channel, data: got.append(data))

    def wait_for_one():
        while True:
            try:
                lc.handle()  # waits until something is published
                return
            except RuntimeError:  # the main thread was inside handle_timeout(0) just then
                time.sleep(0.001)
    waiting = threading.Thread(target=wait_for_one)
    waiting.start()
    deadline = time.monotonic() + 60
    while True:  # until the other thread is inside handle()
        try:
            lc.handle_timeout(0)
        except RuntimeError as e:
            assert "already handling" in str(e)
            break
        assert time.monotonic() < deadline, "the other thread never started handling"
        time.sleep(0.001)
    lc.publish("A", b"1")
    waiting.join(60)
    assert not waiting.is_alive() and got == [b"1"]


def test_event_log_writes_and_reads_as_upstream(tmp_path):
    path = tmp_path / "log.lcmlog"
    log = lcm.EventLog(str(path), "w")
    for k in range(5):
        log.write_event(1000 * k, f"CH{k % 2}", bytes([k]) * (k + 1))
    log.close()
    with pytest.raises(ValueError, match="overwrite"):
        lcm.EventLog(str(path), "w")
    with pytest.raises(ValueError):
        lcm.EventLog(str(path), "x")
    log = lcm.EventLog(path)  # a path-like object, mode "r"
    events = list(log)
    assert [(e.eventnum, e.timestamp, e.channel, e.data) for e in events] == [
        (k, 1000 * k, f"CH{k % 2}", bytes([k]) * (k + 1)) for k in range(5)]
    assert log.size() == path.stat().st_size
    log.seek_to_timestamp(3000)  # liblcm's search: the event of that time, or one near it
    assert log.read_next_event().timestamp == 3000
    with pytest.raises(OSError):
        log.seek_to_timestamp(10**9)  # after the last event
    log.seek(0)
    first = log.read_next_event()
    at = log.tell()
    assert first.eventnum == 0 and at > 0
    assert log.read_next_event().eventnum == 1
    log.seek(at)
    assert log.read_next_event().eventnum == 1
    log.close()
    with pytest.raises(ValueError):
        log.read_next_event()
    lcm.EventLog(str(path), "w", overwrite=True).close()
    assert list(lcm.EventLog(str(path))) == []


def test_event_log_reads_what_hunav_run_recorded(tmp_path, hunav_run):
    """A log liblcm's C++ side wrote (hunav_run --record) reads back, every event a message of ours."""
    subprocess.run([hunav_run, "--scenario", str(REPO / "scenarios" / "passing.yaml"), "--duration", "0.5",
                    "--record", str(tmp_path / "run.lcmlog"), "--out", str(tmp_path), "--quiet"], check=True)
    import hunav
    fingerprints = {getattr(hunav, n)._get_packed_fingerprint(): getattr(hunav, n) for n in hunav.MESSAGES}
    channels = set()
    for event in lcm.EventLog(str(tmp_path / "run.lcmlog")):
        cls = fingerprints[event.data[:8]]
        assert cls.decode(event.data).encode() == event.data
        channels.add(event.channel)
    assert {"WORLD_STATE", "EPISODE_EVENT", "MAP", "ROBOT_OBSERVATION", "ROBOT_COMMAND"} <= channels
