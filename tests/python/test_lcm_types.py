"""The Python LCM message classes (lcm-gen --python, copied into the package hunav of build/python):
they import without LCM's Python package, numpy or the simulation; they import together with the
simulation module; they decode every message of a recorded hunav_run and encode it back to the bytes
the C++ side wrote; the Python planner of docs/planner_contract.md answers recorded observations
through a stand-in for lcm.LCM (its runs against the real world: tests/integration/python_planners.sh)."""
import math
import os
import pathlib
import re
import struct
import subprocess
import sys
import types

import pytest

import hunav
from conftest import REPO

PYTHON_DIR = pathlib.Path(hunav.__file__).parent.parent  # build/python


@pytest.fixture(scope="module")
def lcmtypes():
    return hunav


def test_messages_need_neither_lcm_numpy_nor_the_simulation():
    script = ("import sys\n"
              "sys.modules['lcm'] = None\n"
              "sys.modules['numpy'] = None\n"
              "from hunav import robot_command_t, map_t\n"
              "assert robot_command_t.decode(robot_command_t().encode()).v == 0.0\n"
              "assert 'hunav._hunav' not in sys.modules\n")
    subprocess.run([sys.executable, "-c", script], check=True, env=dict(os.environ, PYTHONPATH=str(PYTHON_DIR)))


def test_messages_and_the_simulation_import_together():
    from hunav import Simulation, robot_observation_t  # noqa: F401 (one package, one path)
    assert hunav.Simulation is Simulation and "robot_observation_t" in hunav.MESSAGES
    assert set(hunav.MESSAGES) <= set(dir(hunav)) and "Simulation" in dir(hunav)


def read_lcm_log(path):
    """(channel, data) of every event of an LCM log file (LCM's log format, big-endian)."""
    data = path.read_bytes()
    events, i = [], 0
    while i < len(data):
        sync, _, _, channel_len, data_len = struct.unpack(">IqqII", data[i:i + 28])
        assert sync == 0xEDA1DA01, f"bad sync word at byte {i}"
        i += 28
        channel = data[i:i + channel_len].decode()
        i += channel_len
        events.append((channel, data[i:i + data_len]))
        i += data_len
    return events


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """hunav_run's log of 1 s of passing with dwb (every message of the run, C++ encoded)."""
    binary = os.environ.get("HUNAV_RUN", str(REPO / "build" / "bin" / "hunav_run"))
    out = tmp_path_factory.mktemp("record")
    subprocess.run([binary, "--scenario", str(REPO / "scenarios" / "passing.yaml"), "--planner", "dwb",
                    "--duration", "1", "--record", str(out / "run.lcmlog"), "--out", str(out), "--quiet"],
                   check=True, capture_output=True)
    return read_lcm_log(out / "run.lcmlog")


def test_generated_files_need_no_lcm(lcmtypes):
    lcm_files = sorted(p.stem for p in (REPO / "lcmtypes").glob("*.lcm"))
    generated = sorted(p.stem for p in (PYTHON_DIR / "hunav").glob("*_t.py"))
    assert generated == lcm_files == list(hunav.MESSAGES)
    for name in generated:
        text = (PYTHON_DIR / "hunav" / f"{name}.py").read_text()
        assert not re.search(r"^\s*(import|from)\s+lcm\b", text, re.M), name
        assert hasattr(getattr(lcmtypes, name), "decode")


