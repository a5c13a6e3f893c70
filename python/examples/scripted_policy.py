"""Runs a simple scripted policy (no learning) in HuNavEnv over many episodes and prints the success
rate and the mean return; the shape of a training loop with hunav.gym.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/scripted_policy.py [--episodes 100]
"""
import argparse
import pathlib
import time

import numpy as np

from hunav.gym import HuNavEnv

REPO = pathlib.Path(__file__).resolve().parents[2]


def policy(obs):
    """Turn towards the goal (robot frame), slow down while turning."""
    gx, gy = obs["goal"]
    heading = np.arctan2(gy, gx)
    return np.array([0.6 if abs(heading) < 0.5 else 0.1, np.clip(2.0 * heading, -1.2, 1.2)])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default=str(REPO / "scenarios" / "passing.yaml"))
    parser.add_argument("--episodes", type=int, default=100)
    args = parser.parse_args()

    env = HuNavEnv(args.scenario)
    successes, returns, steps = 0, [], 0
    start = time.perf_counter()
    for episode in range(args.episodes):
        obs, info = env.reset(seed=episode + 1)
        total, done = 0.0, False
        while not done:
            obs, reward, terminated, truncated, info = env.step(policy(obs))
            total += reward
            steps += 1
            done = terminated or truncated
        successes += info["goal_reached"]
        returns.append(total)
    wall = time.perf_counter() - start
    print(f"{args.episodes} episodes: success rate {successes / args.episodes:.2f}, "
          f"mean return {np.mean(returns):.2f}, {steps / wall:.0f} steps/s")


if __name__ == "__main__":
    main()
