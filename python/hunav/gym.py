"""Gymnasium-style environments on hunav.Simulation (HuNavEnv) and hunav.VectorSimulation
(HuNavVectorEnv, many worlds stepped together over threads): the robot driven by the agent's actions
among HuNavSim's people.

Gymnasium is not a Debian package: the spaces below are small classes of our own with the attributes
Gymnasium's have (shape, dtype, low, high, sample(), contains(), seed()); HuNavEnv subclasses
gymnasium.Env when gymnasium can be imported, and follows its API either way:

    env = HuNavEnv("scenarios/passing.yaml")
    obs, info = env.reset(seed=1)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

Observation (a dict of float32 arrays, robot frame: x ahead, y to the left):
    "robot":  (2,)  [v, w], the robot's forward speed (m/s) and yaw rate (rad/s)
    "goal":   (2,)  the goal's position relative to the robot (m)
    "scan":   (beams,) laser ranges (m), in [0, range_max]
    "people": (max_people, 6) the perceived people nearest first, one row [dx, dy, vx, vy, radius,
              present]: position relative to the robot and velocity, both in the robot frame (rows
              beyond those perceived are 0)
Action: [v, w] (m/s, rad/s), or [v, w, vy] for a holonomic robot; clipped to action_space's bounds.

Default reward of a step (one control period), with d the robot's distance to its goal and d_i its
distance (centre to centre) to person i of the ground truth after the step:
    r = progress_weight * (d_before - d_after)
        - intrusion_weight * sum_i max(0, (personal_distance - d_i) / personal_distance)
        - collision_penalty * [the robot touched a person or a wall in the step]
        + goal_bonus * [goal reached]
with progress_weight 1 per metre, intrusion_weight 0.1, personal_distance 1.2 m (the evaluator's
personal band, docs/metrics.md), collision_penalty 10, goal_bonus 10 (RewardWeights). Pass
reward_fn(env, before, after, info) -> float to use your own (before/after: sim.state() around the
step; info: the step's info dict).
terminated: the goal is reached, or the robot collided (terminate_on_collision: the simulation's
episode then ends with status "collision", its own, and a reason naming what the robot touched) or
got stuck; truncated: the scenario's time limit. A step() after the episode ended raises RuntimeError
(call reset()), as Gymnasium's order checks would; so do step() and reset() after close().

Result files: none by default (no folder, no temporary file: the metrics are computed in memory,
env.sim.metrics(), info's fingerprint). results_dir=DIR writes every file of every episode (what
hunav_run writes: metrics.csv, run.json, states.csv, the per-tick and per-behavior files) into
DIR/seed<s> (DIR/seed<s>-2, -3, ... for a seed played again or a folder already there; env.run_dir
is the episode's). save(out_dir) after an episode without results_dir writes the files that need no
samples (metrics.csv, the per-behavior metrics files, run.json) and warns that states.csv and the
per-tick files need results_dir=.

Seeds: reset(seed=s) plays the episode of seed s (the scenario's random people and sensor noise) and
seeds env.np_random; reset() without a seed plays the next seed (s + 1, s + 2, ...: every episode a
new one; the first reset() without any seed plays the `seed` given to HuNavEnv, else the scenario's).

The rules of Gymnasium's env_checker hold and are tested without Gymnasium
(tests/python/test_gym_rules.py): spaces printing their real bounds, observations inside
observation_space, the step 5-tuple's types, reset(seed) determinism, np_random, unwrapped, spec,
metadata.
"""
import math
import os

import numpy as np

from . import _hunav
from .render import render_top_view

try:  # subclass gymnasium.Env (and VectorEnv) when it is installed
    import gymnasium as _gymnasium
    _EnvBase = _gymnasium.Env
    _VecBase = getattr(getattr(_gymnasium, "vector", None), "VectorEnv", object)
except ImportError:  # pragma: no cover - the usual case on Debian
    _gymnasium = None
    _EnvBase = object
    _VecBase = object


