"""Shared fixtures of the Python tests: the repository, the scenarios, hunav_run of this build.

ctest sets PYTHONPATH=<build>/python, HUNAV_REPO and HUNAV_RUN (python/CMakeLists.txt).
"""
import math
import os
import pathlib

import pytest

REPO = pathlib.Path(os.environ.get("HUNAV_REPO", pathlib.Path(__file__).resolve().parents[2]))
PASSING = str(REPO / "scenarios" / "passing.yaml")


@pytest.fixture(autouse=True)
def private_tmpdir(tmp_path, monkeypatch):
    """TMPDIR inside the test's tmp_path: the result folders Simulation makes when given none
    (hunav-py-XXXXXX, python/src/hunav_module.cpp) go with pytest's folders, not into /tmp."""
    tmp = tmp_path / "tmpdir"
    tmp.mkdir()
    monkeypatch.setenv("TMPDIR", str(tmp))


@pytest.fixture
def passing():
    return PASSING


@pytest.fixture
def hunav_run():
    path = os.environ.get("HUNAV_RUN", str(REPO / "build" / "bin" / "hunav_run"))
    if not os.path.exists(path):
        pytest.fail(f"hunav_run not found at {path} (set HUNAV_RUN)")
    return path


def keep_right_policy(robot, goal, lane_y=-1.0):
    """A scripted (v, w) for the passing corridor: along the lane on the robot's right, then to the goal.

    robot: [x, y, yaw, ...] in the world frame; goal: [x, y, ...].
    """
    x, y, yaw = robot[0], robot[1], robot[2]
    tx, ty = (x + 1.5, lane_y) if x < goal[0] - 2.0 else (goal[0], goal[1])
    err = math.atan2(ty - y, tx - x) - yaw
    err = math.atan2(math.sin(err), math.cos(err))
    w = max(-1.2, min(1.2, 2.0 * err))
    v = 0.6 if abs(err) < 0.5 else 0.1
    return v, w
