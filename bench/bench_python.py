#!/usr/bin/env python3
"""Speed of the hunav Python module: control steps per second with the action from Python.

    PYTHONPATH=build/python taskset -c 0 /usr/bin/python3 bench/bench_python.py [--episodes 20]
    PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py --vector-only --worlds 2
    ... --no-states-csv: every loop without states.csv (states_csv=False; the same episodes)
    ... --no-per-tick-files: every loop without the per-tick metric files (per_tick_files=False)

A step is one control period (10 world ticks of 0.01 s in scenarios/passing.yaml) with the action
computed in Python by the go-to-goal policy below; episodes use seeds first_seed.. and run to their
end (goal, time limit or stuck), resets included in the time. Figures (the best of --repeat):

  cpp:     build/bin/bench_stepped, the same episodes stepped from C++ (no Python), when built;
  sim:     hunav.Simulation.step(v, w) in a Python loop;
  env:     hunav.gym.HuNavEnv.step(action) (observation in the robot frame, reward, info), as
           made by default: no result file (metrics in memory);
  env, results_dir=: the same writing every file of every episode (into a temporary folder,
           removed after the figure);
  vector:  hunav.VectorSimulation(worlds).step(actions) with threads=1 and threads=worlds: world
           steps per second (worlds x vector steps), and the speed-up of the threads.

"CPU" is the CPU time per step of the stepping thread and, after the slash, of the whole process
(the evaluator's worker threads and the pool's too: 1e6 / that is what one core would do), the
figures least disturbed by other work on the machine. Each line ends with a digest of the episodes' fingerprints:
equal digests, equal episodes (the C++ and Python loops, and a vector and a single simulation, give the same).
python/README.md, "Speed".
"""
import argparse
import math
import os
import pathlib
import shutil
import subprocess
import tempfile
import time

import numpy as np

import hunav
from hunav.gym import HuNavEnv

REPO = pathlib.Path(__file__).resolve().parents[1]
SIM_OPTIONS = {}  # extra keyword arguments of every Simulation, HuNavEnv and VectorSimulation (--no-states-csv)


def go_to_goal(robot, goal):
    """Turn towards the goal, slow down while turning (bench_stepped.cpp's goToGoal)."""
    err = math.atan2(goal[1] - robot[1], goal[0] - robot[0]) - robot[2]
    err = math.atan2(math.sin(err), math.cos(err))
    return (0.6 if abs(err) < 0.5 else 0.1), max(-1.2, min(1.2, 2.0 * err))