class Box:
    """A box in R^shape, like gymnasium.spaces.Box: low <= x <= high element-wise."""

    def __init__(self, low, high, shape=None, dtype=np.float32, seed=None):
        self.dtype = np.dtype(dtype)
        if shape is None:
            shape = np.broadcast(np.asarray(low), np.asarray(high)).shape
        self.shape = tuple(int(s) for s in shape)
        self.low = np.broadcast_to(np.asarray(low, dtype=self.dtype), self.shape).copy()
        self.high = np.broadcast_to(np.asarray(high, dtype=self.dtype), self.shape).copy()
        self.np_random = np.random.default_rng(seed)

    def seed(self, seed=None):
        self.np_random = np.random.default_rng(seed)
        return [seed]

    def sample(self):
        """Uniform within finite bounds; normal around the bound (or 0) on an unbounded side."""
        low = np.where(np.isfinite(self.low), self.low, -np.inf).astype(np.float64)
        high = np.where(np.isfinite(self.high), self.high, np.inf).astype(np.float64)
        out = self.np_random.standard_normal(self.shape)
        both = np.isfinite(low) & np.isfinite(high)
        out[both] = self.np_random.uniform(low[both], high[both])
        lo_only = np.isfinite(low) & ~np.isfinite(high)
        out[lo_only] = low[lo_only] + self.np_random.exponential(size=int(lo_only.sum()))
        hi_only = ~np.isfinite(low) & np.isfinite(high)
        out[hi_only] = high[hi_only] - self.np_random.exponential(size=int(hi_only.sum()))
        return out.astype(self.dtype)

    def contains(self, x):
        x = np.asarray(x)
        if x.shape != self.shape or not np.can_cast(x.dtype, self.dtype, casting="same_kind"):
            return False
        return bool(np.all(x >= self.low) and np.all(x <= self.high))

    def __contains__(self, x):
        return self.contains(x)

    def __repr__(self):
        """As gymnasium's: a bound that is one number throughout prints as that number, else its array."""
        def bound(a):
            return str(a.flat[0]) if a.size and np.all(a == a.flat[0]) else str(a)
        return f"Box({bound(self.low)}, {bound(self.high)}, {self.shape}, {self.dtype})"

    def __eq__(self, other):
        return (isinstance(other, Box) and self.shape == other.shape and self.dtype == other.dtype
                and np.array_equal(self.low, other.low) and np.array_equal(self.high, other.high))


class Dict:
    """A dict of spaces, like gymnasium.spaces.Dict."""

    def __init__(self, spaces, seed=None):
        self.spaces = dict(spaces)
        self.shape = None
        self.dtype = None
        self.seed(seed)

    def seed(self, seed=None):
        seeds = np.random.SeedSequence(seed).spawn(len(self.spaces))
        for space, s in zip(self.spaces.values(), seeds):
            space.seed(int(s.generate_state(1)[0]))
        return [seed]

    def sample(self):
        return {k: s.sample() for k, s in self.spaces.items()}

    def contains(self, x):
        return isinstance(x, dict) and x.keys() == self.spaces.keys() and all(
            s.contains(x[k]) for k, s in self.spaces.items())

    def __contains__(self, x):
        return self.contains(x)

    def __getitem__(self, key):
        return self.spaces[key]

    def keys(self):
        return self.spaces.keys()

    def __eq__(self, other):
        return isinstance(other, Dict) and self.spaces == other.spaces

    def __repr__(self):
        return "Dict(" + ", ".join(f"{k}: {s}" for k, s in self.spaces.items()) + ")"


class RewardWeights:
    """The default reward's weights (module docstring)."""

    def __init__(self, progress=1.0, intrusion=0.1, personal_distance=1.2, collision=10.0, goal=10.0):
        self.progress = progress
        self.intrusion = intrusion
        self.personal_distance = personal_distance
        self.collision = collision
        self.goal = goal


def default_reward(env, before, after, info, weights=None):
    """The documented default reward from the ground truth before and after a step (sim.state())."""
    w = weights or env.reward_weights
    goal = np.asarray(env._goal)
    d_before = math.hypot(*(before["robot"][:2] - goal))
    d_after = math.hypot(*(after["robot"][:2] - goal))
    r = w.progress * (d_before - d_after)
    people = after["agents"]["pose"][:, :2]
    if len(people):
        d = np.hypot(*(people - after["robot"][:2]).T)
        r -= w.intrusion * float(np.sum(np.maximum(0.0, (w.personal_distance - d) / w.personal_distance)))
    if info["collided"]:
        r -= w.collision
    if info["goal_reached"]:
        r += w.goal
    return float(r)


