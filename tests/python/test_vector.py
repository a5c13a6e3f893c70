"""hunav.VectorSimulation and hunav.gym.HuNavVectorEnv: n worlds stepped together over threads give
exactly the episodes of n single simulations stepped one by one."""
import numpy as np
import pytest

import hunav
from conftest import keep_right_policy
from hunav.gym import HuNavEnv, HuNavVectorEnv, default_vector_reward

SEEDS = [3, 7, 11]


def policy_rows(obs, t):
    """keep_right_policy per world, with a per-world twist so the worlds get different commands."""
    rows = []
    for i in range(len(obs["robot"])):
        v, w = keep_right_policy(obs["robot"][i], obs["goal"][i])
        rows.append([v, w + 0.05 * np.sin(0.1 * t + i)])
    return np.array(rows)


def run_sequential(scenario, seeds, steps):
    """Each world alone on a Simulation with the commands the vector run gives it."""
    out = []
    for i, seed in enumerate(seeds):
        sim = hunav.Simulation(scenario, seed=seed)
        obs = sim.reset()
        trace = [obs]
        for t in range(steps):
            if sim.done:
                break
            v, w = keep_right_policy(obs["robot"], obs["goal"])
            obs = sim.step(v, w + 0.05 * np.sin(0.1 * t + i))
            trace.append(obs)
        out.append((trace, sim.fingerprint(), sim.metrics(), sim.info()["status"], sim.state()))
    return out


@pytest.mark.parametrize("threads,evaluator_thread", [(1, False), (2, False), (3, False), (2, True)])
def test_vector_equals_sequential(passing, threads, evaluator_thread):
    """The single simulations run the evaluator on its worker thread (the default); the vector ones
    on the stepping threads (their default) or on workers: the same metrics either way."""
    steps = 400  # past the encounter with both people; some worlds reach their goal before
    vs = hunav.VectorSimulation(len(SEEDS), passing, seeds=SEEDS, threads=threads, evaluator_thread=evaluator_thread)
    assert vs.threads == min(threads, len(SEEDS)) and len(vs) == 3 and vs.seeds == SEEDS
    obs = vs.reset()
    traces = [[{k: obs[k][i] for k in obs}] for i in range(len(SEEDS))]
    for t in range(steps):
        if vs.done.all():
            break
        was_done = vs.done.copy()
        obs = vs.step(policy_rows(obs, t))
        for i in range(len(SEEDS)):
            if not was_done[i]:
                traces[i].append({k: obs[k][i] for k in obs})
    expected = run_sequential(passing, SEEDS, steps)
    fingerprints = vs.fingerprints()
    metrics = vs.metrics()
    state = vs.state()
    assert len(set(fingerprints)) == 3  # three different episodes
    for i, (trace, fingerprint, sim_metrics, status, sim_state) in enumerate(expected):
        assert fingerprints[i] == fingerprint
        assert metrics[i] == sim_metrics
        assert vs.status[i] == status
        assert len(traces[i]) == len(trace)
        for got, want in zip(traces[i], trace):
            np.testing.assert_array_equal(got["robot"], want["robot"])
            np.testing.assert_array_equal(got["scan"], want["scan"])
            k = len(want["people"])
            assert got["people_count"] == k
            np.testing.assert_array_equal(got["people"][:k], want["people"])
            np.testing.assert_array_equal(got["people"][k:], 0.0)
            np.testing.assert_array_equal(got["people_ids"][:k], want["people_ids"])
            assert got["time"] == want["time"] and got["seq"] == want["seq"]
        np.testing.assert_array_equal(state["robot"][i], sim_state["robot"])
        np.testing.assert_array_equal(state["agents"]["pose"][i], sim_state["agents"]["pose"])
        assert state["robot_collisions"][i] == sim_state["robot_collisions"]
    assert "social_work" in metrics[0]


def test_vector_run_with_planner_matches_simulation(passing):
    vs = hunav.VectorSimulation(2, passing, seeds=[1, 2], planner="dwb", threads=2)
    infos = vs.run()
    assert [i["status"] for i in infos] == ["goal_reached", "goal_reached"]
    for i, seed in enumerate([1, 2]):
        sim = hunav.Simulation(passing, seed=seed, planner="dwb")
        sim.run()
        assert infos[i]["fingerprint"] == sim.fingerprint()


def test_vector_reset_some_worlds_and_default_seeds(passing):
    vs = hunav.VectorSimulation(2, passing)  # the scenario's seed (1), then 2
    assert vs.seeds == [1, 2] and vs.max_people == 2
    first = vs.reset()
    vs.step(np.full((2, 2), [0.5, 0.0]))
    obs = vs.reset(seeds=[9], indices=[1])  # world 1 restarts with seed 9; world 0 keeps going
    assert vs.seeds == [1, 9]
    assert obs["time"][0] == pytest.approx(0.1) and obs["time"][1] == 0.0
    np.testing.assert_array_equal(obs["robot"][1], first["robot"][1])
    sim = hunav.Simulation(passing, seed=9)
    np.testing.assert_array_equal(sim.reset()["people"], obs["people"][1][: obs["people_count"][1]])


