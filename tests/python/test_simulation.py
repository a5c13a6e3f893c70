"""hunav.Simulation: the native module against hunav_run, its observations, determinism, bad input."""
import csv
import json
import math
import re
import subprocess

import numpy as np
import pytest

import hunav
from conftest import keep_right_policy


def hunav_run_fingerprint(binary, scenario, planner, seed, out_dir):
    out = subprocess.run([binary, "--scenario", scenario, "--planner", planner, "--seed", str(seed),
                          "--out", str(out_dir), "--quiet"], capture_output=True, text=True, check=True)
    match = re.search(r"fingerprint ([0-9a-f]+)", out.stdout)
    assert match, out.stdout
    return match.group(1)


@pytest.mark.parametrize("planner", ["dwb", "none"])
def test_run_matches_hunav_run(passing, hunav_run, tmp_path, planner):
    sim = hunav.Simulation(passing, seed=1, planner=planner)
    info = sim.run()
    assert info["done"]
    expected = hunav_run_fingerprint(hunav_run, passing, planner, 1, tmp_path / "cli")
    assert sim.fingerprint() == expected
    assert info["fingerprint"] == expected
    if planner == "dwb":
        assert info["status"] == "goal_reached" and info["goal_reached"]


def test_reset_then_run_with_planner(passing, hunav_run, tmp_path):
    sim = hunav.Simulation(passing, seed=2, planner="sfw")
    obs = sim.reset()  # the planner's first observation
    assert obs["seq"] == 1 and obs["scan"].shape == (180,) and not sim.done
    sim.run()
    assert sim.observation()["seq"] > 100
    assert sim.fingerprint() == hunav_run_fingerprint(hunav_run, passing, "sfw", 2, tmp_path / "cli")


def test_observation_shapes_and_dtypes(passing):
    sim = hunav.Simulation(passing, seed=1)
    obs = sim.reset()
    assert set(obs) >= {"robot", "goal", "goal_valid", "scan", "people", "people_ids", "time", "seq"}
    assert obs["robot"].shape == (5,) and obs["robot"].dtype == np.float64
    assert obs["goal"].shape == (4,) and obs["goal"].dtype == np.float64
    assert obs["scan"].shape == (sim.robot["laser_beams"],) and obs["scan"].dtype == np.float32
    assert obs["people"].ndim == 2 and obs["people"].shape[1] == 6 and obs["people"].dtype == np.float64
    assert obs["people_ids"].dtype == np.int32 and len(obs["people_ids"]) == len(obs["people"])
    assert obs["time"] == 0.0 and obs["goal_valid"]
    np.testing.assert_allclose(obs["goal"], [15.0, 0.0, 0.0, 0.3])
    period = sim.robot["control_period"]
    nxt = sim.step(0.5, 0.0)
    assert nxt["time"] == pytest.approx(period)
    assert nxt["robot"][0] > 0.0  # moved forward
    assert sim.info()["status"] == "running" and not sim.done


