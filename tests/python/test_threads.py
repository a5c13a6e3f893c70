"""Threads (issue 31): a Simulation or VectorSimulation used from a second thread while it is busy
raises RuntimeError instead of killing the interpreter. Before, one Simulation stepped from two
threads died of SIGSEGV, hung, or failed a Box2D allocator assertion, and a vector's world stepped
alone while the vector stepped was a double free. The last two tests are bounded property tests:
threads call random methods of one object for about a second; every call works or raises one of the
documented errors, the interpreter lives, and the object then runs an episode to the fingerprint a
fresh one gives."""
import random
import threading
import time

import numpy as np
import pytest

import hunav

BUSY = "busy in another thread"


def wait_busy(call, thread, bound_s=30.0):
    """Calls `call` until it raises the busy RuntimeError (True), or `thread` has ended (False)."""
    deadline = time.monotonic() + bound_s
    while thread.is_alive() and time.monotonic() < deadline:
        try:
            call()
        except RuntimeError as e:
            if BUSY in str(e):
                return True
            raise
        time.sleep(0.0005)
    return False


def busy_while(target, probe, attempts=5):
    """Runs target() in a thread until probe() has seen it busy; returns the thread (joined)."""
    for _ in range(attempts):
        t = threading.Thread(target=target)
        t.start()
        seen = wait_busy(probe, t)
        t.join()
        if seen:
            return True
    return False


def test_a_second_thread_gets_runtime_error_while_a_simulation_runs(passing):
    sim = hunav.Simulation(passing, seed=1, planner="none", duration=50)  # 5000 ticks: long enough to be seen busy
    sim.reset()
    calls = {
        "step": lambda: sim.step(0.0, 0.0),
        "reset": lambda: sim.reset(),
        "run": lambda: sim.run(),
        "state": lambda: sim.state(),
        "info": lambda: sim.info(),
        "observation": lambda: sim.observation(),
        "metrics": lambda: sim.metrics(),
        "fingerprint": lambda: sim.fingerprint(),
        "done": lambda: sim.done,
        "seed": lambda: sim.seed,
        "map": lambda: sim.map(),
    }
    for name, call in calls.items():
        sim.reset()
        assert busy_while(sim.run, call), f"{name}() never saw the simulation busy"
    # The object is sound afterwards: the same episode as a fresh one.
    sim.reset()
    fresh = hunav.Simulation(passing, seed=1, planner="none", duration=50)
    assert sim.run()["fingerprint"] == fresh.run()["fingerprint"]


def test_a_world_of_a_vector_used_alone_while_the_vector_steps_raises(passing):
    vec = hunav.VectorSimulation(2, passing, seeds=[1, 2], planner="none", duration=50)
    vec.reset()
    world = vec[0]
    assert busy_while(vec.run, lambda: world.step(0.0, 0.0))
    vec.reset()
    assert busy_while(vec.run, lambda: world.reset())
    vec.reset()
    assert busy_while(vec.run, lambda: vec.state())
    # And the vector while one of its worlds runs alone.
    vec.reset()
    assert busy_while(world.run, lambda: vec.step(np.zeros((2, 2))))
    vec.reset()
    assert busy_while(world.run, lambda: vec.run())
    vec.reset()
    fresh = hunav.VectorSimulation(2, passing, seeds=[1, 2], planner="none", duration=50)
    assert [i["fingerprint"] for i in vec.run()] == [i["fingerprint"] for i in fresh.run()]


# The errors a call may raise when threads share an object: busy, or the object's state as another
# thread left it (no episode yet, the episode ended, a planner drives the robot).
ALLOWED = (BUSY, "call reset()", "has ended", "use run()", "no episode yet")


def hammer(calls, seconds, seed, threads=4):
    """Threads calling random entries of `calls` for `seconds`; returns the unexpected errors."""
    problems = []
    counts = {"ok": 0, "busy": 0, "state": 0}
    lock = threading.Lock()
    stop = time.monotonic() + seconds

    def worker(k):
        rng = random.Random(seed * 100 + k)
        while time.monotonic() < stop:
            name, call = rng.choice(calls)
            try:
                call(rng)
                what = "ok"
            except RuntimeError as e:
                if not any(a in str(e) for a in ALLOWED):
                    with lock:
                        problems.append(f"{name}: RuntimeError {e}")
                what = "busy" if BUSY in str(e) else "state"
            except Exception as e:  # anything else is a defect
                with lock:
                    problems.append(f"{name}: {type(e).__name__} {e}")
                what = "state"
            with lock:
                counts[what] += 1
    ts = [threading.Thread(target=worker, args=(k,)) for k in range(threads)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    return problems, counts


def test_threads_calling_random_methods_of_one_simulation(passing):
    sim = hunav.Simulation(passing, seed=1, duration=3)  # driven from Python: 300 ticks an episode
    calls = [
        ("reset", lambda r: sim.reset(seed=r.choice([1, 2, None]))),
        ("step", lambda r: sim.step(r.uniform(0, 1), r.uniform(-1, 1))),
        ("run", lambda r: sim.run()),
        ("state", lambda r: sim.state()),
        ("info", lambda r: sim.info()),
        ("observation", lambda r: sim.observation()),
        ("metrics", lambda r: sim.metrics()),
        ("positions", lambda r: sim.positions()),
        ("reward_terms", lambda r: sim.reward_terms(1.0)),
        ("fingerprint", lambda r: sim.fingerprint()),
        ("done", lambda r: sim.done),
    ]
    problems, counts = hammer(calls, 1.5, seed=31)
    print("calls:", counts)
    assert not problems, problems[:10]
    assert counts["busy"] > 0 and counts["ok"] > 0
    sim.reset(seed=2)
    assert sim.run()["fingerprint"] == hunav.Simulation(passing, seed=2, duration=3).run()["fingerprint"]


def test_threads_calling_a_vector_and_its_worlds(passing):
    vec = hunav.VectorSimulation(3, passing, seeds=[1, 2, 3], duration=3)
    vec.reset()
    calls = [
        ("vec.reset", lambda r: vec.reset()),
        ("vec.step", lambda r: vec.step(np.full((3, 2), 0.3))),
        ("vec.run", lambda r: vec.run()),
        ("vec.observation", lambda r: vec.observation()),
        ("vec.state", lambda r: vec.state()),
        ("vec.done", lambda r: vec.done),
        ("world.step", lambda r: vec[r.randrange(3)].step(0.3, 0.0)),
        ("world.reset", lambda r: vec[r.randrange(3)].reset()),
        ("world.run", lambda r: vec[r.randrange(3)].run()),
        ("world.state", lambda r: vec[r.randrange(3)].state()),
    ]
    problems, counts = hammer(calls, 1.5, seed=32)
    print("calls:", counts)
    assert not problems, problems[:10]
    assert counts["busy"] > 0 and counts["ok"] > 0
    vec.reset(seeds=[4, 5, 6])
    fresh = hunav.VectorSimulation(3, passing, seeds=[4, 5, 6], duration=3)
    assert [i["fingerprint"] for i in vec.run()] == [i["fingerprint"] for i in fresh.run()]


def test_duration_zero_is_refused(passing):
    # It was accepted and kept the scenario's 60 s (hunav_run --duration 0 is refused).
    for bad in [0, -1, float("nan"), 2e7]:
        with pytest.raises(ValueError, match="duration"):
            hunav.Simulation(passing, duration=bad)
        with pytest.raises(ValueError, match="duration"):
            hunav.VectorSimulation(2, passing, duration=bad)
