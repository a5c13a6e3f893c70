"""Runs a simple policy (no learning) over many episodes on a hunav.VectorSimulation and prints the
success rate and the mean social work (the evaluator's social_work metric, docs/metrics.md).

    PYTHONPATH=build/python /usr/bin/python3 python/examples/vector_policy.py [--episodes 100]
        [--worlds 4] [--threads 2] [--scenario scenarios/passing.yaml]

Episode k uses seed k (1..episodes). The worlds step together, one control period per call; a world
whose episode ends starts the next seed. The policy keeps to the right of the corridor while it
passes people, then heads for the goal.
"""
import argparse
import pathlib
import time

import numpy as np

import hunav

REPO = pathlib.Path(__file__).resolve().parents[2]


def policy(obs, lane_y=-1.0):
    """[v, w] for every world (rows of obs): along the lane on the right, the last 2 m to the goal."""
    x, y, yaw = obs["robot"][:, 0], obs["robot"][:, 1], obs["robot"][:, 2]
    gx, gy = obs["goal"][:, 0], obs["goal"][:, 1]
    on_lane = x < gx - 2.0
    tx = np.where(on_lane, x + 1.5, gx)
    ty = np.where(on_lane, lane_y, gy)
    err = np.arctan2(ty - y, tx - x) - yaw
    err = np.arctan2(np.sin(err), np.cos(err))
    v = np.where(np.abs(err) < 0.5, 0.6, 0.1)
    return np.stack([v, np.clip(2.0 * err, -1.2, 1.2)], axis=1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default=str(REPO / "scenarios" / "passing.yaml"))
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--worlds", type=int, default=4, help="worlds stepped together")
    parser.add_argument("--threads", type=int, default=None, help="threads (default: the machine's cores)")
    args = parser.parse_args()
    if args.episodes < 1 or args.worlds < 1:
        parser.error("--episodes and --worlds must be >= 1")

    start = time.perf_counter()
    worlds = min(args.worlds, args.episodes)
    seeds = list(range(1, args.episodes + 1))
    # files=False: the metrics in memory, no result folder per episode (nothing here reads one).
    vs = hunav.VectorSimulation(worlds, args.scenario, seeds=seeds[:worlds], threads=args.threads, files=False)
    obs = vs.reset()
    playing = seeds[:worlds]  # the seed each world plays (None: no episode left for it)
    pending = seeds[worlds:]
    results = {}  # seed -> (goal reached, social work)
    steps = 0
    while True:
        done = vs.done
        ended = [i for i in np.flatnonzero(done) if playing[i] is not None]
        if ended:
            infos, metrics = vs.infos(), vs.metrics()
            for i in ended:
                results[playing[i]] = (infos[i]["goal_reached"], metrics[i]["social_work"])
                playing[i] = pending.pop(0) if pending else None
            restart = [int(i) for i in ended if playing[i] is not None]
            if restart:
                obs = vs.reset(seeds=[playing[i] for i in restart], indices=restart)
        if all(p is None for p in playing):
            break
        steps += int((~vs.done).sum())
        obs = vs.step(policy(obs))
    wall = time.perf_counter() - start

    reached = [results[s][0] for s in seeds]
    work = [results[s][1] for s in seeds]
    print(f"{args.episodes} episodes (seeds 1..{args.episodes}) on {worlds} worlds, {vs.threads} threads: "
          f"success rate {np.mean(reached):.2f}, mean social work {np.mean(work):.3f}, "
          f"{steps} steps in {wall:.1f} s ({steps / wall:.0f} steps/s)")


if __name__ == "__main__":
    main()
