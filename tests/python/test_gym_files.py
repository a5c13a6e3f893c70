"""Result files of hunav.gym's environments: none by default (a learning loop), every file of every
episode with results_dir=, the same episodes, metrics and fingerprints either way, and what save()
writes without results_dir (python/README.md, "hunav.gym.HuNavEnv")."""
import csv
import json
import math
import os
import warnings

import numpy as np
import pytest

import hunav
from hunav.gym import HuNavEnv, HuNavVectorEnv
from test_gym_rules import wall_ahead

# What an episode of passing.yaml (two regular people, behavior 1) writes with every file.
EVERY_FILE = ["metrics.csv", "metrics_beh_1.csv", "metrics_beh_1_steps.csv", "metrics_steps.csv", "run.json",
              "states.csv"]
SUMMARIES = ["metrics.csv", "metrics_beh_1.csv", "run.json"]


def go_to_goal(obs):
    """Towards the goal in the robot frame (HuNavEnv's observation)."""
    heading = math.atan2(obs["goal"][1], obs["goal"][0])
    return np.array([0.6 if abs(heading) < 0.5 else 0.1, max(-1.2, min(1.2, 2.0 * heading))])


def play(env, seed):
    """One episode to its end; returns the trace of (reward, terminated, truncated, obs) and the last info."""
    obs, info = env.reset(seed=seed)
    trace, done = [], False
    while not done:
        obs, reward, terminated, truncated, info = env.step(go_to_goal(obs))
        trace.append((reward, terminated, truncated, {k: v.copy() for k, v in obs.items()}))
        done = terminated or truncated
    return trace, info


def same_trace(a, b):
    assert len(a) == len(b)
    for (ra, ta, ua, oa), (rb, tb, ub, ob) in zip(a, b):
        assert (ra, ta, ua) == (rb, tb, ub)
        for k in oa:
            np.testing.assert_array_equal(oa[k], ob[k])


def files_in(folder):
    return sorted(os.listdir(folder))


def test_the_control_a_simulation_with_files_writes_into_tmpdir(passing, tmp_path):
    """The watch of the next test sees files: hunav.Simulation's default writes into TMPDIR."""
    sim = hunav.Simulation(passing, duration=1.0)
    sim.reset()
    assert len(os.listdir(tmp_path / "tmpdir")) == 1


def test_the_envs_write_no_file_by_default(passing, tmp_path, monkeypatch):
    """Episodes played to their end (a goal, a time limit and a collision; resets and autoresets)
    leave TMPDIR (a fresh folder, conftest.py) and the working folder empty, with metrics in memory."""
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    env = HuNavEnv(passing)
    _, info = play(env, 1)
    assert info["status"] == "goal_reached" and env.run_dir is None
    assert env.sim.metrics()["path_length"] > 10.0 and len(info["fingerprint"]) == 16
    env = HuNavEnv(passing, duration=2.0)
    _, info = play(env, 2)
    assert info["status"] == "time_limit"
    env = HuNavEnv(wall_ahead(tmp_path))  # a collision ends the episode
    env.reset(seed=3)
    for _ in range(400):
        *_, terminated, truncated, info = env.step([0.6, 0.0])
        if terminated or truncated:
            break
    assert info["status"] == "collision"
    vec = HuNavVectorEnv(passing, num_envs=2, threads=1, duration=1.0)
    vec.reset(seed=5)
    ended = 0
    for _ in range(30):  # 10 control steps an episode: autoresets
        *_, terminated, truncated, infos = vec.step(np.tile([0.3, 0.0], (2, 1)))
        ended += int((terminated | truncated).sum())
    assert ended >= 4
    assert os.listdir(tmp_path / "tmpdir") == [] and os.listdir(cwd) == []


def test_results_dir_writes_every_file_of_every_episode(passing, tmp_path):
    results = tmp_path / "results"
    env = HuNavEnv(passing, results_dir=results, duration=6.0)
    run_dirs, fingerprints = [], []
    for seed in (3, 4, 3):  # seed 3 twice: a folder of its own each time
        _, info = play(env, seed)
        run_dirs.append(env.run_dir)
        fingerprints.append(info["fingerprint"])
    assert run_dirs == [str(results / "seed3"), str(results / "seed4"), str(results / "seed3-2")]
    assert files_in(results) == ["seed3", "seed3-2", "seed4"]
    for run_dir, fingerprint, seed in zip(run_dirs, fingerprints, (3, 4, 3)):
        assert files_in(run_dir) == EVERY_FILE
        run = json.loads(open(os.path.join(run_dir, "run.json")).read())
        assert run["fingerprint"] == fingerprint and run["seed"] == seed and run["complete"]
        rows = list(csv.DictReader(open(os.path.join(run_dir, "metrics.csv"))))
        assert len(rows) == 1 and rows[0]["seed"] == str(seed)
        assert len(open(os.path.join(run_dir, "states.csv")).readlines()) > 30
    assert fingerprints[0] == fingerprints[2]
    # A new environment on the same folder adds to it.
    env = HuNavEnv(passing, results_dir=results, duration=1.0)
    play(env, 4)
    assert env.run_dir == str(results / "seed4-2") and files_in(env.run_dir) == EVERY_FILE