def test_state_metrics_fingerprint_and_save(passing, tmp_path):
    sim = hunav.Simulation(passing, seed=2, duration=3.0)
    sim.reset()
    state = sim.state()
    agents = state["agents"]
    n = len(agents["id"])
    assert n == 2 and state["robot"].shape == (7,)
    assert agents["pose"].shape == (n, 3) and agents["velocity"].shape == (n, 3)
    assert agents["behavior"].dtype == np.int8 and list(agents["behavior"]) == [1, 1]
    assert agents["behavior_state"].shape == (n,) and agents["goal"].shape == (n, 2)
    while not sim.done:
        sim.step(0.3, 0.0)
    info = sim.info()
    assert info["status"] == "time_limit" and info["time_limit"] and info["time"] == pytest.approx(3.0)
    metrics = sim.metrics()
    assert "path_length" in metrics and metrics["path_length"] > 0.5
    out = tmp_path / "saved"
    sim.save(str(out))
    run = json.loads((out / "run.json").read_text())
    assert run["fingerprint"] == sim.fingerprint() and run["status"] == "time_limit"
    with open(out / "metrics.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 1 and rows[0]["seed"] == "2"
    assert (out / "states.csv").read_text().startswith("t,kind,id,x,y,yaw")


def test_fewer_files_the_same_episode_and_metrics(passing, tmp_path):
    """states_csv=False and per_tick_files=False (for learning loops that never read them) leave out
    states.csv and the per-tick metric files only."""
    results = []
    for files in (True, False):
        sim = hunav.Simulation(passing, seed=4, states_csv=files, per_tick_files=files)
        trace, fingerprint = run_scripted(sim, 4, 400)
        out = tmp_path / f"files_{files}"
        sim.save(str(out))
        results.append((trace, fingerprint, sim.metrics(), sim.info()["status"], out))
    (trace, fingerprint, metrics, status, out), (trace2, fingerprint2, metrics2, status2, out2) = results
    assert fingerprint2 == fingerprint and status2 == status == "goal_reached"
    assert metrics2 == metrics and metrics["social_work"] > 0.0
    assert len(trace2) == len(trace) and all((a["robot"] == b["robot"]).all() for a, b in zip(trace, trace2))
    assert (out / "states.csv").exists() and (out / "metrics_steps.csv").exists()
    assert sorted(p.name for p in out2.iterdir()) == ["metrics.csv", "metrics_beh_1.csv", "run.json"]
    assert (out2 / "metrics.csv").read_text() == (out / "metrics.csv").read_text()
    vs = hunav.VectorSimulation(2, passing, seeds=[4, 5], states_csv=False, per_tick_files=False)
    vs.reset()
    vs.step(np.zeros((2, 2)))
    with pytest.raises(TypeError):
        hunav.Simulation(passing, states_csv="no")


def test_metrics_while_running(passing):
    sim = hunav.Simulation(passing, seed=1)
    sim.reset()
    for _ in range(15):  # 1.5 s: the evaluator's running values come once per simulated second
        sim.step(0.5, 0.0)
    assert "path_length" in sim.metrics()


def run_scripted(sim, seed, steps):
    obs = sim.reset(seed=seed)
    trace = [obs]
    for _ in range(steps):
        if sim.done:
            break
        trace.append(sim.step(*keep_right_policy(obs["robot"], obs["goal"])))
        obs = trace[-1]
    return trace, sim.fingerprint()


def test_same_seed_same_observations(passing):
    a, fa = run_scripted(hunav.Simulation(passing), 3, 40)
    b, fb = run_scripted(hunav.Simulation(passing), 3, 40)
    assert fa == fb and len(a) == len(b)
    for oa, ob in zip(a, b):
        for key in ("robot", "scan", "people", "people_ids"):
            np.testing.assert_array_equal(oa[key], ob[key])
    # reset(seed) on one simulation replays its episode too
    sim = hunav.Simulation(passing)
    run_scripted(sim, 5, 10)
    c, fc = run_scripted(sim, 3, 40)
    assert fc == fa


def test_scripted_policy_reaches_goal(passing):
    sim = hunav.Simulation(passing, seed=1)
    trace, _ = run_scripted(sim, 1, 1000)
    info = sim.info()
    assert info["status"] == "goal_reached", info
    assert info["robot_collisions"] == 0
    assert len(trace) < 600


def test_bad_scenario_raises_with_file_line(passing, tmp_path):
    text = open(passing).read().replace("dt: 0.01 ", "dt: fast ")
    bad = tmp_path / "bad.yaml"
    bad.write_text(text)
    with pytest.raises(hunav.ConfigError) as err:
        hunav.Simulation(str(bad))
    assert re.search(r"bad\.yaml:\d+: dt", str(err.value)), str(err.value)
    assert isinstance(err.value, ValueError)
    with pytest.raises(hunav.ConfigError, match="missing.yaml"):
        hunav.Simulation(str(tmp_path / "missing.yaml"))


def test_bad_calls_raise(passing, tmp_path):
    with pytest.raises(ValueError, match="unknown planner"):
        hunav.Simulation(passing, planner="nope")
    sim = hunav.Simulation(passing, duration=0.2)
    with pytest.raises(RuntimeError, match="reset"):
        sim.step(0.1, 0.0)
    sim.reset()
    with pytest.raises(ValueError, match="not finite"):
        sim.step(float("nan"), 0.0)
    with pytest.raises(ValueError, match="holonomic"):
        sim.step(0.1, 0.0, vy=0.2)
    sim.step(0.1, 0.0)
    sim.step(0.1, 0.0)
    assert sim.done and sim.info()["status"] == "time_limit"
    with pytest.raises(RuntimeError, match="ended"):
        sim.step(0.1, 0.0)
    with pytest.raises(RuntimeError, match="planner 'dwb' drives the robot"):
        planned = hunav.Simulation(passing, planner="dwb", duration=0.5)
        planned.reset()
        planned.step(0.1, 0.0)
    running = hunav.Simulation(passing)
    running.reset()
    with pytest.raises(RuntimeError, match="still running"):
        running.save(str(tmp_path / "never"))


def test_map_and_robot(passing):
    sim = hunav.Simulation(passing)
    world = sim.map()
    assert world["segments"].shape == (4, 4) and world["circles"].shape == (0, 3)
    assert world["bounds"].shape == (4,)
    assert sim.robot["max_v"] == 0.6 and not sim.robot["holonomic"]
    assert math.isclose(sim.robot["control_period"], 0.1)
    assert "dwb" in hunav.planners()


def test_holonomic_robot(passing, tmp_path):
    text = open(passing).read().replace("  radius: 0.3\n", "  radius: 0.3\n  drive: holonomic\n", 1)
    scenario = tmp_path / "holonomic.yaml"
    scenario.write_text(text)
    sim = hunav.Simulation(str(scenario))
    assert sim.robot["holonomic"]
    sim.reset()
    for _ in range(10):
        obs = sim.step(0.0, 0.0, vy=0.4)  # sideways, to the robot's left
    assert obs["robot"][1] > 0.2 and abs(obs["robot"][0]) < 1e-6
