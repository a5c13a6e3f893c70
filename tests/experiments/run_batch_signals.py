"""run_batch.sh stopped at any moment (issue 31): SIGINT or SIGTERM, from its first lines to the
middle of its runs, stops its jobs and exits 130 or 143 (it exited 1 on SIGINT, and died of the
signal when interrupted in its first half second); no process of the batch is left, and the same
command run again finishes the batch (exit 0) with every run finished. --jobs beyond 1024 is a usage
error (exit 2, at once: GNU parallel probed its limits for minutes), and more jobs than runs are not
started. A bounded property test: 10 moments, each signal. Expects REPO and BIN (ctest sets them)."""
import ctypes
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

REPO, BIN = os.environ["REPO"], os.environ["BIN"]
BATCH = os.path.join(REPO, "launch_scripts", "run_batch.sh")
ENV = dict(os.environ, HUNAV_BIN_DIR=BIN)


def descendants(pid):
    """PIDs below `pid` (its process tree, by /proc's parent links)."""
    parent = {}
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open("/proc/%s/stat" % d) as f:
                    parent[int(d)] = int(f.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                pass
    out, frontier = set(), {pid}
    while frontier:
        frontier = {p for p, q in parent.items() if q in frontier} - out
        out |= frontier
    return out


def catches_signals(pid, bound_s=10.0):
    """Waits until the script catches SIGTERM (its first lines set its traps: before them the shell
    itself is still starting, and no program can handle a signal before its first instruction)."""
    deadline = time.monotonic() + bound_s
    while time.monotonic() < deadline:
        try:
            with open("/proc/%d/status" % pid) as f:
                caught = int(next(line for line in f if line.startswith("SigCgt:")).split()[1], 16)
            if caught & (1 << (signal.SIGTERM - 1)):
                return True
        except (OSError, StopIteration):
            return False
        time.sleep(0.001)
    return False


def wait_reaping(p, bound_s):
    """p's exit code, reaping meanwhile the orphans that come to this test (a child subreaper) as init
    would: run_batch.sh waits until its job group is gone, and a zombie nobody reaps stays in it.
    None after bound_s."""
    deadline = time.monotonic() + bound_s
    while p.returncode is None and time.monotonic() < deadline:  # p.poll() may have reaped it
        try:
            pid, status = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            pid, status = 0, 0
        if pid == p.pid:
            p.returncode = os.waitstatus_to_exitcode(status)
        elif pid == 0:
            time.sleep(0.01)
    return p.returncode


def left_behind(bound_s=30.0):
    """Processes of this test's tree still alive after bound_s (orphans come to this test, a child
    subreaper); zombies are reaped."""
    deadline = time.monotonic() + bound_s
    while True:
        try:
            while os.waitpid(-1, os.WNOHANG)[0] > 0:
                pass
        except ChildProcessError:
            pass
        alive = set()
        for q in descendants(os.getpid()):
            try:
                with open("/proc/%d/stat" % q) as f:
                    if f.read().rsplit(")", 1)[1].split()[0] != "Z":
                        alive.add(q)
            except OSError:
                pass
        if not alive or time.monotonic() > deadline:
            return alive
        time.sleep(0.1)


def main():
    if ctypes.CDLL(None, use_errno=True).prctl(36, 1, 0, 0, 0) != 0:  # PR_SET_CHILD_SUBREAPER
        print("cannot become a child subreaper")
        return 1
    work = tempfile.mkdtemp(prefix="hunav_batch_signals.")
    problems = []
    try:
        args = ["--scenarios", "passing", "--planners", "dwb,sfw", "--seeds", "1-3", "--duration", "20", "--jobs", "2"]
        started = time.monotonic()
        r = subprocess.run([BATCH] + args + ["--jobs", "65536", "--out", os.path.join(work, "x")], env=ENV,
                           capture_output=True, text=True, timeout=60)
        if r.returncode != 2 or "--jobs must be at most 1024" not in r.stderr:
            problems.append("--jobs 65536: exit %d, %r" % (r.returncode, r.stderr[-300:]))
        print("--jobs 65536: exit %d in %.1f s" % (r.returncode, time.monotonic() - started))

        moments = [0.0, 0.01, 0.05, 0.1, 0.3, 0.5, 0.8, 1.2, 2.0, 3.0]
        for k, delay in enumerate(moments):
            sig = signal.SIGINT if k % 2 == 0 else signal.SIGTERM
            out = os.path.join(work, "b%d" % k)
            log = open(os.path.join(work, "b%d.log" % k), "w")
            # A session of its own: the signal goes to the script alone (not to a terminal's group),
            # and SIGINT is not ignored as it is in a shell's background job.
            p = subprocess.Popen([BATCH] + args + ["--out", out], env=ENV, stdout=log, stderr=subprocess.STDOUT,
                                 start_new_session=True)
            catches_signals(p.pid)
            time.sleep(delay)
            alive = p.poll() is None
            if alive:
                os.kill(p.pid, sig)
            rc = wait_reaping(p, 120)
            if rc is None:
                p.kill()
                rc = p.wait()
                problems.append("%s after %.2f s: still running 120 s later" % (sig.name, delay))
            want = 130 if sig == signal.SIGINT else 143
            ok = rc == want or (not alive and rc == 0)
            print("%s after %.2f s: exit %d%s" % (sig.name, delay, rc, "" if ok else "  <- wrong"))
            if not ok:
                log.close()
                with open(os.path.join(work, "b%d.log" % k)) as f:
                    tail = f.read()[-1500:]
                problems.append("%s after %.2f s: exit %d, expected %d; its output:\n%s"
                                % (sig.name, delay, rc, want, tail))
            left = left_behind()
            if left:
                problems.append("%s after %.2f s: processes left: %s" % (sig.name, delay, sorted(left)))
            if k in (1, 6):  # resumable: the same command finishes the batch
                r = subprocess.run([BATCH] + args + ["--out", out], env=ENV, capture_output=True, text=True,
                                   timeout=600)
                if r.returncode != 0 or "6 of 6 finished" not in r.stdout:
                    problems.append("the batch interrupted after %.2f s did not finish when run again: exit %d %s"
                                    % (delay, r.returncode, r.stdout[-500:] + r.stderr[-500:]))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for p in problems:
        print("FAIL:", p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
