"""A map-based robot planner over LCM, in Python: a global path on the static map (MAP: Dijkstra over
the occupancy grid, kept clear of walls by the robot's radius) and a local controller that follows it,
slows down near people and waits for them, and plans round people who block the way.

The template for a planner of your own that needs the map (a Nav2-style global planner + local
controller). It depends on LCM's Python API (`import lcm`), the message classes (`hunav`) and numpy:

    PYTHONPATH=build/python /usr/bin/python3 python/examples/map_planner.py [--lcm-url URL] [--episodes N]

Run it in a run: launch_scripts/run_experiment.sh --scenario scenarios/cafe.yaml --mode lockstep
    --planner-cmd "exec /usr/bin/python3 python/examples/map_planner.py --episodes 1" --planner map
(docs/planner_contract.md, "A planner on the map").
"""
import argparse
import heapq
import math
import sys
import time

import numpy as np

import lcm
from hunav import episode_event_t, map_t, planned_path_t, planner_ready_t, point2d_t, robot_command_t
from hunav import robot_observation_t

NAME = "map_planner"
CLEARANCE = 0.05  # m kept between the robot and the walls, beyond its radius
COMFORT = 0.6  # m: closer to a wall than this (beyond the radius), the path costs more
LOOKAHEAD = 0.8  # m along the path: the point the robot steers at
SLOW_DISTANCE = 1.5  # m between the robot's and a person's surfaces: below it, slow down
STOP_DISTANCE = 0.25  # m: a person or an obstacle this close ahead stops the robot
BLOCKED_FOR = 3.0  # s stopped by a person before the path is planned round the people
DETOUR_FOR = 5.0  # s a path planned round people is followed before the plain path again


def map_problem(msg):
    """Why a MAP cannot be used (a malformed message is dropped and counted), or None."""
    if not (math.isfinite(msg.resolution) and 0.0 < msg.resolution <= 1e3):
        return "resolution"
    if not all(math.isfinite(v) and abs(v) <= 1e6 for v in (msg.origin_x, msg.origin_y, msg.origin_yaw)):
        return "origin"
    if msg.width < 1 or msg.height < 1 or msg.width * msg.height != msg.num_cells or msg.num_cells > 1 << 22:
        return "size"
    return None


class Grid:
    """The map for a robot of a given radius: where its centre may go, and each cell's cost to the goal."""

    def __init__(self, msg, robot_radius):
        self.resolution = msg.resolution
        self.origin = np.array([msg.origin_x, msg.origin_y])
        self.shape = (msg.height, msg.width)  # rows (y), columns (x)
        occupied = np.asarray(msg.cells, dtype=np.int8).reshape(self.shape) >= 50
        comfort_cells = int(math.ceil((robot_radius + COMFORT) / msg.resolution)) + 1
        self.clearance = self.distance_to(occupied, comfort_cells) * msg.resolution  # m to the nearest wall
        self.walls = occupied
        self.robot_radius = robot_radius

    @staticmethod
    def distance_to(occupied, limit):
        """Distance in cells from each cell's centre to the nearest occupied cell's edge (up to limit):
        the walls grown ring by ring, 4- and 8-neighbour rings in turn (an octagon: within 8% of the
        Euclidean distance)."""
        dist = np.full(occupied.shape, float(limit))
        reached = occupied.copy()
        dist[reached] = 0.0
        for k in range(1, limit):
            grown = reached.copy()
            grown[1:, :] |= reached[:-1, :]
            grown[:-1, :] |= reached[1:, :]
            grown[:, 1:] |= reached[:, :-1]
            grown[:, :-1] |= reached[:, 1:]
            if k % 2 == 0:
                grown[1:, 1:] |= reached[:-1, :-1]
                grown[1:, :-1] |= reached[:-1, 1:]
                grown[:-1, 1:] |= reached[1:, :-1]
                grown[:-1, :-1] |= reached[1:, 1:]
            dist[grown & ~reached] = k - 0.5
            reached = grown
        return dist

    def cell(self, x, y):
        col = int((x - self.origin[0]) / self.resolution)
        row = int((y - self.origin[1]) / self.resolution)
        return min(max(row, 0), self.shape[0] - 1), min(max(col, 0), self.shape[1] - 1)

    def center(self, row, col):
        return self.origin + (np.array([col, row]) + 0.5) * self.resolution

    def plan_to(self, goal, people=()):
        """Dijkstra from the goal over the whole grid: the cost to go from each cell, in metres
        (weighted near walls and people). Cells too close to a wall for the robot cost 50 times more
        rather than being closed, so that a robot that starts (or is pushed) there still finds its way
        out. `people`: (x, y, radius) to plan round as if they were walls."""
        free = self.clearance.copy()
        res = self.resolution
        for px, py, pr in people:
            reach = int(math.ceil((pr + self.robot_radius + COMFORT) / res))
            r0, c0 = self.cell(px, py)
            rows = np.arange(max(r0 - reach, 0), min(r0 + reach + 1, self.shape[0]))
            cols = np.arange(max(c0 - reach, 0), min(c0 + reach + 1, self.shape[1]))
            ys = self.origin[1] + (rows + 0.5) * res
            xs = self.origin[0] + (cols + 0.5) * res
            gap = np.maximum(np.hypot(ys[:, None] - py, xs[None, :] - px) - pr, 0.0)
            block = free[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1]
            np.minimum(block, gap, out=block)
        weight = 1.0 + 3.0 * np.clip(1.0 - (free - self.robot_radius) / COMFORT, 0.0, 1.0)
        weight[free < self.robot_radius + CLEARANCE] = 50.0
        weight[self.walls] = math.inf
        height, width = self.shape
        flat_weight = weight.ravel().tolist()
        cost = [math.inf] * (height * width)
        row, col = self.cell(*goal)
        cost[row * width + col] = 0.0
        queue = [(0.0, row * width + col)]
        diagonal = math.sqrt(2.0)
        steps = [(-1, 0, 1.0), (1, 0, 1.0), (0, -1, 1.0), (0, 1, 1.0),
                 (-1, -1, diagonal), (-1, 1, diagonal), (1, -1, diagonal), (1, 1, diagonal)]
        while queue:
            c, index = heapq.heappop(queue)
            if c > cost[index]:
                continue
            row, col = divmod(index, width)
            for dr, dc, length in steps:
                r, q = row + dr, col + dc
                if 0 <= r < height and 0 <= q < width:
                    n = r * width + q
                    total = c + length * res * 0.5 * (flat_weight[index] + flat_weight[n])
                    if total < cost[n]:
                        cost[n] = total
                        heapq.heappush(queue, (total, n))
        return np.array(cost).reshape(self.shape)

    def path_from(self, cost_to_go, x, y, length):
        """Cell centres down `cost_to_go` from (x, y) towards the goal: about `length` metres of them
        (math.inf: all the way)."""
        row, col = self.cell(x, y)
        points = [self.center(row, col)]
        travelled = 0.0
        while travelled < length:
            best, best_cost = None, cost_to_go[row, col]
            for dr in (-1, 0, 1):
                for dc in (-1, 0, 1):
                    r, c = row + dr, col + dc
                    if (dr or dc) and 0 <= r < self.shape[0] and 0 <= c < self.shape[1]:
                        if cost_to_go[r, c] < best_cost:
                            best, best_cost = (r, c), cost_to_go[r, c]
            if best is None:  # the goal cell (or no way on)
                break
            travelled += math.hypot(best[0] - row, best[1] - col) * self.resolution
            row, col = best
            points.append(self.center(row, col))
        return points