def test_vector_bad_input(passing):
    with pytest.raises(ValueError, match="n must be"):
        hunav.VectorSimulation(0, passing)
    with pytest.raises(ValueError, match="seeds has 1 values for 2 worlds"):
        hunav.VectorSimulation(2, passing, seeds=[1])
    with pytest.raises(ValueError, match="threads"):
        hunav.VectorSimulation(2, passing, threads=0)
    with pytest.raises(hunav.ConfigError, match="missing.yaml"):
        hunav.VectorSimulation(2, "missing.yaml")
    vs = hunav.VectorSimulation(2, passing, duration=0.2)
    with pytest.raises(RuntimeError, match="reset"):
        vs.step(np.zeros((2, 2)))
    vs.reset()
    with pytest.raises(ValueError, match=r"shape \(3, 2\)"):
        vs.step(np.zeros((3, 2)))
    with pytest.raises(ValueError, match=r"shape \(2,\)"):
        vs.step(np.zeros(2))
    with pytest.raises(ValueError, match="world 1: w is not finite"):
        vs.step(np.array([[0.1, 0.0], [0.1, np.nan]]))
    with pytest.raises(ValueError, match="world 0: vy is for a holonomic robot"):
        vs.step(np.array([[0.1, 0.0, 0.3], [0.1, 0.0, 0.0]]))
    with pytest.raises(ValueError, match="listed twice"):
        vs.reset(indices=[0, 0])
    with pytest.raises(IndexError):
        vs.reset(indices=[2])
    with pytest.raises(ValueError, match="seed must be >= 0"):
        vs.reset(seeds=[-1, 2])
    assert vs.observation()["time"].tolist() == [0.0, 0.0]  # nothing moved
    vs.step(np.zeros((2, 2)))
    vs.step(np.zeros((2, 2)))
    assert vs.done.all() and vs.status == ["time_limit", "time_limit"]
    with pytest.raises(RuntimeError, match="every world's episode has ended"):
        vs.step(np.zeros((2, 2)))


def test_vector_env_matches_single_envs(passing):
    n = 2
    venv = HuNavVectorEnv(passing, n, threads=2, duration=6.0)
    assert venv.action_space.shape == (n, 2) and venv.single_action_space.shape == (2,)
    assert venv.observation_space["people"].shape == (n, 2, 6)
    obs, infos = venv.reset(seed=4)
    assert list(infos["seed"]) == [4, 5]
    envs = [HuNavEnv(passing, duration=6.0) for _ in range(n)]
    single = [env.reset(seed=4 + i)[0] for i, env in enumerate(envs)]
    for i, first in enumerate(single):
        for k in first:
            np.testing.assert_array_equal(obs[k][i], first[k])
    ended = np.zeros(n, dtype=bool)
    resets = 0
    for t in range(70):  # 7 s: every world hits the 6 s limit once and starts its next episode
        actions = np.stack([[0.6, 0.3 * np.sin(0.2 * t + i)] for i in range(n)])
        obs, rewards, terminated, truncated, infos = venv.step(actions)
        for i, env in enumerate(envs):
            if ended[i]:
                continue
            o, r, term, trunc, info = env.step(actions[i])
            final = infos["final_observation"][i] if (terminated[i] or truncated[i]) else obs
            for k in o:
                np.testing.assert_allclose(final[k] if final is not obs else obs[k][i], o[k], rtol=0, atol=1e-6)
            assert rewards[i] == pytest.approx(r, abs=1e-9)
            assert (terminated[i], truncated[i]) == (term, trunc)
            if term or trunc:
                ended[i] = True
                resets += 1
    assert resets == n
    assert list(infos["seed"]) == [6, 7]  # the next episodes: seed + num_envs
    assert obs["goal"].shape == (n, 2) and obs["scan"].dtype == np.float32


def test_vector_env_default_reward_is_default_vector_reward(passing):
    """The vector env's native reward terms give default_vector_reward's formula on vsim.state()s."""
    fast = HuNavVectorEnv(passing, 2, terminate_on_collision=False)
    full = HuNavVectorEnv(passing, 2, reward_fn=default_vector_reward, terminate_on_collision=False)
    fast.reset(seed=2)
    full.reset(seed=2)
    for t in range(150):  # down the corridor past both people
        actions = np.array([[0.6, 0.3 * np.sin(0.05 * t)], [0.5, -0.2 * np.sin(0.05 * t)]])
        _, r_fast, *_ = fast.step(actions)
        _, r_full, *_ = full.step(actions)
        np.testing.assert_allclose(r_fast, r_full, rtol=1e-12, atol=1e-12)
