"""The rules of Gymnasium's env_checker (gymnasium/utils/env_checker.py and passive_env_checker.py),
written here because Gymnasium is not a Debian package: they hold for hunav.gym.HuNavEnv and
HuNavVectorEnv. Also what a terminated episode leaves: its status and reason, and its results."""
import copy
import csv
import json

import numpy as np
import pytest

from hunav.gym import Box, Dict, HuNavEnv, HuNavVectorEnv


def assert_same_observation(a, b):
    assert a.keys() == b.keys()
    for k in a:
        np.testing.assert_array_equal(a[k], b[k])


def check_space(space):
    """A space as Gymnasium's: shape, dtype, seed(), sample() inside it, contains(), a repr with its
    real bounds, and the same samples after the same seed."""
    if isinstance(space, Dict):
        for sub in space.spaces.values():
            check_space(sub)
        space.seed(5)
        a = space.sample()
        space.seed(5)
        assert_same_observation(a, space.sample())
        assert space.contains(a)
        return
    assert isinstance(space, Box)
    assert isinstance(space.shape, tuple) and isinstance(space.dtype, np.dtype)
    assert space.low.shape == space.high.shape == space.shape
    assert np.all(space.low <= space.high)
    space.seed(3)
    first = [space.sample() for _ in range(5)]
    space.seed(3)
    for x in first:
        np.testing.assert_array_equal(x, space.sample())
        assert space.contains(x) and x.dtype == space.dtype and x.shape == space.shape
    text = repr(space)
    for bound in (space.low, space.high):  # every distinct bound value shows
        for v in np.unique(bound):
            if np.isfinite(v):
                assert f"{v}" in text or f"{v:g}" in text, (text, v)


def test_the_action_space_prints_its_real_bounds(passing):
    env = HuNavEnv(passing)
    # [v, w] within [min_v, -max_w] .. [max_v, max_w]: [0, -1.2] .. [0.6, 1.2].
    assert repr(env.action_space) == "Box([ 0.  -1.2], [0.6 1.2], (2,), float32)"
    assert repr(Box(-1.0, 1.0, (3,))) == "Box(-1.0, 1.0, (3,), float32)"
    check_space(env.action_space)
    check_space(env.observation_space)


def test_env_attributes(passing):
    env = HuNavEnv(passing)
    assert env.unwrapped is env
    assert env.spec is None
    assert "render_modes" in env.metadata and env.render_mode in env.metadata["render_modes"]
    assert isinstance(env.np_random, np.random.Generator)
    with pytest.raises(ValueError):
        HuNavEnv(passing, render_mode="human")


def test_reset_seed_determinism(passing):
    """check_reset_seed: reset(seed=123) twice gives the same observation and np_random; reset()
    without a seed does not re-seed np_random; another seed gives another generator."""
    env = HuNavEnv(passing)
    obs_1, info = env.reset(seed=123)
    assert env.observation_space.contains(obs_1) and isinstance(info, dict)
    rng_123 = copy.deepcopy(env.np_random)
    obs_2, _ = env.reset(seed=123)
    assert_same_observation(obs_1, obs_2)
    assert env.np_random.bit_generator.state == rng_123.bit_generator.state
    assert env.np_random_seed == 123
    env.reset()
    assert env.np_random.bit_generator.state == rng_123.bit_generator.state  # not re-seeded
    env.reset(seed=456)
    assert env.np_random.bit_generator.state != rng_123.bit_generator.state

    # The whole episode of a seed is the same, step for step.
    def play(seed):
        env.reset(seed=seed)
        return [env.step([0.5, 0.2])[1] for _ in range(40)], env.sim.fingerprint()
    assert play(9) == play(9)
    assert play(9)[1] != play(10)[1]


def test_reset_without_a_seed_plays_the_next_seed(passing):
    env = HuNavEnv(passing, seed=4)
    env.reset()
    assert env.sim.seed == 4
    env.reset()
    assert env.sim.seed == 5
    env.reset(seed=20)
    env.reset()
    assert env.sim.seed == 21


def test_step_returns_the_five_tuple_inside_the_spaces(passing):
    """check_step_determinism / passive checks: types of the step's returns."""
    env = HuNavEnv(passing)
    env.reset(seed=1)
    env.action_space.seed(1)
    for _ in range(30):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert env.observation_space.contains(obs)
        for k, v in obs.items():
            assert isinstance(v, np.ndarray) and v.dtype == env.observation_space[k].dtype, k
        assert isinstance(reward, float) and np.isfinite(reward)
        assert isinstance(terminated, bool) and isinstance(truncated, bool)
        assert isinstance(info, dict)
        if terminated or truncated:
            break