class MapPlanner:
    def __init__(self, lc):
        self.lc = lc
        self.maps = {}  # episode -> MAP message
        self.episode = None  # the latest episode heard of (START or an observation)
        self.grid = None  # of the current episode, for the robot's radius
        self.grid_episode = None
        self.plain = None  # cost to go on the map alone
        self.detour = None  # cost to go round the people who blocked the robot, and until when
        self.detour_until = 0.0
        self.last = None  # (episode, seq, encoded command) of the last answer
        self.ends = 0
        self.dropped = 0  # messages dropped (undecodable, or a MAP that is not a grid)
        self.blocked_since = None  # sim time the robot was first stopped by a person

    # --- messages ---
    def on_map(self, channel, data):
        try:
            msg = map_t.decode(data)
        except Exception:
            self.dropped += 1
            return
        if map_problem(msg) is not None:
            self.dropped += 1
            return
        if msg.episode not in self.maps:
            print(f"{NAME}: map of episode {msg.episode}: {msg.width} x {msg.height} cells of {msg.resolution} m",
                  file=sys.stderr, flush=True)
        self.maps = {e: m for e, m in self.maps.items() if e >= msg.episode - 1}  # keep the latest two
        self.maps[msg.episode] = msg

    def on_event(self, channel, data):
        event = episode_event_t.decode(data)
        if event.event == episode_event_t.START:
            self.episode = event.episode
        if event.event == episode_event_t.END:
            self.ends += 1
            print(f"{NAME}: episode {event.episode} ended: {event.status} ({event.reason})", file=sys.stderr)

    def on_observation(self, channel, data):
        try:
            obs = robot_observation_t.decode(data)
        except Exception:
            self.dropped += 1
            return
        if self.last is not None and self.last[0] == obs.episode:
            if obs.seq == self.last[1]:  # a resend: the same answer again
                self.lc.publish("ROBOT_COMMAND", self.last[2])
                return
            if obs.seq < self.last[1]:  # a late duplicate
                return
        self.episode = obs.episode
        cmd, path = self.plan(obs)
        cmd.utime, cmd.seq, cmd.episode = obs.utime, obs.seq, obs.episode
        self.last = (obs.episode, obs.seq, cmd.encode())
        self.lc.publish("ROBOT_COMMAND", self.last[2])
        if path:
            msg = planned_path_t()
            msg.utime, msg.seq, msg.episode = obs.utime, obs.seq, obs.episode
            msg.points = [point2d_t() for _ in path]
            for p, (x, y) in zip(msg.points, path):
                p.x, p.y = float(x), float(y)
            msg.num_points = len(msg.points)
            self.lc.publish("ROBOT_PATH", msg.encode())

    def wants_map(self):
        """True while the current episode's MAP has not arrived (PLANNER_READY asks for it)."""
        return self.episode is not None and self.episode not in self.maps

    # --- planning ---
    def plan(self, obs):
        cmd = robot_command_t()
        if not obs.goal.valid or math.hypot(obs.goal.x - obs.x, obs.goal.y - obs.y) <= obs.goal.radius:
            return cmd, None
        if obs.episode not in self.maps:  # no map yet: stand still (the readiness loop asks for it)
            return cmd, None
        t = obs.utime * 1e-6
        goal = (obs.goal.x, obs.goal.y)
        if self.grid_episode != obs.episode:
            self.grid = Grid(self.maps[obs.episode], obs.radius)
            self.plain = self.grid.plan_to(goal)
            self.grid_episode = obs.episode
            self.detour, self.blocked_since = None, None
        if self.detour is not None and t >= self.detour_until:
            self.detour = None
        path = self.grid.path_from(self.plain if self.detour is None else self.detour, obs.x, obs.y, math.inf)
        target = np.array([obs.goal.x, obs.goal.y])  # the point LOOKAHEAD along the path, else the goal
        travelled = 0.0
        for a, b in zip(path, path[1:]):
            travelled += math.hypot(*(b - a))
            if travelled >= LOOKAHEAD:
                target = b
                break
        error = math.remainder(math.atan2(target[1] - obs.y, target[0] - obs.x) - obs.yaw, 2 * math.pi)
        cmd.w = max(-obs.max_w, min(obs.max_w, 1.5 * error))
        v = obs.max_v * max(0.0, math.cos(error)) if abs(error) < 1.0 else 0.0
        v = min(v, math.hypot(obs.goal.x - obs.x, obs.goal.y - obs.y))  # ease into the goal
        v, by_person = self.slow_for_people(obs, v)
        v = min(v, self.room_ahead(obs))
        # Stopped by people for a while: plan round them (and back to the plain plan once moving).
        if by_person and v == 0.0:
            if self.blocked_since is None:
                self.blocked_since = t
            elif t - self.blocked_since >= BLOCKED_FOR:
                self.detour = self.grid.plan_to(goal, [(p.x, p.y, p.radius) for p in obs.people])
                self.detour_until = t + BLOCKED_FOR + DETOUR_FOR
                self.blocked_since = t
        elif v > 0.0:
            self.blocked_since = None
        cmd.v = v
        return cmd, [tuple(p) for p in path[::4]] + [goal]  # for the view: every fourth cell

    def slow_for_people(self, obs, v):
        """The speed allowed by the people ahead, and whether one of them limits it."""
        limited = False
        for p in obs.people:
            dx, dy = p.x - obs.x, p.y - obs.y
            ahead = abs(math.remainder(math.atan2(dy, dx) - obs.yaw, 2 * math.pi)) < 1.0
            gap = math.hypot(dx, dy) - obs.radius - p.radius
            if ahead and gap < SLOW_DISTANCE:
                allowed = obs.max_v * max(0.0, (gap - STOP_DISTANCE) / (SLOW_DISTANCE - STOP_DISTANCE))
                if allowed < v:
                    v, limited = allowed, True
        return v, limited

    @staticmethod
    def room_ahead(obs):
        """0 when the laser sees something within STOP_DISTANCE of the robot's front, else no limit."""
        scan = obs.scan
        for i, r in enumerate(scan.ranges):
            if scan.range_min <= r < scan.range_max and r < obs.radius + STOP_DISTANCE:
                beam = math.remainder(scan.sensor_yaw + scan.angle_min + i * scan.angle_increment - obs.yaw,
                                      2 * math.pi)
                if abs(beam) < 0.5:
                    return 0.0
        return math.inf


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lcm-url", default=None, help="the run's LCM URL (default: $LCM_DEFAULT_URL)")
    parser.add_argument("--episodes", type=int, default=0, help="exit after this many episodes ended (0: never)")
    args = parser.parse_args()

    lc = lcm.LCM(args.lcm_url)
    planner = MapPlanner(lc)
    lc.subscribe("MAP", planner.on_map)
    lc.subscribe("EPISODE_EVENT", planner.on_event)
    lc.subscribe("ROBOT_OBSERVATION", planner.on_observation).set_queue_capacity(1000)

    # Readiness (docs/planner_contract.md): announce every 0.5 s, and at once when asking for the map.
    ready = planner_ready_t()
    ready.name = NAME
    next_announce = 0.0
    asked = False
    while args.episodes == 0 or planner.ends < args.episodes:
        wants = planner.wants_map()
        now = time.monotonic()
        if now >= next_announce or (wants and not asked):
            ready.dropped_messages = planner.dropped
            ready.wants_map = wants
            lc.publish("PLANNER_READY", ready.encode())
            next_announce, asked = now + 0.5, wants
        lc.handle_timeout(100)


if __name__ == "__main__":
    main()