def episode_folder(results_dir, seed, taken=()):
    """results_dir/seed<seed>, or seed<seed>-2, -3, ... when that folder exists or is in `taken`."""
    base = os.path.join(results_dir, f"seed{seed}")
    path, n = base, 1
    while path in taken or os.path.exists(path):
        n += 1
        path = f"{base}-{n}"
    return path


def _simulation_kwargs(sim_kwargs):
    """The keyword arguments for the environments' simulations: no file unless results_dir asks."""
    for key in ("out_dir", "files"):
        if key in sim_kwargs:
            raise ValueError(f"{key}= is not an environment's option: results_dir=DIR writes every episode's "
                             "result files (default: none)")
    return dict(sim_kwargs, files=False)


def collision_reason(sim):
    """What the robot touched, in words: the nearest person when one is in contact, else an obstacle."""
    state = sim.state()
    robot = state["robot"]
    agents = state["agents"]
    if len(agents["id"]):
        gaps = np.hypot(*(agents["pose"][:, :2] - robot[:2]).T) - agents["radius"] - robot[6]
        i = int(np.argmin(gaps))
        if gaps[i] < 0.05:
            return (f"the robot touched person {int(agents['id'][i])} ({agents['name'][i]}) at "
                    f"t = {state['time']:.2f} s (terminate_on_collision)")
    return f"the robot touched an obstacle at t = {state['time']:.2f} s (terminate_on_collision)"


