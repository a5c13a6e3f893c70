"""Starts hunav_view for a test and reads the URL it prints."""
import json
import os
import re
import subprocess
import time
import urllib.error
import urllib.request

from cdp import GENEROUS


class View:
    def __init__(self, args, timeout=GENEROUS):
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

    def token(self):
        """The token of this start, as the page carries it (<meta name="hunav-token">)."""
        if getattr(self, "_token", None):
            return self._token
        with urllib.request.urlopen(self.url + "/", timeout=GENEROUS) as r:
            page = r.read().decode()
        m = re.search(r'<meta name="hunav-token" content="([0-9a-f]+)">', page)
        if not m:
            raise RuntimeError("the page carries no token")
        self._token = m.group(1)
        return self._token

    def request(self, path, body=None, raw=None, method=None, headers=None, token=True, timeout=GENEROUS):
        """(status, text) of a request to this view; POSTs carry the page's token unless token=False,
        and the JSON content type unless headers say otherwise."""
        data = raw if raw is not None else (json.dumps(body).encode() if body is not None else None)
        h = {"Content-Type": "application/json"}
        if data is not None and token:
            h["X-HuNav-Token"] = self.token() if token is True else token
        h.update(headers or {})
        req = urllib.request.Request(self.url + path, data=data, method=method, headers=h)
        try:
            with urllib.request.urlopen(req, timeout=timeout) as r:
                return r.status, r.read().decode(errors="replace")
        except urllib.error.HTTPError as e:
            return e.code, e.read().decode(errors="replace")

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