def digest(fingerprints):
    """FNV-1a 64 of the fingerprints, one per line (bench_stepped.cpp's digestOf)."""
    h = 0xCBF29CE484222325
    for c in "".join(f + "\n" for f in fingerprints).encode():
        h = ((h ^ c) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return f"{h:016x}"


def bench_sim(scenario, seeds):
    sim = hunav.Simulation(scenario, **SIM_OPTIONS)
    steps, prints = 0, []
    start, cpu, proc = time.perf_counter(), time.thread_time(), time.process_time()
    for seed in seeds:
        obs = sim.reset(seed=seed)
        while not sim.done:
            obs = sim.step(*go_to_goal(obs["robot"], obs["goal"]))
            steps += 1
        prints.append(sim.fingerprint())
    return steps, time.perf_counter() - start, prints, (time.thread_time() - cpu, time.process_time() - proc)


def bench_env(scenario, seeds, results_dir=None):
    env = HuNavEnv(scenario, results_dir=results_dir, **SIM_OPTIONS)
    steps, prints = 0, []
    start, cpu, proc = time.perf_counter(), time.thread_time(), time.process_time()
    for seed in seeds:
        obs, info = env.reset(seed=seed)
        done = False
        while not done:
            gx, gy = obs["goal"]  # robot frame
            heading = math.atan2(gy, gx)
            action = np.array([0.6 if abs(heading) < 0.5 else 0.1, max(-1.2, min(1.2, 2.0 * heading))])
            obs, reward, terminated, truncated, info = env.step(action)
            steps += 1
            # Played to the sim's end (not stopped at a collision) to match the other loops.
            done = env.sim.done
        prints.append(env.sim.fingerprint())
    return steps, time.perf_counter() - start, prints, (time.thread_time() - cpu, time.process_time() - proc)


def bench_env_files(scenario, seeds):
    """bench_env with results_dir= (every file of every episode), in a fresh temporary folder."""
    folder = tempfile.mkdtemp(prefix="bench_python_")
    try:
        return bench_env(scenario, seeds, folder)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def bench_vector(scenario, seeds, worlds, threads):
    """The episodes over `worlds` worlds: a world whose episode ends starts the next seed."""
    vs = hunav.VectorSimulation(worlds, scenario, seeds=seeds[:worlds], threads=threads, **SIM_OPTIONS)
    steps, prints = 0, {}
    start, cpu, proc = time.perf_counter(), time.thread_time(), time.process_time()
    obs = vs.reset()
    running = list(seeds[:worlds])  # the seed each world plays
    pending = list(seeds[worlds:])
    while True:
        done = vs.done
        ended = [k for k in np.flatnonzero(done) if running[k] is not None]
        for k in ended:
            prints[running[k]] = vs.fingerprints()[k]
            running[k] = pending.pop(0) if pending else None
        restart = [int(k) for k in ended if running[k] is not None]
        if restart:
            obs = vs.reset(seeds=[running[k] for k in restart], indices=restart)
            done = vs.done
        if all(r is None for r in running):
            break
        robot, goal = obs["robot"], obs["goal"]
        err = np.arctan2(goal[:, 1] - robot[:, 1], goal[:, 0] - robot[:, 0]) - robot[:, 2]
        err = np.arctan2(np.sin(err), np.cos(err))
        actions = np.stack([np.where(np.abs(err) < 0.5, 0.6, 0.1), np.clip(2.0 * err, -1.2, 1.2)], axis=1)
        steps += int((~done).sum())
        obs = vs.step(actions)
    cpu_times = (time.thread_time() - cpu, time.process_time() - proc)
    return steps, time.perf_counter() - start, [prints[s] for s in seeds], cpu_times


def best_of(repeat, fn, *args):
    """The fastest run (wall clock), with the least CPU time of all runs."""
    runs = [fn(*args) for _ in range(repeat)]
    assert all(r[2] == runs[0][2] for r in runs), "episodes differ between repeats"
    steps, seconds, prints, _ = min(runs, key=lambda r: r[1])
    return steps, seconds, prints, (min(r[3][0] for r in runs), min(r[3][1] for r in runs))


def line(name, steps, seconds, prints, cpu):
    print(f"{name:<30} {steps:>6} steps {seconds:7.3f} s {steps / seconds:7.0f} steps/s "
          f"{1e6 * seconds / steps:6.1f} us/step, CPU {1e6 * cpu[0] / steps:5.1f} / {1e6 * cpu[1] / steps:5.1f} "
          f"us/step, digest {digest(prints)}", flush=True)
    return seconds / steps, cpu[0] / steps, cpu[1] / steps


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default=str(REPO / "scenarios" / "passing.yaml"))
    parser.add_argument("--episodes", type=int, default=20)
    parser.add_argument("--first-seed", type=int, default=1)
    parser.add_argument("--repeat", type=int, default=3, help="runs of each figure; the best is printed")
    parser.add_argument("--worlds", type=int, default=2, help="worlds of the vector figure")
    parser.add_argument("--threads", type=int, default=0,
                        help="threads of the vector figure's second line (default: the worlds, at most the CPUs)")
    parser.add_argument("--bench-stepped", default=str(REPO / "build" / "bin" / "bench_stepped"),
                        help="the C++ baseline binary")
    parser.add_argument("--vector-only", action="store_true", help="only the vector figures")
    parser.add_argument("--no-states-csv", action="store_true",
                        help="without states.csv (states_csv=False; bench_stepped --no-states-csv)")
    parser.add_argument("--no-per-tick-files", action="store_true",
                        help="without the per-tick metric files (per_tick_files=False; bench_stepped too)")
    args = parser.parse_args()
    if args.no_states_csv:
        SIM_OPTIONS["states_csv"] = False
    if args.no_per_tick_files:
        SIM_OPTIONS["per_tick_files"] = False
    seeds = list(range(args.first_seed, args.first_seed + args.episodes))
    cpus = sorted(os.sched_getaffinity(0))
    print(f"scenario {args.scenario}, {args.episodes} episodes (seeds {seeds[0]}..{seeds[-1]}), "
          f"CPUs {cpus}, best of {args.repeat}")

    if not args.vector_only:
        cpp = None
        if os.path.exists(args.bench_stepped):
            runs = []
            for _ in range(args.repeat):
                out = subprocess.run([args.bench_stepped, "--scenario", args.scenario, "--episodes",
                                      str(args.episodes), "--first-seed", str(args.first_seed)]
                                     + (["--no-states-csv"] if args.no_states_csv else [])
                                     + (["--no-per-tick-files"] if args.no_per_tick_files else []),
                                     capture_output=True, text=True, check=True).stdout
                fields = out.split()
                cpu = [i for i, f in enumerate(fields) if f == "CPU"]
                runs.append((int(fields[fields.index("steps") - 1]), float(fields[fields.index("s:") - 1]),
                             float(fields[cpu[0] + 1]) * 1e-6, float(fields[cpu[1] + 1]) * 1e-6,
                             fields[fields.index("digest") + 1]))
            steps, seconds, _, _, dig = min(runs, key=lambda r: r[1])
            cpp = (seconds / steps, min(r[2] for r in runs), min(r[3] for r in runs))
            print(f"{'cpp (bench_stepped)':<30} {steps:>6} steps {seconds:7.3f} s {steps / seconds:7.0f} steps/s "
                  f"{1e6 * cpp[0]:6.1f} us/step, CPU {1e6 * cpp[1]:5.1f} / {1e6 * cpp[2]:5.1f} us/step, digest {dig}")
        else:
            print(f"no {args.bench_stepped}: build the bench_stepped target for the C++ figure")
        for name, fn in (("sim (Simulation.step)", bench_sim), ("env (HuNavEnv.step)", bench_env),
                         ("env, results_dir=", bench_env_files)):
            per = line(name, *best_of(args.repeat, fn, args.scenario, seeds))
            if cpp is not None:
                print(f"{'':<30} Python's cost over C++: {1e6 * (per[0] - cpp[0]):.1f} us/step wall, "
                      f"{1e6 * (per[1] - cpp[1]):.1f} / {1e6 * (per[2] - cpp[2]):.1f} us/step CPU")

    one = line(f"vector {args.worlds} worlds, 1 thread",
               *best_of(args.repeat, bench_vector, args.scenario, seeds, args.worlds, 1))
    threads = args.threads or min(args.worlds, len(cpus))
    many = line(f"vector {args.worlds} worlds, {threads} threads",
                *best_of(args.repeat, bench_vector, args.scenario, seeds, args.worlds, threads))
    print(f"{'':<30} speed-up of {threads} threads: {one[0] / many[0]:.2f}x (wall clock)")


if __name__ == "__main__":
    main()