def test_round_trip_of_recorded_messages(lcmtypes, recorded):
    by_fingerprint = {}
    for name in dir(lcmtypes):
        cls = getattr(lcmtypes, name)
        if isinstance(cls, type) and hasattr(cls, "_get_packed_fingerprint"):
            by_fingerprint[cls._get_packed_fingerprint()] = cls
    seen = {}
    for channel, data in recorded:
        cls = by_fingerprint.get(data[:8])
        assert cls is not None, f"{channel}: no generated type has fingerprint {data[:8].hex()}"
        message = cls.decode(data)
        assert message.encode() == data, f"{channel}: {cls.__name__} re-encoded differs"
        seen.setdefault(cls.__name__, message)
    assert {"world_state_t", "robot_observation_t", "robot_command_t", "step_request_t", "step_reply_t",
            "episode_event_t", "nav_goal_t", "map_t"} <= set(seen)
    # The MAP is the grid the simulation module gives for the scenario.
    grid = hunav.Simulation(str(REPO / "scenarios" / "passing.yaml")).occupancy_grid()
    m = seen["map_t"]
    assert (m.episode, m.seq, m.resolution) == (1, 1, grid["resolution"])
    assert (m.origin_x, m.origin_y) == tuple(grid["origin"])
    assert (m.height, m.width) == grid["cells"].shape and list(m.cells) == grid["cells"].ravel().tolist()
    # Values as the C++ side wrote them: the run's first observation is the robot at its start,
    # heading to the passing scenario's goal (15, 0).
    obs = seen["robot_observation_t"]
    assert (obs.seq, obs.x, obs.y, obs.goal.x, obs.goal.y, obs.goal.valid) == (1, 0.0, 0.0, 15.0, 0.0, True)
    assert len(obs.scan.ranges) == obs.scan.num_ranges == 180
    # A command built field by field in Python encodes to the C++ bytes of the same command.
    recorded_cmd = seen["robot_command_t"]
    cmd = lcmtypes.robot_command_t()
    cmd.utime, cmd.seq, cmd.episode = recorded_cmd.utime, recorded_cmd.seq, recorded_cmd.episode
    cmd.v, cmd.w, cmd.vy = recorded_cmd.v, recorded_cmd.w, recorded_cmd.vy
    first_cmd = next(data for channel, data in recorded if channel == "ROBOT_COMMAND")
    assert cmd.encode() == first_cmd


class FakeLCM:
    """Stands in for lcm.LCM: handle_timeout() delivers the next recorded observation (each twice:
    the second as the world's resend), publish() keeps what the planner sends."""

    class Done(Exception):
        pass

    def __init__(self, observations):
        self.queue = [d for d in observations for _ in range(2)]
        self.handlers = {}
        self.published = []

    def subscribe(self, channel, handler):
        self.handlers[channel] = handler

    def publish(self, channel, data):
        self.published.append((channel, data))

    def handle_timeout(self, ms):
        if not self.queue:
            raise FakeLCM.Done()
        self.handlers["ROBOT_OBSERVATION"]("ROBOT_OBSERVATION", self.queue.pop(0))
        return 1


def test_planner_of_the_contract_answers_each_observation_once(lcmtypes, recorded):
    doc = (REPO / "docs" / "planner_contract.md").read_text()
    block = re.search(r"<!-- python-planner:[^\n]*-->\n```python\n(.*?)```", doc, re.S)
    assert block, "the Python planner block of docs/planner_contract.md"
    observations = [data for channel, data in recorded if channel == "ROBOT_OBSERVATION"]
    fake = FakeLCM(observations)
    sys.modules["lcm"] = types.SimpleNamespace(LCM=lambda url=None: fake)
    try:
        program = {"__name__": "planner"}  # not "__main__": main() does not run
        exec(compile(block.group(1), "planner_contract.md", "exec"), program)
        planner = program["GoToGoal"](fake)
        fake.subscribe("ROBOT_OBSERVATION", planner.on_observation)
        with pytest.raises(FakeLCM.Done):
            while True:
                fake.handle_timeout(100)
    finally:
        del sys.modules["lcm"]
    assert len(fake.published) == 2 * len(observations) == 20
    for k, data in enumerate(observations):
        obs = lcmtypes.robot_observation_t.decode(data)
        (channel, first), (_, resent) = fake.published[2 * k:2 * k + 2]
        assert channel == "ROBOT_COMMAND" and first == resent  # the resend gets the same bytes
        cmd = lcmtypes.robot_command_t.decode(first)
        assert (cmd.utime, cmd.seq, cmd.episode) == (obs.utime, obs.seq, obs.episode)
        error = math.remainder(math.atan2(obs.goal.y - obs.y, obs.goal.x - obs.x) - obs.yaw, 2 * math.pi)
        assert cmd.w == pytest.approx(max(-obs.max_w, min(obs.max_w, 1.5 * error)))
