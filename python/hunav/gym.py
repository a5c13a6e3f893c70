"""A Gymnasium-style environment on hunav.Simulation: the robot driven by the agent's actions among
HuNavSim's people.

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
terminated: the goal is reached, or the robot collided (terminate_on_collision) or got stuck;
truncated: the scenario's time limit.
"""
import math

import numpy as np

from . import _hunav
from .render import render_top_view

try:  # subclass gymnasium.Env when it is installed
    import gymnasium as _gymnasium
    _EnvBase = _gymnasium.Env
except ImportError:  # pragma: no cover - the usual case on Debian
    _gymnasium = None
    _EnvBase = object


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
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"


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
    goal = env.sim.robot["goal"][:2]
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


class HuNavEnv(_EnvBase):
    """One hunav.Simulation stepped by the agent, one control period per step (module docstring).

    scenario: the scenario file; seed: the first episode's seed (default: the scenario's);
    max_people: rows of obs["people"] (default: the scenario's number of people, at least 1);
    reward_fn(env, before, after, info) -> float replaces default_reward (before/after: sim.state());
    terminate_on_collision: end the episode at the robot's first contact;
    render_mode: "rgb_array" (render() returns the top view) or None; render_size: (width, height)
    in pixels (default: 20 pixels per metre of the scenario's bounds).
    Further keyword arguments go to hunav.Simulation (duration, sample_rate, profile, out_dir...).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(self, scenario, seed=None, max_people=None, reward_fn=None, reward_weights=None,
                 terminate_on_collision=True, render_mode="rgb_array", render_size=None, **sim_kwargs):
        self.sim = _hunav.Simulation(scenario, seed=seed, planner=None, **sim_kwargs)
        self.scenario = scenario
        self.reward_fn = reward_fn
        self.reward_weights = reward_weights or RewardWeights()
        self.terminate_on_collision = terminate_on_collision
        self.render_mode = render_mode
        self.render_size = render_size
        robot = self.sim.robot
        self.holonomic = robot["holonomic"]
        self.max_people = max(1, int(max_people) if max_people is not None else self._people_count())
        self.action_space = self._make_action_space(robot)
        self.observation_space = self._make_observation_space(robot)
        self._state = None
        self._robot_collisions = 0

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
        """Starts an episode (with `seed`, or the last one); returns (obs, info)."""
        if seed is not None:
            self.action_space.seed(seed)
        raw = self.sim.reset(seed=seed)
        self._state = self.sim.state()
        self._robot_collisions = 0
        info = self._info(collided=False)
        return self._observe(raw), info

    def step(self, action):
        """Applies `action` for one control period; returns (obs, reward, terminated, truncated, info)."""
        if self._state is None:
            raise RuntimeError("call reset() before step()")
        if self.sim.done:
            raise RuntimeError("the episode has ended: call reset()")
        a = np.asarray(action, dtype=np.float64)
        if a.shape != self.action_space.shape:
            raise ValueError(f"action of shape {a.shape}, expected {self.action_space.shape}")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"action {a} is not finite")
        a = np.clip(a, self.action_space.low, self.action_space.high)
        raw = self.sim.step(float(a[0]), float(a[1]), float(a[2]) if self.holonomic else 0.0)
        before, self._state = self._state, self.sim.state()
        collided = self._state["robot_collisions"] > self._robot_collisions
        self._robot_collisions = self._state["robot_collisions"]
        info = self._info(collided)
        fn = self.reward_fn or default_reward
        reward = float(fn(self, before, self._state, info))
        terminated = info["goal_reached"] or info["stuck"] or (collided and self.terminate_on_collision)
        truncated = info["time_limit"] and not terminated
        return self._observe(raw), reward, bool(terminated), bool(truncated), info

    def render(self):
        """The top view as a (height, width, 3) uint8 array (render_mode "rgb_array")."""
        if self._state is None:
            raise RuntimeError("call reset() before render()")
        w, h = self.render_size or (None, None)
        return render_top_view(self.sim, width=w, height=h, resolution=0.05)

    def close(self):
        self.sim = None

    # --- helpers ---
    def _info(self, collided):
        info = self.sim.info()
        info["collided"] = bool(collided)
        return info

    def _observe(self, raw):
        x, y, yaw, v, w = raw["robot"]
        c, s = math.cos(yaw), math.sin(yaw)
        rot = np.array([[c, s], [-s, c]])  # world -> robot frame
        goal = rot @ (raw["goal"][:2] - (x, y))
        people = np.zeros((self.max_people, 6), dtype=np.float32)
        p = raw["people"]
        if len(p):
            rel = (p[:, 0:2] - (x, y)) @ rot.T
            vel = p[:, 3:5] @ rot.T
            order = np.argsort(np.hypot(rel[:, 0], rel[:, 1]))[: self.max_people]
            k = len(order)
            people[:k, 0:2] = rel[order]
            people[:k, 2:4] = vel[order]
            people[:k, 4] = p[order, 5]
            people[:k, 5] = 1.0
        scan = np.clip(raw["scan"], 0.0, self.observation_space["scan"].high[0]).astype(np.float32)
        return {
            "robot": np.array([v, w], dtype=np.float32),
            "goal": goal.astype(np.float32),
            "scan": scan,
            "people": people,
        }
