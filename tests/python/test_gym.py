"""hunav.gym.HuNavEnv: the Gymnasium API, its spaces, reward, termination and render()."""
import numpy as np
import pytest

from hunav.gym import Box, Dict, HuNavEnv, HuNavVectorEnv, RewardWeights, default_reward


def test_spaces(passing):
    env = HuNavEnv(passing)
    assert isinstance(env.action_space, Box) or env.action_space.__class__.__name__ == "Box"
    assert env.action_space.shape == (2,) and env.action_space.dtype == np.float32
    np.testing.assert_allclose(env.action_space.low, [0.0, -1.2])
    np.testing.assert_allclose(env.action_space.high, [0.6, 1.2])
    space = env.observation_space
    assert set(space.keys()) == {"robot", "goal", "scan", "people"}
    assert space["scan"].shape == (180,) and space["people"].shape == (2, 6)
    for _ in range(20):
        assert env.action_space.contains(env.action_space.sample())
    assert not env.action_space.contains(np.array([5.0, 0.0], dtype=np.float32))
    assert not env.action_space.contains(np.zeros(3, dtype=np.float32))


def test_reset_step_api(passing):
    env = HuNavEnv(passing)
    obs, info = env.reset(seed=1)
    assert env.observation_space.contains(obs), obs
    assert info["status"] == "running" and not info["collided"]
    np.testing.assert_allclose(obs["goal"], [15.0, 0.0], atol=1e-6)  # robot at the origin facing +x
    obs, reward, terminated, truncated, info = env.step(np.array([0.6, 0.0]))
    assert env.observation_space.contains(obs)
    assert isinstance(reward, float) and reward > 0.0  # progress towards the goal
    assert terminated is False and truncated is False
    for _ in range(60):  # the people come within the 8 m perception range
        obs, *_ = env.step([0.6, 0.0])
    assert obs["people"][:, 5].sum() == 2  # both perceived, nearest first, in the robot frame
    d = np.hypot(obs["people"][:, 0], obs["people"][:, 1])
    assert d[0] <= d[1] and (obs["people"][:, 0] > 0).all()  # ahead of the robot
    assert (obs["people"][:, 2] < 0).all()  # walking towards it


def test_same_seed_same_episode(passing):
    def play(seed):
        env = HuNavEnv(passing)
        obs, _ = env.reset(seed=seed)
        rewards = []
        for _ in range(30):
            obs, r, term, trunc, _ = env.step(env.action_space.sample())
            rewards.append(r)
        return obs, rewards
    (oa, ra), (ob, rb) = play(7), play(7)
    assert ra == rb
    for k in oa:
        np.testing.assert_array_equal(oa[k], ob[k])


def test_truncated_at_time_limit(passing):
    env = HuNavEnv(passing, duration=0.5)
    env.reset()
    steps, done = 0, False
    while not done:
        _, _, terminated, truncated, info = env.step([0.0, 0.0])
        steps += 1
        done = terminated or truncated
    assert truncated and not terminated and steps == 5 and info["time_limit"]
    with pytest.raises(RuntimeError, match="reset"):
        env.step([0.0, 0.0])


def test_goal_terminates_with_bonus(passing):
    env = HuNavEnv(passing, seed=1)
    obs, _ = env.reset()
    total, terminated = 0.0, False
    for _ in range(1000):
        gx, gy = obs["goal"]
        heading = np.arctan2(gy, gx)
        action = [0.6 if abs(heading) < 0.5 else 0.1, np.clip(2.0 * heading, -1.2, 1.2)]
        obs, r, terminated, truncated, info = env.step(action)
        total += r
        if terminated or truncated:
            break
    # straight at the goal the robot may meet the people: either way the episode terminated
    assert terminated
    if info["goal_reached"]:
        assert r > RewardWeights().goal - 1.0
    else:
        assert info["collided"]


def test_bad_actions(passing):
    env = HuNavEnv(passing)
    with pytest.raises(RuntimeError):
        env.step([0.0, 0.0])
    env.reset()
    with pytest.raises(ValueError, match="shape"):
        env.step([0.1, 0.0, 0.0])
    with pytest.raises(ValueError, match="finite"):
        env.step([np.nan, 0.0])


def test_custom_reward(passing):
    calls = []

    def reward(env, before, after, info):
        calls.append(info["time"])
        return default_reward(env, before, after, info) * 0.0 + 1.0
    env = HuNavEnv(passing, reward_fn=reward)
    env.reset()
    _, r, *_ = env.step([0.3, 0.0])
    assert r == 1.0 and calls == [pytest.approx(0.1)]


def test_render(passing):
    env = HuNavEnv(passing)
    env.reset()
    img = env.render()
    assert img.dtype == np.uint8 and img.ndim == 3 and img.shape[2] == 3
    assert img.shape[:2] == (int(np.ceil(6.0 / 0.05)), int(np.ceil(22.0 / 0.05)))  # bounds + 1 m margin
    assert (img != 255).any()  # something drawn
    env2 = HuNavEnv(passing, render_size=(320, 120))
    env2.reset()
    assert env2.render().shape == (120, 320, 3)


def test_dict_space():
    space = Dict({"a": Box(0.0, 1.0, (3,)), "b": Box(-1.0, 1.0, (2, 2))}, seed=0)
    x = space.sample()
    assert space.contains(x) and x["b"].shape == (2, 2)
    assert not space.contains({"a": x["a"]})


def test_holonomic_action_space(passing, tmp_path):
    text = open(passing).read().replace("  radius: 0.3\n", "  radius: 0.3\n  drive: holonomic\n", 1)
    scenario = tmp_path / "holonomic.yaml"
    scenario.write_text(text)
    env = HuNavEnv(str(scenario))
    assert env.action_space.shape == (3,)
    env.reset()
    for _ in range(5):
        env.step([0.0, 0.0, -0.4])  # [v, w, vy]: to the right
    assert env.sim.state()["robot"][1] < -0.1


def test_default_reward_is_the_documented_one(passing):
    """HuNavEnv's default reward (native terms) equals default_reward on full sim.state()s (to the
    last bits: a hypot computed by libm here, by Python's math.hypot there)."""
    fast, full = HuNavEnv(passing, terminate_on_collision=False), HuNavEnv(passing, reward_fn=default_reward,
                                                                           terminate_on_collision=False)
    fast.reset(seed=2)
    full.reset(seed=2)
    closest = np.inf
    for t in range(200):  # straight down the corridor past both people
        action = [0.6, 0.3 * np.sin(0.05 * t)]
        _, r_fast, *_ = fast.step(action)
        _, r_full, *_ = full.step(action)
        assert r_fast == pytest.approx(r_full, rel=1e-12, abs=1e-12)
        state = fast.sim.state()
        closest = min(closest, np.hypot(*(state["agents"]["pose"][:, :2] - state["robot"][:2]).T).min())
    assert closest < 1.2  # the personal-space term was in play


def test_a_closed_environment_raises_runtime_error(passing):
    # Issue 31: step() after close() was an AttributeError on None.
    env = HuNavEnv(passing, seed=1)
    env.reset()
    env.close()
    for call in [lambda: env.step(env.action_space.sample()), lambda: env.reset(), lambda: env.render()]:
        with pytest.raises(RuntimeError, match="closed"):
            call()
    venv = HuNavVectorEnv(passing, num_envs=2)
    venv.reset()
    venv.close()
    with pytest.raises(RuntimeError, match="closed"):
        venv.step(np.zeros((2, 2)))
