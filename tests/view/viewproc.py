"""Starts hunav_view for a test and reads the URL it prints."""
import os
import re
import subprocess
import time


class View:
    def __init__(self, args, timeout=20.0):
        self.bin = os.path.join(os.environ["BIN"], "hunav_view")
        self.proc = subprocess.Popen([self.bin, "--port", "0"] + args, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True)
        self.url = None
        deadline = time.time() + timeout
        for line in self.proc.stdout:
            m = re.match(r"hunav_view: open (http://\S+) in a browser", line)
            if m:
                self.url = m.group(1).rstrip("/")
            if line.strip() == "ready":
                break
            if time.time() > deadline:
                break
        if self.url is None:
            self.proc.kill()
            raise RuntimeError("hunav_view did not start: " + self.proc.stderr.read())

    def alive(self):
        return self.proc.poll() is None

    def stop(self):
        self.proc.terminate()
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        return self.proc.returncode