def test_results_dir_gives_the_same_episodes_metrics_and_fingerprints(passing, tmp_path):
    """With and without files: the same steps, metrics and fingerprints; save() without results_dir
    writes the same metrics.csv and per-behavior rows and a run.json with the same metrics, and
    warns that states.csv and the per-tick files need results_dir=."""
    for seed in (1, 6):
        plain = HuNavEnv(passing)
        filed = HuNavEnv(passing, results_dir=tmp_path / "results")
        trace, info = play(plain, seed)
        trace_filed, info_filed = play(filed, seed)
        same_trace(trace, trace_filed)
        assert info["fingerprint"] == info_filed["fingerprint"] and info["status"] == info_filed["status"]
        assert plain.sim.metrics() == filed.sim.metrics() and len(plain.sim.metrics()) > 20
        out = tmp_path / f"saved{seed}"
        with pytest.warns(UserWarning, match=r"states\.csv and the per-tick metric files .*results_dir="):
            assert plain.save(out) == str(out)
        assert files_in(out) == SUMMARIES
        for name in ("metrics.csv", "metrics_beh_1.csv"):
            assert (out / name).read_text() == open(os.path.join(filed.run_dir, name)).read(), name
        saved = json.loads((out / "run.json").read_text())
        written = json.loads(open(os.path.join(filed.run_dir, "run.json")).read())
        assert saved["metrics"] == written["metrics"]
        for key in ("fingerprint", "recorded_fingerprint", "status", "seed", "ticks", "recorded_ticks"):
            assert saved[key] == written[key], key
        assert saved["states_file"] == "" and written["states_file"].endswith("states.csv")
        # With results_dir, save() copies every file, without a warning.
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            filed.save(tmp_path / f"copied{seed}")
        assert files_in(tmp_path / f"copied{seed}") == EVERY_FILE


def test_the_vector_env_with_and_without_results_dir(passing, tmp_path):
    """Every world's every episode in results_dir/seed<s> (final_info's run_dir); the same rewards,
    observations and fingerprints as without files."""
    results = tmp_path / "results"
    runs = []
    for results_dir in (None, results):
        env = HuNavVectorEnv(passing, num_envs=2, threads=1, duration=1.0, results_dir=results_dir)
        obs, _ = env.reset(seed=10)
        trace, finals = [], []
        for _ in range(25):  # 10 control steps an episode: two autoresets per world
            obs, rewards, terminated, truncated, infos = env.step(np.tile([0.3, 0.1], (2, 1)))
            trace.append((rewards, obs))
            for i in np.flatnonzero(terminated | truncated):
                finals.append(infos["final_info"][i])
        runs.append((trace, finals, env.vsim.fingerprints()))
    (trace, finals, prints), (trace_filed, finals_filed, prints_filed) = runs
    assert prints == prints_filed
    for (ra, oa), (rb, ob) in zip(trace, trace_filed):
        np.testing.assert_array_equal(ra, rb)
        for k in oa:
            np.testing.assert_array_equal(oa[k], ob[k])
    assert len(finals_filed) == 4 and all("run_dir" not in f for f in finals)
    assert sorted(f["run_dir"] for f in finals_filed) == [str(results / f"seed{s}") for s in (10, 11, 12, 13)]
    for f in finals_filed:
        assert files_in(f["run_dir"]) == EVERY_FILE
        run = json.loads(open(os.path.join(f["run_dir"], "run.json")).read())
        assert run["status"] == str(f["status"]) == "time_limit" and run["seed"] == int(f["seed"])
    # The worlds' current episodes (seeds 14, 15) write theirs as they go.
    assert files_in(results) == [f"seed{s}" for s in (10, 11, 12, 13, 14, 15)]


def test_the_envs_refuse_the_simulations_file_options(passing, tmp_path):
    for kwargs in ({"out_dir": str(tmp_path)}, {"files": True}):
        with pytest.raises(ValueError, match="results_dir="):
            HuNavEnv(passing, **kwargs)
        with pytest.raises(ValueError, match="results_dir="):
            HuNavVectorEnv(passing, num_envs=2, **kwargs)


def test_simulation_files_false_and_reset_out_dir(passing, tmp_path):
    """hunav.Simulation(files=False): no file (out_dir with it is a ValueError); reset(out_dir=...)
    writes that episode's files there all the same."""
    with pytest.raises(ValueError, match="files=False"):
        hunav.Simulation(passing, files=False, out_dir=str(tmp_path / "x"))
    sim = hunav.Simulation(passing, files=False, duration=1.0)
    sim.run()
    assert os.listdir(tmp_path / "tmpdir") == []
    sim.reset(out_dir=str(tmp_path / "episode"))
    sim.run()
    assert files_in(tmp_path / "episode") == EVERY_FILE
    with pytest.raises(ValueError, match="out_dir is empty"):
        sim.reset(out_dir="")
    vs = hunav.VectorSimulation(2, passing, files=False, duration=1.0)
    with pytest.raises(ValueError, match="out_dirs has 1 values for 2 worlds"):
        vs.reset(out_dirs=[str(tmp_path / "a")])
    vs.reset(out_dirs=[None, str(tmp_path / "w1")])
    vs.run()
    assert files_in(tmp_path / "w1") == EVERY_FILE and os.listdir(tmp_path / "tmpdir") == []