def test_step_after_the_end_raises_until_reset(passing):
    env = HuNavEnv(passing, duration=0.3)
    env.reset(seed=1)
    with pytest.raises(RuntimeError, match="reset"):
        for _ in range(10):
            _, _, terminated, truncated, _ = env.step([0.0, 0.0])
    assert truncated
    with pytest.raises(RuntimeError, match="time_limit"):
        env.step([0.0, 0.0])
    env.reset()
    env.step([0.0, 0.0])  # a new episode steps again


def test_render_and_close(passing):
    env = HuNavEnv(passing)
    with pytest.raises(RuntimeError):
        env.render()  # before reset
    env.reset()
    frame = env.render()
    assert isinstance(frame, np.ndarray) and frame.dtype == np.uint8 and frame.ndim == 3
    assert HuNavEnv(passing, render_mode=None).render_mode is None
    env.close()
    env.close()  # twice is fine
    for call in (lambda: env.step([0.0, 0.0]), env.reset, env.render):
        with pytest.raises(RuntimeError, match="closed"):
            call()


def wall_ahead(tmp_path):
    """The robot faces a wall 1 m ahead, its goal behind the wall: driving ahead collides."""
    text = """name: wall_ahead
dt: 0.01
time_limit: 30
seed: 1
map:
  walls:
    - [[1.5, -2.0], [1.5, 2.0]]
robot:
  radius: 0.3
  start: {x: 0.0, y: 0.0, yaw: 0.0}
  goal: {x: 4.0, y: 0.0}
"""
    path = tmp_path / "wall_ahead.yaml"
    path.write_text(text)
    return str(path)


def test_a_collision_ends_the_episode_with_its_status_reason_and_results(tmp_path):
    env = HuNavEnv(wall_ahead(tmp_path))
    env.reset(seed=1)
    for _ in range(100):
        obs, reward, terminated, truncated, info = env.step([0.6, 0.0])
        if terminated or truncated:
            break
    assert terminated and not truncated and info["collided"]
    assert info["status"] == "collision" and info["done"]
    assert "the robot touched an obstacle" in info["reason"]
    assert env.sim.info()["status"] == "collision"
    with pytest.raises(RuntimeError, match="collision"):
        env.step([0.0, 0.0])
    with pytest.warns(UserWarning, match="results_dir="):  # no states.csv: made without results_dir
        out = env.save(tmp_path / "saved")
    run = json.loads((tmp_path / "saved" / "run.json").read_text())
    assert run["status"] == "collision" and run["reason"] == info["reason"]
    rows = list(csv.DictReader(open(f"{out}/metrics.csv")))
    assert len(rows) == 1 and rows[0]["seed"] == "1"


def test_the_vector_env_follows_the_same_rules(passing, tmp_path):
    env = HuNavVectorEnv(passing, num_envs=2, threads=1)
    assert env.unwrapped is env and env.spec is None and "autoreset_mode" in env.metadata
    check_space(env.single_action_space)
    check_space(env.single_observation_space)
    assert repr(env.single_action_space) == "Box([ 0.  -1.2], [0.6 1.2], (2,), float32)"
    obs_1, infos = env.reset(seed=11)
    assert env.observation_space.contains(obs_1) and isinstance(infos, dict)
    rng = copy.deepcopy(env.np_random)
    obs_2, _ = env.reset(seed=11)
    assert_same_observation(obs_1, obs_2)
    assert env.np_random.bit_generator.state == rng.bit_generator.state
    obs, rewards, terminated, truncated, infos = env.step(np.zeros((2, 2)))
    assert env.observation_space.contains(obs)
    assert rewards.shape == (2,) and rewards.dtype == np.float64
    assert terminated.dtype == bool and truncated.dtype == bool and terminated.shape == (2,)
    env.close()
    with pytest.raises(RuntimeError, match="closed"):
        env.step(np.zeros((2, 2)))


def test_a_vector_worlds_collision_has_its_status_and_its_results_saved(tmp_path):
    env = HuNavVectorEnv(wall_ahead(tmp_path), num_envs=2, threads=1, results_dir=str(tmp_path / "episodes"))
    env.reset(seed=1)
    actions = np.array([[0.6, 0.0], [0.0, 0.0]])  # world 0 drives into the wall, world 1 stands
    for _ in range(100):
        _, _, terminated, truncated, infos = env.step(actions)
        if terminated[0]:
            break
    assert terminated[0] and not terminated[1]
    final = infos["final_info"][0]
    assert final["status"] == "collision" and "touched an obstacle" in final["reason"]
    assert final["run_dir"] == str(tmp_path / "episodes" / "seed1")
    run = json.loads(open(f"{final['run_dir']}/run.json").read())
    assert run["status"] == "collision" and run["seed"] == 1
    assert infos["status"][0] == "collision"
    assert env.vsim.status[0] == "running"  # world 0 was reset at once (same-step autoreset)