class HuNavEnv(_EnvBase):
    """One hunav.Simulation stepped by the agent, one control period per step (module docstring).

    scenario: the scenario file; seed: the first episode's seed (default: the scenario's);
    max_people: rows of obs["people"] (default: the scenario's number of people, at least 1);
    reward_fn(env, before, after, info) -> float replaces default_reward (before/after: sim.state());
    terminate_on_collision: end the episode at the robot's first contact;
    render_mode: "rgb_array" (render() returns the top view) or None; render_size: (width, height)
    in pixels (default: 20 pixels per metre of the scenario's bounds); results_dir: where every
    episode's result files go (module docstring; default None: no file at all).
    Further keyword arguments go to hunav.Simulation (duration, sample_rate, profile, metrics,
    format, states_csv...).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}
    spec = None  # gymnasium.make() sets it on the environments it makes

    def __init__(self, scenario, seed=None, max_people=None, reward_fn=None, reward_weights=None,
                 terminate_on_collision=True, render_mode="rgb_array", render_size=None, results_dir=None,
                 **sim_kwargs):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode {render_mode!r} is not one of {self.metadata['render_modes']}")
        self.sim = _hunav.Simulation(scenario, seed=seed, planner=None, **_simulation_kwargs(sim_kwargs))
        self.results_dir = None if results_dir is None else os.fspath(results_dir)
        self.run_dir = None  # the episode's result folder (results_dir only)
        self.scenario = scenario
        self.reward_fn = reward_fn
        self.reward_weights = reward_weights or RewardWeights()
        self.terminate_on_collision = terminate_on_collision
        self.render_mode = render_mode
        self.render_size = render_size
        robot = self.sim.robot
        self.holonomic = robot["holonomic"]
        self._goal = (float(robot["goal"][0]), float(robot["goal"][1]))
        self.max_people = max(1, int(max_people) if max_people is not None else self._people_count())
        self.action_space = self._make_action_space(robot)
        self.observation_space = self._make_observation_space(robot)
        # The action box as Python floats (clipping a 2-vector with them is cheaper than np.clip).
        self._low = [float(x) for x in self.action_space.low]
        self._high = [float(x) for x in self.action_space.high]
        self._scan_max = self.observation_space["scan"].high[0]
        self._started = False
        self._state = None  # sim.state() of the last step, kept for a reward_fn only
        self._goal_distance = 0.0
        self._robot_collisions = 0
        self._next_seed = int(self.sim.seed)  # of the next reset() without a seed
        self._np_random = None
        self._np_random_seed = None

    # --- Gymnasium's Env attributes ---
    @property
    def np_random(self):
        """The environment's numpy Generator (for your own randomness: the simulation has its own
        seeded streams); seeded by reset(seed=...), else from fresh entropy on first use."""
        if self._np_random is None:
            self._np_random_seed = int(np.random.SeedSequence().entropy % (2**63))
            self._np_random = np.random.default_rng(self._np_random_seed)
        return self._np_random

    @np_random.setter
    def np_random(self, value):
        self._np_random, self._np_random_seed = value, -1

    @property
    def np_random_seed(self):
        """The seed np_random was made from (-1: a generator that was set from outside)."""
        _ = self.np_random
        return self._np_random_seed

    @property
    def unwrapped(self):
        return self

    def _people_count(self):
        self.sim.reset()
        return len(self.sim.state()["agents"]["id"])

    def _make_action_space(self, r):
        if self.holonomic:
            return Box([r["min_v"], -r["max_w"], -r["max_vy"]], [r["max_v"], r["max_w"], r["max_vy"]])
        return Box([r["min_v"], -r["max_w"]], [r["max_v"], r["max_w"]])

    def _make_observation_space(self, r):
        inf = np.inf
        return Dict({
            "robot": Box(-inf, inf, (2,)),
            "goal": Box(-inf, inf, (2,)),
            "scan": Box(0.0, r["laser_range_max"], (int(r["laser_beams"]),)),
            "people": Box(-inf, inf, (self.max_people, 6)),
        })

    # --- Gymnasium API ---
    def reset(self, seed=None, options=None):
        """Starts an episode: the episode of `seed`, or without one the next seed (module docstring).
        Returns (obs, info). options: not used (accepted for Gymnasium's signature)."""
        self._require_open()
        if seed is not None:
            seed = int(seed)
            if seed < 0:
                raise ValueError("seed must be >= 0")
            self._np_random_seed = seed
            self._np_random = np.random.default_rng(seed)
            self.action_space.seed(seed)
        else:
            seed = self._next_seed
        if self.results_dir is not None:
            self.run_dir = episode_folder(self.results_dir, seed)
        self.sim.reset(seed=seed, out_dir=self.run_dir)
        self._next_seed = seed + 1
        self._started = True
        self._robot_collisions = 0
        self._state = self.sim.state() if self.reward_fn is not None else None
        self._goal_distance = self.sim.reward_terms(self.reward_weights.personal_distance)[0]
        info = self.sim.info()
        info["collided"] = False
        return self._observe(), info

    def step(self, action):
        """Applies `action` for one control period; returns (obs, reward, terminated, truncated, info)."""
        self._require_open()
        if not self._started:
            raise RuntimeError("call reset() before step()")
        if self.sim.done:
            raise RuntimeError(f"the episode has ended ({self.sim.info()['status']}): call reset()")
        a = np.asarray(action, dtype=np.float64)
        if a.shape != self.action_space.shape:
            raise ValueError(f"action of shape {a.shape}, expected {self.action_space.shape}")
        a = a.tolist()
        if not all(math.isfinite(x) for x in a):
            raise ValueError(f"action {a} is not finite")
        a = [min(max(x, lo), hi) for x, lo, hi in zip(a, self._low, self._high)]
        self.sim.step(a[0], a[1], a[2] if self.holonomic else 0.0)
        info = self.sim.info()
        collided = info["robot_collisions"] > self._robot_collisions
        self._robot_collisions = info["robot_collisions"]
        info["collided"] = bool(collided)
        if self.reward_fn is None:
            reward = self._default_reward(info)
        else:
            before, self._state = self._state, self.sim.state()
            reward = float(self.reward_fn(self, before, self._state, info))
        if collided and self.terminate_on_collision and not info["done"]:
            info = self._end_at_collision(info)
        terminated = info["goal_reached"] or info["stuck"] or (collided and self.terminate_on_collision)
        truncated = info["time_limit"] and not terminated
        return self._observe(), reward, bool(terminated), bool(truncated), info

    def render(self):
        """The top view as a (height, width, 3) uint8 array (render_mode "rgb_array"); None without a
        render mode."""
        self._require_open()
        if not self._started:
            raise RuntimeError("call reset() before render()")
        if self.render_mode is None:
            return None
        w, h = self.render_size or (None, None)
        return render_top_view(self.sim, width=w, height=h, resolution=0.05)

    def save(self, out_dir):
        """Copies the ended episode's result files (metrics.csv, states.csv, run.json, ...) into
        out_dir and returns it; RuntimeError while the episode runs. Without results_dir there are
        none: it writes metrics.csv, the per-behavior metrics files and run.json from the episode's
        results and warns (UserWarning) that states.csv and the per-tick files need results_dir=."""
        self._require_open()
        if not self._started:
            raise RuntimeError("call reset() before save()")
        return self.sim.save(os.fspath(out_dir))

    def close(self):
        """Frees the simulation; the environment cannot be used afterwards (closing twice is fine)."""
        self.sim = None

    def _require_open(self):
        if self.sim is None:
            raise RuntimeError("the environment is closed")

    def _end_at_collision(self, info):
        """Ends the simulation's episode with status "collision" and a reason naming what the robot
        touched; returns the step's info updated."""
        collided = info["collided"]
        info = self.sim.end_episode("collision", collision_reason(self.sim))
        info["collided"] = collided
        return info

    # --- helpers ---
    def _default_reward(self, info):
        """default_reward's formula on sim.reward_terms() (computed natively: no sim.state() a step)."""
        w = self.reward_weights
        d_after, intrusion, _ = self.sim.reward_terms(w.personal_distance)
        r = w.progress * (self._goal_distance - d_after) - w.intrusion * intrusion
        self._goal_distance = d_after
        if info["collided"]:
            r -= w.collision
        if info["goal_reached"]:
            r += w.goal
        return float(r)

    def _observe(self):
        """The observation (module docstring), computed natively from the simulation's last one."""
        return self.sim.robot_frame_observation(self.max_people, self._scan_max)


def default_vector_reward(env, before, after, infos, weights=None):
    """default_reward for every world at once: (num_envs,) float64. before/after: vsim.state()."""
    w = weights or env.reward_weights
    goal = env._goal
    d_before = np.hypot(*(before["robot"][:, :2] - goal).T)
    d_after = np.hypot(*(after["robot"][:, :2] - goal).T)
    r = w.progress * (d_before - d_after)
    agents = after["agents"]
    if agents["pose"].shape[1]:
        d = np.hypot(*(agents["pose"][:, :, :2] - after["robot"][:, None, :2]).transpose(2, 0, 1))
        intrusion = np.maximum(0.0, (w.personal_distance - d) / w.personal_distance)
        r = r - w.intrusion * np.where(agents["id"] >= 0, intrusion, 0.0).sum(axis=1)
    r = r - w.collision * infos["collided"] + w.goal * infos["goal_reached"]
    return r.astype(np.float64)


class HuNavVectorEnv(_VecBase):
    """num_envs worlds of one scenario on a hunav.VectorSimulation, stepped together over threads.

    The Gymnasium vector API (num_envs, single_observation_space, single_action_space, batched
    observation_space/action_space; reset(seed, options) -> (obs, infos); step(actions) -> (obs,
    rewards, terminations, truncations, infos)) with each world's observation, action, reward and
    end conditions those of HuNavEnv (module docstring), stacked on a first axis of num_envs.

    Autoreset in the same step (as Stable-Baselines3's VecEnv and Gymnasium's SAME_STEP mode): a
    world whose episode ends in step() is reset at once; step() returns its new episode's first
    observation, and infos["final_observation"][i] (a dict of that world's arrays) and
    infos["final_info"][i] its last. World i's episodes use seeds s_i, s_i + num_envs,
    s_i + 2 num_envs, ... (s_i: its first seed), so the worlds never replay each other's episodes.

    A world's episode that ends by a collision (terminate_on_collision) ends with status "collision"
    and a reason, as HuNavEnv's; infos["final_info"][i] holds the ended episode's "status" and
    "reason". Result files: none by default; results_dir=DIR writes every file of every episode
    into DIR/seed<s> (as HuNavEnv's; infos["final_info"][i]["run_dir"]).

    seeds: the first episodes' seeds (default: the scenario's seed + i); threads: the pool's
    threads (default: the machine's cores, at most num_envs); reward_fn(env, before, after, infos)
    -> (num_envs,) replaces default_vector_reward (before/after: vsim.state()). Further keyword
    arguments go to hunav.VectorSimulation (duration, sample_rate, metrics, profile...).
    """

    metadata = {"autoreset_mode": "same_step", "render_modes": []}
    spec = None
    render_mode = None

    def __init__(self, scenario, num_envs, seeds=None, threads=None, max_people=None, reward_fn=None,
                 reward_weights=None, terminate_on_collision=True, results_dir=None, **sim_kwargs):
        self.vsim = _hunav.VectorSimulation(num_envs, scenario, seeds=seeds, planner=None, threads=threads,
                                            **_simulation_kwargs(sim_kwargs))
        self.num_envs = int(num_envs)
        self.scenario = scenario
        self.reward_fn = reward_fn
        self.reward_weights = reward_weights or RewardWeights()
        self.terminate_on_collision = terminate_on_collision
        robot = self.vsim.robot
        self.holonomic = robot["holonomic"]
        self._goal = np.asarray(robot["goal"][:2])
        self.max_people = max(1, int(max_people) if max_people is not None else self.vsim.max_people)
        single = HuNavEnv._make_action_space(self, robot)
        self.single_action_space = single
        self.single_observation_space = HuNavEnv._make_observation_space(self, robot)
        self.action_space = Box(np.broadcast_to(single.low, (self.num_envs,) + single.shape),
                                np.broadcast_to(single.high, (self.num_envs,) + single.shape))
        self.observation_space = Dict({k: Box(np.broadcast_to(s.low, (self.num_envs,) + s.shape),
                                              np.broadcast_to(s.high, (self.num_envs,) + s.shape))
                                       for k, s in self.single_observation_space.spaces.items()})
        self._scan_max = self.single_observation_space["scan"].high[0]
        self._started = False
        self._state = None  # vsim.state() of the last step, kept for a reward_fn only
        self._goal_distance = None
        self._robot_collisions = None
        self._next_seed = None
        self.results_dir = None if results_dir is None else os.fspath(results_dir)
        self.run_dirs = [None] * self.num_envs  # each world's episode's result folder (results_dir only)
        self._np_random = None
        self._np_random_seed = None

    np_random = HuNavEnv.np_random
    np_random_seed = HuNavEnv.np_random_seed
    unwrapped = HuNavEnv.unwrapped

    def reset(self, seed=None, options=None):
        """Starts every world's episode: seed an int (world i gets seed + i), a list of num_envs
        seeds, or None (each world's next seed). Returns (obs, infos)."""
        self._require_open()
        if seed is not None and np.ndim(seed) == 0:
            self._np_random_seed = int(seed)
            self._np_random = np.random.default_rng(int(seed))
        if seed is None:
            seeds = self._next_seed if self._next_seed is not None else self.vsim.seeds
        elif np.ndim(seed) == 0:
            seeds = [int(seed) + i for i in range(self.num_envs)]
        else:
            seeds = [int(s) for s in seed]
        seeds = [int(s) for s in seeds]
        self.vsim.reset(seeds=seeds, out_dirs=self._out_dirs(range(self.num_envs), seeds))
        self._next_seed = [s + self.num_envs for s in seeds]
        self._started = True
        self._after_reset()
        infos = self._infos(np.zeros(self.num_envs, dtype=bool), self._robot_collisions)
        return self._observe(), infos

    def step(self, actions):
        """Applies actions (num_envs, action dims) for one control period in every world."""
        self._require_open()
        if not self._started:
            raise RuntimeError("call reset() before step()")
        a = np.asarray(actions, dtype=np.float64)
        expected = (self.num_envs,) + self.single_action_space.shape
        if a.shape != expected:
            raise ValueError(f"actions of shape {a.shape}, expected {expected}")
        if not np.all(np.isfinite(a)):
            bad = int(np.flatnonzero(~np.all(np.isfinite(a), axis=1))[0])
            raise ValueError(f"action {a[bad]} of world {bad} is not finite")
        a = np.clip(a, self.single_action_space.low, self.single_action_space.high)
        if not self.holonomic:
            a = np.concatenate([a, np.zeros((self.num_envs, 1))], axis=1)
        self.vsim.step(a)
        w = self.reward_weights
        d_after, intrusion, robot_collisions = self.vsim.reward_terms(w.personal_distance)
        collided = robot_collisions > self._robot_collisions
        infos = self._infos(collided, robot_collisions)
        if self.reward_fn is None:  # default_vector_reward's formula, on the native terms
            rewards = (w.progress * (self._goal_distance - d_after) - w.intrusion * intrusion
                       - w.collision * collided + w.goal * infos["goal_reached"])
        else:
            before, self._state = self._state, self.vsim.state()
            rewards = np.asarray(self.reward_fn(self, before, self._state, infos), dtype=np.float64)
        self._goal_distance, self._robot_collisions = d_after, robot_collisions
        if self.terminate_on_collision:  # a collision ends the world's episode, with its own status
            for i in np.flatnonzero(collided & (infos["status"] == "running")):
                world = self.vsim.world(int(i))
                world.end_episode("collision", collision_reason(world))
                infos["status"][i] = "collision"
        terminated = infos["goal_reached"] | infos["stuck"] | (collided & self.terminate_on_collision)
        truncated = infos["time_limit"] & ~terminated
        obs = self._observe()
        ended = np.flatnonzero(terminated | truncated)
        if len(ended):
            infos["final_observation"] = np.array([None] * self.num_envs, dtype=object)
            infos["final_info"] = np.array([None] * self.num_envs, dtype=object)
            for i in ended:
                infos["final_observation"][i] = {k: v[i].copy() for k, v in obs.items()}
                final = {k: v[i] for k, v in infos.items() if isinstance(v, np.ndarray) and v.dtype != object}
                world = self.vsim.world(int(i))
                final["status"] = str(final["status"])
                final["reason"] = world.info()["reason"]
                if self.results_dir is not None:
                    final["run_dir"] = self.run_dirs[i]
                infos["final_info"][i] = final
            seeds = [self._next_seed[i] for i in ended]
            for i in ended:
                self._next_seed[i] += self.num_envs
            self.vsim.reset(seeds=seeds, indices=[int(i) for i in ended], out_dirs=self._out_dirs(ended, seeds))
            fresh = self._observe()
            for k in obs:
                obs[k][ended] = fresh[k][ended]
            self._after_reset()
        return obs, rewards, terminated, truncated, infos

    def close(self):
        """Frees the worlds; the environment cannot be used afterwards (closing twice is fine)."""
        self.vsim = None

    def _require_open(self):
        if self.vsim is None:
            raise RuntimeError("the environment is closed")

    def _out_dirs(self, worlds, seeds):
        """The result folders of these worlds' next episodes (None: no files), distinct."""
        if self.results_dir is None:
            return None
        taken = set()
        for i, seed in zip(worlds, seeds):
            self.run_dirs[i] = episode_folder(self.results_dir, seed, taken)
            taken.add(self.run_dirs[i])
        return [self.run_dirs[i] for i in worlds]

    def _after_reset(self):
        d, _, collisions = self.vsim.reward_terms(self.reward_weights.personal_distance)
        self._goal_distance, self._robot_collisions = d, collisions
        self._state = self.vsim.state() if self.reward_fn is not None else None

    def _infos(self, collided, robot_collisions):
        status = np.array(self.vsim.status, dtype="<U16")  # room for every status name
        return {
            "status": status,
            "goal_reached": status == "goal_reached",
            "time_limit": status == "time_limit",
            "stuck": status == "stuck",
            "collided": np.asarray(collided, dtype=bool),
            "time": self.vsim.time,
            "robot_collisions": robot_collisions.copy(),
            "seed": np.array(self.vsim.seeds),
        }

    def _observe(self):
        """HuNavEnv's observation of every world, stacked (computed natively)."""
        return self.vsim.robot_frame_observation(self.max_people, self._scan_max)
